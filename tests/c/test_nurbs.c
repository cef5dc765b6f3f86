/*
** test_nurbs.c
** Rational curves against exact geometry: the quarter circle as a rational quadratic and
** the 9-point full circle of The NURBS Book (ex. 7.1) stay at radius 1, their tangent is
** perpendicular to the radius and the full circle is 2 pi long; rational derivatives
** against finite differences; knot insertion and degree elevation keep the circle; the
** closest point of the circle to an outside point lies on the ray through it.
*/
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>

#include "bsfit.h"
#include "cmocka_double.h"
#include "testutil.h"

#define EPS_RADIUS 1e-14
#define NPAR 1000

static const double SQ = 0.70710678118654752440; /* sqrt(2)/2 */

static void make_full_circle(bsfit_curve *c) {
  static const double U[12] = {0, 0, 0, 0.25, 0.25, 0.5, 0.5, 0.75, 0.75, 1, 1, 1};
  const double P[18] = {1, 0, 1, 1, 0, 1, -1, 1, -1, 0, -1, -1, 0, -1, 1, -1, 1, 0};
  const double W[9] = {1, SQ, 1, SQ, 1, SQ, 1, SQ, 1};
  bsfit_curve_init(c);
  assert_int_equal(bsfit_curve_new(c, 2, 2, 9, U, P, W, 0, NULL, NULL), BSFIT_OK);
}

/* every point at radius 1, every tangent perpendicular to the radius */
static void assert_unit_circle(const bsfit_curve *c, double eps) {
  double a, b, D[2 * 2];
  int i;
  bsfit_curve_domain(c, &a, &b);
  for (i = 0; i <= NPAR; i++) {
    double u = a + (b - a) * (double)i / NPAR;
    assert_int_equal(bsfit_curve_derivs(c, u, 1, D, NULL), BSFIT_OK);
    assert_float_equal(hypot(D[0], D[1]), 1.0, eps);
    assert_float_equal(D[0] * D[2] + D[1] * D[3], 0.0, 1e-12 * (1 + hypot(D[2], D[3])));
  }
}

static void test_quarter_circle(void **state) {
  const double P[6] = {1, 0, 1, 1, 0, 1}, W[3] = {1, SQ, 1};
  double len, x[2];
  bsfit_curve c;
  (void)state;
  bsfit_curve_init(&c);
  assert_int_equal(bsfit_curve_new(&c, 2, 2, 3, NULL, P, W, 0, NULL, NULL), BSFIT_OK);
  assert_unit_circle(&c, EPS_RADIUS);
  /* symmetric weights: the middle parameter is the middle of the arc, 45 degrees */
  bsfit_curve_eval(&c, 0.5, x, NULL);
  assert_float_equal(x[0], SQ, EPS_RADIUS);
  assert_float_equal(x[1], SQ, EPS_RADIUS);
  assert_int_equal(bsfit_curve_length(&c, 0.0, 1.0, &len, NULL), BSFIT_OK);
  assert_float_equal(len, 3.14159265358979323846 / 2, 1e-12);
  bsfit_curve_free(&c);
}

static void test_full_circle(void **state) {
  double len;
  bsfit_curve c;
  (void)state;
  make_full_circle(&c);
  assert_unit_circle(&c, EPS_RADIUS);
  assert_int_equal(bsfit_curve_length(&c, 0.0, 1.0, &len, NULL), BSFIT_OK);
  assert_float_equal(len, 2 * 3.14159265358979323846, 1e-12);
  bsfit_curve_free(&c);
}

