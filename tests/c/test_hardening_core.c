/*
** test_hardening_core.c
** Regression tests of issue 13's findings in the core, each over random inputs:
** the exact filter with windows down to 1e-15 (it read past a buffer and returned
** garbage), periodic knot vectors with a knot of multiplicity p+1 (elevation wrote
** before its buffer), ... Every OK result is checked against mathematics (quadrature of
** the window average, an independent evaluator), every refusal for its code.
*/
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>
#include <float.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "bsfit.h"
#include "hardening.h"

/* {====================================================================
** Finding 4: the exact filter for any window, any knots
** ===================================================================== */

#define GLN 12 /* exact to degree 23 */

/* C extended by its end values outside [a, b] (the end rule of a clamped curve) */
static void ext_eval(const bsfit_curve *c, double u, double *out) {
  double a, b;
  bsfit_curve_domain(c, &a, &b);
  ref_eval(c, u < a ? a : (u > b ? b : u), out);
}

/* (1 / 2 delta) * integral of the extended C over [t - delta, t + delta], by
** Gauss-Legendre between the knots (the integrand is a polynomial between them) */
static void window_average(const bsfit_curve *c, double t, double delta, double *out) {
  double x[GLN], w[GLN], lo = t - delta, hi = t + delta, v[4], brk[64];
  size_t nk = c->n + (size_t)c->degree + 1, nb = 0, i, j;
  int k, g;
  gl_nodes(GLN, x, w);
  brk[nb++] = lo;
  for (i = 0; i < nk && nb < 63; i++)
    if (c->knots[i] > lo && c->knots[i] < hi && c->knots[i] != brk[nb - 1]) brk[nb++] = c->knots[i];
  brk[nb++] = hi;
  for (k = 0; k < c->dim; k++) out[k] = 0.0;
  for (j = 0; j + 1 < nb; j++) {
    double m = 0.5 * (brk[j] + brk[j + 1]), h = 0.5 * (brk[j + 1] - brk[j]);
    for (g = 0; g < GLN; g++) {
      ext_eval(c, m + h * x[g], v);
      for (k = 0; k < c->dim; k++) out[k] += w[g] * h * v[k];
    }
  }
  for (k = 0; k < c->dim; k++) out[k] /= 2.0 * delta;
}

/* Given random clamped curves (degrees 1-5, knots clustered down to 1e-15) and windows
** from 1e-15 to a quarter of the domain, when filtered exactly, then either the result
** is valid and equals the window average to 1e-8 of the control points' extent, or the
** window is below the documented resolution and the answer is BSFIT_EDOMAIN. */
static void test_filter_any_delta(void **state) {
  test_rng r = {0x5eed4u};
  int trial, ok = 0, refused = 0;
  (void)state;
  for (trial = 0; trial < 60; trial++) {
    int p = 1 + trial % 5, dim = 2, e10;
    size_t n = (size_t)p + 1 + (size_t)(rng_uniform(&r) * 8), i;
    double U[64], P[64], a, b, len;
    bsfit_curve c, f;
    bsfit_status st;
    clustered_knots(&r, p, n, 1, p, U);
    for (i = 0; i < n * 2; i++) P[i] = rng_range(&r, -5.0, 5.0);
    bsfit_curve_init(&c);
    bsfit_curve_init(&f);
    assert_int_equal(bsfit_curve_new(&c, p, dim, n, U, P, NULL, 0, NULL, &st), BSFIT_OK);
    bsfit_curve_domain(&c, &a, &b);
    len = b - a;
    for (e10 = -15; e10 <= 0; e10 += 3) {
      /* the curve is known to its knots' rounding, eps |a| / len of the domain */
      double delta = len * (e10 == 0 ? 0.25 : pow(10.0, e10));
      double tol = 10.0 * (1e-8 + 1e4 * DBL_EPSILON * (fabs(a) + fabs(b)) / len);
      bsfit_err e = bsfit_filter_box_curve_delta(&c, delta, &f, &st);
      if (e != BSFIT_OK) {
        assert_int_equal(e, BSFIT_EDOMAIN);
        assert_true(delta < 2.0 * BSFIT_FILTER_MIN_DELTA * len + 1e-9 * (fabs(a) + fabs(b)));
        refused++;
        continue;
      }
      ok++;
      assert_true(curve_sound(&f));
      for (i = 0; i < 40; i++) {
        double t = a - delta + (len + 2.0 * delta) * ((double)i + 0.5) / 40.0, got[4], want[4];
        ref_eval(&f, t, got);
        window_average(&c, t, delta, want);
        if (pt_dist(got, want, dim) > tol)
          fail_msg("p=%d n=%zu [%g, %g] delta=%g t=%.17g: off by %.3g", p, n, a, b, delta, t,
                   pt_dist(got, want, dim));
      }
    }
    bsfit_curve_free(&c);
    bsfit_curve_free(&f);
  }
  assert_true(ok > 100);
  assert_true(refused > 100);
}

