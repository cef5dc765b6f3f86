/*
** filter_exact.c
** The exact box filter of a spline with any knot vector, the case Persiano's paper
** leaves "in progress" (F section 5): with I the antiderivative of the curve extended
** by its end control points, C_F(t) = (I(t + delta) - I(t - delta)) / (2 delta); both
** shifted copies of I are brought to one knot vector by knot refinement (NURBS Book
** A5.4, written here for points of any dimension, since surfaces are filtered as
** curves whose points are whole rows of the control net) and subtracted.
** Closed curves are unwrapped over a few periods, filtered as open curves, and one
** period of the result is read back in expanded periodic form.
*/
#include "filter_internal.h"
#include "curve_ops_internal.h"
#include "../bsfit_filter.h"

#include <float.h>
#include <math.h>
#include <string.h>

/* {====================================================================
** Scratch memory: every array of one computation, released in one place
** ===================================================================== */

#define MAX_SCRATCH 12

typedef struct scratch {
  const bsfit_allocator *a;
  int count;
  double *ptr[MAX_SCRATCH];
  size_t size[MAX_SCRATCH];
} scratch;

static double *scratch_get(scratch *s, size_t n, size_t d) {
  size_t bytes = bsfit__mulsize(bsfit__mulsize(n, d), sizeof(double));
  double *p;
  if (bytes == 0 || s->count == MAX_SCRATCH) return NULL;
  p = bsfit__alloc(s->a, bytes);
  if (p != NULL) {
    s->ptr[s->count] = p;
    s->size[s->count++] = bytes;
  }
  return p;
}

static void scratch_release(scratch *s) {
  while (s->count > 0) {
    s->count--;
    bsfit__free(s->a, s->ptr[s->count], s->size[s->count]);
  }
}

/* }==================================================================== */


/* {====================================================================
** Open splines
** ===================================================================== */

/* The end-rule extension as a clamped spline on [L, R] extended by constants
** (bsfit_filter.h): knots W = [L x (p+1), U_{1+r} .. U_{n+p-1-r'}, R x (p+1)] and
** points Q = [V^0 x lead, V^1 .. V^{n-2}, V^{n-1} x trail]. Q is not stored: q_index
** maps an index of Q to one of V. */
typedef struct clamped_ext {
  double L, R;
  size_t first, last; /* interior knots U[first..last] (last < first when none) */
  size_t lead, m;     /* copies of V^0 at the start; number of points of Q */
} clamped_ext;

static bsfit_err make_clamped_ext(const bsfit__fview *in, clamped_ext *x, bsfit_status *st) {
  size_t p = (size_t)in->p, n = in->n, r = 0, r2 = 0, i;
  const double *U = in->U;
  memset(x, 0, sizeof *x);
  if (p == 0) {
    x->L = U[0];
    x->R = U[n];
  } else {
    x->L = U[1];
    x->R = U[n + p - 1];
    for (i = 1; i <= n + p - 1 && U[i] == x->L; i++) r++;
    for (i = n + p - 1; i >= 1 && U[i] == x->R; i--) r2++;
    if (r > p || r2 > p)
      return bsfit__fail(st, BSFIT_EMULT,
                         "knot %g has multiplicity %d next to the domain's %s: the end control "
                         "point is unused and the end rule would jump",
                         r > p ? x->L : x->R, (int)p + 1, r > p ? "start" : "end");
  }
  x->first = 1 + r;
  x->last = n + p - 1 - r2;
  x->lead = p - r + 1;
  x->m = n + 2 * p - r - r2;
  return BSFIT_OK;
}

static size_t q_index(const clamped_ext *x, size_t n, size_t j) {
  if (j < x->lead) return 0;
  j = j - x->lead + 1;
  return j < n ? j : n - 1;
}

/* W' = [L, W, R]: the clamped knots of the antiderivative (degree p+1), m+p+3 of them */
static void antiderivative_knots(const bsfit__fview *in, const clamped_ext *x, double *Wp) {
  size_t p = (size_t)in->p, j, at = 0;
  for (j = 0; j < p + 2; j++) Wp[at++] = x->L;
  for (j = x->first; j <= x->last; j++) Wp[at++] = in->U[j];
  for (j = 0; j < p + 2; j++) Wp[at++] = x->R;
}

