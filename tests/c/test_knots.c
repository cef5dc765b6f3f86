/*
** test_knots.c
** Knot vectors: validation of every invalid input, span search against a linear
** scan, multiplicity, and the uniform / clamped / periodic kinds.
*/
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>
#include <string.h>

#include "bsfit.h"
#include "testutil.h"

static void expect_error(bsfit_err got, bsfit_err want, const bsfit_status *st) {
  assert_int_equal(got, want);
  assert_int_equal(st->code, want);
  assert_true(strlen(st->msg) > 0);
}

static void test_validate_accepts_nurbs_book_vector(void **state) {
  /* given the knot vector of The NURBS Book ex. 2.3 (p = 2, n = 8) */
  const double U[] = {0, 0, 0, 1, 2, 3, 4, 4, 5, 5, 5};
  bsfit_status st;
  (void)state;
  assert_int_equal(bsfit_knots_validate(U, 11, 2, 8, &st), BSFIT_OK);
  assert_int_equal(st.code, BSFIT_OK);
}

static void test_validate_rejects_bad_vectors(void **state) {
  bsfit_status st;
  double U[] = {0, 0, 0, 1, 2, 3, 3, 3};
  (void)state;
  /* wrong count */
  expect_error(bsfit_knots_validate(U, 7, 2, 5, &st), BSFIT_ENKNOTS, &st);
  /* degree too high for the number of control points */
  expect_error(bsfit_knots_validate(U, 8, 5, 2, &st), BSFIT_EDEGREE, &st);
  expect_error(bsfit_knots_validate(U, 8, -1, 5, &st), BSFIT_EDEGREE, &st);
  /* decreasing */
  U[4] = 0.5;
  expect_error(bsfit_knots_validate(U, 8, 2, 5, &st), BSFIT_EKNOTS_DECR, &st);
  /* NaN and Inf */
  U[4] = NAN;
  expect_error(bsfit_knots_validate(U, 8, 2, 5, &st), BSFIT_ENONFINITE, &st);
  U[4] = INFINITY;
  expect_error(bsfit_knots_validate(U, 8, 2, 5, &st), BSFIT_ENONFINITE, &st);
  /* interior multiplicity p+2 */
  {
    const double V[] = {0, 0, 0, 1, 1, 1, 1, 2, 2, 2};
    expect_error(bsfit_knots_validate(V, 10, 2, 7, &st), BSFIT_EMULT, &st);
  }
  /* empty domain */
  {
    const double V[] = {0, 0, 0, 0, 0, 0};
    expect_error(bsfit_knots_validate(V, 6, 2, 3, &st), BSFIT_EMULT, &st);
    const double W[] = {0, 0, 1, 1};
    expect_error(bsfit_knots_validate(W, 4, 2, 1, &st), BSFIT_EDEGREE, &st);
    const double X[] = {0, 1, 1, 1, 1, 2};
    expect_error(bsfit_knots_validate(X, 6, 1, 4, &st), BSFIT_EMULT, &st);
    const double Y[] = {0, 1, 2, 3};
    assert_int_equal(bsfit_knots_validate(Y, 4, 1, 2, &st), BSFIT_OK);
    const double Z[] = {0, 1, 1, 3};
    expect_error(bsfit_knots_validate(Z, 4, 1, 2, &st), BSFIT_EDOMAIN, &st);
  }
  /* NULL status is allowed */
  assert_int_equal(bsfit_knots_validate(U, 7, 2, 5, NULL), BSFIT_ENKNOTS);
}

static size_t linear_span(const double *U, size_t n, int p, double u) {
  size_t s, best = (size_t)p;
  for (s = (size_t)p; s < n; s++)
    if (U[s] <= u && U[s] < U[s + 1]) best = s;
  return best;
}

static void test_find_span_matches_linear_scan(void **state) {
  test_rng r = {12345};
  int trial;
  (void)state;
  for (trial = 0; trial < 200; trial++) {
    int p = 1 + trial % 5, k;
    size_t n = (size_t)p + 1 + (size_t)(trial % 17), s;
    double U[64], a, b;
    random_knots(&r, p, n, trial % 2, U);
    assert_int_equal(bsfit_knots_validate(U, n + (size_t)p + 1, p, n, NULL), BSFIT_OK);
    bsfit_knots_domain(U, n, p, &a, &b);
    for (k = 0; k <= 50; k++) {
      double u = a + (b - a) * k / 50.0;
      s = bsfit_knots_find_span(U, n, p, u);
      assert_true(U[s] <= u || s == (size_t)p);
      assert_true(U[s] < U[s + 1]);
      assert_int_equal(s, linear_span(U, n, p, u));
    }
    /* each knot value itself lands in the span that starts there */
    for (s = (size_t)p; s < n; s++)
      if (U[s] < U[s + 1]) assert_int_equal(bsfit_knots_find_span(U, n, p, U[s]), s);
    /* the domain end belongs to the last non-empty span */
    s = bsfit_knots_find_span(U, n, p, b);
    assert_true(U[s] < U[s + 1] && U[s + 1] == b);
  }
}

