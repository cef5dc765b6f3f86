/*
** bsfit_lua.h
** The Lua binding: luaopen_bsfit, and check/push helpers for hosts that add their
** own Lua functions working on bsfit objects.
*/
#ifndef BSFIT_LUA_H
#define BSFIT_LUA_H

#include "bsfit.h"

#include <lua.h>

/* Registry fields a host sets before it opens the module (the engine does, see
** bsfit_engine.h); the binding only reads them.
** BSFIT_LUA_SANDBOX: `true` when the state is sandboxed. It is the one place the
**   sandbox is known: the binding refuses file access and bs.parallel.map, the
**   command line refuses subcommands, all by reading it (bsfit_lua_sandboxed).
** BSFIT_LUA_INTERRUPT: a light userdata pointing at the host's `volatile int`
**   interrupt flag; the binding gives it to the core's long loops through the
**   bsfit_allocator of every object it creates (non-zero: stop, BSFIT_EINTR). */
#define BSFIT_LUA_SANDBOX "bsfit.sandbox"
#define BSFIT_LUA_INTERRUPT "bsfit.interrupt"

/** Non-zero when the registry field BSFIT_LUA_SANDBOX of L is true. */
BSFIT_API int bsfit_lua_sandboxed(lua_State *L);

/** Opens the bsfit module: returns (pushes) its table. Use with luaL_requiref or as
** the C loader of `require "bsfit"`. Sets no globals. */
BSFIT_API int luaopen_bsfit(lua_State *L);

/* Check/push helpers. The check functions raise a Lua error (bad argument #arg)
** when the value at `arg` is not of the type; the returned pointers are borrowed:
** valid while the value stays reachable from Lua (e.g. on the stack). */

/** Points at arg: returns the row-major coordinates, sets *n (points) and *dim. */
BSFIT_API const double *bsfit_lua_checkpoints(lua_State *L, int arg, size_t *n, size_t *dim);
/** Pushes new zeroed Points (n x dim, dim 1..4) and returns its coordinates for the
** caller to fill. Raises on bad sizes or out of memory. */
BSFIT_API double *bsfit_lua_pushpoints(lua_State *L, size_t n, size_t dim);
/** Vector at arg: returns its n doubles and sets *n. */
BSFIT_API const double *bsfit_lua_checkvector(lua_State *L, int arg, size_t *n);
/** Pushes a new zeroed Vector of n doubles and returns them for the caller to fill. */
BSFIT_API double *bsfit_lua_pushvector(lua_State *L, size_t n);
/** Curve at arg (raises for a closed curve). */
BSFIT_API const bsfit_curve *bsfit_lua_checkcurve(lua_State *L, int arg);
/** Pushes a Curve holding a deep copy of src (memory from Lua's allocator). */
BSFIT_API void bsfit_lua_pushcurve(lua_State *L, const bsfit_curve *src);

/** Surface at arg (raises for a closed surface). */
BSFIT_API const bsfit_surface *bsfit_lua_checksurface(lua_State *L, int arg);
/** Pushes a Surface holding a deep copy of src (memory from Lua's allocator). */
BSFIT_API void bsfit_lua_pushsurface(lua_State *L, const bsfit_surface *src);

#endif
