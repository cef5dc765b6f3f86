/*
** lgeom.c
** bs.params and bs.geom: the kernels on point sequences that are not methods of one
** type (docs/method.md §2, §7-10 and issue 7, src/bsfit_geom.h, src/bsfit_analysis.h):
**   bs.params(P [, "uniform"|"chord"|"centripetal" [, {closed = false}]]) --> Vector
**   bs.geom.circumradius(P [, {closed = true, centered = true}]) --> Vector (inf: straight)
**   bs.geom.angles(P [, {closed = true}])                        --> Vector (degrees)
**   bs.geom.inflections(P [, {closed = true}])                   --> integer
**   bs.geom.noise_sigma(P [, {closed = true}])                   --> sigma
**   bs.geom.longest_step(P [, {closed = true}])                  --> the longest step
**   bs.geom.corners(P [, {closed = true, sigma =, min_angle =, scale =}])
**                                       --> table of 1-based indices, Vector of turns (degrees)
**   bs.geom.project(P, origin, dir)      --> x, y[, z]   (points given as tables)
**   bs.geom.line_distance(P, origin, dir) --> distance
** P is a bsfit.Points of dim 2 or 3 or a table of points. In bs.geom `closed`
** defaults to true, because the points are cross-sections whose last point joins the
** first; bs.params keeps false, as parameters also serve open curves. The loops run
** in the core and write straight into the result's block.
*/
#include "laux.h"

#include <math.h>
#include <string.h>

/* {====================================================================
** Parameters
** ===================================================================== */

/* bs.params(P [, kind [, {closed = false}]]) --> Vector; all points coincident gives
** the fail triple (EDEGENERATE) */
static int l_params(lua_State *L) {
  static const char *const kinds[] = {"uniform", "chord", "centripetal", NULL};
  static const bsfit_param_kind kind_of[] = {BSFIT_PARAM_UNIFORM, BSFIT_PARAM_CHORD,
                                             BSFIT_PARAM_CENTRIPETAL};
  static const char *const opts[] = {"closed", NULL};
  bsfit_points_ud *P = bsfit__lua_topoints(L, 1);
  int kind = luaL_checkoption(L, 2, "chord", kinds);
  int t = bsfit__lua_opttable(L, 3, opts);
  int closed = opt_boolean(L, t, "closed", 0);
  bsfit_vector_ud *u;
  bsfit_status st;
  bsfit_err e;
  bsfit__lua_checkfinite(L, 1, P);
  u = bsfit__lua_newvector(L, P->n);
  e = bsfit_params(P->xy, P->n, (int)P->dim, kind_of[kind], closed, u->x, &st);
  return bsfit__lua_result(L, e, &st, 1, 1);
}

/* }==================================================================== */

/* {====================================================================
** Per-point kernels
** ===================================================================== */

static const char *const opts_closed[] = {"closed", NULL};
static const char *const opts_radius[] = {"closed", "centered", NULL};

/* Points at 1 (checked finite) and the `closed` option of the table at 2 (names
** allowed: `names`); *t receives the table's index (0: none). */
static bsfit_points_ud *kernel_args(lua_State *L, const char *const names[], int *t,
                                    int *closed) {
  bsfit_points_ud *P = bsfit__lua_topoints(L, 1);
  *t = bsfit__lua_opttable(L, 2, names);
  *closed = opt_boolean(L, *t, "closed", 1);
  bsfit__lua_checkfinite(L, 1, P);
  return P;
}

static int geom_circumradius(lua_State *L) {
  int t, closed;
  bsfit_points_ud *P = kernel_args(L, opts_radius, &t, &closed);
  int centered = opt_boolean(L, t, "centered", 1);
  bsfit_vector_ud *r = bsfit__lua_newvector(L, P->n);
  bsfit_status st;
  bsfit_err e = bsfit_geom_circumradius(P->xy, P->n, (int)P->dim, closed, centered, r->x, &st);
  return bsfit__lua_result(L, e, &st, 1, 1);
}

