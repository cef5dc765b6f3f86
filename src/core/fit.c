/*
** fit.c
** The fitter: settings, a workspace reused across fits, the span-by-span assembly of the
** banded normal equations N^T W N P = N^T W Q (SPEC 2.3), the open solve with exact end
** constraints, the diagnostics pass, global interpolation and the paper's wrap closing.
** The periodic solve lives in periodic.c, every LAPACK call in linalg.c.
*/
#include "fit_internal.h"

#include <math.h>
#include <string.h>

#if defined(__GNUC__)
#  define FIT_INLINE static inline __attribute__((always_inline))
#else
#  define FIT_INLINE static inline
#endif

void bsfit_fit_opts_init(bsfit_fit_opts *o) {
  memset(o, 0, sizeof *o);
  o->degree = 3;
  o->rule = BSFIT_KNOTS_AVERAGING;
}

/* {======================================================================
** Configuration and workspace
** ======================================================================= */

/* Sizes of the workspace block, in doubles / ints / bytes, for a configured fitter. */
static size_t block_bytes(const bsfit_fitter *f, size_t off[12]) {
  size_t p = (size_t)f->p, n = f->nraw, N = f->count, np = f->periodic ? N - p : 0;
  size_t counts[11], i, total = 0;
  counts[0] = f->nk;                             /* U */
  counts[1] = f->periodic ? N + 1 : 0;           /* period */
  counts[2] = (n - p) * f->tri;                  /* inv */
  counts[3] = (p + 1) * n;                       /* band */
  counts[4] = 4 * n;                             /* rhs */
  counts[5] = 3 * n;                             /* work */
  counts[6] = (p + 1) * np;                      /* a11 */
  counts[7] = np * p;                            /* a12 */
  counts[8] = f->periodic ? np * p : 0;          /* y */
  counts[9] = f->periodic ? p * p : 0;           /* s22 */
  counts[10] = f->periodic ? 4 * N : 0;          /* r2 */
  for (i = 0; i < 11; i++) {
    off[i] = total;
    total += counts[i] * sizeof(double);
  }
  off[11] = total; /* iwork, then occ */
  return total + n * sizeof(int) + n;
}

static void carve(bsfit_fitter *f, const size_t off[12]) {
  char *b = f->block;
  f->U = (double *)(void *)(b + off[0]);
  f->period = (double *)(void *)(b + off[1]);
  f->inv = (double *)(void *)(b + off[2]);
  f->band = (double *)(void *)(b + off[3]);
  f->rhs = (double *)(void *)(b + off[4]);
  f->work = (double *)(void *)(b + off[5]);
  f->a11 = (double *)(void *)(b + off[6]);
  f->a12 = (double *)(void *)(b + off[7]);
  f->y = (double *)(void *)(b + off[8]);
  f->s22 = (double *)(void *)(b + off[9]);
  f->r2 = (double *)(void *)(b + off[10]);
  f->iwork = (int *)(void *)(b + off[11]);
  f->occ = (unsigned char *)(b + off[11] + f->nraw * sizeof(int));
}

static bsfit_err check_opts(const bsfit_fit_opts *o, bsfit_status *st) {
  size_t need;
  if (o == NULL) return bsfit__fail(st, BSFIT_EINVAL, "fit options are NULL");
  if (o->degree < 1 || o->degree > BSFIT_MAX_DEGREE)
    return bsfit__fail(st, BSFIT_EDEGREE, "degree %d out of range 1..%d", o->degree,
                       BSFIT_MAX_DEGREE);
  if (o->count < (size_t)o->degree + 1 || o->count < 2)
    return bsfit__fail(st, BSFIT_EDEGREE, "degree %d needs more than %zu control points",
                       o->degree, o->count);
  if (o->count > ((size_t)1 << 28))
    return bsfit__fail(st, BSFIT_EINVAL, "control point count %zu is too large", o->count);
  if (o->knots == NULL && bsfit_knots_place_count(o->rule, o->degree, o->count) == 0)
    return bsfit__fail(st, BSFIT_EINVAL, "unknown knot rule %d", (int)o->rule);
  if (o->periodic && (o->fix_ends || o->tangent_start || o->tangent_end))
    return bsfit__fail(st, BSFIT_EINVAL, "fixed ends and end tangents need an open fit");
  if ((o->tangent_start || o->tangent_end) && (o->tangent_dim < 1 || o->tangent_dim > 4))
    return bsfit__fail(st, BSFIT_EINVAL, "tangent_dim %d out of range 1..4", o->tangent_dim);
  if (o->tangent_start && !bsfit__all_finite(o->tangent_start, (size_t)o->tangent_dim))
    return bsfit__fail(st, BSFIT_ENONFINITE, "tangent_start is not finite");
  if (o->tangent_end && !bsfit__all_finite(o->tangent_end, (size_t)o->tangent_dim))
    return bsfit__fail(st, BSFIT_ENONFINITE, "tangent_end is not finite");
  need = (size_t)(o->tangent_start ? 2 : o->fix_ends ? 1 : 0) +
         (size_t)(o->tangent_end ? 2 : o->fix_ends ? 1 : 0);
  if (need > o->count)
    return bsfit__fail(st, BSFIT_EINVAL, "the end constraints need %zu control points, count is %zu",
                       need, o->count);
  return BSFIT_OK;
}

