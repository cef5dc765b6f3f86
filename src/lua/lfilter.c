/*
** lfilter.c
** bs.filter.box: smoothing by a box filter (SPEC 3, Persiano; src/bsfit_filter.h).
**   bs.filter.box(C, k)                     moving average over k knot spans (uniform C)
**   bs.filter.box(C, {delta = d})           exact filter of half-width d, any polynomial C
**   bs.filter.box(S, k, l)                  k x l knot spans of a uniform surface
**   bs.filter.box(S, {delta_u =, delta_v =}) exact filter of any polynomial surface
** Each returns a new Curve / Surface of one degree more (the input is unchanged); the
** work is done in the core. Inputs the filter cannot take (a rational curve, a window
** wider than the curve, non-uniform knots for the moving average) are misuse: raised.
*/
#include "laux.h"

#include <stdint.h>

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

static const luaL_Reg filter_funcs[] = {{"box", filter_box}, {NULL, NULL}};

/* sets bs.filter in the module table on the stack top */
void bsfit__lua_lib_filter(lua_State *L) {
  luaL_newlib(L, filter_funcs);
  lua_setfield(L, -2, "filter");
}
