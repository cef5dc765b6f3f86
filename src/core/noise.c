/*
** noise.c
** Noise level of an ordered point sequence, from the data alone: local polynomial fits
** in a moving frame, each point predicted from its neighbours (leave-one-out) by the
** window that follows them best, a median-based scale refined by a trimmed mean of
** squares (see bsfit_analysis.h).
*/
#include "internal.h"

#include <math.h>
#include <string.h>

#define NCOEF_MAX BSFIT__SMALL /* quartic */

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

/* A window of a point k: the samples k + lo .. k + hi (lo <= 0 <= hi), fitted by a
** polynomial of the given degree. */
typedef struct window_kind {
  int lo, hi, degree;
} window_kind;

/* The windows tried for each point, in order of preference: centred ones predict the
** point by interpolation (the long one with more degrees of freedom, the short one
** where a sparse contour bends too fast for the long one), one-sided ones predict a
** point next to a corner from its own side only. */
static const window_kind kinds[] = {{-4, 4, 3}, {-3, 3, 4}, {-2, 2, 2}, {-8, 0, 3}, {0, 8, 3},
                                     {-5, 0, 2}, {0, 5, 2}};
#define NKINDS 7
#define NCENTRED 3
/* how far a window's misfit (its RSS per degree of freedom over sigma^2) may go and
** still be taken as noise alone: about the 95% point of chi^2 with its degrees of
** freedom (4, 1, 1, 4, 4, 2, 2) over them */
static const double misfit_ok[NKINDS] = {2.4, 3.8, 3.8, 2.4, 2.4, 3.0, 3.0};

/* The prediction of point k from the other samples of window w: its squared error
** (summed over the normal components) over its variance factor (1 + leverage of the
** prediction), so that it is sigma^2 (times the number of normal components) on
** average; and the fit's residual sum of squares per degree of freedom (the window's
** own misfit: noise, plus bias where the polynomial cannot follow the shape). Both are
** returned as their square roots, z and mf, in the data's units: the window is worked
** in differences scaled by a power of two 2^ex near its extent (exact), so that no
** square underflows for data of 1e-170 nor overflows. 0 when the window is degenerate
** or does not fit in open data. */
static int predict(const double *pts, size_t m, int dim, int closed, size_t k,
                   const window_kind *w, double *z, double *mf) {
  int ncoef = w->degree + 1, ny = dim == 2 ? 1 : 3, a, b, d, j, n = w->hi - w->lo;
  const double *Q = pts + k * (size_t)dim, *F, *L;
  double t[3] = {0, 0, 0}, nv[3] = {0, 0, 0}, tn = 0, scale = 0, A[NCOEF_MAX][NCOEF_MAX];
  double rhs[3][NCOEF_MAX], x0[NCOEF_MAX] = {1, 0, 0, 0, 0}, syy = 0, rss, lev, pred2 = 0;
  double s[17], y[17][3], big = 0.0;
  size_t first, idx;
  int ex;
  if (!closed && ((long)k + w->lo < 0 || (long)k + w->hi >= (long)m)) return 0;
  if ((size_t)(n + 1) > m || n + 1 > 17) return 0;
  first = (size_t)(((long)k + w->lo) % (long)m + (long)m) % m;
  F = pts + first * (size_t)dim;
  L = pts + ((first + (size_t)n) % m) * (size_t)dim;
  for (j = 0, idx = first; j <= n; j++) {
    for (d = 0; d < dim; d++) big = fmax(big, fabs(pts[idx * (size_t)dim + (size_t)d] - Q[d]));
    if (++idx == m) idx = 0;
  }
  if (!(big > 0)) return 0;
  (void)frexp(big, &ex);
  for (d = 0; d < dim; d++) {
    t[d] = ldexp(L[d] - F[d], -ex);
    tn += t[d] * t[d];
  }
  if (!(tn > 0)) return 0;
  tn = sqrt(tn);
  for (d = 0; d < dim; d++) t[d] /= tn;
  nv[0] = -t[1], nv[1] = t[0]; /* 2D: the signed normal coordinate */
  /* the window in the frame of its chord, origin at Q_k: s along, y across */
  for (j = 0, idx = first; j <= n; j++) {
    const double *P = pts + idx * (size_t)dim;
    double sj = 0, D[3] = {0, 0, 0};
    for (d = 0; d < dim; d++) D[d] = ldexp(P[d] - Q[d], -ex);
    for (d = 0; d < dim; d++) sj += D[d] * t[d];
    s[j] = sj;
    if (fabs(sj) > scale) scale = fabs(sj);
    if (dim == 2) y[j][0] = D[0] * nv[0] + D[1] * nv[1];
    else
      for (d = 0; d < 3; d++) y[j][d] = D[d] - sj * t[d];
    if (++idx == m) idx = 0;
  }
  if (!(scale > 0)) return 0;
  memset(A, 0, sizeof A);
  memset(rhs, 0, sizeof rhs);
  for (j = 0; j <= n; j++) {
    double x[NCOEF_MAX];
    if (j == -w->lo) continue; /* leave k out */
    x[0] = 1.0;
    for (a = 1; a < ncoef; a++) x[a] = x[a - 1] * s[j] / scale;
    for (a = 0; a < ncoef; a++) {
      for (b = 0; b <= a; b++) A[a][b] += x[a] * x[b];
      for (d = 0; d < ny; d++) rhs[d][a] += x[a] * y[j][d];
    }
    for (d = 0; d < ny; d++) syy += y[j][d] * y[j][d];
  }
  for (a = 0; a < ncoef; a++)
    for (b = a + 1; b < ncoef; b++) A[a][b] = A[b][a];
  if (!bsfit__small_cholesky(ncoef, A)) return 0;
  bsfit__small_chol_solve(ncoef, (const double(*)[BSFIT__SMALL])A, x0); /* x0[0] = (A^-1)_00: the prediction's variance factor at s = 0 */
  lev = x0[0];
  rss = syy;
  for (d = 0; d < ny; d++) {
    double c[NCOEF_MAX];
    memcpy(c, rhs[d], sizeof c);
    bsfit__small_chol_solve(ncoef, (const double(*)[BSFIT__SMALL])A, c);
    for (a = 0; a < ncoef; a++) rss -= c[a] * rhs[d][a];
    pred2 += c[0] * c[0]; /* the fit at s = 0 minus the point itself (at the origin) */
  }
  *z = ldexp(sqrt(pred2 / (1.0 + lev)), ex);
  *mf = ldexp(sqrt(fmax(rss, 0.0) / (double)((n - ncoef) * (dim - 1))), ex);
  return 1;
}