/* Copies the user's fixed knots into f (sizes already set) and checks them. */
static bsfit_err load_knots(bsfit_fitter *f, const bsfit_fit_opts *o, bsfit_status *st) {
  size_t p = (size_t)f->p, n = f->nraw;
  bsfit_err e;
  if (f->periodic) {
    if (o->nknots != f->count + 1)
      return bsfit__fail(st, BSFIT_ENKNOTS, "a periodic fit with %zu control points needs %zu "
                         "knots (one period), got %zu", f->count, f->count + 1, o->nknots);
    memcpy(f->period, o->knots, (f->count + 1) * sizeof(double));
    e = bsfit_knots_periodic(f->p, f->count, f->period, f->U, st);
  } else {
    if (o->nknots != f->nk)
      return bsfit__fail(st, BSFIT_ENKNOTS, "%zu control points of degree %d need %zu knots, got %zu",
                         n, f->p, f->nk, o->nknots);
    memcpy(f->U, o->knots, f->nk * sizeof(double));
    e = bsfit_knots_validate(f->U, f->nk, f->p, n, st);
  }
  if (e != BSFIT_OK) return e;
  if ((f->fix_ends || f->has_t0 || f->has_t1) && (f->U[0] != f->U[p] || f->U[n] != f->U[n + p]))
    return bsfit__fail(st, BSFIT_EINVAL, "fixed ends and end tangents need clamped knots");
  bsfit__fit_inverses(f);
  return BSFIT_OK;
}

static void apply_settings(bsfit_fitter *f, const bsfit_fit_opts *o) {
  int k;
  f->p = o->degree;
  f->periodic = o->periodic != 0;
  f->count = o->count;
  f->rule = o->rule;
  if (f->periodic && !bsfit_knot_rule_closed(f->rule)) f->rule = BSFIT_KNOTS_PERIODIC_AVERAGING;
  if (!f->periodic && bsfit_knot_rule_closed(f->rule)) f->rule = BSFIT_KNOTS_AVERAGING;
  f->user_knots = o->knots != NULL;
  f->fix_ends = o->fix_ends != 0;
  f->has_t0 = o->tangent_start != NULL;
  f->has_t1 = o->tangent_end != NULL;
  f->tangent_dim = f->has_t0 || f->has_t1 ? o->tangent_dim : 0;
  for (k = 0; k < f->tangent_dim; k++) {
    f->t0[k] = f->has_t0 ? o->tangent_start[k] : 0.0;
    f->t1[k] = f->has_t1 ? o->tangent_end[k] : 0.0;
  }
  f->nraw = f->count + (f->periodic ? (size_t)f->p : 0);
  f->nk = f->nraw + (size_t)f->p + 1;
  f->tri = (size_t)f->p * (size_t)(f->p + 1) / 2;
  f->fitted = 0;
}

bsfit_err bsfit_fitter_configure(bsfit_fitter *f, const bsfit_fit_opts *o, bsfit_status *st) {
  bsfit_fitter next;
  size_t off[12];
  bsfit_err e;
  if (f == NULL) return bsfit__fail(st, BSFIT_EINVAL, "fitter is NULL");
  e = check_opts(o, st);
  if (e != BSFIT_OK) return e;
  /* build the new configuration aside, so a failure leaves f as it was */
  memset(&next, 0, sizeof next);
  next.alloc = f->alloc;
  apply_settings(&next, o);
  next.block_size = block_bytes(&next, off);
  next.block = bsfit__alloc(&next.alloc, next.block_size);
  if (next.block == NULL)
    return bsfit__fail(st, BSFIT_ENOMEM, "out of memory for a fitter of %zu control points",
                       next.count);
  carve(&next, off);
  if (next.user_knots) {
    e = load_knots(&next, o, st);
    if (e != BSFIT_OK) {
      bsfit__free(&next.alloc, next.block, next.block_size);
      return e;
    }
  }
  bsfit__free(&f->alloc, f->block, f->block_size);
  *f = next;
  return bsfit__ok(st);
}

bsfit_err bsfit_fitter_new(bsfit_fitter **f, const bsfit_fit_opts *o, const bsfit_allocator *a,
                           bsfit_status *st) {
  bsfit_fitter *g;
  bsfit_allocator al = {NULL, NULL};
  bsfit_err e;
  if (f == NULL) return bsfit__fail(st, BSFIT_EINVAL, "fitter output is NULL");
  *f = NULL;
  if (a != NULL) al = *a;
  e = check_opts(o, st);
  if (e != BSFIT_OK) return e;
  g = bsfit__alloc(&al, sizeof *g);
  if (g == NULL) return bsfit__fail(st, BSFIT_ENOMEM, "out of memory for a fitter");
  memset(g, 0, sizeof *g);
  g->alloc = al;
  e = bsfit_fitter_configure(g, o, st);
  if (e != BSFIT_OK) {
    bsfit__free(&al, g, sizeof *g);
    return e;
  }
  *f = g;
  return BSFIT_OK;
}

void bsfit_fitter_free(bsfit_fitter *f) {
  bsfit_allocator al;
  if (f == NULL) return;
  al = f->alloc;
  bsfit__free(&al, f->block, f->block_size);
  bsfit__free(&al, f, sizeof *f);
}

const double *bsfit_fitter_knots(const bsfit_fitter *f, size_t *nknots) {
  if (f == NULL || !(f->fitted || f->user_knots)) return NULL;
  if (nknots) *nknots = f->nk;
  return f->U;
}

/* }====================================================================== */

/* {======================================================================
** Span kernels: basis functions from precomputed reciprocal knot differences
** ======================================================================= */

void bsfit__fit_inverses(bsfit_fitter *f) {
  size_t s, p = (size_t)f->p;
  const double *U = f->U;
  double *inv = f->inv;
  /* the Cox-de Boor denominators U[s+r+1] - U[s+1-j+r] depend on the span only */
  for (s = p; s < f->nraw; s++) {
    size_t j, r;
    for (j = 1; j <= p; j++)
      for (r = 0; r < j; r++) {
        double den = U[s + r + 1] - U[s + 1 - j + r];
        *inv++ = den != 0.0 ? 1.0 / den : 0.0; /* 0/0 = 0 at repeated knots */
      }
  }
}

