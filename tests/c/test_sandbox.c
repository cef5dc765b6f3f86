/*
** test_sandbox.c
** A C host driving sandboxed engines the way a hostile script would: every escape
** found so far (issue 13: a looping xpcall message handler, writable metatables with
** a looping __gc, package.searchpath probing files) and the classic ones (io, os, C
** modules, bytecode, memory, loops in pcall / xpcall / coroutines / __close /
** __tostring, string.rep bombs). Each case checks the code and message the host
** gets, and that the host's next call on the same engine still works. A case that
** hangs is a failure: alarm() ends the program.
*/
#include "bsfit.h"
#include "bsfit_engine.h"

#include <lauxlib.h>
#include <lua.h>

#include <math.h>
#include <pthread.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stdatomic.h>
#include <stddef.h>
#include <stdio.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

#include <cmocka.h>

#define BUDGET 20000000ULL  /* instructions per call: a loop runs out in well under a second */
#define MEM (32u << 20)     /* Lua heap cap of the sandboxes */

static bsfit_engine *sandbox(size_t mem, unsigned long long budget) {
  bsfit_engine_opts o = {1, mem, budget, NULL, NULL};
  bsfit_engine *e = bsfit_engine_new(&o);
  assert_non_null(e);
  return e;
}

static void assert_msg_has(const bsfit_engine *e, const char *part) {
  const char *msg = bsfit_engine_errmsg(e);
  if (strstr(msg, part) == NULL) fail_msg("message \"%s\" lacks \"%s\"", msg, part);
}

/* The engine still works: bsfit loads and computes, the stack is clean. */
static void still_works(bsfit_engine *e) {
  lua_State *L = bsfit_engine_lua(e);
  bsfit_err code = bsfit_engine_run_string(
      e, "local bs = require 'bsfit'\n"
         "local C = bs.curve.new{degree = 1, knots = {0, 0, 1, 1},"
         " control_points = {{0, 0}, {2, 4}}}\n"
         "local x, y = C:eval(0.5)\n"
         "assert(x == 1 and y == 2)\n"
         "local s = 0 for i = 1, 1000 do s = s + i end assert(s == 500500)",
      "=next call");
  if (code != BSFIT_OK) fail_msg("next call failed: %s", bsfit_engine_errmsg(e));
  assert_int_equal(lua_gettop(L), 0);
}

/* Runs chunk, expects code and (unless NULL) a message fragment, then a good call. */
static void expect(bsfit_engine *e, const char *chunk, bsfit_err code, const char *part) {
  bsfit_err got = bsfit_engine_run_string(e, chunk, "=hostile");
  if (got != code)
    fail_msg("%s\n  gave %s (%s), expected %s", chunk, bsfit_errname(got),
             bsfit_engine_errmsg(e), bsfit_errname(code));
  if (part != NULL) assert_msg_has(e, part);
  assert_int_equal(lua_gettop(bsfit_engine_lua(e)), 0);
  still_works(e);
}

static double now(void) {
  struct timespec ts;
  clock_gettime(CLOCK_MONOTONIC, &ts);
  return (double)ts.tv_sec + (double)ts.tv_nsec * 1e-9;
}

/* {====================================================================
** Finding 1: a message handler that loops
** ===================================================================== */

