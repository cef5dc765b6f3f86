/*
** curve.c
** The curve object: construction, validation, ownership and point evaluation of
** B-spline, NURBS and Bézier curves, open or periodic. Further operations
** (derivatives, knot insertion, ...) live in curve_ops.c.
*/
#include "internal.h"

#include <math.h>
#include <string.h>

void bsfit_curve_init(bsfit_curve *c) {
  memset(c, 0, sizeof *c);
}

static size_t nknots_of(const bsfit_curve *c) { return c->n + (size_t)c->degree + 1; }

void bsfit_curve_free(bsfit_curve *c) {
  if (c == NULL) return;
  bsfit__free(&c->alloc, c->knots, nknots_of(c) * sizeof(double));
  bsfit__free(&c->alloc, c->ctrl, c->n * (size_t)c->dim * sizeof(double));
  bsfit__free(&c->alloc, c->weights, c->n * sizeof(double));
  bsfit_curve_init(c);
}

bsfit_err bsfit_curve_alloc(bsfit_curve *c, int degree, int dim, size_t n, int rational,
                            const bsfit_allocator *a, bsfit_status *st) {
  size_t nk = n + (size_t)degree + 1, nc;
  bsfit_curve_free(c);
  if (dim < 1 || dim > 4) return bsfit__fail(st, BSFIT_EDIM, "dimension %d out of range 1..4", dim);
  if (degree < 0 || degree > BSFIT_MAX_DEGREE)
    return bsfit__fail(st, BSFIT_EDEGREE, "degree %d out of range 0..%d", degree,
                       BSFIT_MAX_DEGREE);
  nc = bsfit__mulsize(n, (size_t)dim * sizeof(double));
  if (n == 0 || nc == 0 || bsfit__mulsize(nk, sizeof(double)) == 0)
    return bsfit__fail(st, BSFIT_EINVAL, "bad number of control points %zu", n);
  if (a != NULL) c->alloc = *a;
  c->degree = degree;
  c->dim = dim;
  c->n = n;
  c->knots = bsfit__alloc(&c->alloc, nk * sizeof(double));
  c->ctrl = bsfit__alloc(&c->alloc, nc);
  c->weights = rational ? bsfit__alloc(&c->alloc, n * sizeof(double)) : NULL;
  if (c->knots == NULL || c->ctrl == NULL || (rational && c->weights == NULL)) {
    bsfit_curve_free(c);
    return bsfit__fail(st, BSFIT_ENOMEM, "out of memory for a curve of %zu control points", n);
  }
  memset(c->knots, 0, nk * sizeof(double));
  memset(c->ctrl, 0, nc);
  if (c->weights) memset(c->weights, 0, n * sizeof(double));
  return bsfit__ok(st);
}

/* A closed curve has no ends: a knot of multiplicity p + 1 anywhere, the seam included,
** would break it into pieces (a jump the expanded form cannot express, and that every
** operation on the period would mishandle). The stored vector holds p knots beyond each
** end of the period, so a seam run of more than p copies shows there as a run > p. */
static bsfit_err periodic_multiplicity(const bsfit_curve *c, bsfit_status *st) {
  size_t i, run = 1, p = (size_t)c->degree;
  for (i = 1; i < nknots_of(c); i++) {
    run = c->knots[i] == c->knots[i - 1] ? run + 1 : 1;
    if (run > p)
      return bsfit__fail(st, BSFIT_EMULT,
                         "knot %g of a closed curve has multiplicity %zu > degree %zu: the "
                         "curve would not be continuous there",
                         c->knots[i], run, p);
  }
  return BSFIT_OK;
}

