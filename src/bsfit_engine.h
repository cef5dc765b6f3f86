/*
** bsfit_engine.h
** The embedding API: an engine owns one Lua state with the bsfit module preloaded
** and the shipped lua/ directory on the module path, optionally sandboxed and
** limited in memory and instructions. Hosts run scripts or call a fitting
** strategy on a point array and get the curve back as a plain bsfit_curve.
**
** Conventions:
** - Every call that runs Lua code returns a bsfit_err; on failure the message
**   (with file:line and a stack traceback for script errors) is available from
**   bsfit_engine_errmsg until the next call on the same engine.
** - Engines share no state: two threads may each use their own engine at the
**   same time. One engine must not be used by two threads at once (except
**   bsfit_engine_interrupt, which may be called from anywhere, see there).
** - A failed call leaves the engine usable: its stack is restored, its hooks
**   disarmed; only what the script itself changed (globals) persists.
*/
#ifndef BSFIT_ENGINE_H
#define BSFIT_ENGINE_H

#include "bsfit.h"

#ifdef __cplusplus
extern "C" {
#endif

/** An engine: a Lua state plus its limits and last error message. Opaque. */
typedef struct bsfit_engine bsfit_engine;

/** How to build an engine. A zeroed struct (or NULL) means: full standard
** library, no limits, lua/ directory found automatically. */
typedef struct bsfit_engine_opts {
  /** Non-zero: only the base, table, string, math, utf8 and coroutine libraries;
  ** no io, os, debug, dofile, loadfile, no C modules; `load` only accepts text
  ** chunks; `require` only finds `bsfit` and the .lua modules of the lua/ directory
  ** (package keeps loaded, preload and searchers: no searchpath, loadlib, cpath);
  ** setmetatable refuses a __gc field and bsfit's metatables are protected (Lua
  ** runs finalizers with hooks off, so no limit could stop one); an xpcall message
  ** handler is not run once the call is stopping; bsfit's file functions and
  ** bs.parallel.map raise. The engine records it in the registry field
  ** BSFIT_LUA_SANDBOX (bsfit_lua.h), which every layer reads. C code is not counted
  ** by the instruction budget: a pathological string.find pattern can still run
  ** long (docs/embedding.md says what the sandbox does not guarantee). */
  int sandbox;
  /** Maximum bytes the Lua state may hold at once (0 = no limit). An allocation
  ** beyond it fails, which Lua turns into a "not enough memory" error and the
  ** engine into BSFIT_ENOMEM. Must leave room for the libraries (about 100 KB). */
  size_t mem_limit;
  /** Maximum Lua VM instructions per call (run_file, run_string, fit, pcall);
  ** 0 = no limit. When it runs out the call fails with BSFIT_EINTR, and a
  ** script's own pcall cannot catch that. */
  unsigned long long instr_budget;
  /** Directory holding the shipped Lua modules (bsfit/...), or NULL: then
  ** $BSFIT_PATH, else <exe dir>/../share/lua/5.4 (an installed program reads its
  ** own modules, even while the tree it was built from still exists), else, for the
  ** installed libbsfit_engine, <its lib dir>/../share/lua/5.4, else the build tree's
  ** lua/ (a program run from the build directory), else the install prefix's
  ** share/lua/5.4 (where stock lua5.4 finds them too). The string is copied. */
  const char *lua_path;
  /** Optional argv[0] of the host program, used to find <exe dir> when
  ** /proc/self/exe is unavailable. May be NULL. The string is copied. */
  const char *argv0;
} bsfit_engine_opts;

/** What a fitting strategy reports besides its curve (bsfit_engine_fit). */
typedef struct bsfit_engine_report {
  double rms;         /**< root mean square deviation of the points (NaN if not reported) */
  double max;         /**< maximum deviation (NaN if not reported) */
  size_t count;       /**< the report's `count`: the curve's number of distinct control
                           points, as the bsfit.strategy modules report it; 0 if absent */
  size_t start_index; /**< 0-based index of the point the curve starts at (the Lua
                           report's `start_index` is 1-based); 0 if not reported */
} bsfit_engine_report;

/** Creates an engine.
** @param[in] opts  options, or NULL for the defaults. Not kept after the call.
** @return the engine, to be released with bsfit_engine_free; NULL when memory
**         runs out (including a mem_limit too small for the libraries). */
BSFIT_API bsfit_engine *bsfit_engine_new(const bsfit_engine_opts *opts);

/** Closes the engine's Lua state (running finalizers) and frees everything it
** owns. NULL-safe. Curves returned by bsfit_engine_fit stay valid. */
BSFIT_API void bsfit_engine_free(bsfit_engine *e);

/** Runs a Lua script file (text only in sandbox mode).
** @param[in] path  file name; the chunk is named "@path" so messages say path:line.
** @return BSFIT_OK; BSFIT_EIO (file unreadable); BSFIT_EFORMAT (syntax error or
**         binary chunk refused); BSFIT_EINVAL (the script raised an error);
**         BSFIT_ENOMEM (memory limit or allocation failure); BSFIT_EINTR
**         (instruction budget exhausted or bsfit_engine_interrupt). */
BSFIT_API bsfit_err bsfit_engine_run_file(bsfit_engine *e, const char *path);

/** Runs a chunk of Lua source (never bytecode).
** @param[in] chunk  the source text, NUL-terminated.
** @param[in] name   chunk name as Lua takes it ("=name" or "@file"), or NULL for
**                   "=(string)".
** @return as bsfit_engine_run_file, without BSFIT_EIO. */
BSFIT_API bsfit_err bsfit_engine_run_string(bsfit_engine *e, const char *chunk,
                                            const char *name);

/** Loads a script file as a function and pushes it on the engine's Lua stack (text
** only in sandbox mode; a first line starting with '#' is skipped), for hosts that
** pass it arguments and call it with bsfit_engine_pcall.
** @param[in] path  file name, or NULL for the standard input.
** @return BSFIT_OK (one value pushed); BSFIT_EIO, BSFIT_EFORMAT or BSFIT_ENOMEM
**         (nothing pushed). */
BSFIT_API bsfit_err bsfit_engine_load(bsfit_engine *e, const char *path);

/** Calls the function below nargs arguments on the engine's Lua stack, exactly
** as lua_pcall(L, nargs, nresults, 0) would, but with the engine's message
** handler (traceback), instruction budget, interrupt and error conversion. On
** success the results are left on the stack; on failure the function and
** arguments are popped and nothing is pushed.
** @return BSFIT_OK, BSFIT_EINVAL, BSFIT_ENOMEM or BSFIT_EINTR. */
BSFIT_API bsfit_err bsfit_engine_pcall(bsfit_engine *e, int nargs, int nresults);

/** Fits a curve to points with a strategy.
** @param[in]  strategy  a module name (e.g. "bsfit.strategy.periodic", loaded with
**                       require) or a script path (contains '/' or ends in ".lua")
**                       returning the module. The module is a table with a function
**                       `run(P, opts)` returning a bsfit curve and a report table.
** @param[in]  pts       m points of dim coordinates, row-major [x0,y0,(z0,)x1,...].
**                       Copied; the caller keeps ownership.
** @param[in]  m         number of points (>= 1).
** @param[in]  dim       2 or 3.
** @param[in]  w         m per-point weights, or NULL. They mean what a point file's w
**                       column means to `bsfit reconstruct`: the strategy's
**                       `point_weights`, multiplying its weighting rule (they do not
**                       replace it). All positive and finite.
** @param[in]  opts_lua  a Lua table constructor with the strategy's options, e.g.
**                       "{ degree = 3, closed = true }", or NULL for {}. It is
**                       evaluated as data: it sees no globals.
** @param[out] out       an initialised curve (bsfit_curve_init, or holding a curve,
**                       which is freed first); receives a deep copy of the strategy's
**                       curve allocated with the C library's realloc, independent of
**                       the engine. Release it with bsfit_curve_free. Empty on failure.
** @param[out] rep       the report, or NULL if not wanted.
** @return BSFIT_OK; the strategy's own code when `run` answers `nil, message, code`
**         (code a name such as "ESINGULAR"; the message is the strategy's, prefixed
**         with its name; EINVAL when the code names no bsfit_err); BSFIT_EINVAL (bad
**         arguments, a strategy error, or `run` returning something not a curve);
**         BSFIT_EFORMAT (opts_lua or the strategy file does not parse); BSFIT_EIO
**         (strategy file unreadable); BSFIT_EDIM (dim not 2 or 3); BSFIT_ENONFINITE
**         (a NaN or Inf in pts) and BSFIT_EWEIGHT (a weight not positive and finite),
**         both naming the array element, before any Lua runs; BSFIT_ENOMEM;
**         BSFIT_EINTR. */
BSFIT_API bsfit_err bsfit_engine_fit(bsfit_engine *e, const char *strategy,
                                     const double *pts, size_t m, int dim, const double *w,
                                     const char *opts_lua, bsfit_curve *out,
                                     bsfit_engine_report *rep);

/** The message of the last failed call on e ("" after a successful one). Owned by
** the engine, valid until the next call on e. Never NULL (NULL e gives a fixed
** "no engine" text). */
BSFIT_API const char *bsfit_engine_errmsg(const bsfit_engine *e);

/** Asks the running call to stop: it fails with BSFIT_EINTR at the next Lua
** instruction it executes, or sooner inside a C kernel that looks at the flag (the
** fitter's loops do, every few thousand points, through the bsfit_allocator of the
** objects the binding makes: registry field BSFIT_LUA_INTERRUPT). Async-signal-safe, and
** may be called from another thread (it only stores a flag and sets a hook, as
** lua.c's SIGINT handler does). An interrupt that arrives while no call runs is
** forgotten when the next call starts. NULL-safe. */
BSFIT_API void bsfit_engine_interrupt(bsfit_engine *e);

/** The engine's Lua state, for hosts that push their own functions (see
** bsfit_lua.h). Call Lua code on it through bsfit_engine_pcall so limits and
** messages apply. Do not lua_close it. */
BSFIT_API struct lua_State *bsfit_engine_lua(bsfit_engine *e);

/** The engine owning L (or a coroutine of it), or NULL when L was not made by
** bsfit_engine_new. For C functions called from Lua that need the engine's
** settings, e.g. to give worker engines the same sandbox and limits. */
BSFIT_API bsfit_engine *bsfit_engine_from_lua(struct lua_State *L);

/** Copies the options e was created with into *out; lua_path is the directory in
** use (bsfit_engine_luadir, borrowed from e) and argv0 is NULL. */
BSFIT_API void bsfit_engine_get_opts(const bsfit_engine *e, bsfit_engine_opts *out);

/** The lua/ directory the engine put on its module path ("" if none was found). */
BSFIT_API const char *bsfit_engine_luadir(const bsfit_engine *e);

/** Opens bs.parallel (map, clock, cpus) and returns (pushes) its table: the C loader
** of `require "bsfit.parallel"`. An engine preloads it and its `require "bsfit"`
** sets the field `parallel` of the module; bsfit.so exports it for stock lua5.4.
** bs.parallel.map raises in a sandboxed state. */
BSFIT_API int luaopen_bsfit_parallel(struct lua_State *L);

#ifdef __cplusplus
}
#endif

#endif /* BSFIT_ENGINE_H */
