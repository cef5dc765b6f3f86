/*
** lfilter.c
** bs.filter.box: smoothing by a box filter (docs/filtering.md, Persiano; src/bsfit_filter.h).
**   bs.filter.box(C, k)                     moving average over k knot spans (uniform C)
**   bs.filter.box(C, {delta = d})           exact filter of half-width d, any polynomial C
**   bs.filter.box(S, k, l)                  k x l knot spans of a uniform surface
**   bs.filter.box(S, {delta_u =, delta_v =}) exact filter of any polynomial surface
** Each returns a new Curve / Surface of one degree more (the input is unchanged); the
** work is done in the core. Inputs the filter cannot take (a rational curve, a window
** wider than the curve, non-uniform knots for the moving average) are misuse: raised.
**   bs.filter.kernel(C, {order = r, k = k | delta = d})   r box passes (B-spline kernel)
**   bs.filter.kernel(S, {order = r | order_u =, order_v =, k =, l = | delta_u =, delta_v =})
**   bs.filter.reduce(C [, {degree = 3, tol = t, max_added =, samples =}])  -> C', report
**   bs.filter.reduce(S [, {degree = 3 | {3, 3}, tol = t, max_added =}])    -> S', report
**   bs.filter.smooth(C, {tol = t [, degree = 3] [, order = r]})           -> C', report
**   bs.filter.distance(A, B [, per_span])   distance between two curves as point sets
** reduce and smooth return nil, message, code for numerical outcomes (a tolerance not
** reached: ENOCONV); bad options raise.
*/
#include "laux.h"

#include <math.h>
#include <stdint.h>
#include <string.h>

/* {====================================================================
** Arguments
** ===================================================================== */

/* The required number field k of the option table t. */
static double req_number(lua_State *L, int t, const char *k) {
  if (bsfit__lua_field(L, t, k) == LUA_TNIL)
    luaL_argerror(L, t, lua_pushfstring(L, "field '%s' is required", k));
  lua_pop(L, 1);
  return opt_number(L, t, k, 0.0);
}

/* A window width in knot spans at arg. */
static int checkwidth(lua_State *L, int arg) {
  lua_Integer k = luaL_checkinteger(L, arg);
  luaL_argcheck(L, k >= 1 && k <= INT32_MAX, arg, "window width must be at least 1");
  return (int)k;
}

/* }==================================================================== */

/* {====================================================================
** Curves and surfaces
** ===================================================================== */

static int box_curve(lua_State *L) {
  static const char *const opts[] = {"delta", NULL};
  bsfit_curve *c = bsfit__lua_checkcurve(L, 1);
  bsfit_allocator a;
  bsfit_curve_ud *ud;
  bsfit_status st;
  bsfit_err e;
  if (lua_type(L, 2) == LUA_TTABLE) {
    double delta;
    bsfit__lua_check_options(L, 2, opts);
    delta = req_number(L, 2, "delta");
    lua_settop(L, 2);
    ud = bsfit__lua_newcurve(L, &a);
    e = bsfit_filter_box_curve_delta(c, delta, &ud->c, &st);
  } else {
    int k = checkwidth(L, 2);
    ud = bsfit__lua_newcurve(L, &a);
    e = bsfit_filter_box_curve(c, k, &ud->c, &st);
  }
  if (e != BSFIT_OK) return bsfit__lua_raise(L, e, &st, 2);
  return 1;
}

static int box_surface(lua_State *L) {
  static const char *const opts[] = {"delta_u", "delta_v", NULL};
  bsfit_surface *s = bsfit__lua_checksurface(L, 1);
  bsfit_allocator a;
  bsfit_surface_ud *ud;
  bsfit_status st;
  bsfit_err e;
  if (lua_type(L, 2) == LUA_TTABLE) {
    double du, dv;
    bsfit__lua_check_options(L, 2, opts);
    du = req_number(L, 2, "delta_u");
    dv = req_number(L, 2, "delta_v");
    lua_settop(L, 2);
    ud = bsfit__lua_newsurface(L, &a);
    e = bsfit_filter_box_surface_delta(s, du, dv, &ud->s, &st);
  } else {
    int k = checkwidth(L, 2), l = checkwidth(L, 3);
    lua_settop(L, 3);
    ud = bsfit__lua_newsurface(L, &a);
    e = bsfit_filter_box_surface(s, k, l, &ud->s, &st);
  }
  if (e != BSFIT_OK) return bsfit__lua_raise(L, e, &st, 2);
  return 1;
}

