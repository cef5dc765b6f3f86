/*
** lexchange.c
** CAD exchange files holding several curves (a batch's sections), src/bsfit_io.h:
**   bs.io.write_step({C1, C2, ...}, path) --> true, or nil, message, code
**   bs.io.write_dxf({C1, C2, ...}, path)  --> true, or nil, message, code
** One curve or a surface goes through C:write / S:write (lcurve.c, lsurface.c). The
** functions are added to bs.io, which is created when no other file made it.
*/
#include "laux.h"

#include <string.h>

typedef bsfit_err (*curves_writer)(const bsfit_curve *const *c, size_t n, const char *path,
                                   bsfit_status *st);

/* The curves of the sequence at arg, as an array of pointers kept in a userdata pushed on
** the stack (so a raise cannot leak it). Checks what the format holds, counting from 1. */
static const bsfit_curve *const *check_curves(lua_State *L, int arg, size_t *n,
                                              const char *format) {
  const bsfit_curve **c;
  lua_Integer len, i;
  luaL_checktype(L, arg, LUA_TTABLE);
  len = luaL_len(L, arg);
  luaL_argcheck(L, len >= 1 && len <= 10000000, arg, "a non-empty list of curves expected");
  c = (const bsfit_curve **)lua_newuserdatauv(L, (size_t)len * sizeof *c, 0);
  for (i = 1; i <= len; i++) {
    const bsfit_curve *ci;
    lua_geti(L, arg, i);
    if (!luaL_testudata(L, -1, BSFIT_CURVE_T))
      luaL_argerror(L, arg, lua_pushfstring(L, "item %I is a %s, not a bsfit.Curve", i,
                                            luaL_typename(L, -1)));
    ci = bsfit__lua_checkcurve(L, -1);
    if (ci->dim < 2 || ci->dim > 3 || ci->degree < 1)
      luaL_argerror(L, arg, lua_pushfstring(L, "curve %I (dim %d, degree %d): %s holds 2D and "
                                               "3D curves of degree >= 1", i, ci->dim,
                                               ci->degree, format));
    c[i - 1] = ci;
    lua_pop(L, 1); /* the list keeps the curve alive */
  }
  *n = (size_t)len;
  return c;
}

static int write_curves(lua_State *L, curves_writer w, const char *format) {
  const char *path = luaL_checkstring(L, 2);
  size_t n;
  const bsfit_curve *const *c = check_curves(L, 1, &n, format);
  bsfit_status st;
  bsfit_err e;
  bsfit__lua_check_files(L, w == bsfit_curves_write_step ? "bs.io.write_step" : "bs.io.write_dxf");
  e = w(c, n, path, &st);
  lua_pushboolean(L, 1);
  return bsfit__lua_result(L, e, &st, 1, 1);
}

/* bs.io.write_step(curves, path) */
static int io_write_step(lua_State *L) { return write_curves(L, bsfit_curves_write_step, "STEP"); }

/* bs.io.write_dxf(curves, path) */
static int io_write_dxf(lua_State *L) { return write_curves(L, bsfit_curves_write_dxf, "DXF"); }

static const luaL_Reg io_funcs[] = {
  {"write_step", io_write_step}, {"write_dxf", io_write_dxf}, {NULL, NULL}};

/* sets bs.io.write_step (and the others) in the module table on the stack top */
void bsfit__lua_lib_exchange(lua_State *L) {
  if (lua_getfield(L, -1, "io") != LUA_TTABLE) {
    lua_pop(L, 1);
    lua_newtable(L);
    lua_pushvalue(L, -1);
    lua_setfield(L, -3, "io");
  }
  luaL_setfuncs(L, io_funcs, 0);
  lua_pop(L, 1);
}