/* ctr = the middle of the control points' bounding box. The filter keeps constants, so it
** runs on V - ctr and adds ctr back: the antiderivative then grows with the spread of the
** points, not with their distance from the origin, and so does its rounding. */
static void centre(const bsfit__fview *in, double *ctr) {
  size_t i, c, d = in->d;
  for (c = 0; c < d; c++) {
    double lo = in->P[c], hi = in->P[c];
    for (i = 1; i < in->n; i++) {
      lo = fmin(lo, in->P[i * d + c]);
      hi = fmax(hi, in->P[i * d + c]);
    }
    ctr[c] = 0.5 * lo + 0.5 * hi;
  }
}

/* J^0 = 0, J^i = J^{i-1} + Q^{i-1} (W_{i+p} - W_{i-1}) / (p+1), W = W' without its ends;
** Q centred on ctr */
static void antiderivative_points(const bsfit__fview *in, const clamped_ext *x, const double *Wp,
                                  const double *ctr, double *J) {
  size_t p = (size_t)in->p, d = in->d, i, c;
  memset(J, 0, d * sizeof(double));
  for (i = 1; i <= x->m; i++) {
    const double *Q = in->P + q_index(x, in->n, i - 1) * d;
    double w = (Wp[i + p + 1] - Wp[i]) / (double)(p + 1);
    for (c = 0; c < d; c++) J[i * d + c] = J[(i - 1) * d + c] + w * (Q[c] - ctr[c]);
  }
}

/* A+(t) = I(t + delta) on [L - delta, R + delta]: I on knots W' - delta joined (C^0,
** knot multiplicity q at R - delta) with the linear piece I(R) + V^{n-1} (t + delta - R)
** written as a Bezier segment of degree q on [R - delta, R + delta]. */
static void shifted_plus(const bsfit__fview *in, const clamped_ext *x, const double *Wp,
                         const double *J, const double *ctr, double delta, double *K, double *A) {
  size_t q = (size_t)in->p + 1, d = in->d, m = x->m, j, c;
  const double *last = in->P + (in->n - 1) * d, *Jm = J + m * d;
  for (j = 0; j <= m + q; j++) K[j] = Wp[j] - delta;
  for (j = 0; j <= q; j++) K[m + q + 1 + j] = x->R + delta;
  memcpy(A, J, (m + 1) * d * sizeof(double));
  for (j = 1; j <= q; j++)
    for (c = 0; c < d; c++)
      A[(m + j) * d + c] = Jm[c] + (last[c] - ctr[c]) * (2.0 * delta * (double)j / (double)q);
}

/* A-(t) = I(t - delta): the linear piece V^0 (t - delta - L) on [L - delta, L + delta],
** then I on knots W' + delta. */
static void shifted_minus(const bsfit__fview *in, const clamped_ext *x, const double *Wp,
                          const double *J, const double *ctr, double delta, double *K,
                          double *A) {
  size_t q = (size_t)in->p + 1, d = in->d, m = x->m, j, c;
  const double *first = in->P;
  for (j = 0; j <= q; j++) K[j] = x->L - delta;
  for (j = 1; j <= m + q + 1; j++) K[q + j] = Wp[j] + delta;
  for (j = 0; j < q; j++)
    for (c = 0; c < d; c++)
      A[j * d + c] = -(first[c] - ctr[c]) * (2.0 * delta * (double)(q - j) / (double)q);
  memcpy(A + q * d, J, (m + 1) * d * sizeof(double));
}

/* The result is a difference of two antiderivatives divided by 2 delta: their rounding,
** about eps (R - L) times the spread of the control points, is amplified by (R - L) /
** delta. Below BSFIT_FILTER_MIN_DELTA (2^-24) of the domain that reaches 1e-9 of the
** spread, and u - delta, u + delta must stay distinct knots: refuse such windows (they
** change the curve by delta^2 |C''| / 6, less than its rounding, anyway). */
static bsfit_err check_resolution(const clamped_ext *x, double delta, bsfit_status *st) {
  double len = x->R - x->L, dmin;
  dmin = BSFIT_FILTER_MIN_DELTA * len + 1048576.0 * DBL_EPSILON * fmax(fabs(x->L), fabs(x->R));
  if (delta < dmin)
    return bsfit__fail(st, BSFIT_EDOMAIN,
                       "delta = %g is below the exact filter's resolution %g (2^-24 of "
                       "the domain length %g): rounding would swamp it",
                       delta, dmin, len);
  return BSFIT_OK;
}

/* Smallest positive gap between consecutive knots of K (nk of them); HUGE_VAL if none. */
static double min_gap(const double *K, size_t nk) {
  double g = HUGE_VAL;
  size_t i;
  for (i = 1; i < nk; i++)
    if (K[i] > K[i - 1] && K[i] - K[i - 1] < g) g = K[i] - K[i - 1];
  return g;
}

