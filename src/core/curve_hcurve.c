/*
** curve_hcurve.c
** The working form of the curve operations (see curve_ops_internal.h): conversion to and
** from homogeneous control points, unrolling a periodic curve over three periods, knot
** refinement (NURBS Book A5.4), extraction of a clamped piece, and re-assembly of the
** expanded periodic form.
*/
#include "curve_ops_internal.h"

#include <math.h>
#include <string.h>

/* {====================================================================
** Life cycle
** ===================================================================== */

void bsfit__hc_init(bsfit__hcurve *h) { memset(h, 0, sizeof *h); }

static size_t hc_nknots(const bsfit__hcurve *h) { return h->n + (size_t)h->p + 1; }

void bsfit__hc_free(bsfit__hcurve *h) {
  if (h == NULL) return;
  bsfit__free(&h->alloc, h->U, hc_nknots(h) * sizeof(double));
  bsfit__free(&h->alloc, h->P, h->n * (size_t)h->hd * sizeof(double));
  bsfit__hc_init(h);
}

bsfit_err bsfit__hc_alloc(bsfit__hcurve *h, int p, int hd, size_t n, const bsfit_allocator *a,
                          bsfit_status *st) {
  size_t nk = n + (size_t)p + 1, np = bsfit__mulsize(n, (size_t)hd * sizeof(double));
  bsfit__hc_init(h);
  if (np == 0 || bsfit__mulsize(nk, sizeof(double)) == 0)
    return bsfit__fail(st, BSFIT_EINVAL, "curve of %zu control points is too large", n);
  if (a != NULL) h->alloc = *a;
  h->p = p;
  h->hd = hd;
  h->n = n;
  h->U = bsfit__alloc(&h->alloc, nk * sizeof(double));
  h->P = bsfit__alloc(&h->alloc, np);
  if (h->U == NULL || h->P == NULL) {
    bsfit__hc_free(h);
    return bsfit__fail(st, BSFIT_ENOMEM, "out of memory for %zu control points", n);
  }
  return BSFIT_OK;
}

/* Control point i of c in homogeneous coordinates (or as is when polynomial). */
static void load_point(const bsfit_curve *c, size_t i, double *q) {
  size_t k, d = (size_t)c->dim;
  double w = c->weights ? c->weights[i] : 1.0;
  for (k = 0; k < d; k++) q[k] = w * c->ctrl[i * d + k];
  if (c->weights) q[d] = w;
}

bsfit_err bsfit__hc_from_curve(const bsfit_curve *c, bsfit__hcurve *h, bsfit_status *st) {
  size_t i, hd = (size_t)c->dim + (c->weights != NULL);
  bsfit_err e = bsfit__hc_alloc(h, c->degree, (int)hd, c->n, &c->alloc, st);
  if (e != BSFIT_OK) return e;
  memcpy(h->U, c->knots, hc_nknots(h) * sizeof(double));
  for (i = 0; i < c->n; i++) load_point(c, i, h->P + i * hd);
  return BSFIT_OK;
}

bsfit_err bsfit__hc_unroll(const bsfit_curve *c, bsfit__hcurve *h, bsfit_status *st) {
  size_t p = (size_t)c->degree, N = c->n - p, hd = (size_t)c->dim + (c->weights != NULL);
  size_t j, nk = c->n + p + 1; /* = N + 2p + 1 stored knots */
  double T = c->knots[N + p] - c->knots[p];
  bsfit_err e = bsfit__hc_alloc(h, c->degree, (int)hd, 3 * N + p, &c->alloc, st);
  if (e != BSFIT_OK) return e;
  /* control point j of the unrolled curve is P[(j - N) mod N] */
  for (j = 0; j < h->n; j++) load_point(c, j % N, h->P + j * hd);
  /* knots: one period shifted down, the stored knots, one period shifted up */
  for (j = 0; j < hc_nknots(h); j++) {
    double v;
    if (j < N) v = c->knots[j] - T;
    else if (j - N < nk) v = c->knots[j - N];
    else v = c->knots[j - 2 * N] + T;
    /* spans repeat only up to the validator's tolerance: keep the vector sorted */
    h->U[j] = (j > 0 && v < h->U[j - 1]) ? h->U[j - 1] : v;
  }
  return BSFIT_OK;
}

/* }==================================================================== */

/* {====================================================================
** Refinement and pieces
** ===================================================================== */

/* What A5.4 assumes and, when it does not hold, overruns its arrays: U sorted, X sorted
** and finite inside the domain [U[q], U[n]], no knot above multiplicity q + 1 after. */
static int refine_args_ok(int q, size_t n, const double *U, const double *X, size_t r) {
  size_t p = (size_t)q, i, j;
  for (i = 1; i < n + p + 1; i++)
    if (!(U[i] >= U[i - 1])) return 0;
  if (!(U[p] < U[n])) return 0;
  for (i = 0; i < r; i = j) {
    if (!(X[i] >= U[p] && X[i] <= U[n]) || (i > 0 && !(X[i] > X[i - 1]))) return 0;
    for (j = i; j < r && X[j] == X[i]; j++) {}
    if ((size_t)bsfit_knots_multiplicity(U, n + p + 1, X[i]) + (j - i) > p + 1) return 0;
  }
  return 1;
}

