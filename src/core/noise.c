/*
** noise.c
** Noise level of an ordered point sequence, from the data alone: local cubic fits in a
** moving frame, leverage-corrected residuals, a median-based scale (see bsfit_analysis.h).
*/
#include "internal.h"

#include <math.h>
#include <string.h>

#define NOISE_HALF_WINDOW 4
#define NOISE_NCOEF 4 /* cubic */

/* k-th smallest of x[0..n-1] (Wirth's selection; reorders x so that x[i] <= x[k]
** for i < k and x[i] >= x[k] for i > k) */
double bsfit__select(double *x, size_t n, size_t k) {
  long lo = 0, hi = (long)n - 1, kk = (long)k;
  while (lo < hi) {
    double pivot = x[kk];
    long i = lo, j = hi;
    do {
      while (x[i] < pivot) i++;
      while (pivot < x[j]) j--;
      if (i <= j) {
        double t = x[i];
        x[i] = x[j];
        x[j] = t;
        i++;
        j--;
      }
    } while (i <= j);
    if (j < kk) lo = i;
    if (kk < i) hi = j;
  }
  return x[kk];
}

/* Cholesky of the 4x4 SPD matrix A in place (lower); 0 if not numerically SPD */
static int cholesky4(double A[NOISE_NCOEF][NOISE_NCOEF]) {
  int i, j, k;
  double tr = A[0][0] + A[1][1] + A[2][2] + A[3][3];
  for (j = 0; j < NOISE_NCOEF; j++) {
    double d = A[j][j];
    for (k = 0; k < j; k++) d -= A[j][k] * A[j][k];
    if (!(d > 1e-13 * tr)) return 0;
    A[j][j] = sqrt(d);
    for (i = j + 1; i < NOISE_NCOEF; i++) {
      double s = A[i][j];
      for (k = 0; k < j; k++) s -= A[i][k] * A[j][k];
      A[i][j] = s / A[j][j];
    }
  }
  return 1;
}

/* solves L L^T x = b in place */
static void chol_solve4(double L[NOISE_NCOEF][NOISE_NCOEF], double *b) {
  int i, k;
  for (i = 0; i < NOISE_NCOEF; i++) {
    for (k = 0; k < i; k++) b[i] -= L[i][k] * b[k];
    b[i] /= L[i][i];
  }
  for (i = NOISE_NCOEF - 1; i >= 0; i--) {
    for (k = i + 1; k < NOISE_NCOEF; k++) b[i] -= L[k][i] * b[k];
    b[i] /= L[i][i];
  }
}

/* window [first, first + len) of point k (indices modulo m when closed) */
static size_t window_first(size_t k, size_t m, size_t h, int closed) {
  if (closed) return (k + m - h) % m;
  if (k < h) return 0;
  if (k + h >= m) return m - 1 - 2 * h;
  return k - h;
}