static void test_xpcall_handler_loops(void **state) {
  bsfit_engine *e = sandbox(MEM, BUDGET);
  (void)state;
  /* the case: the budget's stop raised inside the handler re-entered it
  ** with hooks off, forever */
  expect(e, "xpcall(function() error('x') end, function() while true do end end)", BSFIT_EINTR,
         "instruction budget exceeded");
  /* the function and the handler both loop */
  expect(e, "xpcall(function() while true do end end, function() while true do end end)",
         BSFIT_EINTR, "instruction budget exceeded");
  /* the handler loops inside pcall, in a coroutine, through a wrapped coroutine */
  expect(e, "xpcall(error, function() while true do pcall(error) end end, 'x')", BSFIT_EINTR,
         NULL);
  expect(e, "coroutine.wrap(function() xpcall(error, function() while true do end end) end)()",
         BSFIT_EINTR, NULL);
  expect(e, "xpcall(error, coroutine.wrap(function() while true do end end), 'x')", BSFIT_EINTR,
         NULL);
  /* a handler that raises again and again ends in an error, not a hang */
  expect(e, "xpcall(error, function(m) error(m) end, 'x') error('after')", BSFIT_EINVAL, "after");
  /* a handler that is itself xpcall */
  expect(e, "xpcall(error, xpcall, 'x') error('after')", BSFIT_EINVAL, "after");
  /* xpcall still works as Lua's: the handler sees the error, results come back,
  ** and a function in it may yield */
  expect(e, "local ok, m = xpcall(error, function(m) return 'handled ' .. m end, 'x', 0)\n"
            "assert(ok == false and m == 'handled x', m)\n"
            "local ok2, a, b = xpcall(function(p, q) return p + q, p * q end, print, 3, 4)\n"
            "assert(ok2 and a == 7 and b == 12)\n"
            "local co = coroutine.wrap(function()\n"
            "  return xpcall(function() coroutine.yield(1) return 2 end, print) end)\n"
            "assert(co() == 1) local ok3, v = co() assert(ok3 and v == 2)\n"
            "assert(not pcall(xpcall, error, 'not a function'))",
         BSFIT_OK, NULL);
  bsfit_engine_free(e);
}

typedef struct stopper {
  bsfit_engine *e;
  double delay;
  atomic_int *go;   /* wait until non-zero (NULL: do not wait) */
  double t_stop;    /* when the interrupt was sent */
} stopper;

static void *interrupt_after(void *arg) {
  stopper *s = (stopper *)arg;
  struct timespec ts;
  if (s->go != NULL)
    while (atomic_load(s->go) == 0) {
      ts.tv_sec = 0;
      ts.tv_nsec = 100000;
      nanosleep(&ts, NULL);
    }
  ts.tv_sec = (time_t)s->delay;
  ts.tv_nsec = (long)((s->delay - (double)ts.tv_sec) * 1e9);
  nanosleep(&ts, NULL);
  s->t_stop = now();
  bsfit_engine_interrupt(s->e);
  return NULL;
}

/* Without a budget, bsfit_engine_interrupt stops a looping handler (it used to run
** with hooks off, out of the interrupt's reach too). */
static void test_xpcall_handler_interrupt(void **state) {
  static const char *const loops[] = {
    "xpcall(function() error('x') end, function() while true do end end)",
    "xpcall(function() while true do end end, function() while true do end end)",
    "error(setmetatable({}, {__tostring = function() while true do end end}))",
  };
  bsfit_engine *e = sandbox(MEM, 0);
  size_t i;
  (void)state;
  for (i = 0; i < sizeof loops / sizeof loops[0]; i++) {
    stopper s = {e, 0.05, NULL, 0};
    pthread_t t;
    assert_int_equal(pthread_create(&t, NULL, interrupt_after, &s), 0);
    assert_int_equal(bsfit_engine_run_string(e, loops[i], "=hostile"), BSFIT_EINTR);
    assert_int_equal(pthread_join(t, NULL), 0);
    assert_msg_has(e, "interrupted");
    still_works(e);
  }
  bsfit_engine_free(e);
}

/* }==================================================================== */

/* {====================================================================
** Finding 2: metatables of bsfit objects and finalizers
** ===================================================================== */

/* One object of every bsfit type a script can make, as `objs`. */
#define MAKE_OBJECTS                                                                  \
  "local bs = require 'bsfit'\n"                                                      \
  "local C = bs.curve.new{degree = 1, knots = {0, 0, 1, 1},"                          \
  " control_points = {{0, 0}, {1, 1}}}\n"                                             \
  "local S = bs.surface.new{degree_u = 1, degree_v = 1, knots_u = {0, 0, 1, 1},"      \
  " knots_v = {0, 0, 1, 1}, control_points = {{{0, 0, 0}, {0, 1, 0}},"                \
  " {{1, 0, 0}, {1, 1, 1}}}}\n"                                                       \
  "objs = {bs.points.new{{1, 2}}, bs.vector.new{1, 2}, C:knots(), C,"                 \
  " bs.fitter{degree = 1, count = 2}, S, bs.svg.new(C)}\n"

