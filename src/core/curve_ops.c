/*
** curve_ops.c
** Operations that rebuild a curve without changing its shape or parametrisation:
** knot insertion and refinement, splitting, reversal. They run on the homogeneous
** working form of curve_hcurve.c; periodic curves are unrolled over three periods,
** processed as open curves, and folded back into the expanded periodic form.
*/
#include "curve_ops_internal.h"

#include <float.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

bsfit_err bsfit__curve_check(const bsfit_curve *c, bsfit_status *st) {
  if (c == NULL || c->ctrl == NULL || c->knots == NULL || c->n == 0)
    return bsfit__fail(st, BSFIT_EINVAL, "empty curve");
  if (c->dim < 1 || c->dim > 4)
    return bsfit__fail(st, BSFIT_EDIM, "dimension %d out of range 1..4", c->dim);
  if (c->degree < 0 || c->degree > BSFIT_MAX_DEGREE || c->n < (size_t)c->degree + 1)
    return bsfit__fail(st, BSFIT_EDEGREE, "degree %d invalid for %zu control points", c->degree,
                       c->n);
  return BSFIT_OK;
}

bsfit_err bsfit__curve_result(bsfit_curve *tmp, const char *op, bsfit_status *st) {
  bsfit_status vs;
  bsfit_err e = bsfit_curve_validate(tmp, &vs);
  if (e == BSFIT_OK) return BSFIT_OK;
  bsfit_curve_free(tmp);
  return bsfit__fail(st, e, "%s: the result would be invalid (%.80s)", op, vs.msg);
}

/* {====================================================================
** Knot refinement
** ===================================================================== */

static int cmp_double(const void *x, const void *y) {
  double a = *(const double *)x, b = *(const double *)y;
  return (a > b) - (a < b);
}

/* X finite, sorted, inside [a, b]; multiplicities after insertion within the limits. */
static bsfit_err check_new_knots(const bsfit_curve *c, const double *X, size_t nx,
                                 bsfit_status *st) {
  size_t i, j, nk = c->n + (size_t)c->degree + 1;
  double a, b;
  bsfit_curve_domain(c, &a, &b);
  for (i = 0; i < nx; i++) {
    if (!isfinite(X[i])) return bsfit__fail(st, BSFIT_ENONFINITE, "knot X[%zu] is not finite", i);
    if (i > 0 && X[i] < X[i - 1])
      return bsfit__fail(st, BSFIT_EKNOTS_DECR, "knots to insert decrease at X[%zu] = %g", i,
                         X[i]);
    if (X[i] < a || X[i] > b)
      return bsfit__fail(st, BSFIT_EDOMAIN, "knot X[%zu] = %g outside the domain [%g, %g]", i,
                         X[i], a, b);
  }
  for (i = 0; i < nx; i = j) {
    /* degree 0 has no continuity to keep: a new knot may appear once */
    int mult, limit = c->degree > 0 ? c->degree : 1;
    for (j = i; j < nx && X[j] == X[i]; j++) {}
    mult = bsfit_knots_multiplicity(c->knots, nk, X[i]) + (int)(j - i);
    if (!c->periodic && (X[i] == a || X[i] == b)) limit = c->degree + 1;
    if (mult > limit)
      return bsfit__fail(st, BSFIT_EMULT, "knot %g would have multiplicity %d > %d", X[i], mult,
                         limit);
  }
  return BSFIT_OK;
}

static bsfit_err refine_open(const bsfit_curve *c, const double *X, size_t nx, bsfit_curve *tmp,
                             bsfit_status *st) {
  bsfit__hcurve h, r;
  bsfit_err e;
  bsfit__hc_init(&r);
  e = bsfit__hc_from_curve(c, &h, st);
  if (e != BSFIT_OK) return e;
  e = bsfit__hc_refine(&h, X, nx, &r, st);
  if (e == BSFIT_OK) e = bsfit__hc_to_curve(&r, c->dim, tmp, st);
  /* one more knot always makes more than one span */
  if (e == BSFIT_OK) tmp->bezier = c->bezier && nx == 0;
  bsfit__hc_free(&h);
  bsfit__hc_free(&r);
  return e;
}

