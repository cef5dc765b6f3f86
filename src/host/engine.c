/*
** engine.c
** The embedding engine (bsfit_engine.h): one Lua state per engine with a
** counting allocator (memory cap), a restricted library set in sandbox mode,
** bsfit in package.preload, the lua/ directory on the module path, and one
** docall through which every host->Lua call goes (message handler with
** traceback, instruction budget and interrupt through a count hook, error
** message copied into an engine-owned buffer, BSFIT_* code returned).
*/
#define _POSIX_C_SOURCE 200809L

#include "bsfit_engine.h"
#include "bsfit_lua.h"
#include "libdir.h"

#include <lauxlib.h>
#include <lua.h>
#include <lualib.h>

#include <limits.h>
#include <math.h>
#include <stdarg.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

/* With a budget, the count hook fires every HOOK_CHUNK instructions: lua_sethook's
** int count never overflows whatever the budget, and a stop seen in one coroutine
** reaches the threads that are not re-armed (see stop) within that many of their
** instructions. Without a budget the main thread runs with no hook at all: any count
** hook makes Lua 5.4 trace every instruction (luaG_traceexec), which halves the speed
** of Lua code whatever the count; coroutines alone keep one (see hook_new_thread). */
#define HOOK_CHUNK 1000
#define ERRMSG_MIN 256

struct bsfit_engine {
  lua_State *L;
  size_t mem_limit;          /* 0 = none */
  size_t mem_used;           /* bytes the Lua state holds now */
  int mem_refused;           /* an allocation failed during the current call */
  unsigned long long budget; /* instructions per call, 0 = none */
  unsigned long long left;   /* instructions left in the current call */
  int armed;                 /* count the hook is armed with */
  int tripped;               /* the budget ran out in the current call */
  volatile int interrupted;  /* an int (the core's bsfit_allocator.interrupt reads it);
                                ** storing an int is atomic on every platform bsfit runs on */
  int sandbox;
  int depth;                 /* nesting of docall (a host C function may call back) */
  int warn_on, warn_cont;    /* lua_setwarnf state (lauxlib's warnf on/off) */
  char *luadir;
  char *errmsg;
  size_t errcap;
};

/* {====================================================================
** Memory: the ltests.c memlimit design, with the engine as allocator ud
** ===================================================================== */

static void *engine_alloc(void *ud, void *ptr, size_t osize, size_t nsize) {
  bsfit_engine *e = (bsfit_engine *)ud;
  size_t old = ptr != NULL ? osize : 0; /* for new blocks osize is a type tag */
  void *p;
  if (nsize == 0) {
    free(ptr);
    e->mem_used -= old;
    return NULL;
  }
  /* Refusing only growth keeps Lua's rule that shrinking never fails. */
  if (e->mem_limit != 0 && nsize > old && nsize - old > e->mem_limit - e->mem_used) {
    e->mem_refused = 1;
    return NULL;
  }
  p = realloc(ptr, nsize);
  if (p == NULL) {
    e->mem_refused = 1;
    return NULL;
  }
  e->mem_used = e->mem_used - old + nsize;
  return p;
}

static bsfit_engine *engine_of(lua_State *L) {
  void *ud = NULL;
  (void)lua_getallocf(L, &ud);
  return (bsfit_engine *)ud;
}

/* }==================================================================== */

/* {====================================================================
** Error messages: an engine-owned buffer, as sqlite3_errmsg
** ===================================================================== */

static void set_errmsg(bsfit_engine *e, const char *msg, size_t len) {
  if (len + 1 > e->errcap) {
    char *p = (char *)realloc(e->errmsg, len + 1);
    if (p != NULL) {
      e->errmsg = p;
      e->errcap = len + 1;
    } else {
      len = e->errcap - 1; /* keep what fits rather than lose the message */
    }
  }
  memcpy(e->errmsg, msg, len);
  e->errmsg[len] = '\0';
}

static bsfit_err fail(bsfit_engine *e, bsfit_err code, const char *fmt, ...) {
  char buf[512];
  va_list ap;
  int n;
  va_start(ap, fmt);
  n = vsnprintf(buf, sizeof buf, fmt, ap);
  va_end(ap);
  if (n < 0) n = 0;
  set_errmsg(e, buf, (size_t)n < sizeof buf ? (size_t)n : sizeof buf - 1);
  return code;
}

/* Copies the error value on top of the stack into errmsg and pops it. */
static void take_error(bsfit_engine *e) {
  size_t len = 0;
  const char *msg = lua_tolstring(e->L, -1, &len);
  if (msg == NULL) {
    msg = "(error object is not a string)";
    len = strlen(msg);
  }
  set_errmsg(e, msg, len);
  lua_pop(e->L, 1);
}

/* }==================================================================== */