static int geom_angles(lua_State *L) {
  int t, closed;
  bsfit_points_ud *P = kernel_args(L, opts_closed, &t, &closed);
  bsfit_vector_ud *a = bsfit__lua_newvector(L, P->n);
  bsfit_status st;
  bsfit_err e = bsfit_geom_angles(P->xy, P->n, (int)P->dim, closed, a->x, &st);
  return bsfit__lua_result(L, e, &st, 1, 1);
}

/* number of turn-direction sign changes (docs/method.md §9-10) */
static int geom_inflections(lua_State *L) {
  int t, closed;
  bsfit_points_ud *P = kernel_args(L, opts_closed, &t, &closed);
  size_t count = 0;
  bsfit_status st;
  bsfit_err e = bsfit_geom_inflections(P->xy, P->n, (int)P->dim, closed, &count, &st);
  lua_pushinteger(L, (lua_Integer)count);
  return bsfit__lua_result(L, e, &st, 1, 1);
}

/* the longest step between consecutive points, the closing one too when closed */
static int geom_longest_step(lua_State *L) {
  int t, closed;
  bsfit_points_ud *P = kernel_args(L, opts_closed, &t, &closed);
  double h = 0.0;
  bsfit_status st;
  bsfit_err e = bsfit_geom_longest_step(P->xy, P->n, (int)P->dim, closed, &h, &st);
  lua_pushnumber(L, h);
  return bsfit__lua_result(L, e, &st, 1, 1);
}

/* standard deviation of the noise normal to the contour; EDEGENERATE (no window of
** distinct points) is an outcome: the fail triple */
static int geom_noise_sigma(lua_State *L) {
  int t, closed;
  bsfit_points_ud *P = kernel_args(L, opts_closed, &t, &closed);
  double sigma = 0.0;
  bsfit_status st;
  bsfit_allocator a = bsfit__lua_allocator(L);
  bsfit_err e = bsfit_noise_sigma(P->xy, P->n, (int)P->dim, closed, &sigma, &a, &st);
  lua_pushnumber(L, sigma);
  return bsfit__lua_result(L, e, &st, 1, 1);
}

/* a non-negative finite option (0 = automatic); `hi` excluded when > 0 */
static double opt_nonneg(lua_State *L, int t, const char *k, double hi) {
  double v = opt_number(L, t, k, 0.0);
  if (!(v >= 0.0 && isfinite(v)) || (hi > 0.0 && v >= hi))
    luaL_argerror(L, t, lua_pushfstring(L, hi > 0.0 ? "field '%s' must be in [0, %d)"
                                                    : "field '%s' must be finite and >= 0",
                                        k, (int)hi));
  return v;
}

/* bs.geom.corners(P [, opts]) --> {i1, i2, ...} (increasing, 1-based), Vector of the
** turns in degrees, Vector of the positions (1-based fractional indices: where each
** corner lies between samples), Points of the corner points (where the sides meet).
** The core writes at most m corners into a scratch userdata (Lua's memory, R4)
** before the exact-size results are made. */
static int geom_corners(lua_State *L) {
  static const char *const opts[] = {"closed", "sigma", "min_angle", "scale", NULL};
  int t, closed;
  bsfit_points_ud *P = kernel_args(L, opts, &t, &closed);
  bsfit_corner_opts o;
  bsfit_corner *found;
  size_t count = 0, k, d, cap = P->n > 0 ? P->n : 1;
  bsfit_vector_ud *turns, *where;
  bsfit_points_ud *at;
  bsfit_allocator al = bsfit__lua_allocator(L); /* scratch counted by the engine's cap */
  bsfit_status st;
  bsfit_err e;
  memset(&o, 0, sizeof o);
  o.closed = closed;
  o.sigma = opt_nonneg(L, t, "sigma", 0.0);
  o.min_angle_deg = opt_nonneg(L, t, "min_angle", 180.0);
  o.scale = opt_nonneg(L, t, "scale", 0.0);
  found = (bsfit_corner *)lua_newuserdatauv(L, cap * sizeof(bsfit_corner), 0);
  e = bsfit_corners_detect(P->xy, P->n, (int)P->dim, &o, found, cap, &count, &al, &st);
  if (e != BSFIT_OK) return bsfit__lua_result(L, e, &st, 0, 1);
  if (count > cap) count = cap; /* cannot happen: one corner per point at most */
  lua_createtable(L, (int)count, 0);
  turns = bsfit__lua_newvector(L, count);
  where = bsfit__lua_newvector(L, count);
  at = bsfit__lua_newpoints(L, count, P->dim);
  for (k = 0; k < count; k++) {
    lua_pushinteger(L, (lua_Integer)found[k].index + 1);
    lua_rawseti(L, -5, (lua_Integer)k + 1);
    turns->x[k] = found[k].angle;
    where->x[k] = found[k].position + 1;
    for (d = 0; d < P->dim; d++) at->xy[k * P->dim + d] = found[k].point[d];
  }
  return 4;
}

