/*
** lfeatures.c
** Lua access to the sharp-feature kernels (src/bsfit_features.h):
**   bs.geom.segment(P [, {closed = true, sigma = 0, tol_sigma = 4, exact = 1e-10,
**                         min_line = 3, min_arc = 4, param_cost = 32}]) --> table of pieces
**   bs.geom.self_intersections(C [, k = 2000]) --> number of crossings, parameter of one
**   bs.geom.piece_distances(C, P, pieces [, iters = 8]) --> Vector: each sample's distance
**        to the curve assembled from the pieces (their first, count and range = {lo, hi})
**   bs.curve.line(a, b)                                  --> Curve (degree 3)
**   bs.curve.arc{centre = {x, y}, radius = r, start = a0, sweep = s} --> Curve (NURBS)
**   bs.curve.join({C1, C2, ...}, {len1, len2, ...})      --> Curve
** A piece is {kind = "line"|"arc"|"free", join = "corner"|"tangent"|"end", first =,
** last =, count = (1-based samples; last < first when it wraps), start = {x, y},
** ["end"] = {x, y}, t_start =, t_end = (unit tangents), centre =, radius =, sweep =,
** radius_se = (arcs), turn = (degrees) and evidence = (sigma^2) at corner joins, rms =, max =
** (distances of its samples to its model; 0 for a free run)}.
**   bs.geom.segment_sigma(P [, {closed = true, max = 0}]) --> the noise of a section of
** lines and arcs, read off their own residuals (levels up to `max`; 0: 5% of the size;
** at most 500 evenly spread samples are read).
**   bs.geom.SEGMENT_SIGMA_STEP: the step between the levels of that search (10^(1/4)).
**   bs.geom.segment_start(P) --> the 1-based index a closed section is read from, whichever
** sample its data start at (after its longest step; ties: lowest x, then y).
*/
#include "laux.h"

#include <string.h>

static void set_pair(lua_State *L, const char *k, const double *x) {
  lua_createtable(L, 2, 0);
  lua_pushnumber(L, x[0]);
  lua_rawseti(L, -2, 1);
  lua_pushnumber(L, x[1]);
  lua_rawseti(L, -2, 2);
  lua_setfield(L, -2, k);
}

static void push_piece(lua_State *L, const bsfit_piece *p, size_t m) {
  static const char *const kinds[] = {"line", "arc", "free"};
  static const char *const joins[] = {"end", "corner", "tangent"};
  lua_createtable(L, 0, 14);
  lua_pushstring(L, kinds[p->kind]);
  lua_setfield(L, -2, "kind");
  lua_pushstring(L, joins[p->join]);
  lua_setfield(L, -2, "join");
  lua_pushinteger(L, (lua_Integer)p->first + 1);
  lua_setfield(L, -2, "first");
  lua_pushinteger(L, (lua_Integer)((p->first + (p->count ? p->count - 1 : 0)) % m) + 1);
  lua_setfield(L, -2, "last");
  lua_pushinteger(L, (lua_Integer)p->count);
  lua_setfield(L, -2, "count");
  set_pair(L, "start", p->start);
  set_pair(L, "end", p->end);
  set_pair(L, "t_start", p->t_start);
  set_pair(L, "t_end", p->t_end);
  if (p->kind == BSFIT_PIECE_ARC) {
    set_pair(L, "centre", p->centre);
    lua_pushnumber(L, p->radius);
    lua_setfield(L, -2, "radius");
    lua_pushnumber(L, p->sweep);
    lua_setfield(L, -2, "sweep");
    lua_pushnumber(L, p->radius_se);
    lua_setfield(L, -2, "radius_se");
  }
  if (p->join == BSFIT_JOIN_CORNER) {
    lua_pushnumber(L, p->turn * 57.29577951308232);
    lua_setfield(L, -2, "turn");
    lua_pushnumber(L, p->evidence);
    lua_setfield(L, -2, "evidence");
  }
  lua_pushnumber(L, p->rms);
  lua_setfield(L, -2, "rms");
  lua_pushnumber(L, p->max);
  lua_setfield(L, -2, "max");
}

/* argument 1, a section: at least `least` finite 2D points */
static void check_section(lua_State *L, const bsfit_points_ud *P, size_t least) {
  luaL_argcheck(L, P->dim == 2, 1, "2D points expected");
  if (P->n < least)
    luaL_argerror(L, 1, lua_pushfstring(L, "at least %d point%s expected", (int)least,
                                        least == 1 ? "" : "s"));
  bsfit__lua_checkfinite(L, 1, P);
}

