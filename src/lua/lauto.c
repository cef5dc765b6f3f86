/*
** lauto.c
** Lua access to the kernels of the automatic strategy (src/bsfit_analysis.h):
**   bs.params_trusted(P [, kind [, {closed = true, weights = w, trust = 0.1}]]) --> Vector
**   bs.knots.breaks{params = u, degree = 3, count = N, breaks = {i, ...}} --> Vector, N
** (one period of knots with triple knots at the corner points i, 1-based, and the
** number N of distinct control points actually placed after the empty-span guard).
*/
#include "laux.h"

#include <string.h>

_Static_assert(sizeof(size_t) == sizeof(double), "corner indices are stored in a Vector block");

/* bs.params_trusted(P [, kind [, opts]]) */
static int auto_params_trusted(lua_State *L) {
  static const char *const kinds[] = {"uniform", "chord", "centripetal", NULL};
  static const char *const names[] = {"closed", "weights", "trust", NULL};
  bsfit_points_ud *P = bsfit__lua_topoints(L, 1);
  int kind = luaL_checkoption(L, 2, "chord", kinds);
  int t = bsfit__lua_opttable(L, 3, names);
  int closed = opt_boolean(L, t, "closed", 1);
  lua_Number trust = opt_number(L, t, "trust", 0.1);
  const double *w = NULL;
  bsfit_vector_ud *u;
  bsfit_status st;
  bsfit_err e;
  if (bsfit__lua_field(L, t, "weights") != LUA_TNIL) {
    bsfit_vector_ud *wv = bsfit__lua_tovector(L, lua_gettop(L));
    if (wv->n != P->n)
      return luaL_argerror(L, 3, lua_pushfstring(L, "field 'weights' has %d values for %d points",
                                                 (int)wv->n, (int)P->n));
    bsfit__lua_checkweights(L, 3, wv->x, wv->n);
    w = wv->x;
  }
  luaL_argcheck(L, trust >= 0 && trust < 1, 3, "field 'trust' must be in [0, 1)");
  bsfit__lua_checkfinite(L, 1, P);
  u = bsfit__lua_newvector(L, P->n);
  e = bsfit_params_trusted(P->xy, P->n, (int)P->dim, (bsfit_param_kind)kind, closed, w, trust,
                           u->x, &st);
  return bsfit__lua_result(L, e, &st, 1, 1);
}

/* the corner indices of field 'breaks' (1-based numbers in a table or Vector), 0-based
** into a scratch Vector left on the stack */
static bsfit_vector_ud *read_breaks(lua_State *L, int t, size_t m, size_t *nb) {
  bsfit_vector_ud *in, *out;
  size_t i;
  if (bsfit__lua_field(L, t, "breaks") == LUA_TNIL) {
    lua_pop(L, 1);
    *nb = 0;
    return bsfit__lua_newvector(L, 0);
  }
  in = bsfit__lua_tovector(L, lua_gettop(L));
  out = bsfit__lua_newvector(L, in->n);
  for (i = 0; i < in->n; i++) {
    double b = in->x[i];
    if (!(b >= 1 && b <= (double)m && b == (double)(size_t)b))
      luaL_argerror(L, t, lua_pushfstring(L, "field 'breaks': entry %d is not a point index 1..%d",
                                          (int)i + 1, (int)m));
    out->x[i] = b - 1;
  }
  *nb = in->n;
  return out;
}

/* bs.knots.breaks{params =, degree =, count =, breaks =} */
static int auto_knots_breaks(lua_State *L) {
  static const char *const names[] = {"params", "degree", "count", "breaks", NULL};
  bsfit_vector_ud *u, *bv, *period;
  lua_Integer p, n;
  size_t nb, i, N = 0, *idx;
  bsfit_status st;
  bsfit_err e;
  luaL_checktype(L, 1, LUA_TTABLE);
  bsfit__lua_check_options(L, 1, names);
  if (bsfit__lua_field(L, 1, "params") == LUA_TNIL) return luaL_argerror(L, 1, "field 'params' is required");
  u = bsfit__lua_tovector(L, lua_gettop(L));
  p = opt_integer(L, 1, "degree", 3);
  n = req_integer(L, 1, "count");
  luaL_argcheck(L, p >= 1 && p <= BSFIT_MAX_DEGREE, 1, "field 'degree' out of range");
  luaL_argcheck(L, n >= 2 && n <= (lua_Integer)(1 << 28), 1, "field 'count' out of range");
  bv = read_breaks(L, 1, u->n, &nb);
  /* size_t indices live in a second scratch vector's storage (same size as doubles) */
  {
    bsfit_vector_ud *iv = bsfit__lua_newvector(L, nb);
    idx = (size_t *)(void *)iv->x;
    for (i = 0; i < nb; i++) idx[i] = (size_t)bv->x[i];
  }
  period = bsfit__lua_newvector(L, (size_t)n + 1);
  e = bsfit_knots_place_breaks(u->x, u->n, (int)p, (size_t)n, idx, nb, period->x, &N, &st);
  if (e != BSFIT_OK) return bsfit__lua_result(L, e, &st, 0, 1);
  period->n = N + 1; /* the guard may have merged spans: shrink the visible length */
  lua_pushinteger(L, (lua_Integer)N);
  return 2;
}

void bsfit__lua_lib_auto(lua_State *L) {
  lua_pushcfunction(L, auto_params_trusted);
  lua_setfield(L, -2, "params_trusted");
  if (lua_getfield(L, -1, "knots") == LUA_TTABLE) {
    lua_pushcfunction(L, auto_knots_breaks);
    lua_setfield(L, -2, "breaks");
  }
  lua_pop(L, 1);
}
