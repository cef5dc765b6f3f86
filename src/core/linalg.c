/*
** linalg.c
** The only file that calls LAPACKE: banded and dense Cholesky, triangular (band) solves,
** condition estimates and banded LU, column-major, through the *_work entry points so that
** no call allocates.
** LAPACK's `info` is turned into a bsfit_err in one function, bsfit__lapack_status.
*/
#define _GNU_SOURCE /* RTLD_DEFAULT */
#include "fit_internal.h"

#include <dlfcn.h>

#include <limits.h>
#include <math.h>
#include <lapacke.h>

/* the int work arrays of fit_internal.h are handed to LAPACK as lapack_int */
_Static_assert(sizeof(lapack_int) == sizeof(int), "an ILP64 LAPACKE is not supported");

bsfit_err bsfit__lapack_status(int info, const char *routine, int spd, bsfit_status *st) {
  if (info == 0) return BSFIT_OK;
  if (info == LAPACK_WORK_MEMORY_ERROR || info == LAPACK_TRANSPOSE_MEMORY_ERROR)
    return bsfit__fail(st, BSFIT_ENOMEM, "%s: LAPACKE ran out of memory", routine);
  if (info < 0)
    return bsfit__fail(st, BSFIT_ELAPACK, "%s: LAPACK rejected argument %d", routine, -info);
  if (spd)
    return bsfit__fail(st, BSFIT_ENOTSPD,
                       "%s: the leading minor of order %d is not positive definite", routine,
                       info);
  return bsfit__fail(st, BSFIT_ESINGULAR, "%s: exactly singular at pivot %d", routine, info);
}

/* LAPACK takes int sizes: anything larger is reported rather than truncated. */
static int fits_int(size_t a, size_t b, size_t c) {
  return a <= (size_t)INT_MAX && b <= (size_t)INT_MAX && c <= (size_t)INT_MAX;
}

static bsfit_err too_big(const char *routine, bsfit_status *st) {
  return bsfit__fail(st, BSFIT_EINVAL, "%s: system too large for LAPACK's int sizes", routine);
}

bsfit_err bsfit__pb_factor(size_t n, int kd, double *ab, size_t ldab, bsfit_status *st) {
  if (!fits_int(n, ldab, 0)) return too_big("dpbtrf", st);
  return bsfit__lapack_status(
      LAPACKE_dpbtrf_work(LAPACK_COL_MAJOR, 'L', (lapack_int)n, kd, ab, (lapack_int)ldab),
      "dpbtrf", 1, st);
}

bsfit_err bsfit__pb_solve(size_t n, int kd, const double *ab, size_t ldab, size_t nrhs,
                          double *b, size_t ldb, bsfit_status *st) {
  if (!fits_int(n, ldab, nrhs) || !fits_int(ldb, 0, 0)) return too_big("dpbtrs", st);
  return bsfit__lapack_status(LAPACKE_dpbtrs_work(LAPACK_COL_MAJOR, 'L', (lapack_int)n, kd,
                                                  (lapack_int)nrhs, ab, (lapack_int)ldab, b,
                                                  (lapack_int)ldb),
                              "dpbtrs", 1, st);
}

bsfit_err bsfit__tb_solve(size_t n, int kd, int trans, const double *ab, size_t ldab,
                          size_t nrhs, double *b, size_t ldb, bsfit_status *st) {
  if (!fits_int(n, ldab, nrhs) || !fits_int(ldb, 0, 0)) return too_big("dtbtrs", st);
  return bsfit__lapack_status(LAPACKE_dtbtrs_work(LAPACK_COL_MAJOR, 'L', trans ? 'T' : 'N', 'N',
                                                  (lapack_int)n, kd, (lapack_int)nrhs, ab,
                                                  (lapack_int)ldab, b, (lapack_int)ldb),
                              "dtbtrs", 0, st);
}

