/*
** filter_distance.c
** How far apart two curves are, as a true distance between point sets: points sampled
** densely on each curve (per knot span) are projected onto the other one, and the
** largest foot distance either way is returned (the Hausdorff distance of the two
** curves, up to the sampling between samples). Two modes: the global closest point of
** curve_geom.c (coarse samples indexed by a k-d tree, then Newton), and a cheap local
** one for searches, Newton from the same parameter on the other curve, which can only
** overestimate the distance (a foot is never farther than its start), so a search that
** keeps the local measure under a tolerance keeps the true one under it too. The global
** mode takes, per sample, the nearer of the two feet: the closest-point search starts
** from the nearest coarse sample, which on a curve that comes back close to itself can
** lie on the wrong branch, while the curves compared here (a curve and its smoothing or
** reduction) correspond parameter by parameter.
*/
#include "filter_internal.h"

#include <math.h>
#include <string.h>

#define LOCAL_ITERS 2   /* Newton steps of the local mode (the start is close already) */
#define REFINE_ITERS 20 /* golden-section steps for the largest distance (1e-4 of 2 samples) */
#define REFINE_MAX 16    /* local maxima refined, at most ... */
#define REFINE_NEAR 0.5  /* ... among those within this fraction of the largest sample */
#define FEET_ROUNDS 4    /* FEET mode: rounds of REFINE_MAX checked maxima, at most */
#define FEET_SLACK 0.97  /* a sampled maximum this close to the largest checked is checked */

/* Number of samples on the domain spans of c, per_span per span plus the end. */
static size_t sample_count(const bsfit_curve *c, size_t per_span) {
  size_t nk = c->n + (size_t)c->degree + 1, i, spans = 0;
  double a, b;
  bsfit_curve_domain(c, &a, &b);
  for (i = 0; i + 1 < nk; i++)
    if (c->knots[i] >= a && c->knots[i + 1] <= b && c->knots[i + 1] > c->knots[i]) spans++;
  return spans * per_span + 1;
}

/* The sample parameters and points of c. */
static void sample(const bsfit_curve *c, size_t per_span, double *t, double *pts) {
  size_t nk = c->n + (size_t)c->degree + 1, i, j, m = 0, d = (size_t)c->dim;
  double a, b;
  bsfit_curve_domain(c, &a, &b);
  for (i = 0; i + 1 < nk; i++) {
    double x0 = c->knots[i], x1 = c->knots[i + 1];
    if (!(x0 >= a && x1 <= b && x1 > x0)) continue;
    for (j = 0; j < per_span; j++) t[m++] = x0 + (x1 - x0) * (double)j / (double)per_span;
  }
  t[m++] = b;
  for (i = 0; i < m; i++) bsfit__curve_eval_unchecked(c, t[i], pts + i * d);
}

size_t bsfit__break_span(const bsfit__breaks *br, double u) {
  size_t lo = 0, hi = br->n - 1;
  if (u <= br->x[0]) return 0;
  if (u >= br->x[br->n - 1]) return br->n - 2;
  while (hi - lo > 1) {
    size_t mid = (lo + hi) / 2;
    if (br->x[mid] <= u) lo = mid;
    else hi = mid;
  }
  return lo;
}

/* Distance from x(t) to y, by Newton on y from the foot u (updated) and from t itself
** (the curves compared correspond parameter by parameter); the nearer foot is kept. */
static double dist_from(const bsfit_curve *x, const bsfit_curve *y, double t, double *u,
                        const bsfit_allocator *al) {
  double P[4], d = INFINITY, d2 = INFINITY, v = t;
  bsfit__curve_eval_unchecked(x, t, P);
  if (bsfit_curve_project_many(y, P, 1, u, &d, 2 * LOCAL_ITERS, al, NULL) != BSFIT_OK) d = INFINITY;
  if (bsfit_curve_project_many(y, P, 1, &v, &d2, 2 * LOCAL_ITERS, al, NULL) == BSFIT_OK && d2 < d) {
    d = d2;
    *u = v;
  }
  return isfinite(d) ? d : 0.0;
}