/* {====================================================================
** Hooks: instruction budget and interrupt
** ===================================================================== */

static void engine_hook(lua_State *L, lua_Debug *ar);

/* Arms the count hook of L for the budget left, or takes L's hook off when the engine
** has no budget (this also clears a stale interrupt hook). */
static void arm_budget(bsfit_engine *e, lua_State *L) {
  if (e->budget == 0) {
    lua_sethook(L, NULL, 0, 0);
    return;
  }
  e->armed = e->left < HOOK_CHUNK ? (int)e->left : HOOK_CHUNK;
  lua_sethook(L, engine_hook, LUA_MASKCOUNT, e->armed);
}

/* Raises the stop error and re-arms the hook on every line and instruction, so a
** script's pcall that catches one raise meets the next one at once (Redis). */
static void stop(lua_State *L, const char *why) {
  bsfit_engine *e = engine_of(L);
  lua_sethook(L, engine_hook, LUA_MASKLINE | LUA_MASKCOUNT, 1);
  if (L != e->L) lua_sethook(e->L, engine_hook, LUA_MASKLINE | LUA_MASKCOUNT, 1);
  luaL_where(L, 0);
  lua_pushstring(L, why);
  lua_concat(L, 2);
  lua_error(L);
}

static void engine_hook(lua_State *L, lua_Debug *ar) {
  bsfit_engine *e = engine_of(L);
  if (e->interrupted) stop(L, "interrupted");
  if (e->budget != 0 && !e->tripped && ar->event == LUA_HOOKCOUNT) {
    unsigned long long done = (unsigned long long)e->armed;
    if (e->left > done) {
      e->left -= done;
      arm_budget(e, L);
      return;
    }
    e->left = 0;
    e->tripped = 1;
  }
  if (e->tripped) stop(L, "instruction budget exceeded");
}

void bsfit_engine_interrupt(bsfit_engine *e) {
  if (e == NULL) return;
  e->interrupted = 1;
  /* lua_sethook is signal-safe (lua.c's laction relies on it). */
  lua_sethook(e->L, engine_hook, LUA_MASKCALL | LUA_MASKRET | LUA_MASKLINE | LUA_MASKCOUNT, 1);
}

/* A new coroutine gets the count hook the main thread lacks without a budget, so that
** an interrupt reaches a loop inside it (the interrupt can only hook the main thread,
** the one it knows to be alive); with a budget it keeps the hook it inherited. Only
** code inside coroutines pays the tracing cost. */
static void hook_new_thread(lua_State *co) {
  if (lua_gethook(co) == NULL) lua_sethook(co, engine_hook, LUA_MASKCOUNT, HOOK_CHUNK);
}

/* Calls the wrapped library function (upvalue 1) with the arguments, leaving its one
** result; the function argument is checked here, so that an error names the function
** as the caller called it. */
static void call_wrapped(lua_State *L) {
  luaL_checktype(L, 1, LUA_TFUNCTION);
  lua_pushvalue(L, lua_upvalueindex(1));
  lua_insert(L, 1);
  lua_call(L, lua_gettop(L) - 1, 1);
}

/* coroutine.create, then hook_new_thread. */
static int hooked_create(lua_State *L) {
  call_wrapped(L);
  hook_new_thread(lua_tothread(L, -1));
  return 1;
}

/* coroutine.wrap, then hook_new_thread on the thread it made (its function's first
** upvalue, as in lcorolib.c). */
static int hooked_wrap(lua_State *L) {
  call_wrapped(L);
  if (lua_getupvalue(L, -1, 1) != NULL) {
    if (lua_type(L, -1) == LUA_TTHREAD) hook_new_thread(lua_tothread(L, -1));
    lua_pop(L, 1);
  }
  return 1;
}

static void hook_coroutines(lua_State *L) {
  lua_getglobal(L, LUA_COLIBNAME);
  lua_getfield(L, -1, "create");
  lua_pushcclosure(L, hooked_create, 1);
  lua_setfield(L, -2, "create");
  lua_getfield(L, -1, "wrap");
  lua_pushcclosure(L, hooked_wrap, 1);
  lua_setfield(L, -2, "wrap");
  lua_pop(L, 1);
}

/* }==================================================================== */

/* {====================================================================
** docall: the one way into Lua (lua.c's docall + msghandler)
** ===================================================================== */

/* Stopping: the budget ran out or the host interrupted. Handlers must then run no
** script code: Lua calls a message handler again, with hooks off, for an error
** raised by a hook, and nothing could stop a loop there. */
static int stopping(const bsfit_engine *e) {
  return e->tripped || e->interrupted;
}

