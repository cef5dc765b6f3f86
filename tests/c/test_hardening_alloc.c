/*
** test_hardening_alloc.c
** The core's scratch memory goes through the caller's allocator and its long loops
** look at the interrupt flag (issue 13, finding 16): every routed function allocates
** through the allocator, and with its N-th allocation failing (every N) it answers
** BSFIT_ENOMEM (or OK, where the scratch only speeds it up: the span polynomials of the
** closest-point searches) and leaks nothing; with the flag set beforehand the long
** loops return BSFIT_EINTR, leak nothing, and the same call succeeds once the flag is
** cleared.
*/
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "bsfit.h"
#include "hardening.h"

#define BIG 20000 /* points or control points: several interrupt checks (every 4096) */

typedef struct fixture {
  double pts[2 * BIG], u[BIG], dist[BIG], out[2 * BIG], t[BIG + 1];
  bsfit_curve c; /* a periodic cubic through BIG control points, made with realloc */
} fixture;

static int setup(void **state) {
  fixture *f = calloc(1, sizeof *f);
  size_t i;
  bsfit_status st;
  if (f == NULL) return -1;
  for (i = 0; i < BIG; i++) {
    double th = 2.0 * 3.14159265358979323846 * (double)i / BIG;
    f->pts[2 * i] = cos(th) + 1e-3 * sin(37.0 * th);
    f->pts[2 * i + 1] = sin(th) + 1e-3 * cos(29.0 * th);
    f->u[i] = (double)i / BIG;
  }
  bsfit_curve_init(&f->c);
  if (bsfit_curve_new_periodic(&f->c, 3, 2, BIG, NULL, f->pts, NULL, NULL, &st) != BSFIT_OK) {
    free(f);
    return -1;
  }
  *state = f;
  return 0;
}

static int teardown(void **state) {
  fixture *f = *state;
  bsfit_curve_free(&f->c);
  free(f);
  return 0;
}

/* {====================================================================
** ENOMEM at every allocation, nothing leaked
** ===================================================================== */

typedef bsfit_err (*routed_fn)(fixture *f, const bsfit_allocator *a, bsfit_status *st);

static bsfit_err run_closest(fixture *f, const bsfit_allocator *a, bsfit_status *st) {
  double u, d;
  return bsfit_curve_closest(&f->c, f->pts + 10, &u, &d, a, st);
}
static bsfit_err run_closest_many(fixture *f, const bsfit_allocator *a, bsfit_status *st) {
  return bsfit_curve_closest_many(&f->c, f->pts, 500, f->u, f->dist, a, st);
}
static bsfit_err run_project(fixture *f, const bsfit_allocator *a, bsfit_status *st) {
  size_t i;
  for (i = 0; i < 500; i++) f->u[i] = (double)i / BIG;
  return bsfit_curve_project_many(&f->c, f->pts, 500, f->u, f->dist, 5, a, st);
}
static bsfit_err run_noise(fixture *f, const bsfit_allocator *a, bsfit_status *st) {
  double s;
  return bsfit_noise_sigma(f->pts, 2000, 2, 1, &s, a, st);
}
static bsfit_err run_trusted(fixture *f, const bsfit_allocator *a, bsfit_status *st) {
  size_t i;
  for (i = 0; i < 2000; i++) f->dist[i] = i % 10 == 0 ? 0.01 : 1.0; /* weights */
  return bsfit_params_trusted(f->pts, 2000, 2, BSFIT_PARAM_CHORD, 1, f->dist, 0.5, f->u, a, st);
}
static bsfit_err run_untrusted(fixture *f, const bsfit_allocator *a, bsfit_status *st) {
  static size_t out[2000];
  size_t i, n;
  for (i = 0; i < 2000; i++) f->dist[i] = i % 10 == 0 ? 0.01 : 1.0; /* weights */
  return bsfit_untrusted(f->dist, 2000, 0.5, out, &n, a, st);
}
static bsfit_err run_breaks(fixture *f, const bsfit_allocator *a, bsfit_status *st) {
  const double corners[] = {0, 500, 1000, 1500};
  size_t N, i;
  for (i = 0; i < 2000; i++) f->u[i] = (double)i / 2000.0;
  return bsfit_knots_place_breaks(f->u, 2000, 3, 40, corners, 4, f->t, &N, a, st);
}

