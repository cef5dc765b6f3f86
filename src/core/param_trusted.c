/*
** param_trusted.c
** Parameters computed over trusted points only (down-weighted outliers do not stretch
** their neighbours' chords), the others interpolated by index.
*/
#include "internal.h"

#include <math.h>
#include <string.h>

static bsfit_err check_weights(const double *w, size_t m, bsfit_status *st) {
  size_t i;
  for (i = 0; i < m; i++)
    if (!isfinite(w[i]) || !(w[i] > 0))
      return bsfit__fail(st, BSFIT_EWEIGHT, "weight %zu is %g (must be positive and finite)", i,
                         w[i]);
  return BSFIT_OK;
}

/* the trust cut: `trust` times the median weight (copy, selection) */
static bsfit_err trust_cut(const double *w, size_t m, double trust, double *cut,
                           const bsfit_allocator *a, bsfit_status *st) {
  double *tmp = bsfit__alloc(a, m * sizeof(double));
  if (tmp == NULL) return bsfit__fail(st, BSFIT_ENOMEM, "out of memory for %zu weights", m);
  memcpy(tmp, w, m * sizeof(double));
  *cut = trust * bsfit__select(tmp, m, m / 2);
  bsfit__free(a, tmp, m * sizeof(double));
  return BSFIT_OK;
}

bsfit_err bsfit_untrusted(const double *w, size_t m, double trust, size_t *out, size_t *n_out,
                          const bsfit_allocator *a, bsfit_status *st) {
  size_t i, n = 0;
  double lo = HUGE_VAL, hi = 0, cut = 0;
  bsfit_err e;
  if (n_out != NULL) *n_out = 0;
  if (!(trust >= 0 && trust < 1))
    return bsfit__fail(st, BSFIT_EINVAL, "trust %g must be in [0, 1)", trust);
  if ((w == NULL && m > 0) || n_out == NULL || (out == NULL && m > 0))
    return bsfit__fail(st, BSFIT_EINVAL, "NULL weights or output");
  if ((e = check_weights(w, m, st)) != BSFIT_OK) return e;
  for (i = 0; i < m; i++) {
    if (w[i] < lo) lo = w[i];
    if (w[i] > hi) hi = w[i];
  }
  /* every weight >= trust x max >= trust x median: no selection needed (equal weights) */
  if (m == 0 || trust == 0 || !(trust * hi > lo)) return bsfit__ok(st);
  if ((e = trust_cut(w, m, trust, &cut, a, st)) != BSFIT_OK) return e;
  for (i = 0; i < m; i++)
    if (w[i] < cut) out[n++] = i;
  *n_out = n;
  return bsfit__ok(st);
}

/* untrusted points between trusted indices a and b (walking forward, b after a
** modulo m) get parameters interpolated from ua to ub */
static void fill_gap(double *u, size_t m, size_t a, size_t b, double ua, double ub) {
  size_t gap = (b + m - a) % m, j;
  for (j = 1; j < gap; j++) u[(a + j) % m] = ua + (ub - ua) * (double)j / (double)gap;
}

bsfit_err bsfit_params_trusted(const double *pts, size_t m, int dim, bsfit_param_kind kind,
                               int closed, const double *w, double trust, double *u,
                               const bsfit_allocator *a, bsfit_status *st) {
  size_t i, nt = 0, *idx = NULL, first, prev;
  double cut = 0, *sub = NULL, *su = NULL, shift;
  bsfit_err e;
  if (!(trust >= 0 && trust < 1))
    return bsfit__fail(st, BSFIT_EINVAL, "trust %g must be in [0, 1)", trust);
  if (w == NULL || trust == 0) {
    if (w != NULL && (e = check_weights(w, m, st)) != BSFIT_OK) return e;
    return bsfit_params(pts, m, dim, kind, closed, u, st);
  }
  if (pts == NULL || u == NULL) return bsfit__fail(st, BSFIT_EINVAL, "NULL points or parameters");
  if ((e = check_weights(w, m, st)) != BSFIT_OK) return e;
  if ((e = trust_cut(w, m, trust, &cut, a, st)) != BSFIT_OK) return e;
  idx = bsfit__alloc(a, m * sizeof(size_t));
  sub = bsfit__alloc(a, m * (size_t)dim * sizeof(double));
  su = bsfit__alloc(a, m * sizeof(double));
  if (idx == NULL || sub == NULL || su == NULL) {
    e = bsfit__fail(st, BSFIT_ENOMEM, "out of memory for %zu points", m);
    goto done;
  }
  for (i = 0; i < m; i++)
    if (w[i] >= cut) {
      memcpy(sub + nt * (size_t)dim, pts + i * (size_t)dim, (size_t)dim * sizeof(double));
      idx[nt++] = i;
    }
  if (nt < 2) {
    e = bsfit__fail(st, BSFIT_EDEGENERATE, "only %zu trusted point(s) (weight >= %g)", nt, cut);
    goto done;
  }
  if ((e = bsfit_params(sub, nt, dim, kind, closed, su, st)) != BSFIT_OK) goto done;
  for (i = 0; i < nt; i++) u[idx[i]] = su[i];
  first = idx[0];
  prev = first;
  for (i = 1; i < nt; i++) {
    fill_gap(u, m, prev, idx[i], su[i - 1], su[i]);
    prev = idx[i];
  }
  if (closed) {
    /* the gap across the end, then shift so that u[0] = 0 and u increases with i */
    fill_gap(u, m, prev, first, su[nt - 1], 1.0);
    shift = u[0];
    for (i = 0; i < m; i++) {
      double v = u[i] - shift;
      u[i] = v < 0 ? v + 1.0 : v;
      if (u[i] >= 1.0) u[i] = nextafter(1.0, 0.0);
    }
  } else {
    /* untrusted ends of open data take the end parameters */
    for (i = 0; i < first; i++) u[i] = 0.0;
    for (i = idx[nt - 1] + 1; i < m; i++) u[i] = 1.0;
  }
  e = bsfit__ok(st);
done:
  bsfit__free(a, idx, m * sizeof(size_t));
  bsfit__free(a, sub, m * (size_t)dim * sizeof(double));
  bsfit__free(a, su, m * sizeof(double));
  return e;
}