/* Robust scale of the n standardised errors r (reordered): the 40% quantile (corners
** and outliers inflate the upper errors; of |N(0,1)| it is 0.52440, Phi^-1(0.7); of a
** chi with 2 degrees of freedom sqrt(-2 ln 0.6) = 1.01077), then the mean square of
** the errors below a cut, far less noisy than a quantile: below 2.5 s0 in 2D (the
** mean square of |N(0,1)| below 2.5 is 0.91126), below 3 s0 in 3D (of a chi-2 below
** 3: 1.89890). */
static double robust_scale(double *r, size_t n, int dim) {
  double s0, cut, sum = 0;
  size_t k, nt = 0;
  if (n == 0) return 0.0;
  s0 = bsfit__select(r, n, (size_t)(0.4 * (double)(n - 1) + 0.5)) /
       (dim == 2 ? 0.5244005127080407 : 1.0107676525947897);
  if (!(s0 > 0)) return 0.0;
  cut = (dim == 2 ? 2.5 : 3.0) * s0;
  for (k = 0; k < n; k++) /* squares relative to s0: no underflow for tiny data */
    if (r[k] <= cut) sum += (r[k] / s0) * (r[k] / s0), nt++;
  return nt > 0 ? s0 * sqrt(sum / (double)nt / (dim == 2 ? 0.9112593 : 1.8989008)) : s0;
}

bsfit_err bsfit_noise_sigma(const double *pts, size_t m, int dim, int closed, double *sigma,
                            const bsfit_allocator *a, bsfit_status *st) {
  size_t k, i, n, stride = m >= 600 ? 3 : 1;
  double *r, pilot = INFINITY, z, f;
  size_t bytes = 2 * m * sizeof(double);
  if (dim != 2 && dim != 3) return bsfit__fail(st, BSFIT_EDIM, "noise estimate needs 2D or 3D points, got dim %d", dim);
  if (pts == NULL || m < 6) return bsfit__fail(st, BSFIT_ETOOFEW, "noise estimate needs at least 6 points, got %zu", m);
  if (!bsfit__all_finite(pts, m * (size_t)dim))
    return bsfit__fail(st, BSFIT_ENONFINITE, "points contain NaN or Inf");
  r = bsfit__alloc(a, bytes);
  if (r == NULL) return bsfit__fail(st, BSFIT_ENOMEM, "out of memory for %zu residuals", m);
  /* A pilot scale from the centred windows alone (on every third point of a long
  ** section: a pilot needs no more): the smallest of theirs (the long one's is biased
  ** up where a sparse contour bends fast). */
  for (i = 0; i < NCENTRED; i++) {
    for (n = 0, k = 0; k < m; k += stride)
      if (predict(pts, m, dim, closed, k, &kinds[i], &z, &f)) r[n++] = z;
    if (n > 0) pilot = fmin(pilot, robust_scale(r, n, dim));
  }
  if (!(pilot < INFINITY)) {
    bsfit__free(a, r, bytes);
    return bsfit__fail(st, BSFIT_EDEGENERATE, "no window of distinct points to estimate the noise");
  }
  /* Each point's error from the first centred window (in order of preference) whose
  ** fit of the other samples is as good as the noise allows: the point takes no part
  ** in the choice, so the choice does not favour small errors, and most points stop
  ** at the first window. Failing them all (a corner nearby), the one-sided windows
  ** that fit: the point may lie past the corner, beyond the reach of the side a window
  ** stands on, which its fit cannot tell; the smallest of their errors is taken (a
  ** bias towards small errors, on these few points only). Failing all, the best
  ** fitting window. */
  for (n = 0, k = 0; k < m; k++) {
    double best = INFINITY, pick = -1.0, side = INFINITY;
    if ((k & 4095) == 4095 && bsfit__interrupted(a)) {
      bsfit__free(a, r, bytes);
      return bsfit__fail(st, BSFIT_EINTR, "noise estimate interrupted");
    }
    for (i = 0; i < NKINDS; i++) {
      if (!predict(pts, m, dim, closed, k, &kinds[i], &z, &f)) continue;
      /* misfit <= ok sigma^2, compared as square roots (f is one) */
      if (f <= sqrt(misfit_ok[i]) * pilot) {
        if (i < NCENTRED) { pick = z; side = -1.0; break; }
        if (z < side) side = z;
      } else if (f < best) {
        best = f, pick = z;
      }
    }
    if (side >= 0 && side < INFINITY) pick = side;
    if (pick >= 0) r[n++] = pick;
  }
  *sigma = robust_scale(r, n, dim);
  bsfit__free(a, r, bytes);
  return bsfit__ok(st);
}
