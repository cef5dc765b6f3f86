/*
** lcurve.c
** bsfit.Curve: B-spline, NURBS and Bézier curves, open or periodic. The userdata
** holds a bsfit_curve whose arrays come from Lua's allocator (STYLE R7), freed by
** an idempotent __gc that __close shares; a closed curve refuses further use.
*/
#include "laux.h"

#include <math.h>
#include <string.h>

/* {====================================================================
** 1. Type name and checker
** ===================================================================== */

static bsfit_curve_ud *toud(lua_State *L, int i) {
  return (bsfit_curve_ud *)luaL_checkudata(L, i, BSFIT_CURVE_T);
}

static bsfit_curve *checkcurve(lua_State *L, int i) {
  bsfit_curve_ud *ud = toud(L, i);
  if (ud->c.ctrl == NULL) luaL_error(L, "attempt to use a closed curve");
  return &ud->c;
}

bsfit_curve *bsfit__lua_checkcurve(lua_State *L, int arg) { return checkcurve(L, arg); }

/* }==================================================================== */

/* {====================================================================
** 2. Constructors
** ===================================================================== */

/* An empty curve first, like liolib's newprefile: if anything below raises, __gc
** finds a curve that is safe to free. The core functions that fill it take the
** allocator by pointer and reset the curve first, so callers pass a copy (`*a`),
** never &a. */
bsfit_curve_ud *bsfit__lua_newcurve(lua_State *L, bsfit_allocator *a) {
  bsfit_curve_ud *ud = (bsfit_curve_ud *)lua_newuserdatauv(L, sizeof *ud, 0);
  bsfit_curve_init(&ud->c);
  luaL_setmetatable(L, BSFIT_CURVE_T);
  *a = bsfit__lua_allocator(L);
  return ud;
}

/* Field k of the options table t converted to Points / Vector on the stack top
** (NULL and a nil pushed when absent). */
static bsfit_points_ud *field_points(lua_State *L, int t, const char *k) {
  int ty = bsfit__lua_field(L, t, k);
  if (ty == LUA_TNIL) return NULL;
  if (ty != LUA_TTABLE && !luaL_testudata(L, -1, BSFIT_POINTS_T))
    luaL_argerror(L, t, lua_pushfstring(L, "field '%s' must be a table or bsfit.Points", k));
  return bsfit__lua_topoints(L, -1);
}

static bsfit_vector_ud *field_vector(lua_State *L, int t, const char *k) {
  int ty = bsfit__lua_field(L, t, k);
  if (ty == LUA_TNIL) return NULL;
  if (luaL_testudata(L, -1, BSFIT_KNOTS_T)) {
    bsfit_knots_ud *K = bsfit__lua_checkknots(L, -1);
    bsfit_vector_ud *v = bsfit__lua_newvector(L, K->n);
    memcpy(v->x, K->U, K->n * sizeof(double));
    lua_replace(L, -2);
    return v;
  }
  if (ty != LUA_TTABLE && !luaL_testudata(L, -1, BSFIT_VECTOR_T))
    luaL_argerror(L, t, lua_pushfstring(L, "field '%s' must be a table or bsfit.Vector", k));
  return bsfit__lua_tovector(L, -1);
}

static int degree_field(lua_State *L, int t, int minp) {
  lua_Integer p;
  bsfit_knots_ud *K;
  bsfit__lua_field(L, t, "knots");
  K = (bsfit_knots_ud *)luaL_testudata(L, -1, BSFIT_KNOTS_T);
  lua_pop(L, 1);
  p = K ? opt_integer(L, t, "degree", K->degree) : req_integer(L, t, "degree");
  if (p < minp || p > BSFIT_MAX_DEGREE)
    luaL_argerror(L, t, lua_pushfstring(L, "field 'degree' must be in %d..%d", minp, BSFIT_MAX_DEGREE));
  if (K && K->degree != p)
    luaL_argerror(L, t, lua_pushfstring(L, "knots of degree %d for a curve of degree %d",
                                        K->degree, (int)p));
  return (int)p;
}

/* For a periodic curve `knots` is one period (N+1 values) or the expanded vector
** (N+2p+1 values, whose period is U[p..p+N]). */
static const double *periodic_period(lua_State *L, int t, bsfit_vector_ud *U, size_t N, int p) {
  if (U == NULL) return NULL;
  if (U->n == N + 1) return U->x;
  if (U->n == N + 2 * (size_t)p + 1) return U->x + p;
  luaL_argerror(L, t, lua_pushfstring(L, "a periodic curve of %d control points needs %d or %d knots, got %d",
                                      (int)N, (int)N + 1, (int)N + 2 * p + 1, (int)U->n));
  return NULL;
}

