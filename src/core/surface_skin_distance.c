/*
** surface_skin_distance.c
** How far a section is from the cubic that replaces it in a tolerance skin: the Hausdorff
** distance between the two closed curves (both on [0, 1)), measured as distances, not at
** equal parameters (a section of an exact mesh loop has a C0 knot at every facet, and its
** parametrisation jumps between them: at equal parameters two curves a few micrometres
** apart were centimetres apart).
**   1. from the section to the cubic: the section's samples (every knot, where a mesh
**      loop's vertices stand, and points inside each span) projected onto the cubic by
**      Newton from their fitting parameters;
**   2. from the cubic to the section: the cubic at the same parameters and at 4 points per
**      span, each given its exact closest point on the section (bsfit_curve_closest_many);
**   3. each way, every local maximum of the sampled distance above half the largest is
**      refined by a golden-section search between its neighbours (the distance along a
**      curve is smooth between knots, so the peak is found to a small fraction of the gap):
**      the distance reported is the true one, not only a bound that passes.
** A projection never reports a foot farther than the true one is near, so a distance is
** never underestimated by more than the search's resolution.
*/
#include "skin_internal.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#define REFINE_ITERS 12 /* golden-section steps: the bracket shrinks to 0.3% */
#define PROJECT_ITERS 30 /* Newton steps of a projection */
#define CUBIC_SAMPLES 4 /* samples per span of the cubic, for the way back */

static const double GOLD = 0.38196601125010515; /* (3 - sqrt 5) / 2 */

/* One way: curve X at sorted parameters x[0..n-1] of [0, 1), with feet y on curve Y and
** distances d. */
typedef struct way {
  const bsfit_curve *X, *Y;
  const double *x;
  double *y, *d;
  size_t n;
} way;

/* y_j seen from y_i: within half a period of it (the feet of neighbours straddle the seam). */
static double near_foot(double yi, double yj) {
  if (yj - yi > 0.5) return yj - 1.0;
  if (yi - yj > 0.5) return yj + 1.0;
  return yj;
}

/* The starting foot for the parameter t in [x_l, x_r] (unwrapped around x_i): the feet
** of the three samples interpolated linearly. */
static double start_foot(const way *w, size_t i, double t) {
  size_t n = w->n, l = (i + n - 1) % n, r = (i + 1) % n;
  double xi = w->x[i], xl = w->x[l] - (l > i ? 1.0 : 0.0), xr = w->x[r] + (r < i ? 1.0 : 0.0);
  double yi = w->y[i], yl = near_foot(yi, w->y[l]), yr = near_foot(yi, w->y[r]);
  if (t <= xi) return xi > xl ? yi + (yl - yi) * (xi - t) / (xi - xl) : yi;
  return xr > xi ? yi + (yr - yi) * (t - xi) / (xr - xi) : yi;
}

/* A local maximum's bracket [lo, hi], its inner points x1 < x2 and their distances; `fresh`
** says which inner point is new (1, 2; 3: both). */
typedef struct bracket {
  size_t i;
  double lo, hi, x1, x2, g1, g2;
  int fresh;
} bracket;

/* The distances of X at the brackets' new inner points to Y, each projected from its
** interpolated foot: one batch for all the brackets. P, u, g: scratch of 6 nb, 2 nb, 2 nb. */
static bsfit_err measure(const way *w, bracket *B, size_t nb, double *P, double *u, double *g,
                         const bsfit_allocator *a, bsfit_status *st) {
  size_t j, k = 0;
  bsfit_err e;
  for (j = 0; j < nb; j++) {
    int s;
    for (s = 1; s <= 2; s++) {
      double t = s == 1 ? B[j].x1 : B[j].x2;
      if (!(B[j].fresh & s)) continue;
      bsfit__curve_eval_unchecked(w->X, bsfit__curve_wrap(w->X, t), P + 3 * k);
      u[k++] = bsfit__curve_wrap(w->Y, start_foot(w, B[j].i, t));
    }
  }
  e = bsfit_curve_project_many(w->Y, P, k, u, g, PROJECT_ITERS, a, st);
  for (j = 0, k = 0; e == BSFIT_OK && j < nb; j++) {
    if (B[j].fresh & 1) B[j].g1 = g[k++];
    if (B[j].fresh & 2) B[j].g2 = g[k++];
  }
  return e;
}