/* W: the nx knots wrapped into [a, b) and sorted; Xall: their images in the three
** unrolled periods; t: the new period knots (N+nx+1). All in one block `buf`. */
static bsfit_err refine_periodic(const bsfit_curve *c, const double *X, size_t nx,
                                 bsfit_curve *tmp, bsfit_status *st) {
  size_t p = (size_t)c->degree, N = c->n - p, i, j, k, nbuf = 5 * nx + N + 1;
  double a, b, T, *buf, *W, *Xall, *t;
  bsfit__hcurve h, r;
  bsfit_err e;
  bsfit_curve_domain(c, &a, &b);
  T = b - a;
  buf = bsfit__alloc(&c->alloc, nbuf * sizeof(double));
  if (buf == NULL) return bsfit__fail(st, BSFIT_ENOMEM, "out of memory for %zu knots", nx);
  W = buf;
  Xall = W + nx;
  t = Xall + 3 * nx;
  for (i = 0; i < nx; i++) W[i] = X[i] >= b ? a : X[i];
  qsort(W, nx, sizeof(double), cmp_double);
  for (i = 0; i < nx; i++) {
    Xall[i] = W[i] - T;
    Xall[nx + i] = W[i];
    Xall[2 * nx + i] = W[i] + T;
  }
  /* merge the period's knots t[0..N-1] with W, then close the period at b */
  for (i = 0, j = 0, k = 0; k < N + nx; k++)
    t[k] = (j >= nx || (i < N && c->knots[p + i] <= W[j])) ? c->knots[p + i++] : W[j++];
  t[N + nx] = b;
  bsfit__hc_init(&h);
  bsfit__hc_init(&r);
  e = bsfit__hc_unroll(c, &h, st);
  if (e == BSFIT_OK) e = bsfit__hc_refine(&h, Xall, 3 * nx, &r, st);
  if (e == BSFIT_OK) e = bsfit__hc_to_periodic(&r, c->dim, t, N + nx, tmp, st);
  bsfit__hc_free(&h);
  bsfit__hc_free(&r);
  bsfit__free(&c->alloc, buf, nbuf * sizeof(double));
  return e;
}

bsfit_err bsfit_curve_refine(const bsfit_curve *c, const double *X, size_t nx, bsfit_curve *out,
                             bsfit_status *st) {
  bsfit_curve tmp;
  bsfit_err e = bsfit_curve_validate(c, st);
  if (e != BSFIT_OK) return e;
  if (out == NULL) return bsfit__fail(st, BSFIT_EINVAL, "no output curve");
  if (X == NULL && nx > 0) return bsfit__fail(st, BSFIT_EINVAL, "no knots to insert");
  e = check_new_knots(c, X, nx, st);
  if (e != BSFIT_OK) return e;
  if (nx == 0 && out == c) return bsfit__ok(st);
  bsfit_curve_init(&tmp);
  e = c->periodic && nx > 0 ? refine_periodic(c, X, nx, &tmp, st)
                            : refine_open(c, X, nx, &tmp, st);
  if (e == BSFIT_OK) e = bsfit__curve_result(&tmp, "knot insertion", st);
  if (e != BSFIT_OK) return e;
  bsfit_curve_move(&tmp, out);
  return bsfit__ok(st);
}

bsfit_err bsfit_curve_insert_knot(const bsfit_curve *c, double u, int times, bsfit_curve *out,
                                  bsfit_status *st) {
  double X[BSFIT_MAX_DEGREE + 2];
  int i;
  bsfit_err e = bsfit__curve_check(c, st);
  if (e != BSFIT_OK) return e;
  if (times < 0) return bsfit__fail(st, BSFIT_EINVAL, "times = %d is negative", times);
  if (!isfinite(u)) return bsfit__fail(st, BSFIT_ENONFINITE, "knot u is not finite");
  /* more than p+1 copies can never be allowed: no need for a larger buffer */
  if (times > c->degree + 1)
    return bsfit__fail(st, BSFIT_EMULT, "inserting %d copies exceeds multiplicity %d", times,
                       c->degree + 1);
  if (c->periodic) u = bsfit__curve_wrap(c, u);
  for (i = 0; i < times; i++) X[i] = u;
  return bsfit_curve_refine(c, X, (size_t)times, out, st);
}

/* }==================================================================== */

/* {====================================================================
** Splitting
** ===================================================================== */

/* The part of c over [lo, hi] as a clamped curve (lo, hi within the open curve's domain). */
static bsfit_err open_piece(const bsfit_curve *c, double lo, double hi, bsfit_curve *out,
                            bsfit_status *st) {
  bsfit__hcurve h, piece;
  bsfit_err e;
  bsfit__hc_init(&piece);
  e = bsfit__hc_from_curve(c, &h, st);
  if (e == BSFIT_OK) e = bsfit__hc_piece(&h, lo, hi, &piece, st);
  if (e == BSFIT_OK) e = bsfit__hc_to_curve(&piece, c->dim, out, st);
  if (e == BSFIT_OK) out->bezier = c->bezier;
  bsfit__hc_free(&h);
  bsfit__hc_free(&piece);
  return e;
}

/* x moved onto the knot of U (nk sorted values) within a few ulps of it, if any: u + T
** rounds differently from the knot one period on (stored or unrolled as knot + T, and the
** period T itself rounded), and a cut an ulp beside a knot leaves a span an ulp wide. */
static double snap_to_knot(const double *U, size_t nk, double x, double T) {
  double tol = 8.0 * DBL_EPSILON * (fabs(x) + fabs(T));
  size_t lo = 0, hi = nk; /* the first knot >= x - tol, by bisection */
  while (lo < hi) {
    size_t mid = lo + (hi - lo) / 2;
    if (U[mid] < x - tol) lo = mid + 1;
    else hi = mid;
  }
  if (lo < nk && fabs(U[lo] - x) <= tol) return U[lo];
  return x;
}

