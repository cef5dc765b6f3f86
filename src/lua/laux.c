/*
** laux.c
** Helpers shared by the binding files: the single place where core status codes
** become Lua errors or fail triples (STYLE R3), the option-table readers that
** name the bad field (R6), the 1-based index rule and the Lua allocator (R7).
*/
#include "laux.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* {====================================================================
** Status conversion
** ===================================================================== */

/* Outcomes that depend on the data rather than on how the API was called: a
** strategy branches on them, so they come back as `nil, msg, name`. */
static int is_outcome(bsfit_err e) {
  switch (e) {
    case BSFIT_ESINGULAR:
    case BSFIT_ENOTSPD:
    case BSFIT_ENOCONV:
    case BSFIT_EEMPTYSPAN:
    case BSFIT_EDEGENERATE:
    case BSFIT_EIO:
    case BSFIT_EFORMAT:
      return 1;
    default:
      return 0;
  }
}

/* The core's messages name C functions where a Lua user has another name. */
static const char *const lua_names[][2] = {
  {"bsfit_filter_box_curve_delta", "bs.filter.box(C, {delta = d})"},
  {"bsfit_filter_box_surface_delta", "bs.filter.box(S, {delta_u = du, delta_v = dv})"},
};

/* Pushes the message of a core status as a Lua user reads it: Lua names for C ones,
** and knot spans counted from 1 as K:span counts them (the core's EEMPTYSPAN
** messages count from 0: "knot span 3 [0.2, 0.4) holds no data"). Other indices are
** checked by the binding before the core sees the data (bsfit__lua_checkfinite, ...). */
static const char *push_message(lua_State *L, bsfit_err e, const bsfit_status *st) {
  const char *msg = st != NULL && st->code == e && st->msg[0] != '\0' ? st->msg
                                                                       : bsfit_strerror(e);
  const char *at;
  char *end;
  unsigned long long i;
  size_t k;
  lua_pushstring(L, msg);
  for (k = 0; k < sizeof lua_names / sizeof lua_names[0]; k++)
    if (strstr(lua_tostring(L, -1), lua_names[k][0]) != NULL) {
      luaL_gsub(L, lua_tostring(L, -1), lua_names[k][0], lua_names[k][1]);
      lua_remove(L, -2);
    }
  msg = lua_tostring(L, -1);
  at = e == BSFIT_EEMPTYSPAN ? strstr(msg, "knot span ") : NULL;
  if (at == NULL) return msg;
  at += strlen("knot span ");
  i = strtoull(at, &end, 10);
  if (end == at) return msg;
  lua_pushlstring(L, msg, (size_t)(at - msg));
  lua_pushfstring(L, "%I%s", (lua_Integer)(i + 1), end);
  lua_concat(L, 2);
  lua_remove(L, -2);
  return lua_tostring(L, -1);
}

int bsfit__lua_raise(lua_State *L, bsfit_err e, const bsfit_status *st, int arg) {
  const char *msg = push_message(L, e, st);
  if (arg > 0) return luaL_argerror(L, arg, msg);
  return luaL_error(L, "%s", msg);
}

int bsfit__lua_result(lua_State *L, bsfit_err e, const bsfit_status *st, int nret, int arg) {
  if (e == BSFIT_OK) return nret;
  if (!is_outcome(e)) return bsfit__lua_raise(L, e, st, arg);
  luaL_pushfail(L);
  push_message(L, e, st);
  lua_pushstring(L, bsfit_errname(e));
  return 3;
}

/* The host's interrupt flag travels with the allocator, so every core loop that
** can run long on an object made here (a fitter's assembly, ...) sees it. */
bsfit_allocator bsfit__lua_allocator(lua_State *L) {
  bsfit_allocator a;
  a.fn = (bsfit_alloc_fn)lua_getallocf(L, &a.ud);
  lua_getfield(L, LUA_REGISTRYINDEX, BSFIT_LUA_INTERRUPT);
  a.interrupt = (const volatile int *)lua_touserdata(L, -1); /* NULL when absent */
  lua_pop(L, 1);
  return a;
}

#define BSFIT_SCRATCH_T "bsfit.Scratch"

void bsfit__lua_scratch_free(bsfit_scratch_ud *s) {
  int i;
  for (i = 0; i < 2; i++) {
    if (s->p[i] != NULL) s->a.fn(s->a.ud, s->p[i], s->size[i], 0);
    s->p[i] = NULL;
    s->size[i] = 0;
  }
}

static int scratch_gc(lua_State *L) {
  bsfit__lua_scratch_free((bsfit_scratch_ud *)luaL_checkudata(L, 1, BSFIT_SCRATCH_T));
  return 0;
}

bsfit_scratch_ud *bsfit__lua_newscratch(lua_State *L) {
  bsfit_scratch_ud *s = (bsfit_scratch_ud *)lua_newuserdatauv(L, sizeof *s, 0);
  memset(s, 0, sizeof *s);
  s->a = bsfit__lua_allocator(L);
  if (luaL_newmetatable(L, BSFIT_SCRATCH_T)) {
    lua_pushcfunction(L, scratch_gc);
    lua_setfield(L, -2, "__gc");
    bsfit__lua_protect_metatable(L, -1);
  }
  lua_setmetatable(L, -2);
  return s;
}

