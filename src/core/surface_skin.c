/*
** surface_skin.c
** Skinning (The NURBS Book, section 10.3, adapted to closed sections): K closed section
** curves are made compatible, then interpolated across, into one tensor-product surface
** periodic in u (around the sections) and clamped in v (across them).
**
**   1. each section is reparametrised onto [0, 1) (an affine map of its knots);
**   2. orientation: a section whose winding (its area vector) disagrees with the
**      previous section's is reversed;
**   3. seams: each section's start is moved (knot insertion, then a rotation of the
**      periodic arrays) to the point nearest to where the previous section's start falls
**      when carried over by the centroids and the mean radii;
**   4. degree elevation to the highest degree, then knot refinement to the union of the
**      period knots (largest multiplicity of each value): all sections now share one
**      knot vector and are still exactly the same curves;
**   5. v parameters by the averaged chord length between corresponding control points
**      (NURBS Book eq. 10.8), and each column of control points interpolated by a
**      clamped B-spline of degree q (NURBS Book A9.1, knots by averaging).
** Rational sections are refused: interpolating their homogeneous points across can give
** non-positive weights between the sections.
*/
#include "skin_internal.h"

#include <float.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

/* {====================================================================
** Checks and normalisation
** ===================================================================== */

/* Records the section an error is about ((size_t)-1: none). */
static void bad_section(bsfit_skin_report *rep, size_t k) {
  if (rep != NULL) rep->bad_section = k;
}

static bsfit_err check_sections(const bsfit_curve *const *c, size_t K, int q,
                                bsfit_skin_report *rep, bsfit_status *st) {
  size_t k;
  bsfit_err e;
  if (c == NULL || K < 2)
    return bsfit__fail(st, BSFIT_ETOOFEW, "skinning needs at least 2 sections, got %zu",
                       c == NULL ? (size_t)0 : K);
  if (q < 0 || q > 3 || (q > 0 && (size_t)q > K - 1))
    return bsfit__fail(st, BSFIT_EDEGREE, "degree in v %d: 1..3 and below the %zu sections "
                                          "(0 = min(3, sections - 1))", q, K);
  for (k = 0; k < K; k++) {
    bad_section(rep, k);
    if (c[k] == NULL) return bsfit__fail(st, BSFIT_EINVAL, "section %zu is NULL", k);
    if ((e = bsfit_curve_validate(c[k], st)) != BSFIT_OK) return e;
    if (!c[k]->periodic)
      return bsfit__fail(st, BSFIT_EINVAL, "section %zu is open: skinning needs closed "
                                           "(periodic) sections", k);
    if (c[k]->weights != NULL)
      return bsfit__fail(st, BSFIT_EINVAL, "section %zu is rational: skinning needs polynomial "
                                           "sections", k);
    if (c[k]->dim != 3)
      return bsfit__fail(st, BSFIT_EDIM, "section %zu has dim %d: skinning needs 3D sections",
                         k, c[k]->dim);
  }
  bad_section(rep, (size_t)-1);
  return BSFIT_OK;
}

/* out = c on [0, 1): the period's knots mapped affinely, the same control points. */
static bsfit_err normalise(const bsfit_curve *c, bsfit_curve *out, const bsfit_allocator *a,
                           bsfit_status *st) {
  size_t p = (size_t)c->degree, N = c->n - p, i;
  double ua, ub, *t = bsfit__alloc(a, (N + 1) * sizeof(double));
  bsfit_err e;
  if (t == NULL) return bsfit__fail(st, BSFIT_ENOMEM, "out of memory for %zu knots", N + 1);
  bsfit_curve_domain(c, &ua, &ub);
  for (i = 0; i < N; i++) t[i] = (c->knots[p + i] - ua) / (ub - ua);
  t[0] = 0.0;
  t[N] = 1.0;
  e = bsfit_curve_new_periodic(out, c->degree, c->dim, N, t, c->ctrl, NULL, a, st);
  bsfit__free(a, t, (N + 1) * sizeof(double));
  return e;
}

/* }==================================================================== */

/* {====================================================================
** Orientation and seams
** ===================================================================== */

#define SHAPE_SAMPLES 256

/* Centroid, area vector (1/2 sum s_i x s_i+1 of the closed polygon of samples) and RMS
** radius of a closed 3D curve, from SHAPE_SAMPLES samples (scratch from a). */
typedef struct shape {
  double c[3], area[3], radius;
} shape;