/* }==================================================================== */

/* {====================================================================
** Line kernels on single points given as tables {x, y[, z]}
** ===================================================================== */

/* a point argument: table of 2 or 3 numbers; returns its dimension */
static int checkpoint(lua_State *L, int arg, double *x) {
  int k, n;
  luaL_checktype(L, arg, LUA_TTABLE);
  n = (int)luaL_len(L, arg);
  if (n < 2 || n > 3) luaL_argerror(L, arg, "point of 2 or 3 coordinates expected");
  for (k = 0; k < n; k++) {
    int ok;
    lua_geti(L, arg, k + 1);
    x[k] = lua_tonumberx(L, -1, &ok);
    if (!ok || lua_type(L, -1) != LUA_TNUMBER) luaL_argerror(L, arg, "coordinates must be numbers");
    lua_pop(L, 1);
  }
  return n;
}

static int check3(lua_State *L, double *P, double *O, double *D) {
  int d = checkpoint(L, 1, P);
  if (checkpoint(L, 2, O) != d) luaL_argerror(L, 2, "dimension differs from argument #1");
  if (checkpoint(L, 3, D) != d) luaL_argerror(L, 3, "dimension differs from argument #1");
  return d;
}

/* bs.geom.project(P, origin, dir) --> x, y[, z]: P projected onto the line; a zero
** direction is the fail triple (EDEGENERATE) */
static int geom_project(lua_State *L) {
  double P[3], O[3], D[3], out[3];
  int d = check3(L, P, O, D), k;
  bsfit_status st;
  bsfit_err e = bsfit_geom_tangent_project(P, O, D, d, out, &st);
  if (e != BSFIT_OK) return bsfit__lua_result(L, e, &st, 0, 0);
  for (k = 0; k < d; k++) lua_pushnumber(L, out[k]);
  return d;
}

/* bs.geom.line_distance(P, origin, dir) --> distance */
static int geom_line_distance(lua_State *L) {
  double P[3], O[3], D[3], dist = 0.0;
  int d = check3(L, P, O, D);
  bsfit_status st;
  bsfit_err e = bsfit_geom_line_distance(P, O, D, d, &dist, &st);
  lua_pushnumber(L, dist);
  return bsfit__lua_result(L, e, &st, 1, 0);
}

/* }==================================================================== */

/* {====================================================================
** Registration
** ===================================================================== */

static const luaL_Reg geom_funcs[] = {
  {"circumradius", geom_circumradius}, {"angles", geom_angles},
  {"inflections", geom_inflections},   {"noise_sigma", geom_noise_sigma},
  {"longest_step", geom_longest_step},
  {"corners", geom_corners},           {"project", geom_project},
  {"line_distance", geom_line_distance}, {NULL, NULL}};

/* sets bs.params and bs.geom in the module table on the stack top */
void bsfit__lua_lib_geom(lua_State *L) {
  lua_pushcfunction(L, l_params);
  lua_setfield(L, -2, "params");
  luaL_newlib(L, geom_funcs);
  lua_setfield(L, -2, "geom");
}

/* }==================================================================== */