static bsfit_err validate_periodic(const bsfit_curve *c, bsfit_status *st) {
  size_t i, p = (size_t)c->degree, N, d = (size_t)c->dim;
  const double *U = c->knots;
  double tol;
  if (c->degree < 1 || c->n < 2 * p + 1 || c->n < p + 2)
    return bsfit__fail(st, BSFIT_ENOTPERIODIC,
                       "periodic curve of degree %d needs more than %zu stored control points",
                       c->degree, c->n);
  N = c->n - p;
  tol = bsfit__periodic_span_tol(U[p], U[N + p]);
  for (i = 0; i < p * d; i++)
    if (c->ctrl[i] != c->ctrl[N * d + i])
      return bsfit__fail(st, BSFIT_ENOTPERIODIC,
                         "wrapped control point %zu differs from control point %zu", N + i / d,
                         i / d);
  for (i = 0; c->weights && i < p; i++)
    if (c->weights[i] != c->weights[N + i])
      return bsfit__fail(st, BSFIT_ENOTPERIODIC, "wrapped weight %zu differs from weight %zu",
                         N + i, i);
  for (i = 1; i < nknots_of(c) - N; i++)
    if (fabs((U[i + N] - U[i + N - 1]) - (U[i] - U[i - 1])) > tol)
      return bsfit__fail(st, BSFIT_ENOTPERIODIC, "knot spans %zu and %zu differ", i - 1,
                         i + N - 1);
  return periodic_multiplicity(c, st);
}

bsfit_err bsfit_curve_validate(const bsfit_curve *c, bsfit_status *st) {
  size_t i;
  bsfit_err e;
  if (c == NULL || c->ctrl == NULL || c->knots == NULL)
    return bsfit__fail(st, BSFIT_EINVAL, "empty curve");
  if (c->dim < 1 || c->dim > 4)
    return bsfit__fail(st, BSFIT_EDIM, "dimension %d out of range 1..4", c->dim);
  e = bsfit_knots_validate(c->knots, nknots_of(c), c->degree, c->n, st);
  if (e != BSFIT_OK) return e;
  i = bsfit__first_out_of_range(c->ctrl, c->n * (size_t)c->dim);
  if (i < c->n * (size_t)c->dim && !isfinite(c->ctrl[i]))
    return bsfit__fail(st, BSFIT_ENONFINITE, "control points contain NaN or Inf");
  if (i < c->n * (size_t)c->dim)
    return bsfit__fail(st, BSFIT_ERANGE, "control point %zu has a coordinate %g beyond 1e100",
                       i / (size_t)c->dim, c->ctrl[i]);
  /* normal, bounded weights: subnormal ones lose their digits, and with the coordinate
  ** bound every homogeneous product w x stays below 1e200 */
  for (i = 0; c->weights && i < c->n; i++)
    if (!(c->weights[i] >= BSFIT_WEIGHT_MIN && c->weights[i] <= BSFIT_WEIGHT_MAX))
      return bsfit__fail(st, BSFIT_EWEIGHT, "weight %zu is %g (must be in [1e-100, 1e100])", i,
                         c->weights[i]);
  if (c->bezier && c->n != (size_t)c->degree + 1)
    return bsfit__fail(st, BSFIT_EINVAL, "a Bezier curve of degree %d needs %d control points",
                       c->degree, c->degree + 1);
  if (c->periodic) {
    e = validate_periodic(c, st);
    if (e != BSFIT_OK) return e;
  }
  return bsfit__ok(st);
}

bsfit_err bsfit_curve_new(bsfit_curve *c, int degree, int dim, size_t n, const double *knots,
                          const double *ctrl, const double *weights, int periodic,
                          const bsfit_allocator *a, bsfit_status *st) {
  bsfit_err e;
  if (ctrl == NULL) return bsfit__fail(st, BSFIT_EINVAL, "no control points");
  e = bsfit_curve_alloc(c, degree, dim, n, weights != NULL, a, st);
  if (e != BSFIT_OK) return e;
  if (n < (size_t)degree + 1) {
    bsfit_curve_free(c);
    return bsfit__fail(st, BSFIT_EDEGREE, "degree %d needs at least %d control points, got %zu",
                       degree, degree + 1, n);
  }
  memcpy(c->ctrl, ctrl, n * (size_t)dim * sizeof(double));
  if (weights) memcpy(c->weights, weights, n * sizeof(double));
  if (knots) memcpy(c->knots, knots, (n + (size_t)degree + 1) * sizeof(double));
  else (void)bsfit_knots_clamped(degree, n, 0.0, 1.0, c->knots, NULL);
  c->periodic = periodic != 0;
  e = bsfit_curve_validate(c, st);
  if (e != BSFIT_OK) bsfit_curve_free(c);
  return e;
}