static void test_metatables_protected(void **state) {
  bsfit_engine *e = sandbox(MEM, BUDGET);
  double t0;
  (void)state;
  /* the case: a looping __gc written into a bsfit metatable, which ran with
  ** hooks off when the object was collected (here, or in bsfit_engine_free) */
  expect(e, MAKE_OBJECTS
            "for _, o in ipairs(objs) do\n"
            "  local mt = getmetatable(o)\n"
            "  assert(type(mt) == 'table' and mt.__name:find('^bsfit%.'), tostring(mt))\n"
            "  mt.__gc = function() while true do end end\n"
            "  mt.__index = function() error('hijacked') end\n"
            "  mt.__close = function() while true do end end\n"
            "end\n"
            "assert(objs[4]:eval(1))  -- methods untouched\n"
            "assert(not pcall(setmetatable, objs[1], {}))\n"
            "objs = nil\n"
            "collectgarbage() collectgarbage()",
         BSFIT_OK, NULL);
  /* the objects made in the last call are collected when the engine closes */
  expect(e, MAKE_OBJECTS
            "for _, o in ipairs(objs) do getmetatable(o).__gc = function() while true do end end"
            " end",
         BSFIT_OK, NULL);
  t0 = now();
  bsfit_engine_free(e);
  assert_true(now() - t0 < 5.0);
}

static void test_gc_refused(void **state) {
  bsfit_engine *e = sandbox(MEM, BUDGET);
  (void)state;
  expect(e, "setmetatable({}, {__gc = function() while true do end end})", BSFIT_EINVAL,
         "__gc metamethod is not allowed");
  expect(e, "setmetatable({}, {__gc = false})", BSFIT_EINVAL, "__gc metamethod is not allowed");
  /* a __gc added after setmetatable does not mark the table for finalization */
  expect(e, "local mt = {} local t = setmetatable({}, mt)\n"
            "mt.__gc = function() while true do end end\n"
            "t = nil collectgarbage() collectgarbage()",
         BSFIT_OK, NULL);
  /* other metamethods stay available */
  expect(e, "local t = setmetatable({}, {__index = function(_, k) return k .. '!' end})\n"
            "assert(t.a == 'a!')",
         BSFIT_OK, NULL);
  bsfit_engine_free(e);
}

/* }==================================================================== */

/* {====================================================================
** Finding 3 and the classic escapes: files, C code, bytecode
** ===================================================================== */

static void test_package_probe(void **state) {
  bsfit_engine *e = sandbox(MEM, BUDGET);
  (void)state;
  /* the case: package.searchpath told whether any file exists */
  expect(e, "return package.searchpath('shadow', '/etc/?')", BSFIT_EINVAL, "attempt to call a nil");
  expect(e, "assert(package.searchpath == nil and package.loadlib == nil and"
            " package.cpath == nil and package.path == nil and #package.searchers == 2)",
         BSFIT_OK, NULL);
  /* the remaining searchers look in the lua directory only */
  expect(e, "require 'etc.passwd'", BSFIT_EINVAL, "not found");
  /* a name with .. or / cannot climb out of the lua directory */
  expect(e, "require '../../../../etc/passwd'", BSFIT_EINVAL, "not found");
  /* C modules: no C searcher, whatever package.cpath says */
  expect(e, "require 'lfs'", BSFIT_EINVAL, "module 'lfs' not found");
  expect(e, "package.cpath = '/usr/lib/x86_64-linux-gnu/lua/5.4/?.so' require 'lpeg'",
         BSFIT_EINVAL, "module 'lpeg' not found");
  bsfit_engine_free(e);
}