/* Given uniform curves and delta = k h / 2 (the knots u_i + delta and u_j - delta
** coincide in exact arithmetic and are merged), the exact filter equals the moving
** average and is a valid curve, for open and closed curves. */
static void test_filter_uniform_merge(void **state) {
  test_rng r = {0x77u};
  int p, k;
  (void)state;
  for (p = 1; p <= 5; p++)
    for (k = 1; k <= 6; k++) {
      size_t n = (size_t)p + 8, i;
      double P[64], a, b, h;
      int per;
      for (i = 0; i < 2 * n; i++) P[i] = rng_range(&r, -1e3, 1e3);
      for (per = 0; per <= 1; per++) {
        bsfit_curve c, f1, f2;
        bsfit_status st;
        bsfit_curve_init(&c);
        bsfit_curve_init(&f1);
        bsfit_curve_init(&f2);
        if (per) assert_int_equal(bsfit_curve_new_periodic(&c, p, 2, n, NULL, P, NULL, NULL, &st), 0);
        else {
          double U[64];
          assert_int_equal(bsfit_knots_uniform(p, n, 0.3, 7.1, U, &st), BSFIT_OK);
          assert_int_equal(bsfit_curve_new(&c, p, 2, n, U, P, NULL, 0, NULL, &st), BSFIT_OK);
        }
        bsfit_curve_domain(&c, &a, &b);
        h = c.knots[p + 1] - c.knots[p];
        assert_int_equal(bsfit_filter_box_curve(&c, k, &f1, &st), BSFIT_OK);
        assert_int_equal(bsfit_filter_box_curve_delta(&c, 0.5 * k * h, &f2, &st), BSFIT_OK);
        assert_true(curve_sound(&f2));
        for (i = 0; i <= 50; i++) {
          double t = a + (b - a) * (double)i / 50.0, y1[2], y2[2];
          ref_eval(&f1, t, y1);
          ref_eval(&f2, t, y2);
          assert_true(pt_dist(y1, y2, 2) <= 1e-9 * 1e3);
        }
        bsfit_curve_free(&c);
        bsfit_curve_free(&f1);
        bsfit_curve_free(&f2);
      }
    }
}

/* }==================================================================== */

/* {====================================================================
** Finding 5: periodic knot vectors with a knot of multiplicity p + 1
** ===================================================================== */

/* Given closed curves of degree 1-6 whose period has one knot (the seam or an
** interior one) of multiplicity p + 1, when built, then they are refused with
** BSFIT_EMULT; with multiplicity p they are accepted, and elevating them gives a curve
** equal to the original. */
static void test_periodic_multiplicity(void **state) {
  int p, where;
  (void)state;
  for (p = 1; p <= 6; p++)
    for (where = 0; where < 3; where++) {
      size_t N = (size_t)p + 4, i, j;
      double t[32], P[64];
      int mult;
      for (i = 0; i < 2 * N; i++) P[i] = sin(1.7 * (double)i) * 3.0;
      for (mult = p; mult <= p + 1; mult++) {
        bsfit_curve c, e2;
        bsfit_status st;
        bsfit_err e;
        /* t[0..N]: spans of 1, and `mult` equal knots at the seam's end (where 0),
        ** its start (1) or inside (2) */
        for (i = 0; i <= N; i++) t[i] = (double)i;
        if (where == 0)
          for (j = 1; j < (size_t)mult; j++) t[N - j] = t[N];
        if (where == 1)
          for (j = 1; j < (size_t)mult; j++) t[j] = t[0];
        if (where == 2)
          for (j = 1; j < (size_t)mult; j++) t[2 + j] = t[2];
        bsfit_curve_init(&c);
        bsfit_curve_init(&e2);
        e = bsfit_curve_new_periodic(&c, p, 2, N, t, P, NULL, NULL, &st);
        if (mult > p) {
          assert_int_equal(e, BSFIT_EMULT);
          continue;
        }
        assert_int_equal(e, BSFIT_OK);
        assert_int_equal(bsfit_curve_elevate(&c, 2, &e2, &st), BSFIT_OK);
        assert_true(curve_sound(&e2));
        for (i = 0; i < 64; i++) {
          double u = t[0] + (t[N] - t[0]) * (double)i / 64.0, y1[2], y2[2];
          ref_eval(&c, u, y1);
          ref_eval(&e2, u, y2);
          assert_true(pt_dist(y1, y2, 2) <= 1e-12 * 3.0);
        }
        bsfit_curve_free(&c);
        bsfit_curve_free(&e2);
      }
    }
}

/* The issue's case, through the expanded form: degree 1, knots {0,0,1,1,2}. */
static void test_periodic_issue_case(void **state) {
  double U[5] = {0, 0, 1, 1, 2}, P[6] = {0, 0, 1, 0, 0, 0};
  bsfit_curve c;
  bsfit_status st;
  (void)state;
  bsfit_curve_init(&c);
  assert_int_equal(bsfit_curve_new(&c, 1, 2, 3, U, P, NULL, 1, NULL, &st), BSFIT_EMULT);
  assert_non_null(strstr(st.msg, "multiplicity 2"));
}

/* }==================================================================== */

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_filter_any_delta),
      cmocka_unit_test(test_filter_uniform_merge),
      cmocka_unit_test(test_periodic_multiplicity),
      cmocka_unit_test(test_periodic_issue_case),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