/* Knots u_i + delta and u_j - delta that coincide in exact arithmetic (uniform spacing)
** differ here by a few ulps: every knot of Km within tol of a knot of Kp takes that
** knot's value, all its copies alike. The caller keeps tol below a quarter of every
** positive gap in Kp and Km, so at most one knot of Kp is in reach, the map keeps Km
** sorted, and no two distinct knots of one vector become one (no multiplicity grows). */
static void snap_knots(const double *Kp, double *Km, size_t nk, double tol) {
  size_t i = 0, j;
  for (j = 0; j < nk; j++) {
    while (i + 1 < nk && Kp[i] < Km[j] - tol) i++;
    if (fabs(Kp[i] - Km[j]) <= tol) Km[j] = Kp[i];
  }
}

/* T = the union of the sorted multisets Kp and Km (each value with the larger of its two
** multiplicities); Xp and Xm receive the knots of T missing from Kp and from Km. */
static size_t union_knots(const double *Kp, const double *Km, size_t nk, double *T, double *Xp,
                          size_t *nxp, double *Xm, size_t *nxm) {
  size_t i = 0, j = 0, nt = 0;
  *nxp = *nxm = 0;
  while (i < nk || j < nk) {
    if (j >= nk || (i < nk && Kp[i] < Km[j])) {
      Xm[(*nxm)++] = Kp[i];
      T[nt++] = Kp[i++];
    } else if (i >= nk || Km[j] < Kp[i]) {
      Xp[(*nxp)++] = Km[j];
      T[nt++] = Km[j++];
    } else {
      T[nt++] = Kp[i++];
      j++;
    }
  }
  return nt;
}

bsfit_err bsfit__filter_exact_open(const bsfit__fview *in, double delta,
                                   const bsfit_allocator *a, bsfit__fspline *out,
                                   bsfit_status *st) {
  size_t q = (size_t)in->p + 1, d = in->d, nk, nA, nt, nxp, nxm, i;
  double *Wp, *J, *Kp, *Km, *Ap, *Am, *T, *Xp, *Xm, *Rm, *ctr, tol, inv;
  clamped_ext x;
  scratch s;
  bsfit_err e = make_clamped_ext(in, &x, st);
  if (e == BSFIT_OK) e = check_resolution(&x, delta, st);
  if (e != BSFIT_OK) return e;
  nA = x.m + q + 1;
  nk = nA + q + 1;
  memset(&s, 0, sizeof s);
  s.a = a;
  Wp = scratch_get(&s, x.m + q + 2, 1);
  J = scratch_get(&s, x.m + 1, d);
  Kp = scratch_get(&s, nk, 1);
  Km = scratch_get(&s, nk, 1);
  Ap = scratch_get(&s, nA, d);
  Am = scratch_get(&s, nA, d);
  T = scratch_get(&s, 2 * nk, 1);
  Xp = scratch_get(&s, nk, 1);
  Xm = scratch_get(&s, nk, 1);
  ctr = scratch_get(&s, d, 1);
  if (!Wp || !J || !Kp || !Km || !Ap || !Am || !T || !Xp || !Xm || !ctr) {
    scratch_release(&s);
    return bsfit__fail(st, BSFIT_ENOMEM, "out of memory filtering %zu control points", in->n);
  }
  antiderivative_knots(in, &x, Wp);
  if (bsfit__interrupted(a)) { /* each phase below is O(n): look between them */
    scratch_release(&s);
    return bsfit__fail(st, BSFIT_EINTR, "filter interrupted");
  }
  centre(in, ctr);
  antiderivative_points(in, &x, Wp, ctr, J);
  shifted_plus(in, &x, Wp, J, ctr, delta, Kp, Ap);
  shifted_minus(in, &x, Wp, J, ctr, delta, Km, Am);
  /* rounding of the shifts is a few ulps of the knots; a tolerance that reached a gap
  ** between distinct knots (2 delta between u - delta and u + delta, or clustered knots)
  ** would merge knots that differ, and the refinements would then overrun */
  tol = 64.0 * DBL_EPSILON * (fabs(x.L) + fabs(x.R) + 2.0 * delta);
  tol = fmin(tol, 0.25 * fmin(min_gap(Kp, nk), min_gap(Km, nk)));
  snap_knots(Kp, Km, nk, tol);
  nt = union_knots(Kp, Km, nk, T, Xp, &nxp, Xm, &nxm);
  e = bsfit__fspline_alloc(a, out, (int)q, nt - q - 1, d, st);
  Rm = e == BSFIT_OK ? scratch_get(&s, nt - q - 1, d) : NULL;
  if (e == BSFIT_OK && Rm == NULL) {
    bsfit__fspline_free(a, out);
    e = bsfit__fail(st, BSFIT_ENOMEM, "out of memory filtering %zu control points", in->n);
  }
  if (e == BSFIT_OK && bsfit__interrupted(a)) {
    bsfit__fspline_free(a, out);
    e = bsfit__fail(st, BSFIT_EINTR, "filter interrupted");
  }
  if (e != BSFIT_OK) {
    scratch_release(&s);
    return e;
  }
  if (!bsfit__refine_raw((int)q, nA, d, Kp, Ap, Xp, nxp, out->U, out->P) ||
      !bsfit__refine_raw((int)q, nA, d, Km, Am, Xm, nxm, T, Rm)) { /* T rebuilt identical */
    bsfit__fspline_free(a, out);
    scratch_release(&s);
    return bsfit__fail(st, BSFIT_EDOMAIN,
                       "delta = %g is too small for the knots of this curve", delta);
  }
  inv = 1.0 / (2.0 * delta);
  for (i = 0; i < out->n * d; i++) out->P[i] = (out->P[i] - Rm[i]) * inv + ctr[i % d];
  scratch_release(&s);
  return bsfit__ok(st);
}

