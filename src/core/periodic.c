/*
** periodic.c
** Periodic weighted least squares (docs/method.md §13): the N distinct control points of a closed
** curve. The assembly (fit.c) works on the N+p stored control points of the expanded form
** exactly as an open fit does; here the wrapped unknowns are folded onto their originals
** (P_{N+i} = P_i), which gives a banded matrix plus p x p wrap-around corners, and the
** cyclic system is solved by block elimination of the last p unknowns:
**   [A11 A12; A12^T A22] [x1; x2] = [b1; b2],  A11 = L L^T banded (N-p unknowns),
**   Z = L^-1 A12, z = L^-1 b1,  S = A22 - Z^T Z (p x p),  x2 = S^-1 (b2 - Z^T z),
**   x1 = L^-T (z - Z x2),
** one banded Cholesky of A11, forward substitutions for Z and z, one backward for x1 and a
** dense p x p Cholesky: O(N p^2), never a dense N x N.
*/
#include "fit_internal.h"

#include <math.h>
#include <string.h>

/* Adds v to the lower entry (hi, lo) of the folded matrix, in whichever block holds it. */
static void add_folded(bsfit_fitter *f, size_t i, size_t j, double v) {
  size_t p = (size_t)f->p, n1 = f->count - p, hi = i > j ? i : j, lo = i > j ? j : i;
  if (hi < n1) f->a11[(hi - lo) + lo * (p + 1)] += v;
  else if (lo < n1) f->a12[lo + (hi - n1) * n1] += v;
  else f->s22[(hi - n1) + (lo - n1) * p] += v;
}

/* Folds the raw (N+p) band and right-hand sides onto the N distinct unknowns. */
static void fold(bsfit_fitter *f, int dim) {
  size_t p = (size_t)f->p, N = f->count, n = f->nraw, n1 = N - p, r, c, k;
  memset(f->a11, 0, (p + 1) * n1 * sizeof(double));
  memset(f->a12, 0, n1 * p * sizeof(double));
  memset(f->s22, 0, p * p * sizeof(double));
  memset(f->r2, 0, N * (size_t)dim * sizeof(double));
  for (c = 0; c < n; c++)
    for (r = c; r < n && r <= c + p; r++) add_folded(f, r % N, c % N, f->band[(r - c) + c * (p + 1)]);
  for (k = 0; k < (size_t)dim; k++)
    for (r = 0; r < n; r++) f->r2[k * N + r % N] += f->rhs[k * n + r];
}

/* 1-norm of the folded symmetric matrix, from its three blocks (colsum: N doubles). */
static double folded_norm1(const bsfit_fitter *f, double *colsum) {
  size_t p = (size_t)f->p, N = f->count, n1 = N - p, i, j;
  double mx = 0.0;
  for (j = 0; j < N; j++) colsum[j] = 0.0;
  for (j = 0; j < n1; j++)
    for (i = j; i < n1 && i <= j + p; i++) {
      double v = fabs(f->a11[(i - j) + j * (p + 1)]);
      colsum[j] += v;
      if (i != j) colsum[i] += v;
    }
  for (j = 0; j < p; j++)
    for (i = 0; i < n1; i++) {
      double v = fabs(f->a12[i + j * n1]);
      colsum[i] += v;
      colsum[n1 + j] += v;
    }
  for (j = 0; j < p; j++)
    for (i = j; i < p; i++) {
      double v = fabs(f->s22[i + j * p]);
      colsum[n1 + j] += v;
      if (i != j) colsum[n1 + i] += v;
    }
  for (j = 0; j < N; j++)
    if (colsum[j] > mx) mx = colsum[j];
  return mx;
}

/* S = A22 - Z^T Z (lower triangle), Z = L^-1 A12 in f->y. */
static void schur(bsfit_fitter *f) {
  size_t p = (size_t)f->p, n1 = f->count - p, i, j, k;
  for (j = 0; j < p; j++)
    for (i = j; i < p; i++) {
      double s = 0.0;
      for (k = 0; k < n1; k++) s += f->y[k + i * n1] * f->y[k + j * n1];
      f->s22[i + j * p] -= s;
    }
}

bsfit_err bsfit__periodic_solve(bsfit_fitter *f, int dim, double *ctrl, double *rcond,
                                bsfit_status *st) {
  size_t p = (size_t)f->p, N = f->count, n1 = N - p, d = (size_t)dim, i, j, k;
  int kd = (int)(n1 - 1 < p ? n1 - 1 : p);
  double anorm = 0.0, *t = f->work; /* p*dim scratch (work holds 3(N+p) doubles) */
  bsfit_err e;
  fold(f, dim);
  if (rcond) anorm = folded_norm1(f, f->work);
  e = bsfit__pb_factor(n1, kd, f->a11, p + 1, st);
  if (e != BSFIT_OK) return e;
  memcpy(f->y, f->a12, n1 * p * sizeof(double)); /* Z = L^-1 A12 */
  e = bsfit__tb_solve(n1, kd, 0, f->a11, p + 1, p, f->y, n1, st);
  if (e != BSFIT_OK) return e;
  schur(f);
  e = bsfit__po_factor(p, f->s22, p, st);
  if (e != BSFIT_OK) return e;
  /* z = L^-1 b1 in place, then t = b2 - Z^T z */
  e = bsfit__tb_solve(n1, kd, 0, f->a11, p + 1, d, f->r2, N, st);
  if (e != BSFIT_OK) return e;
  for (k = 0; k < d; k++)
    for (j = 0; j < p; j++) {
      double s = f->r2[k * N + n1 + j];
      for (i = 0; i < n1; i++) s -= f->y[i + j * n1] * f->r2[k * N + i];
      t[k * p + j] = s;
    }
  e = bsfit__po_solve(p, f->s22, p, d, t, p, st);
  if (e != BSFIT_OK) return e;
  for (k = 0; k < d; k++) { /* z - Z x2, then x1 = L^-T (z - Z x2) */
    for (i = 0; i < n1; i++)
      for (j = 0; j < p; j++) f->r2[k * N + i] -= f->y[i + j * n1] * t[k * p + j];
    for (j = 0; j < p; j++) ctrl[(n1 + j) * d + k] = t[k * p + j];
  }
  e = bsfit__tb_solve(n1, kd, 1, f->a11, p + 1, d, f->r2, N, st);
  if (e != BSFIT_OK) return e;
  for (k = 0; k < d; k++)
    for (i = 0; i < n1; i++) ctrl[i * d + k] = f->r2[k * N + i];
  if (rcond) {
    /* A11 is the Gram matrix of the periodic basis functions 0..N-p-1, none of which
    ** straddles the first knot U[0] (function j lives on [U_j, U_{j+p+1}], j+p+1 <= N):
    ** cut the circle there and they are ordinary B-splines, so A11 is totally nonnegative
    ** and its |A11^-1|_1 comes exactly from one solve (linalg.c) */
    double r1 = bsfit__pb_rcond_tn(n1, kd, f->a11, p + 1, anorm, f->work);
    double r2 = bsfit__po_rcond(p, f->s22, p, anorm, f->work, f->iwork);
    *rcond = r1 < r2 ? r1 : r2;
  }
  return BSFIT_OK;
}