/* The p+1 non-zero basis functions at u in span s (NURBS Book A2.2 without divisions). */
FIT_INLINE void basis_inv(const double *U, const double *inv, size_t s, double u, int p,
                          double *N) {
  double left[BSFIT_MAX_DEGREE + 1], right[BSFIT_MAX_DEGREE + 1];
  int j, r;
  N[0] = 1.0;
  for (j = 1; j <= p; j++) {
    double saved = 0.0;
    left[j] = u - U[s + 1 - (size_t)j];
    right[j] = U[s + (size_t)j] - u;
    for (r = 0; r < j; r++) {
      double tmp = N[r] * *inv++;
      N[r] = saved + right[r + 1] * tmp;
      saved = left[j - r] * tmp;
    }
    N[j] = saved;
  }
}

/* Last span of positive length: parameters at or beyond the domain's end belong to it. */
static size_t last_span(const double *U, size_t n, int p) {
  size_t last = n - 1;
  while (last > (size_t)p && U[last] == U[n]) last--;
  return last;
}

/* Bounds of the parameter interval handled by span s without a new search: the end
** spans extend to infinity so extrapolated or end-point parameters stay in them. */
FIT_INLINE void span_bounds(const double *U, int p, size_t last, size_t s, double *lo,
                            double *hi) {
  *lo = s == (size_t)p ? -INFINITY : U[s];
  *hi = s >= last ? INFINITY : U[s + 1];
}

FIT_INLINE size_t next_span(const double *U, size_t n, int p, size_t s, double x) {
  /* sorted parameters mostly move to the next span: try it before a binary search */
  if (x >= U[s + 1] && s + 2 <= n && x < U[s + 2] && U[s + 2] > U[s + 1]) return s + 1;
  return bsfit_knots_find_span(U, n, p, x);
}

FIT_INLINE double wrap_param(double x, double a, double b) {
  double T = b - a, v;
  if (x >= a && x < b) return x;
  v = a + fmod(x - a, T);
  if (v < a) v += T;
  return v >= b ? a : v;
}

/* Adds one span's local sums to the band (lower storage) and the right-hand sides. */
FIT_INLINE void flush_span(bsfit_fitter *f, size_t s, const int p, const int dim,
                           const double *acc, const double *racc) {
  size_t ldab = (size_t)p + 1, first = s - (size_t)p, n = f->nraw;
  int i, j, c;
  for (i = 0; i <= p; i++)
    for (j = 0; j <= i; j++)
      f->band[(size_t)(i - j) + (first + (size_t)j) * ldab] += acc[i * (p + 1) + j];
  for (i = 0; i <= p; i++)
    for (c = 0; c < dim; c++) f->rhs[(size_t)c * n + first + (size_t)i] += racc[i * dim + c];
  f->occ[first] = 1;
}

/* One pass over the points: accumulates the lower band of N^T W N and N^T W Q span by
** span (local sums, flushed when the span changes) plus the validation sums, which are
** NaN-propagating adds instead of branches so the loop stays branch-light. */
FIT_INLINE void assemble_kernel(bsfit_fitter *f, const double *pts, size_t m, const int dim,
                                const double *u, const double *w, const int p,
                                bsfit__asm_sums *sums) {
  const double *U = f->U, *inv = f->inv;
  size_t n = f->nraw, s = (size_t)p, k, last = last_span(U, n, p);
  double acc[(BSFIT_MAX_DEGREE + 1) * (BSFIT_MAX_DEGREE + 1)];
  double racc[(BSFIT_MAX_DEGREE + 1) * 4];
  double N[BSFIT_MAX_DEGREE + 1], wN[BSFIT_MAX_DEGREE + 1];
  double lo = 1.0, hi = 0.0, a = U[p], b = U[n], bad = 0.0, spread = 0.0;
  int badw = 0, have = 0, i, j, c;
  for (k = 0; k < m; k++) {
    const double *q = pts + k * (size_t)dim;
    double x = f->periodic ? wrap_param(u[k], a, b) : u[k], wk = w ? w[k] : 1.0;
    if (!(x >= lo && x < hi)) {
      if (have) flush_span(f, s, p, dim, acc, racc);
      s = next_span(U, n, p, s, x);
      span_bounds(U, p, last, s, &lo, &hi);
      if (x != x) lo = 1.0, hi = 0.0; /* a NaN parameter: search again next time */
      inv = f->inv + (s - (size_t)p) * f->tri;
      for (i = 0; i < (p + 1) * (p + 1); i++) acc[i] = 0.0;
      for (i = 0; i < (p + 1) * dim; i++) racc[i] = 0.0;
      have = 1;
    }
    basis_inv(U, inv, s, x, p, N);
    bad += x * 0.0 + wk * 0.0;
    badw |= !(wk > 0.0);
    for (c = 0; c < dim; c++) {
      bad += q[c] * 0.0;
      spread += fabs(q[c] - pts[c]);
    }
    for (i = 0; i <= p; i++) wN[i] = wk * N[i];
    for (i = 0; i <= p; i++)
      for (j = 0; j <= i; j++) acc[i * (p + 1) + j] += wN[i] * N[j];
    for (i = 0; i <= p; i++)
      for (c = 0; c < dim; c++) racc[i * dim + c] += wN[i] * q[c];
  }
  if (have) flush_span(f, s, p, dim, acc, racc);
  sums->bad = bad;
  sums->spread = spread;
  sums->badw = badw;
}

