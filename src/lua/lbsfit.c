/*
** lbsfit.c
** luaopen_bsfit: builds every userdata metatable, then returns the module table
** of constructors and kernels (bs.points, bs.vector, bs.knots, bs.curve, bs.bezier,
** bs.surface, bs.bezier_surface, bs.params, bs.geom, bs.weights, bs.fitter,
** bs.filter, bs.svg; the engine adds bs.parallel, src/host/lparallel.c). Sets no
** globals (STYLE R5, R9).
*/
#include "laux.h"

/* {====================================================================
** Module table
** ===================================================================== */

typedef void (*lib_fn)(lua_State *L);

typedef struct sublib {
  const char *name;
  lib_fn push;
} sublib;

/* constructors pushed as tables and stored under their name */
static const sublib sublibs[] = {
  {"points", bsfit__lua_lib_points}, {"vector", bsfit__lua_lib_vector},
  {"knots", bsfit__lua_lib_knots},   {"curve", bsfit__lua_lib_curve},
  {"bezier", bsfit__lua_lib_bezier}, {NULL, NULL}};

/* functions that set their own fields in the module table on the stack top */
static const lib_fn setters[] = {
  bsfit__lua_lib_geom,   bsfit__lua_lib_weights, bsfit__lua_lib_fitter,
  bsfit__lua_lib_filter, bsfit__lua_lib_surface, bsfit__lua_lib_svg,
  bsfit__lua_lib_auto,   bsfit__lua_lib_io,      bsfit__lua_lib_exchange, bsfit__lua_lib_skin,
  bsfit__lua_lib_scan,   bsfit__lua_lib_features, NULL};

/* bs.errname(code) --> "ESINGULAR": the names the fail triple carries */
static int l_errname(lua_State *L) {
  lua_Integer code = luaL_checkinteger(L, 1);
  lua_pushstring(L, bsfit_errname((bsfit_err)code));
  return 1;
}

static const luaL_Reg bsfit_funcs[] = {{"errname", l_errname}, {NULL, NULL}};

BSFIT_API int luaopen_bsfit(lua_State *L) {
  const sublib *s;
  const lib_fn *f;
  bsfit_lua_open_points(L);
  bsfit_lua_open_vector(L);
  bsfit_lua_open_knots(L);
  bsfit_lua_open_curve(L);
  bsfit_lua_open_surface(L);
  bsfit_lua_open_fitter(L);
  bsfit_lua_open_svg(L);
  luaL_newlib(L, bsfit_funcs); /* checks the Lua version too */
  for (s = sublibs; s->name != NULL; s++) {
    s->push(L);
    lua_setfield(L, -2, s->name);
  }
  for (f = setters; *f != NULL; f++) (*f)(L);
  bsfit__lua_protect_metatables(L); /* after every luaL_newmetatable above */
  lua_pushliteral(L, BSFIT_VERSION);
  lua_setfield(L, -2, "version");
  lua_pushliteral(L, "bsfit " BSFIT_VERSION);
  lua_setfield(L, -2, "_VERSION");
  return 1;
}

/* }==================================================================== */
