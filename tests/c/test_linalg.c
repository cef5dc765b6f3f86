/*
** test_linalg.c
** The LAPACK layer: mapping of every kind of `info` to a status code, banded Cholesky and
** banded LU solves checked by multiplying back, condition estimates on matrices whose
** condition number is known exactly.
*/
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include "cmocka_double.h"
#include <string.h>

#include "core/fit_internal.h"
#include "testutil.h"

static void test_info_mapping(void **state) {
  bsfit_status st;
  (void)state;
  assert_int_equal(bsfit__lapack_status(0, "dpbtrf", 1, &st), BSFIT_OK);
  assert_int_equal(bsfit__lapack_status(-4, "dpbtrf", 1, &st), BSFIT_ELAPACK);
  assert_non_null(strstr(st.msg, "argument 4"));
  assert_int_equal(bsfit__lapack_status(3, "dpbtrf", 1, &st), BSFIT_ENOTSPD);
  assert_int_equal(bsfit__lapack_status(3, "dgbsv", 0, &st), BSFIT_ESINGULAR);
  assert_int_equal(bsfit__lapack_status(-1010, "dgbsv", 0, &st), BSFIT_ENOMEM);
  assert_int_equal(bsfit__lapack_status(-1011, "dgbsv", 0, &st), BSFIT_ENOMEM);
}

/* the tridiagonal (2, -1) matrix of order n, lower band storage, plus shift */
static void tridiag(size_t n, double shift, double *ab) {
  size_t j;
  for (j = 0; j < n; j++) {
    ab[2 * j] = 2.0 + shift;
    ab[2 * j + 1] = j + 1 < n ? -1.0 : 0.0;
  }
}

static void test_band_cholesky_solves(void **state) {
  const size_t n = 50;
  double ab[100], b[100], x[100];
  size_t i, c;
  bsfit_status st;
  (void)state;
  tridiag(n, 0.5, ab);
  for (i = 0; i < 2 * n; i++) b[i] = x[i] = sin((double)i);
  assert_int_equal(bsfit__pb_factor(n, 1, ab, 2, &st), BSFIT_OK);
  assert_int_equal(bsfit__pb_solve(n, 1, ab, 2, 2, x, n, &st), BSFIT_OK);
  /* A x = b for both right-hand sides */
  for (c = 0; c < 2; c++)
    for (i = 0; i < n; i++) {
      double ax = 2.5 * x[c * n + i] - (i > 0 ? x[c * n + i - 1] : 0.0) -
                  (i + 1 < n ? x[c * n + i + 1] : 0.0);
      assert_float_equal(ax, b[c * n + i], 1e-12);
    }
  /* an indefinite band is reported as not positive definite */
  tridiag(n, -3.0, ab);
  assert_int_equal(bsfit__pb_factor(n, 1, ab, 2, &st), BSFIT_ENOTSPD);
  assert_int_equal(st.code, BSFIT_ENOTSPD);
}

static void test_condition_estimates(void **state) {
  /* diag(1, 2, 4, 8): |A|_1 = 8, |A^-1|_1 = 1, rcond = 1/8 exactly */
  double ab[8] = {1, 0, 2, 0, 4, 0, 8, 0}, work[12], a[16];
  int iwork[4];
  size_t i;
  (void)state;
  assert_int_equal(bsfit__pb_factor(4, 1, ab, 2, NULL), BSFIT_OK);
  assert_float_equal(bsfit__pb_rcond_tn(4, 1, ab, 2, 8.0, work), 0.125, EPS_EXACT);
  memset(a, 0, sizeof a);
  for (i = 0; i < 4; i++) a[i * 5] = (double)(1u << i);
  assert_int_equal(bsfit__po_factor(4, a, 4, NULL), BSFIT_OK);
  assert_float_equal(bsfit__po_rcond(4, a, 4, 8.0, work, iwork), 0.125, EPS_EXACT);
}