static int msghandler(lua_State *L) {
  const char *msg = lua_tostring(L, 1);
  if (msg == NULL) {
    if (!stopping(engine_of(L)) && luaL_callmeta(L, 1, "__tostring") &&
        lua_type(L, -1) == LUA_TSTRING)
      return 1;
    msg = lua_pushfstring(L, "(error object is a %s value)", luaL_typename(L, 1));
  }
  luaL_traceback(L, L, msg, 1);
  return 1;
}

/* The one mapping of a Lua status (of a load or a call) to a bsfit_err, for every
** engine entry. A stop (budget, interrupt) or a refused allocation wins over the
** status Lua reports, because a script may have caught the first error and
** raised another, or Lua may report the failure as an error in error handling. */
static bsfit_err status_code(const bsfit_engine *e, int status) {
  if (status == LUA_OK) return BSFIT_OK;
  if (e->tripped || e->interrupted) return BSFIT_EINTR;
  if (e->mem_refused || status == LUA_ERRMEM) return BSFIT_ENOMEM;
  if (status == LUA_ERRSYNTAX) return BSFIT_EFORMAT;
  if (status == LUA_ERRFILE) return BSFIT_EIO;
  return BSFIT_EINVAL;
}

static void begin_call(bsfit_engine *e) {
  e->interrupted = 0;
  e->tripped = 0;
  e->mem_refused = 0;
  e->left = e->budget;
  arm_budget(e, e->L); /* also replaces a stale interrupt hook */
}

static bsfit_err docall(bsfit_engine *e, int nargs, int nresults) {
  lua_State *L = e->L;
  int base = lua_gettop(L) - nargs;
  int status;
  bsfit_err code;
  if (e->depth++ == 0) begin_call(e);
  lua_pushcfunction(L, msghandler);
  lua_insert(L, base);
  status = lua_pcall(L, nargs, nresults, base);
  lua_remove(L, base);
  code = status_code(e, status);
  if (--e->depth == 0) lua_sethook(L, NULL, 0, 0);
  if (status != LUA_OK)
    take_error(e);
  else
    set_errmsg(e, "", 0);
  return code;
}

bsfit_err bsfit_engine_pcall(bsfit_engine *e, int nargs, int nresults) {
  if (e == NULL) return BSFIT_EINVAL;
  if (nargs < 0 || lua_gettop(e->L) < nargs + 1)
    return fail(e, BSFIT_EINVAL, "bsfit_engine_pcall: %d arguments but only %d values on the stack",
                nargs, lua_gettop(e->L));
  return docall(e, nargs, nresults);
}

/* Converts a load status (luaL_load*: the message is on the stack) and pops it. */
static bsfit_err load_code(bsfit_engine *e, int status) {
  bsfit_err code = status_code(e, status);
  if (code != BSFIT_OK) take_error(e);
  return code;
}

/* Loads a file (NULL = stdin) as a function on the stack; text only when sandboxed. */
static bsfit_err load_file(bsfit_engine *e, const char *path) {
  e->mem_refused = 0;
  return load_code(e, luaL_loadfilex(e->L, path, e->sandbox ? "t" : NULL));
}

/* }==================================================================== */

/* {====================================================================
** Finding the lua/ directory
** ===================================================================== */

static int is_dir(const char *path) {
  struct stat sb;
  return path != NULL && path[0] != '\0' && stat(path, &sb) == 0 && S_ISDIR(sb.st_mode);
}

static char *dup_str(const char *s) {
  size_t n = strlen(s) + 1;
  char *p = (char *)malloc(n);
  if (p != NULL) memcpy(p, s, n);
  return p;
}

/* <dir>/<rel> when it holds the bsfit modules (a bsfit/ directory); NULL otherwise.
** dir may be a file's path: its last component is dropped. */
static char *luadir_under(const char *path, const char *rel) {
  const char *slash = path != NULL ? strrchr(path, '/') : NULL;
  size_t n;
  char *out;
  if (slash == NULL) return NULL;
  n = (size_t)(slash - path);
  out = (char *)malloc(n + strlen(rel) + sizeof "//bsfit");
  if (out == NULL) return NULL;
  memcpy(out, path, n);
  out[n] = '/';
  strcpy(out + n + 1, rel);
  strcat(out, "/bsfit");
  if (is_dir(out)) {
    out[strlen(out) - sizeof "/bsfit" + 1] = '\0';
    return out;
  }
  free(out);
  return NULL;
}

