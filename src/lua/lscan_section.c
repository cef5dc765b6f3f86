/*
** lscan_section.c
** bs.scan, the steps on one section's points: the centre-of-mass reduction, the
** ordering into loops, and one IGES file of several curves.
**
**   local R, w, cell = bs.scan.reduce(P, {cell = C | target = N, weights = w})
**   local loops, rep = bs.scan.order(P, {method = "auto"|"angle"|"graph", k = 8, gap = 4,
**                                        min_points = 3})
**   bs.scan.write_iges(path, {C1, C2, ...})       -- one IGES file, one entity 126 per curve
*/
#include "lscan.h"

#include <math.h>
#include <stdint.h>
#include <string.h>

/* {====================================================================
** Reduction and ordering
** ===================================================================== */

static const char *const reduce_opts[] = {"cell", "target", "weights", NULL};

/* bs.scan.reduce(P, {cell = C | target = N, weights = w}) --> R, w, cell */
static int scan_reduce(lua_State *L) {
  bsfit_points_ud *P = bsfit__lua_checkpoints(L, 1), *R;
  bsfit_vector_ud *W = NULL, *RW;
  int t = bsfit__lua_opttable(L, 2, reduce_opts);
  double cell = opt_number(L, t, "cell", 0), *buf;
  lua_Integer target = opt_integer(L, t, "target", 0);
  size_t m = P->n, n = 0;
  bsfit_status st;
  bsfit_allocator a = bsfit__lua_allocator(L);
  bsfit_err e;
  luaL_argcheck(L, P->dim == 2, 1, "2D points expected (a section in its plane)");
  luaL_argcheck(L, m >= 1, 1, "no points");
  luaL_argcheck(L, (cell > 0) != (target > 0), 2,
                "give exactly one of cell (> 0) and target (>= 1)");
  luaL_argcheck(L, cell == 0 || isfinite(cell), 2, "field 'cell' must be finite");
  if (bsfit__lua_field(L, t, "weights") != LUA_TNIL) {
    W = bsfit__lua_tovector(L, lua_gettop(L));
    luaL_argcheck(L, W->n == m, 2, "field 'weights' must hold one weight per point");
    bsfit__lua_checkweights(L, 2, W->x, m);
  }
  bsfit__lua_checkfinite(L, 1, P);
  luaL_argcheck(L, m <= SIZE_MAX / (3 * sizeof(double)), 1, "too many points");
  buf = (double *)lua_newuserdatauv(L, 3 * m * sizeof(double), 0);
  if (cell > 0)
    e = bsfit_reduce_grid(P->xy, m, W ? W->x : NULL, cell, buf, buf + 2 * m, &n, &a, &st);
  else
    e = bsfit_reduce_target(P->xy, m, W ? W->x : NULL, (size_t)target, &cell, buf, buf + 2 * m, &n,
                            &a, &st);
  if (e == BSFIT_EDEGENERATE) return bsfit__lua_result(L, e, &st, 0, 0);
  if (e != BSFIT_OK) return bsfit__lua_raise(L, e, &st, 2);
  R = bsfit__lua_allocpoints(L, n, 2);
  memcpy(R->xy, buf, 2 * n * sizeof(double));
  RW = bsfit__lua_allocvector(L, n);
  memcpy(RW->x, buf + 2 * m, n * sizeof(double));
  lua_pushnumber(L, cell);
  return 3;
}

static const char *const order_opts[] = {"method", "k", "gap", "min_points", NULL};
static const char *const method_names[] = {"auto", "angle", "graph", NULL};

/* The report table of an ordering. */
static void push_order_report(lua_State *L, const bsfit_order_result *r) {
  size_t l, open = 0;
  for (l = 0; l < r->nloops; l++) open += !r->closed[l];
  lua_createtable(L, 0, 6);
  lua_pushstring(L, r->method == BSFIT_ORDER_ANGLE ? "angle" : "graph");
  lua_setfield(L, -2, "method");
  lua_pushboolean(L, r->star);
  lua_setfield(L, -2, "star");
  lua_pushinteger(L, (lua_Integer)r->nloops);
  lua_setfield(L, -2, "loops");
  lua_pushinteger(L, (lua_Integer)open);
  lua_setfield(L, -2, "open");
  lua_pushinteger(L, (lua_Integer)r->dropped);
  lua_setfield(L, -2, "dropped");
  if (r->nloops == 1 && open == 0)
    lua_pushstring(L, "one closed loop");
  else
    lua_pushfstring(L, "%d loops, %d of them open (a C shape or a hole in the scan)",
                    (int)r->nloops, (int)open);
  lua_setfield(L, -2, "message");
}