/* bs.curve.new{degree =, knots =, control_points =, weights =, periodic =} */
static int curve_new(lua_State *L) {
  static const char *const opts[] = {"degree", "knots", "control_points", "weights", "periodic", NULL};
  bsfit_status st;
  bsfit_points_ud *P;
  bsfit_vector_ud *U, *w;
  bsfit_curve_ud *ud;
  bsfit_allocator a;
  int p, periodic;
  bsfit_err e;
  luaL_checktype(L, 1, LUA_TTABLE);
  bsfit__lua_check_options(L, 1, opts);
  periodic = opt_boolean(L, 1, "periodic", 0);
  p = degree_field(L, 1, periodic ? 1 : 0);
  P = field_points(L, 1, "control_points");
  if (P == NULL) return luaL_argerror(L, 1, "field 'control_points' is required");
  U = field_vector(L, 1, "knots");
  w = field_vector(L, 1, "weights");
  if (w && w->n != P->n)
    return luaL_argerror(L, 1, lua_pushfstring(L, "%d weights for %d control points", (int)w->n, (int)P->n));
  bsfit__lua_checkfinite(L, 1, P); /* 1-based messages before the core's 0-based ones */
  if (w) bsfit__lua_checkweights(L, 1, w->x, w->n);
  if (U) bsfit__lua_checkknotvalues(L, 1, U->x, U->n, periodic ? -1 : p);
  if (P->n < (size_t)p + 1)
    return luaL_argerror(L, 1, lua_pushfstring(L, "degree %d needs at least %d control points, got %d",
                                                p, p + 1, (int)P->n));
  if (!periodic && U && U->n != P->n + (size_t)p + 1)
    return luaL_argerror(L, 1, lua_pushfstring(L, "degree %d with %d control points needs %d knots, got %d",
                                                p, (int)P->n, (int)P->n + p + 1, (int)U->n));
  ud = bsfit__lua_newcurve(L, &a);
  if (periodic) {
    const double *period = periodic_period(L, 1, U, P->n, p);
    e = bsfit_curve_new_periodic(&ud->c, p, (int)P->dim, P->n, period, P->xy, w ? w->x : NULL,
                                 &a, &st);
  } else {
    e = bsfit_curve_new(&ud->c, p, (int)P->dim, P->n, U ? U->x : NULL, P->xy, w ? w->x : NULL, 0,
                        &a, &st);
  }
  if (e != BSFIT_OK) return bsfit__lua_raise(L, e, &st, 1);
  return 1;
}

/* bs.bezier.new{control_points =, weights =} */
static int bezier_new(lua_State *L) {
  static const char *const opts[] = {"control_points", "weights", NULL};
  bsfit_status st;
  bsfit_points_ud *P;
  bsfit_vector_ud *w;
  bsfit_curve_ud *ud;
  bsfit_allocator a;
  bsfit_err e;
  luaL_checktype(L, 1, LUA_TTABLE);
  bsfit__lua_check_options(L, 1, opts);
  P = field_points(L, 1, "control_points");
  if (P == NULL) return luaL_argerror(L, 1, "field 'control_points' is required");
  w = field_vector(L, 1, "weights");
  if (w && w->n != P->n)
    return luaL_argerror(L, 1, lua_pushfstring(L, "%d weights for %d control points", (int)w->n, (int)P->n));
  bsfit__lua_checkfinite(L, 1, P);
  if (w) bsfit__lua_checkweights(L, 1, w->x, w->n);
  ud = bsfit__lua_newcurve(L, &a);
  e = bsfit_curve_new_bezier(&ud->c, (int)P->dim, P->n, P->xy, w ? w->x : NULL, &a, &st);
  if (e != BSFIT_OK) return bsfit__lua_raise(L, e, &st, 1);
  return 1;
}

/* }==================================================================== */

/* {====================================================================
** 3. Methods and metamethods
** ===================================================================== */

static int push_coords(lua_State *L, const double *x, int dim) {
  int k;
  luaL_checkstack(L, dim, "too many coordinates");
  for (k = 0; k < dim; k++) lua_pushnumber(L, x[k]);
  return dim;
}

/* C:eval(t) --> x, y[, z] */
static int curve_eval(lua_State *L) {
  bsfit_curve *c = checkcurve(L, 1);
  double t = luaL_checknumber(L, 2), x[4];
  bsfit_status st;
  bsfit_err e = bsfit_curve_eval(c, t, x, &st);
  if (e != BSFIT_OK) return bsfit__lua_raise(L, e, &st, 2);
  return push_coords(L, x, c->dim);
}

