/*
** laux.c
** Helpers shared by the binding files: the single place where core status codes
** become Lua errors or fail triples (STYLE R3), the option-table readers that
** name the bad field (R6), the 1-based index rule and the Lua allocator (R7).
*/
#include "laux.h"

#include <math.h>
#include <stdio.h>
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

static const char *message_of(bsfit_err e, const bsfit_status *st) {
  if (st != NULL && st->code == e && st->msg[0] != '\0') return st->msg;
  return bsfit_strerror(e);
}

int bsfit__lua_raise(lua_State *L, bsfit_err e, const bsfit_status *st, int arg) {
  const char *msg = message_of(e, st);
  if (arg > 0) return luaL_argerror(L, arg, msg);
  return luaL_error(L, "%s", msg);
}

int bsfit__lua_result(lua_State *L, bsfit_err e, const bsfit_status *st, int nret, int arg) {
  if (e == BSFIT_OK) return nret;
  if (!is_outcome(e)) return bsfit__lua_raise(L, e, st, arg);
  luaL_pushfail(L);
  lua_pushstring(L, message_of(e, st));
  lua_pushstring(L, bsfit_errname(e));
  return 3;
}

bsfit_allocator bsfit__lua_allocator(lua_State *L) {
  bsfit_allocator a;
  a.fn = (bsfit_alloc_fn)lua_getallocf(L, &a.ud);
  a.interrupt = NULL;
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
  }
  lua_setmetatable(L, -2);
  return s;
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

void bsfit__lua_checkweights(lua_State *L, int arg, const double *w, size_t n) {
  size_t i;
  for (i = 0; i < n; i++)
    if (!(w[i] > 0.0 && isfinite(w[i]))) /* NaN fails the first test */
      luaL_argerror(L, arg, lua_pushfstring(L, "weight %I is %s (must be positive and finite)",
                                            (lua_Integer)i + 1, number_text(L, w[i])));
}

/* }==================================================================== */
