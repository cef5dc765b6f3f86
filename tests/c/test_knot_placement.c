/*
** test_knot_placement.c
** Knot rules against hand-computed values of their formulas (NURBS Book 9.68-9.69, the
** paper's P-12/P-13 as read in docs/method.md §3-4, periodic averaging), the Schoenberg-Whitney
** guarantee on random data, empty spans (which and how many), invalid inputs.
*/
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include "cmocka_double.h"
#include <string.h>

#include "bsfit.h"
#include "testutil.h"

static void expect_error(bsfit_err got, bsfit_err want, const bsfit_status *st) {
  assert_int_equal(got, want);
  assert_int_equal(st->code, want);
  assert_true(strlen(st->msg) > 0);
}

static void assert_knots(const double *got, const double *want, size_t n) {
  size_t i;
  for (i = 0; i < n; i++) assert_float_equal(got[i], want[i], EPS_KNOT);
}

static void test_averaging_by_hand(void **state) {
  /* m = 11 parameters k/10, p = 3, n = 5: d = 11/2; j = 1: i = 5, alpha = 0.5 */
  double u[11], U[9];
  const double want[] = {0, 0, 0, 0, 0.45, 1, 1, 1, 1};
  size_t k;
  (void)state;
  for (k = 0; k < 11; k++) u[k] = (double)k / 10.0;
  assert_int_equal(bsfit_knots_place_count(BSFIT_KNOTS_AVERAGING, 3, 5), 9);
  assert_int_equal(bsfit_knots_place(BSFIT_KNOTS_AVERAGING, u, 11, 3, 5, U, NULL), BSFIT_OK);
  assert_knots(U, want, 9);
  {
    const double wu[] = {0, 0, 0, 0, 0.5, 1, 1, 1, 1};
    assert_int_equal(bsfit_knots_place(BSFIT_KNOTS_UNIFORM, u, 11, 3, 5, U, NULL), BSFIT_OK);
    assert_knots(U, wu, 9);
  }
}

static void test_closed_rules_by_hand(void **state) {
  /* m = 10 closed parameters k/10, N = 4: d = 2.5 */
  double u[10], T[5];
  size_t k;
  (void)state;
  for (k = 0; k < 10; k++) u[k] = (double)k / 10.0;
  assert_int_equal(bsfit_knots_place_count(BSFIT_KNOTS_CARVALHO_CLOSED, 3, 4), 5);
  /* carvalho: t_k at fractional index k d - 1: 1.5, 4, 6.5 */
  {
    const double want[] = {0, 0.15, 0.4, 0.65, 1};
    assert_int_equal(bsfit_knots_place(BSFIT_KNOTS_CARVALHO_CLOSED, u, 10, 3, 4, T, NULL), BSFIT_OK);
    assert_knots(T, want, 5);
  }
  /* periodic averaging, odd p: index k d = 0, 2.5, 5, 7.5 */
  {
    const double want[] = {0, 0.25, 0.5, 0.75, 1};
    assert_int_equal(bsfit_knots_place(BSFIT_KNOTS_PERIODIC_AVERAGING, u, 10, 3, 4, T, NULL),
                     BSFIT_OK);
    assert_knots(T, want, 5);
  }
  /* even p: shifted by d/2: 1.25, 3.75, 6.25, 8.75 */
  {
    const double want[] = {0.125, 0.375, 0.625, 0.875, 1.125};
    assert_int_equal(bsfit_knots_place(BSFIT_KNOTS_PERIODIC_AVERAGING, u, 10, 2, 4, T, NULL),
                     BSFIT_OK);
    assert_knots(T, want, 5);
  }
  {
    const double want[] = {0, 0.25, 0.5, 0.75, 1};
    assert_int_equal(bsfit_knots_place(BSFIT_KNOTS_PERIODIC_UNIFORM, u, 10, 3, 4, T, NULL), BSFIT_OK);
    assert_knots(T, want, 5);
  }
}

static void test_every_span_holds_data(void **state) {
  /* given random sorted parameters and every rule, counts from p+1 to m */
  test_rng r = {101};
  double u[200], U[260];
  size_t m = 200, n, k, count;
  int p;
  (void)state;
  for (k = 0; k < m; k++) u[k] = ((double)k + rng_range(&r, 0.0, 0.9)) / (double)m;
  u[0] = 0.0;
  for (p = 1; p <= 5; p++)
    for (n = (size_t)p + 1; n <= m; n += 13) {
      double full[260];
      /* open averaging: Schoenberg-Whitney */
      assert_int_equal(bsfit_knots_place(BSFIT_KNOTS_AVERAGING, u, m, p, n, U, NULL), BSFIT_OK);
      assert_int_equal(bsfit_knots_empty_spans(U, n + (size_t)p + 1, p, 0, u, m, NULL, 0, &count, NULL),
                       BSFIT_OK);
      assert_int_equal(count, 0);
      /* periodic averaging, expanded, checked modulo the period */
      if (n >= 2) {
        assert_int_equal(bsfit_knots_place(BSFIT_KNOTS_PERIODIC_AVERAGING, u, m, p, n, U, NULL),
                         BSFIT_OK);
        assert_int_equal(bsfit_knots_periodic(p, n, U, full, NULL), BSFIT_OK);
        assert_int_equal(bsfit_knots_empty_spans(full, n + 2 * (size_t)p + 1, p, 1, u, m, NULL, 0,
                                                 &count, NULL),
                         BSFIT_OK);
        assert_int_equal(count, 0);
      }
    }
}