/* The common case, cubic 2D, written out: per span, scalar accumulators that stay in
** registers while the inner loop runs over the points of that span. */
#define CUBIC_BASIS(x)                                                                   \
  do {                                                                                   \
    double l1 = (x) - U0, l2 = (x) - Um1, l3 = (x) - Um2;                                \
    double r1 = U1 - (x), r2 = U2 - (x), r3 = U3 - (x), t, sv;                           \
    double b0 = r1 * iv[0], b1 = l1 * iv[0], b2;                                         \
    t = b0 * iv[1];                                                                      \
    b0 = r1 * t;                                                                         \
    sv = l2 * t;                                                                         \
    t = b1 * iv[2];                                                                      \
    b1 = sv + r2 * t;                                                                    \
    b2 = l1 * t;                                                                         \
    t = b0 * iv[3];                                                                      \
    N0 = r1 * t;                                                                         \
    sv = l3 * t;                                                                         \
    t = b1 * iv[4];                                                                      \
    N1 = sv + r2 * t;                                                                    \
    sv = l2 * t;                                                                         \
    t = b2 * iv[5];                                                                      \
    N2 = sv + r3 * t;                                                                    \
    N3 = l1 * t;                                                                         \
  } while (0)

static void assemble_cubic2(bsfit_fitter *f, const double *pts, size_t m, const double *u,
                            const double *w, bsfit__asm_sums *sums) {
  const double *U = f->U;
  size_t n = f->nraw, s = 3, k = 0, last = last_span(U, n, 3), ld = 4;
  double a = U[3], b = U[n], bad = 0.0, spread = 0.0, qx0 = pts[0], qy0 = pts[1];
  int badw = 0, per = f->periodic;
  while (k < m) {
    double x = per ? wrap_param(u[k], a, b) : u[k], lo, hi;
    double U0, U1, U2, U3, Um1, Um2, N0, N1, N2, N3;
    double a00 = 0, a10 = 0, a11 = 0, a20 = 0, a21 = 0, a22 = 0, a30 = 0, a31 = 0, a32 = 0,
           a33 = 0, rx0 = 0, rx1 = 0, rx2 = 0, rx3 = 0, ry0 = 0, ry1 = 0, ry2 = 0, ry3 = 0;
    const double *iv;
    double *B;
    s = next_span(U, n, 3, s, x);
    span_bounds(U, 3, last, s, &lo, &hi);
    iv = f->inv + (s - 3) * 6;
    U0 = U[s], U1 = U[s + 1], U2 = U[s + 2], U3 = U[s + 3], Um1 = U[s - 1], Um2 = U[s - 2];
    do {
      double wk = w ? w[k] : 1.0, qx = pts[2 * k], qy = pts[2 * k + 1], w0, w1, w2, w3;
      CUBIC_BASIS(x);
      bad += x * 0.0 + wk * 0.0 + qx * 0.0 + qy * 0.0;
      badw |= !(wk > 0.0);
      spread += fabs(qx - qx0) + fabs(qy - qy0);
      w0 = wk * N0, w1 = wk * N1, w2 = wk * N2, w3 = wk * N3;
      a00 += w0 * N0, a10 += w1 * N0, a11 += w1 * N1, a20 += w2 * N0, a21 += w2 * N1;
      a22 += w2 * N2, a30 += w3 * N0, a31 += w3 * N1, a32 += w3 * N2, a33 += w3 * N3;
      rx0 += w0 * qx, rx1 += w1 * qx, rx2 += w2 * qx, rx3 += w3 * qx;
      ry0 += w0 * qy, ry1 += w1 * qy, ry2 += w2 * qy, ry3 += w3 * qy;
      if (++k == m) break;
      x = per ? wrap_param(u[k], a, b) : u[k];
    } while (x >= lo && x < hi);
    B = f->band + (s - 3) * ld; /* column s-3 of the lower band */
    B[0] += a00, B[1] += a10, B[2] += a20, B[3] += a30;
    B[ld + 0] += a11, B[ld + 1] += a21, B[ld + 2] += a31;
    B[2 * ld + 0] += a22, B[2 * ld + 1] += a32;
    B[3 * ld + 0] += a33;
    B = f->rhs + s - 3;
    B[0] += rx0, B[1] += rx1, B[2] += rx2, B[3] += rx3;
    B += n;
    B[0] += ry0, B[1] += ry1, B[2] += ry2, B[3] += ry3;
    f->occ[s - 3] = 1;
  }
  sums->bad = bad;
  sums->spread = spread;
  sums->badw = badw;
}

void bsfit__fit_assemble(bsfit_fitter *f, const double *pts, size_t m, int dim, const double *u,
                         const double *w, bsfit__asm_sums *sums) {
  memset(f->band, 0, (size_t)(f->p + 1) * f->nraw * sizeof(double));
  memset(f->rhs, 0, (size_t)dim * f->nraw * sizeof(double));
  memset(f->occ, 0, f->nraw);
  if (f->p == 3 && dim == 2) assemble_cubic2(f, pts, m, u, w, sums);
  else if (f->p == 3 && dim == 3) assemble_kernel(f, pts, m, 3, u, w, 3, sums);
  else assemble_kernel(f, pts, m, dim, u, w, f->p, sums);
}

typedef struct resid_sums {
  double wss, wsum, max;
  size_t imax;
} resid_sums;

/* Second pass: distances |Q_k - C(u_k)| with the solved control points (expanded). */
FIT_INLINE void residual_kernel(const bsfit_fitter *f, const double *ctrl, const double *pts,
                                size_t m, const int dim, const double *u, const double *w,
                                const int p, double *res, resid_sums *out) {
  const double *U = f->U, *inv = f->inv;
  size_t n = f->nraw, s = (size_t)p, k, last = last_span(U, n, p);
  double N[BSFIT_MAX_DEGREE + 1], lo = 1.0, hi = 0.0, a = U[p], b = U[n];
  double wss = 0.0, wsum = 0.0, mx = -1.0;
  size_t imax = 0;
  int i, c;
  for (k = 0; k < m; k++) {
    const double *q = pts + k * (size_t)dim;
    double x = f->periodic ? wrap_param(u[k], a, b) : u[k], wk = w ? w[k] : 1.0, r2 = 0.0, r;
    if (!(x >= lo && x < hi)) {
      s = next_span(U, n, p, s, x);
      span_bounds(U, p, last, s, &lo, &hi);
      inv = f->inv + (s - (size_t)p) * f->tri;
    }
    basis_inv(U, inv, s, x, p, N);
    for (c = 0; c < dim; c++) {
      double v = q[c];
      for (i = 0; i <= p; i++) v -= N[i] * ctrl[(s - (size_t)p + (size_t)i) * (size_t)dim + (size_t)c];
      r2 += v * v;
    }
    r = sqrt(r2);
    if (res) res[k] = r;
    wss += wk * r2;
    wsum += wk;
    if (r > mx) {
      mx = r;
      imax = k;
    }
  }
  out->wss = wss;
  out->wsum = wsum;
  out->max = mx < 0.0 ? 0.0 : mx;
  out->imax = imax;
}