/* C:eval_many(params) --> Points: one C loop, no Lua call per point */
static int curve_eval_many(lua_State *L) {
  bsfit_curve *c = checkcurve(L, 1);
  bsfit_vector_ud *u = bsfit__lua_tovector(L, 2);
  bsfit_points_ud *P = bsfit__lua_allocpoints(L, u->n, (size_t)c->dim);
  bsfit_status st;
  bsfit_err e = bsfit_curve_eval_many(c, u->x, u->n, P->xy, &st);
  if (e != BSFIT_OK) return bsfit__lua_raise(L, e, &st, 2);
  return 1;
}

/* Highest derivative order of a rational curve: each order costs O(k) more work and
** the values overflow long before (they grow like k!). */
#define RATIONAL_MAX_DERIV 1000

/* C:deriv(t [, k]) --> the k-th derivative (default 1) at t, dim numbers. Any k >= 0:
** above the degree a polynomial curve's derivatives are 0 (no work is done). */
static int curve_deriv(lua_State *L) {
  bsfit_curve *c = checkcurve(L, 1);
  double t = luaL_checknumber(L, 2);
  lua_Integer k = luaL_optinteger(L, 3, 1);
  size_t d = (size_t)c->dim, len;
  double *out;
  bsfit_status st;
  bsfit_err e;
  luaL_argcheck(L, k >= 0, 3, "derivative order must be >= 0");
  if (c->weights == NULL && k > c->degree) {
    double zero[4] = {0.0, 0.0, 0.0, 0.0};
    luaL_argcheck(L, isfinite(t), 2, "parameter is not finite");
    return push_coords(L, zero, c->dim);
  }
  luaL_argcheck(L, k <= RATIONAL_MAX_DERIV, 3, "derivative order of a rational curve out of range 0..1000");
  len = ((size_t)k + 1) * d;
  out = (double *)lua_newuserdatauv(L, len * sizeof(double), 0); /* scratch Lua owns */
  e = bsfit_curve_derivs(c, t, (int)k, out, &st);
  if (e != BSFIT_OK) return bsfit__lua_raise(L, e, &st, 2);
  return push_coords(L, out + (size_t)k * d, c->dim);
}

/* C:insert(t [, times]) --> a new curve with the knot t inserted `times` (1) times */
static int curve_insert(lua_State *L) {
  bsfit_curve *c = checkcurve(L, 1);
  double t = luaL_checknumber(L, 2);
  lua_Integer times = luaL_optinteger(L, 3, 1);
  bsfit_allocator a;
  bsfit_curve_ud *ud;
  bsfit_status st;
  bsfit_err e;
  luaL_argcheck(L, times >= 0 && times <= BSFIT_MAX_DEGREE + 1, 3, "times out of range");
  ud = bsfit__lua_newcurve(L, &a);
  e = bsfit_curve_insert_knot(c, t, (int)times, &ud->c, &st);
  if (e != BSFIT_OK) return bsfit__lua_raise(L, e, &st, e == BSFIT_EMULT ? 3 : 2);
  return 1;
}

/* C:refine(knots) --> a new curve with all the knots (Vector or table) inserted */
static int curve_refine(lua_State *L) {
  bsfit_curve *c = checkcurve(L, 1);
  bsfit_vector_ud *X = bsfit__lua_tovector(L, 2);
  bsfit_allocator a;
  bsfit_curve_ud *ud = bsfit__lua_newcurve(L, &a);
  bsfit_status st;
  bsfit_err e = bsfit_curve_refine(c, X->x, X->n, &ud->c, &st);
  if (e != BSFIT_OK) return bsfit__lua_raise(L, e, &st, 2);
  return 1;
}

/* C:sample([K]) --> Points of K samples (default 1000): open curves from a to b, ends
** included; periodic curves over the period [a, b) (C(b) would repeat C(a)). The block
** is not zeroed first: the core writes every coordinate. */
static int curve_sample(lua_State *L) {
  bsfit_curve *c = checkcurve(L, 1);
  size_t k = lua_isnoneornil(L, 2) ? 1000 : bsfit__lua_checkcount(L, 2, 2, LUA_MAXINTEGER);
  bsfit_points_ud *P = bsfit__lua_allocpoints(L, k, (size_t)c->dim);
  bsfit_status st;
  bsfit_allocator a = bsfit__lua_allocator(L);
  bsfit_err e = bsfit_curve_sample(c, k, P->xy, &a, &st);
  if (e != BSFIT_OK) return bsfit__lua_raise(L, e, &st, 2);
  return 1;
}