static void test_empty_spans_are_named(void **state) {
  /* uniform p = 1, n = 5 on [0, 1]: spans [0,.25) [.25,.5) [.5,.75) [.75,1]; no data in the third */
  const double u[] = {0, 0.1, 0.2, 0.3, 1.0, 1.0};
  double U[7];
  size_t spans[4], count;
  bsfit_status st;
  (void)state;
  expect_error(bsfit_knots_place(BSFIT_KNOTS_UNIFORM, u, 6, 1, 5, U, &st), BSFIT_EEMPTYSPAN, &st);
  assert_non_null(strstr(st.msg, "span 3"));
  /* the knots are still filled in */
  assert_float_equal(U[3], 0.5, EPS_KNOT);
  assert_int_equal(bsfit_knots_empty_spans(U, 7, 1, 0, u, 6, spans, 4, &count, &st), BSFIT_OK);
  assert_int_equal(count, 1);
  assert_int_equal(spans[0], 3);
  /* the list is capped, the count is not */
  {
    const double few[] = {0.0, 1.0};
    assert_int_equal(bsfit_knots_empty_spans(U, 7, 1, 0, few, 2, spans, 1, &count, NULL), BSFIT_OK);
    assert_int_equal(count, 2);
    assert_int_equal(spans[0], 2);
  }
  /* closed rule: period index named */
  {
    const double uc[] = {0.0, 0.05, 0.1, 0.15, 0.6};
    double T[5];
    expect_error(bsfit_knots_place(BSFIT_KNOTS_PERIODIC_UNIFORM, uc, 5, 3, 4, T, &st),
                 BSFIT_EEMPTYSPAN, &st);
    assert_non_null(strstr(st.msg, "span 1"));
  }
}

static void test_invalid_inputs(void **state) {
  double u[] = {0, 0.2, 0.4, 0.6, 0.8, 1.0}, U[20];
  bsfit_status st;
  size_t count;
  (void)state;
  expect_error(bsfit_knots_place((bsfit_knot_rule)42, u, 6, 2, 4, U, &st), BSFIT_EINVAL, &st);
  assert_int_equal(bsfit_knots_place_count((bsfit_knot_rule)42, 2, 4), 0);
  expect_error(bsfit_knots_place(BSFIT_KNOTS_AVERAGING, NULL, 6, 2, 4, U, &st), BSFIT_EINVAL, &st);
  expect_error(bsfit_knots_place(BSFIT_KNOTS_AVERAGING, u, 6, 0, 4, U, &st), BSFIT_EDEGREE, &st);
  expect_error(bsfit_knots_place(BSFIT_KNOTS_AVERAGING, u, 6, 4, 4, U, &st), BSFIT_EDEGREE, &st);
  expect_error(bsfit_knots_place(BSFIT_KNOTS_AVERAGING, u, 3, 2, 4, U, &st), BSFIT_ETOOFEW, &st);
  u[2] = 0.1;
  u[3] = 0.05;
  expect_error(bsfit_knots_place(BSFIT_KNOTS_AVERAGING, u, 6, 2, 4, U, &st), BSFIT_EINVAL, &st);
  u[3] = NAN;
  expect_error(bsfit_knots_place(BSFIT_KNOTS_AVERAGING, u, 6, 2, 4, U, &st), BSFIT_ENONFINITE, &st);
  {
    const double flat[] = {0.5, 0.5, 0.5, 0.5};
    expect_error(bsfit_knots_place(BSFIT_KNOTS_AVERAGING, flat, 4, 2, 3, U, &st), BSFIT_EDEGENERATE,
                 &st);
  }
  {
    /* open parameters [0, 1] are more than one period for closed rules */
    const double uo[] = {0, 0.25, 0.5, 0.75, 1.0};
    expect_error(bsfit_knots_place(BSFIT_KNOTS_CARVALHO_CLOSED, uo, 5, 3, 4, U, &st), BSFIT_EINVAL,
                 &st);
  }
  {
    const double Ubad[] = {0, 0, 1, 0.5, 2, 2};
    const double uu[] = {0, 1};
    expect_error(bsfit_knots_empty_spans(Ubad, 6, 1, 0, uu, 2, NULL, 0, &count, &st),
                 BSFIT_EKNOTS_DECR, &st);
    expect_error(bsfit_knots_empty_spans(NULL, 6, 1, 0, uu, 2, NULL, 0, &count, &st), BSFIT_EINVAL,
                 &st);
  }
}

int main(void) {
  const struct CMUnitTest tests[] = {
    cmocka_unit_test(test_averaging_by_hand),
    cmocka_unit_test(test_closed_rules_by_hand),
    cmocka_unit_test(test_every_span_holds_data),
    cmocka_unit_test(test_empty_spans_are_named),
    cmocka_unit_test(test_invalid_inputs),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