/* bs.filter.box(C | S, ...) */
static int filter_box(lua_State *L) {
  if (luaL_testudata(L, 1, BSFIT_SURFACE_T)) return box_surface(L);
  if (luaL_testudata(L, 1, BSFIT_CURVE_T)) return box_curve(L);
  return luaL_typeerror(L, 1, "bsfit.Curve or bsfit.Surface");
}

/* }==================================================================== */

/* {====================================================================
** Kernel filters, reduction, smoothing (issue 17)
** ===================================================================== */

/* An order field: absent gives def; present must be an integer >= 1. */
static int opt_order(lua_State *L, int t, const char *k, int def) {
  lua_Integer r = opt_integer(L, t, k, def);
  if (r < 1 || r > BSFIT_MAX_DEGREE)
    luaL_argerror(L, t, lua_pushfstring(L, "field '%s' must be an integer in 1..%d", k,
                                        BSFIT_MAX_DEGREE));
  return (int)r;
}

/* A window field k (integer >= 1), present. */
static int req_width(lua_State *L, int t, const char *k) {
  lua_Integer w = bsfit__lua_req_integer(L, t, k);
  if (w < 1 || w > INT32_MAX)
    luaL_argerror(L, t, lua_pushfstring(L, "field '%s' must be an integer >= 1", k));
  return (int)w;
}

static int kernel_curve(lua_State *L) {
  static const char *const opts[] = {"order", "k", "delta", NULL};
  bsfit_curve *c = bsfit__lua_checkcurve(L, 1);
  bsfit_allocator a;
  bsfit_curve_ud *ud;
  bsfit_status st;
  bsfit_err e;
  int r, has_k;
  luaL_checktype(L, 2, LUA_TTABLE);
  bsfit__lua_check_options(L, 2, opts);
  r = opt_order(L, 2, "order", 1);
  has_k = bsfit__lua_field(L, 2, "k") != LUA_TNIL;
  lua_pop(L, 1);
  if (has_k == (bsfit__lua_field(L, 2, "delta") != LUA_TNIL))
    return luaL_argerror(L, 2, "give exactly one of the fields 'k' and 'delta'");
  lua_pop(L, 1);
  if (has_k) {
    int k = req_width(L, 2, "k");
    lua_settop(L, 2);
    ud = bsfit__lua_newcurve(L, &a);
    e = bsfit_filter_kernel_curve(c, r, k, &ud->c, &st);
  } else {
    double delta = req_number(L, 2, "delta");
    lua_settop(L, 2);
    ud = bsfit__lua_newcurve(L, &a);
    e = bsfit_filter_kernel_curve_delta(c, r, delta, &ud->c, &st);
  }
  if (e != BSFIT_OK) return bsfit__lua_raise(L, e, &st, 2);
  return 1;
}

static int kernel_surface(lua_State *L) {
  static const char *const opts[] = {"order", "order_u", "order_v", "k", "l",
                                     "delta_u", "delta_v", NULL};
  bsfit_surface *s = bsfit__lua_checksurface(L, 1);
  bsfit_allocator a;
  bsfit_surface_ud *ud;
  bsfit_status st;
  bsfit_err e;
  int r, ru, rv;
  luaL_checktype(L, 2, LUA_TTABLE);
  bsfit__lua_check_options(L, 2, opts);
  r = opt_order(L, 2, "order", 1);
  ru = opt_order(L, 2, "order_u", r);
  rv = opt_order(L, 2, "order_v", r);
  if (bsfit__lua_field(L, 2, "k") != LUA_TNIL) {
    int k, l;
    lua_pop(L, 1);
    k = req_width(L, 2, "k");
    l = req_width(L, 2, "l");
    lua_settop(L, 2);
    ud = bsfit__lua_newsurface(L, &a);
    e = bsfit_filter_kernel_surface(s, ru, rv, k, l, &ud->s, &st);
  } else {
    double du, dv;
    lua_pop(L, 1);
    du = req_number(L, 2, "delta_u");
    dv = req_number(L, 2, "delta_v");
    lua_settop(L, 2);
    ud = bsfit__lua_newsurface(L, &a);
    e = bsfit_filter_kernel_surface_delta(s, ru, rv, du, dv, &ud->s, &st);
  }
  if (e != BSFIT_OK) return bsfit__lua_raise(L, e, &st, 2);
  return 1;
}

