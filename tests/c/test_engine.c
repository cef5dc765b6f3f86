/*
** test_engine.c
** Tests of the embedding engine (bsfit_engine.h): running chunks and files, error
** messages with file:line, the sandbox's deny list, the memory cap, the
** instruction budget (also against a script's pcall), interrupts from another
** thread, independent engines in two threads, and bsfit_engine_fit round trips
** checked against the mathematics of the test strategy (degree-1 interpolation).
*/
#include "bsfit_engine.h"

#include <lauxlib.h>
#include <lua.h>

#include <math.h>
#include <pthread.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <threads.h> /* thrd_sleep: C11, needs no feature macro */
#include <time.h>

#include <cmocka.h>

#define STRATEGY BSFIT_TEST_DATA "/lua/test_strategy.lua"
#define PT_EPS 1e-12 /* point coordinates of an exact interpolation */

static bsfit_engine *new_engine(int sandbox, size_t mem, unsigned long long budget) {
  bsfit_engine_opts o = {sandbox, mem, budget, NULL, NULL};
  bsfit_engine *e = bsfit_engine_new(&o);
  assert_non_null(e);
  return e;
}

static void assert_msg_has(const bsfit_engine *e, const char *part) {
  const char *msg = bsfit_engine_errmsg(e);
  if (strstr(msg, part) == NULL) fail_msg("message \"%s\" lacks \"%s\"", msg, part);
}

/* Writes text to a file of the build tree; returns its path in buf. */
static const char *write_file(char *buf, size_t cap, const char *name, const char *text,
                              size_t len) {
  FILE *f;
  snprintf(buf, cap, "%s/%s", BSFIT_BINARY_DIR, name);
  f = fopen(buf, "wb");
  assert_non_null(f);
  assert_int_equal(fwrite(text, 1, len, f), len);
  fclose(f);
  return buf;
}

/* {====================================================================
** Running chunks and files
** ===================================================================== */

static void test_run_string_ok(void **state) {
  bsfit_engine *e = new_engine(0, 0, 0);
  lua_State *L = bsfit_engine_lua(e);
  (void)state;
  /* given a chunk that sets a global, when run, then it is visible and no error is left */
  assert_int_equal(bsfit_engine_run_string(e, "x = 6 * 7", "=t"), BSFIT_OK);
  assert_string_equal(bsfit_engine_errmsg(e), "");
  lua_getglobal(L, "x");
  assert_int_equal(lua_tointeger(L, -1), 42);
  lua_pop(L, 1);
  /* the bsfit module is preloaded, whole (file functions included) outside the sandbox */
  assert_int_equal(bsfit_engine_run_string(
                       e, "local bs = require 'bsfit'; v = type(bs) == 'table' and bs.points.read ~= nil", NULL),
                   BSFIT_OK);
  lua_getglobal(L, "v");
  assert_true(lua_toboolean(L, -1));
  lua_pop(L, 1);
  assert_int_equal(lua_gettop(L), 0);
  bsfit_engine_free(e);
}

static void test_syntax_error(void **state) {
  bsfit_engine *e = new_engine(0, 0, 0);
  (void)state;
  assert_int_equal(bsfit_engine_run_string(e, "x = = 1", "@bad.lua"), BSFIT_EFORMAT);
  assert_msg_has(e, "bad.lua:1:");
  assert_int_equal(bsfit_engine_run_string(e, "y = 1", NULL), BSFIT_OK);
  assert_int_equal(lua_gettop(bsfit_engine_lua(e)), 0);
  bsfit_engine_free(e);
}

static void test_runtime_error_file_line(void **state) {
  static const char script[] = "local t = {}\n"
                               "half = true\n"
                               "local function f() error('boom') end\n"
                               "f()\n"
                               "never = true\n";
  char path[512];
  bsfit_engine *e = new_engine(0, 0, 0);
  lua_State *L = bsfit_engine_lua(e);
  (void)state;
  write_file(path, sizeof path, "engine_halfway.lua", script, sizeof script - 1);
  /* given a script that errors halfway, when run, then the message names file:line,
  ** carries a traceback, and the lines before the error ran but not those after */
  assert_int_equal(bsfit_engine_run_file(e, path), BSFIT_EINVAL);
  assert_msg_has(e, "engine_halfway.lua:3: boom");
  assert_msg_has(e, "stack traceback:");
  lua_getglobal(L, "half");
  lua_getglobal(L, "never");
  assert_true(lua_toboolean(L, -2));
  assert_true(lua_isnil(L, -1));
  lua_pop(L, 2);
  /* a non-string error object is described, not lost */
  assert_int_equal(bsfit_engine_run_string(e, "error({})", NULL), BSFIT_EINVAL);
  assert_msg_has(e, "error object is a table value");
  /* an unreadable file is an I/O error */
  assert_int_equal(bsfit_engine_run_file(e, BSFIT_BINARY_DIR "/no/such/file.lua"), BSFIT_EIO);
  assert_msg_has(e, "no/such/file.lua");
  assert_int_equal(bsfit_engine_run_string(e, "assert(half)", NULL), BSFIT_OK);
  assert_int_equal(lua_gettop(L), 0);
  bsfit_engine_free(e);
}