/* }==================================================================== */

/* {====================================================================
** The sandbox and protected metatables
** ===================================================================== */

BSFIT_API int bsfit_lua_sandboxed(lua_State *L) {
  int on;
  lua_getfield(L, LUA_REGISTRYINDEX, BSFIT_LUA_SANDBOX);
  on = lua_toboolean(L, -1);
  lua_pop(L, 1);
  return on;
}

void bsfit__lua_check_files(lua_State *L, const char *what) {
  if (bsfit_lua_sandboxed(L))
    luaL_error(L, "%s: file access is not allowed in the sandbox", what);
}

/* getmetatable(obj) answers a fresh table holding only __name: scripts still read
** the type name, but writing to it (a looping __gc, a changed method) changes
** nothing that the binding uses. Finalizers run with hooks off, so a writable
** __gc would be a way around the engine's limits. */
void bsfit__lua_protect_metatable(lua_State *L, int mt) {
  mt = lua_absindex(L, mt);
  lua_createtable(L, 0, 1);
  lua_getfield(L, mt, "__name");
  lua_setfield(L, -2, "__name");
  lua_setfield(L, mt, "__metatable");
}

void bsfit__lua_protect_metatables(lua_State *L) {
  lua_pushnil(L);
  while (lua_next(L, LUA_REGISTRYINDEX) != 0) {
    if (lua_type(L, -2) == LUA_TSTRING && strncmp(lua_tostring(L, -2), "bsfit.", 6) == 0 &&
        lua_istable(L, -1)) {
      if (lua_getfield(L, -1, "__metatable") == LUA_TNIL) bsfit__lua_protect_metatable(L, -2);
      lua_pop(L, 1);
    }
    lua_pop(L, 1); /* the value; the key stays for lua_next */
  }
}

/* }==================================================================== */

/* {====================================================================
** Option tables
** ===================================================================== */

void bsfit__lua_check_options(lua_State *L, int t, const char *const names[]) {
  if (t == 0) return;
  lua_pushnil(L);
  while (lua_next(L, t) != 0) {
    size_t i;
    int known = 0;
    lua_pop(L, 1); /* the value */
    if (lua_type(L, -1) != LUA_TSTRING)
      luaL_argerror(L, t, lua_pushfstring(L, "option names must be strings, got %s",
                                          luaL_typename(L, -1)));
    for (i = 0; names[i] != NULL && !known; i++) known = strcmp(names[i], lua_tostring(L, -1)) == 0;
    if (!known) luaL_argerror(L, t, lua_pushfstring(L, "unknown option '%s'", lua_tostring(L, -1)));
  }
}

int bsfit__lua_field(lua_State *L, int t, const char *k) {
  if (t == 0) {
    lua_pushnil(L);
    return LUA_TNIL;
  }
  return lua_getfield(L, t, k);
}

int bsfit__lua_opttable(lua_State *L, int arg, const char *const names[]) {
  if (lua_isnoneornil(L, arg)) return 0;
  luaL_checktype(L, arg, LUA_TTABLE);
  bsfit__lua_check_options(L, arg, names);
  return arg;
}

static int field_error(lua_State *L, int t, const char *k, const char *what) {
  return luaL_argerror(L, t, lua_pushfstring(L, "field '%s' must be %s", k, what));
}

lua_Number bsfit__lua_opt_number(lua_State *L, int t, const char *k, lua_Number def) {
  lua_Number v = def;
  int ok = 1;
  if (bsfit__lua_field(L, t, k) != LUA_TNIL) v = lua_tonumberx(L, -1, &ok);
  if (!ok || lua_type(L, -1) == LUA_TSTRING) field_error(L, t, k, "a number");
  lua_pop(L, 1);
  return v;
}

lua_Integer bsfit__lua_opt_integer(lua_State *L, int t, const char *k, lua_Integer def) {
  lua_Integer v = def;
  int ok = 1;
  if (bsfit__lua_field(L, t, k) != LUA_TNIL) v = lua_tointegerx(L, -1, &ok);
  if (!ok || lua_type(L, -1) == LUA_TSTRING) field_error(L, t, k, "an integer");
  lua_pop(L, 1);
  return v;
}

lua_Integer bsfit__lua_req_integer(lua_State *L, int t, const char *k) {
  lua_Integer v;
  if (bsfit__lua_field(L, t, k) == LUA_TNIL)
    luaL_argerror(L, t, lua_pushfstring(L, "field '%s' is required", k));
  lua_pop(L, 1);
  v = bsfit__lua_opt_integer(L, t, k, 0);
  return v;
}

int bsfit__lua_opt_boolean(lua_State *L, int t, const char *k, int def) {
  int v = def, ty = bsfit__lua_field(L, t, k);
  if (ty == LUA_TBOOLEAN) v = lua_toboolean(L, -1);
  else if (ty != LUA_TNIL) field_error(L, t, k, "a boolean");
  lua_pop(L, 1);
  return v;
}

