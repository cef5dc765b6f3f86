/*
** test_bezier.c
** Bézier curves against their definition: end points interpolated, Bernstein symmetry
** and partition of unity, de Casteljau (bsfit_curve_eval) equal to the Bernstein sum
** written with binomials, a Bézier curve equal to the clamped one-span B-spline, the
** curve inside the bounding box of its control polygon, the rational quadratic conic
** (a circular arc), and Bézier elevation and splitting keeping the curve.
*/
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>

#include "bsfit.h"
#include "cmocka_double.h"
#include "testutil.h"

static double binomial(int n, int k) {
  double r = 1.0;
  int i;
  for (i = 1; i <= k; i++) r = r * (n - k + i) / i;
  return r;
}

static void random_bezier(test_rng *r, bsfit_curve *c, size_t n, int rational) {
  double P[32 * 2], W[32];
  size_t i;
  for (i = 0; i < 2 * n; i++) P[i] = rng_range(r, -3, 3);
  for (i = 0; i < n; i++) W[i] = rng_range(r, 0.3, 3);
  bsfit_curve_init(c);
  assert_int_equal(bsfit_curve_new_bezier(c, 2, n, P, rational ? W : NULL, NULL, NULL), BSFIT_OK);
}

static void test_end_points(void **state) {
  test_rng r = {1};
  size_t n;
  (void)state;
  for (n = 1; n <= 12; n++) {
    bsfit_curve c;
    double x[2];
    random_bezier(&r, &c, n, (int)n % 2);
    bsfit_curve_eval(&c, 0.0, x, NULL);
    assert_float_equal(x[0], c.ctrl[0], EPS_EXACT);
    assert_float_equal(x[1], c.ctrl[1], EPS_EXACT);
    bsfit_curve_eval(&c, 1.0, x, NULL);
    assert_float_equal(x[0], c.ctrl[2 * n - 2], EPS_EXACT * 10);
    assert_float_equal(x[1], c.ctrl[2 * n - 1], EPS_EXACT * 10);
    bsfit_curve_free(&c);
  }
}

static void test_bernstein_symmetry_and_unity(void **state) {
  double B[32], Bm[32];
  int n, k, i;
  (void)state;
  for (n = 0; n <= 20; n++)
    for (i = 0; i <= 50; i++) {
      double u = i / 50.0, sum = 0.0;
      bsfit_bernstein(n, u, B);
      bsfit_bernstein(n, 1.0 - u, Bm);
      for (k = 0; k <= n; k++) {
        assert_float_equal(B[k], Bm[n - k], EPS_EXACT);
        assert_float_equal(B[k], binomial(n, k) * pow(u, k) * pow(1 - u, n - k), EPS_EXACT * 10);
        assert_true(B[k] >= 0.0);
        sum += B[k];
      }
      assert_float_equal(sum, 1.0, EPS_EXACT);
    }
}

static void test_de_casteljau_equals_bernstein_sum(void **state) {
  test_rng r = {2};
  size_t n;
  (void)state;
  for (n = 2; n <= 15; n++) {
    bsfit_curve c;
    int i;
    random_bezier(&r, &c, n, 0);
    for (i = 0; i <= 40; i++) {
      double u = i / 40.0, x[2], y[2] = {0, 0};
      size_t k;
      bsfit_curve_eval(&c, u, x, NULL);
      for (k = 0; k < n; k++) {
        double b = binomial((int)n - 1, (int)k) * pow(u, (double)k) *
                   pow(1 - u, (double)(n - 1 - k));
        y[0] += b * c.ctrl[2 * k];
        y[1] += b * c.ctrl[2 * k + 1];
      }
      assert_float_equal(x[0], y[0], 1e-12);
      assert_float_equal(x[1], y[1], 1e-12);
    }
    bsfit_curve_free(&c);
  }
}

static void test_bezier_is_one_span_bspline(void **state) {
  test_rng r = {3};
  size_t n;
  (void)state;
  for (n = 2; n <= 10; n++) {
    bsfit_curve bz, bs;
    double U[32], Dz[3 * 2], Ds[3 * 2];
    size_t i;
    int j, k;
    random_bezier(&r, &bz, n, (int)n % 2);
    for (i = 0; i < 2 * n; i++) U[i] = i < n ? 0.0 : 1.0;
    bsfit_curve_init(&bs);
    assert_int_equal(bsfit_curve_new(&bs, (int)n - 1, 2, n, U, bz.ctrl, bz.weights, 0, NULL, NULL),
                     BSFIT_OK);
    assert_false(bs.bezier);
    for (j = 0; j <= 30; j++) {
      double u = j / 30.0;
      bsfit_curve_derivs(&bz, u, 2, Dz, NULL);
      bsfit_curve_derivs(&bs, u, 2, Ds, NULL);
      for (k = 0; k < 6; k++) assert_float_equal(Dz[k], Ds[k], 1e-9 * (1 + fabs(Ds[k])));
      bsfit_curve_eval(&bz, u, Dz, NULL); /* de Casteljau */
      assert_float_equal(Dz[0], Ds[0], 1e-12);
      assert_float_equal(Dz[1], Ds[1], 1e-12);
    }
    bsfit_curve_free(&bz);
    bsfit_curve_free(&bs);
  }
}