bsfit_err bsfit__tr_solve(size_t n, int trans, const double *a, size_t lda, size_t nrhs,
                          double *b, size_t ldb, bsfit_status *st) {
  if (!fits_int(n, lda, nrhs) || !fits_int(ldb, 0, 0)) return too_big("dtrtrs", st);
  return bsfit__lapack_status(LAPACKE_dtrtrs_work(LAPACK_COL_MAJOR, 'U', trans ? 'T' : 'N', 'N',
                                                  (lapack_int)n, (lapack_int)nrhs, a,
                                                  (lapack_int)lda, b, (lapack_int)ldb),
                              "dtrtrs", 0, st);
}

/* For a totally nonnegative A (an open fit's normal matrix: see fit_internal.h) the
** inverse has the checkerboard sign pattern, (-1)^(i+j) (A^-1)_ij >= 0, so column j of
** |A^-1| sums to |(A^-1 s)_j| with s_i = (-1)^i: |A^-1|_1 = |A^-1 s|_inf, one solve and
** exact. For any other matrix the same value is a lower bound of |A^-1|_1 (what
** LAPACK's estimators give too). */
double bsfit__pb_rcond_tn(size_t n, int kd, const double *ab, size_t ldab, double anorm,
                          double *work) {
  double est = 0.0;
  size_t j;
  if (n == 0 || !(anorm > 0.0)) return 0.0;
  for (j = 0; j < n; j++) work[j] = j % 2 ? -1.0 : 1.0;
  if (bsfit__pb_solve(n, kd, ab, ldab, 1, work, n, NULL) != BSFIT_OK) return 0.0;
  for (j = 0; j < n; j++)
    if (fabs(work[j]) > est) est = fabs(work[j]);
  return est > 0.0 && isfinite(est) ? 1.0 / (est * anorm) : 0.0;
}

bsfit_err bsfit__po_factor(size_t n, double *a, size_t lda, bsfit_status *st) {
  if (!fits_int(n, lda, 0)) return too_big("dpotrf", st);
  return bsfit__lapack_status(
      LAPACKE_dpotrf_work(LAPACK_COL_MAJOR, 'L', (lapack_int)n, a, (lapack_int)lda), "dpotrf", 1,
      st);
}

bsfit_err bsfit__po_solve(size_t n, const double *a, size_t lda, size_t nrhs, double *b,
                          size_t ldb, bsfit_status *st) {
  if (!fits_int(n, lda, nrhs) || !fits_int(ldb, 0, 0)) return too_big("dpotrs", st);
  return bsfit__lapack_status(LAPACKE_dpotrs_work(LAPACK_COL_MAJOR, 'L', (lapack_int)n,
                                                  (lapack_int)nrhs, a, (lapack_int)lda, b,
                                                  (lapack_int)ldb),
                              "dpotrs", 1, st);
}

double bsfit__po_rcond(size_t n, const double *a, size_t lda, double anorm, double *work,
                       int *iwork) {
  double rc = 0.0;
  lapack_int info;
  if (!fits_int(n, lda, 0)) return 0.0;
  info = LAPACKE_dpocon_work(LAPACK_COL_MAJOR, 'L', (lapack_int)n, a, (lapack_int)lda, anorm,
                             &rc, work, (lapack_int *)iwork);
  return info == 0 ? rc : 0.0;
}

bsfit_err bsfit__gb_solve(size_t n, int kl, int ku, double *ab, size_t ldab, int *ipiv,
                          size_t nrhs, double *b, size_t ldb, bsfit_status *st) {
  if (!fits_int(n, ldab, nrhs) || !fits_int(ldb, 0, 0)) return too_big("dgbsv", st);
  return bsfit__lapack_status(LAPACKE_dgbsv_work(LAPACK_COL_MAJOR, (lapack_int)n, kl, ku,
                                                 (lapack_int)nrhs, ab, (lapack_int)ldab,
                                                 (lapack_int *)ipiv, b, (lapack_int)ldb),
                              "dgbsv", 0, st);
}

int bsfit_blas_single_thread(void) {
  /* looked up at run time: the symbol exists only when the BLAS behind LAPACKE is
  ** OpenBLAS, and a reference BLAS must link and run too */
  union {
    void *sym;
    void (*set)(int);
  } f;
  f.sym = dlsym(RTLD_DEFAULT, "openblas_set_num_threads");
  if (f.sym == NULL) return 0;
  f.set(1);
  return 1;
}