/* <exe dir>/<BSFIT_LUA_DIR_FROM_BIN> (share/lua/5.4 of the prefix), the program's
** path from /proc/self/exe or else argv0; then, for the installed engine library,
** the same from the library's own directory, so `cmake --install --prefix P`
** works whatever prefix the build was configured with. NULL if none. */
static char *installed_luadir(const char *argv0) {
  char exe[4096];
  char *out = NULL;
  ssize_t n = readlink("/proc/self/exe", exe, sizeof exe - 1);
  if (n > 0) exe[n] = '\0';
  else if (argv0 != NULL && strlen(argv0) < sizeof exe) strcpy(exe, argv0);
  else exe[0] = '\0';
#ifdef BSFIT_LUA_DIR_FROM_BIN
  out = luadir_under(exe, BSFIT_LUA_DIR_FROM_BIN);
#endif
#ifdef BSFIT_LUA_DIR_FROM_LIB
  if (out == NULL) {
    char *lib = bsfit__code_path();
    out = luadir_under(lib, BSFIT_LUA_DIR_FROM_LIB);
    free(lib);
  }
#endif
  return out;
}

/* The directory by the order of bsfit_engine_opts.lua_path's documentation;
** "" when none exists. NULL only when out of memory. */
static char *find_luadir(const bsfit_engine_opts *o) {
  const char *env = getenv("BSFIT_PATH");
  char *inst;
  if (o->lua_path != NULL) return dup_str(o->lua_path);
  if (env != NULL && env[0] != '\0') return dup_str(env);
  inst = installed_luadir(o->argv0); /* before the build tree: see lua_path's doc */
  if (inst != NULL) return inst;
#ifdef BSFIT_LUA_DIR_BUILD
  if (is_dir(BSFIT_LUA_DIR_BUILD)) return dup_str(BSFIT_LUA_DIR_BUILD);
#endif
#ifdef BSFIT_LUA_DIR_INSTALL
  if (is_dir(BSFIT_LUA_DIR_INSTALL)) return dup_str(BSFIT_LUA_DIR_INSTALL);
#endif
  return dup_str("");
}

/* }==================================================================== */

/* {====================================================================
** Opening the state: full or sandboxed library set
** ===================================================================== */

/* load that forces text mode: bytecode is never checked by Lua (manual 6.1). */
static int sandbox_load(lua_State *L) {
  int n = lua_gettop(L);
  luaL_checkany(L, 1);
  lua_pushvalue(L, lua_upvalueindex(1));
  lua_pushvalue(L, 1);
  if (n >= 2) lua_pushvalue(L, 2); else lua_pushnil(L);
  lua_pushliteral(L, "t");
  if (n >= 4) lua_pushvalue(L, 4); /* an explicit env, even nil, must stay explicit */
  lua_call(L, n >= 4 ? 4 : 3, LUA_MULTRET);
  return lua_gettop(L) - n;
}

/* setmetatable that refuses a metatable with a __gc field: Lua runs finalizers
** with hooks off (lgc.c GCTM), so neither the budget nor an interrupt could stop
** a looping finalizer, during a call or in bsfit_engine_free. The field is
** refused even when it is not a function, because an object is marked for
** finalization by the field's presence at setmetatable time. */
static int sandbox_setmetatable(lua_State *L) {
  if (lua_istable(L, 2)) {
    lua_pushliteral(L, "__gc");
    if (lua_rawget(L, 2) != LUA_TNIL)
      return luaL_argerror(L, 2, "a __gc metamethod is not allowed in the sandbox");
    lua_pop(L, 1);
  }
  lua_pushvalue(L, lua_upvalueindex(1));
  lua_insert(L, 1);
  lua_call(L, lua_gettop(L) - 1, 1);
  return 1;
}

/* package.searchers entry of the sandbox: .lua files of the lua/ directory only,
** loaded as text. Dots in the name become '/', so a name cannot climb out. */
static int sandbox_searcher(lua_State *L) {
  static const char *const pats[] = {"%s/%s.lua", "%s/%s/init.lua"};
  const char *name = luaL_checkstring(L, 1);
  const char *dir = lua_tostring(L, lua_upvalueindex(1));
  const char *rel = luaL_gsub(L, name, ".", "/");
  luaL_Buffer b;
  size_t i;
  luaL_buffinit(L, &b);
  for (i = 0; i < sizeof pats / sizeof pats[0]; i++) {
    const char *fn = lua_pushfstring(L, pats[i], dir, rel);
    FILE *f = fopen(fn, "r");
    if (f != NULL) {
      fclose(f);
      if (luaL_loadfilex(L, fn, "t") != LUA_OK)
        return luaL_error(L, "error loading module '%s' from file '%s':\n\t%s", name, fn,
                          lua_tostring(L, -1));
      lua_pushstring(L, fn);
      return 2;
    }
    lua_pop(L, 1);
  }
  lua_pushfstring(L, "no file '%s/%s.lua'\n\tno file '%s/%s/init.lua'", dir, rel, dir, rel);
  return 1;
}

