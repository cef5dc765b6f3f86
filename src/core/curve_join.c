/*
** curve_join.c
** The one curve of a segmented section (bsfit_features.h): exact degree-3 lines and
** circular arcs, and the joining of open curves end to end into one curve with knots of
** multiplicity 3 at the joins.
*/
#include "internal.h"

#include <float.h>
#include <math.h>
#include <string.h>

#define PI 3.14159265358979323846

bsfit_err bsfit_curve_line(const double *a, const double *b, int dim, bsfit_curve *c,
                           const bsfit_allocator *al, bsfit_status *st) {
  static const double U[8] = {0, 0, 0, 0, 1, 1, 1, 1};
  double ctrl[16];
  int k, d;
  if (dim < 1 || dim > 4) return bsfit__fail(st, BSFIT_EDIM, "line: dim %d out of 1..4", dim);
  if (!bsfit__all_finite(a, (size_t)dim) || !bsfit__all_finite(b, (size_t)dim))
    return bsfit__fail(st, BSFIT_ENONFINITE, "line: end points contain NaN or Inf");
  /* evenly spaced on the chord: the ends exact, the inner points collinear to rounding */
  for (k = 0; k < 4; k++)
    for (d = 0; d < dim; d++)
      ctrl[k * dim + d] = k == 0 ? a[d] : k == 3 ? b[d] : a[d] + (b[d] - a[d]) * (double)k / 3.0;
  return bsfit_curve_new(c, 3, dim, 4, U, ctrl, NULL, 0, al, st);
}

/* one part of at most 90 degrees from angle a of sweep th, as a cubic (4 points, weights) */
static void arc_part(const double *c, double r, double a, double th, double *P, double *w) {
  double wm = cos(0.5 * th), rm = r / wm, am = a + 0.5 * th, s = 1.0 + 2.0 * wm;
  double P0[2] = {c[0] + r * cos(a), c[1] + r * sin(a)};
  double P1[2] = {c[0] + rm * cos(am), c[1] + rm * sin(am)};
  double P2[2] = {c[0] + r * cos(a + th), c[1] + r * sin(a + th)};
  int d;
  /* degree elevation of the rational quadratic (1, wm, 1) in homogeneous coordinates */
  for (d = 0; d < 2; d++) {
    P[d] = P0[d];
    P[2 + d] = (P0[d] + 2.0 * wm * P1[d]) / s;
    P[4 + d] = (2.0 * wm * P1[d] + P2[d]) / s;
    P[6 + d] = P2[d];
  }
  w[0] = 1.0;
  w[1] = w[2] = s / 3.0;
  w[3] = 1.0;
}

bsfit_err bsfit_curve_arc(const double *centre, double radius, double a0, double sweep,
                          bsfit_curve *c, const bsfit_allocator *al, bsfit_status *st) {
  size_t parts, n, i, k;
  bsfit_err e;
  if (!bsfit__all_finite(centre, 2) || !isfinite(radius) || !isfinite(a0) || !isfinite(sweep))
    return bsfit__fail(st, BSFIT_ENONFINITE, "arc: centre, radius or angles not finite");
  if (!(radius > 0) || !(fabs(sweep) > 0) || fabs(sweep) > 2.0 * PI * (1 + 1e-12))
    return bsfit__fail(st, BSFIT_EINVAL, "arc: radius %g must be > 0 and |sweep| %g in (0, 2 pi]",
                       radius, sweep);
  parts = (size_t)ceil(fabs(sweep) / (0.5 * PI) - 1e-9);
  if (parts < 1) parts = 1;
  n = 3 * parts + 1;
  e = bsfit_curve_alloc(c, 3, 2, n, 1, al, st);
  if (e != BSFIT_OK) return e;
  for (i = 0; i < parts; i++) {
    double P[8], w[4], th = sweep / (double)parts;
    arc_part(centre, radius, a0 + th * (double)i, th, P, w);
    for (k = 0; k < 4; k++) {
      c->ctrl[2 * (3 * i + k)] = P[2 * k];
      c->ctrl[2 * (3 * i + k) + 1] = P[2 * k + 1];
      c->weights[3 * i + k] = w[k];
    }
  }
  for (k = 0; k < 4; k++) c->knots[k] = 0.0, c->knots[n + k] = 1.0;
  for (i = 1; i < parts; i++)
    for (k = 0; k < 3; k++) c->knots[1 + 3 * i + k] = (double)i / (double)parts;
  return bsfit_curve_validate(c, st);
}

