/*
** curve_elevate.c
** Degree elevation: the Bézier formula for Bézier curves, NURBS Book A5.9 (elevation of
** the Bézier segments with the knot removal folded in, so every distinct knot gains
** exactly t copies) for clamped B-splines, and unrolling for periodic ones.
*/
#include "curve_ops_internal.h"

#include <string.h>

static double binom(int n, int k) {
  double r = 1.0;
  int i;
  for (i = 1; i <= k; i++) r = r * (double)(n - k + i) / (double)i;
  return r;
}

static long lmin(long x, long y) { return x < y ? x : y; }
static long lmax(long x, long y) { return x > y ? x : y; }

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
** Clamped B-splines: NURBS Book A5.9
** ===================================================================== */

/* Workspace of A5.9, one block: bezalfs (ph+1)x(p+1), alfs, bpts, ebpts, nextbpts. */
typedef struct elev_work {
  double *bez, *alfs, *bpts, *ebpts, *next;
  size_t size;
} elev_work;

static bsfit_err work_alloc(elev_work *w, long p, long t, size_t hd, const bsfit_allocator *a,
                            bsfit_status *st) {
  size_t ph = (size_t)(p + t), np = (size_t)p;
  size_t nb = (ph + 1) * (np + 1), na = np + 1, n1 = (np + 1) * hd, n2 = (ph + 1) * hd;
  memset(w, 0, sizeof *w);
  w->size = (nb + na + n1 + n2 + n1) * sizeof(double);
  w->bez = bsfit__alloc(a, w->size);
  if (w->bez == NULL) return bsfit__fail(st, BSFIT_ENOMEM, "out of memory for degree elevation");
  memset(w->bez, 0, w->size);
  w->alfs = w->bez + nb;
  w->bpts = w->alfs + na;
  w->ebpts = w->bpts + n1;
  w->next = w->ebpts + n2;
  return BSFIT_OK;
}

/* Coefficients of the Bézier degree elevation p -> ph: bez[i][j] = C(p,j) C(t,i-j) / C(ph,i). */
static void bezier_alphas(long p, long t, double *bez) {
  long ph = p + t, i, j;
  for (i = 0; i <= ph; i++)
    for (j = lmax(0, i - t); j <= lmin(p, i); j++)
      bez[i * (p + 1) + j] = binom((int)p, (int)j) * binom((int)t, (int)(i - j)) /
                             binom((int)ph, (int)i);
}

/* Number of knots of the elevated vector: each run of equal knots gains t copies. */
static size_t elevated_knots(const bsfit__hcurve *h, long t) {
  size_t i, nk = h->n + (size_t)h->p + 1, runs = 1;
  for (i = 1; i < nk; i++) runs += h->U[i] != h->U[i - 1];
  return nk + runs * (size_t)t;
}

/* A5.9 on a clamped curve h (interior multiplicities <= p) into e2. Indices follow the
** book: n is the last control point, m the last knot. */
static bsfit_err elevate_clamped(const bsfit__hcurve *h, long t, bsfit__hcurve *e2,
                                 bsfit_status *st) {
  const long p = h->p, n = (long)h->n - 1, m = n + p + 1, ph = p + t;
  const size_t hd = (size_t)h->hd, bsz = hd * sizeof(double);
  const double *U = h->U, *Pw = h->P;
  double *Uh, *Qw, ua = U[0], ub;
  long mh = ph, kind = ph + 1, r = -1, a = p, b = p + 1, cind = 1, i, j, k;
  size_t nkh = elevated_knots(h, t);
  elev_work w;
  bsfit_err e = bsfit__hc_alloc(e2, (int)ph, h->hd, nkh - (size_t)ph - 1, &h->alloc, st);
  if (e != BSFIT_OK) return e;
  e = work_alloc(&w, p, t, hd, &h->alloc, st);
  if (e != BSFIT_OK) {
    bsfit__hc_free(e2);
    return e;
  }
#define PT(arr, idx) ((arr) + (size_t)(idx) * hd)
  Uh = e2->U;
  Qw = e2->P;
  bezier_alphas(p, t, w.bez);
  memcpy(Qw, Pw, bsz);
  for (i = 0; i <= ph; i++) Uh[i] = ua;
  memcpy(w.bpts, Pw, (size_t)(p + 1) * bsz);
  while (b < m) {
    long mul, oldr, lbz, rbz;
    i = b;
    while (b < m && U[b] == U[b + 1]) b++;
    mul = b - i + 1;
    mh += mul + t;
    ub = U[b];
    oldr = r;
    r = p - mul;
    lbz = oldr > 0 ? (oldr + 2) / 2 : 1;
    rbz = r > 0 ? ph - (r + 1) / 2 : ph;
    if (r > 0) { /* insert ub r times: the Bézier segment [ua, ub] */
      double numer = ub - ua;
      for (k = p; k > mul; k--) w.alfs[k - mul - 1] = numer / (U[a + k] - ua);
      for (j = 1; j <= r; j++) {
        long save = r - j, s = mul + j;
        for (k = p; k >= s; k--)
          lerp(PT(w.bpts, k), w.alfs[k - s], PT(w.bpts, k), PT(w.bpts, k - 1), hd);
        memcpy(PT(w.next, save), PT(w.bpts, p), bsz);
      }
    }
    for (i = lbz; i <= ph; i++) { /* elevate the segment */
      double *E = PT(w.ebpts, i);
      size_t q;
      memset(E, 0, bsz);
      for (j = lmax(0, i - t); j <= lmin(p, i); j++)
        for (q = 0; q < hd; q++) E[q] += w.bez[i * (p + 1) + j] * PT(w.bpts, j)[q];
    }
    if (oldr > 1) { /* remove the knot ua oldr times */
      long first = kind - 2, last = kind, tr;
      double den = ub - ua, bet = (ub - Uh[kind - 1]) / den;
      for (tr = 1; tr < oldr; tr++) {
        long ii = first, jj = last, kj = jj - kind + 1;
        while (jj - ii > tr) {
          if (ii < cind) {
            double alf = (ub - Uh[ii]) / (ua - Uh[ii]);
            lerp(PT(Qw, ii), alf, PT(Qw, ii), PT(Qw, ii - 1), hd);
          }
          if (jj >= lbz) {
            double gam = (jj - tr <= kind - ph + oldr) ? (ub - Uh[jj - tr]) / den : bet;
            lerp(PT(w.ebpts, kj), gam, PT(w.ebpts, kj), PT(w.ebpts, kj + 1), hd);
          }
          ii++;
          jj--;
          kj--;
        }
        first--;
        last++;
      }
    }
    if (a != p)
      for (i = 0; i < ph - oldr; i++) Uh[kind++] = ua;
    for (j = lbz; j <= rbz; j++) memcpy(PT(Qw, cind++), PT(w.ebpts, j), bsz);
    if (b < m) { /* next segment */
      for (j = 0; j < r; j++) memcpy(PT(w.bpts, j), PT(w.next, j), bsz);
      for (j = r; j <= p; j++) memcpy(PT(w.bpts, j), PT(Pw, b - p + j), bsz);
      a = b;
      b++;
      ua = ub;
    } else {
      for (i = 0; i <= ph; i++) Uh[kind + i] = ub;
    }
  }
#undef PT
  bsfit__free(&h->alloc, w.bez, w.size);
  (void)mh; /* mh + 1 == nkh: counted beforehand by elevated_knots */
  return BSFIT_OK;
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
