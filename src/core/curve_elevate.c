/*
** curve_elevate.c
** Degree elevation: the Bézier formula for Bézier curves, blossoms one degree at a time
** for clamped B-splines (every distinct knot gains exactly t copies; stable next to
** clustered knots, where A5.9's knot removal was not), and unrolling for periodic ones.
*/
#include "curve_ops_internal.h"

#include <string.h>

/* dst = alpha x + (1 - alpha) y; dst may be x or y */
static void lerp(double *dst, double alpha, const double *x, const double *y, size_t hd) {
  size_t k;
  for (k = 0; k < hd; k++) dst[k] = alpha * x[k] + (1.0 - alpha) * y[k];
}

/* {====================================================================
** Bézier curves
** ===================================================================== */

/* One step p -> p+1: Q_i = i/(p+1) P_{i-1} + (1 - i/(p+1)) P_i, in place (P has room). */
static void bezier_elevate_once(double *P, int p, size_t hd) {
  long i;
  memcpy(P + (size_t)(p + 1) * hd, P + (size_t)p * hd, hd * sizeof(double));
  for (i = p; i >= 1; i--) {
    double alpha = (double)i / (double)(p + 1);
    lerp(P + (size_t)i * hd, alpha, P + (size_t)(i - 1) * hd, P + (size_t)i * hd, hd);
  }
}

static bsfit_err elevate_bezier(const bsfit_curve *c, int t, bsfit_curve *out, bsfit_status *st) {
  int q = c->degree + t, j;
  size_t i;
  double a, b;
  bsfit__hcurve h, e2;
  bsfit_err e = bsfit__hc_from_curve(c, &h, st);
  if (e != BSFIT_OK) return e;
  e = bsfit__hc_alloc(&e2, q, h.hd, (size_t)q + 1, &c->alloc, st);
  if (e == BSFIT_OK) {
    memcpy(e2.P, h.P, h.n * (size_t)h.hd * sizeof(double));
    for (j = c->degree; j < q; j++) bezier_elevate_once(e2.P, j, (size_t)h.hd);
    bsfit_curve_domain(c, &a, &b);
    for (i = 0; i <= (size_t)q; i++) {
      e2.U[i] = a;
      e2.U[(size_t)q + 1 + i] = b;
    }
    e = bsfit__hc_to_curve(&e2, c->dim, out, st);
    if (e == BSFIT_OK) out->bezier = c->bezier;
  }
  bsfit__hc_free(&h);
  bsfit__hc_free(&e2);
  return e;
}

/* }==================================================================== */

/* {====================================================================
** Clamped B-splines: one degree at a time, by blossoms
** ===================================================================== */

/* NURBS Book A5.9 folds knot removal into the elevation; removal divides by differences
** of knots, and next to a cluster (a knot 1e-12 from another) it came back wrong by 9e-5,
** or with negative weights. Here each elevated control point comes straight from the
** blossom b of the curve (Ramshaw): raising p to p+1 on the knots v (each run of the old
** vector one copy longer),
**   Q_i = 1/(p+1) sum_{j=1..p+1} b(v_{i+1}, .., v_{i+j} left out, .., v_{i+p+1}),
** with b the blossom of the polynomial piece on any span inside Q_i's support
** [v_i, v_{i+p+2}]. De Boor's algorithm evaluates it with ratios whose denominators are at
** least that span's length: taking the longest span of the support keeps every ratio
** below about p + 2 whatever the clusters, so the result is exact to rounding. The cost is
** O(p^3) per control point and per degree raised. */

/* The blossom of h's piece on span s at x[0..p-1], homogeneous, into out (work: (p+1)hd) */
static void blossom(const bsfit__hcurve *h, size_t s, const double *x, double *work,
                    double *out) {
  size_t p = (size_t)h->p, hd = (size_t)h->hd, r, j;
  const double *U = h->U;
  memcpy(work, h->P + (s - p) * hd, (p + 1) * hd * sizeof(double));
  for (r = 1; r <= p; r++)
    for (j = p; j >= r; j--) {
      size_t i = s - p + j;
      double al = (x[r - 1] - U[i]) / (U[i + p + 1 - r] - U[i]);
      lerp(work + j * hd, al, work + j * hd, work + (j - 1) * hd, hd);
    }
  memcpy(out, work + p * hd, hd * sizeof(double));
}