/* The message handler a sandboxed xpcall gives Lua: the script's handler (upvalue
** 1), unless the call is stopping. Lua runs a message handler with hooks off when
** the error came from a hook (the budget's or the interrupt's stop), so a looping
** handler could not be stopped there; and a handler that runs when the stop
** comes is stopped in turn, whose error calls this again, now stopping. */
static int sandbox_msgh(lua_State *L) {
  lua_settop(L, 1);
  if (stopping(engine_of(L))) return 1; /* the stop's message, unchanged */
  lua_pushvalue(L, lua_upvalueindex(1));
  lua_insert(L, 1);
  lua_call(L, 1, 1);
  return 1;
}

static int sandbox_xpcall_k(lua_State *L, int status, lua_KContext ctx) {
  (void)status;
  (void)ctx;
  return lua_gettop(L);
}

/* xpcall(f, msgh, ...) with msgh wrapped by sandbox_msgh; f may yield, as in Lua's. */
static int sandbox_xpcall(lua_State *L) {
  int n = lua_gettop(L);
  luaL_checktype(L, 2, LUA_TFUNCTION);
  lua_pushvalue(L, 2);
  lua_pushcclosure(L, sandbox_msgh, 1);
  lua_replace(L, 2);
  lua_pushvalue(L, lua_upvalueindex(1)); /* the real xpcall */
  lua_insert(L, 1);
  lua_callk(L, n, LUA_MULTRET, 0, sandbox_xpcall_k);
  return sandbox_xpcall_k(L, LUA_OK, 0);
}

/* Wraps global `name` in a C closure of f with the original as upvalue 1. */
static void wrap_global(lua_State *L, const char *name, lua_CFunction f) {
  lua_getglobal(L, name);
  lua_pushcclosure(L, f, 1);
  lua_setglobal(L, name);
}

/* package keeps only what require needs: loaded, preload, and searchers of our
** own (preload, then .lua files of dir). Gone: loadlib and the C searchers (C
** code), searchpath (it tells whether any file exists and is readable), cpath and
** path (a script cannot point require elsewhere: dir is the searcher's upvalue). */
static void sandbox_package(lua_State *L, const char *dir) {
  static const char *const drop[] = {"loadlib", "searchpath", "cpath", "path", "config"};
  size_t i;
  lua_getglobal(L, LUA_LOADLIBNAME);
  for (i = 0; i < sizeof drop / sizeof drop[0]; i++) {
    lua_pushnil(L);
    lua_setfield(L, -2, drop[i]);
  }
  lua_createtable(L, 2, 0);
  lua_getfield(L, -2, "searchers");
  lua_rawgeti(L, -1, 1); /* the preload searcher */
  lua_rawseti(L, -3, 1);
  lua_pop(L, 1);
  lua_pushstring(L, dir);
  lua_pushcclosure(L, sandbox_searcher, 1);
  lua_rawseti(L, -2, 2);
  lua_setfield(L, -2, "searchers");
  lua_pop(L, 1);
}

static void open_sandbox(lua_State *L, const char *dir) {
  static const luaL_Reg libs[] = {
    {LUA_GNAME, luaopen_base},         {LUA_TABLIBNAME, luaopen_table},
    {LUA_STRLIBNAME, luaopen_string},  {LUA_MATHLIBNAME, luaopen_math},
    {LUA_UTF8LIBNAME, luaopen_utf8},   {LUA_COLIBNAME, luaopen_coroutine},
    {LUA_LOADLIBNAME, luaopen_package}, {NULL, NULL}};
  const luaL_Reg *lib;
  for (lib = libs; lib->func != NULL; lib++) {
    luaL_requiref(L, lib->name, lib->func, 1);
    lua_pop(L, 1);
  }
  lua_pushnil(L);
  lua_setglobal(L, "dofile");
  lua_pushnil(L);
  lua_setglobal(L, "loadfile");
  wrap_global(L, "load", sandbox_load);
  wrap_global(L, "setmetatable", sandbox_setmetatable);
  wrap_global(L, "xpcall", sandbox_xpcall);
  hook_coroutines(L);
  sandbox_package(L, dir);
}

static void open_full(lua_State *L, const char *dir) {
  luaL_openlibs(L);
  hook_coroutines(L);
  if (dir[0] == '\0') return;
  lua_getglobal(L, LUA_LOADLIBNAME);
  lua_getfield(L, -1, "path");
  lua_pushfstring(L, "%s/?.lua;%s/?/init.lua;%s", dir, dir, lua_tostring(L, -1));
  lua_setfield(L, -3, "path");
  lua_pop(L, 2);
}

/* The engine's loader of `require "bsfit"`: the binding's module plus bs.parallel,
** which lives here with the host (the binding does not know about it). */
static int engine_open_bsfit(lua_State *L) {
  luaopen_bsfit(L);
  luaL_requiref(L, "bsfit.parallel", luaopen_bsfit_parallel, 0);
  lua_setfield(L, -2, "parallel");
  return 1;
}

