/*
** test_basis.c
** Basis functions: The NURBS Book examples 2.3/2.4 by hand, partition of unity and
** non-negativity on random knot vectors, derivatives against finite differences,
** Bernstein polynomials against the binomial formula.
*/
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>

#include "bsfit.h"
#include "testutil.h"

static void test_nurbs_book_example_2_3(void **state) {
  /* U = {0,0,0,1,2,3,4,4,5,5,5}, p = 2, u = 5/2: span 4 and
  ** N_{2,2} = 1/8, N_{3,2} = 6/8, N_{4,2} = 1/8 (The NURBS Book, ex. 2.3);
  ** derivatives (ex. 2.4): N'_{2,2} = -1/2, N'_{3,2} = 0, N'_{4,2} = 1/2. */
  const double U[] = {0, 0, 0, 1, 2, 3, 4, 4, 5, 5, 5};
  double N[3], D[2 * 3];
  size_t s = bsfit_knots_find_span(U, 8, 2, 2.5);
  (void)state;
  assert_int_equal(s, 4);
  bsfit_basis_funs(s, 2.5, 2, U, N);
  assert_float_equal(N[0], 1.0 / 8.0, EPS_EXACT);
  assert_float_equal(N[1], 6.0 / 8.0, EPS_EXACT);
  assert_float_equal(N[2], 1.0 / 8.0, EPS_EXACT);
  bsfit_basis_ders(s, 2.5, 2, 1, U, D);
  assert_float_equal(D[0], 1.0 / 8.0, EPS_EXACT);
  assert_float_equal(D[3], -0.5, EPS_EXACT);
  assert_float_equal(D[4], 0.0, EPS_EXACT);
  assert_float_equal(D[5], 0.5, EPS_EXACT);
  /* second derivatives of a quadratic in span [2,3): N_{2,2} = (3-u)^2/2 -> 1,
  ** N_{4,2} = (u-2)^2/2 -> 1, N_{3,2} -> -2 (they sum to 0) */
  {
    double D2[3 * 3];
    bsfit_basis_ders(s, 2.5, 2, 2, U, D2);
    assert_float_equal(D2[6], 1.0, EPS_EXACT);
    assert_float_equal(D2[7], -2.0, EPS_EXACT);
    assert_float_equal(D2[8], 1.0, EPS_EXACT);
  }
}

static void test_partition_of_unity_random(void **state) {
  test_rng r = {987654321};
  int trial;
  (void)state;
  for (trial = 0; trial < 300; trial++) {
    int p = trial % 7, j, k;
    size_t n = (size_t)p + 1 + (size_t)(trial % 13);
    double U[64], a, b, N[BSFIT_MAX_DEGREE + 1];
    random_knots(&r, p, n, trial % 3 == 0, U);
    bsfit_knots_domain(U, n, p, &a, &b);
    for (k = 0; k <= 40; k++) {
      double u = a + (b - a) * rng_uniform(&r), sum = 0.0;
      size_t s = bsfit_knots_find_span(U, n, p, u);
      bsfit_basis_funs(s, u, p, U, N);
      for (j = 0; j <= p; j++) {
        assert_true(N[j] >= 0.0);
        sum += N[j];
      }
      assert_float_equal(sum, 1.0, 1e-13);
    }
  }
}

/* the value of basis function i of degree p at u, straight from Cox-de Boor's
** recursive definition (independent of the triangular algorithm) */
static double cox_de_boor(const double *U, int i, int p, double u, double b) {
  double left = 0.0, right = 0.0, d;
  if (p == 0) {
    /* the domain end belongs to the last non-empty span, not to the one after it */
    if (u == b) return (U[i] < U[i + 1] && U[i + 1] == b) ? 1.0 : 0.0;
    return (U[i] <= u && u < U[i + 1]) ? 1.0 : 0.0;
  }
  d = U[i + p] - U[i];
  if (d > 0) left = (u - U[i]) / d * cox_de_boor(U, i, p - 1, u, b);
  d = U[i + p + 1] - U[i + 1];
  if (d > 0) right = (U[i + p + 1] - u) / d * cox_de_boor(U, i + 1, p - 1, u, b);
  return left + right;
}

static void test_matches_recursive_definition(void **state) {
  test_rng r = {42};
  int trial;
  (void)state;
  for (trial = 0; trial < 60; trial++) {
    int p = 1 + trial % 5, j, k;
    size_t n = (size_t)p + 2 + (size_t)(trial % 7);
    double U[64], a, b, N[BSFIT_MAX_DEGREE + 1];
    random_knots(&r, p, n, trial % 2, U);
    bsfit_knots_domain(U, n, p, &a, &b);
    for (k = 0; k <= 20; k++) {
      double u = k == 20 ? b : a + (b - a) * k / 20.0; /* exactly b: no rounding past the end */
      size_t s = bsfit_knots_find_span(U, n, p, u);
      bsfit_basis_funs(s, u, p, U, N);
      for (j = 0; j <= p; j++)
        assert_float_equal(N[j], cox_de_boor(U, (int)s - p + j, p, u, b), 1e-12);
    }
  }
}