static bsfit_err section_shape(const bsfit_curve *c, shape *sh, const bsfit_allocator *a,
                               bsfit_status *st) {
  size_t i, m = SHAPE_SAMPLES;
  double *s = bsfit__alloc(a, m * 3 * sizeof(double)), r2 = 0.0;
  bsfit_err e;
  int t;
  if (s == NULL) return bsfit__fail(st, BSFIT_ENOMEM, "out of memory for section samples");
  e = bsfit_curve_sample(c, m, s, a, st);
  memset(sh, 0, sizeof *sh);
  for (i = 0; e == BSFIT_OK && i < m; i++)
    for (t = 0; t < 3; t++) sh->c[t] += s[i * 3 + t] / (double)m;
  for (i = 0; e == BSFIT_OK && i < m; i++) {
    const double *P = s + i * 3, *Q = s + ((i + 1) % m) * 3;
    double x[3], y[3];
    for (t = 0; t < 3; t++) {
      x[t] = P[t] - sh->c[t];
      y[t] = Q[t] - sh->c[t];
      r2 += x[t] * x[t] / (double)m;
    }
    sh->area[0] += 0.5 * (x[1] * y[2] - x[2] * y[1]);
    sh->area[1] += 0.5 * (x[2] * y[0] - x[0] * y[2]);
    sh->area[2] += 0.5 * (x[0] * y[1] - x[1] * y[0]);
  }
  sh->radius = sqrt(r2);
  bsfit__free(a, s, m * 3 * sizeof(double));
  return e;
}

/* Where section c's start goes: the point of c nearest to the previous start `prev`
** carried over from the previous shape to this one (centroid, mean radius). A parameter
** near a knot (BSFIT__SKIN_MERGE for a C0 knot, BSFIT__SKIN_SNAP for others) is moved
** onto the nearest, so no sliver span is made: closest points at a corner land off it. */
static bsfit_err seam_param(const bsfit_curve *c, const shape *ps, const shape *sh,
                            const double *prev, double *u, const bsfit_allocator *a,
                            bsfit_status *st) {
  double P[3], scale = ps->radius > 0 ? sh->radius / ps->radius : 1.0, best, snap;
  size_t i, p = (size_t)c->degree;
  int t;
  bsfit_err e;
  for (t = 0; t < 3; t++) P[t] = sh->c[t] + (prev[t] - ps->c[t]) * scale;
  e = bsfit_curve_closest(c, P, u, NULL, a, st);
  if (e != BSFIT_OK) return e;
  for (i = p, best = HUGE_VAL, snap = *u; i <= c->n; i++) {
    double d = fabs(c->knots[i] - *u);
    int corner = bsfit_knots_multiplicity(c->knots, c->n + p + 1, c->knots[i]) >= (int)p;
    if (d < best && d < (corner ? BSFIT__SKIN_MERGE : BSFIT__SKIN_SNAP)) best = d, snap = c->knots[i];
  }
  *u = snap;
  if (*u >= 1.0) *u = 0.0;
  return BSFIT_OK;
}

static double dot3(const double *x, const double *y) {
  return x[0] * y[0] + x[1] * y[1] + x[2] * y[2];
}

/* Steps 1-3 for section k: w[k] becomes the normalised, oriented, rotated section. */
static bsfit_err orient_section(const bsfit_curve *c, size_t k, int align, bsfit_curve *w,
                                shape *sh, bsfit_skin_report *rep, const bsfit_allocator *a,
                                bsfit_status *st) {
  double u = 0.0, ua, ub, start[3];
  int rev = 0;
  bsfit_curve tmp;
  bsfit_err e = normalise(c, &w[k], a, st);
  if (e == BSFIT_OK) e = bsfit__skin_seam_whole(&w[k], a, st);
  if (e == BSFIT_OK) e = section_shape(&w[k], &sh[k], a, st);
  if (e != BSFIT_OK || !align || k == 0) goto done;
  if (dot3(sh[k].area, sh[k - 1].area) < 0) {
    rev = 1;
    if ((e = bsfit_curve_reverse(&w[k], &w[k], st)) != BSFIT_OK) return e;
    if ((e = bsfit__skin_seam_whole(&w[k], a, st)) != BSFIT_OK) return e;
    sh[k].area[0] = -sh[k].area[0], sh[k].area[1] = -sh[k].area[1];
    sh[k].area[2] = -sh[k].area[2];
  }
  bsfit__curve_eval_unchecked(&w[k - 1], 0.0, start);
  e = seam_param(&w[k], &sh[k - 1], &sh[k], start, &u, a, st);
  if (e != BSFIT_OK || u == 0.0) goto done;
  bsfit_curve_init(&tmp);
  e = bsfit__skin_rotate(&w[k], u, &tmp, a, st);
  if (e == BSFIT_OK) bsfit_curve_move(&tmp, &w[k]);
  bsfit_curve_free(&tmp);
done:
  bsfit_curve_domain(c, &ua, &ub);
  if (rep && rep->reversed) rep->reversed[k] = rev;
  if (rep && rep->shifts) rep->shifts[k] = ua + (ub - ua) * (rev ? (u > 0 ? 1.0 - u : 0.0) : u);
  return e;
}