/* {====================================================================
** Joining
** ===================================================================== */

/* checks part i; its degree-3 form into tmp when it must be raised (else *use = part) */
static bsfit_err join_part(const bsfit_curve *part, size_t i, int dim, bsfit_curve *tmp,
                           const bsfit_curve **use, bsfit_status *st) {
  int p = part->degree, k;
  size_t n = part->n;
  if (part->periodic || part->dim != dim)
    return bsfit__fail(st, part->periodic ? BSFIT_EINVAL : BSFIT_EDIM,
                       "join: part %zu is periodic or of another dimension", i + 1);
  if (p < 1 || p > 3)
    return bsfit__fail(st, BSFIT_EDEGREE, "join: part %zu has degree %d (1..3)", i + 1, p);
  for (k = 1; k <= p; k++)
    if (part->knots[k] != part->knots[0] || part->knots[n + k - 1] != part->knots[n])
      return bsfit__fail(st, BSFIT_EINVAL, "join: part %zu is not clamped", i + 1);
  if (part->weights &&
      (fabs(part->weights[0] - 1) > 1e-12 || fabs(part->weights[n - 1] - 1) > 1e-12))
    return bsfit__fail(st, BSFIT_EINVAL, "join: part %zu has end weights other than 1", i + 1);
  *use = part;
  if (p == 3) return BSFIT_OK;
  *use = tmp;
  return bsfit_curve_elevate(part, 3 - p, tmp, st);
}

static double ends_apart(const bsfit_curve *a, const bsfit_curve *b) {
  double s = 0;
  int d;
  for (d = 0; d < a->dim; d++) {
    double x = a->ctrl[(a->n - 1) * (size_t)a->dim + d] - b->ctrl[d];
    s += x * x;
  }
  return sqrt(s);
}

/* the size of the parts: the largest extent of their control points */
static double parts_size(const bsfit_curve *const *u, size_t n) {
  double lo[4], hi[4], s = 0;
  size_t i, k;
  int d, dim = u[0]->dim;
  for (d = 0; d < dim; d++) lo[d] = hi[d] = u[0]->ctrl[d];
  for (i = 0; i < n; i++)
    for (k = 0; k < u[i]->n; k++)
      for (d = 0; d < dim; d++) {
        double x = u[i]->ctrl[k * (size_t)dim + d];
        if (x < lo[d]) lo[d] = x;
        if (x > hi[d]) hi[d] = x;
      }
  for (d = 0; d < dim; d++) s += (hi[d] - lo[d]) * (hi[d] - lo[d]);
  return sqrt(s);
}

/* How far apart the ends of consecutive parts may lie: 1e-9 of their size, and no less than
** 64 units of the last place of their largest coordinate (parts far from the origin, 10^7
** times their size, meet only to the rounding of their coordinates). */
static double join_tol(const bsfit_curve *const *u, size_t n) {
  double big = 0;
  size_t i, k;
  for (i = 0; i < n; i++)
    for (k = 0; k < u[i]->n * (size_t)u[i]->dim; k++) big = fmax(big, fabs(u[i]->ctrl[k]));
  return fmax(1e-9 * parts_size(u, n), 64.0 * DBL_EPSILON * big);
}