/* the parameter measure of a length: the chord itself, or its square root */
static double measure(bsfit_param_kind kind, double len) {
  return kind == BSFIT_PARAM_CENTRIPETAL ? sqrt(len) : len;
}

static double dist_between(const double *a, const double *b, int dim) {
  double s = 0;
  int d;
  for (d = 0; d < dim; d++) s += (a[d] - b[d]) * (a[d] - b[d]);
  return sqrt(s);
}

bsfit_err bsfit_params_through_corners(const double *pts, size_t m, int dim,
                                       bsfit_param_kind kind, int closed,
                                       const bsfit_corner *corners, size_t nc, double *u,
                                       bsfit_status *st) {
  size_t c, i, next = 0;
  double added = 0, total;
  if (kind != BSFIT_PARAM_UNIFORM && kind != BSFIT_PARAM_CHORD && kind != BSFIT_PARAM_CENTRIPETAL)
    return bsfit__fail(st, BSFIT_EINVAL, "unknown parameter kind %d", (int)kind);
  for (c = 0; c < nc; c++)
    if (!(corners[c].position >= 0 && corners[c].position < (double)m) ||
        (c > 0 && !(corners[c].position > corners[c - 1].position)))
      return bsfit__fail(st, BSFIT_EINVAL, "corner %zu position %g out of [0, %zu) or not increasing",
                         c, corners[c].position, m);
  if (kind == BSFIT_PARAM_UNIFORM || nc == 0) return bsfit__ok(st);
  /* walk the points, adding each corner's stretch to every parameter after it */
  for (i = 0; i < m; i++) {
    while (next < nc && corners[next].position < (double)i) {
      size_t j = (size_t)corners[next].position, j1 = (j + 1) % m;
      double f = corners[next].position - (double)j;
      double du = u[j1] - (u[j] - added); /* u[j] already moved by `added`, u[j1] not yet */
      double chord = measure(kind, dist_between(pts + j * (size_t)dim, pts + j1 * (size_t)dim, dim));
      double path = measure(kind, dist_between(pts + j * (size_t)dim, corners[next].point, dim)) +
                    measure(kind, dist_between(corners[next].point, pts + j1 * (size_t)dim, dim));
      if (f > 0 && chord > 0 && du > 0) added += du * (path - chord) / chord;
      next++;
    }
    u[i] += added;
  }
  /* the corner after the last point (closed data) stretches the closing step */
  while (next < nc) {
    size_t j = (size_t)corners[next].position;
    double f = corners[next].position - (double)j;
    double du = 1.0 + u[0] - (u[j] - added);
    double chord = measure(kind, dist_between(pts + j * (size_t)dim, pts, dim));
    double path = measure(kind, dist_between(pts + j * (size_t)dim, corners[next].point, dim)) +
                  measure(kind, dist_between(corners[next].point, pts, dim));
    if (closed && f > 0 && chord > 0 && du > 0) added += du * (path - chord) / chord;
    next++;
  }
  total = closed ? 1.0 + added : u[m - 1];
  for (i = 0; i < m; i++) u[i] /= total;
  if (!closed) u[m - 1] = 1.0;
  return bsfit__ok(st);
}