static void test_rational_derivs_vs_fd(void **state) {
  test_rng r = {17};
  int trial, k, q;
  (void)state;
  for (trial = 0; trial < 60; trial++) {
    int p = 1 + trial % 4;
    size_t n = (size_t)p + 3, i, s;
    double U[32], P[32 * 3], W[32], D[4 * 3], Dm[4 * 3], Dp[4 * 3], u, h;
    bsfit_curve c;
    bsfit_curve_init(&c);
    random_knots(&r, p, n, 1, U);
    for (i = 0; i < 3 * n; i++) P[i] = rng_range(&r, -2, 2);
    for (i = 0; i < n; i++) W[i] = rng_range(&r, 0.2, 5);
    assert_int_equal(bsfit_curve_new(&c, p, 3, n, U, P, W, 0, NULL, NULL), BSFIT_OK);
    do {
      s = (size_t)p + (size_t)(rng_uniform(&r) * (double)(n - (size_t)p));
    } while (s >= n || U[s + 1] == U[s]);
    u = U[s] + (U[s + 1] - U[s]) * rng_range(&r, 0.2, 0.8);
    h = 1e-5 * (U[s + 1] - U[s]);
    bsfit_curve_derivs(&c, u, 3, D, NULL);
    bsfit_curve_derivs(&c, u - h, 3, Dm, NULL);
    bsfit_curve_derivs(&c, u + h, 3, Dp, NULL);
    for (k = 1; k <= 3; k++)
      for (q = 0; q < 3; q++) {
        double fd = (Dp[(k - 1) * 3 + q] - Dm[(k - 1) * 3 + q]) / (2 * h);
        assert_float_equal(fd, D[k * 3 + q], EPS_FD * (1 + fabs(D[k * 3 + q])));
      }
    bsfit_curve_free(&c);
  }
}

static void test_circle_insert_elevate(void **state) {
  const double X[3] = {0.1, 0.3, 0.6}; /* 0.25 already has multiplicity p */
  bsfit_curve c, o;
  (void)state;
  make_full_circle(&c);
  bsfit_curve_init(&o);
  assert_int_equal(bsfit_curve_refine(&c, X, 3, &o, NULL), BSFIT_OK);
  assert_int_equal(o.n, 12);
  assert_non_null(o.weights);
  assert_unit_circle(&o, EPS_RADIUS * 4);
  assert_int_equal(bsfit_curve_insert_knot(&c, 0.4, 2, &o, NULL), BSFIT_OK);
  assert_unit_circle(&o, EPS_RADIUS * 4);
  assert_int_equal(bsfit_curve_elevate(&c, 2, &o, NULL), BSFIT_OK);
  assert_int_equal(o.degree, 4);
  assert_unit_circle(&o, EPS_RADIUS * 4);
  /* the same circle split at 0.3: both pieces still on it */
  {
    bsfit_curve l, rr;
    bsfit_curve_init(&l);
    bsfit_curve_init(&rr);
    assert_int_equal(bsfit_curve_split(&c, 0.3, &l, &rr, NULL), BSFIT_OK);
    assert_unit_circle(&l, EPS_RADIUS * 4);
    assert_unit_circle(&rr, EPS_RADIUS * 4);
    bsfit_curve_free(&l);
    bsfit_curve_free(&rr);
  }
  bsfit_curve_free(&c);
  bsfit_curve_free(&o);
}

static void test_circle_closest(void **state) {
  bsfit_curve c;
  int i;
  (void)state;
  make_full_circle(&c);
  for (i = 0; i < 24; i++) {
    double th = 0.1 + 0.26 * i, Q[2] = {3 * cos(th), 3 * sin(th)}, u, dist, x[2];
    assert_int_equal(bsfit_curve_closest(&c, Q, &u, &dist, NULL, NULL), BSFIT_OK);
    assert_float_equal(dist, 2.0, 1e-12);
    bsfit_curve_eval(&c, u, x, NULL);
    assert_float_equal(x[0], cos(th), 1e-12);
    assert_float_equal(x[1], sin(th), 1e-12);
  }
  bsfit_curve_free(&c);
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_quarter_circle),
      cmocka_unit_test(test_full_circle),
      cmocka_unit_test(test_rational_derivs_vs_fd),
      cmocka_unit_test(test_circle_insert_elevate),
      cmocka_unit_test(test_circle_closest),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