static void test_derivatives_against_finite_differences(void **state) {
  test_rng r = {7};
  int trial;
  (void)state;
  for (trial = 0; trial < 100; trial++) {
    int p = 1 + trial % 6, j, k, order;
    size_t n = (size_t)p + 1 + (size_t)(trial % 9);
    double U[64], a, b;
    double D[(BSFIT_MAX_DEGREE + 1) * (BSFIT_MAX_DEGREE + 1)];
    double Dp[(BSFIT_MAX_DEGREE + 1) * (BSFIT_MAX_DEGREE + 1)];
    double Dm[(BSFIT_MAX_DEGREE + 1) * (BSFIT_MAX_DEGREE + 1)];
    random_knots(&r, p, n, trial % 2, U);
    bsfit_knots_domain(U, n, p, &a, &b);
    for (k = 0; k < 10; k++) {
      size_t s = bsfit_knots_find_span(U, n, p, a + (b - a) * rng_uniform(&r));
      /* a point well inside span s, so that u +- h stays in the same polynomial piece */
      double u = U[s] + (U[s + 1] - U[s]) * rng_range(&r, 0.2, 0.8);
      double h = 1e-5 * (U[s + 1] - U[s]);
      int nd = p + 1;
      bsfit_basis_ders(s, u, p, nd, U, D);
      bsfit_basis_ders(s, u + h, p, nd, U, Dp);
      bsfit_basis_ders(s, u - h, p, nd, U, Dm);
      for (order = 1; order <= p; order++) {
        double scale = 0.0;
        for (j = 0; j <= p; j++) {
          double v = fabs(D[order * (p + 1) + j]);
          if (v > scale) scale = v;
        }
        for (j = 0; j <= p; j++) {
          /* d/du of the (order-1)-th derivative by central differences */
          double fd = (Dp[(order - 1) * (p + 1) + j] - Dm[(order - 1) * (p + 1) + j]) / (2 * h);
          assert_float_equal(D[order * (p + 1) + j], fd, EPS_FD * (1.0 + scale));
        }
      }
      /* derivatives sum to zero (derivative of the partition of unity), order p+1 is zero */
      for (order = 1; order <= nd; order++) {
        double sum = 0.0;
        for (j = 0; j <= p; j++) sum += D[order * (p + 1) + j];
        assert_float_equal(sum, 0.0, 1e-8 * (1.0 + fabs(D[order * (p + 1)])));
      }
      for (j = 0; j <= p; j++) assert_true(D[nd * (p + 1) + j] == 0.0);
    }
  }
}

static double binomial(int n, int k) {
  double c = 1.0;
  int i;
  for (i = 1; i <= k; i++) c = c * (n - k + i) / i;
  return c;
}

static void test_bernstein(void **state) {
  int n, k, i;
  double B[BSFIT_MAX_DEGREE + 1], Bs[BSFIT_MAX_DEGREE + 1];
  (void)state;
  for (n = 0; n <= 12; n++) {
    for (i = 0; i <= 20; i++) {
      double u = i / 20.0, sum = 0.0;
      bsfit_bernstein(n, u, B);
      bsfit_bernstein(n, 1.0 - u, Bs);
      for (k = 0; k <= n; k++) {
        double exact = binomial(n, k) * pow(u, k) * pow(1.0 - u, n - k);
        assert_float_equal(B[k], exact, 1e-13);
        assert_float_equal(B[k], Bs[n - k], 1e-13); /* B_{k,n}(u) = B_{n-k,n}(1-u) */
        assert_true(B[k] >= 0.0);
        sum += B[k];
      }
      assert_float_equal(sum, 1.0, 1e-13);
    }
  }
}

static void test_bernstein_is_bspline_on_bezier_knots(void **state) {
  /* on knots {0^(p+1), 1^(p+1)} the B-spline basis is the Bernstein basis */
  double U[2 * (BSFIT_MAX_DEGREE + 1)], N[BSFIT_MAX_DEGREE + 1], B[BSFIT_MAX_DEGREE + 1];
  int p, j, i;
  (void)state;
  for (p = 1; p <= 8; p++) {
    for (j = 0; j <= p; j++) {
      U[j] = 0.0;
      U[p + 1 + j] = 1.0;
    }
    for (i = 0; i <= 10; i++) {
      double u = i / 10.0;
      size_t s = bsfit_knots_find_span(U, (size_t)p + 1, p, u);
      bsfit_basis_funs(s, u, p, U, N);
      bsfit_bernstein(p, u, B);
      for (j = 0; j <= p; j++) assert_float_equal(N[j], B[j], 1e-14);
    }
  }
}

int main(void) {
  const struct CMUnitTest tests[] = {
    cmocka_unit_test(test_nurbs_book_example_2_3),
    cmocka_unit_test(test_partition_of_unity_random),
    cmocka_unit_test(test_matches_recursive_definition),
    cmocka_unit_test(test_derivatives_against_finite_differences),
    cmocka_unit_test(test_bernstein),
    cmocka_unit_test(test_bernstein_is_bspline_on_bezier_knots),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