/* Runs protected: any memory error while opening makes bsfit_engine_new fail. The
** registry fields come first: the binding reads them whenever it runs. */
static int engine_init(lua_State *L) {
  bsfit_engine *e = engine_of(L);
  lua_pushboolean(L, e->sandbox);
  lua_setfield(L, LUA_REGISTRYINDEX, BSFIT_LUA_SANDBOX);
  lua_pushlightuserdata(L, (void *)(uintptr_t)&e->interrupted); /* read as volatile */
  lua_setfield(L, LUA_REGISTRYINDEX, BSFIT_LUA_INTERRUPT);
  if (e->sandbox)
    open_sandbox(L, e->luadir);
  else
    open_full(L, e->luadir);
  luaL_getsubtable(L, LUA_REGISTRYINDEX, LUA_PRELOAD_TABLE); /* the linit.c recipe */
  lua_pushcfunction(L, engine_open_bsfit);
  lua_setfield(L, -2, "bsfit");
  lua_pushcfunction(L, luaopen_bsfit_parallel);
  lua_setfield(L, -2, "bsfit.parallel");
  lua_pop(L, 1);
  return 0;
}

/* Warnings as lauxlib's default: off until "@on", pieces joined, to stderr. */
static void engine_warn(void *ud, const char *msg, int tocont) {
  bsfit_engine *e = (bsfit_engine *)ud;
  if (!e->warn_cont && msg[0] == '@') {
    if (strcmp(msg, "@on") == 0) e->warn_on = 1;
    if (strcmp(msg, "@off") == 0) e->warn_on = 0;
    return;
  }
  if (e->warn_on) {
    if (!e->warn_cont) fputs("Lua warning: ", stderr);
    fputs(msg, stderr);
    if (!tocont) fputs("\n", stderr);
    fflush(stderr);
  }
  e->warn_cont = tocont;
}

bsfit_engine *bsfit_engine_new(const bsfit_engine_opts *opts) {
  static const bsfit_engine_opts defaults = {0, 0, 0, NULL, NULL};
  const bsfit_engine_opts *o = opts != NULL ? opts : &defaults;
  bsfit_engine *e = (bsfit_engine *)calloc(1, sizeof *e);
  if (e == NULL) return NULL;
  e->mem_limit = o->mem_limit;
  e->budget = o->instr_budget;
  e->sandbox = o->sandbox != 0;
  e->luadir = find_luadir(o);
  e->errmsg = (char *)malloc(ERRMSG_MIN);
  if (e->luadir == NULL || e->errmsg == NULL) goto fail;
  e->errcap = ERRMSG_MIN;
  e->errmsg[0] = '\0';
  e->L = lua_newstate(engine_alloc, e);
  if (e->L == NULL) goto fail;
  lua_setwarnf(e->L, engine_warn, e);
  lua_pushcfunction(e->L, engine_init);
  if (lua_pcall(e->L, 0, 0, 0) != LUA_OK) goto fail;
  return e;
fail:
  bsfit_engine_free(e);
  return NULL;
}

void bsfit_engine_free(bsfit_engine *e) {
  if (e == NULL) return;
  if (e->L != NULL) {
    lua_sethook(e->L, NULL, 0, 0);
    lua_close(e->L);
  }
  free(e->luadir);
  free(e->errmsg);
  free(e);
}

/* }==================================================================== */

/* {====================================================================
** Running scripts
** ===================================================================== */

bsfit_err bsfit_engine_run_file(bsfit_engine *e, const char *path) {
  bsfit_err code;
  if (e == NULL) return BSFIT_EINVAL;
  if (path == NULL) return fail(e, BSFIT_EINVAL, "bsfit_engine_run_file: path is NULL");
  code = load_file(e, path);
  if (code != BSFIT_OK) return code;
  return docall(e, 0, 0);
}

bsfit_err bsfit_engine_run_string(bsfit_engine *e, const char *chunk, const char *name) {
  bsfit_err code;
  if (e == NULL) return BSFIT_EINVAL;
  if (chunk == NULL) return fail(e, BSFIT_EINVAL, "bsfit_engine_run_string: chunk is NULL");
  e->mem_refused = 0;
  code = load_code(e, luaL_loadbufferx(e->L, chunk, strlen(chunk), name ? name : "=(string)", "t"));
  if (code != BSFIT_OK) return code;
  return docall(e, 0, 0);
}

bsfit_err bsfit_engine_load(bsfit_engine *e, const char *path) {
  if (e == NULL) return BSFIT_EINVAL;
  return load_file(e, path);
}

const char *bsfit_engine_errmsg(const bsfit_engine *e) {
  return e != NULL ? e->errmsg : "no engine";
}

struct lua_State *bsfit_engine_lua(bsfit_engine *e) {
  return e != NULL ? e->L : NULL;
}

