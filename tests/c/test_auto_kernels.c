/*
** test_auto_kernels.c
** Trusted parameters and knots with corner breaks: the building blocks of the
** automatic strategy.
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
#include "shapes.h"

static void test_trusted_params_without_weights_are_chord_params(void **state) {
  static double xy[2 * 200], u1[200], u2[200];
  test_rng r = {1};
  size_t i;
  (void)state;
  make_shape(&r, SHAPE_ELLIPSE, 200, 1, 1e-3, xy);
  assert_int_equal(bsfit_params(xy, 200, 2, BSFIT_PARAM_CHORD, 1, u1, NULL), BSFIT_OK);
  assert_int_equal(bsfit_params_trusted(xy, 200, 2, BSFIT_PARAM_CHORD, 1, NULL, 0.1, u2, NULL, NULL), BSFIT_OK);
  for (i = 0; i < 200; i++) assert_float_equal(u1[i], u2[i], 0.0);
}

static void test_outlier_does_not_stretch_neighbours(void **state) {
  /* a closed polygon with a gross outlier at index k (weight 1e-3): the trusted points'
  ** parameters equal those of the polygon without the outlier, up to the shift that
  ** keeps u[0] = 0 */
  static double xy[2 * 100], clean[2 * 99], u[100], uc[99];
  test_rng r = {2};
  size_t i, j, k = 37, first;
  double w[100];
  (void)state;
  make_shape(&r, SHAPE_CIRCLE, 100, 0, 0.0, xy);
  for (i = 0; i < 100; i++) w[i] = 1.0;
  xy[2 * k] += 0.8;
  w[k] = 1e-3;
  for (i = 0, j = 0; i < 100; i++)
    if (i != k) {
      clean[2 * j] = xy[2 * i];
      clean[2 * j + 1] = xy[2 * i + 1];
      j++;
    }
  assert_int_equal(bsfit_params_trusted(xy, 100, 2, BSFIT_PARAM_CHORD, 1, w, 0.1, u, NULL, NULL), BSFIT_OK);
  assert_int_equal(bsfit_params(clean, 99, 2, BSFIT_PARAM_CHORD, 1, uc, NULL), BSFIT_OK);
  for (i = 0, j = 0; i < 100; i++) {
    if (i == k) continue;
    assert_float_equal(u[i], uc[j], 1e-12);
    j++;
  }
  /* the outlier sits halfway between its neighbours */
  assert_float_equal(u[k], 0.5 * (u[k - 1] + u[k + 1]), 1e-12);
  /* untrusted first point: u[0] = 0 and non-decreasing */
  w[k] = 1.0;
  w[0] = 1e-4;
  first = 0;
  assert_int_equal(bsfit_params_trusted(xy, 100, 2, BSFIT_PARAM_CHORD, 1, w, 0.1, u, NULL, NULL), BSFIT_OK);
  assert_float_equal(u[first], 0.0, 0.0);
  for (i = 1; i < 100; i++) assert_true(u[i] >= u[i - 1] && u[i] < 1.0);
}

static void test_trusted_params_errors(void **state) {
  double xy[12] = {0, 0, 1, 0, 1, 1, 0, 1, 0.5, 0.5, 0.2, 0.1}, w[6] = {1, 1, 1, 1, 1, 1}, u[6];
  bsfit_status st;
  (void)state;
  assert_int_equal(bsfit_params_trusted(xy, 6, 2, BSFIT_PARAM_CHORD, 1, w, 1.5, u, NULL, &st), BSFIT_EINVAL);
  w[2] = 0.0;
  assert_int_equal(bsfit_params_trusted(xy, 6, 2, BSFIT_PARAM_CHORD, 1, w, 0.1, u, NULL, &st), BSFIT_EWEIGHT);
  w[2] = NAN;
  assert_int_equal(bsfit_params_trusted(xy, 6, 2, BSFIT_PARAM_CHORD, 1, w, 0.1, u, NULL, &st), BSFIT_EWEIGHT);
  w[2] = 1.0;
  assert_int_equal(bsfit_params_trusted(NULL, 6, 2, BSFIT_PARAM_CHORD, 1, w, 0.5, u, NULL, &st), BSFIT_EINVAL);
  assert_true(strlen(st.msg) > 0);
}