/* C:split(t) --> left over [a, t], right over [t, b] (clamped curves). A periodic
** curve is cut open at t instead: one open curve over [t, t + period], and nil. */
static int curve_split(lua_State *L) {
  bsfit_curve *c = checkcurve(L, 1);
  double t = luaL_checknumber(L, 2);
  bsfit_allocator a;
  bsfit_curve_ud *left = bsfit__lua_newcurve(L, &a), *right = NULL;
  bsfit_status st;
  bsfit_err e;
  if (!c->periodic) right = bsfit__lua_newcurve(L, &a);
  e = bsfit_curve_split(c, t, &left->c, right ? &right->c : NULL, &st);
  if (e != BSFIT_OK) return bsfit__lua_raise(L, e, &st, 2);
  if (right == NULL) luaL_pushfail(L);
  return 2;
}

/* C:reverse() --> a new curve R with R(t) = C(a + b - t) on the same domain */
static int curve_reverse(lua_State *L) {
  bsfit_curve *c = checkcurve(L, 1);
  bsfit_allocator a;
  bsfit_curve_ud *ud = bsfit__lua_newcurve(L, &a);
  bsfit_status st;
  bsfit_err e = bsfit_curve_reverse(c, &ud->c, &st);
  if (e != BSFIT_OK) return bsfit__lua_raise(L, e, &st, 0);
  return 1;
}

/* C:elevate([times]) --> the same curve with its degree raised by times (default 1) */
static int curve_elevate(lua_State *L) {
  bsfit_curve *c = checkcurve(L, 1);
  lua_Integer t = luaL_optinteger(L, 2, 1);
  bsfit_allocator a;
  bsfit_curve_ud *ud;
  bsfit_status st;
  bsfit_err e;
  luaL_argcheck(L, t >= 0 && t <= BSFIT_MAX_DEGREE - c->degree, 2,
                lua_pushfstring(L, "elevation out of range 0..%d (degree %d, at most %d)",
                                BSFIT_MAX_DEGREE - c->degree, c->degree, BSFIT_MAX_DEGREE));
  ud = bsfit__lua_newcurve(L, &a);
  e = bsfit_curve_elevate(c, (int)t, &ud->c, &st);
  if (e != BSFIT_OK) return bsfit__lua_raise(L, e, &st, e == BSFIT_EMULT ? 0 : 2);
  return 1;
}

/* C:length([a, b]) --> arc length over [a, b] (default: the whole domain) */
static int curve_length(lua_State *L) {
  bsfit_curve *c = checkcurve(L, 1);
  double a, b, len = 0.0;
  bsfit_status st;
  bsfit_err e;
  bsfit_curve_domain(c, &a, &b);
  a = luaL_optnumber(L, 2, a);
  b = luaL_optnumber(L, 3, b);
  e = bsfit_curve_length(c, a, b, &len, &st);
  if (e != BSFIT_OK) return bsfit__lua_raise(L, e, &st, isfinite(a) ? 3 : 2);
  lua_pushnumber(L, len);
  return 1;
}

/* C:closest(x, y[, z]) --> t, distance: the foot of the point on the curve */
static int curve_closest(lua_State *L) {
  bsfit_curve *c = checkcurve(L, 1);
  double x[4], u = 0.0, dist = 0.0;
  int k;
  bsfit_status st;
  bsfit_err e;
  for (k = 0; k < c->dim; k++) {
    x[k] = luaL_checknumber(L, 2 + k);
    luaL_argcheck(L, isfinite(x[k]), 2 + k, "coordinate is not finite");
  }
  if (!lua_isnone(L, 2 + c->dim))
    return luaL_argerror(L, 2 + c->dim, lua_pushfstring(L, "too many coordinates (curve has %d)", c->dim));
  {
    bsfit_allocator a = bsfit__lua_allocator(L); /* scratch counted by the memory cap */
    e = bsfit_curve_closest(c, x, &u, &dist, &a, &st);
  }
  if (e != BSFIT_OK) return bsfit__lua_raise(L, e, &st, 0);
  lua_pushnumber(L, u);
  lua_pushnumber(L, dist);
  return 2;
}