/* One run with an allocator failing at allocation fail_at (0: never); returns the code,
** *calls the allocations made; fails the test if bytes stay live. */
static bsfit_err counted_run(fixture *f, routed_fn fn, long fail_at, long *calls,
                             const char *name) {
  counting cnt = {0, 0, 0};
  bsfit_allocator a;
  bsfit_status st;
  bsfit_err e;
  cnt.fail_at = fail_at;
  a.fn = counting_alloc;
  a.ud = &cnt;
  a.interrupt = NULL;
  e = fn(f, &a, &st);
  if (cnt.live != 0)
    fail_msg("%s: %lld bytes leaked (failing allocation %ld)", name, cnt.live, fail_at);
  *calls = cnt.calls;
  return e;
}

/* `fallback`: the scratch only speeds the call up, which does without it */
static void enomem_loop(fixture *f, routed_fn fn, int fallback, const char *name) {
  long n, total, calls;
  if (counted_run(f, fn, 0, &total, name) != BSFIT_OK) fail_msg("%s: fails without a limit", name);
  if (total == 0) fail_msg("%s: allocated nothing through the allocator", name);
  for (n = 1; n <= total; n++) {
    bsfit_err e = counted_run(f, fn, n, &calls, name);
    if (!(e == BSFIT_ENOMEM || (fallback && e == BSFIT_OK)))
      fail_msg("%s: allocation %ld of %ld failed, got %d", name, n, total, e);
  }
}

/* Given each routed function, when the N-th allocation fails (N = 1, 2, ...), then
** BSFIT_ENOMEM and no bytes live, until N passes the number of allocations. */
static void test_enomem_every_allocation(void **state) {
  fixture *f = *state;
  enomem_loop(f, run_closest, 1, "bsfit_curve_closest");
  enomem_loop(f, run_closest_many, 1, "bsfit_curve_closest_many");
  enomem_loop(f, run_project, 1, "bsfit_curve_project_many");
  enomem_loop(f, run_noise, 0, "bsfit_noise_sigma");
  enomem_loop(f, run_breaks, 0, "bsfit_knots_place_breaks");
  enomem_loop(f, run_trusted, 0, "bsfit_params_trusted");
  enomem_loop(f, run_untrusted, 0, "bsfit_untrusted");
}

/* }==================================================================== */

/* {====================================================================
** Interrupts
** ===================================================================== */

/* Given the flag set before the call, when a long loop runs over BIG points or control
** points, then BSFIT_EINTR and nothing leaked; with the flag cleared, OK. */
static void test_interrupt_preset(void **state) {
  fixture *f = *state;
  volatile int flag = 1;
  counting cnt = {0, 0, 0};
  bsfit_allocator a;
  bsfit_status st;
  bsfit_curve cc, out;
  double s;
  int pass;
  a.fn = counting_alloc;
  a.ud = &cnt;
  a.interrupt = &flag;
  bsfit_curve_init(&cc);
  bsfit_curve_init(&out);
  /* a copy of the curve that carries the flag: filters and elevation use its allocator */
  assert_int_equal(bsfit_curve_copy(&f->c, &cc, &a, &st), BSFIT_OK);
  for (pass = 0; pass < 2; pass++) {
    bsfit_err want = pass == 0 ? BSFIT_EINTR : BSFIT_OK;
    long long live = cnt.live;
    size_t i;
    flag = pass == 0;
    assert_int_equal(bsfit_curve_closest_many(&f->c, f->pts, BIG, f->u, f->dist, &a, &st), want);
    for (i = 0; i < BIG; i++) f->u[i] = (double)i / BIG;
    assert_int_equal(bsfit_curve_project_many(&f->c, f->pts, BIG, f->u, f->dist, 3, &a, &st), want);
    assert_int_equal(bsfit_curve_sample(&f->c, BIG, f->out, &a, &st), want);
    assert_int_equal(bsfit_noise_sigma(f->pts, BIG, 2, 1, &s, &a, &st), want);
    assert_int_equal(bsfit_filter_box_curve(&cc, 3, &out, &st), want);
    assert_int_equal(bsfit_filter_box_curve_delta(&cc, 1e-3, &out, &st), want);
    assert_int_equal(bsfit_curve_elevate(&cc, 1, &out, &st), want);
    if (pass == 0) {
      assert_int_equal(st.code, BSFIT_EINTR);
      assert_true(cnt.live == live); /* nothing kept */
    } else {
      assert_true(curve_sound(&out));
    }
    bsfit_curve_free(&out);
  }
  bsfit_curve_free(&cc);
  assert_true(cnt.live == 0);
}

/* }==================================================================== */

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_enomem_every_allocation),
      cmocka_unit_test(test_interrupt_preset),
  };
  return cmocka_run_group_tests(tests, setup, teardown);
}
