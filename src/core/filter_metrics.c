/*
** filter_metrics.c
** Shape measures that tell whether a smoothing did its job, computed on a sampled
** polygon so they work for every kind of curve (polygons with corners included):
** total absolute turning, bending energy (integral of curvature^2 ds), and the
** maximum parametric deviation between two curves.
*/
#include "filter_internal.h"

#include <math.h>
#include <string.h>

/* {====================================================================
** Sampled polygon
** ===================================================================== */

typedef struct measures {
  double turning, energy;
} measures;

static bsfit_err check_measured(const bsfit_curve *c, size_t samples, const double *out,
                                bsfit_status *st) {
  bsfit_err e;
  if (c == NULL || out == NULL) return bsfit__fail(st, BSFIT_EINVAL, "curve or output is NULL");
  e = bsfit_curve_validate(c, st);
  if (e != BSFIT_OK) return e;
  if (c->dim < 2)
    return bsfit__fail(st, BSFIT_EDIM, "turning needs a curve of dimension 2..4, got %d", c->dim);
  if (samples < 3)
    return bsfit__fail(st, BSFIT_EINVAL, "need at least 3 samples, got %zu", samples);
  return BSFIT_OK;
}

/* Angle in [0, pi] between two vectors of d <= 4 coordinates; the sine comes from the
** sum of squared 2x2 minors (Lagrange's identity), which keeps small angles accurate. */
static double angle_between(const double *e1, const double *e2, size_t d) {
  double dot = 0.0, cross2 = 0.0;
  size_t i, j;
  for (i = 0; i < d; i++) {
    dot += e1[i] * e2[i];
    for (j = i + 1; j < d; j++) {
      double m = e1[i] * e2[j] - e1[j] * e2[i];
      cross2 += m * m;
    }
  }
  return atan2(sqrt(cross2), dot);
}

static double norm(const double *e, size_t d) {
  double s = 0.0;
  size_t i;
  for (i = 0; i < d; i++) s += e[i] * e[i];
  return sqrt(s);
}

/* A vertex between chords e1 (length l1) and e2 (length l2) turns by theta; as a piece
** of curve of length (l1 + l2)/2 with curvature theta / length it adds theta^2 / length. */
static void add_vertex(measures *m, const double *e1, double l1, const double *e2, double l2,
                       size_t d) {
  double theta = angle_between(e1, e2, d);
  m->turning += theta;
  m->energy += theta * theta / (0.5 * (l1 + l2));
}

/* Evaluation at increasing parameters: the knot span is carried from one sample to the
** next instead of searched (polynomial B-splines; others through the general evaluator). */
typedef struct cursor {
  const bsfit_curve *c;
  size_t s;
} cursor;

static void cursor_eval(cursor *k, double t, double *out) {
  const bsfit_curve *c = k->c;
  double N[BSFIT_MAX_DEGREE + 1];
  size_t p = (size_t)c->degree, d = (size_t)c->dim, j, q;
  const double *P;
  if (c->weights != NULL || c->bezier) {
    bsfit__curve_eval_unchecked(c, t, out);
    return;
  }
  while (k->s + 1 < c->n && t >= c->knots[k->s + 1]) k->s++;
  bsfit_basis_funs(k->s, t, c->degree, c->knots, N);
  P = c->ctrl + (k->s - p) * d;
  for (q = 0; q < d; q++) out[q] = 0.0;
  for (j = 0; j <= p; j++)
    for (q = 0; q < d; q++) out[q] += N[j] * P[j * d + q];
}