static void test_classic_escapes(void **state) {
  static const char *const absent[] = {
    "io.open('/etc/passwd')",   "os.execute('true')",     "os.exit(3)",
    "debug.sethook()",          "dofile('/etc/passwd')",  "loadfile('/etc/passwd')",
    "package.loadlib('libc.so.6', 'puts')", "require('io').open('/etc/passwd')"};
  bsfit_engine *e = sandbox(MEM, BUDGET);
  size_t i;
  (void)state;
  for (i = 0; i < sizeof absent / sizeof absent[0]; i++)
    expect(e, absent[i], BSFIT_EINVAL, NULL);
  /* bytecode: load refuses binary chunks whatever the mode asked */
  expect(e, "local b = string.dump(function() return 1 end)\n"
            "for _, mode in ipairs{'b', 'bt', 't'} do\n"
            "  local f, err = load(b, 'x', mode)\n"
            "  assert(f == nil and err:find('binary', 1, true), mode)\n"
            "end\n"
            "local f = load(function() local s = b b = nil return s end)\n"
            "assert(f == nil)",
         BSFIT_OK, NULL);
  /* bsfit's file functions and worker pool, by the registry's sandbox flag */
  expect(e, "require('bsfit').points.read('/etc/passwd')", BSFIT_EINVAL,
         "bs.points.read: file access is not allowed in the sandbox");
  expect(e, "require('bsfit').curve.read('/etc/passwd')", BSFIT_EINVAL, "not allowed");
  expect(e, "require('bsfit').points.new{{1, 2}}:write('/tmp/bsfit_sandbox_x.csv')",
         BSFIT_EINVAL, "not allowed");
  expect(e, MAKE_OBJECTS "objs[4]:write('/tmp/bsfit_sandbox_x.json')", BSFIT_EINVAL,
         "not allowed");
  expect(e, MAKE_OBJECTS "objs[6]:write('/tmp/bsfit_sandbox_x.json')", BSFIT_EINVAL,
         "not allowed");
  expect(e, MAKE_OBJECTS "objs[7]:write('/tmp/bsfit_sandbox_x.svg')", BSFIT_EINVAL,
         "not allowed");
  expect(e, MAKE_OBJECTS "bs.io.write_step({C}, '/tmp/bsfit_sandbox_x.step')", BSFIT_EINVAL,
         "bs.io.write_step: file access is not allowed");
  expect(e, MAKE_OBJECTS "bs.io.write_dxf({C}, '/tmp/bsfit_sandbox_x.dxf')", BSFIT_EINVAL,
         "bs.io.write_dxf: file access is not allowed");
  expect(e, "require('bsfit').parallel.map('bsfit', 'x', {'a'}, 2)", BSFIT_EINVAL,
         "bs.parallel.map is not allowed in the sandbox");
  assert_int_equal(access("/tmp/bsfit_sandbox_x.csv", F_OK), -1);
  assert_int_equal(access("/tmp/bsfit_sandbox_x.json", F_OK), -1);
  assert_int_equal(access("/tmp/bsfit_sandbox_x.svg", F_OK), -1);
  assert_int_equal(access("/tmp/bsfit_sandbox_x.step", F_OK), -1);
  assert_int_equal(access("/tmp/bsfit_sandbox_x.dxf", F_OK), -1);
  bsfit_engine_free(e);
}

/* }==================================================================== */

/* {====================================================================
** Limits: memory and instructions
** ===================================================================== */

static void test_memory_cap(void **state) {
  static const char *const bombs[] = {
    "local s = string.rep('x', 1 << 30)",
    "local s = ('x'):rep(1 << 15):rep(1 << 15)",
    "local t = {} for i = 1, 1e9 do t[i] = i end",
    "local t = {} for i = 1, 1e9 do t[i] = ('x'):rep(64) .. i end",
    "local s = 'x' while true do s = s .. s end",
    "local t = {} for i = 1, 30 do t[#t + 1] = table.concat(t) .. ('y'):rep(1 << i) end",
    "require('bsfit').points.new(1e9, 2)",
    "require('bsfit').vector.new(1e9)",
    "local bs = require 'bsfit' local C = bs.curve.new{degree = 1, knots = {0, 0, 1, 1},"
    " control_points = {{0, 0}, {1, 1}}} C:sample(1e8)",
  };
  bsfit_engine *e = sandbox(MEM, 0); /* no budget: only the cap stops these */
  size_t i;
  (void)state;
  for (i = 0; i < sizeof bombs / sizeof bombs[0]; i++) expect(e, bombs[i], BSFIT_ENOMEM, NULL);
  /* a script may catch a memory error and go on: the memory was never given */
  expect(e, "local ok = pcall(string.rep, 'x', 1 << 30) assert(not ok) x = 1", BSFIT_OK, NULL);
  /* unbounded recursion ends in Lua's stack overflow or the cap, not a crash */
  {
    bsfit_err got = bsfit_engine_run_string(e, "local function f(n) return 1 + f(n + 1) end f(1)",
                                            "=hostile");
    assert_true(got == BSFIT_EINVAL || got == BSFIT_ENOMEM);
    still_works(e);
    got = bsfit_engine_run_string(e, "local function f() return coroutine.wrap(f)() end f()",
                                  "=hostile");
    assert_true(got == BSFIT_EINVAL || got == BSFIT_ENOMEM);
    still_works(e);
  }
  /* string.rep beyond what a string can hold is an error, not a crash */
  expect(e, "string.rep('ab', math.maxinteger)", BSFIT_EINVAL, "too large");
  bsfit_engine_free(e);
}