static void test_null_and_misuse(void **state) {
  bsfit_engine *e = new_engine(0, 0, 0);
  (void)state;
  bsfit_engine_free(NULL);
  bsfit_engine_interrupt(NULL);
  assert_string_equal(bsfit_engine_errmsg(NULL), "no engine");
  assert_null(bsfit_engine_lua(NULL));
  assert_int_equal(bsfit_engine_run_string(NULL, "x=1", NULL), BSFIT_EINVAL);
  assert_int_equal(bsfit_engine_run_string(e, NULL, NULL), BSFIT_EINVAL);
  assert_msg_has(e, "chunk is NULL");
  assert_int_equal(bsfit_engine_run_file(e, NULL), BSFIT_EINVAL);
  assert_msg_has(e, "path is NULL");
  /* the engine is found from its state, and only from its state */
  assert_ptr_equal(bsfit_engine_from_lua(bsfit_engine_lua(e)), e);
  assert_null(bsfit_engine_from_lua(NULL));
  {
    lua_State *other = luaL_newstate();
    bsfit_engine_opts o;
    bsfit_engine *limited = new_engine(1, 1u << 24, 12345);
    assert_null(bsfit_engine_from_lua(other));
    lua_close(other);
    bsfit_engine_get_opts(limited, &o);
    assert_int_equal(o.sandbox, 1);
    assert_int_equal(o.mem_limit, 1u << 24);
    assert_int_equal(o.instr_budget, 12345);
    assert_string_equal(o.lua_path, bsfit_engine_luadir(limited));
    bsfit_engine_free(limited);
  }
  /* pcall with more arguments than values on the stack */
  assert_int_equal(bsfit_engine_pcall(e, 2, 0), BSFIT_EINVAL);
  assert_msg_has(e, "2 arguments");
  bsfit_engine_free(e);
}

static int host_add(lua_State *L) {
  lua_pushnumber(L, luaL_checknumber(L, 1) + luaL_checknumber(L, 2));
  return 1;
}

static void test_pcall_host_function(void **state) {
  bsfit_engine *e = new_engine(1, 0, 0);
  lua_State *L = bsfit_engine_lua(e);
  (void)state;
  /* a host function called through the engine returns its result ... */
  lua_pushcfunction(L, host_add);
  lua_pushnumber(L, 1.5);
  lua_pushnumber(L, 2.25);
  assert_int_equal(bsfit_engine_pcall(e, 2, 1), BSFIT_OK);
  assert_float_equal(lua_tonumber(L, -1), 3.75, 0.0);
  lua_pop(L, 1);
  /* ... and its argument errors come back as messages, the stack balanced */
  lua_pushcfunction(L, host_add);
  lua_pushliteral(L, "x");
  assert_int_equal(bsfit_engine_pcall(e, 1, 1), BSFIT_EINVAL);
  assert_msg_has(e, "bad argument #1");
  assert_int_equal(lua_gettop(L), 0);
  bsfit_engine_free(e);
}

/* }==================================================================== */

/* {====================================================================
** Sandbox
** ===================================================================== */