/* bs.filter.kernel(C | S, opts) */
static int filter_kernel(lua_State *L) {
  if (luaL_testudata(L, 1, BSFIT_SURFACE_T)) return kernel_surface(L);
  if (luaL_testudata(L, 1, BSFIT_CURVE_T)) return kernel_curve(L);
  return luaL_typeerror(L, 1, "bsfit.Curve or bsfit.Surface");
}

/* The distinct knots of out that c does not have, as a list, at the stack top. */
static void push_added(lua_State *L, const bsfit_curve *c, const bsfit_curve *out) {
  size_t nk = out->n + (size_t)out->degree + 1, i, cnk = c->n + (size_t)c->degree + 1;
  lua_Integer at = 0;
  double a, b;
  bsfit_curve_domain(out, &a, &b);
  lua_newtable(L);
  for (i = 0; i < nk; i++) {
    double x = out->knots[i];
    if ((i > 0 && x == out->knots[i - 1]) || x <= a || x >= b) continue;
    if (bsfit_knots_multiplicity(c->knots, cnk, x) == 0) {
      lua_pushnumber(L, x);
      lua_rawseti(L, -2, ++at);
    }
  }
}

static void set_number(lua_State *L, const char *k, double v) {
  lua_pushnumber(L, v);
  lua_setfield(L, -2, k);
}

static void set_integer(lua_State *L, const char *k, lua_Integer v) {
  lua_pushinteger(L, v);
  lua_setfield(L, -2, k);
}

/* A tolerance field: absent gives def; NaN, <= 0 raise. */
static double opt_tol(lua_State *L, int t, double def) {
  double tol = opt_number(L, t, "tol", def);
  if (!(tol > 0))
    luaL_argerror(L, t, lua_pushfstring(L, "field 'tol' must be a number > 0, got %f", tol));
  return tol;
}

/* The degree field of reduce's options at t: absent 3, a number, or {qu, qv} (surfaces);
** each in 1..max. */
static void opt_degrees(lua_State *L, int t, int surface, int max, int *qu, int *qv) {
  int i, q[2] = {3, 3};
  int ty = bsfit__lua_field(L, t, "degree");
  if (ty == LUA_TTABLE && surface) {
    for (i = 0; i < 2; i++) {
      lua_Integer v;
      int isint;
      lua_rawgeti(L, -1 - i, i + 1);
      v = lua_tointegerx(L, -1, &isint);
      if (!isint || v < 1 || v > max)
        luaL_argerror(L, t, lua_pushfstring(L, "field 'degree' must be {qu, qv}, each in 1..%d",
                                            max));
      q[i] = (int)v;
    }
    lua_pop(L, 3);
  } else {
    lua_pop(L, 1);
    q[0] = q[1] = (int)opt_integer(L, t, "degree", 3);
    if (q[0] < 1 || q[0] > max)
      luaL_argerror(L, t, lua_pushfstring(L, "field 'degree' must be in 1..%d", max));
  }
  *qu = q[0];
  *qv = q[1];
}

