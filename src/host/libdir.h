/*
** libdir.h
** Where the engine's code was loaded from, for finding the Lua modules installed
** next to it (engine.c's lua/ directory search).
*/
#ifndef BSFIT_HOST_LIBDIR_H
#define BSFIT_HOST_LIBDIR_H

/* The Lua module directory relative to the program's directory (bindir) and to the
** engine library's (libdir); CMake passes the installed layout's values. */
#ifndef BSFIT_LUA_DIR_FROM_BIN
#define BSFIT_LUA_DIR_FROM_BIN "../share/lua/5.4"
#endif

/* The path of the shared object (or program) holding the engine's code, in a
** malloc'd string the caller frees; NULL when unknown or out of memory. */
char *bsfit__code_path(void);

#endif