static void test_sandbox_denies(void **state) {
  static const char *const denied[] = {
    "io.open('/etc/passwd')",  "os.execute('true')", "debug.getinfo(1)",
    "dofile('/etc/passwd')",   "loadfile('/etc/passwd')",
    "package.loadlib('libc.so.6', 'puts')"};
  bsfit_engine *e = new_engine(1, 0, 0);
  size_t i;
  (void)state;
  for (i = 0; i < sizeof denied / sizeof denied[0]; i++) {
    /* each of these is a call on nil: the library or function is absent */
    assert_int_equal(bsfit_engine_run_string(e, denied[i], "=sandbox"), BSFIT_EINVAL);
    assert_msg_has(e, "attempt to");
  }
  /* require of a C module finds no C loader (searchers: preload and lua/ only) */
  assert_int_equal(bsfit_engine_run_string(e, "require 'lfs'", NULL), BSFIT_EINVAL);
  assert_msg_has(e, "module 'lfs' not found");
  assert_int_equal(bsfit_engine_run_string(e, "package.cpath = '/usr/lib/x86_64-linux-gnu/lua/5.4/?.so'"
                                              "; require 'lpeg'", NULL),
                   BSFIT_EINVAL);
  assert_msg_has(e, "module 'lpeg' not found");
  /* changing package.path does not widen the search */
  assert_int_equal(bsfit_engine_run_string(e, "package.path = '/etc/?'; require 'passwd'", NULL),
                   BSFIT_EINVAL);
  assert_msg_has(e, "module 'passwd' not found");
  /* load refuses a binary chunk even when asked for mode "b", accepts text */
  assert_int_equal(bsfit_engine_run_string(
                       e, "local f, err = load(string.dump(function() return 1 end), 'x', 'b')\n"
                          "assert(f == nil and err:find('binary', 1, true))\n"
                          "assert(load('return 7')() == 7)\n"
                          "assert(load('return y', 'c', 't', {y = 8})() == 8)",
                       NULL),
                   BSFIT_OK);
  /* bsfit's file functions (constructors and methods) and parallel.map refuse, by
  ** the registry's sandbox flag; the rest of bsfit works */
  assert_int_equal(bsfit_engine_run_string(
                       e, "local bs = require 'bsfit'\n"
                          "local function refused(f, ...)\n"
                          "  local ok, err = pcall(f, ...)\n"
                          "  assert(not ok and err:find('not allowed in the sandbox', 1, true), err)\n"
                          "end\n"
                          "refused(bs.points.read, '/etc/passwd')\n"
                          "refused(bs.curve.read, '/etc/passwd')\n"
                          "local P = bs.points.new(3, 2)\n"
                          "refused(P.write, P, '/tmp/bsfit_sandbox_should_not_exist.csv')\n"
                          "refused(bs.parallel.map, 'bsfit', 'x', {})\n"
                          "assert(P:get(1) and bs.parallel.clock() > 0)",
                       NULL),
                   BSFIT_OK);
  /* what stays: bsfit, string, table, math, utf8, coroutine */
  assert_int_equal(bsfit_engine_run_string(e, "assert(require 'bsfit' and string and table and"
                                              " math and utf8 and coroutine)", NULL),
                   BSFIT_OK);
  bsfit_engine_free(e);
}

static void test_sandbox_binary_file(void **state) {
  char path[512];
  bsfit_engine *full = new_engine(0, 0, 0);
  bsfit_engine *box = new_engine(1, 0, 0);
  lua_State *L = bsfit_engine_lua(full);
  size_t len;
  const char *code;
  (void)state;
  assert_int_equal(bsfit_engine_run_string(full, "bc = string.dump(load('x = 1'))", NULL), BSFIT_OK);
  lua_getglobal(L, "bc");
  code = lua_tolstring(L, -1, &len);
  write_file(path, sizeof path, "engine_bytecode.luac", code, len);
  lua_pop(L, 1);
  /* the full engine runs bytecode files as lua does; the sandbox refuses them */
  assert_int_equal(bsfit_engine_run_file(full, path), BSFIT_OK);
  assert_int_equal(bsfit_engine_run_file(box, path), BSFIT_EFORMAT);
  assert_msg_has(box, "binary chunk");
  bsfit_engine_free(full);
  bsfit_engine_free(box);
}

static void test_sandbox_require_luadir(void **state) {
  bsfit_engine_opts o = {1, 0, 0, BSFIT_TEST_DATA "/lua", NULL};
  bsfit_engine *e = bsfit_engine_new(&o);
  (void)state;
  assert_non_null(e);
  assert_string_equal(bsfit_engine_luadir(e), BSFIT_TEST_DATA "/lua");
  /* a .lua module of the lua directory loads in the sandbox */
  assert_int_equal(bsfit_engine_run_string(e, "assert(type(require('test_strategy').run) == 'function')",
                                           NULL),
                   BSFIT_OK);
  bsfit_engine_free(e);
}

/* }==================================================================== */

/* {====================================================================
** Memory cap and instruction budget
** ===================================================================== */

static void test_memory_cap(void **state) {
  static const bsfit_engine_opts tiny = {1, 1024, 0, NULL, NULL};
  bsfit_engine *e = new_engine(1, 4u << 20, 0);
  (void)state;
  /* a table growing without bound */
  assert_int_equal(bsfit_engine_run_string(e, "local t = {} for i = 1, 1e9 do t[i] = {i} end",
                                           "=bomb"),
                   BSFIT_ENOMEM);
  assert_msg_has(e, "not enough memory");
  /* one huge string (raised by a C function, not by the allocator) */
  assert_int_equal(bsfit_engine_run_string(e, "local s = string.rep('x', 1 << 30)", NULL),
                   BSFIT_ENOMEM);
  /* a bomb inside pcall is caught by the script: that is the script's choice */
  assert_int_equal(bsfit_engine_run_string(e, "caught = not pcall(string.rep, 'x', 1 << 30)",
                                           NULL),
                   BSFIT_OK);
  /* the engine is still usable once the garbage is collected */
  assert_int_equal(bsfit_engine_run_string(e, "collectgarbage() local t = {} for i = 1, 1000 do"
                                              " t[i] = i end assert(#t == 1000 and caught)", NULL),
                   BSFIT_OK);
  bsfit_engine_free(e);
  /* a cap too small for the libraries: no engine */
  assert_null(bsfit_engine_new(&tiny));
}