/* bs.filter.reduce(S [, {degree = q | {qu, qv}, tol = t, max_added =}]) -> surface,
** {max_deviation, bound, knots_added = count, rounds} */
static int reduce_surface(lua_State *L) {
  static const char *const names[] = {"degree", "tol", "max_added", NULL};
  bsfit_surface *s = bsfit__lua_checksurface(L, 1);
  int t = bsfit__lua_opttable(L, 2, names);
  bsfit_reduce_surface_opts o;
  bsfit_reduce_report rep;
  bsfit_allocator a;
  bsfit_surface_ud *ud;
  bsfit_status st;
  bsfit_err e;
  lua_Integer mx = opt_integer(L, t, "max_added", 0);
  memset(&o, 0, sizeof o);
  opt_degrees(L, t, 1, 12, &o.degree_u, &o.degree_v);
  luaL_argcheck(L, mx >= 0, 2, "field 'max_added' must be >= 0");
  o.tol = opt_tol(L, t, HUGE_VAL);
  o.max_added = (size_t)mx;
  lua_settop(L, 2);
  ud = bsfit__lua_newsurface(L, &a);
  e = bsfit_filter_reduce_surface(s, &o, &ud->s, &rep, &st);
  if (e != BSFIT_OK) return bsfit__lua_result(L, e, &st, 0, 2);
  lua_createtable(L, 0, 4);
  set_number(L, "max_deviation", rep.max_deviation);
  set_number(L, "bound", rep.bound);
  set_integer(L, "rounds", rep.rounds);
  set_integer(L, "knots_added", (lua_Integer)rep.knots_added);
  return 2;
}

/* bs.filter.reduce(C [, opts]) -> curve, {max_deviation, bound, knots_added = {...}, rounds};
** a surface: reduce_surface */
static int filter_reduce(lua_State *L) {
  static const char *const names[] = {"degree", "tol", "max_added", "samples", NULL};
  bsfit_curve *c;
  int t;
  bsfit_reduce_opts o;
  bsfit_reduce_report rep;
  bsfit_allocator a;
  bsfit_curve_ud *ud;
  bsfit_status st;
  bsfit_err e;
  lua_Integer q, mx, ns;
  if (luaL_testudata(L, 1, BSFIT_SURFACE_T)) return reduce_surface(L);
  c = bsfit__lua_checkcurve(L, 1);
  t = bsfit__lua_opttable(L, 2, names);
  q = opt_integer(L, t, "degree", 3);
  mx = opt_integer(L, t, "max_added", 0);
  ns = opt_integer(L, t, "samples", 0);
  memset(&o, 0, sizeof o);
  luaL_argcheck(L, q >= 1 && q <= BSFIT_MAX_DEGREE, 2, "field 'degree' must be in 1..30");
  luaL_argcheck(L, mx >= 0 && ns >= 0, 2, "fields 'max_added' and 'samples' must be >= 0");
  o.degree = (int)q;
  o.tol = opt_tol(L, t, HUGE_VAL);
  o.max_added = (size_t)mx;
  o.samples = (size_t)ns;
  lua_settop(L, 2);
  ud = bsfit__lua_newcurve(L, &a);
  e = bsfit_filter_reduce_curve(c, &o, &ud->c, &rep, &st);
  if (e != BSFIT_OK) return bsfit__lua_result(L, e, &st, 0, 2);
  lua_createtable(L, 0, 4);
  set_number(L, "max_deviation", rep.max_deviation);
  set_number(L, "bound", rep.bound);
  set_integer(L, "rounds", rep.rounds);
  push_added(L, c, &ud->c);
  lua_setfield(L, -2, "knots_added");
  return 2;
}

static void push_smooth_report(lua_State *L, const bsfit_smooth_report *r) {
  lua_createtable(L, 0, 11);
  lua_pushboolean(L, r->changed);
  lua_setfield(L, -2, "changed");
  set_integer(L, "order", r->order);
  set_number(L, "delta", r->delta);
  set_number(L, "max_deviation", r->max_deviation);
  set_integer(L, "knots_added", (lua_Integer)r->knots_added);
  set_number(L, "turning_before", r->turning_before);
  set_number(L, "turning_after", r->turning_after);
  set_number(L, "energy_before", r->energy_before);
  set_number(L, "energy_after", r->energy_after);
  set_integer(L, "evaluations", r->evaluations);
  set_number(L, "bound", r->bound);
}