/* Standardised squared residual of point k (sum over the normal components), or a
** negative value when the window is degenerate. */
static double point_residual2(const double *pts, size_t m, int dim, int closed, size_t h,
                              size_t k) {
  size_t len = 2 * h + 1, first = window_first(k, m, h, closed), i, last;
  const double *Q = pts + k * (size_t)dim;
  double t[3] = {0, 0, 0}, tn = 0, scale = 0, A[NOISE_NCOEF][NOISE_NCOEF];
  double rhs[3][NOISE_NCOEF], unit[NOISE_NCOEF] = {1, 0, 0, 0}, r2 = 0, lev;
  int d, a, b;
  last = (first + len - 1) % m;
  for (d = 0; d < dim; d++) {
    t[d] = pts[last * (size_t)dim + d] - pts[first * (size_t)dim + d];
    tn += t[d] * t[d];
  }
  if (!(tn > 0)) return -1.0;
  tn = sqrt(tn);
  for (d = 0; d < dim; d++) t[d] /= tn;
  for (i = 0; i < len; i++) {
    const double *P = pts + ((first + i) % m) * (size_t)dim;
    double s = 0;
    for (d = 0; d < dim; d++) s += (P[d] - Q[d]) * t[d];
    if (fabs(s) > scale) scale = fabs(s);
  }
  if (!(scale > 0)) return -1.0;
  memset(A, 0, sizeof A);
  memset(rhs, 0, sizeof rhs);
  for (i = 0; i < len; i++) {
    const double *P = pts + ((first + i) % m) * (size_t)dim;
    double s = 0, x[NOISE_NCOEF];
    for (d = 0; d < dim; d++) s += (P[d] - Q[d]) * t[d];
    x[0] = 1.0;
    x[1] = s / scale;
    x[2] = x[1] * x[1];
    x[3] = x[2] * x[1];
    for (a = 0; a < NOISE_NCOEF; a++) {
      for (b = 0; b <= a; b++) A[a][b] += x[a] * x[b];
      for (d = 0; d < dim; d++) rhs[d][a] += x[a] * (P[d] - Q[d] - s * t[d]); /* normal part */
    }
  }
  for (a = 0; a < NOISE_NCOEF; a++)
    for (b = a + 1; b < NOISE_NCOEF; b++) A[a][b] = A[b][a];
  if (!cholesky4(A)) return -1.0;
  chol_solve4(A, unit); /* unit[0] = (A^-1)_00 = leverage of the centre (x = e_0) */
  lev = unit[0];
  if (!(lev < 1.0 - 1e-9)) return -1.0;
  for (d = 0; d < dim; d++) {
    chol_solve4(A, rhs[d]);
    r2 += rhs[d][0] * rhs[d][0]; /* the fit at s = 0 minus the point itself (0) */
  }
  return r2 / (1.0 - lev);
}

bsfit_err bsfit_noise_sigma(const double *pts, size_t m, int dim, int closed, double *sigma,
                            bsfit_status *st) {
  size_t h, k, nvalid = 0;
  double *r, med;
  if (dim != 2 && dim != 3) return bsfit__fail(st, BSFIT_EDIM, "noise estimate needs 2D or 3D points, got dim %d", dim);
  if (pts == NULL || m < 6) return bsfit__fail(st, BSFIT_ETOOFEW, "noise estimate needs at least 6 points, got %zu", m);
  if (!bsfit__all_finite(pts, m * (size_t)dim))
    return bsfit__fail(st, BSFIT_ENONFINITE, "points contain NaN or Inf");
  h = (m - 1) / 2 < NOISE_HALF_WINDOW ? (m - 1) / 2 : NOISE_HALF_WINDOW;
  r = bsfit__alloc(NULL, m * sizeof(double));
  if (r == NULL) return bsfit__fail(st, BSFIT_ENOMEM, "out of memory for %zu residuals", m);
  for (k = 0; k < m; k++) {
    double r2 = point_residual2(pts, m, dim, closed, h, k);
    if (r2 >= 0) r[nvalid++] = sqrt(r2);
  }
  if (nvalid == 0) {
    bsfit__free(NULL, r, m * sizeof(double));
    return bsfit__fail(st, BSFIT_EDEGENERATE, "no window of distinct points to estimate the noise");
  }
  /* The 40% quantile rather than the median: corners and outliers inflate the upper
  ** residuals, and a section with many corners can have a third of its windows on one. */
  med = bsfit__select(r, nvalid, (size_t)(0.4 * (double)(nvalid - 1) + 0.5));
  bsfit__free(NULL, r, m * sizeof(double));
  /* the 40% quantile of |N(0,1)| is 0.52440 (Phi^-1(0.7)); of a chi with 2 degrees of
  ** freedom sqrt(-2 ln 0.6) = 1.01077 */
  *sigma = med / (dim == 2 ? 0.5244005127080407 : 1.0107676525947897);
  return bsfit__ok(st);
}