static void residual_cubic2(const bsfit_fitter *f, const double *ctrl, const double *pts,
                            size_t m, const double *u, const double *w, double *res,
                            resid_sums *out) {
  const double *U = f->U;
  size_t n = f->nraw, s = 3, k = 0, last = last_span(U, n, 3), imax = 0;
  double a = U[3], b = U[n], wss = 0.0, wsum = 0.0, mx = -1.0;
  int per = f->periodic;
  while (k < m) {
    double x = per ? wrap_param(u[k], a, b) : u[k], lo, hi;
    double U0, U1, U2, U3, Um1, Um2, N0, N1, N2, N3;
    const double *iv, *P;
    double px0, px1, px2, px3, py0, py1, py2, py3;
    s = next_span(U, n, 3, s, x);
    span_bounds(U, 3, last, s, &lo, &hi);
    iv = f->inv + (s - 3) * 6;
    U0 = U[s], U1 = U[s + 1], U2 = U[s + 2], U3 = U[s + 3], Um1 = U[s - 1], Um2 = U[s - 2];
    P = ctrl + (s - 3) * 2;
    px0 = P[0], py0 = P[1], px1 = P[2], py1 = P[3], px2 = P[4], py2 = P[5], px3 = P[6], py3 = P[7];
    do {
      double wk = w ? w[k] : 1.0, dx, dy, dd, r;
      CUBIC_BASIS(x);
      dx = pts[2 * k] - (N0 * px0 + N1 * px1 + N2 * px2 + N3 * px3);
      dy = pts[2 * k + 1] - (N0 * py0 + N1 * py1 + N2 * py2 + N3 * py3);
      dd = dx * dx + dy * dy;
      r = sqrt(dd);
      if (res) res[k] = r;
      wss += wk * dd;
      wsum += wk;
      if (r > mx) mx = r, imax = k;
      if (++k == m) break;
      x = per ? wrap_param(u[k], a, b) : u[k];
    } while (x >= lo && x < hi);
  }
  out->wss = wss;
  out->wsum = wsum;
  out->max = mx < 0.0 ? 0.0 : mx;
  out->imax = imax;
}

static void residuals(const bsfit_fitter *f, const double *ctrl, const double *pts, size_t m,
                      int dim, const double *u, const double *w, double *res, resid_sums *out) {
  if (f->p == 3 && dim == 2) residual_cubic2(f, ctrl, pts, m, u, w, res, out);
  else if (f->p == 3 && dim == 3) residual_kernel(f, ctrl, pts, m, 3, u, w, 3, res, out);
  else residual_kernel(f, ctrl, pts, m, dim, u, w, f->p, res, out);
}

/* }====================================================================== */

/* {======================================================================
** The open solve, with end constraints by elimination
** ======================================================================= */

double bsfit__band_norm1(const double *ab, size_t ldab, int kd, size_t lo, size_t hi,
                         double *colsum) {
  size_t c, r;
  double mx = 0.0;
  for (c = lo; c <= hi; c++) colsum[c - lo] = 0.0;
  for (c = lo; c <= hi; c++)
    for (r = c; r <= hi && r <= c + (size_t)kd; r++) {
      double v = fabs(ab[(r - c) + c * ldab]);
      colsum[c - lo] += v;
      if (r != c) colsum[r - lo] += v;
    }
  for (c = lo; c <= hi; c++)
    if (colsum[c - lo] > mx) mx = colsum[c - lo];
  return mx;
}

/* Values of the fixed control points: index -> coordinates (row-major, 4 slots). */
typedef struct fixed_set {
  size_t idx[4];
  double val[4][4];
  size_t count, lo, hi; /* free unknowns lo..hi (empty when count covers all) */
} fixed_set;

static void fixed_points(const bsfit_fitter *f, const double *pts, size_t m, int dim,
                         fixed_set *fx) {
  size_t n = f->nraw, p = (size_t)f->p, c;
  const double *U = f->U, *Q0 = pts, *Q1 = pts + (m - 1) * (size_t)dim;
  fx->count = 0;
  fx->lo = 0;
  fx->hi = n; /* one past */
  if (f->fix_ends || f->has_t0) {
    fx->idx[fx->count] = 0;
    for (c = 0; c < (size_t)dim; c++) fx->val[fx->count][c] = Q0[c];
    fx->count++;
    fx->lo = 1;
  }
  if (f->has_t0) { /* C'(a) = p / (U[p+1] - U[1]) (P_1 - P_0) */
    double h = (U[p + 1] - U[1]) / (double)p;
    fx->idx[fx->count] = 1;
    for (c = 0; c < (size_t)dim; c++) fx->val[fx->count][c] = Q0[c] + h * f->t0[c];
    fx->count++;
    fx->lo = 2;
  }
  if (f->fix_ends || f->has_t1) {
    fx->idx[fx->count] = n - 1;
    for (c = 0; c < (size_t)dim; c++) fx->val[fx->count][c] = Q1[c];
    fx->count++;
    fx->hi = n - 1;
  }
  if (f->has_t1) { /* C'(b) = p / (U[n+p] - U[n-1]) (P_{n-1} - P_{n-2}) */
    double h = (U[n + p] - U[n - 1]) / (double)p;
    fx->idx[fx->count] = n - 2;
    for (c = 0; c < (size_t)dim; c++) fx->val[fx->count][c] = Q1[c] - h * f->t1[c];
    fx->count++;
    fx->hi = n - 2;
  }
}