/* bs.scan.order(P, opts) --> {{points = Points, closed = bool, index = {...}}, ...}, report */
static int scan_order(lua_State *L) {
  bsfit_points_ud *P = bsfit__lua_checkpoints(L, 1);
  int t = bsfit__lua_opttable(L, 2, order_opts);
  bsfit_order_opts o;
  tmp_ud *tmp;
  bsfit_status st;
  bsfit_allocator a = bsfit__lua_allocator(L);
  bsfit_err e;
  size_t l, q;
  const char *meth = opt_string(L, t, "method", "auto");
  bsfit_order_opts_init(&o);
  for (q = 0; method_names[q] != NULL && strcmp(method_names[q], meth) != 0; q++) {
  }
  if (method_names[q] == NULL)
    luaL_argerror(
        L, 2, lua_pushfstring(L, "field 'method' must be auto, angle or graph, got '%s'", meth));
  o.method = (bsfit_order_method)q;
  o.k = (int)opt_integer(L, t, "k", 8);
  o.gap = opt_number(L, t, "gap", 4);
  o.min_points = (size_t)opt_integer(L, t, "min_points", 3);
  luaL_argcheck(L, o.k >= 2 && o.k <= 32, 2, "field 'k' must be in 2..32");
  luaL_argcheck(L, o.gap >= 1 && isfinite(o.gap), 2, "field 'gap' must be >= 1");
  luaL_argcheck(L, P->dim == 2, 1, "2D points expected (a section in its plane)");
  luaL_argcheck(L, P->n >= 1, 1, "no points");
  bsfit__lua_checkfinite(L, 1, P);
  tmp = bsfit__lua_scan_tmp(L);
  e = bsfit_order(P->xy, P->n, &o, &tmp->ord, &a, &st);
  if (e == BSFIT_ETOOFEW || (e == BSFIT_EINVAL && o.method == BSFIT_ORDER_ANGLE)) {
    luaL_pushfail(L);
    lua_pushstring(L, st.msg);
    lua_pushstring(L, bsfit_errname(e));
    return 3;
  }
  if (e != BSFIT_OK) return bsfit__lua_raise(L, e, &st, 0);
  lua_createtable(L, (int)tmp->ord.nloops, 0);
  for (l = 0; l < tmp->ord.nloops; l++) {
    size_t s = tmp->ord.start[l], n = tmp->ord.start[l + 1] - s;
    bsfit_points_ud *R;
    lua_createtable(L, 0, 3);
    R = bsfit__lua_allocpoints(L, n, 2);
    lua_createtable(L, (int)n, 0);
    for (q = 0; q < n; q++) {
      size_t i = tmp->ord.index[s + q];
      R->xy[2 * q] = P->xy[2 * i];
      R->xy[2 * q + 1] = P->xy[2 * i + 1];
      lua_pushinteger(L, (lua_Integer)i + 1);
      lua_seti(L, -2, (lua_Integer)q + 1);
    }
    lua_setfield(L, -3, "index");
    lua_setfield(L, -2, "points");
    lua_pushboolean(L, tmp->ord.closed[l]);
    lua_setfield(L, -2, "closed");
    lua_seti(L, -2, (lua_Integer)l + 1);
  }
  push_order_report(L, &tmp->ord);
  bsfit_order_result_free(&tmp->ord);
  return 2;
}

/* }==================================================================== */

/* {====================================================================
** Writing the curves of the sections
** ===================================================================== */

/* bs.scan.write_iges(path, {C1, C2, ...}) --> true, or nil, msg, code (file errors) */
static int scan_write_iges(lua_State *L) {
  const char *path = luaL_checkstring(L, 1);
  size_t n, i;
  const bsfit_curve **cs;
  bsfit_status st;
  bsfit_err e;
  luaL_checktype(L, 2, LUA_TTABLE);
  n = (size_t)luaL_len(L, 2);
  luaL_argcheck(L, n >= 1, 2, "no curves");
  luaL_argcheck(L, n <= SIZE_MAX / sizeof *cs, 2, "too many curves");
  cs = (const bsfit_curve **)lua_newuserdatauv(L, n * sizeof *cs, 0);
  for (i = 0; i < n; i++) {
    lua_geti(L, 2, (lua_Integer)i + 1);
    cs[i] = bsfit__lua_checkcurve(L, lua_gettop(L)); /* the table keeps it alive */
    lua_pop(L, 1);
  }
  e = bsfit_curves_write_iges(cs, n, path, &st);
  if (e == BSFIT_OK) {
    lua_pushboolean(L, 1);
    return 1;
  }
  return bsfit__lua_result(L, e, &st, 0, 2);
}

/* }==================================================================== */

/* {====================================================================
** Registration
** ===================================================================== */

static const luaL_Reg section_funcs[] = {
    {"reduce", scan_reduce}, {"order", scan_order}, {"write_iges", scan_write_iges}, {NULL, NULL}};

void bsfit__lua_scan_section_funcs(lua_State *L) {
  luaL_setfuncs(L, section_funcs, 0);
}

/* }==================================================================== */