static void test_loops(void **state) {
  static const char *const loops[] = {
    "while true do end",
    "while true do pcall(function() while true do end end) end",
    "local ok, err = pcall(function() while true do end end) while true do end",
    "while true do xpcall(function() while true do end end, function(m) return m end) end",
    "while true do coroutine.resume(coroutine.create(function() while true do end end)) end",
    "coroutine.wrap(function() while true do coroutine.yield() end end)() while true do end",
    "local co = coroutine.wrap(function() while true do coroutine.yield() end end)"
    " while true do co() end",
    "do local x <close> = setmetatable({}, {__close = function() while true do end end}) end",
    "do local x <close> = setmetatable({}, {__close = function() while true do end end})"
    " error('x') end",
    "error(setmetatable({}, {__tostring = function() while true do end end}))",
    "pcall(error, setmetatable({}, {__tostring = function() while true do end end}))"
    " while true do end",
    "local t = setmetatable({}, {__index = function(t, k) return t[k .. 'x'] end}) return t.a",
    "string.rep('x', 100):gsub('.', function() while true do end end)",
    "table.sort({3, 2, 1, 5, 4}, function() while true do end end)",
    "load(function() while true do end end)",
  };
  bsfit_engine *e = sandbox(MEM, BUDGET);
  size_t i;
  (void)state;
  for (i = 0; i < sizeof loops / sizeof loops[0]; i++) {
    bsfit_err got = bsfit_engine_run_string(e, loops[i], "=hostile");
    /* the __index recursion may run out of C stack or memory first: an error, no hang */
    if (i == 11) {
      assert_true(got == BSFIT_EINTR || got == BSFIT_EINVAL || got == BSFIT_ENOMEM);
      still_works(e);
      continue;
    }
    if (got != BSFIT_EINTR)
      fail_msg("%s\n  gave %s (%s)", loops[i], bsfit_errname(got), bsfit_engine_errmsg(e));
    assert_msg_has(e, "instruction budget exceeded");
    still_works(e);
  }
  bsfit_engine_free(e);
}

/* }==================================================================== */

/* {====================================================================
** Finding 16: the interrupt reaches the fitter's C loops
** ===================================================================== */

static atomic_int fit_started;
static double t_started;

/* mark(): the script is about to call the fit (a host function in the sandbox). */
static int mark(lua_State *L) {
  (void)L;
  t_started = now();
  atomic_store(&fit_started, 1);
  return 0;
}

/* 10^7 points on a closed curve, their parameters, fixed knots (no O(m) knot
** placement before the assembly) and a cubic fitter with 2000 control points. */
static const char *const fit_setup =
    "local bs = require 'bsfit'\n"
    "local ctrl = {}\n"
    "for i = 1, 40 do local t = 2 * math.pi * i / 40\n"
    "  ctrl[i] = {5 * math.cos(t) + 0.3 * math.sin(7 * t), 3 * math.sin(t)} end\n"
    "local G = bs.curve.new{degree = 3, control_points = ctrl,"
    " knots = bs.knots.clamped{degree = 3, count = 40}}\n"
    "P = G:sample(1e7)\n"
    "u = bs.params(P, 'chord')\n"
    "local K = bs.knots.averaging{params = u, count = 2000, degree = 3}\n"
    "fitters = {cholesky = bs.fitter{degree = 3, knots = K},"
    " qr = bs.fitter{degree = 3, knots = K, solver = 'qr'}}\n";

static const char *const fit_run =
    "local F = fitters[solver]\n"
    "mark()\n"
    "local C, rep = F:fit(P, u)\n"
    "assert(C and rep.rms < 1e-3, 'fit failed')\n"
    "done = true\n";