/* Moves the fixed unknowns' columns to the right-hand side: R_i -= A_ij P_j. */
static void eliminate_fixed(bsfit_fitter *f, int dim, const fixed_set *fx) {
  size_t t, i, n = f->nraw, p = (size_t)f->p, ldab = p + 1, c;
  for (t = 0; t < fx->count; t++) {
    size_t j = fx->idx[t];
    for (i = fx->lo; i < fx->hi; i++) {
      size_t hi = i > j ? i : j, lo = i > j ? j : i;
      double a;
      if (hi - lo > p) continue;
      a = f->band[(hi - lo) + lo * ldab];
      for (c = 0; c < (size_t)dim; c++) f->rhs[c * n + i] -= a * fx->val[t][c];
    }
  }
}

static bsfit_err empty_span_error(const bsfit_fitter *f, bsfit_err e, bsfit_status *st,
                                  size_t *count, size_t *first) {
  size_t s, p = (size_t)f->p, found = 0, first_s = 0;
  for (s = p; s < f->nraw; s++)
    if (f->U[s + 1] > f->U[s] && !f->occ[s - p] && found++ == 0) first_s = s;
  if (count) *count = found;
  if (first) *first = first_s;
  if (e != BSFIT_OK && found > 0)
    return bsfit__fail(st, BSFIT_EEMPTYSPAN,
                       "knot span %zu [%g, %g) holds no data (%zu empty): normal matrix singular",
                       first_s, f->U[first_s], f->U[first_s + 1], found);
  return e;
}

static bsfit_err open_solve(bsfit_fitter *f, const double *pts, size_t m, int dim,
                            double *ctrl, double *rcond, bsfit_status *st) {
  size_t p = (size_t)f->p, n = f->nraw, ldab = p + 1, t, i, c, nf;
  fixed_set fx;
  bsfit_err e = BSFIT_OK;
  int kd;
  fixed_points(f, pts, m, dim, &fx);
  nf = fx.hi > fx.lo ? fx.hi - fx.lo : 0;
  if (rcond) *rcond = 1.0;
  if (nf > 0) {
    double *ab = f->band + fx.lo * ldab, anorm = 0.0;
    kd = (int)(nf - 1 < p ? nf - 1 : p);
    eliminate_fixed(f, dim, &fx);
    if (rcond) anorm = bsfit__band_norm1(f->band, ldab, kd, fx.lo, fx.hi - 1, f->work);
    e = bsfit__pb_factor(nf, kd, ab, ldab, st);
    if (e == BSFIT_OK) e = bsfit__pb_solve(nf, kd, ab, ldab, (size_t)dim, f->rhs + fx.lo, n, st);
    if (e != BSFIT_OK) return empty_span_error(f, e, st, NULL, NULL);
    if (rcond) *rcond = bsfit__pb_rcond(nf, kd, ab, ldab, anorm, f->work, f->iwork);
  }
  for (i = fx.lo; i < fx.hi; i++)
    for (c = 0; c < (size_t)dim; c++) ctrl[i * (size_t)dim + c] = f->rhs[c * n + i];
  for (t = 0; t < fx.count; t++)
    for (c = 0; c < (size_t)dim; c++) ctrl[fx.idx[t] * (size_t)dim + c] = fx.val[t][c];
  return BSFIT_OK;
}

/* }====================================================================== */

/* {======================================================================
** The fit
** ======================================================================= */

static bsfit_err check_fit_args(const bsfit_fitter *f, const double *pts, size_t m, int dim,
                                const double *u, const bsfit_curve *out, bsfit_status *st) {
  if (f == NULL || pts == NULL || u == NULL || out == NULL)
    return bsfit__fail(st, BSFIT_EINVAL, "fitter, points, parameters or output curve is NULL");
  if (dim < 1 || dim > 4) return bsfit__fail(st, BSFIT_EDIM, "dimension %d out of range 1..4", dim);
  if (f->tangent_dim && dim != f->tangent_dim)
    return bsfit__fail(st, BSFIT_EDIM, "points have dimension %d, the end tangents %d", dim,
                       f->tangent_dim);
  if (m < f->count)
    return bsfit__fail(st, BSFIT_ETOOFEW, "%zu points are fewer than %zu control points", m,
                       f->count);
  return BSFIT_OK;
}

/* Knots of this fit from the rule (fixed knots were loaded at configuration). */
static bsfit_err place_fit_knots(bsfit_fitter *f, const double *u, size_t m, bsfit_status *st) {
  bsfit_err e;
  if (f->user_knots) return BSFIT_OK;
  e = bsfit_knots_place(f->rule, u, m, f->p, f->count, f->periodic ? f->period : f->U, st);
  if (e != BSFIT_OK && e != BSFIT_EEMPTYSPAN) return e;
  if (f->periodic) {
    e = bsfit_knots_periodic(f->p, f->count, f->period, f->U, st);
    if (e != BSFIT_OK) return e;
  }
  bsfit__fit_inverses(f);
  f->fitted = 1;
  return BSFIT_OK;
}