/* The largest distance lies between samples in general: golden-section search for the
** maximum of the distance over the two sample intervals around the worst sample i, the
** foot followed by Newton from the sample's. */
static double refine_max(const bsfit_curve *x, const bsfit_curve *y, const double *t,
                         const double *u, size_t m, size_t i, double worst, int verify,
                         const bsfit_allocator *al) {
  const double g = 0.6180339887498949;
  double lo = t[i > 0 ? i - 1 : 0], hi = t[i + 1 < m ? i + 1 : m - 1], x1, x2, f1, f2;
  double u1 = u[i], u2 = u[i];
  int it;
  x1 = hi - g * (hi - lo);
  x2 = lo + g * (hi - lo);
  f1 = dist_from(x, y, x1, &u1, al);
  f2 = dist_from(x, y, x2, &u2, al);
  for (it = 0; it < REFINE_ITERS; it++) {
    if (f1 > f2) {
      hi = x2, x2 = x1, f2 = f1, u2 = u1;
      x1 = hi - g * (hi - lo);
      f1 = dist_from(x, y, x1, &u1, al);
    } else {
      lo = x1, x1 = x2, f1 = f2, u1 = u2;
      x2 = lo + g * (hi - lo);
      f2 = dist_from(x, y, x2, &u2, al);
    }
  }
  if (verify) {
    /* the search followed feet by Newton: for curves that need not correspond, the
    ** global closest point may be nearer */
    double tb = f1 > f2 ? x1 : x2, fb = fmax(f1, f2), P[4], ug, dg;
    bsfit__curve_eval_unchecked(x, tb, P);
    if (bsfit_curve_closest(y, P, &ug, &dg, al, NULL) == BSFIT_OK && dg < fb) fb = dg;
    return fmax(worst, fb);
  }
  return fmax(worst, fmax(f1, f2));
}

/* The (at most REFINE_MAX) largest local maxima of dist[0..m-1] at or above floor, into
** top (insertion into a short sorted list: O(m REFINE_MAX) at worst, no allocation). */
static int largest_maxima(const double *dist, size_t m, double floor, size_t *top) {
  size_t i;
  int n = 0, k;
  for (i = 0; i < m; i++) {
    if (dist[i] < floor || (i > 0 && dist[i - 1] > dist[i]) || (i + 1 < m && dist[i + 1] > dist[i]))
      continue;
    if (n == REFINE_MAX && dist[i] <= dist[top[n - 1]]) continue;
    k = n < REFINE_MAX ? n++ : n - 1;
    for (; k > 0 && dist[top[k - 1]] < dist[i]; k--) top[k] = top[k - 1];
    top[k] = i;
  }
  return n;
}

/* The distance from x(ti) to y: the local foot's d, or the global closest point's if nearer. */
static double checked_sample(const bsfit_curve *x, const bsfit_curve *y, double ti, double d,
                             const bsfit_allocator *al) {
  double P[4], ug, dg;
  bsfit__curve_eval_unchecked(x, ti, P);
  if (bsfit_curve_closest(y, P, &ug, &dg, al, NULL) == BSFIT_OK && dg < d) return dg;
  return d;
}

/* FEET mode: the local feet only bound each sample's distance from above (near a corner
** the foot from the same parameter can stop on the wrong side), so the sampled maxima are
** refined and checked by a global closest point, largest first, until the next one's
** sampled value cannot reach what the checked ones give (FEET_SLACK: the rise between
** samples). dist is consumed. */
static void feet_maxima(const bsfit_curve *x, const bsfit_curve *y, const double *t,
                        const double *u, double *dist, size_t m, const bsfit_allocator *al,
                        double *worst) {
  size_t top[REFINE_MAX];
  double found = 0.0;
  int round, k, n = 0;
  for (round = 0; round < FEET_ROUNDS; round++) {
    n = largest_maxima(dist, m, FEET_SLACK * found, top);
    for (k = 0; k < n && dist[top[k]] >= FEET_SLACK * found; k++) {
      found = fmax(found, checked_sample(x, y, t[top[k]], dist[top[k]], al));
      found = refine_max(x, y, t, u, m, top[k], found, 1, al);
    }
    if (k < n || n < REFINE_MAX) break;
    for (k = 0; k < n; k++) dist[top[k]] = -1.0;
  }
  if (round == FEET_ROUNDS) /* what is left unchecked still bounds from above */
    for (k = 0; (size_t)k < m; k++) found = fmax(found, dist[k]);
  *worst = fmax(*worst, found);
}