/* One period [u, u+T] of a periodic curve as an open clamped curve that starts and ends
** at the same point. */
static bsfit_err periodic_piece(const bsfit_curve *c, double u, bsfit_curve *out,
                                bsfit_status *st) {
  double a, b;
  size_t d = (size_t)c->dim, last;
  bsfit__hcurve h, piece;
  bsfit_err e;
  bsfit_curve_domain(c, &a, &b);
  bsfit__hc_init(&piece);
  e = bsfit__hc_unroll(c, &h, st);
  if (e == BSFIT_OK) {
    size_t nk = h.n + (size_t)h.p + 1;
    e = bsfit__hc_piece(&h, snap_to_knot(h.U, nk, u, b - a),
                        snap_to_knot(h.U, nk, u + (b - a), b - a), &piece, st);
  }
  if (e == BSFIT_OK) e = bsfit__hc_to_curve(&piece, c->dim, out, st);
  if (e == BSFIT_OK) { /* equal up to rounding: make the closure exact */
    last = out->n - 1;
    memcpy(out->ctrl + last * d, out->ctrl, d * sizeof(double));
    if (out->weights) out->weights[last] = out->weights[0];
  }
  bsfit__hc_free(&h);
  bsfit__hc_free(&piece);
  return e;
}

bsfit_err bsfit_curve_split(const bsfit_curve *c, double u, bsfit_curve *left,
                            bsfit_curve *right, bsfit_status *st) {
  bsfit_curve l, r;
  double a, b;
  bsfit_err e = bsfit_curve_validate(c, st);
  if (e != BSFIT_OK) return e;
  if (left == NULL || (right == NULL && !c->periodic) || left == right)
    return bsfit__fail(st, BSFIT_EINVAL, "split needs two distinct output curves");
  if (!isfinite(u)) return bsfit__fail(st, BSFIT_ENONFINITE, "split parameter is not finite");
  bsfit_curve_domain(c, &a, &b);
  bsfit_curve_init(&l);
  bsfit_curve_init(&r);
  if (c->periodic) {
    e = periodic_piece(c, bsfit__curve_wrap(c, u), &l, st);
    if (e == BSFIT_OK) e = bsfit__curve_result(&l, "split", st);
    if (e != BSFIT_OK) return e;
    bsfit_curve_move(&l, left);
    if (right != NULL) bsfit_curve_free(right);
    return bsfit__ok(st);
  }
  if (!(u > a && u < b))
    return bsfit__fail(st, BSFIT_EDOMAIN, "split parameter %g not inside the domain (%g, %g)", u,
                       a, b);
  e = open_piece(c, a, u, &l, st);
  if (e == BSFIT_OK) e = open_piece(c, u, b, &r, st);
  if (e == BSFIT_OK) e = bsfit__curve_result(&l, "split", st);
  if (e == BSFIT_OK) e = bsfit__curve_result(&r, "split", st);
  if (e != BSFIT_OK) {
    bsfit_curve_free(&l);
    bsfit_curve_free(&r);
    return e;
  }
  bsfit_curve_move(&l, left);
  bsfit_curve_move(&r, right);
  return bsfit__ok(st);
}

/* }==================================================================== */

/* {====================================================================
** Reversal
** ===================================================================== */

/* a + b - x, computed from the nearer end so that a and b map exactly onto b and a */
static double mirror(double x, double a, double b) {
  return (x - a <= b - x) ? b - (x - a) : a + (b - x);
}

bsfit_err bsfit_curve_reverse(const bsfit_curve *c, bsfit_curve *out, bsfit_status *st) {
  bsfit_curve tmp;
  size_t i, k, n, d, nk;
  double a, b;
  bsfit_err e = bsfit_curve_validate(c, st);
  if (e != BSFIT_OK) return e;
  if (out == NULL) return bsfit__fail(st, BSFIT_EINVAL, "no output curve");
  n = c->n;
  d = (size_t)c->dim;
  nk = n + (size_t)c->degree + 1;
  bsfit_curve_domain(c, &a, &b);
  bsfit_curve_init(&tmp);
  e = bsfit_curve_alloc(&tmp, c->degree, c->dim, n, c->weights != NULL, &c->alloc, st);
  if (e != BSFIT_OK) return e;
  for (i = 0; i < nk; i++) {
    double v = mirror(c->knots[nk - 1 - i], a, b);
    tmp.knots[i] = (i > 0 && v < tmp.knots[i - 1]) ? tmp.knots[i - 1] : v;
  }
  for (i = 0; i < n; i++) {
    for (k = 0; k < d; k++) tmp.ctrl[i * d + k] = c->ctrl[(n - 1 - i) * d + k];
    if (c->weights) tmp.weights[i] = c->weights[n - 1 - i];
  }
  tmp.periodic = c->periodic;
  tmp.bezier = c->bezier;
  /* a knot within an ulp of an end mirrors onto the end (1 - 2e-99 == 1) and may pass
  ** its multiplicity: refuse rather than return an invalid curve */
  e = bsfit__curve_result(&tmp, "reverse", st);
  if (e != BSFIT_OK) return e;
  bsfit_curve_move(&tmp, out);
  return bsfit__ok(st);
}

/* }==================================================================== */