/* bs.geom.segment(P [, opts]) */
static int features_segment(lua_State *L) {
  static const char *const names[] = {"closed",  "sigma",   "tol_sigma",  "exact",
                                      "min_line", "min_arc", "param_cost", NULL};
  bsfit_points_ud *P = bsfit__lua_topoints(L, 1);
  int t = bsfit__lua_opttable(L, 2, names);
  bsfit_segment_opts o;
  bsfit_piece *pieces;
  bsfit_allocator a = bsfit__lua_allocator(L);
  size_t cap, n = 0, i;
  lua_Integer ml, ma;
  bsfit_status st;
  bsfit_err e;
  memset(&o, 0, sizeof o);
  o.closed = opt_boolean(L, t, "closed", 1);
  o.sigma = opt_number(L, t, "sigma", 0);
  o.tol_sigma = opt_number(L, t, "tol_sigma", 4);
  o.exact = opt_number(L, t, "exact", 1e-10);
  ml = opt_integer(L, t, "min_line", 3);
  ma = opt_integer(L, t, "min_arc", 4);
  if (bsfit__lua_field(L, t, "param_cost") != LUA_TNIL) { /* absent: the core's default */
    o.param_cost = opt_number(L, t, "param_cost", 0);
    luaL_argcheck(L, o.param_cost > 0, 2, "field 'param_cost' must be > 0 (math.huge: parameters only)");
  }
  lua_pop(L, 1);
  luaL_argcheck(L, o.sigma >= 0, 2, "field 'sigma' must be >= 0");
  luaL_argcheck(L, o.tol_sigma > 0, 2, "field 'tol_sigma' must be > 0");
  luaL_argcheck(L, o.exact > 0 && o.exact < 1, 2, "field 'exact' must be in (0, 1)");
  luaL_argcheck(L, ml >= 2 && ml <= 1000000, 2, "field 'min_line' must be >= 2");
  luaL_argcheck(L, ma >= 3 && ma <= 1000000, 2, "field 'min_arc' must be >= 3");
  check_section(L, P, 3);
  o.min_line = (size_t)ml;
  o.min_arc = (size_t)ma;
  cap = 2 * P->n + 2;
  pieces = (bsfit_piece *)lua_newuserdatauv(L, cap * sizeof *pieces, 0);
  e = bsfit_segment(P->xy, P->n, 2, &o, pieces, cap, &n, &a, &st);
  if (e != BSFIT_OK) return bsfit__lua_result(L, e, &st, 0, 1);
  lua_createtable(L, (int)n, 0);
  for (i = 0; i < n && i < cap; i++) {
    push_piece(L, &pieces[i], P->n);
    lua_rawseti(L, -2, (lua_Integer)i + 1);
  }
  return 1;
}

/* bs.geom.segment_sigma(P [, {closed = true, max = 0}]) --> sigma */
static int features_segment_sigma(lua_State *L) {
  static const char *const names[] = {"closed", "max", NULL};
  bsfit_points_ud *P = bsfit__lua_topoints(L, 1);
  int t = bsfit__lua_opttable(L, 2, names);
  int closed = opt_boolean(L, t, "closed", 1);
  lua_Number mx = opt_number(L, t, "max", 0);
  bsfit_allocator a = bsfit__lua_allocator(L);
  double sigma = 0;
  bsfit_status st;
  bsfit_err e;
  check_section(L, P, 3);
  luaL_argcheck(L, mx >= 0, 2, "field 'max' must be >= 0");
  e = bsfit_segment_sigma(P->xy, P->n, 2, closed, mx, &sigma, &a, &st);
  if (e != BSFIT_OK) return bsfit__lua_result(L, e, &st, 0, 1);
  lua_pushnumber(L, sigma);
  return 1;
}

/* bs.geom.segment_start(P) --> the 1-based index a closed section is read from */
static int features_segment_start(lua_State *L) {
  bsfit_points_ud *P = bsfit__lua_topoints(L, 1);
  size_t first = 0;
  bsfit_status st;
  bsfit_err e;
  check_section(L, P, 1);
  e = bsfit_segment_start(P->xy, P->n, 2, &first, &st);
  if (e != BSFIT_OK) return bsfit__lua_result(L, e, &st, 0, 1);
  lua_pushinteger(L, (lua_Integer)first + 1);
  return 1;
}