static int cmp_double(const void *a, const void *b) {
  double x = *(const double *)a, y = *(const double *)b;
  return (x > y) - (x < y);
}

/* the rule written out: sorted copy, element m / 2 (0-based) is the median */
static size_t untrusted_by_sorting(const double *w, size_t m, double trust, size_t *out) {
  static double sorted[400];
  size_t i, n = 0;
  memcpy(sorted, w, m * sizeof(double));
  qsort(sorted, m, sizeof(double), cmp_double);
  for (i = 0; i < m; i++)
    if (w[i] < trust * sorted[m / 2]) out[n++] = i;
  return n;
}

static void test_untrusted_is_the_median_rule(void **state) {
  /* many sizes, seeds and kinds of weights: a few distinct values (files), continuous
  ** spreads over decades, outliers of 1e-3 among ones, huge weights */
  static double w[400];
  static size_t got[400], want[400];
  static const double trusts[] = {0.0, 0.05, 0.1, 0.5, 0.99};
  test_rng r = {11};
  int trial;
  (void)state;
  for (trial = 0; trial < 2000; trial++) {
    size_t m = 1 + (size_t)(rng_uniform(&r) * 399), i, n = 99, nw;
    int kind = trial % 4;
    double trust = trusts[trial % 5];
    for (i = 0; i < m; i++) {
      double x = rng_uniform(&r);
      w[i] = kind == 0 ? (x < 0.02 ? 1e-3 : 1.0)
           : kind == 1 ? pow(10.0, -6.0 * x)
           : kind == 2 ? (double)(1 + (int)(x * 3)) /* 1, 2, 3 */
                       : (x < 0.05 ? 1e12 : 0.5 + x);
    }
    assert_int_equal(bsfit_untrusted(w, m, trust, got, &n, NULL, NULL), BSFIT_OK);
    nw = untrusted_by_sorting(w, m, trust, want);
    assert_int_equal(n, nw);
    for (i = 0; i < n; i++) assert_int_equal(got[i], want[i]);
  }
}

static void test_untrusted_agrees_with_trusted_params(void **state) {
  /* bsfit_params_trusted computes its chords over the points bsfit_untrusted keeps: the
  ** parameters of the kept points are those of the kept points alone (open data, where
  ** no shift applies) */
  static double xy[2 * 300], kept[2 * 300], w[300], u[300], uk[300];
  static size_t out[300];
  test_rng r = {12};
  size_t i, j, k, n;
  (void)state;
  make_shape(&r, SHAPE_ELLIPSE, 300, 1, 1e-3, xy);
  for (i = 0; i < 300; i++) w[i] = rng_uniform(&r) < 0.1 ? 1e-3 * (1 + rng_uniform(&r)) : 1 + rng_uniform(&r);
  w[0] = w[299] = 1.0;
  assert_int_equal(bsfit_untrusted(w, 300, 0.1, out, &n, NULL, NULL), BSFIT_OK);
  assert_true(n > 10);
  for (i = 0, j = 0, k = 0; i < 300; i++) {
    if (k < n && out[k] == i) { k++; continue; }
    kept[2 * j] = xy[2 * i], kept[2 * j + 1] = xy[2 * i + 1], j++;
  }
  assert_int_equal(bsfit_params_trusted(xy, 300, 2, BSFIT_PARAM_CHORD, 0, w, 0.1, u, NULL, NULL), BSFIT_OK);
  assert_int_equal(bsfit_params(kept, j, 2, BSFIT_PARAM_CHORD, 0, uk, NULL), BSFIT_OK);
  for (i = 0, j = 0, k = 0; i < 300; i++) {
    if (k < n && out[k] == i) { k++; continue; }
    assert_float_equal(u[i], uk[j], 1e-14);
    j++;
  }
}