/* C:project(P, u0 [, iters = 20]) --> Vector of feet, Vector of distances: each point
** P_i slides from its parameter u0_i to a foot on the curve by safeguarded Newton steps
** (the fitter's parameter correction); u0 is not modified. */
static int curve_project(lua_State *L) {
  bsfit_curve *c = checkcurve(L, 1);
  bsfit_points_ud *P = bsfit__lua_topoints(L, 2);
  bsfit_vector_ud *u0 = bsfit__lua_tovector(L, 3), *u, *dist;
  lua_Integer iters = luaL_optinteger(L, 4, 20);
  bsfit_status st;
  size_t i;
  bsfit_err e;
  luaL_argcheck(L, (int)P->dim == c->dim, 2,
                lua_pushfstring(L, "points of dimension %d for a curve of dimension %d", (int)P->dim, c->dim));
  if (u0->n != P->n)
    return luaL_argerror(L, 3, lua_pushfstring(L, "%d parameters for %d points", (int)u0->n, (int)P->n));
  luaL_argcheck(L, iters >= 0 && iters <= 1000, 4, "iterations out of range 0..1000");
  bsfit__lua_checkfinite(L, 2, P);
  for (i = 0; i < u0->n; i++)
    if (!isfinite(u0->x[i]))
      return luaL_argerror(L, 3, lua_pushfstring(L, "parameter %I is not finite", (lua_Integer)i + 1));
  u = bsfit__lua_newvector(L, P->n);
  dist = bsfit__lua_newvector(L, P->n);
  if (P->n) memcpy(u->x, u0->x, P->n * sizeof(double));
  {
    bsfit_allocator a = bsfit__lua_allocator(L);
    e = bsfit_curve_project_many(c, P->xy, P->n, u->x, dist->x, (int)iters, &a, &st);
  }
  if (e != BSFIT_OK) return bsfit__lua_raise(L, e, &st, 2);
  return 2;
}

/* C:closest_many(P) --> Vector of parameters, Vector of distances: C:closest for every
** point of P in one call (the curve is sampled once) */
static int curve_closest_many(lua_State *L) {
  bsfit_curve *c = checkcurve(L, 1);
  bsfit_points_ud *P = bsfit__lua_topoints(L, 2);
  bsfit_vector_ud *u, *dist;
  bsfit_status st;
  bsfit_err e;
  luaL_argcheck(L, (int)P->dim == c->dim, 2,
                lua_pushfstring(L, "points of dimension %d for a curve of dimension %d", (int)P->dim, c->dim));
  bsfit__lua_checkfinite(L, 2, P);
  u = bsfit__lua_allocvector(L, P->n);
  dist = bsfit__lua_allocvector(L, P->n);
  {
    bsfit_allocator a = bsfit__lua_allocator(L);
    e = bsfit_curve_closest_many(c, P->xy, P->n, u->x, dist->x, &a, &st);
  }
  if (e != BSFIT_OK) return bsfit__lua_raise(L, e, &st, 2);
  return 2;
}

/* C:is_uniform() --> true when every knot span is equal (relative 1e-8): the curves
** bs.filter.box(C, k) takes */
static int curve_is_uniform(lua_State *L) {
  lua_pushboolean(L, bsfit_curve_is_uniform(checkcurve(L, 1)));
  return 1;
}

typedef bsfit_err (*measure_fn)(const bsfit_curve *, size_t, double *, bsfit_status *);

/* C:total_turning([K]) / C:bending_energy([K]): shape measures from K samples (1000) */
static int measure(lua_State *L, measure_fn fn) {
  bsfit_curve *c = checkcurve(L, 1);
  size_t k = lua_isnoneornil(L, 2) ? 1000 : bsfit__lua_checkcount(L, 2, 3, LUA_MAXINTEGER);
  double out = 0.0;
  bsfit_status st;
  bsfit_err e = fn(c, k, &out, &st);
  if (e != BSFIT_OK) return bsfit__lua_raise(L, e, &st, 0);
  lua_pushnumber(L, out);
  return 1;
}

static int curve_total_turning(lua_State *L) { return measure(L, bsfit_curve_total_turning); }
static int curve_bending_energy(lua_State *L) { return measure(L, bsfit_curve_bending_energy); }

/* C:max_deviation(D [, K]) --> max |C(t) - D(t)| over K (1000) parameters of the common
** domain: how far a smoothing moved the curve */
static int curve_max_deviation(lua_State *L) {
  bsfit_curve *c = checkcurve(L, 1), *d = checkcurve(L, 2);
  size_t k = lua_isnoneornil(L, 3) ? 1000 : bsfit__lua_checkcount(L, 3, 2, LUA_MAXINTEGER);
  double out = 0.0;
  bsfit_status st;
  bsfit_err e = bsfit_curve_max_deviation(c, d, k, &out, &st);
  if (e != BSFIT_OK) return bsfit__lua_raise(L, e, &st, 2);
  lua_pushnumber(L, out);
  return 1;
}

/* C:to_json() --> the JSON text of docs/formats.md */
static int curve_to_json(lua_State *L) {
  bsfit_curve *c = checkcurve(L, 1);
  bsfit_scratch_ud *box = bsfit__lua_newscratch(L);
  bsfit_status st;
  char *text = NULL;
  size_t len = 0;
  bsfit_err e = bsfit_curve_to_json(c, &text, &len, &box->a, &st);
  if (e != BSFIT_OK) return bsfit__lua_raise(L, e, &st, 1);
  box->p[0] = text;
  box->size[0] = len + 1;
  lua_pushlstring(L, text, len);
  bsfit__lua_scratch_free(box);
  return 1;
}

