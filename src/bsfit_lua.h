/*
** bsfit_lua.h
** The Lua binding: luaopen_bsfit, and check/push helpers for hosts that add their
** own Lua functions working on bsfit objects.
*/
#ifndef BSFIT_LUA_H
#define BSFIT_LUA_H

#include "bsfit.h"

#include <lua.h>

/** Opens the bsfit module: returns (pushes) its table. Use with luaL_requiref or as
** the C loader of `require "bsfit"`. Sets no globals. */
BSFIT_API int luaopen_bsfit(lua_State *L);

#endif