/* bs.geom.self_intersections(C [, k]) --> count, parameter (nil when none) */
static int features_self_intersections(lua_State *L) {
  bsfit_curve *c = bsfit__lua_checkcurve(L, 1);
  lua_Integer k = luaL_optinteger(L, 2, 2000);
  bsfit_allocator a = bsfit__lua_allocator(L);
  size_t count = 0;
  double where = 0;
  bsfit_status st;
  bsfit_err e;
  luaL_argcheck(L, c->dim == 2, 1, "2D curve expected");
  luaL_argcheck(L, k >= 3 && k <= (lua_Integer)1 << 26, 2, "sample count out of range");
  e = bsfit_curve_self_intersections(c, (size_t)k, &count, &where, &a, &st);
  if (e != BSFIT_OK) return bsfit__lua_raise(L, e, &st, 0);
  lua_pushinteger(L, (lua_Integer)count);
  if (count > 0)
    lua_pushnumber(L, where);
  else
    lua_pushnil(L);
  return 2;
}

/* integer field k of the table on top, in [lo, hi] (argument arg's piece j) */
static size_t piece_field(lua_State *L, int arg, lua_Integer j, const char *k, lua_Integer lo,
                          lua_Integer hi) {
  int isnum;
  lua_Integer v;
  lua_getfield(L, -1, k);
  v = lua_tointegerx(L, -1, &isnum);
  lua_pop(L, 1);
  if (!isnum || v < lo || v > hi)
    return (size_t)luaL_argerror(L, arg, lua_pushfstring(L, "piece %I: field '%s' must be an "
                                 "integer in [%I, %I]", j, k, lo, hi));
  return (size_t)v;
}

/* bs.geom.piece_distances(C, P, pieces [, iters]) --> Vector of distances */
static int features_piece_distances(lua_State *L) {
  bsfit_curve *c = bsfit__lua_checkcurve(L, 1);
  bsfit_points_ud *P = bsfit__lua_topoints(L, 2);
  lua_Integer np, j, iters = luaL_optinteger(L, 4, 8), m = (lua_Integer)P->n;
  size_t *first, *count;
  double *range;
  bsfit_vector_ud *d;
  bsfit_allocator a = bsfit__lua_allocator(L);
  bsfit_status st;
  bsfit_err e;
  luaL_checktype(L, 3, LUA_TTABLE);
  luaL_argcheck(L, (int)P->dim == c->dim, 2, "points of the curve's dimension expected");
  luaL_argcheck(L, iters >= 0 && iters <= 1000, 4, "iterations must be in [0, 1000]");
  bsfit__lua_checkfinite(L, 2, P);
  np = luaL_len(L, 3);
  luaL_argcheck(L, np >= 0 && np <= m, 3, "at most one piece per point expected");
  first = (size_t *)lua_newuserdatauv(L, ((size_t)np + 1) * 2 * sizeof *first, 0);
  count = first + np + 1;
  range = (double *)lua_newuserdatauv(L, ((size_t)np + 1) * 2 * sizeof *range, 0);
  for (j = 1; j <= np; j++) {
    int k;
    lua_rawgeti(L, 3, j);
    luaL_argcheck(L, lua_istable(L, -1), 3, "pieces must be tables");
    first[j - 1] = piece_field(L, 3, j, "first", 1, m) - 1;
    count[j - 1] = piece_field(L, 3, j, "count", 0, m);
    if (lua_getfield(L, -1, "range") != LUA_TTABLE)
      return luaL_argerror(L, 3, lua_pushfstring(L, "piece %I: field 'range' must be "
                                                 "{lo, hi}", j));
    for (k = 0; k < 2; k++) {
      lua_rawgeti(L, -1, k + 1);
      if (!lua_isnumber(L, -1))
        return luaL_argerror(L, 3, lua_pushfstring(L, "piece %I: field 'range' must be "
                                                   "{lo, hi}", j));
      range[2 * (j - 1) + k] = lua_tonumber(L, -1);
      lua_pop(L, 1);
    }
    lua_pop(L, 2);
  }
  d = bsfit__lua_allocvector(L, P->n);
  e = bsfit_curve_piece_distances(c, P->xy, P->n, first, count, range, (size_t)np, (int)iters,
                                  d->x, &a, &st);
  if (e != BSFIT_OK) return bsfit__lua_raise(L, e, &st, 3);
  return 1;
}

/* a point {x, y[, z, w]} at stack index i into x; returns its dimension */
static int read_point(lua_State *L, int i, double *x) {
  int d, n;
  luaL_checktype(L, i, LUA_TTABLE);
  n = (int)luaL_len(L, i);
  luaL_argcheck(L, n >= 1 && n <= 4, i, "point of 1 to 4 numbers expected");
  for (d = 0; d < n; d++) {
    lua_rawgeti(L, i, d + 1);
    if (!lua_isnumber(L, -1)) return luaL_argerror(L, i, "point coordinates must be numbers");
    x[d] = lua_tonumber(L, -1);
    lua_pop(L, 1);
  }
  return n;
}

