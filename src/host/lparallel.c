/*
** lparallel.c
** bs.parallel: run a Lua function over many string items on worker threads, one
** bsfit engine per worker (parallel.c), plus a monotonic clock. It lives with the
** host because its workers are engines: the binding (src/lua) knows nothing of
** it. The engine preloads it as `bsfit.parallel` and sets it as bs.parallel;
** under stock lua5.4, require "bsfit.parallel" finds it in bsfit.so.
**
**   local results, errors = bs.parallel.map(module, fn, items [, nthreads])
**
** calls require(module)[fn](item) for every string of the array `items` in a
** fresh Lua state per worker and returns the results (strings) in item order;
** results[i] is false when item i failed, and errors[i] then holds the message.
** Workers see the caller's package.path/cpath. A sandboxed caller
** (bsfit_lua_sandboxed) may not call it: its workers would run outside the
** caller's instruction budget, memory cap and interrupt.
**
**   bs.parallel.clock() --> seconds (monotonic wall clock, for timing)
**   bs.parallel.cpus()  --> number of online processors
*/
#define _POSIX_C_SOURCE 200809L

#include "bsfit_engine.h"
#include "bsfit_lua.h"
#include "parallel.h"

#include <lauxlib.h>
#include <lua.h>

#include <limits.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

#define BSFIT_PJOB_T "bsfit.ParallelJob"

/* {====================================================================
** The job userdata: owns the worker outputs until they are copied into Lua,
** so that a memory error while building the result tables leaks nothing.
** ===================================================================== */

static bsfit_pmap *newjob(lua_State *L, size_t n) {
  bsfit_pmap *job = (bsfit_pmap *)lua_newuserdatauv(L, sizeof *job, 1);
  memset(job, 0, sizeof *job);
  luaL_setmetatable(L, BSFIT_PJOB_T);
  /* the item array is a second userdata, anchored as the job's user value */
  job->items = (bsfit_pmap_item *)lua_newuserdatauv(L, n * sizeof(bsfit_pmap_item), 0);
  memset(job->items, 0, n * sizeof(bsfit_pmap_item));
  job->n = n;
  lua_setiuservalue(L, -2, 1);
  return job;
}

static int job_gc(lua_State *L) {
  bsfit_pmap *job = (bsfit_pmap *)luaL_checkudata(L, 1, BSFIT_PJOB_T);
  bsfit__pmap_clear(job);
  return 0;
}

/* }==================================================================== */

/* {====================================================================
** Functions
** ===================================================================== */

/* package.<k> of the calling state, or NULL (the string stays anchored in
** package while map runs: no Lua code of this state runs meanwhile). */
static const char *package_field(lua_State *L, const char *k) {
  const char *s = NULL;
  if (lua_getglobal(L, "package") == LUA_TTABLE && lua_getfield(L, -1, k) == LUA_TSTRING)
    s = lua_tostring(L, -1);
  lua_settop(L, 4);
  return s;
}

static int parallel_map(lua_State *L) {
  const char *module = luaL_checkstring(L, 1);
  const char *fn = luaL_checkstring(L, 2);
  lua_Integer nt = luaL_optinteger(L, 4, 1), len;
  const char *path, *cpath;
  size_t n, i;
  bsfit_pmap *job;
  if (bsfit_lua_sandboxed(L))
    return luaL_error(L, "bs.parallel.map is not allowed in the sandbox");
  luaL_checktype(L, 3, LUA_TTABLE);
  luaL_argcheck(L, nt >= 1 && nt <= 256, 4, "number of threads must be in 1..256");
  len = luaL_len(L, 3);
  luaL_argcheck(L, len >= 0 && (lua_Unsigned)len < (size_t)-1 / sizeof(bsfit_pmap_item), 3,
                "too many items");
  lua_settop(L, 4);
  n = (size_t)len;
  for (i = 1; i <= n; i++) {
    if (lua_geti(L, 3, (lua_Integer)i) != LUA_TSTRING)
      return luaL_argerror(L, 3, lua_pushfstring(L, "item %d is a %s, not a string", (int)i,
                                                 luaL_typename(L, -1)));
    lua_pop(L, 1);
  }
  path = package_field(L, "path");
  cpath = package_field(L, "cpath");
  job = newjob(L, n); /* slot 5: from here the outputs are owned by its __gc */
  job->module = module;
  job->fn = fn;
  job->sandbox = 0;
  job->path = path;
  job->cpath = cpath;
  for (i = 0; i < n; i++) { /* the strings stay anchored in the items table */
    lua_geti(L, 3, (lua_Integer)(i + 1));
    job->items[i].in = lua_tolstring(L, -1, &job->items[i].inlen);
    lua_pop(L, 1);
  }
  bsfit__pmap_run(job, (int)nt);
  lua_createtable(L, (int)(n < INT_MAX ? n : 0), 0); /* results, slot 6 */
  lua_newtable(L);                                    /* errors, slot 7 */
  for (i = 0; i < n; i++) {
    const bsfit_pmap_item *it = &job->items[i];
    if (it->ok) {
      lua_pushlstring(L, it->out, it->outlen);
    } else {
      lua_pushstring(L, it->out != NULL ? it->out : "not enough memory for the result");
      lua_rawseti(L, 7, (lua_Integer)(i + 1));
      lua_pushboolean(L, 0);
    }
    lua_rawseti(L, 6, (lua_Integer)(i + 1));
  }
  bsfit__pmap_clear(job);
  return 2;
}

static int parallel_clock(lua_State *L) {
  struct timespec ts;
  clock_gettime(CLOCK_MONOTONIC, &ts);
  lua_pushnumber(L, (lua_Number)ts.tv_sec + (lua_Number)ts.tv_nsec * 1e-9);
  return 1;
}

static int parallel_cpus(lua_State *L) {
  long n = sysconf(_SC_NPROCESSORS_ONLN);
  lua_pushinteger(L, n > 0 ? (lua_Integer)n : 1);
  return 1;
}

/* }==================================================================== */

/* {====================================================================
** Registration
** ===================================================================== */

static const luaL_Reg job_metameth[] = {{"__gc", job_gc}, {"__close", job_gc}, {NULL, NULL}};

static const luaL_Reg parallel_funcs[] = {
  {"map", parallel_map}, {"clock", parallel_clock}, {"cpus", parallel_cpus}, {NULL, NULL}};

BSFIT_API int luaopen_bsfit_parallel(lua_State *L) {
  if (luaL_newmetatable(L, BSFIT_PJOB_T)) {
    luaL_setfuncs(L, job_metameth, 0);
    lua_pushliteral(L, BSFIT_PJOB_T); /* protected, like the binding's metatables */
    lua_setfield(L, -2, "__metatable");
  }
  lua_pop(L, 1);
  luaL_newlib(L, parallel_funcs);
  return 1;
}

/* }==================================================================== */