/* NURBS Book A5.4 with the book's last index n-1 and r knots X (declared in
** curve_ops_internal.h: also the exact filter's refinement of surface rows). */
int bsfit__refine_raw(int q, size_t n, size_t d, const double *U, const double *P,
                      const double *X, size_t r, double *Ub, double *Q) {
  size_t p = (size_t)q, m = n + p, a, b, j, row = d * sizeof(double);
  ptrdiff_t i, k, jj;
  if (!refine_args_ok(q, n, U, X, r)) return 0;
  if (r == 0) {
    memcpy(Ub, U, (n + p + 1) * sizeof(double));
    memcpy(Q, P, n * row);
    return 1;
  }
  a = bsfit_knots_find_span(U, n, q, X[0]);
  b = bsfit_knots_find_span(U, n, q, X[r - 1]) + 1;
  memcpy(Q, P, (a - p + 1) * row);
  memcpy(Q + (b - 1 + r) * d, P + (b - 1) * d, (n - b + 1) * row);
  memcpy(Ub, U, (a + 1) * sizeof(double));
  for (j = b + p; j <= m; j++) Ub[j + r] = U[j];
  i = (ptrdiff_t)(b + p) - 1;
  k = i + (ptrdiff_t)r;
  for (jj = (ptrdiff_t)r - 1; jj >= 0; jj--) {
    size_t l;
    while (X[jj] <= U[i] && i > (ptrdiff_t)a) {
      memcpy(Q + (size_t)(k - (ptrdiff_t)p - 1) * d, P + (size_t)(i - (ptrdiff_t)p - 1) * d, row);
      Ub[k] = U[i];
      k--;
      i--;
    }
    memcpy(Q + (size_t)(k - (ptrdiff_t)p - 1) * d, Q + (size_t)(k - (ptrdiff_t)p) * d, row);
    for (l = 1; l <= p; l++) {
      size_t ind = (size_t)k - p + l, c;
      double alfa = Ub[(size_t)k + l] - X[jj], *lo = Q + (ind - 1) * d, *hi = Q + ind * d;
      if (alfa == 0.0) {
        memcpy(lo, hi, row);
        continue;
      }
      alfa /= Ub[(size_t)k + l] - U[(size_t)i - p + l];
      for (c = 0; c < d; c++) lo[c] = alfa * lo[c] + (1.0 - alfa) * hi[c];
    }
    Ub[k] = X[jj];
    k--;
  }
  return 1;
}

/* }==================================================================== */

bsfit_err bsfit__hc_refine(const bsfit__hcurve *h, const double *X, size_t nx,
                           bsfit__hcurve *out, bsfit_status *st) {
  bsfit_err e = bsfit__hc_alloc(out, h->p, h->hd, h->n + nx, &h->alloc, st);
  if (e != BSFIT_OK) return e;
  if (!bsfit__refine_raw(h->p, h->n, (size_t)h->hd, h->U, h->P, X, nx, out->U, out->P)) {
    bsfit__hc_free(out);
    return bsfit__fail(st, BSFIT_EMULT,
                       "knot refinement: knots outside the domain, unsorted or above "
                       "multiplicity degree + 1");
  }
  return BSFIT_OK;
}

bsfit_err bsfit__hc_piece(const bsfit__hcurve *h, double lo, double hi, bsfit__hcurve *out,
                          bsfit_status *st) {
  size_t p = (size_t)h->p, hd = (size_t)h->hd, nk, i, f, g, nlo, nhi, nx = 0, np;
  int slo = bsfit_knots_multiplicity(h->U, hc_nknots(h), lo);
  int shi = bsfit_knots_multiplicity(h->U, hc_nknots(h), hi);
  double X[2 * BSFIT_MAX_DEGREE];
  bsfit__hcurve R;
  bsfit_err e;
  /* raise both ends to multiplicity p: the control points there are C(lo), C(hi) */
  nlo = slo < h->p ? p - (size_t)slo : 0;
  nhi = shi < h->p ? p - (size_t)shi : 0;
  for (i = 0; i < nlo; i++) X[nx++] = lo;
  for (i = 0; i < nhi; i++) X[nx++] = hi;
  e = bsfit__hc_refine(h, X, nx, &R, st);
  if (e != BSFIT_OK) return e;
  nk = hc_nknots(&R);
  for (f = 0; f + 1 < nk && R.U[f + 1] <= lo; f++) {}
  for (g = f + 1; g < nk && R.U[g] < hi; g++) {}
  /* knots [lo]*(p+1), R.U[f+1 .. g-1], [hi]*(p+1); control points R.P[f-p .. g-1] */
  np = g - f + p;
  e = bsfit__hc_alloc(out, h->p, h->hd, np, &h->alloc, st);
  if (e == BSFIT_OK) {
    for (i = 0; i <= p; i++) {
      out->U[i] = lo;
      out->U[np + i] = hi;
    }
    memcpy(out->U + p + 1, R.U + f + 1, (g - f - 1) * sizeof(double));
    memcpy(out->P, R.P + (f - p) * hd, np * hd * sizeof(double));
  }
  bsfit__hc_free(&R);
  return e;
}