/* The options of bs.filter.smooth at 2 into o. */
static void smooth_opts(lua_State *L, bsfit_smooth_opts *o) {
  static const char *const names[] = {"tol", "degree", "order", NULL};
  lua_Integer q;
  luaL_checktype(L, 2, LUA_TTABLE);
  bsfit__lua_check_options(L, 2, names);
  memset(o, 0, sizeof *o);
  o->tol = req_number(L, 2, "tol");
  if (!(o->tol > 0) || !isfinite(o->tol))
    luaL_argerror(L, 2, lua_pushfstring(L, "field 'tol' must be a finite number > 0, got %f",
                                        o->tol));
  q = opt_integer(L, 2, "degree", 3);
  luaL_argcheck(L, q >= 1 && q <= BSFIT_MAX_DEGREE, 2, "field 'degree' must be in 1..30");
  o->degree = (int)q;
  o->order = bsfit__lua_field(L, 2, "order") == LUA_TNIL ? 0 : opt_order(L, 2, "order", 1);
  lua_settop(L, 2);
}

/* bs.filter.smooth(S, {tol = t [, degree =] [, order =]}) -> surface, report */
static int smooth_surface(lua_State *L) {
  bsfit_surface *s = bsfit__lua_checksurface(L, 1);
  bsfit_smooth_opts o;
  bsfit_smooth_report rep;
  bsfit_allocator a;
  bsfit_surface_ud *ud;
  bsfit_status st;
  bsfit_err e;
  smooth_opts(L, &o);
  ud = bsfit__lua_newsurface(L, &a);
  e = bsfit_filter_smooth_surface(s, &o, &ud->s, &rep, &st);
  if (e != BSFIT_OK) return bsfit__lua_result(L, e, &st, 0, 2);
  push_smooth_report(L, &rep);
  return 2;
}

/* bs.filter.smooth(C | S, {tol = t [, degree =] [, order =]}) -> curve | surface, report */
static int filter_smooth(lua_State *L) {
  bsfit_curve *c;
  bsfit_smooth_opts o;
  bsfit_smooth_report rep;
  bsfit_allocator a;
  bsfit_curve_ud *ud;
  bsfit_status st;
  bsfit_err e;
  if (luaL_testudata(L, 1, BSFIT_SURFACE_T)) return smooth_surface(L);
  c = bsfit__lua_checkcurve(L, 1);
  smooth_opts(L, &o);
  ud = bsfit__lua_newcurve(L, &a);
  e = bsfit_filter_smooth_curve(c, &o, &ud->c, &rep, &st);
  if (e != BSFIT_OK) return bsfit__lua_result(L, e, &st, 0, 2);
  push_smooth_report(L, &rep);
  return 2;
}

/* bs.filter.distance(A, B [, per_span]) */
static int filter_distance(lua_State *L) {
  bsfit_curve *a = bsfit__lua_checkcurve(L, 1), *b = bsfit__lua_checkcurve(L, 2);
  lua_Integer k = luaL_optinteger(L, 3, 16);
  bsfit_status st;
  double d;
  bsfit_err e;
  luaL_argcheck(L, k >= 1 && k <= 100000, 3, "samples per span must be in 1..100000");
  e = bsfit_curve_distance(a, b, (size_t)k, &d, &st);
  if (e != BSFIT_OK) return bsfit__lua_raise(L, e, &st, 1);
  lua_pushnumber(L, d);
  return 1;
}

/* }==================================================================== */

static const luaL_Reg filter_funcs[] = {{"box", filter_box},
                                        {"kernel", filter_kernel},
                                        {"reduce", filter_reduce},
                                        {"smooth", filter_smooth},
                                        {"distance", filter_distance},
                                        {NULL, NULL}};

/* sets bs.filter in the module table on the stack top */
void bsfit__lua_lib_filter(lua_State *L) {
  luaL_newlib(L, filter_funcs);
  lua_setfield(L, -2, "filter");
}
