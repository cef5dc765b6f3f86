/*
** lio.c
** bs.io: the file system as the command-line jobs need it, without a shell
** (src/core/io_dir.c). Absent from a sandboxed state (the registry flag
** "bsfit.sandbox"): listing directories tells a script what exists.
**   bs.io.listdir(path)  --> sorted array of names ("." and ".." left out), or
**                            nil, message, "EIO" (missing, not a directory, unreadable)
**   bs.io.kind(path)     --> "file" | "directory" | "other" | nil (nothing there)
**   bs.io.mkdir(path)    --> true, or nil, message, "EIO" (mkdir -p)
*/
#include "laux.h"

#include <string.h>

#define BSFIT_NAMES_T "bsfit.io.names"

/* Owns what bsfit_dir_list returned until the names are in a Lua table, so that a
** memory error while pushing them cannot leak them. */
typedef struct names_ud {
  char **v;
  size_t n;
} names_ud;

static int names_gc(lua_State *L) {
  names_ud *u = (names_ud *)luaL_checkudata(L, 1, BSFIT_NAMES_T);
  bsfit_dir_free(u->v, u->n, NULL);
  u->v = NULL;
  u->n = 0;
  return 0;
}

static int io_listdir(lua_State *L) {
  const char *path = luaL_checkstring(L, 1);
  names_ud *u = (names_ud *)lua_newuserdatauv(L, sizeof *u, 0);
  bsfit_status st;
  bsfit_err e;
  size_t i;
  u->v = NULL;
  u->n = 0;
  if (luaL_newmetatable(L, BSFIT_NAMES_T)) {
    lua_pushcfunction(L, names_gc);
    lua_setfield(L, -2, "__gc");
    lua_pushliteral(L, "locked");
    lua_setfield(L, -2, "__metatable");
  }
  lua_setmetatable(L, -2);
  e = bsfit_dir_list(path, &u->v, &u->n, NULL, &st);
  if (e != BSFIT_OK) return bsfit__lua_result(L, e, &st, 0, 1);
  luaL_argcheck(L, u->n < (size_t)0x7fffffff, 1, "too many entries");
  lua_createtable(L, (int)u->n, 0);
  for (i = 0; i < u->n; i++) {
    lua_pushstring(L, u->v[i]);
    lua_rawseti(L, -2, (lua_Integer)i + 1);
  }
  bsfit_dir_free(u->v, u->n, NULL);
  u->v = NULL;
  u->n = 0;
  return 1;
}

static int io_kind(lua_State *L) {
  static const char *const kinds[] = {NULL, "file", "directory", "other"};
  int k = bsfit_path_kind(luaL_checkstring(L, 1));
  if (k == BSFIT_PATH_NONE)
    luaL_pushfail(L);
  else
    lua_pushstring(L, kinds[k]);
  return 1;
}

static int io_mkdir(lua_State *L) {
  const char *path = luaL_checkstring(L, 1);
  bsfit_status st;
  bsfit_err e = bsfit_dir_make(path, NULL, &st);
  if (e == BSFIT_OK) lua_pushboolean(L, 1);
  return bsfit__lua_result(L, e, &st, 1, 1);
}

static const luaL_Reg io_funcs[] = {
    {"listdir", io_listdir}, {"kind", io_kind}, {"mkdir", io_mkdir}, {NULL, NULL}};

void bsfit__lua_lib_io(lua_State *L) {
  if (bsfit_lua_sandboxed(L)) return;
  luaL_newlib(L, io_funcs);
  lua_setfield(L, -2, "io");
}
