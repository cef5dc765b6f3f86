/*
** lauto.c
** Lua access to the kernels of the automatic strategy (src/bsfit_analysis.h):
**   bs.params_trusted(P [, kind [, {closed = true, weights = w, trust = 0.1}]]) --> Vector
**   bs.params_through_corners(P, u, positions, points [, kind [, {closed = true}]]) --> Vector
**   bs.knots.breaks{params = u, degree = 3, count = N, breaks = {x, ...}} --> Vector, N
** (one period of knots with knots of multiplicity `degree` at the corners x: 1-based
** fractional point positions, as the third result of bs.geom.corners; and the number
** N of distinct control points actually placed after the empty-span guard).
*/
#include "laux.h"

#include <string.h>

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
  {
    bsfit_allocator a = bsfit__lua_allocator(L);
    e = bsfit_params_trusted(P->xy, P->n, (int)P->dim, (bsfit_param_kind)kind, closed, w, trust,
                             u->x, &a, &st);
  }
  return bsfit__lua_result(L, e, &st, 1, 1);
}

/* the corners of field 'breaks': 1-based fractional point positions (a table or a
** Vector, as bs.geom.corners gives them) made 0-based in a new Vector on the stack */
static bsfit_vector_ud *read_breaks(lua_State *L, int t, size_t m) {
  bsfit_vector_ud *in, *out;
  size_t i;
  if (bsfit__lua_field(L, t, "breaks") == LUA_TNIL) return bsfit__lua_newvector(L, 0);
  in = bsfit__lua_tovector(L, lua_gettop(L));
  out = bsfit__lua_newvector(L, in->n);
  for (i = 0; i < in->n; i++) {
    double b = in->x[i];
    if (!(b >= 1 && b < (double)m + 1) || (i > 0 && !(b > in->x[i - 1])))
      luaL_argerror(L, t, lua_pushfstring(L, "field 'breaks': entry %d is not an increasing "
                                          "position in [1, %d]", (int)i + 1, (int)m));
    out->x[i] = b - 1;
  }
  return out;
}

/* bs.knots.breaks{params =, degree =, count =, breaks =} */
static int auto_knots_breaks(lua_State *L) {
  static const char *const names[] = {"params", "degree", "count", "breaks", NULL};
  bsfit_vector_ud *u, *bv, *scratch, *period;
  lua_Integer p, n;
  size_t N = 0;
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
  bv = read_breaks(L, 1, u->n);
  scratch = bsfit__lua_allocvector(L, (size_t)n + 1); /* room for the count asked */
  {
    bsfit_allocator a = bsfit__lua_allocator(L);
    e = bsfit_knots_place_breaks(u->x, u->n, (int)p, (size_t)n, bv->x, bv->n, scratch->x, &N,
                                 &a, &st);
  }
  /* too few points for the spans a fit needs is the data's outcome, not a misuse: the
  ** fail triple, for the strategy to report */
  if (e == BSFIT_ETOOFEW) {
    luaL_pushfail(L);
    lua_pushstring(L, st.msg);
    lua_pushstring(L, bsfit_errname(e));
    return 3;
  }
  if (e != BSFIT_OK) return bsfit__lua_result(L, e, &st, 0, 1);
  /* the guard may have merged spans: the result has the N + 1 knots actually placed */
  period = bsfit__lua_allocvector(L, N + 1);
  memcpy(period->x, scratch->x, (N + 1) * sizeof(double));
  lua_pushinteger(L, (lua_Integer)N);
  return 2;
}

/* bs.params_through_corners(P, u, positions, points [, kind [, {closed = true}]]) -->
** Vector: u made to agree with corners between samples (positions 1-based, as the
** third and fourth results of bs.geom.corners). u itself is not changed. */
static int auto_params_through_corners(lua_State *L) {
  static const char *const kinds[] = {"uniform", "chord", "centripetal", NULL};
  static const char *const names[] = {"closed", NULL};
  bsfit_points_ud *P = bsfit__lua_topoints(L, 1);
  bsfit_vector_ud *u = bsfit__lua_tovector(L, 2);
  bsfit_vector_ud *pos = bsfit__lua_tovector(L, 3);
  bsfit_points_ud *at = bsfit__lua_topoints(L, 4);
  int kind = luaL_checkoption(L, 5, "chord", kinds);
  int t = bsfit__lua_opttable(L, 6, names);
  int closed = opt_boolean(L, t, "closed", 1);
  bsfit_corner *corners;
  bsfit_vector_ud *out;
  bsfit_status st;
  size_t k, d;
  bsfit_err e;
  luaL_argcheck(L, u->n == P->n, 2, "one parameter per point expected");
  luaL_argcheck(L, at->n == pos->n && at->dim == P->dim, 4, "one corner point per position expected");
  corners = (bsfit_corner *)lua_newuserdatauv(L, (pos->n > 0 ? pos->n : 1) * sizeof(bsfit_corner), 0);
  for (k = 0; k < pos->n; k++) {
    memset(&corners[k], 0, sizeof corners[k]);
    corners[k].position = pos->x[k] - 1;
    for (d = 0; d < P->dim; d++) corners[k].point[d] = at->xy[k * P->dim + d];
  }
  out = bsfit__lua_newvector(L, P->n);
  memcpy(out->x, u->x, P->n * sizeof(double));
  e = bsfit_params_through_corners(P->xy, P->n, (int)P->dim, (bsfit_param_kind)kind, closed,
                                   corners, pos->n, out->x, &st);
  return bsfit__lua_result(L, e, &st, 1, 3);
}

void bsfit__lua_lib_auto(lua_State *L) {
  lua_pushcfunction(L, auto_params_trusted);
  lua_setfield(L, -2, "params_trusted");
  lua_pushcfunction(L, auto_params_through_corners);
  lua_setfield(L, -2, "params_through_corners");
  if (lua_getfield(L, -1, "knots") == LUA_TTABLE) {
    lua_pushcfunction(L, auto_knots_breaks);
    lua_setfield(L, -2, "breaks");
  }
  lua_pop(L, 1);
}