static void test_budget_infinite_loop(void **state) {
  bsfit_engine *e = new_engine(1, 0, 1000000);
  lua_State *L = bsfit_engine_lua(e);
  (void)state;
  assert_int_equal(bsfit_engine_run_string(e, "while true do end", "=loop"), BSFIT_EINTR);
  assert_msg_has(e, "instruction budget exceeded");
  /* the loop wrapped in pcall, retried forever: still stopped */
  assert_int_equal(bsfit_engine_run_string(
                       e, "while true do pcall(function() while true do end end) end", NULL),
                   BSFIT_EINTR);
  /* a script that catches the stop and carries on does not get to carry on */
  assert_int_equal(bsfit_engine_run_string(
                       e, "local ok, err = pcall(function() while true do end end)\n"
                          "after = true",
                       NULL),
                   BSFIT_EINTR);
  lua_getglobal(L, "after");
  assert_true(lua_isnil(L, -1));
  lua_pop(L, 1);
  /* each call has the whole budget again: a bounded loop runs */
  assert_int_equal(bsfit_engine_run_string(e, "local s = 0 for i = 1, 10000 do s = s + i end"
                                              " assert(s == 50005000)", NULL),
                   BSFIT_OK);
  /* loops inside coroutines are counted too */
  assert_int_equal(bsfit_engine_run_string(
                       e, "while true do coroutine.resume(coroutine.create(function()"
                          " while true do end end)) end", NULL),
                   BSFIT_EINTR);
  /* Lua runs finalizers with hooks off, so the sandbox refuses them: a looping
  ** __gc could otherwise hang a later call or the engine's free */
  assert_int_equal(bsfit_engine_run_string(
                       e, "setmetatable({}, {__gc = function() while true do end end})", NULL),
                   BSFIT_EINVAL);
  assert_msg_has(e, "__gc metamethod is not allowed");
  assert_int_equal(bsfit_engine_run_string(e, "setmetatable({}, {__gc = true})", NULL),
                   BSFIT_EINVAL);
  assert_int_equal(bsfit_engine_run_string(e, "local t = setmetatable({}, {__index = {a = 1}})"
                                              " assert(t.a == 1)", NULL),
                   BSFIT_OK);
  bsfit_engine_free(e);
}

static void test_budget_large(void **state) {
  /* a budget above INT_MAX is counted in chunks: a short loop finishes */
  bsfit_engine *e = new_engine(0, 0, 5000000000ULL);
  (void)state;
  assert_int_equal(bsfit_engine_run_string(e, "for i = 1, 300000 do end", NULL), BSFIT_OK);
  bsfit_engine_free(e);
}

static void *interrupt_later(void *arg) {
  struct timespec ts = {0, 50 * 1000 * 1000};
  thrd_sleep(&ts, NULL);
  bsfit_engine_interrupt((bsfit_engine *)arg);
  return NULL;
}

static void test_interrupt_from_thread(void **state) {
  bsfit_engine *e = new_engine(0, 0, 0);
  pthread_t t;
  (void)state;
  /* an interrupt while idle is forgotten when the next call starts */
  bsfit_engine_interrupt(e);
  assert_int_equal(bsfit_engine_run_string(e, "x = 1", NULL), BSFIT_OK);
  /* an unbudgeted endless loop (catching errors) is stopped by another thread */
  assert_int_equal(pthread_create(&t, NULL, interrupt_later, e), 0);
  assert_int_equal(bsfit_engine_run_string(e, "while true do pcall(error, 'x') end", NULL),
                   BSFIT_EINTR);
  assert_int_equal(pthread_join(t, NULL), 0);
  assert_msg_has(e, "interrupted");
  /* also when the loop runs inside a coroutine */
  assert_int_equal(pthread_create(&t, NULL, interrupt_later, e), 0);
  assert_int_equal(bsfit_engine_run_string(e, "coroutine.wrap(function() while true do end end)()",
                                           NULL),
                   BSFIT_EINTR);
  assert_int_equal(pthread_join(t, NULL), 0);
  assert_int_equal(bsfit_engine_run_string(e, "x = 2", NULL), BSFIT_OK);
  bsfit_engine_free(e);
}