/* The first bad input, found by a precise scan once the assembly sums flagged one. */
static bsfit_err input_error(const double *pts, size_t m, int dim, const double *u,
                             const double *w, bsfit_status *st) {
  size_t k, c;
  for (k = 0; k < m; k++) {
    for (c = 0; c < (size_t)dim; c++)
      if (!isfinite(pts[k * (size_t)dim + c]))
        return bsfit__fail(st, BSFIT_ENONFINITE, "point %zu has a NaN or Inf coordinate", k);
    if (!isfinite(u[k]))
      return bsfit__fail(st, BSFIT_ENONFINITE, "parameter %zu is not finite", k);
    if (w && !(isfinite(w[k]) && w[k] > 0.0))
      return bsfit__fail(st, BSFIT_EWEIGHT, "weight %zu is %g (must be positive and finite)", k,
                         w[k]);
  }
  return bsfit__fail(st, BSFIT_ENONFINITE, "the normal equations overflow");
}

static bsfit_err prepare_out(const bsfit_fitter *f, int dim, bsfit_curve *out, bsfit_status *st) {
  if (out->ctrl && out->knots && !out->weights && !out->bezier && out->n == f->nraw &&
      out->degree == f->p && out->dim == dim && out->alloc.fn == f->alloc.fn &&
      out->alloc.ud == f->alloc.ud)
    return BSFIT_OK; /* same shape: reuse the arrays, no allocation */
  return bsfit_curve_alloc(out, f->p, dim, f->nraw, 0, &f->alloc, st);
}

static bsfit_err fit_solve(bsfit_fitter *f, const double *pts, size_t m, int dim,
                           bsfit_curve *out, bsfit_fit_report *rep, bsfit_status *st) {
  double *rc = rep ? &rep->rcond : NULL;
  bsfit_err e;
  size_t p = (size_t)f->p, d = (size_t)dim;
  if (!f->periodic) return open_solve(f, pts, m, dim, out->ctrl, rc, st);
  e = bsfit__periodic_solve(f, dim, out->ctrl, rc, st);
  if (e != BSFIT_OK) return empty_span_error(f, e, st, NULL, NULL);
  memcpy(out->ctrl + f->count * d, out->ctrl, p * d * sizeof(double));
  return BSFIT_OK;
}

static bsfit_err fit_body(bsfit_fitter *f, const double *pts, size_t m, int dim, const double *u,
                          const double *w, bsfit_curve *out, bsfit_fit_report *rep,
                          double *res, bsfit_status *st) {
  bsfit__asm_sums sums;
  resid_sums rs;
  bsfit_err e = place_fit_knots(f, u, m, st);
  if (e != BSFIT_OK) return e;
  bsfit__fit_assemble(f, pts, m, dim, u, w, &sums);
  if (sums.bad != 0.0 || sums.badw) return input_error(pts, m, dim, u, w, st);
  if (sums.spread == 0.0) return bsfit__fail(st, BSFIT_EDEGENERATE, "all %zu points coincide", m);
  e = prepare_out(f, dim, out, st);
  if (e == BSFIT_OK) e = fit_solve(f, pts, m, dim, out, rep, st);
  if (e != BSFIT_OK) return e;
  if (!bsfit__all_finite(out->ctrl, f->nraw * (size_t)dim))
    return bsfit__fail(st, BSFIT_ESINGULAR, "the solution is not finite: the normal matrix is "
                       "numerically singular");
  memcpy(out->knots, f->U, f->nk * sizeof(double));
  out->periodic = f->periodic;
  residuals(f, out->ctrl, pts, m, dim, u, w, res, &rs);
  if (rep) {
    rep->rms = rs.wsum > 0.0 ? sqrt(rs.wss / rs.wsum) : 0.0;
    rep->max = rs.max;
    rep->max_index = rs.imax;
    rep->m = m;
    rep->first_empty_span = 0;
    (void)empty_span_error(f, BSFIT_OK, NULL, &rep->n_empty_spans, &rep->first_empty_span);
  }
  return bsfit__ok(st);
}

bsfit_err bsfit_fitter_fit(bsfit_fitter *f, const double *pts, size_t m, int dim, const double *u,
                           const double *w, bsfit_curve *out, bsfit_fit_report *rep,
                           double *residuals_out, bsfit_status *st) {
  bsfit_err e = check_fit_args(f, pts, m, dim, u, out, st);
  if (e == BSFIT_OK) e = fit_body(f, pts, m, dim, u, w, out, rep, residuals_out, st);
  if (e != BSFIT_OK && out != NULL) bsfit_curve_free(out);
  return e;
}

/* }====================================================================== */

/* {======================================================================
** Interpolation and wrap closing
** ======================================================================= */

static bsfit_err check_interp(const double *pts, size_t m, int dim, const double *u, int p,
                              int periodic, const bsfit_curve *out, bsfit_status *st) {
  size_t k;
  if (pts == NULL || u == NULL || out == NULL)
    return bsfit__fail(st, BSFIT_EINVAL, "points, parameters or output curve is NULL");
  if (dim < 1 || dim > 4) return bsfit__fail(st, BSFIT_EDIM, "dimension %d out of range 1..4", dim);
  if (p < 1 || p > BSFIT_MAX_DEGREE || m < (size_t)p + 1 || m < 2)
    return bsfit__fail(st, BSFIT_EDEGREE, "degree %d cannot interpolate %zu points", p, m);
  if (!bsfit__all_finite(pts, m * (size_t)dim) || !bsfit__all_finite(u, m))
    return bsfit__fail(st, BSFIT_ENONFINITE, "points or parameters contain NaN or Inf");
  for (k = 1; k < m; k++)
    if (!(u[k] > u[k - 1]))
      return bsfit__fail(st, BSFIT_EINVAL, "interpolation parameters must increase strictly "
                         "(index %zu)", k);
  if (periodic && !(u[m - 1] < u[0] + 1.0))
    return bsfit__fail(st, BSFIT_EINVAL, "closed parameters must lie in one period [u0, u0+1)");
  return BSFIT_OK;
}