bsfit_err bsfit_curve_new_periodic(bsfit_curve *c, int degree, int dim, size_t N,
                                   const double *period, const double *ctrl,
                                   const double *weights, const bsfit_allocator *a,
                                   bsfit_status *st) {
  size_t p = (size_t)degree, i, d = (size_t)dim;
  bsfit_err e;
  if (ctrl == NULL) return bsfit__fail(st, BSFIT_EINVAL, "no control points");
  if (degree < 1 || N < 2 || N < p + 1)
    return bsfit__fail(st, BSFIT_EDEGREE,
                       "periodic curve of degree %d needs at least %zu distinct control points, got %zu",
                       degree, p + 1 > 2 ? p + 1 : 2, N);
  e = bsfit_curve_alloc(c, degree, dim, N + p, weights != NULL, a, st);
  if (e != BSFIT_OK) return e;
  if (period != NULL) {
    e = bsfit_knots_periodic(degree, N, period, c->knots, st);
  } else {
    for (i = 0; i < N + 2 * p + 1; i++) c->knots[i] = ((double)i - (double)p) / (double)N;
  }
  if (e != BSFIT_OK) {
    bsfit_curve_free(c);
    return e;
  }
  memcpy(c->ctrl, ctrl, N * d * sizeof(double));
  memcpy(c->ctrl + N * d, ctrl, p * d * sizeof(double));
  if (weights) {
    memcpy(c->weights, weights, N * sizeof(double));
    memcpy(c->weights + N, weights, p * sizeof(double));
  }
  c->periodic = 1;
  e = bsfit_curve_validate(c, st);
  if (e != BSFIT_OK) bsfit_curve_free(c);
  return e;
}

bsfit_err bsfit_curve_new_bezier(bsfit_curve *c, int dim, size_t n, const double *ctrl,
                                 const double *weights, const bsfit_allocator *a,
                                 bsfit_status *st) {
  bsfit_err e;
  if (n == 0 || n > BSFIT_MAX_DEGREE + 1)
    return bsfit__fail(st, BSFIT_EDEGREE, "a Bezier curve needs 1..%d control points, got %zu",
                       BSFIT_MAX_DEGREE + 1, n);
  e = bsfit_curve_new(c, (int)n - 1, dim, n, NULL, ctrl, weights, 0, a, st);
  if (e == BSFIT_OK) c->bezier = 1;
  return e;
}

bsfit_err bsfit_curve_copy(const bsfit_curve *src, bsfit_curve *dst, const bsfit_allocator *a,
                           bsfit_status *st) {
  bsfit_err e = bsfit_curve_alloc(dst, src->degree, src->dim, src->n, src->weights != NULL,
                                  a ? a : &src->alloc, st);
  if (e != BSFIT_OK) return e;
  memcpy(dst->knots, src->knots, nknots_of(src) * sizeof(double));
  memcpy(dst->ctrl, src->ctrl, src->n * (size_t)src->dim * sizeof(double));
  if (src->weights) memcpy(dst->weights, src->weights, src->n * sizeof(double));
  dst->periodic = src->periodic;
  dst->bezier = src->bezier;
  return bsfit__ok(st);
}

void bsfit_curve_move(bsfit_curve *src, bsfit_curve *dst) {
  if (src == dst) return;
  bsfit_curve_free(dst);
  *dst = *src;
  bsfit_curve_init(src);
}