static void test_condition_estimate_of_a_cubic_band(void **state) {
  /* given a random SPD matrix of bandwidth 3 that is not totally nonnegative (signs of
  ** both kinds off the diagonal), when its condition is read off one solve with
  ** s = (1, -1, ...), then the value does not depend on the band's storage (kd = 3 or 4)
  ** and is an upper bound of the exact rcond from a dense inverse (|A^-1 s|_inf is at
  ** most |A^-1|_1); the exact case, totally nonnegative normal matrices, is test_wls's */
  enum { n = 12 };
  double a[n * n], inv[n * n], ab3[4 * n], ab4[5 * n], work[n], anorm = 0.0, inorm = 0.0;
  size_t i, j;
  test_rng r = {4242};
  (void)state;
  memset(a, 0, sizeof a);
  for (j = 0; j < n; j++)
    for (i = j; i < n && i <= j + 3; i++) a[i + j * n] = a[j + i * n] = rng_range(&r, -1.0, 1.0);
  for (j = 0; j < n; j++) a[j + j * n] = 4.0 + rng_range(&r, 0.0, 1.0) * (double)(j % 3);
  memset(ab4, 0, sizeof ab4);
  for (j = 0; j < n; j++)
    for (i = j; i < n && i <= j + 3; i++) ab3[(i - j) + j * 4] = ab4[(i - j) + j * 5] = a[i + j * n];
  for (j = 0; j < n; j++) { /* |A|_1 and, from a dense inverse, |A^-1|_1 */
    double cs = 0.0;
    for (i = 0; i < n; i++) cs += fabs(a[i + j * n]), inv[i + j * n] = i == j ? 1.0 : 0.0;
    if (cs > anorm) anorm = cs;
  }
  assert_int_equal(bsfit__po_factor(n, a, n, NULL), BSFIT_OK);
  assert_int_equal(bsfit__po_solve(n, a, n, n, inv, n, NULL), BSFIT_OK);
  for (j = 0; j < n; j++) {
    double cs = 0.0;
    for (i = 0; i < n; i++) cs += fabs(inv[i + j * n]);
    if (cs > inorm) inorm = cs;
  }
  assert_int_equal(bsfit__pb_factor(n, 3, ab3, 4, NULL), BSFIT_OK);
  assert_int_equal(bsfit__pb_factor(n, 4, ab4, 5, NULL), BSFIT_OK);
  {
    double rc3 = bsfit__pb_rcond_tn(n, 3, ab3, 4, anorm, work);
    double rc4 = bsfit__pb_rcond_tn(n, 4, ab4, 5, anorm, work), exact = 1.0 / (anorm * inorm);
    assert_float_equal(rc3, rc4, 1e-12 * rc4);
    assert_true(rc3 >= exact * (1.0 - 1e-12));
  }
}

static void test_band_lu_and_dense_cholesky(void **state) {
  /* non-symmetric tridiagonal [3 1; -1 3 1; ...] with kl = ku = 1: ldab = 4 */
  const size_t n = 6;
  double ab[24], b[6], x[6], a[9] = {4, 1, 0, 1, 3, 1, 0, 1, 2}, y[3] = {1, 2, 3};
  int ipiv[6];
  size_t i;
  bsfit_status st;
  (void)state;
  memset(ab, 0, sizeof ab);
  for (i = 0; i < n; i++) {
    ab[2 + i * 4] = 3.0;                  /* diagonal: row kl+ku */
    if (i > 0) ab[1 + i * 4] = 1.0;       /* super-diagonal A(i-1, i) */
    if (i + 1 < n) ab[3 + i * 4] = -1.0;  /* sub-diagonal A(i+1, i) */
    b[i] = x[i] = (double)i + 1.0;
  }
  assert_int_equal(bsfit__gb_solve(n, 1, 1, ab, 4, ipiv, 1, x, n, &st), BSFIT_OK);
  for (i = 0; i < n; i++) {
    double ax = 3.0 * x[i] + (i + 1 < n ? x[i + 1] : 0.0) - (i > 0 ? x[i - 1] : 0.0);
    assert_float_equal(ax, b[i], 1e-12);
  }
  memset(ab, 0, sizeof ab);
  assert_int_equal(bsfit__gb_solve(n, 1, 1, ab, 4, ipiv, 1, x, n, &st), BSFIT_ESINGULAR);
  /* dense SPD 3x3 */
  assert_int_equal(bsfit__po_factor(3, a, 3, &st), BSFIT_OK);
  assert_int_equal(bsfit__po_solve(3, a, 3, 1, y, 3, &st), BSFIT_OK);
  assert_float_equal(4 * y[0] + y[1], 1.0, 1e-13);
  assert_float_equal(y[0] + 3 * y[1] + y[2], 2.0, 1e-13);
  assert_float_equal(y[1] + 2 * y[2], 3.0, 1e-13);
}

static void test_blas_single_thread(void **state) {
  /* asking for one BLAS thread is harmless whatever the BLAS (1: a setting was found,
  ** 0: none to make), and banded solves are still right afterwards */
  double ab[100], x[50];
  size_t i;
  int r = bsfit_blas_single_thread();
  (void)state;
  assert_true(r == 0 || r == 1);
  tridiag(50, 0.5, ab);
  for (i = 0; i < 50; i++) x[i] = 1.0;
  assert_int_equal(bsfit__pb_factor(50, 1, ab, 2, NULL), BSFIT_OK);
  assert_int_equal(bsfit__pb_solve(50, 1, ab, 2, 1, x, 50, NULL), BSFIT_OK);
  for (i = 0; i < 50; i++) { /* (2.5, -1) tridiagonal times x gives back the ones */
    double ax = 2.5 * x[i] - (i > 0 ? x[i - 1] : 0.0) - (i + 1 < 50 ? x[i + 1] : 0.0);
    assert_float_equal(ax, 1.0, 1e-12);
  }
}

int main(void) {
  const struct CMUnitTest tests[] = {
    cmocka_unit_test(test_info_mapping),
    cmocka_unit_test(test_band_cholesky_solves),
    cmocka_unit_test(test_condition_estimates),
    cmocka_unit_test(test_condition_estimate_of_a_cubic_band),
    cmocka_unit_test(test_blas_single_thread),
    cmocka_unit_test(test_band_lu_and_dense_cholesky),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