/* The brackets of the local maxima above `floor`, into B (room for n); returns their count. */
static size_t local_maxima(const way *w, double floor, bracket *B) {
  size_t i, n = w->n, nb = 0;
  for (i = 0; i < n; i++) {
    size_t l = (i + n - 1) % n, r = (i + 1) % n;
    if (!(w->d[i] > floor) || w->d[i] < w->d[l] || w->d[i] < w->d[r]) continue;
    B[nb].i = i;
    B[nb].lo = w->x[l] - (l > i ? 1.0 : 0.0);
    B[nb].hi = w->x[r] + (r < i ? 1.0 : 0.0);
    B[nb].x1 = B[nb].lo + GOLD * (B[nb].hi - B[nb].lo);
    B[nb].x2 = B[nb].hi - GOLD * (B[nb].hi - B[nb].lo);
    B[nb].fresh = 3;
    nb++;
  }
  return nb;
}

/* One golden-section step of bracket b (maximising): the side of the smaller inner point
** is dropped, and one new inner point placed. */
static void golden_step(bracket *b) {
  if (b->g1 >= b->g2) {
    b->hi = b->x2, b->x2 = b->x1, b->g2 = b->g1;
    b->x1 = b->lo + GOLD * (b->hi - b->lo), b->fresh = 1;
  } else {
    b->lo = b->x1, b->x1 = b->x2, b->g1 = b->g2;
    b->x2 = b->hi - GOLD * (b->hi - b->lo), b->fresh = 2;
  }
}

#define RECHECK_PASSES 4

/* Samples farther than half the tolerance projected again, from their neighbours' feet:
** a projection (Newton from the sample's own parameter) can stop in a valley next to the
** true foot, where the neighbours' are. The nearer foot is kept: each is a point of Y, so
** a distance only comes down to a true one. The way back needs none: its feet are global
** closest points (bsfit_curve_closest_many, also next to the sliver spans that auto leaves
** between two C0 knots, which stopped the old sample-bracketed search at the corner). */
static bsfit_err recheck(way *w, double tol, const bsfit_allocator *a, bsfit_status *st) {
  size_t n = w->n, j, k, pass, bytes = n * (sizeof(size_t) + 10 * sizeof(double));
  size_t *idx = bsfit__alloc(a, bytes);
  double *P, *u, *g;
  int changed = 1;
  bsfit_err e = BSFIT_OK;
  if (idx == NULL) return bsfit__fail(st, BSFIT_ENOMEM, "out of memory for %zu samples", n);
  P = (double *)(idx + n), u = P + 6 * n, g = u + 2 * n;
  for (pass = 0; pass < RECHECK_PASSES && changed && e == BSFIT_OK; pass++) {
    size_t nk = 0;
    for (j = 0; j < n; j++) {
      if (!(w->d[j] > 0.5 * tol)) continue;
      idx[nk] = j;
      bsfit__curve_eval_unchecked(w->X, w->x[j], P + 6 * nk);
      memcpy(P + 6 * nk + 3, P + 6 * nk, 3 * sizeof(double));
      u[2 * nk] = w->y[(j + n - 1) % n];
      u[2 * nk + 1] = w->y[(j + 1) % n];
      nk++;
    }
    e = bsfit_curve_project_many(w->Y, P, 2 * nk, u, g, PROJECT_ITERS, a, st);
    for (k = 0, changed = 0; e == BSFIT_OK && k < 2 * nk; k++)
      if (g[k] < w->d[idx[k / 2]]) w->d[idx[k / 2]] = g[k], w->y[idx[k / 2]] = u[k], changed = 1;
  }
  bsfit__free(a, idx, bytes);
  return e;
}