/* }==================================================================== */

/* {====================================================================
** Periodic splines
** ===================================================================== */

/* Knot t_j of the periodic sequence, j any integer: U[p + (j mod N)] + floor(j/N) T */
static double periodic_knot(const bsfit__fview *in, size_t N, long j) {
  size_t p = (size_t)in->p;
  long m = j % (long)N, fl = j / (long)N;
  double T = in->U[p + N] - in->U[p];
  if (m < 0) {
    m += (long)N;
    fl--;
  }
  return in->U[p + (size_t)m] + (double)fl * T;
}

/* How many knot spans the periodic curve is unwrapped by on each side: enough for the
** kernel's reach `reach` (order * delta: the open filter differs from the periodic one only
** that near the ends of what it is given), plus p + 2 spans for the end rule's ramp.
** Walking the periodic knots from the period's start costs O(margin). */
static size_t margin_spans(const bsfit__fview *in, size_t N, double reach) {
  double lo = in->U[in->p], hi = in->U[in->p + N];
  size_t k = 0, K = 0;
  long j;
  for (j = 0; lo - periodic_knot(in, N, j) <= reach; j--) k++;
  for (j = (long)N; periodic_knot(in, N, j) - hi <= reach; j++) K++;
  return (k > K ? k : K) + (size_t)in->p + 2;
}

/* The periodic curve as an open one, K knot spans added before and after its period. */
static bsfit_err unwrap(const bsfit__fview *in, size_t N, size_t K, scratch *s,
                        bsfit__fview *open) {
  size_t p = (size_t)in->p, d = in->d, n = N + p + 2 * K, i;
  long i0 = -(long)K;
  double *U = scratch_get(s, n + p + 1, 1), *P = scratch_get(s, n, d);
  if (U == NULL || P == NULL) return BSFIT_ENOMEM;
  for (i = 0; i < n + p + 1; i++) {
    U[i] = periodic_knot(in, N, i0 - (long)p + (long)i);
    /* t + k T rounds: a knot an ulp from the seam can land past the next period's
    ** first one; keep the vector sorted (unwrapped_ok then checks the runs) */
    if (i > 0 && U[i] < U[i - 1]) U[i] = U[i - 1];
  }
  for (i = 0; i < n; i++) {
    long j = (i0 + (long)i) % (long)N;
    memcpy(P + i * d, in->P + (size_t)(j < 0 ? j + (long)N : j) * d, d * sizeof(double));
  }
  open->p = in->p;
  open->n = n;
  open->d = d;
  open->U = U;
  open->P = P;
  return BSFIT_OK;
}