static void test_convex_hull_bounding_box(void **state) {
  test_rng r = {4};
  int trial;
  (void)state;
  for (trial = 0; trial < 30; trial++) {
    size_t n = 2 + (size_t)trial % 10, i;
    double lo[2] = {INFINITY, INFINITY}, hi[2] = {-INFINITY, -INFINITY}, out[201 * 2];
    bsfit_curve c;
    random_bezier(&r, &c, n, trial % 2);
    for (i = 0; i < n; i++) {
      lo[0] = fmin(lo[0], c.ctrl[2 * i]);
      hi[0] = fmax(hi[0], c.ctrl[2 * i]);
      lo[1] = fmin(lo[1], c.ctrl[2 * i + 1]);
      hi[1] = fmax(hi[1], c.ctrl[2 * i + 1]);
    }
    assert_int_equal(bsfit_curve_sample(&c, 201, out, NULL, NULL), BSFIT_OK);
    for (i = 0; i < 201; i++) {
      assert_true(out[2 * i] >= lo[0] - 1e-12 && out[2 * i] <= hi[0] + 1e-12);
      assert_true(out[2 * i + 1] >= lo[1] - 1e-12 && out[2 * i + 1] <= hi[1] + 1e-12);
    }
    bsfit_curve_free(&c);
  }
}

static void test_rational_conic_arc(void **state) {
  /* arc of angle 2 th on the unit circle: P0, P2 at -th/+th, P1 where the end tangents
  ** meet (at distance 1/cos th), middle weight cos th */
  int k, i;
  (void)state;
  for (k = 1; k <= 5; k++) {
    double th = 0.25 * k, P[6], W[3], x[2];
    bsfit_curve c;
    P[0] = cos(th);
    P[1] = -sin(th);
    P[2] = 1.0 / cos(th);
    P[3] = 0.0;
    P[4] = cos(th);
    P[5] = sin(th);
    W[0] = W[2] = 1.0;
    W[1] = cos(th);
    bsfit_curve_init(&c);
    assert_int_equal(bsfit_curve_new_bezier(&c, 2, 3, P, W, NULL, NULL), BSFIT_OK);
    for (i = 0; i <= 100; i++) {
      bsfit_curve_eval(&c, i / 100.0, x, NULL);
      assert_float_equal(hypot(x[0], x[1]), 1.0, 1e-14);
    }
    bsfit_curve_free(&c);
  }
}

static void test_bezier_elevate_split(void **state) {
  test_rng r = {5};
  size_t n;
  (void)state;
  for (n = 2; n <= 9; n++) {
    bsfit_curve c, e, l, rr;
    int i;
    random_bezier(&r, &c, n, (int)n % 2);
    bsfit_curve_init(&e);
    bsfit_curve_init(&l);
    bsfit_curve_init(&rr);
    assert_int_equal(bsfit_curve_elevate(&c, 2, &e, NULL), BSFIT_OK);
    assert_true(e.bezier);
    assert_int_equal(e.n, n + 2);
    assert_int_equal(bsfit_curve_split(&c, 0.4, &l, &rr, NULL), BSFIT_OK);
    assert_true(l.bezier && rr.bezier);
    for (i = 0; i <= 100; i++) {
      double u = i / 100.0, x[2], y[2];
      bsfit_curve_eval(&c, u, x, NULL);
      bsfit_curve_eval(&e, u, y, NULL);
      assert_float_equal(x[0], y[0], 1e-12);
      assert_float_equal(x[1], y[1], 1e-12);
      bsfit_curve_eval(u <= 0.4 ? &l : &rr, u, y, NULL);
      assert_float_equal(x[0], y[0], 1e-12);
      assert_float_equal(x[1], y[1], 1e-12);
    }
    bsfit_curve_free(&c);
    bsfit_curve_free(&e);
    bsfit_curve_free(&l);
    bsfit_curve_free(&rr);
  }
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_end_points),
      cmocka_unit_test(test_bernstein_symmetry_and_unity),
      cmocka_unit_test(test_de_casteljau_equals_bernstein_sum),
      cmocka_unit_test(test_bezier_is_one_span_bspline),
      cmocka_unit_test(test_convex_hull_bounding_box),
      cmocka_unit_test(test_rational_conic_arc),
      cmocka_unit_test(test_bezier_elevate_split),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