/* NURBS Book eq. 9.8: interior knots average p consecutive parameters */
static void interp_knots(const double *u, size_t m, int p, double *U) {
  size_t j, i, P = (size_t)p;
  for (j = 0; j <= P; j++) {
    U[j] = u[0];
    U[m + j] = u[m - 1];
  }
  for (j = 1; j + P < m; j++) {
    double s = 0.0;
    for (i = j; i < j + P; i++) s += u[i];
    U[j + P] = s / (double)p;
  }
}

static bsfit_err interp_open(const double *pts, size_t m, int dim, const double *u, int p,
                             bsfit_curve *out, const bsfit_allocator *a, bsfit_status *st) {
  size_t k, j, c, kl = 0, ku = 0, ldab, bytes, P = (size_t)p;
  double N[BSFIT_MAX_DEGREE + 1], *ab, *b;
  void *blk;
  bsfit_err e = bsfit_curve_alloc(out, p, dim, m, 0, a, st);
  if (e != BSFIT_OK) return e;
  interp_knots(u, m, p, out->knots);
  for (k = 0; k < m; k++) { /* band widths from the actual spans */
    size_t s = bsfit_knots_find_span(out->knots, m, p, u[k]);
    if (k + P > s && k + P - s > kl) kl = k + P - s;
    if (s > k && s - k > ku) ku = s - k;
  }
  ldab = 2 * kl + ku + 1;
  bytes = (ldab * m + m * (size_t)dim) * sizeof(double) + m * sizeof(int);
  blk = bsfit__alloc(a, bytes);
  if (blk == NULL) return bsfit__fail(st, BSFIT_ENOMEM, "out of memory interpolating %zu points", m);
  ab = blk;
  b = ab + ldab * m;
  memset(ab, 0, ldab * m * sizeof(double));
  for (k = 0; k < m; k++) {
    size_t s = bsfit_knots_find_span(out->knots, m, p, u[k]);
    bsfit_basis_funs(s, u[k], p, out->knots, N);
    for (j = 0; j <= P; j++) ab[kl + ku + k - (s - P + j) + (s - P + j) * ldab] = N[j];
    for (c = 0; c < (size_t)dim; c++) b[c * m + k] = pts[k * (size_t)dim + c];
  }
  e = bsfit__gb_solve(m, (int)kl, (int)ku, ab, ldab, (int *)(void *)(b + m * (size_t)dim),
                      (size_t)dim, b, m, st);
  if (e == BSFIT_OK)
    for (k = 0; k < m; k++)
      for (c = 0; c < (size_t)dim; c++) out->ctrl[k * (size_t)dim + c] = b[c * m + k];
  bsfit__free(a, blk, bytes);
  if (e == BSFIT_OK && !bsfit__all_finite(out->ctrl, m * (size_t)dim))
    e = bsfit__fail(st, BSFIT_ESINGULAR, "interpolation is numerically singular");
  return e;
}

static bsfit_err interp_periodic(const double *pts, size_t m, int dim, const double *u, int p,
                                 bsfit_curve *out, const bsfit_allocator *a, bsfit_status *st) {
  bsfit_fit_opts o;
  bsfit_fitter *f;
  bsfit_curve c;
  bsfit_err e;
  bsfit_fit_opts_init(&o);
  o.degree = p;
  o.count = m;
  o.periodic = 1;
  o.rule = BSFIT_KNOTS_PERIODIC_AVERAGING;
  e = bsfit_fitter_new(&f, &o, a, st);
  if (e != BSFIT_OK) return e;
  bsfit_curve_init(&c);
  e = bsfit_fitter_fit(f, pts, m, dim, u, NULL, &c, NULL, NULL, st);
  bsfit_fitter_free(f);
  if (e == BSFIT_OK) bsfit_curve_move(&c, out);
  return e;
}

bsfit_err bsfit_interpolate(const double *pts, size_t m, int dim, const double *u, int p,
                            int periodic, bsfit_curve *out, const bsfit_allocator *a,
                            bsfit_status *st) {
  bsfit_err e = check_interp(pts, m, dim, u, p, periodic, out, st);
  if (e != BSFIT_OK) {
    if (out) bsfit_curve_free(out);
    return e;
  }
  bsfit_curve_free(out);
  e = periodic ? interp_periodic(pts, m, dim, u, p, out, a, st)
               : interp_open(pts, m, dim, u, p, out, a, st);
  if (e != BSFIT_OK) bsfit_curve_free(out);
  else e = bsfit__ok(st);
  return e;
}

bsfit_err bsfit_curve_wrap_closed(const bsfit_curve *open, const double *u, size_t m,
                                  bsfit_curve *out, const bsfit_allocator *a, bsfit_status *st) {
  size_t N;
  double *period;
  bsfit_err e;
  if (open == NULL || out == NULL || u == NULL || open->ctrl == NULL || open->knots == NULL)
    return bsfit__fail(st, BSFIT_EINVAL, "open curve, parameters or output is NULL or empty");
  if (open->weights || open->periodic || open->bezier || open == out)
    return bsfit__fail(st, BSFIT_EINVAL, "wrap closing needs a polynomial open B-spline, "
                       "distinct from the output");
  N = open->n;
  period = bsfit__alloc(a, (N + 1) * sizeof(double));
  if (period == NULL) return bsfit__fail(st, BSFIT_ENOMEM, "out of memory for %zu knots", N + 1);
  e = bsfit_knots_place(BSFIT_KNOTS_CARVALHO_CLOSED, u, m, open->degree, N, period, st);
  if (e == BSFIT_OK || e == BSFIT_EEMPTYSPAN)
    e = bsfit_curve_new_periodic(out, open->degree, open->dim, N, period, open->ctrl, NULL, a, st);
  bsfit__free(a, period, (N + 1) * sizeof(double));
  return e;
}

/* }====================================================================== */