const char *bsfit__lua_opt_string(lua_State *L, int t, const char *k, const char *def) {
  const char *v = def;
  int ty = bsfit__lua_field(L, t, k);
  if (ty == LUA_TSTRING) v = lua_tostring(L, -1); /* stays alive: the table holds it */
  else if (ty != LUA_TNIL) field_error(L, t, k, "a string");
  lua_pop(L, 1);
  return v;
}

/* }==================================================================== */

/* {====================================================================
** Indices and sizes
** ===================================================================== */

/* %g, as the core formats numbers (lua_pushfstring's %f prints 14 digits) */
static const char *number_text(lua_State *L, double x) {
  char buf[32];
  snprintf(buf, sizeof buf, "%g", x);
  return lua_pushstring(L, buf);
}

size_t bsfit__lua_index(lua_State *L, int arg, size_t n) {
  lua_Integer i = luaL_checkinteger(L, arg);
  if (i < 0 && (lua_Unsigned)(-(i + 1)) < (lua_Unsigned)n) return n - (size_t)(-(i + 1)) - 1;
  if (i > 0 && (lua_Unsigned)i <= (lua_Unsigned)n) return (size_t)(i - 1);
  return (size_t)luaL_argerror(L, arg, lua_pushfstring(L, "index %I out of range 1..%I", i,
                                                       (lua_Integer)n));
}

size_t bsfit__lua_checkcount(lua_State *L, int arg, lua_Integer lo, lua_Integer hi) {
  lua_Integer v = luaL_checkinteger(L, arg);
  if (v < lo || v > hi)
    luaL_argerror(L, arg, lua_pushfstring(L, "count %I out of range %I..%I", v, lo, hi));
  return (size_t)v;
}

void bsfit__lua_checkfinite(lua_State *L, int arg, const bsfit_points_ud *P) {
  size_t i, len = P->n * P->dim;
  for (i = 0; i < len; i++) {
    if (!isfinite(P->xy[i]))
      luaL_argerror(L, arg, lua_pushfstring(L, "point %I has a non-finite coordinate",
                                            (lua_Integer)(i / P->dim) + 1));
    if (fabs(P->xy[i]) > BSFIT_COORD_MAX) /* the core's range (docs/robustness-core.md) */
      luaL_argerror(L, arg, lua_pushfstring(L, "point %I has a coordinate %s beyond 1e100",
                                            (lua_Integer)(i / P->dim) + 1,
                                            number_text(L, P->xy[i])));
  }
}

void bsfit__lua_checkknotvalues(lua_State *L, int arg, const double *U, size_t n, int p) {
  size_t i, run = 1;
  for (i = 0; i < n; i++)
    if (!isfinite(U[i]))
      luaL_argerror(L, arg, lua_pushfstring(L, "knot %I is not finite", (lua_Integer)i + 1));
  for (i = 1; i < n; i++) {
    if (U[i] < U[i - 1])
      luaL_argerror(L, arg, lua_pushfstring(L, "knots decrease at knot %I (%s < %s)",
                                            (lua_Integer)i + 1, number_text(L, U[i]),
                                            number_text(L, U[i - 1])));
    run = U[i] == U[i - 1] ? run + 1 : 1;
    if (p >= 0 && run == (size_t)p + 2)
      luaL_argerror(L, arg, lua_pushfstring(L, "knots %I..%I equal %s: multiplicity above "
                                            "degree+1 = %d", (lua_Integer)(i + 2 - run),
                                            (lua_Integer)i + 1, number_text(L, U[i]), p + 1));
  }
}

void bsfit__lua_checkparams(lua_State *L, int arg, const double *u, size_t n) {
  size_t i;
  for (i = 0; i < n; i++)
    if (!isfinite(u[i]))
      luaL_argerror(L, arg, lua_pushfstring(L, "parameter %I is not finite", (lua_Integer)i + 1));
  for (i = 1; i < n; i++)
    if (u[i] < u[i - 1])
      luaL_argerror(L, arg, lua_pushfstring(L, "parameters decrease at parameter %I (%s < %s)",
                                            (lua_Integer)i + 1, number_text(L, u[i]),
                                            number_text(L, u[i - 1])));
}

int bsfit__lua_pushbadweight(lua_State *L, const double *w, size_t n) {
  size_t i;
  for (i = 0; i < n; i++)
    if (!(w[i] > 0.0 && isfinite(w[i]))) { /* NaN fails the first test */
      lua_pushfstring(L, "weight %I is %s (must be positive and finite)", (lua_Integer)i + 1,
                      number_text(L, w[i]));
      return 1;
    }
  return 0;
}

void bsfit__lua_checkweights(lua_State *L, int arg, const double *w, size_t n) {
  if (bsfit__lua_pushbadweight(L, w, n)) luaL_argerror(L, arg, lua_tostring(L, -1));
}

/* }==================================================================== */