/* Without a budget the main thread runs unhooked: any count hook makes Lua 5.4 trace
** every instruction, which halved the speed of every script. Coroutines keep a count
** hook (the interrupt above reaches them through it); with a budget both are hooked. */
static void test_hooks_only_where_needed(void **state) {
  static const char *const probe =
      "main_hook = debug.gethook() ~= nil\n"
      "local co = coroutine.create(function() return debug.gethook() ~= nil end)\n"
      "co_hook = select(2, coroutine.resume(co))\n"
      "wrap_hook = coroutine.wrap(function() return debug.gethook() ~= nil end)()";
  static const struct { unsigned long long budget; int main_hooked; } cases[] = {{0, 0},
                                                                                {1u << 30, 1}};
  size_t i;
  (void)state;
  for (i = 0; i < sizeof cases / sizeof cases[0]; i++) {
    bsfit_engine *e = new_engine(0, 0, cases[i].budget);
    lua_State *L = bsfit_engine_lua(e);
    assert_int_equal(bsfit_engine_run_string(e, probe, NULL), BSFIT_OK);
    lua_getglobal(L, "main_hook");
    lua_getglobal(L, "co_hook");
    lua_getglobal(L, "wrap_hook");
    assert_int_equal(lua_toboolean(L, -3), cases[i].main_hooked);
    assert_true(lua_toboolean(L, -2));
    assert_true(lua_toboolean(L, -1));
    lua_pop(L, 3);
    bsfit_engine_free(e);
  }
}

/* }==================================================================== */

/* {====================================================================
** Two engines, two threads
** ===================================================================== */

typedef struct job {
  int k;          /* each thread computes sum_{i<=n} k*i */
  bsfit_err code;
  double result;
  int saw_other;  /* the other engine's global leaked into this one */
} job;

static void *run_job(void *arg) {
  job *j = (job *)arg;
  bsfit_engine *e = bsfit_engine_new(NULL);
  char chunk[256];
  lua_State *L;
  if (e == NULL) {
    j->code = BSFIT_ENOMEM;
    return NULL;
  }
  L = bsfit_engine_lua(e);
  snprintf(chunk, sizeof chunk,
           "owner = %d local s = 0 for i = 1, 200000 do s = s + %d * i end"
           " result = s assert(owner == %d)", j->k, j->k, j->k);
  j->code = bsfit_engine_run_string(e, chunk, NULL);
  lua_getglobal(L, "result");
  j->result = lua_tonumber(L, -1);
  lua_getglobal(L, "owner");
  j->saw_other = lua_tointeger(L, -1) != j->k;
  bsfit_engine_free(e);
  return NULL;
}

static void test_two_threads(void **state) {
  job a = {1, BSFIT_EINVAL, 0, 1}, b = {3, BSFIT_EINVAL, 0, 1};
  pthread_t ta, tb;
  const double n = 200000.0;
  (void)state;
  assert_int_equal(pthread_create(&ta, NULL, run_job, &a), 0);
  assert_int_equal(pthread_create(&tb, NULL, run_job, &b), 0);
  assert_int_equal(pthread_join(ta, NULL), 0);
  assert_int_equal(pthread_join(tb, NULL), 0);
  assert_int_equal(a.code, BSFIT_OK);
  assert_int_equal(b.code, BSFIT_OK);
  /* Gauss: sum k*i = k n (n+1) / 2 */
  assert_float_equal(a.result, 1 * n * (n + 1) / 2, 0.0);
  assert_float_equal(b.result, 3 * n * (n + 1) / 2, 0.0);
  assert_false(a.saw_other);
  assert_false(b.saw_other);
}

/* }==================================================================== */

/* {====================================================================
** bsfit_engine_fit
** ===================================================================== */

#define NPTS 12

/* NPTS points on an ellipse and their chord-length parameters in [0, 1]. */
static void ellipse(double *pts, double *u) {
  double len = 0;
  int i;
  for (i = 0; i < NPTS; i++) {
    double t = 2 * 3.14159265358979323846 * i / (NPTS - 1.0) * 0.9;
    pts[2 * i] = 3 * cos(t);
    pts[2 * i + 1] = 2 * sin(t);
  }
  u[0] = 0;
  for (i = 1; i < NPTS; i++) {
    len += hypot(pts[2 * i] - pts[2 * i - 2], pts[2 * i + 1] - pts[2 * i - 1]);
    u[i] = len;
  }
  for (i = 0; i < NPTS; i++) u[i] /= len;
}

static void assert_interpolates(const bsfit_curve *c, const double *pts, const double *u) {
  double p[2];
  int i;
  assert_int_equal(c->degree, 1);
  assert_int_equal(c->dim, 2);
  assert_int_equal(c->n, NPTS);
  for (i = 0; i < NPTS; i++) {
    assert_int_equal(bsfit_curve_eval(c, u[i], p, NULL), BSFIT_OK);
    assert_float_equal(p[0], pts[2 * i], PT_EPS);
    assert_float_equal(p[1], pts[2 * i + 1], PT_EPS);
  }
}