static void test_untrusted_errors(void **state) {
  double w[4] = {1, 2, 3, 4};
  size_t out[4], n = 7;
  bsfit_status st;
  (void)state;
  assert_int_equal(bsfit_untrusted(w, 4, 1.0, out, &n, NULL, &st), BSFIT_EINVAL);
  assert_int_equal(n, 0);
  assert_int_equal(bsfit_untrusted(w, 4, -0.1, out, &n, NULL, &st), BSFIT_EINVAL);
  assert_int_equal(bsfit_untrusted(NULL, 4, 0.1, out, &n, NULL, &st), BSFIT_EINVAL);
  assert_int_equal(bsfit_untrusted(w, 4, 0.1, NULL, &n, NULL, &st), BSFIT_EINVAL);
  w[3] = -1.0;
  assert_int_equal(bsfit_untrusted(w, 4, 0.1, out, &n, NULL, &st), BSFIT_EWEIGHT);
  assert_non_null(strstr(st.msg, "weight 3"));
  w[3] = INFINITY;
  assert_int_equal(bsfit_untrusted(w, 4, 0.1, out, &n, NULL, &st), BSFIT_EWEIGHT);
  w[3] = NAN;
  assert_int_equal(bsfit_untrusted(w, 4, 0.1, out, &n, NULL, &st), BSFIT_EWEIGHT);
  assert_int_equal(bsfit_untrusted(NULL, 0, 0.1, NULL, &n, NULL, &st), BSFIT_OK);
  assert_int_equal(n, 0);
}

/* number of parameters (taken modulo 1 from t0) in [a, b) */
static size_t params_in(const double *u, size_t m, double t0, double a, double b) {
  size_t i, c = 0;
  for (i = 0; i < m; i++) {
    double v = u[i] < t0 ? u[i] + 1.0 : u[i];
    if (v >= a && v < b) c++;
  }
  return c;
}

static void check_period(const double *u, size_t m, const double *t, size_t N, int p) {
  size_t k, run = 1;
  assert_float_equal(t[N] - t[0], 1.0, 1e-15);
  for (k = 1; k <= N; k++) {
    assert_true(t[k] >= t[k - 1]);
    run = t[k] == t[k - 1] ? run + 1 : 1;
    assert_true(run <= (size_t)p);
  }
  for (k = 0; k < N; k++)
    if (t[k + 1] > t[k] && params_in(u, m, t[0], t[k], t[k + 1]) < 2)
      fail_msg("span %zu [%g, %g) holds fewer than two parameters", k, t[k], t[k + 1]);
}

static void test_breaks_none_is_guarded_periodic_averaging(void **state) {
  static double xy[2 * 300], u[300], t[301];
  test_rng r = {3};
  size_t N;
  (void)state;
  make_shape(&r, SHAPE_STAR, 300, 1, 0.0, xy);
  assert_int_equal(bsfit_params(xy, 300, 2, BSFIT_PARAM_CHORD, 1, u, NULL), BSFIT_OK);
  assert_int_equal(bsfit_knots_place_breaks(u, 300, 3, 40, NULL, 0, t, &N, NULL, NULL), BSFIT_OK);
  assert_int_equal(N, 40);
  assert_float_equal(t[0], 0.0, 0.0);
  check_period(u, 300, t, N, 3);
  /* asking for as many knots as points: the guard merges spans to >= 2 points each */
  assert_int_equal(bsfit_knots_place_breaks(u, 300, 3, 300, NULL, 0, t, &N, NULL, NULL), BSFIT_OK);
  assert_true(N <= 150 && N >= 100);
  check_period(u, 300, t, N, 3);
}

static void test_guard_with_clustered_parameters(void **state) {
  /* 60 parameters in 3 tight clusters: most spans would be empty without the guard */
  double u[60], t[61];
  size_t i, N;
  (void)state;
  for (i = 0; i < 60; i++) u[i] = (double)(i / 20) / 3.0 + 1e-4 * (double)(i % 20);
  assert_int_equal(bsfit_knots_place_breaks(u, 60, 3, 30, NULL, 0, t, &N, NULL, NULL), BSFIT_OK);
  check_period(u, 60, t, N, 3);
}