/* bs.curve.line(a, b) */
static int features_line(lua_State *L) {
  double a[4], b[4];
  int da = read_point(L, 1, a), db = read_point(L, 2, b);
  bsfit_allocator al;
  bsfit_curve_ud *ud;
  bsfit_status st;
  bsfit_err e;
  luaL_argcheck(L, da == db, 2, "points of different dimensions");
  ud = bsfit__lua_newcurve(L, &al);
  e = bsfit_curve_line(a, b, da, &ud->c, &al, &st);
  if (e != BSFIT_OK) return bsfit__lua_raise(L, e, &st, 1);
  return 1;
}

/* bs.curve.arc{centre =, radius =, start =, sweep =} */
static int features_arc(lua_State *L) {
  static const char *const names[] = {"centre", "radius", "start", "sweep", NULL};
  double c[4];
  lua_Number r, a0, sw;
  bsfit_allocator al;
  bsfit_curve_ud *ud;
  bsfit_status st;
  bsfit_err e;
  luaL_checktype(L, 1, LUA_TTABLE);
  bsfit__lua_check_options(L, 1, names);
  if (bsfit__lua_field(L, 1, "centre") == LUA_TNIL)
    return luaL_argerror(L, 1, "field 'centre' is required");
  luaL_argcheck(L, read_point(L, lua_gettop(L), c) == 2, 1, "field 'centre' must be a 2D point");
  r = opt_number(L, 1, "radius", 0);
  a0 = opt_number(L, 1, "start", 0);
  sw = opt_number(L, 1, "sweep", 0);
  ud = bsfit__lua_newcurve(L, &al);
  e = bsfit_curve_arc(c, r, a0, sw, &ud->c, &al, &st);
  if (e != BSFIT_OK) return bsfit__lua_raise(L, e, &st, 1);
  return 1;
}

/* bs.curve.join(curves, lengths) */
static int features_join(lua_State *L) {
  const bsfit_curve **parts;
  double *len;
  lua_Integer n, i;
  bsfit_allocator al;
  bsfit_curve_ud *ud;
  bsfit_status st;
  bsfit_err e;
  luaL_checktype(L, 1, LUA_TTABLE);
  luaL_checktype(L, 2, LUA_TTABLE);
  n = luaL_len(L, 1);
  luaL_argcheck(L, n >= 1 && n <= 1 << 24, 1, "at least one curve expected");
  luaL_argcheck(L, luaL_len(L, 2) == n, 2, "one length per curve expected");
  parts = (const bsfit_curve **)lua_newuserdatauv(L, (size_t)n * sizeof *parts, 0);
  len = (double *)lua_newuserdatauv(L, (size_t)n * sizeof *len, 0);
  for (i = 0; i < n; i++) {
    lua_rawgeti(L, 1, i + 1);
    parts[i] = bsfit__lua_checkcurve(L, lua_gettop(L)); /* anchored by table 1 */
    lua_pop(L, 1);
    lua_rawgeti(L, 2, i + 1);
    if (!lua_isnumber(L, -1)) return luaL_argerror(L, 2, "lengths must be numbers");
    len[i] = lua_tonumber(L, -1);
    lua_pop(L, 1);
  }
  ud = bsfit__lua_newcurve(L, &al);
  e = bsfit_curve_join(parts, (size_t)n, len, &ud->c, &al, &st);
  if (e != BSFIT_OK) return bsfit__lua_raise(L, e, &st, 1);
  return 1;
}

static const luaL_Reg geom_funcs[] = {{"segment", features_segment},
                                      {"segment_sigma", features_segment_sigma},
                                      {"segment_start", features_segment_start},
                                      {"self_intersections", features_self_intersections},
                                      {"piece_distances", features_piece_distances},
                                      {NULL, NULL}};
static const luaL_Reg curve_funcs[] = {
    {"line", features_line}, {"arc", features_arc}, {"join", features_join}, {NULL, NULL}};

/* into the tables bs.geom and bs.curve that the library made before */
void bsfit__lua_lib_features(lua_State *L) {
  if (lua_getfield(L, -1, "geom") == LUA_TTABLE) {
    luaL_setfuncs(L, geom_funcs, 0);
    lua_pushnumber(L, BSFIT_SEGMENT_SIGMA_STEP);
    lua_setfield(L, -2, "SEGMENT_SIGMA_STEP");
  }
  lua_pop(L, 1);
  if (lua_getfield(L, -1, "curve") == LUA_TTABLE) luaL_setfuncs(L, curve_funcs, 0);
  lua_pop(L, 1);
}