/* One direction: samples of x projected onto y. Where `on_y` the span attribution uses
** the feet on y, else the samples' parameters on x. */
static bsfit_err one_way(const bsfit_curve *x, const bsfit_curve *y, size_t per_span,
                         int mode, const bsfit__breaks *br, double *span_max, int on_y,
                         const bsfit_allocator *al, double *worst, bsfit_status *st) {
  size_t m = sample_count(x, per_span), d = (size_t)x->dim, i, imax = 0;
  size_t bytes = bsfit__mulsize(m, (5 + d) * sizeof(double));
  double *t = bsfit__alloc(al, bytes), *u, *dist, *pts, *ug, *dg;
  bsfit_err e;
  if (t == NULL) return bsfit__fail(st, BSFIT_ENOMEM, "out of memory for %zu samples", m);
  u = t + m;
  dist = u + m;
  ug = dist + m;
  dg = ug + m;
  pts = dg + m;
  sample(x, per_span, t, pts);
  memcpy(u, t, m * sizeof(double));
  e = bsfit_curve_project_many(y, pts, m, u, dist, LOCAL_ITERS, al, st);
  if (e == BSFIT_OK && (mode == BSFIT__DIST_CORRESPONDING || mode == BSFIT__DIST_VERIFIED)) {
    e = bsfit_curve_closest_many(y, pts, m, ug, dg, al, st);
    for (i = 0; e == BSFIT_OK && i < m; i++)
      if (dg[i] < dist[i]) dist[i] = dg[i], u[i] = ug[i];
  }
  for (i = 0; e == BSFIT_OK && i < m; i++) {
    if (dist[i] > dist[imax]) imax = i;
    if (dist[i] > *worst && mode != BSFIT__DIST_FEET) *worst = dist[i];
    if (span_max != NULL) {
      size_t s = bsfit__break_span(br, on_y ? u[i] : t[i]);
      if (dist[i] > span_max[s]) span_max[s] = dist[i];
    }
  }
  if (e == BSFIT_OK && mode == BSFIT__DIST_FEET) {
    feet_maxima(x, y, t, u, dist, m, al, worst);
  } else if (e == BSFIT_OK && mode != BSFIT__DIST_LOCAL) {
    size_t top[REFINE_MAX];
    int k, n = largest_maxima(dist, m, REFINE_NEAR * dist[imax], top);
    for (k = 0; k < n; k++)
      *worst = refine_max(x, y, t, u, m, top[k], *worst, mode == BSFIT__DIST_VERIFIED, al);
  }
  bsfit__free(al, t, bytes);
  return e;
}

bsfit_err bsfit__curve_distance(const bsfit_curve *s, const bsfit_curve *c, size_t per_span,
                                int mode, const bsfit__breaks *br, double *span_max,
                                const bsfit_allocator *al, double *out, bsfit_status *st) {
  double worst = 0.0;
  bsfit_err e;
  if (span_max != NULL) memset(span_max, 0, (br->n - 1) * sizeof(double));
  e = one_way(s, c, per_span, mode, br, span_max, 0, al, &worst, st);
  if (e == BSFIT_OK) e = one_way(c, s, per_span, mode, br, span_max, 1, al, &worst, st);
  if (e != BSFIT_OK) return e;
  *out = worst;
  return BSFIT_OK;
}

bsfit_err bsfit_curve_distance(const bsfit_curve *a, const bsfit_curve *b, size_t per_span,
                               double *out, bsfit_status *st) {
  bsfit_allocator al;
  bsfit_err e;
  if (a == NULL || b == NULL || out == NULL)
    return bsfit__fail(st, BSFIT_EINVAL, "curve or output is NULL");
  e = bsfit_curve_validate(a, st);
  if (e == BSFIT_OK) e = bsfit_curve_validate(b, st);
  if (e != BSFIT_OK) return e;
  if (a->dim != b->dim)
    return bsfit__fail(st, BSFIT_EDIM, "curves of dimensions %d and %d", a->dim, b->dim);
  if (per_span < 1) return bsfit__fail(st, BSFIT_EINVAL, "samples per span must be >= 1");
  al = a->alloc;
  e = bsfit__curve_distance(a, b, per_span, BSFIT__DIST_VERIFIED, NULL, NULL, &al, out, st);
  return e == BSFIT_OK ? bsfit__ok(st) : e;
}