static void test_fit_round_trip(void **state) {
  double pts[2 * NPTS], u[NPTS], p[2];
  bsfit_engine *e = new_engine(0, 0, 0);
  bsfit_engine_report rep;
  bsfit_curve c;
  int i;
  (void)state;
  ellipse(pts, u);
  bsfit_curve_init(&c);
  assert_int_equal(bsfit_engine_fit(e, STRATEGY, pts, NPTS, 2, NULL, NULL, &c, &rep), BSFIT_OK);
  /* degree 1 through the points: C(u_k) = Q_k, and between two knots the chord's midpoint */
  assert_interpolates(&c, pts, u);
  assert_null(c.weights);
  for (i = 0; i + 1 < NPTS; i++) {
    assert_int_equal(bsfit_curve_eval(&c, (u[i] + u[i + 1]) / 2, p, NULL), BSFIT_OK);
    assert_float_equal(p[0], (pts[2 * i] + pts[2 * i + 2]) / 2, PT_EPS);
    assert_float_equal(p[1], (pts[2 * i + 1] + pts[2 * i + 3]) / 2, PT_EPS);
  }
  assert_float_equal(rep.rms, 0.0, 0.0);
  assert_float_equal(rep.max, 0.0, 0.0);
  assert_int_equal(rep.count, NPTS);
  assert_int_equal(rep.start_index, 0); /* Lua's 1 */
  assert_int_equal(lua_gettop(bsfit_engine_lua(e)), 0);
  /* a strategy that returns no report: rms and max unknown (NaN), count and start 0 */
  assert_int_equal(bsfit_engine_run_string(
                       e, "package.preload.noreport = function() return {run = function(P)"
                          " return (dofile('" STRATEGY "').run(P)) end} end", NULL),
                   BSFIT_OK);
  assert_int_equal(bsfit_engine_fit(e, "noreport", pts, NPTS, 2, NULL, NULL, &c, &rep), BSFIT_OK);
  assert_interpolates(&c, pts, u);
  assert_true(isnan(rep.rms) && isnan(rep.max));
  assert_int_equal(rep.count, 0);
  assert_int_equal(rep.start_index, 0);
  /* the copy outlives the engine */
  bsfit_engine_free(e);
  assert_int_equal(bsfit_curve_validate(&c, NULL), BSFIT_OK);
  bsfit_curve_free(&c);
}

static void test_fit_weights_and_opts(void **state) {
  double pts[2 * NPTS], u[NPTS], w[NPTS];
  bsfit_engine_opts o = {1, 8u << 20, 10000000ULL, BSFIT_TEST_DATA "/lua", NULL};
  bsfit_engine *e = bsfit_engine_new(&o);
  bsfit_engine_report rep;
  bsfit_curve c;
  int i;
  (void)state;
  assert_non_null(e);
  ellipse(pts, u);
  for (i = 0; i < NPTS; i++) w[i] = 1.0 + i;
  bsfit_curve_init(&c);
  /* sandboxed, strategy by module name, weights and an options table */
  assert_int_equal(bsfit_engine_fit(e, "test_strategy", pts, NPTS, 2, w, "{ start = 5 }", &c, &rep),
                   BSFIT_OK);
  assert_interpolates(&c, pts, u); /* a NURBS of degree 1 still interpolates at its knots */
  assert_non_null(c.weights);
  for (i = 0; i < NPTS; i++) assert_float_equal(c.weights[i], w[i], 0.0);
  assert_int_equal(rep.start_index, 4);
  /* the options table sees no globals: `os` there is nil, not an escape */
  assert_int_equal(bsfit_engine_fit(e, "test_strategy", pts, NPTS, 2, NULL, "{ start = os and 9 }",
                                    &c, &rep),
                   BSFIT_OK);
  assert_int_equal(rep.start_index, 0);
  assert_null(c.weights);
  bsfit_curve_free(&c);
  bsfit_engine_free(e);
}

