/*
** lskin.c
** bs.surface.skin(sections [, {degree_v = 0, align = true, tol = 0}]) --> Surface, report
**   sections: a list of K >= 2 closed (periodic), polynomial, 3D curves.
**   report: {v_params = {v_1..v_K}, reversed = {bool..}, shifts = {s_1..s_K}}:
**   S:eval(u, v_params[k]) is section k at its parameter shifts[k] + (b-a) u (reversed:
**   shifts[k] - (b-a) u); with tol > 0 also count (the uniform cubics' count, 0: none
**   within tol, so exact) and max_deviation. Misuse (a bad list, open, rational or 2D sections) raises,
**   naming the section from 1; coincident sections give nil, message, "EDEGENERATE".
** The core is bsfit_surface_skin (src/core/surface_skin.c, docs/skinning.md).
*/
#include "laux.h"

#include <math.h>
#include <stdio.h>

/* The sections of the list at arg, checked, as an array of pointers in a userdata pushed
** on the stack (a raise cannot leak it). */
static const bsfit_curve *const *check_sections(lua_State *L, int arg, size_t *K) {
  const bsfit_curve **c;
  lua_Integer len, i;
  luaL_checktype(L, arg, LUA_TTABLE);
  len = luaL_len(L, arg);
  luaL_argcheck(L, len >= 2 && len <= 10000000, arg, "a list of at least 2 sections expected");
  c = (const bsfit_curve **)lua_newuserdatauv(L, (size_t)len * sizeof *c, 0);
  for (i = 1; i <= len; i++) {
    const bsfit_curve *ci;
    const char *why = NULL;
    lua_geti(L, arg, i);
    if (!luaL_testudata(L, -1, BSFIT_CURVE_T))
      luaL_argerror(L, arg, lua_pushfstring(L, "section %I is a %s, not a bsfit.Curve", i,
                                            luaL_typename(L, -1)));
    ci = bsfit__lua_checkcurve(L, -1);
    if (!ci->periodic) why = "is open (skinning needs closed, periodic sections)";
    else if (ci->weights != NULL) why = "is rational (skinning needs polynomial sections)";
    else if (ci->dim != 3) why = "is not 3D (map 2D sections to their planes first)";
    if (why != NULL) luaL_argerror(L, arg, lua_pushfstring(L, "section %I %s", i, why));
    c[i - 1] = ci;
    lua_pop(L, 1); /* the list keeps the curve alive */
  }
  *K = (size_t)len;
  return c;
}

static void push_numbers(lua_State *L, const double *x, size_t n) {
  size_t i;
  lua_createtable(L, (int)n, 0);
  for (i = 0; i < n; i++) {
    lua_pushnumber(L, x[i]);
    lua_rawseti(L, -2, (lua_Integer)i + 1);
  }
}

static int surface_skin(lua_State *L) {
  static const char *const opts[] = {"degree_v", "align", "tol", NULL};
  size_t K, k;
  const bsfit_curve *const *c;
  int t, align;
  lua_Integer q;
  lua_Number tol;
  luaL_checktype(L, 1, LUA_TTABLE);
  lua_settop(L, 2); /* the options stay at 2, the scratch goes above */
  t = bsfit__lua_opttable(L, 2, opts);
  q = opt_integer(L, t, "degree_v", 0);
  align = opt_boolean(L, t, "align", 1);
  tol = opt_number(L, t, "tol", 0);
  luaL_argcheck(L, tol >= 0 && tol < HUGE_VAL, t, "field 'tol' must be 0 (exact) or positive");
  c = check_sections(L, 1, &K);
  bsfit_skin_opts o;
  bsfit_skin_report rep;
  bsfit_surface_ud *ud;
  bsfit_allocator a;
  bsfit_status st;
  bsfit_err e;
  double *v, *shifts;
  int *rev;
  if (q < 0 || q > 3 || (q > 0 && (size_t)q > K - 1))
    return luaL_argerror(L, t, lua_pushfstring(L, "field 'degree_v' must be in 1..%d (%d sections)",
                                               K - 1 < 3 ? (int)K - 1 : 3, (int)K));
  bsfit_skin_opts_init(&o);
  o.degree_v = (int)q;
  o.align = align;
  o.tol = (double)tol;
  v = (double *)lua_newuserdatauv(L, K * (2 * sizeof(double) + sizeof(int)), 0);
  shifts = v + K;
  rev = (int *)(shifts + K);
  rep.v_params = v;
  rep.shifts = shifts;
  rep.reversed = rev;
  ud = bsfit__lua_newsurface(L, &a);
  e = bsfit_surface_skin(c, K, &o, &ud->s, &rep, &a, &st);
  if (e == BSFIT_EDEGENERATE && rep.bad_section != (size_t)-1) {
    luaL_pushfail(L);
    lua_pushfstring(L, "sections %d and %d coincide", (int)rep.bad_section,
                    (int)rep.bad_section + 1);
    lua_pushstring(L, bsfit_errname(e));
    return 3;
  }
  if (e != BSFIT_OK) return bsfit__lua_result(L, e, &st, 1, 1);
  lua_createtable(L, 0, 3);
  push_numbers(L, v, K);
  lua_setfield(L, -2, "v_params");
  push_numbers(L, shifts, K);
  lua_setfield(L, -2, "shifts");
  lua_createtable(L, (int)K, 0);
  for (k = 0; k < K; k++) {
    lua_pushboolean(L, rev[k]);
    lua_rawseti(L, -2, (lua_Integer)k + 1);
  }
  lua_setfield(L, -2, "reversed");
  if (o.tol > 0) {
    lua_pushinteger(L, (lua_Integer)rep.count);
    lua_setfield(L, -2, "count");
    lua_pushnumber(L, rep.max_deviation);
    lua_setfield(L, -2, "max_deviation");
  }
  return 2;
}

/* sets bs.surface.skin; bs.surface must exist (bsfit__lua_lib_surface runs first) */
void bsfit__lua_lib_skin(lua_State *L) {
  lua_getfield(L, -1, "surface");
  lua_pushcfunction(L, surface_skin);
  lua_setfield(L, -2, "skin");
  lua_pop(L, 1);
}