static void test_square_with_corner_breaks_is_fitted_exactly(void **state) {
  /* a clean square sampled evenly: with knots of multiplicity 3 at the corners the
  ** cubic space holds the square itself, so the periodic least-squares fit is exact */
  static double xy[2 * 200], u[200], t[201], res[200];
  const double sq[] = {0, 0, 1, 0, 1, 1, 0, 1};
  const double corners[] = {0, 50, 100, 150};
  test_rng r = {4};
  size_t N, k;
  bsfit_fitter *f = NULL;
  bsfit_fit_opts o;
  bsfit_fit_report rep;
  bsfit_curve c;
  (void)state;
  make_polygon(&r, sq, 4, 200, 0.0, xy);
  assert_int_equal(bsfit_params(xy, 200, 2, BSFIT_PARAM_CHORD, 1, u, NULL), BSFIT_OK);
  assert_int_equal(bsfit_knots_place_breaks(u, 200, 3, 24, corners, 4, t, &N, NULL, NULL), BSFIT_OK);
  assert_int_equal(N, 24);
  check_period(u, 200, t, N, 3);
  for (k = 0; k < 4; k++) { /* each corner parameter is a triple knot */
    double tc = u[(size_t)corners[k]];
    size_t j, mult = 0;
    for (j = 0; j < N; j++) mult += t[j] == tc;
    assert_int_equal(mult, 3);
  }
  bsfit_fit_opts_init(&o);
  o.degree = 3;
  o.periodic = 1;
  o.count = N;
  o.knots = t;
  o.nknots = N + 1;
  assert_int_equal(bsfit_fitter_new(&f, &o, NULL, NULL), BSFIT_OK);
  bsfit_curve_init(&c);
  assert_int_equal(bsfit_fitter_fit(f, xy, 200, 2, u, NULL, &c, &rep, res, NULL), BSFIT_OK);
  assert_true(rep.max < 1e-12);
  bsfit_curve_free(&c);
  bsfit_fitter_free(f);
}

static void test_breaks_errors(void **state) {
  double u[10], t[20];
  size_t i, N;
  double bad[] = {3, 2}, far[] = {12};
  bsfit_status st;
  (void)state;
  for (i = 0; i < 10; i++) u[i] = (double)i / 10.0;
  assert_int_equal(bsfit_knots_place_breaks(u, 10, 0, 5, NULL, 0, t, &N, NULL, &st), BSFIT_EDEGREE);
  assert_int_equal(bsfit_knots_place_breaks(u, 10, 3, 5, bad, 2, t, &N, NULL, &st), BSFIT_EINVAL);
  assert_int_equal(bsfit_knots_place_breaks(u, 10, 3, 5, far, 1, t, &N, NULL, &st), BSFIT_EINVAL);
  assert_int_equal(bsfit_knots_place_breaks(u, 10, 3, 3, NULL, 0, t, &N, NULL, &st), BSFIT_EINVAL);
  u[4] = 0.1;
  assert_int_equal(bsfit_knots_place_breaks(u, 10, 3, 5, NULL, 0, t, &N, NULL, &st), BSFIT_EINVAL);
  assert_true(strlen(st.msg) > 0);
}

int main(void) {
  const struct CMUnitTest tests[] = {
    cmocka_unit_test(test_trusted_params_without_weights_are_chord_params),
    cmocka_unit_test(test_outlier_does_not_stretch_neighbours),
    cmocka_unit_test(test_trusted_params_errors),
    cmocka_unit_test(test_untrusted_is_the_median_rule),
    cmocka_unit_test(test_untrusted_agrees_with_trusted_params),
    cmocka_unit_test(test_untrusted_errors),
    cmocka_unit_test(test_breaks_none_is_guarded_periodic_averaging),
    cmocka_unit_test(test_guard_with_clustered_parameters),
    cmocka_unit_test(test_square_with_corner_breaks_is_fitted_exactly),
    cmocka_unit_test(test_breaks_errors),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
