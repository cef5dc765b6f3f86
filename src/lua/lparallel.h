/*
** lparallel.h
** bs.parallel (src/lua/lparallel.c): called by luaopen_bsfit.
*/
#ifndef BSFIT_LPARALLEL_H
#define BSFIT_LPARALLEL_H

#include <lua.h>

/* With the bsfit module table at the top of the stack, adds its field `parallel`
** (map, clock, cpus). Leaves the stack as it found it; returns 0. */
int bsfit_lua_open_parallel(lua_State *L);

#endif