static measures polygon_measures(const bsfit_curve *c, size_t samples) {
  double a, b, h, first[4], prev[4], cur[4], e[4], efirst[4], elast[4], lfirst = 0, llast = 0;
  size_t d = (size_t)c->dim, i, k, chords = c->periodic ? samples : samples - 1;
  measures m = {0.0, 0.0};
  cursor at;
  bsfit_curve_domain(c, &a, &b);
  at.c = c;
  at.s = (size_t)c->degree;
  h = (b - a) / (double)(c->periodic ? samples : samples - 1);
  cursor_eval(&at, a, first);
  memcpy(prev, first, sizeof prev);
  for (i = 1; i <= chords; i++) {
    double len;
    if (i == samples) memcpy(cur, first, sizeof cur); /* closing chord */
    else cursor_eval(&at, i + 1 == samples && !c->periodic ? b : a + (double)i * h, cur);
    for (k = 0; k < d; k++) e[k] = cur[k] - prev[k];
    memcpy(prev, cur, sizeof prev);
    len = norm(e, d);
    if (!(len > 0)) continue; /* a repeated sample has no direction */
    if (llast > 0) add_vertex(&m, elast, llast, e, len, d);
    else {
      memcpy(efirst, e, sizeof e);
      lfirst = len;
    }
    memcpy(elast, e, sizeof e);
    llast = len;
  }
  if (c->periodic && lfirst > 0) add_vertex(&m, elast, llast, efirst, lfirst, d);
  return m;
}

void bsfit__curve_shape(const bsfit_curve *c, size_t samples, double *turning, double *energy) {
  measures m = polygon_measures(c, samples);
  if (turning != NULL) *turning = m.turning;
  if (energy != NULL) *energy = m.energy;
}

bsfit_err bsfit_curve_total_turning(const bsfit_curve *c, size_t samples, double *out,
                                    bsfit_status *st) {
  bsfit_err e = check_measured(c, samples, out, st);
  if (e != BSFIT_OK) return e;
  *out = polygon_measures(c, samples).turning;
  return bsfit__ok(st);
}

bsfit_err bsfit_curve_bending_energy(const bsfit_curve *c, size_t samples, double *out,
                                     bsfit_status *st) {
  bsfit_err e = check_measured(c, samples, out, st);
  if (e != BSFIT_OK) return e;
  *out = polygon_measures(c, samples).energy;
  return bsfit__ok(st);
}

/* }==================================================================== */

/* {====================================================================
** Deviation between two curves
** ===================================================================== */

bsfit_err bsfit_curve_max_deviation(const bsfit_curve *a, const bsfit_curve *b, size_t samples,
                                    double *out, bsfit_status *st) {
  double a0, a1, b0, b1, lo, hi, pa[4], pb[4], worst = 0.0;
  size_t i, k;
  bsfit_err e;
  if (a == NULL || b == NULL || out == NULL)
    return bsfit__fail(st, BSFIT_EINVAL, "curve or output is NULL");
  e = bsfit_curve_validate(a, st);
  if (e == BSFIT_OK) e = bsfit_curve_validate(b, st);
  if (e != BSFIT_OK) return e;
  if (a->dim != b->dim)
    return bsfit__fail(st, BSFIT_EDIM, "curves of dimensions %d and %d", a->dim, b->dim);
  if (samples < 2)
    return bsfit__fail(st, BSFIT_EINVAL, "need at least 2 samples, got %zu", samples);
  bsfit_curve_domain(a, &a0, &a1);
  bsfit_curve_domain(b, &b0, &b1);
  lo = a0 > b0 ? a0 : b0;
  hi = a1 < b1 ? a1 : b1;
  if (!(lo < hi))
    return bsfit__fail(st, BSFIT_EDOMAIN, "domains [%g, %g] and [%g, %g] do not overlap", a0, a1,
                       b0, b1);
  for (i = 0; i < samples; i++) {
    double t = i + 1 == samples ? hi : lo + (hi - lo) * (double)i / (double)(samples - 1), s = 0;
    bsfit__curve_eval_unchecked(a, t, pa);
    bsfit__curve_eval_unchecked(b, t, pb);
    for (k = 0; k < (size_t)a->dim; k++) s += (pa[k] - pb[k]) * (pa[k] - pb[k]);
    if (sqrt(s) > worst) worst = sqrt(s);
  }
  *out = worst;
  return bsfit__ok(st);
}

/* }==================================================================== */