/* writes the joined curve into out (allocated by the caller for N points) */
static void join_fill(const bsfit_curve *const *u, size_t n, const double *s, bsfit_curve *out) {
  size_t i, k, j = 0, kn = 0;
  int d, dim = out->dim;
  for (k = 0; k < 4; k++) out->knots[kn++] = 0.0;
  for (i = 0; i < n; i++) {
    const bsfit_curve *c = u[i];
    double a = c->knots[0], b = c->knots[c->n];
    /* each part after the first starts exactly where the one before ends */
    for (k = i == 0 ? 0 : 1; k < c->n; k++, j++) {
      for (d = 0; d < dim; d++) out->ctrl[j * (size_t)dim + d] = c->ctrl[k * (size_t)dim + d];
      if (out->weights) out->weights[j] = c->weights ? c->weights[k] : 1.0;
    }
    for (k = 4; k < c->n; k++)
      out->knots[kn++] = s[i] + (s[i + 1] - s[i]) * (c->knots[k] - a) / (b - a);
    for (k = 0; k < (i + 1 < n ? 3u : 4u); k++) out->knots[kn++] = i + 1 < n ? s[i + 1] : 1.0;
  }
}

bsfit_err bsfit_curve_join(const bsfit_curve *const *parts, size_t n, const double *lengths,
                           bsfit_curve *out, const bsfit_allocator *al, bsfit_status *st) {
  bsfit_curve *tmp = NULL;
  const bsfit_curve **use = NULL;
  double *s = NULL, total = 0, gap;
  size_t i, N = 0;
  int rational = 0, dim;
  bsfit_err e = BSFIT_OK;
  if (parts == NULL || n == 0 || lengths == NULL || parts[0] == NULL)
    return bsfit__fail(st, BSFIT_EINVAL, "join: no parts");
  dim = parts[0]->dim;
  tmp = bsfit__alloc(al, bsfit__mulsize(n, sizeof *tmp));
  use = bsfit__alloc(al, bsfit__mulsize(n, sizeof *use));
  s = bsfit__alloc(al, bsfit__mulsize(n + 1, sizeof *s));
  if (!tmp || !use || !s) {
    e = bsfit__fail(st, BSFIT_ENOMEM, "join: out of memory");
    goto done;
  }
  for (i = 0; i < n; i++) bsfit_curve_init(&tmp[i]);
  for (i = 0; i < n && e == BSFIT_OK; i++) {
    if (parts[i] == NULL || !(lengths[i] > 0) || !isfinite(lengths[i]))
      e = bsfit__fail(st, BSFIT_EINVAL, "join: part %zu missing or its length not > 0", i + 1);
    else
      e = join_part(parts[i], i, dim, &tmp[i], &use[i], st);
    if (e == BSFIT_OK) {
      total += lengths[i];
      N += use[i]->n - (i > 0);
      rational |= use[i]->weights != NULL;
    }
  }
  if (e != BSFIT_OK) goto done;
  gap = join_tol(use, n);
  for (i = 1; i < n; i++)
    if (ends_apart(use[i - 1], use[i]) > gap) {
      e = bsfit__fail(st, BSFIT_EINVAL, "join: part %zu starts %g away from the end of part %zu",
                      i + 1, ends_apart(use[i - 1], use[i]), i);
      goto done;
    }
  s[0] = 0;
  for (i = 0; i < n; i++) s[i + 1] = s[i] + lengths[i] / total;
  s[n] = 1.0;
  e = bsfit_curve_alloc(out, 3, dim, N, rational, al, st);
  if (e != BSFIT_OK) goto done;
  join_fill(use, n, s, out);
  /* the last part's end lands on the first's start when they are within rounding */
  if (ends_apart(use[n - 1], use[0]) <= gap)
    memcpy(out->ctrl + (N - 1) * (size_t)dim, out->ctrl, (size_t)dim * sizeof(double));
  e = bsfit_curve_validate(out, st);
  if (e != BSFIT_OK) bsfit_curve_free(out);
done:
  if (tmp)
    for (i = 0; i < n; i++) bsfit_curve_free(&tmp[i]);
  bsfit__free(al, tmp, tmp ? n * sizeof *tmp : 0);
  bsfit__free(al, use, use ? n * sizeof *use : 0);
  bsfit__free(al, s, s ? (n + 1) * sizeof *s : 0);
  return e;
}

/* }==================================================================== */