/* The fit interrupted *t_fit / 3 after it starts, by another thread: how long after
** the interrupt the call returned (seconds). A fit that ended before the interrupt (the
** first timing was slow: a fresh machine's first touch of the memory, a busy core) is
** not a failure: it returns NAN and makes its own time the fit's. */
static double interrupted_fit(bsfit_engine *e, double *t_fit) {
  lua_State *L = bsfit_engine_lua(e);
  stopper s = {e, *t_fit / 3, &fit_started, 0};
  pthread_t t;
  bsfit_err code;
  double t_end;
  atomic_store(&fit_started, 0);
  assert_int_equal(bsfit_engine_run_string(e, "done = false", NULL), BSFIT_OK);
  assert_int_equal(pthread_create(&t, NULL, interrupt_after, &s), 0);
  code = bsfit_engine_run_string(e, fit_run, "=fit");
  t_end = now();
  assert_int_equal(pthread_join(t, NULL), 0);
  if (code == BSFIT_OK && t_end < s.t_stop) {
    *t_fit = fmin(*t_fit, t_end - t_started);
    return NAN;
  }
  assert_int_equal(code, BSFIT_EINTR);
  assert_msg_has(e, "interrupted");
  lua_getglobal(L, "done");
  assert_false(lua_toboolean(L, -1));
  lua_pop(L, 1);
  return t_end - s.t_stop;
}

/* One solver: the fit's own time, then the same fit interrupted a third of the way
** in. The C loop must see the flag: the call ends a small fraction of the fit's time
** after the interrupt, where a fit that ran to its end would take two thirds more.
** Best of three interrupted tries (of at most six), so that a busy machine's scheduling
** is not the measure. With rerun, the same fit then runs to its end on the same engine. */
static void interrupt_fit(bsfit_engine *e, const char *solver, int rerun) {
  lua_State *L = bsfit_engine_lua(e);
  double t_fit, latency = INFINITY;
  int k, interrupted = 0;
  lua_pushstring(L, solver);
  lua_setglobal(L, "solver");
  assert_int_equal(bsfit_engine_run_string(e, fit_run, "=fit"), BSFIT_OK);
  t_fit = now() - t_started;
  for (k = 0; k < 6 && interrupted < 3 && !(latency < 0.05 * t_fit); k++) {
    double l = interrupted_fit(e, &t_fit);
    if (!isnan(l)) {
      latency = fmin(latency, l);
      interrupted++;
    }
  }
  print_message("%s fit of 1e7 points: %.1f ms; stopped %.3f ms after the interrupt\n", solver,
                t_fit * 1e3, latency * 1e3);
  assert_true(interrupted > 0);
  assert_true(latency < 0.1 * t_fit);
  if (rerun) assert_int_equal(bsfit_engine_run_string(e, fit_run, "=fit"), BSFIT_OK);
  still_works(e);
}

static void test_interrupt_c_fit(void **state) {
  bsfit_engine *e = sandbox((size_t)2 << 30, 0);
  lua_State *L = bsfit_engine_lua(e);
  (void)state;
  lua_pushcfunction(L, mark);
  lua_setglobal(L, "mark");
  if (bsfit_engine_run_string(e, fit_setup, "=setup") != BSFIT_OK)
    fail_msg("setup: %s", bsfit_engine_errmsg(e));
  interrupt_fit(e, "cholesky", 1);
  interrupt_fit(e, "qr", 0); /* 17 s a fit under the sanitizers: no second full run */
  bsfit_engine_free(e);
}

/* }==================================================================== */

int main(void) {
  const struct CMUnitTest tests[] = {
    cmocka_unit_test(test_xpcall_handler_loops),
    cmocka_unit_test(test_xpcall_handler_interrupt),
    cmocka_unit_test(test_metatables_protected),
    cmocka_unit_test(test_gc_refused),
    cmocka_unit_test(test_package_probe),
    cmocka_unit_test(test_classic_escapes),
    cmocka_unit_test(test_memory_cap),
    cmocka_unit_test(test_loops),
    cmocka_unit_test(test_interrupt_c_fit),
  };
  alarm(600); /* a hang is a failure, not a stuck test run */
  return cmocka_run_group_tests(tests, NULL, NULL);
}