static void test_fit_errors(void **state) {
  double pts[2 * NPTS], u[NPTS];
  bsfit_engine *e = new_engine(0, 0, 1000000);
  bsfit_curve c;
  (void)state;
  ellipse(pts, u);
  bsfit_curve_init(&c);
  /* bad arguments */
  assert_int_equal(bsfit_engine_fit(e, STRATEGY, pts, NPTS, 4, NULL, NULL, &c, NULL), BSFIT_EDIM);
  assert_msg_has(e, "dim = 4");
  assert_int_equal(bsfit_engine_fit(e, STRATEGY, pts, 0, 2, NULL, NULL, &c, NULL), BSFIT_EINVAL);
  assert_int_equal(bsfit_engine_fit(e, STRATEGY, NULL, NPTS, 2, NULL, NULL, &c, NULL), BSFIT_EINVAL);
  assert_int_equal(bsfit_engine_fit(e, NULL, pts, NPTS, 2, NULL, NULL, &c, NULL), BSFIT_EINVAL);
  assert_int_equal(bsfit_engine_fit(e, STRATEGY, pts, NPTS, 2, NULL, NULL, NULL, NULL), BSFIT_EINVAL);
  /* bad host data is named by its C element before any Lua runs */
  {
    double bad[2 * NPTS], w[NPTS];
    size_t i;
    memcpy(bad, pts, sizeof bad);
    bad[7] = NAN;
    assert_int_equal(bsfit_engine_fit(e, STRATEGY, bad, NPTS, 2, NULL, NULL, &c, NULL),
                     BSFIT_ENONFINITE);
    assert_msg_has(e, "pts[7] = nan (point 3) is not finite");
    for (i = 0; i < NPTS; i++) w[i] = 1.0;
    w[4] = -2;
    assert_int_equal(bsfit_engine_fit(e, STRATEGY, pts, NPTS, 2, w, NULL, &c, NULL), BSFIT_EWEIGHT);
    assert_msg_has(e, "w[4] = -2");
    w[4] = INFINITY;
    assert_int_equal(bsfit_engine_fit(e, STRATEGY, pts, NPTS, 2, w, NULL, &c, NULL), BSFIT_EWEIGHT);
    assert_null(c.ctrl);
  }
  /* the strategy raises: its file:line comes back */
  assert_int_equal(bsfit_engine_fit(e, STRATEGY, pts, NPTS, 2, NULL, "{fail = true}", &c, NULL),
                   BSFIT_EINVAL);
  assert_msg_has(e, "test_strategy.lua:");
  assert_msg_has(e, "asked to fail");
  /* options that do not parse, or are not a table */
  assert_int_equal(bsfit_engine_fit(e, STRATEGY, pts, NPTS, 2, NULL, "{", &c, NULL), BSFIT_EFORMAT);
  assert_int_equal(bsfit_engine_fit(e, STRATEGY, pts, NPTS, 2, NULL, "42", &c, NULL), BSFIT_EFORMAT);
  assert_msg_has(e, "table constructor");
  /* options that loop forever are data evaluated under the budget */
  assert_int_equal(bsfit_engine_fit(e, STRATEGY, pts, NPTS, 2, NULL,
                                    "{ x = (function() while true do end end)() }", &c, NULL),
                   BSFIT_EINTR);
  /* missing strategy file and module */
  assert_int_equal(bsfit_engine_fit(e, "/no/such/strategy.lua", pts, NPTS, 2, NULL, NULL, &c, NULL),
                   BSFIT_EIO);
  assert_int_equal(bsfit_engine_fit(e, "no.such.strategy", pts, NPTS, 2, NULL, NULL, &c, NULL),
                   BSFIT_EINVAL);
  assert_msg_has(e, "module 'no.such.strategy' not found");
  /* a module without run, and a run that returns no curve */
  assert_int_equal(bsfit_engine_run_string(
                       e, "package.preload.norun = function() return {} end\n"
                          "package.preload.junk = function() return {run = function() return 42 end} end",
                       NULL),
                   BSFIT_OK);
  assert_int_equal(bsfit_engine_fit(e, "norun", pts, NPTS, 2, NULL, NULL, &c, NULL), BSFIT_EINVAL);
  assert_msg_has(e, "not a module with a run function");
  assert_int_equal(bsfit_engine_fit(e, "junk", pts, NPTS, 2, NULL, NULL, &c, NULL), BSFIT_EINVAL);
  assert_msg_has(e, "bsfit.Curve expected");
  assert_null(c.ctrl);
  /* a strategy's `nil, message, code` reaches the host as itself (it came back as
  ** "bsfit.Curve expected, got nil", EINVAL) */
  assert_int_equal(bsfit_engine_fit(e, STRATEGY, pts, NPTS, 2, NULL, "{outcome = 'ESINGULAR'}",
                                    &c, NULL),
                   BSFIT_ESINGULAR);
  assert_msg_has(e, "no good fit for these points");
  assert_true(strstr(bsfit_engine_errmsg(e), "Curve expected") == NULL);
  assert_int_equal(bsfit_engine_fit(e, STRATEGY, pts, NPTS, 2, NULL, "{outcome = 'EEMPTYSPAN'}",
                                    &c, NULL),
                   BSFIT_EEMPTYSPAN);
  assert_int_equal(bsfit_engine_fit(e, STRATEGY, pts, NPTS, 2, NULL, "{outcome = 'EWHATEVER'}",
                                    &c, NULL),
                   BSFIT_EINVAL);
  assert_msg_has(e, "no good fit for these points");
  assert_null(c.ctrl);
  assert_int_equal(lua_gettop(bsfit_engine_lua(e)), 0);
  /* and after all that, a good fit */
  assert_int_equal(bsfit_engine_fit(e, STRATEGY, pts, NPTS, 2, NULL, NULL, &c, NULL), BSFIT_OK);
  assert_interpolates(&c, pts, u);
  assert_int_equal(lua_gettop(bsfit_engine_lua(e)), 0);
  bsfit_curve_free(&c);
  bsfit_engine_free(e);
}