/* }==================================================================== */

/* After bsfit__skin_compatible every section must have the same knots, exactly. */
static bsfit_err check_compatible(const bsfit_curve *w, size_t K, bsfit_status *st) {
  size_t k;
  for (k = 1; k < K; k++)
    if (w[k].n != w[0].n || w[k].degree != w[0].degree ||
        memcmp(w[k].knots, w[0].knots, (w[0].n + (size_t)w[0].degree + 1) * sizeof(double)) != 0)
      return bsfit__fail(st, BSFIT_EINVAL, "sections 0 and %zu did not become compatible "
                                           "(a bug: please report)", k);
  return BSFIT_OK;
}

/* }==================================================================== */

/* {====================================================================
** Interpolation across the sections
** ===================================================================== */

/* v parameters by the averaged chord length (NURBS Book eq. 10.8) over the N distinct
** control point columns; a column whose points all coincide (an apex) is left out. */
static bsfit_err v_params(const bsfit_curve *w, size_t K, double *v, bsfit_skin_report *rep,
                          bsfit_status *st) {
  size_t N = w[0].n - (size_t)w[0].degree, i, k, used = 0;
  for (k = 0; k < K; k++) v[k] = 0.0;
  for (i = 0; i < N; i++) {
    double total = 0.0, run = 0.0;
    for (k = 1; k < K; k++) {
      const double *P = w[k].ctrl + i * 3, *Q = w[k - 1].ctrl + i * 3;
      total += sqrt((P[0] - Q[0]) * (P[0] - Q[0]) + (P[1] - Q[1]) * (P[1] - Q[1]) +
                    (P[2] - Q[2]) * (P[2] - Q[2]));
    }
    if (!(total > 0)) continue;
    used++;
    for (k = 1; k < K; k++) {
      const double *P = w[k].ctrl + i * 3, *Q = w[k - 1].ctrl + i * 3;
      run += sqrt((P[0] - Q[0]) * (P[0] - Q[0]) + (P[1] - Q[1]) * (P[1] - Q[1]) +
                  (P[2] - Q[2]) * (P[2] - Q[2]));
      v[k] += run / total;
    }
  }
  if (used == 0) return bsfit__fail(st, BSFIT_EDEGENERATE, "all sections coincide");
  for (k = 1; k < K; k++) v[k] /= (double)used;
  v[K - 1] = 1.0;
  for (k = 1; k < K; k++)
    if (!(v[k] > v[k - 1] + 1e-12)) {
      bad_section(rep, k);
      return bsfit__fail(st, BSFIT_EDEGENERATE, "sections %zu and %zu coincide", k - 1, k);
    }
  return BSFIT_OK;
}