/* One period [t0, t0 + T] of the open result f, t0 its first knot at or after a. */
static bsfit_err read_period(const bsfit__fspline *f, double a, double T, double tol,
                             const bsfit_allocator *al, scratch *s, bsfit__fspline *out,
                             bsfit_status *st) {
  size_t q = (size_t)f->p, d = f->d, nk = f->n + q + 1, j0 = 0, jE, N2, i;
  double *per;
  bsfit_err e;
  while (j0 < nk && f->U[j0] < a - tol) j0++;
  for (jE = j0; jE < nk && f->U[jE] < f->U[j0] + T - tol; jE++) continue;
  N2 = jE - j0;
  if (j0 < q || jE + q >= nk || N2 < q + 1)
    return bsfit__fail(st, BSFIT_ENOTPERIODIC,
                       "the filtered closed curve has %zu knot spans per period, fewer than "
                       "degree + 1 = %zu",
                       N2, q + 1);
  per = scratch_get(s, N2 + 1, 1);
  if (per == NULL) return bsfit__fail(st, BSFIT_ENOMEM, "out of memory for periodic knots");
  memcpy(per, f->U + j0, N2 * sizeof(double));
  per[N2] = per[0] + T;
  e = bsfit__fspline_alloc(al, out, (int)q, N2 + q, d, st);
  if (e != BSFIT_OK) return e;
  e = bsfit_knots_periodic((int)q, N2, per, out->U, st);
  if (e != BSFIT_OK) {
    bsfit__fspline_free(al, out);
    return e;
  }
  memcpy(out->P, f->P + (j0 - q) * d, N2 * d * sizeof(double));
  for (i = 0; i < q; i++) memcpy(out->P + (N2 + i) * d, out->P + i * d, d * sizeof(double));
  return BSFIT_OK;
}

/* Knots t + k T of the unwrapped periods round: a cluster of knots closer than that
** rounding can collapse into a run longer than degree + 1, which no spline has. */
static int unwrapped_ok(const bsfit__fview *open) {
  size_t i, run = 1, nk = open->n + (size_t)open->p + 1;
  for (i = 1; i < nk; i++) {
    run = open->U[i] == open->U[i - 1] ? run + 1 : 1;
    if (run > (size_t)open->p + 1) return 0;
  }
  return 1;
}

/* `order` exact passes on the open spline in, each pass's input freed once read. */
static bsfit_err open_passes(const bsfit__fview *in, int order, double delta,
                             const bsfit_allocator *a, bsfit__fspline *out, bsfit_status *st) {
  bsfit__fspline cur, next;
  bsfit__fview v;
  bsfit_err e = bsfit__filter_exact_open(in, delta, a, &cur, st);
  int i;
  for (i = 1; i < order && e == BSFIT_OK; i++) {
    if (bsfit__interrupted(a)) {
      bsfit__fspline_free(a, &cur);
      return bsfit__fail(st, BSFIT_EINTR, "kernel filter interrupted after %d of %d passes", i,
                         order);
    }
    v.p = cur.p;
    v.n = cur.n;
    v.d = cur.d;
    v.U = cur.U;
    v.P = cur.P;
    e = bsfit__filter_exact_open(&v, delta, a, &next, st);
    bsfit__fspline_free(a, &cur);
    cur = next;
  }
  if (e == BSFIT_OK) *out = cur;
  return e;
}

bsfit_err bsfit__filter_exact_periodic(const bsfit__fview *in, int order, double delta,
                                       const bsfit_allocator *a, bsfit__fspline *out,
                                       bsfit_status *st) {
  size_t p = (size_t)in->p, N = in->n - p, K;
  double lo = in->U[p], T = in->U[p + N] - lo, tol;
  bsfit__fview open;
  bsfit__fspline f;
  scratch s;
  bsfit_err e;
  memset(&s, 0, sizeof s);
  s.a = a;
  K = margin_spans(in, N, (double)order * delta);
  if (unwrap(in, N, K, &s, &open) != BSFIT_OK) {
    scratch_release(&s);
    return bsfit__fail(st, BSFIT_ENOMEM, "out of memory unwrapping a closed curve");
  }
  if (!unwrapped_ok(&open)) {
    scratch_release(&s);
    return bsfit__fail(st, BSFIT_EMULT,
                       "knots of this closed curve are closer than the rounding of its "
                       "periods shifted by up to %g: they would merge",
                       open.U[open.n + p] - open.U[0]);
  }
  e = open_passes(&open, order, delta, a, &f, st);
  if (e == BSFIT_OK) {
    tol = 64.0 * DBL_EPSILON * (fabs(lo) + 2.0 * (open.U[open.n + p] - open.U[0]));
    e = read_period(&f, lo, T, tol, a, &s, out, st);
    bsfit__fspline_free(a, &f);
  }
  scratch_release(&s);
  return e == BSFIT_OK ? bsfit__ok(st) : e;
}

/* }==================================================================== */