/* bs.curve.from_json(s) --> Curve, or nil, message, code for malformed text */
static int curve_from_json(lua_State *L) {
  size_t len;
  const char *s = luaL_checklstring(L, 1, &len);
  bsfit_allocator a;
  bsfit_curve_ud *ud = bsfit__lua_newcurve(L, &a);
  bsfit_status st;
  bsfit_err e = bsfit_curve_from_json(s, len, &ud->c, &a, &st);
  if (e == BSFIT_ENOMEM) return bsfit__lua_raise(L, e, &st, 1);
  if (e != BSFIT_OK) return bsfit__lua_result(L, BSFIT_EFORMAT, &st, 1, 1);
  return 1;
}

/* bs.curve.read(path) --> Curve (JSON file), or nil, message, code */
static int curve_read(lua_State *L) {
  const char *path = luaL_checkstring(L, 1);
  bsfit_allocator a;
  bsfit_curve_ud *ud;
  bsfit_status st;
  bsfit_err e;
  bsfit__lua_check_files(L, "bs.curve.read");
  ud = bsfit__lua_newcurve(L, &a);
  e = bsfit_curve_read_json(path, &ud->c, &a, &st);
  if (e == BSFIT_ENOMEM) return bsfit__lua_raise(L, e, &st, 1);
  if (e != BSFIT_OK && e != BSFIT_EIO) e = BSFIT_EFORMAT; /* the file's content is at fault */
  st.code = e;
  return bsfit__lua_result(L, e, &st, 1, 1);
}

static int ends_with(const char *s, size_t len, const char *ext) {
  size_t n = strlen(ext);
  return len > n && strcmp(s + len - n, ext) == 0;
}

/* The samples of a curve written to CSV, in a Points userdata left on the stack. */
static bsfit_err write_csv(lua_State *L, const bsfit_curve *c, const char *path, size_t k,
                           bsfit_status *st) {
  bsfit_points_ud *P = bsfit__lua_allocpoints(L, k, (size_t)c->dim);
  bsfit_allocator a = bsfit__lua_allocator(L);
  bsfit_err e = bsfit_curve_sample(c, k, P->xy, &a, st);
  if (e == BSFIT_OK) e = bsfit_points_write(path, P->xy, k, c->dim, NULL, st);
  return e;
}

/* One curve as STEP (dxf = 0) or DXF (dxf = 1); the formats hold 2D and 3D curves of
** degree >= 1, which is misuse to ask otherwise. */
static bsfit_err write_exchange(lua_State *L, const bsfit_curve *c, const char *path, int dxf,
                                bsfit_status *st) {
  const bsfit_curve *one[1];
  if (c->dim < 2 || c->dim > 3 || c->degree < 1)
    luaL_argerror(L, 2, lua_pushfstring(L, "%s holds 2D and 3D curves of degree >= 1, this one "
                                           "has dim %d, degree %d", dxf ? "DXF" : "STEP", c->dim,
                                        c->degree));
  one[0] = c;
  return dxf ? bsfit_curves_write_dxf(one, 1, path, st) : bsfit_curves_write_step(one, 1, path, st);
}

/* C:write(path [, {samples = 1000}]), by extension: ".json" (docs/formats.md), ".svg" (the
** curve over its control polygon), ".iges"/".igs" (entity 126), ".step"/".stp" (ISO
** 10303-21) and ".dxf" (SPLINE; both in docs/exchange.md), ".csv" (`samples`
** points of the curve, as C:sample). The file is replaced atomically. Returns C, or
** nil, message, code when the file cannot be written. */
static int curve_write(lua_State *L) {
  static const char *const opts[] = {"samples", NULL};
  bsfit_curve *c = checkcurve(L, 1);
  size_t len;
  const char *path = luaL_checklstring(L, 2, &len);
  int t = bsfit__lua_opttable(L, 3, opts);
  lua_Integer k = opt_integer(L, t, "samples", 1000);
  bsfit_status st;
  bsfit_err e;
  if (k < 2 || k > 100000000) return luaL_argerror(L, t, "field 'samples' must be in 2..1e8");
  bsfit__lua_check_files(L, "write");
  if (ends_with(path, len, ".json")) e = bsfit_curve_write_json(c, path, &st);
  else if (ends_with(path, len, ".iges") || ends_with(path, len, ".igs")) e = bsfit_curve_write_iges(c, path, &st);
  else if (ends_with(path, len, ".step") || ends_with(path, len, ".stp"))
    e = write_exchange(L, c, path, 0, &st);
  else if (ends_with(path, len, ".dxf")) e = write_exchange(L, c, path, 1, &st);
  else if (ends_with(path, len, ".svg") && c->dim >= 2) e = bsfit__lua_curve_svg(L, c, path, (size_t)k, &st);
  else if (ends_with(path, len, ".csv") && c->dim >= 2 && c->dim <= 3) e = write_csv(L, c, path, (size_t)k, &st);
  else if (ends_with(path, len, ".svg") || ends_with(path, len, ".csv"))
    return luaL_argerror(L, 2, lua_pushfstring(L, "a curve of dimension %d cannot be written as %s", c->dim,
                                               path + len - 4));
  else
    return luaL_argerror(L, 2, "file name must end in .json, .svg, .iges, .igs, .step, .stp, "
                               ".dxf or .csv");
  lua_settop(L, 1);
  return bsfit__lua_result(L, e, &st, 1, 2);
}