/* }==================================================================== */

/* {====================================================================
** Back to curves
** ===================================================================== */

/* Cartesian point and weight from a homogeneous one. */
static void store_point(const bsfit__hcurve *h, size_t src, size_t i, int dim, bsfit_curve *c) {
  size_t k, d = (size_t)dim;
  const double *q = h->P + src * (size_t)h->hd;
  if (c->weights == NULL) {
    memcpy(c->ctrl + i * d, q, d * sizeof(double));
    return;
  }
  c->weights[i] = q[d];
  for (k = 0; k < d; k++) c->ctrl[i * d + k] = q[k] / q[d];
}

bsfit_err bsfit__hc_to_curve(const bsfit__hcurve *h, int dim, bsfit_curve *out,
                             bsfit_status *st) {
  size_t i;
  bsfit_err e = bsfit_curve_alloc(out, h->p, dim, h->n, h->hd > dim, &h->alloc, st);
  if (e != BSFIT_OK) return e;
  memcpy(out->knots, h->U, hc_nknots(h) * sizeof(double));
  for (i = 0; i < h->n; i++) store_point(h, i, i, dim, out);
  return BSFIT_OK;
}

/* Offset o with h->U[o + j] == V[j] (to tol) for all j < nv, or SIZE_MAX. tol must stay
** below half of V's shortest span, or a shifted offset could match too. */
static size_t find_run(const bsfit__hcurve *h, const double *V, size_t nv, double tol) {
  size_t o, j, nk = hc_nknots(h);
  for (o = 0; o + nv <= nk; o++) {
    for (j = 0; j < nv && fabs(h->U[o + j] - V[j]) <= tol; j++) {}
    if (j == nv) return o;
  }
  return (size_t)-1;
}

/* How far the result's knots may sit from t's period copies: the rounding of t[i] + T
** (a few ulps of the knots' magnitude, plus a relative slack of the period), but under a
** quarter of the shortest span, so that only the right offset matches. A relative
** tolerance of the magnitude alone (1e-10 |t|) matched knots near 4.3e11 spaced by 3 at
** the wrong offset and returned another curve (fuzz input item6-...-3-moves). */
static double periodic_match_tol(const double *t, size_t N) {
  double tol = bsfit__periodic_span_tol(t[0], t[N]);
  size_t i;
  for (i = 1; i <= N; i++)
    if (t[i] > t[i - 1] && tol > 0.25 * (t[i] - t[i - 1])) tol = 0.25 * (t[i] - t[i - 1]);
  return tol;
}

bsfit_err bsfit__hc_to_periodic(const bsfit__hcurve *h, int dim, const double *t, size_t N,
                                bsfit_curve *out, bsfit_status *st) {
  size_t p = (size_t)h->p, d = (size_t)dim, o, i;
  double tol = periodic_match_tol(t, N);
  bsfit_curve tmp;
  bsfit_err e;
  bsfit_curve_init(&tmp);
  e = bsfit_curve_alloc(&tmp, h->p, dim, N + p, h->hd > dim, &h->alloc, st);
  if (e == BSFIT_OK) e = bsfit_knots_periodic(h->p, N, t, tmp.knots, st);
  if (e != BSFIT_OK) {
    bsfit_curve_free(&tmp);
    return e;
  }
  /* bsfit_knots_periodic shifts by T = t[N] - t[0]; t[0] + T may round below t[N], which
  ** would make a repeated seam knot decrease by an ulp: keep the vector sorted */
  for (i = 1; i < N + 2 * p + 1; i++)
    if (tmp.knots[i] < tmp.knots[i - 1]) tmp.knots[i] = tmp.knots[i - 1];
  o = find_run(h, tmp.knots, N + 2 * p + 1, tol);
  if (o == (size_t)-1 || o + N + p > h->n) {
    bsfit_curve_free(&tmp);
    return bsfit__fail(st, BSFIT_ENOTPERIODIC, "periodic knots of the result not found");
  }
  for (i = 0; i < N + p; i++) store_point(h, o + i, i, dim, &tmp);
  /* the wrapped points equal their originals exactly, as the periodic form requires */
  memcpy(tmp.ctrl + N * d, tmp.ctrl, p * d * sizeof(double));
  if (tmp.weights) memcpy(tmp.weights + N, tmp.weights, p * sizeof(double));
  tmp.periodic = 1;
  bsfit_curve_move(&tmp, out);
  return BSFIT_OK;
}

/* }==================================================================== */