/* The longest non-empty span s of h (p <= s < n) inside [lo, hi]; lo < hi are knots.
** *cur: the last s with U[s] <= lo, carried from the previous call (lo never decreases
** from one control point to the next): a step or two instead of a binary search. */
static size_t longest_span(const bsfit__hcurve *h, double lo, double hi, size_t *cur) {
  size_t s, best;
  double len = -1.0;
  while (*cur + 1 < h->n && h->U[*cur + 1] <= lo) (*cur)++;
  s = best = *cur;
  for (; s < h->n && h->U[s] < hi; s++) {
    double w = h->U[s + 1] - h->U[s];
    if (w > len && h->U[s] >= lo && h->U[s + 1] <= hi) {
      len = w;
      best = s;
    }
  }
  return best;
}

/* Number of knots after one elevation: each run of equal knots gains a copy. */
static size_t elevated_knots(const bsfit__hcurve *h) {
  size_t i, nk = h->n + (size_t)h->p + 1, runs = 1;
  for (i = 1; i < nk; i++) runs += h->U[i] != h->U[i - 1];
  return nk + runs;
}

/* Q_i from the blossom (work: (p+2) hd + p + 1 doubles) */
static void elevated_point(const bsfit__hcurve *h, const double *V, size_t i, size_t *cur,
                           double *work, double *Q) {
  size_t p = (size_t)h->p, hd = (size_t)h->hd, j, k, c;
  size_t s = longest_span(h, V[i], V[i + p + 2], cur);
  double *x = work + (p + 2) * hd, *b = work + (p + 1) * hd;
  memset(Q, 0, hd * sizeof(double));
  for (j = 0; j <= p; j++) {
    for (k = 0, c = 0; k <= p; k++)
      if (k != j) x[c++] = V[i + 1 + k];
    blossom(h, s, x, work, b);
    for (c = 0; c < hd; c++) Q[c] += b[c];
  }
  for (c = 0; c < hd; c++) Q[c] /= (double)(p + 1);
}

/* h (clamped, interior multiplicities <= p) raised by one degree into e2 */
static bsfit_err elevate_once(const bsfit__hcurve *h, bsfit__hcurve *e2, bsfit_status *st) {
  size_t nk = h->n + (size_t)h->p + 1, nv = elevated_knots(h), hd = (size_t)h->hd, i, k = 0;
  size_t cur = (size_t)h->p;
  size_t wsize = ((size_t)h->p + 3) * hd + (size_t)h->p + 1;
  double *work;
  bsfit_err e = bsfit__hc_alloc(e2, h->p + 1, h->hd, nv - (size_t)h->p - 2, &h->alloc, st);
  if (e != BSFIT_OK) return e;
  work = bsfit__alloc(&h->alloc, wsize * sizeof(double));
  if (work == NULL) {
    bsfit__hc_free(e2);
    return bsfit__fail(st, BSFIT_ENOMEM, "out of memory for degree elevation");
  }
  for (i = 0; i < nk; i++) {
    e2->U[k++] = h->U[i];
    if (i + 1 == nk || h->U[i + 1] != h->U[i]) e2->U[k++] = h->U[i];
  }
  for (i = 0; i < e2->n; i++) {
    if ((i & 4095) == 4095 && bsfit__interrupted(&h->alloc)) {
      e = bsfit__fail(st, BSFIT_EINTR, "degree elevation interrupted");
      break;
    }
    elevated_point(h, e2->U, i, &cur, work, e2->P + i * hd);
  }
  bsfit__free(&h->alloc, work, wsize * sizeof(double));
  if (e != BSFIT_OK) bsfit__hc_free(e2);
  return e;
}

/* h raised by t degrees into e2, one at a time */
static bsfit_err elevate_clamped(const bsfit__hcurve *h, long t, bsfit__hcurve *e2,
                                 bsfit_status *st) {
  bsfit__hcurve cur, next;
  bsfit_err e = BSFIT_OK;
  long k;
  bsfit__hc_init(&cur);
  for (k = 0; k < t && e == BSFIT_OK; k++) {
    e = elevate_once(k == 0 ? h : &cur, &next, st);
    bsfit__hc_free(&cur);
    if (e == BSFIT_OK) cur = next;
  }
  if (e == BSFIT_OK) *e2 = cur;
  return e;
}

/* }==================================================================== */

/* {====================================================================
** Entry point
** ===================================================================== */