bsfit_engine *bsfit_engine_from_lua(struct lua_State *L) {
  void *ud = NULL;
  if (L == NULL || lua_getallocf(L, &ud) != engine_alloc) return NULL;
  return (bsfit_engine *)ud;
}

void bsfit_engine_get_opts(const bsfit_engine *e, bsfit_engine_opts *out) {
  if (out == NULL) return;
  memset(out, 0, sizeof *out);
  if (e == NULL) return;
  out->sandbox = e->sandbox;
  out->mem_limit = e->mem_limit;
  out->instr_budget = e->budget;
  out->lua_path = e->luadir;
}

const char *bsfit_engine_luadir(const bsfit_engine *e) {
  return e != NULL ? e->luadir : "";
}

/* }==================================================================== */

/* {====================================================================
** bsfit_engine_fit: a strategy module on a host point array
** ===================================================================== */

typedef struct fit_args {
  const char *strategy;
  const double *pts, *w;
  size_t m;
  int dim;
  const char *opts_lua;
  bsfit_curve *out;
  bsfit_engine_report *rep;
  bsfit_err code; /* a more precise code than "script error" (load failures, copy) */
  bsfit_status st;
} fit_args;

/* Raises the load error on the stack, remembering its precise code. */
static int raise_load(lua_State *L, fit_args *fa, int status) {
  fa->code = status_code(engine_of(L), status);
  return lua_error(L);
}

static int is_path(const char *s) {
  size_t n = strlen(s);
  return strchr(s, '/') != NULL || (n > 4 && strcmp(s + n - 4, ".lua") == 0);
}

/* Pushes the strategy's run function. */
static void push_run(lua_State *L, fit_args *fa) {
  bsfit_engine *e = engine_of(L);
  if (is_path(fa->strategy)) {
    int status = luaL_loadfilex(L, fa->strategy, e->sandbox ? "t" : NULL);
    if (status != LUA_OK) raise_load(L, fa, status);
    lua_call(L, 0, 1);
  } else {
    lua_getglobal(L, "require");
    lua_pushstring(L, fa->strategy);
    lua_call(L, 1, 1);
  }
  if (lua_type(L, -1) != LUA_TTABLE || lua_getfield(L, -1, "run") != LUA_TFUNCTION)
    luaL_error(L, "strategy '%s' is not a module with a run function", fa->strategy);
  lua_remove(L, -2);
}

/* Pushes the options table: opts_lua evaluated as data, in an empty environment. */
static void push_opts(lua_State *L, fit_args *fa) {
  if (fa->opts_lua == NULL) {
    lua_newtable(L);
  } else {
    int status;
    lua_pushfstring(L, "return %s", fa->opts_lua);
    status = luaL_loadbufferx(L, lua_tostring(L, -1), lua_rawlen(L, -1), "=opts", "t");
    if (status != LUA_OK) raise_load(L, fa, status);
    lua_remove(L, -2);
    lua_newtable(L);
    lua_setupvalue(L, -2, 1); /* _ENV: no globals */
    lua_call(L, 0, 1);
    if (!lua_istable(L, -1)) {
      fa->code = BSFIT_EFORMAT;
      luaL_error(L, "options must be a Lua table constructor, got a %s", luaL_typename(L, -1));
    }
  }
  if (fa->w != NULL) { /* as a file's w column: it multiplies the strategy's rule */
    memcpy(bsfit_lua_pushvector(L, fa->m), fa->w, fa->m * sizeof(double));
    lua_setfield(L, -2, "point_weights");
  }
}

static size_t opt_size(lua_State *L, int t, const char *k, size_t def) {
  lua_Integer v;
  int ok;
  lua_getfield(L, t, k);
  v = lua_tointegerx(L, -1, &ok);
  lua_pop(L, 1);
  return ok && v >= 0 ? (size_t)v : def;
}

static double opt_double(lua_State *L, int t, const char *k) {
  int ok;
  double v;
  lua_getfield(L, t, k);
  v = (double)lua_tonumberx(L, -1, &ok);
  lua_pop(L, 1);
  return ok ? v : NAN;
}

/* The report first (it may raise, through metamethods), the C copy of the curve
** last: nothing may raise once `out` holds memory Lua does not own (R4). */
static void collect(lua_State *L, fit_args *fa, int curve, int report) {
  const bsfit_curve *c = bsfit_lua_checkcurve(L, curve);
  bsfit_engine_report r = {NAN, NAN, 0, 0};
  bsfit_allocator libc = {NULL, NULL, NULL};
  if (lua_istable(L, report)) {
    size_t start = opt_size(L, report, "start_index", 0);
    r.rms = opt_double(L, report, "rms");
    r.max = opt_double(L, report, "max");
    r.count = opt_size(L, report, "count", 0);
    r.start_index = start > 0 ? start - 1 : 0;
  }
  if (fa->rep != NULL) *fa->rep = r;
  fa->code = bsfit_curve_copy(c, fa->out, &libc, &fa->st);
}