static int curve_domain(lua_State *L) {
  bsfit_curve *c = checkcurve(L, 1);
  double a, b;
  bsfit_curve_domain(c, &a, &b);
  lua_pushnumber(L, a);
  lua_pushnumber(L, b);
  return 2;
}

static int curve_degree(lua_State *L) {
  lua_pushinteger(L, checkcurve(L, 1)->degree);
  return 1;
}

static int curve_dim(lua_State *L) {
  lua_pushinteger(L, checkcurve(L, 1)->dim);
  return 1;
}

/* stored control points (wrapped copies included for periodic curves) */
static int curve_count(lua_State *L) {
  lua_pushinteger(L, (lua_Integer)checkcurve(L, 1)->n);
  return 1;
}

static int curve_distinct(lua_State *L) {
  lua_pushinteger(L, (lua_Integer)bsfit_curve_distinct(checkcurve(L, 1)));
  return 1;
}

static int curve_is_periodic(lua_State *L) {
  lua_pushboolean(L, checkcurve(L, 1)->periodic);
  return 1;
}

static int curve_is_rational(lua_State *L) {
  lua_pushboolean(L, checkcurve(L, 1)->weights != NULL);
  return 1;
}

static int curve_kind(lua_State *L) {
  bsfit_curve *c = checkcurve(L, 1);
  lua_pushstring(L, c->bezier ? "bezier" : c->weights ? "nurbs" : "bspline");
  return 1;
}

static int curve_knots(lua_State *L) {
  bsfit_curve *c = checkcurve(L, 1);
  size_t nk = c->n + (size_t)c->degree + 1;
  bsfit_knots_ud *K = bsfit__lua_newknots(L, nk, c->degree);
  memcpy(K->U, c->knots, nk * sizeof(double));
  return 1;
}

static int curve_control_points(lua_State *L) {
  bsfit_curve *c = checkcurve(L, 1);
  bsfit_points_ud *P = bsfit__lua_newpoints(L, c->n, (size_t)c->dim);
  memcpy(P->xy, c->ctrl, c->n * (size_t)c->dim * sizeof(double));
  return 1;
}

/* C:weights() --> Vector, or nil for a polynomial curve */
static int curve_weights(lua_State *L) {
  bsfit_curve *c = checkcurve(L, 1);
  bsfit_vector_ud *v;
  if (c->weights == NULL) {
    luaL_pushfail(L);
    return 1;
  }
  v = bsfit__lua_newvector(L, c->n);
  memcpy(v->x, c->weights, c->n * sizeof(double));
  return 1;
}

static int curve_control_point(lua_State *L) {
  bsfit_curve *c = checkcurve(L, 1);
  size_t i = bsfit__lua_index(L, 2, c->n);
  return push_coords(L, c->ctrl + i * (size_t)c->dim, c->dim);
}

/* C:set_control_point(i, x, y[, z]): for a periodic curve, the point and its wrapped
** copy move together (docs/method.md §1), whichever of the two i names. */
static int curve_set_control_point(lua_State *L) {
  bsfit_curve *c = checkcurve(L, 1);
  size_t i = bsfit__lua_index(L, 2, c->n), d = (size_t)c->dim, k, N = bsfit_curve_distinct(c);
  double x[4];
  for (k = 0; k < d; k++) {
    x[k] = luaL_checknumber(L, 3 + (int)k);
    luaL_argcheck(L, isfinite(x[k]), 3 + (int)k, "coordinate is not finite");
  }
  if (!lua_isnone(L, 3 + (int)d))
    return luaL_argerror(L, 3 + (int)d, lua_pushfstring(L, "too many coordinates (curve has %d)", (int)d));
  if (c->periodic) i %= N;
  memcpy(c->ctrl + i * d, x, d * sizeof(double));
  if (c->periodic && i < (size_t)c->degree) memcpy(c->ctrl + (i + N) * d, x, d * sizeof(double));
  lua_settop(L, 1);
  return 1;
}