static bsfit_err check_interior_mult(const bsfit_curve *c, bsfit_status *st) {
  size_t i, run = 1, p = (size_t)c->degree, nk = c->n + p + 1;
  double a, b;
  bsfit_curve_domain(c, &a, &b);
  for (i = 1; i < nk; i++) {
    run = c->knots[i] == c->knots[i - 1] ? run + 1 : 1;
    if (run > p && c->knots[i] > a && c->knots[i] < b)
      return bsfit__fail(st, BSFIT_EMULT,
                         "interior knot %g has multiplicity %zu > degree %zu: curve not continuous",
                         c->knots[i], run, p);
  }
  return BSFIT_OK;
}

/* Period knots of the elevated periodic curve: every run of t[0..N-1] gains tt copies,
** except the run equal to t[N] (the seam's copy, already counted at t[0]). */
static size_t elevated_period(const double *t, size_t N, long tt, double *out) {
  size_t i, k = 0;
  long j;
  for (i = 0; i < N; i++) {
    out[k++] = t[i];
    if ((i + 1 == N || t[i + 1] != t[i]) && t[i] != t[N])
      for (j = 0; j < tt; j++) out[k++] = t[i];
  }
  out[k] = t[N];
  return k;
}

static bsfit_err elevate_spline(const bsfit_curve *c, long t, bsfit_curve *out,
                                bsfit_status *st) {
  size_t p = (size_t)c->degree, N = c->n - p, nt = (N + 1) * (size_t)(t + 1), N2;
  double a, b, *t2 = NULL;
  bsfit__hcurve h, piece, e2;
  bsfit_err e;
  bsfit__hc_init(&piece);
  bsfit__hc_init(&e2);
  bsfit_curve_domain(c, &a, &b);
  e = c->periodic ? bsfit__hc_unroll(c, &h, st) : bsfit__hc_from_curve(c, &h, st);
  if (e != BSFIT_OK) return e;
  if (c->periodic) {
    a = h.U[p];
    b = h.U[h.n];
  }
  /* A5.9 wants clamped ends: clamping is a no-op for clamped curves */
  e = bsfit__hc_piece(&h, a, b, &piece, st);
  if (e == BSFIT_OK) e = elevate_clamped(&piece, t, &e2, st);
  if (e == BSFIT_OK && !c->periodic) e = bsfit__hc_to_curve(&e2, c->dim, out, st);
  if (e == BSFIT_OK && c->periodic) {
    t2 = bsfit__alloc(&c->alloc, nt * sizeof(double));
    if (t2 == NULL) e = bsfit__fail(st, BSFIT_ENOMEM, "out of memory for periodic knots");
  }
  if (e == BSFIT_OK && c->periodic) {
    N2 = elevated_period(c->knots + p, N, t, t2);
    e = bsfit__hc_to_periodic(&e2, c->dim, t2, N2, out, st);
  }
  bsfit__free(&c->alloc, t2, nt * sizeof(double));
  bsfit__hc_free(&h);
  bsfit__hc_free(&piece);
  bsfit__hc_free(&e2);
  return e;
}

bsfit_err bsfit_curve_elevate(const bsfit_curve *c, int t, bsfit_curve *out, bsfit_status *st) {
  bsfit_curve tmp;
  bsfit_err e = bsfit_curve_validate(c, st);
  if (e != BSFIT_OK) return e;
  if (out == NULL) return bsfit__fail(st, BSFIT_EINVAL, "no output curve");
  if (t < 0) return bsfit__fail(st, BSFIT_EINVAL, "elevation t = %d is negative", t);
  if (t > BSFIT_MAX_DEGREE - c->degree)
    return bsfit__fail(st, BSFIT_EDEGREE, "degree %d + %d exceeds %d", c->degree, t,
                       BSFIT_MAX_DEGREE);
  if (t == 0) return out == c ? bsfit__ok(st) : bsfit_curve_copy(c, out, NULL, st);
  bsfit_curve_init(&tmp);
  e = c->bezier ? BSFIT_OK : check_interior_mult(c, st);
  /* a continuous degree-0 spline has one span: a constant, elevated like a Bézier curve */
  if (e == BSFIT_OK && (c->bezier || c->degree == 0)) e = elevate_bezier(c, t, &tmp, st);
  else if (e == BSFIT_OK) e = elevate_spline(c, t, &tmp, st);
  if (e == BSFIT_OK) e = bsfit__curve_result(&tmp, "degree elevation", st);
  if (e != BSFIT_OK) return e;
  bsfit_curve_move(&tmp, out);
  return bsfit__ok(st);
}

/* }==================================================================== */