/* The bsfit_err named by a fail triple's third value ("ESINGULAR"); EINVAL when it
** names none. */
static bsfit_err code_of_name(const char *name) {
  int c;
  if (name != NULL)
    for (c = -1; c >= -99; c--)
      if (strcmp(bsfit_errname((bsfit_err)c), name) == 0) return (bsfit_err)c;
  return BSFIT_EINVAL;
}

/* Returns nil, or the strategy's message when it answered `nil, msg, code` (then
** fa->code holds the code): a strategy's outcome reaches the host as itself. */
static int pfit(lua_State *L) {
  fit_args *fa = (fit_args *)lua_touserdata(L, 1);
  size_t nbytes = fa->m * (size_t)fa->dim * sizeof(double);
  lua_settop(L, 0);
  push_run(L, fa);
  memcpy(bsfit_lua_pushpoints(L, fa->m, (size_t)fa->dim), fa->pts, nbytes);
  push_opts(L, fa);
  lua_call(L, 2, 3);
  if (!lua_toboolean(L, 1)) {
    fa->code = code_of_name(lua_tostring(L, 3));
    if (lua_type(L, 2) == LUA_TSTRING || lua_type(L, 2) == LUA_TNUMBER)
      lua_pushfstring(L, "%s: %s", fa->strategy, lua_tostring(L, 2));
    else
      lua_pushfstring(L, "%s: run returned no curve", fa->strategy);
    return 1;
  }
  collect(L, fa, 1, 2);
  lua_pushnil(L);
  return 1;
}

/* The host's arrays, checked before any Lua runs: the message names the C element. */
static bsfit_err check_fit_data(bsfit_engine *e, const double *pts, size_t m, int dim,
                                const double *w) {
  size_t i;
  for (i = 0; i < m * (size_t)dim; i++)
    if (!isfinite(pts[i]))
      return fail(e, BSFIT_ENONFINITE, "bsfit_engine_fit: pts[%zu] = %g (point %zu) is not finite",
                  i, pts[i], i / (size_t)dim);
  for (i = 0; w != NULL && i < m; i++)
    if (!(w[i] > 0.0 && isfinite(w[i])))
      return fail(e, BSFIT_EWEIGHT, "bsfit_engine_fit: w[%zu] = %g (weights must be positive and "
                  "finite)", i, w[i]);
  return BSFIT_OK;
}

bsfit_err bsfit_engine_fit(bsfit_engine *e, const char *strategy, const double *pts, size_t m,
                           int dim, const double *w, const char *opts_lua, bsfit_curve *out,
                           bsfit_engine_report *rep) {
  fit_args fa;
  bsfit_err code;
  if (e == NULL) return BSFIT_EINVAL;
  if (out == NULL) return fail(e, BSFIT_EINVAL, "bsfit_engine_fit: out is NULL");
  bsfit_curve_free(out);
  if (strategy == NULL || strategy[0] == '\0')
    return fail(e, BSFIT_EINVAL, "bsfit_engine_fit: no strategy given");
  if (pts == NULL || m == 0) return fail(e, BSFIT_EINVAL, "bsfit_engine_fit: no points (m = %zu)", m);
  if (dim != 2 && dim != 3)
    return fail(e, BSFIT_EDIM, "bsfit_engine_fit: dim = %d, must be 2 or 3", dim);
  if (m > SIZE_MAX / (3 * sizeof(double)))
    return fail(e, BSFIT_EINVAL, "bsfit_engine_fit: m = %zu is too large", m);
  code = check_fit_data(e, pts, m, dim, w);
  if (code != BSFIT_OK) return code;
  memset(&fa, 0, sizeof fa);
  fa.strategy = strategy;
  fa.pts = pts;
  fa.w = w;
  fa.m = m;
  fa.dim = dim;
  fa.opts_lua = opts_lua;
  fa.out = out;
  fa.rep = rep;
  fa.code = BSFIT_OK;
  lua_pushcfunction(e->L, pfit);
  lua_pushlightuserdata(e->L, &fa);
  code = docall(e, 1, 1);
  if (code != BSFIT_OK) return code == BSFIT_EINVAL && fa.code != BSFIT_OK ? fa.code : code;
  if (lua_isstring(e->L, -1)) { /* the strategy's own failure: its message and code */
    take_error(e);
    return fa.code;
  }
  lua_pop(e->L, 1);
  if (fa.code != BSFIT_OK)
    return fail(e, fa.code, "bsfit_engine_fit: copying the curve: %s", fa.st.msg);
  return BSFIT_OK;
}

/* }==================================================================== */