/* The largest distance along the way (*worst): the samples', and the peaks' refined where
** the samples pass. `global`: the feet are global closest points already (no recheck). */
static bsfit_err refine(way *w, double tol, int global, double *worst,
                        const bsfit_allocator *a, bsfit_status *st) {
  size_t n = w->n, nb, j, it, bytes = n * (sizeof(bracket) + 10 * sizeof(double));
  bracket *B;
  double *P;
  bsfit_err e = global ? BSFIT_OK : recheck(w, tol, a, st);
  if (e != BSFIT_OK) return e;
  for (j = 0, *worst = 0; j < n; j++) *worst = fmax(*worst, w->d[j]);
  if (*worst > tol) return BSFIT_OK; /* it fails already */
  B = bsfit__alloc(a, bytes);
  if (B == NULL) return bsfit__fail(st, BSFIT_ENOMEM, "out of memory for %zu samples", n);
  P = (double *)(B + n);
  nb = local_maxima(w, 0.5 * *worst, B); /* the peaks near the largest: the true maximum */
  e = measure(w, B, nb, P, P + 6 * n, P + 8 * n, a, st);
  for (it = 0; e == BSFIT_OK && it < REFINE_ITERS; it++) {
    for (j = 0; j < nb; j++) golden_step(&B[j]);
    e = measure(w, B, nb, P, P + 6 * n, P + 8 * n, a, st);
  }
  for (j = 0; e == BSFIT_OK && j < nb; j++) *worst = fmax(*worst, fmax(B[j].g1, B[j].g2));
  bsfit__free(a, B, bytes);
  return e;
}

static int cmp_double(const void *x, const void *y) {
  double a = *(const double *)x, b = *(const double *)y;
  return (a > b) - (a < b);
}

/* The parameters of f sampled on the way back: s (sorted) merged with CUBIC_SAMPLES inside
** each span of f, sorted, repeats dropped, into x; returns their count. */
static size_t cubic_params(const bsfit_curve *f, const double *s, size_t m, double *x) {
  size_t p = (size_t)f->degree, N = f->n - p, i, j, n = m;
  memcpy(x, s, m * sizeof(double));
  for (i = 0; i < N; i++) {
    double lo = f->knots[p + i], hi = f->knots[p + i + 1];
    for (j = 0; hi > lo && j < CUBIC_SAMPLES; j++)
      x[n++] = lo + (hi - lo) * ((double)j + 0.5) / CUBIC_SAMPLES;
  }
  qsort(x, n, sizeof(double), cmp_double);
  for (i = 0, j = 0; i < n; i++)
    if (j == 0 || x[i] != x[j - 1]) x[j++] = x[i];
  return j;
}

/* The way back, from the cubic f to the section c: its points at s and inside its spans. */
static bsfit_err way_back(const bsfit_curve *c, const bsfit_curve *f, const double *s, size_t m,
                          double tol, double *dev, const bsfit_allocator *a, bsfit_status *st) {
  size_t n = m + CUBIC_SAMPLES * (f->n - (size_t)f->degree), i;
  size_t bytes = bsfit__mulsize(n, 6 * sizeof(double));
  double *x = bytes ? bsfit__alloc(a, bytes) : NULL, *P, *y, *d;
  way w;
  bsfit_err e;
  if (x == NULL) return bsfit__fail(st, BSFIT_ENOMEM, "out of memory for %zu samples", n);
  P = x + n, y = P + 3 * n, d = y + n;
  n = cubic_params(f, s, m, x);
  for (i = 0; i < n; i++) bsfit__curve_eval_unchecked(f, x[i], P + 3 * i);
  e = bsfit_curve_closest_many(c, P, n, y, d, a, st);
  w.X = f, w.Y = c, w.x = x, w.y = y, w.d = d, w.n = n;
  if (e == BSFIT_OK) e = refine(&w, tol, 1, dev, a, st);
  bsfit__free(a, x, bytes);
  return e;
}

bsfit_err bsfit__skin_distance(const bsfit_curve *c, const bsfit_curve *f, const double *t,
                               const double *s, const double *pts, size_t m, double tol,
                               double *dev, const bsfit_allocator *a, bsfit_status *st) {
  size_t bytes = bsfit__mulsize(m, 2 * sizeof(double));
  double *y = bytes ? bsfit__alloc(a, bytes) : NULL, *d, back = 0;
  way w;
  bsfit_err e;
  *dev = HUGE_VAL;
  if (y == NULL) return bsfit__fail(st, BSFIT_ENOMEM, "out of memory for %zu samples", m);
  d = y + m;
  memcpy(y, s, m * sizeof(double));
  e = bsfit_curve_project_many(f, pts, m, y, d, PROJECT_ITERS, a, st);
  w.X = c, w.Y = f, w.x = t, w.y = y, w.d = d, w.n = m;
  if (e == BSFIT_OK) e = refine(&w, tol, 0, dev, a, st);
  if (e == BSFIT_OK && *dev <= tol) e = way_back(c, f, s, m, tol, &back, a, st);
  *dev = fmax(*dev, back);
  bsfit__free(a, y, bytes);
  return e;
}