/* The surface: row i of the net is column i of the sections' control points,
** interpolated across them; the wrapped rows N..N+p-1 copy rows 0..p-1. */
static bsfit_err interpolate_net(const bsfit_curve *w, size_t K, int q, const double *v,
                                 bsfit_surface *S, const bsfit_allocator *a, bsfit_status *st) {
  size_t p = (size_t)w[0].degree, n = w[0].n, N = n - p, i, k;
  double *col = bsfit__alloc(a, K * 3 * sizeof(double));
  bsfit_curve c;
  bsfit_err e;
  if (col == NULL) return bsfit__fail(st, BSFIT_ENOMEM, "out of memory for %zu sections", K);
  e = bsfit_surface_alloc(S, (int)p, q, 3, n, K, 0, a, st);
  bsfit_curve_init(&c);
  for (i = 0; i < N && e == BSFIT_OK; i++) {
    if (bsfit__interrupted(a)) {
      e = bsfit__fail(st, BSFIT_EINTR, "skinning interrupted");
      break;
    }
    for (k = 0; k < K; k++) memcpy(col + k * 3, w[k].ctrl + i * 3, 3 * sizeof(double));
    e = bsfit_interpolate(col, K, 3, v, q, 0, &c, a, st);
    if (e != BSFIT_OK) break;
    memcpy(S->ctrl + i * K * 3, c.ctrl, K * 3 * sizeof(double));
    if (i == 0) memcpy(S->knots_v, c.knots, (K + (size_t)q + 1) * sizeof(double));
  }
  if (e == BSFIT_OK) {
    memcpy(S->ctrl + N * K * 3, S->ctrl, p * K * 3 * sizeof(double));
    memcpy(S->knots_u, w[0].knots, (n + p + 1) * sizeof(double));
    S->periodic_u = 1;
    e = bsfit_surface_validate(S, st);
  }
  if (e != BSFIT_OK) bsfit_surface_free(S);
  bsfit_curve_free(&c);
  bsfit__free(a, col, K * 3 * sizeof(double));
  return e;
}

/* }==================================================================== */

void bsfit_skin_opts_init(bsfit_skin_opts *o) {
  o->degree_v = 0;
  o->align = 1;
  o->tol = 0.0;
}

/* With a tolerance: the sections replaced by uniform cubics within it (the report says
** which count, and how far). */
static bsfit_err approximate(bsfit_curve *w, size_t K, double tol, bsfit_skin_report *rep,
                             const bsfit_allocator *a, bsfit_status *st) {
  size_t N;
  double dev;
  bsfit_err e;
  if (!(tol > 0)) return BSFIT_OK;
  e = bsfit__skin_approximate(w, K, tol, &N, &dev, a, st);
  if (e == BSFIT_OK && rep != NULL) rep->count = N, rep->max_deviation = dev;
  return e;
}

bsfit_err bsfit_surface_skin(const bsfit_curve *const *sections, size_t K,
                             const bsfit_skin_opts *o, bsfit_surface *out,
                             bsfit_skin_report *rep, const bsfit_allocator *a,
                             bsfit_status *st) {
  bsfit_skin_opts def;
  bsfit_curve *w;
  shape *sh;
  double *v;
  size_t k, bytes;
  int q;
  bsfit_err e;
  if (o == NULL) bsfit_skin_opts_init(&def), o = &def;
  if (rep != NULL) rep->bad_section = (size_t)-1, rep->count = 0, rep->max_deviation = 0.0;
  if (out == NULL) return bsfit__fail(st, BSFIT_EINVAL, "no output surface");
  if (!(o->tol >= 0 && o->tol < HUGE_VAL))
    return bsfit__fail(st, BSFIT_EINVAL, "tolerance %g: must be 0 (exact) or positive", o->tol);
  if ((e = check_sections(sections, K, o->degree_v, rep, st)) != BSFIT_OK) return e;
  q = o->degree_v > 0 ? o->degree_v : (K - 1 < 3 ? (int)K - 1 : 3);
  bytes = bsfit__mulsize(K, sizeof *w + sizeof *sh + sizeof *v);
  w = bytes ? bsfit__alloc(a, bytes) : NULL;
  if (w == NULL) return bsfit__fail(st, BSFIT_ENOMEM, "out of memory for %zu sections", K);
  sh = (shape *)(w + K);
  v = (double *)(sh + K);
  for (k = 0; k < K; k++) bsfit_curve_init(&w[k]);
  for (k = 0, e = BSFIT_OK; k < K && e == BSFIT_OK; k++)
    e = orient_section(sections[k], k, o->align, w, sh, rep, a, st);
  if (e == BSFIT_OK) e = approximate(w, K, o->tol, rep, a, st);
  if (e == BSFIT_OK) e = bsfit__skin_compatible(w, K, a, st);
  if (e == BSFIT_OK) e = check_compatible(w, K, st);
  if (e == BSFIT_OK) e = v_params(w, K, v, rep, st);
  if (e == BSFIT_OK) e = interpolate_net(w, K, q, v, out, a, st);
  if (e == BSFIT_OK && rep != NULL && rep->v_params != NULL)
    memcpy(rep->v_params, v, K * sizeof(double));
  for (k = 0; k < K; k++) bsfit_curve_free(&w[k]);
  bsfit__free(a, w, bytes);
  return e == BSFIT_OK ? bsfit__ok(st) : e;
}