static int curve_copy(lua_State *L) {
  bsfit_curve *c = checkcurve(L, 1);
  bsfit_allocator a;
  bsfit_curve_ud *ud = bsfit__lua_newcurve(L, &a);
  bsfit_status st;
  bsfit_err e = bsfit_curve_copy(c, &ud->c, &a, &st);
  if (e != BSFIT_OK) return bsfit__lua_raise(L, e, &st, 0);
  return 1;
}

/* __gc and __close: free and mark closed; a second call is a no-op */
static int curve_gc(lua_State *L) {
  bsfit_curve_ud *ud = toud(L, 1);
  bsfit_curve_free(&ud->c);
  return 0;
}

static int curve_len(lua_State *L) { return curve_count(L); }

static int curve_tostring(lua_State *L) {
  bsfit_curve_ud *ud = toud(L, 1);
  if (ud->c.ctrl == NULL) lua_pushliteral(L, "bsfit.Curve (closed)");
  else
    lua_pushfstring(L, "bsfit.Curve(deg=%d, n=%I, dim=%d%s): %p", ud->c.degree, (lua_Integer)ud->c.n,
                    ud->c.dim, ud->c.periodic ? ", periodic" : "", (void *)ud);
  return 1;
}

/* }==================================================================== */

/* {====================================================================
** 4. Registration arrays
** ===================================================================== */

static const luaL_Reg curve_meth[] = {
  {"eval", curve_eval}, {"eval_many", curve_eval_many}, {"domain", curve_domain},
  {"degree", curve_degree}, {"dim", curve_dim}, {"count", curve_count},
  {"distinct", curve_distinct}, {"is_periodic", curve_is_periodic},
  {"is_rational", curve_is_rational}, {"kind", curve_kind}, {"knots", curve_knots},
  {"control_points", curve_control_points}, {"weights", curve_weights},
  {"control_point", curve_control_point}, {"set_control_point", curve_set_control_point},
  {"copy", curve_copy}, {"close", curve_gc}, {"deriv", curve_deriv},
  {"insert", curve_insert}, {"refine", curve_refine}, {"to_json", curve_to_json},
  {"write", curve_write}, {"sample", curve_sample}, {"split", curve_split},
  {"reverse", curve_reverse}, {"elevate", curve_elevate}, {"length", curve_length},
  {"closest", curve_closest}, {"project", curve_project}, {"closest_many", curve_closest_many}, {"is_uniform", curve_is_uniform},
  {"total_turning", curve_total_turning}, {"bending_energy", curve_bending_energy},
  {"max_deviation", curve_max_deviation}, {NULL, NULL}};

static const luaL_Reg curve_metameth[] = {
  {"__index", NULL}, {"__gc", curve_gc}, {"__close", curve_gc}, {"__len", curve_len},
  {"__tostring", curve_tostring}, {NULL, NULL}};

static const luaL_Reg curve_funcs[] = {
  {"new", curve_new}, {"from_json", curve_from_json}, {"read", curve_read}, {NULL, NULL}};

static const luaL_Reg bezier_funcs[] = {{"new", bezier_new}, {NULL, NULL}};

/* }==================================================================== */

/* {====================================================================
** 5. Open
** ===================================================================== */

void bsfit_lua_open_curve(lua_State *L) {
  luaL_newmetatable(L, BSFIT_CURVE_T);
  luaL_setfuncs(L, curve_metameth, 0);
  luaL_newlibtable(L, curve_meth);
  luaL_setfuncs(L, curve_meth, 0);
  lua_setfield(L, -2, "__index");
  lua_pop(L, 1);
}

void bsfit__lua_lib_curve(lua_State *L) { luaL_newlib(L, curve_funcs); }
void bsfit__lua_lib_bezier(lua_State *L) { luaL_newlib(L, bezier_funcs); }

/* }==================================================================== */

/* {====================================================================
** Host helpers (bsfit_lua.h)
** ===================================================================== */

const bsfit_curve *bsfit_lua_checkcurve(lua_State *L, int arg) { return checkcurve(L, arg); }

void bsfit_lua_pushcurve(lua_State *L, const bsfit_curve *src) {
  bsfit_allocator a;
  bsfit_curve_ud *ud = bsfit__lua_newcurve(L, &a);
  bsfit_status st;
  bsfit_err e = bsfit_curve_copy(src, &ud->c, &a, &st);
  if (e != BSFIT_OK) bsfit__lua_raise(L, e, &st, 0);
}

/* }==================================================================== */