static void test_multiplicity(void **state) {
  const double U[] = {0, 0, 0, 1, 2, 3, 4, 4, 5, 5, 5};
  (void)state;
  assert_int_equal(bsfit_knots_multiplicity(U, 11, 0.0), 3);
  assert_int_equal(bsfit_knots_multiplicity(U, 11, 4.0), 2);
  assert_int_equal(bsfit_knots_multiplicity(U, 11, 2.0), 1);
  assert_int_equal(bsfit_knots_multiplicity(U, 11, 2.5), 0);
  /* the ends, outside the vector, NaN, and against a plain count on random vectors */
  assert_int_equal(bsfit_knots_multiplicity(U, 11, 5.0), 3);
  assert_int_equal(bsfit_knots_multiplicity(U, 11, -1.0), 0);
  assert_int_equal(bsfit_knots_multiplicity(U, 11, 6.0), 0);
  assert_int_equal(bsfit_knots_multiplicity(U, 11, NAN), 0);
  assert_int_equal(bsfit_knots_multiplicity(U, 0, 0.0), 0);
  {
    test_rng r = {5};
    double V[40];
    int t, i, p;
    for (t = 0; t < 200; t++) {
      p = 1 + t % 5;
      random_knots(&r, p, 40 - (size_t)p - 1, t % 2, V);
      for (i = 0; i < 40; i++) {
        int j, count = 0;
        for (j = 0; j < 40; j++) count += V[j] == V[i];
        assert_int_equal(bsfit_knots_multiplicity(V, 40, V[i]), count);
      }
    }
  }
}

static void test_uniform_and_clamped(void **state) {
  double U[16], V[16];
  size_t i;
  int p = 3;
  size_t n = 7;
  size_t d = (size_t)p + 1;
  (void)state;
  /* clamped equals seed 001's order-d formula, scaled to [0,1] */
  assert_int_equal(bsfit_knots_clamped(p, n, 0.0, 1.0, U, NULL), BSFIT_OK);
  for (i = 0; i < n + d; i++) {
    /* seed 001 indexes control points 0..n-1 here: u_i = 0 (i < d), i-d+1 (d <= i <= n-1), n-d+1 (i > n-1) */
    double seed = i < d ? 0.0 : (i <= n - 1 ? (double)(i - d + 1) : (double)(n - d + 1));
    assert_float_equal(U[i], seed / (double)(n - d + 1), EPS_KNOT);
  }
  assert_int_equal(bsfit_knots_validate(U, n + d, p, n, NULL), BSFIT_OK);
  /* uniform: equal spacing everywhere and domain [a,b] */
  assert_int_equal(bsfit_knots_uniform(p, n, -1.0, 3.0, V, NULL), BSFIT_OK);
  for (i = 1; i < n + d; i++) assert_float_equal(V[i] - V[i - 1], 1.0, EPS_KNOT);
  assert_true(V[p] == -1.0 && V[n] == 3.0);
  /* errors */
  assert_int_equal(bsfit_knots_uniform(p, 2, 0, 1, V, NULL), BSFIT_EDEGREE);
  assert_int_equal(bsfit_knots_clamped(p, n, 1, 1, V, NULL), BSFIT_EDOMAIN);
  assert_int_equal(bsfit_knots_clamped(p, n, 0, NAN, V, NULL), BSFIT_EDOMAIN);
}

static void test_periodic(void **state) {
  const double period[] = {0.0, 0.1, 0.35, 0.5, 0.8, 1.0};
  double U[5 + 2 * 3 + 1];
  size_t N = 5, i;
  int p = 3;
  bsfit_status st;
  (void)state;
  assert_int_equal(bsfit_knots_periodic(p, N, period, U, &st), BSFIT_OK);
  for (i = 0; i <= N; i++) assert_true(U[(size_t)p + i] == period[i]);
  /* spans repeat with the period */
  for (i = 1; i + N < N + 2 * (size_t)p + 1; i++)
    assert_float_equal(U[i + N] - U[i + N - 1], U[i] - U[i - 1], EPS_KNOT);
  assert_int_equal(bsfit_knots_validate(U, N + 2 * (size_t)p + 1, p, N + (size_t)p, NULL), BSFIT_OK);
  /* errors */
  expect_error(bsfit_knots_periodic(p, 2, period, U, &st), BSFIT_EDEGREE, &st);
  expect_error(bsfit_knots_periodic(0, N, period, U, &st), BSFIT_EDEGREE, &st);
  {
    const double bad[] = {0.0, 0.5, 0.4, 0.6, 0.8, 1.0};
    expect_error(bsfit_knots_periodic(p, N, bad, U, &st), BSFIT_EKNOTS_DECR, &st);
    const double flat[] = {1, 1, 1, 1, 1, 1};
    expect_error(bsfit_knots_periodic(p, N, flat, U, &st), BSFIT_EDOMAIN, &st);
    const double nan[] = {0, NAN, 0.3, 0.6, 0.8, 1.0};
    expect_error(bsfit_knots_periodic(p, N, nan, U, &st), BSFIT_ENONFINITE, &st);
  }
}

static void test_error_names(void **state) {
  (void)state;
  assert_string_equal(bsfit_errname(BSFIT_ESINGULAR), "ESINGULAR");
  assert_string_equal(bsfit_errname(BSFIT_EEMPTYSPAN), "EEMPTYSPAN");
  assert_string_equal(bsfit_errname((bsfit_err)-999), "EUNKNOWN");
  assert_true(strlen(bsfit_strerror(BSFIT_EKNOTS_DECR)) > 0);
  assert_int_equal(bsfit_version_number(), BSFIT_VERSION_NUMBER);
}

int main(void) {
  const struct CMUnitTest tests[] = {
    cmocka_unit_test(test_validate_accepts_nurbs_book_vector),
    cmocka_unit_test(test_validate_rejects_bad_vectors),
    cmocka_unit_test(test_find_span_matches_linear_scan),
    cmocka_unit_test(test_multiplicity),
    cmocka_unit_test(test_uniform_and_clamped),
    cmocka_unit_test(test_periodic),
    cmocka_unit_test(test_error_names),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