/* A noisy closed section of m points with uneven weights (seeded, reproducible). */
static void weighted_section(double *pts, double *w, size_t m, unsigned seed) {
  size_t i;
  srand(seed);
  for (i = 0; i < m; i++) {
    double t = 2 * 3.14159265358979323846 * (double)i / (double)m;
    double r = 1 + 0.3 * cos(3 * t) + 0.01 * ((double)rand() / RAND_MAX - 0.5);
    pts[2 * i] = 5 * r * cos(t);
    pts[2 * i + 1] = 3 * r * sin(t);
    w[i] = 0.2 + 3.0 * (double)rand() / RAND_MAX;
  }
}

static double max_ctrl_diff(const bsfit_curve *a, const bsfit_curve *b) {
  double d = 0;
  size_t i;
  if (a->n != b->n || a->dim != b->dim) return INFINITY;
  for (i = 0; i < a->n * (size_t)a->dim; i++) d = fmax(d, fabs(a->ctrl[i] - b->ctrl[i]));
  return d;
}

/* Host weights mean what a file's w column means to `bsfit reconstruct`: both
** multiply the strategy's weighting rule, so the engine and the command line fit
** the same curve to the same data (the engine's weights used to replace the rule). */
static void test_fit_weights_as_cli(void **state) {
  static const char *const strategies[] = {"auto", "periodic", "carvalho"};
  enum { M = 90 };
  double pts[2 * M], w[M];
  char csv[512], dir[512], cmd[2048], json[600];
  size_t s;
  bsfit_engine *e = new_engine(0, 0, 0);
  (void)state;
  for (s = 0; s < sizeof strategies / sizeof strategies[0]; s++) {
    bsfit_curve ce, cc, cu;
    char mod[64];
    weighted_section(pts, w, M, 7u + (unsigned)s);
    snprintf(csv, sizeof csv, "%s/engine_weights_%s.csv", BSFIT_BINARY_DIR, strategies[s]);
    snprintf(dir, sizeof dir, "%s/engine_weights_out", BSFIT_BINARY_DIR);
    assert_int_equal(bsfit_points_write(csv, pts, M, 2, w, NULL), BSFIT_OK);
    snprintf(cmd, sizeof cmd, "'%s/bsfit' reconstruct '%s' -o '%s' --format json --strategy %s"
             " >/dev/null 2>&1", BSFIT_BINARY_DIR, csv, dir, strategies[s]);
    assert_int_equal(system(cmd), 0);
    snprintf(json, sizeof json, "%s/engine_weights_%s.json", dir, strategies[s]);
    bsfit_curve_init(&ce);
    bsfit_curve_init(&cc);
    bsfit_curve_init(&cu);
    assert_int_equal(bsfit_curve_read_json(json, &cc, NULL, NULL), BSFIT_OK);
    snprintf(mod, sizeof mod, "bsfit.strategy.%s", strategies[s]);
    assert_int_equal(bsfit_engine_fit(e, mod, pts, M, 2, w, "{degree = 3}", &ce, NULL), BSFIT_OK);
    /* the JSON keeps 17 significant digits: the same computation agrees to rounding */
    assert_true(max_ctrl_diff(&ce, &cc) < 1e-9);
    /* and the weights matter: without them the curve is another one */
    assert_int_equal(bsfit_engine_fit(e, mod, pts, M, 2, NULL, "{degree = 3}", &cu, NULL),
                     BSFIT_OK);
    assert_true(max_ctrl_diff(&ce, &cu) > 1e-6);
    bsfit_curve_free(&ce);
    bsfit_curve_free(&cc);
    bsfit_curve_free(&cu);
  }
  bsfit_engine_free(e);
}

/* }==================================================================== */

int main(void) {
  const struct CMUnitTest tests[] = {
    cmocka_unit_test(test_run_string_ok),
    cmocka_unit_test(test_syntax_error),
    cmocka_unit_test(test_runtime_error_file_line),
    cmocka_unit_test(test_null_and_misuse),
    cmocka_unit_test(test_pcall_host_function),
    cmocka_unit_test(test_sandbox_denies),
    cmocka_unit_test(test_sandbox_binary_file),
    cmocka_unit_test(test_sandbox_require_luadir),
    cmocka_unit_test(test_memory_cap),
    cmocka_unit_test(test_budget_infinite_loop),
    cmocka_unit_test(test_budget_large),
    cmocka_unit_test(test_interrupt_from_thread),
    cmocka_unit_test(test_hooks_only_where_needed),
    cmocka_unit_test(test_two_threads),
    cmocka_unit_test(test_fit_round_trip),
    cmocka_unit_test(test_fit_weights_and_opts),
    cmocka_unit_test(test_fit_errors),
    cmocka_unit_test(test_fit_weights_as_cli),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