void bsfit_curve_domain(const bsfit_curve *c, double *a, double *b) {
  bsfit_knots_domain(c->knots, c->n, c->degree, a, b);
}

size_t bsfit_curve_distinct(const bsfit_curve *c) {
  return c->periodic ? c->n - (size_t)c->degree : c->n;
}

double bsfit__curve_wrap(const bsfit_curve *c, double u) {
  double a, b, T;
  if (!c->periodic) return u;
  bsfit_curve_domain(c, &a, &b);
  T = b - a;
  if (u < a || u >= b) {
    u = a + fmod(u - a, T);
    if (u < a) u += T;
    if (u >= b) u = a; /* fmod rounding */
  }
  return u;
}

/* de Casteljau on homogeneous coordinates; n <= BSFIT_MAX_DEGREE+1 */
static void eval_bezier(const bsfit_curve *c, double u, double *out) {
  double q[(BSFIT_MAX_DEGREE + 1) * 5];
  size_t i, r, k, n = c->n, d = (size_t)c->dim, hd = d + 1;
  double a, b, t;
  bsfit_curve_domain(c, &a, &b);
  t = (u - a) / (b - a);
  for (i = 0; i < n; i++) {
    double w = c->weights ? c->weights[i] : 1.0;
    for (k = 0; k < d; k++) q[i * hd + k] = w * c->ctrl[i * d + k];
    q[i * hd + d] = w;
  }
  for (r = 1; r < n; r++)
    for (i = 0; i < n - r; i++)
      for (k = 0; k < hd; k++) q[i * hd + k] = (1.0 - t) * q[i * hd + k] + t * q[(i + 1) * hd + k];
  for (k = 0; k < d; k++) out[k] = q[k] / q[d];
}

void bsfit__curve_eval_unchecked(const bsfit_curve *c, double u, double *out) {
  double N[BSFIT_MAX_DEGREE + 1];
  size_t s, j, k, d = (size_t)c->dim, p = (size_t)c->degree;
  if (c->bezier) {
    eval_bezier(c, u, out);
    return;
  }
  u = bsfit__curve_wrap(c, u);
  s = bsfit_knots_find_span(c->knots, c->n, c->degree, u);
  bsfit_basis_funs(s, u, c->degree, c->knots, N);
  for (k = 0; k < d; k++) out[k] = 0.0;
  if (c->weights == NULL) {
    for (j = 0; j <= p; j++) {
      const double *P = c->ctrl + (s - p + j) * d;
      for (k = 0; k < d; k++) out[k] += N[j] * P[k];
    }
  } else {
    double wsum = 0.0;
    for (j = 0; j <= p; j++) {
      const double *P = c->ctrl + (s - p + j) * d;
      double nw = N[j] * c->weights[s - p + j];
      for (k = 0; k < d; k++) out[k] += nw * P[k];
      wsum += nw;
    }
    for (k = 0; k < d; k++) out[k] /= wsum;
  }
}

int bsfit__curve_reach(const bsfit_curve *c, double u) {
  double a, b;
  if (c->periodic) return isfinite(u);
  bsfit_curve_domain(c, &a, &b);
  return u >= a - (b - a) && u <= b + (b - a);
}

bsfit_err bsfit_curve_eval(const bsfit_curve *c, double u, double *out, bsfit_status *st) {
  if (!isfinite(u)) return bsfit__fail(st, BSFIT_ENONFINITE, "parameter is not finite");
  if (!bsfit__curve_reach(c, u))
    return bsfit__fail(st, BSFIT_EDOMAIN,
                       "parameter %g is more than one domain length outside the domain", u);
  bsfit__curve_eval_unchecked(c, u, out);
  if (!bsfit__all_finite(out, (size_t)c->dim))
    return bsfit__fail(st, BSFIT_ERANGE, "C(%g) overflows (extrapolated)", u);
  return bsfit__ok(st);
}
