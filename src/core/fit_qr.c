/*
** fit_qr.c
** The fitter's QR solver (BSFIT_SOLVER_QR): the weighted least-squares problem
** min |W^1/2 (N P - Q)| solved without the normal equations, whose condition number is the
** square of the collocation matrix's. Each point gives one row sqrt(w_k) N(u_k) with p+1
** non-zeros; orthogonal transformations take the rows into an upper triangle R, as FITPACK
** does with Givens rotations (Dierckx, "Curve and Surface Fitting with Splines", ch. 4).
** Here the rows of one span enter together and each column is eliminated by one Householder
** reflection per block (one square root per column and block, not per row). Rows entering
** in the order of their spans keep R banded (bandwidth p+1): the rows of R a block meets
** have nothing right of its p+1 columns yet. Rows out of order would spread fill along the
** band, so such input is sorted by span first.
**
** Periodic fits: the folded rows touch the columns of their span modulo N. Taking the first
** p unknowns apart (the ones the wrapped rows reach) leaves every row's other columns
** consecutive, so R is a band bordered by p dense columns and a p x p triangle:
**   [R11 B; 0 R22] [x1; x2] = [z1; z2],  x2 = R22^-1 z2,  R11 x1 = z1 - B x2.
** Open fits with fixed ends move the fixed columns to the right-hand side (no border).
**
** Storage (all in the fitter's block): R in f->band, row i at band + i(p+1) holding
** R(i, i..i+p), which is LAPACK's lower band storage of R^T; the border B in f->a12,
** column-major nb x q; R22 in f->s22, column-major q x q; the right-hand sides in f->rhs,
** column-major with leading dimension nraw (band rows first, then border rows).
*/
#include "fit_internal.h"

#include <math.h>
#include <stdint.h>
#include <string.h>

typedef struct qr_sys {
  double *R, *B, *R22, *z;
  size_t nb, ld; /* band unknowns; leading dimension of z */
  int p, q, dim;
} qr_sys;

static qr_sys qr_view(const bsfit_fitter *f, int dim) {
  qr_sys S;
  S.R = f->band;
  S.B = f->a12;
  S.R22 = f->s22;
  S.z = f->rhs;
  S.nb = f->qr_nb;
  S.ld = f->nraw;
  S.p = f->p;
  S.q = f->qr_q;
  S.dim = dim;
  return S;
}

/* {======================================================================
** Householder reflections, a block of rows at a time
** ======================================================================= */

/* Rows of one span enter together, at most CHUNK at a time: one reflection per column
** and block instead of one rotation per column and row (a square root and two divisions
** each). */
#define CHUNK 32
/* doubles per block row: band part, border part, right-hand sides */
#define ROW_MAX (2 * BSFIT_MAX_DEGREE + 1 + 4)

#if defined(__GNUC__)
#  define QR_INLINE static inline __attribute__((always_inline))
#else
#  define QR_INLINE static inline
#endif

typedef struct row_block {
  double x[CHUNK * ROW_MAX];
  size_t j0;    /* band column of the rows' first band entry */
  int k, width; /* rows held; doubles per row = (p+1) + q + dim */
} row_block;

/* sqrt(alpha^2 + sum_r x[r*W + j]^2), scaled where the plain sums would under- or
** overflow. *nonzero: whether any x[r*W + j] is non-zero (then there is something to
** eliminate, however small: a square that underflows to 0 does not mean a zero entry). */
QR_INLINE double column_norm(double alpha, const double *x, int k, const int W, int j,
                             int *nonzero) {
  double ss = 0.0, mx = 0.0, sc = 0.0, h;
  int r;
  for (r = 0; r < k; r++) ss += x[r * W + j] * x[r * W + j];
  h = sqrt(alpha * alpha + ss);
  if (ss > 1e-250 && isfinite(h)) {
    *nonzero = 1;
    return h;
  }
  for (r = 0; r < k; r++) {
    double a = fabs(x[r * W + j]);
    if (!(a <= mx)) mx = a; /* a NaN sticks: it must reach R, where the checks see it */
  }
  *nonzero = !(mx == 0.0);
  if (mx < fabs(alpha)) mx = fabs(alpha);
  if (mx == 0.0) return 0.0;
  for (r = 0; r < k; r++) sc += (x[r * W + j] / mx) * (x[r * W + j] / mx);
  return mx * sqrt((alpha / mx) * (alpha / mx) + sc);
}

/* The reflection H = I - tau v v^T, v = (1, x_j / (alpha - beta)), taking (alpha, x_j) to
** (beta, 0) (LAPACK dlarfg), applied to the block's columns j+1..W-1 and to their entries
** in the triangle's row, *t[i] for column j+1+i (a dummy where the triangle has none: the
** block's column is zero there). Column j of the block becomes v's tail. */
QR_INLINE void reflect(double *diag, double *x, int k, const int W, int j, double *const *t) {
  double alpha = *diag, nrm, beta, tau, scale, sv[ROW_MAX];
  int r, i, n = W - j - 1, nonzero;
  nrm = column_norm(alpha, x, k, W, j, &nonzero);
  if (!nonzero) return; /* nothing below the diagonal */
  beta = alpha >= 0.0 ? -nrm : nrm;
  tau = (beta - alpha) / beta;
  scale = 1.0 / (alpha - beta);
  *diag = beta;
  for (i = 0; i < n; i++) sv[i] = *t[i];
  for (r = 0; r < k; r++) { /* sv = v^T [t; x] over the columns, row by row */
    double *row = x + r * W, vr = row[j] *= scale;
    for (i = 0; i < n; i++) sv[i] += vr * row[j + 1 + i];
  }
  for (i = 0; i < n; i++) {
    sv[i] *= tau;
    *t[i] -= sv[i];
  }
  for (r = 0; r < k; r++) {
    double *row = x + r * W, vr = row[j];
    for (i = 0; i < n; i++) row[j + 1 + i] -= sv[i] * vr;
  }
}

/* Takes the block's rows into R (band columns j0..j0+p, border, right-hand sides), then
** what is left of their border parts into R22. W: the block's width, a constant in the
** common instances below so that the loops over a row unroll. */
QR_INLINE void flush_width(qr_sys *S, row_block *blk, const int W) {
  const int p = S->p, q = S->q, d = S->dim, k = blk->k;
  size_t j0 = blk->j0, nb = S->nb;
  int c, j, bandcols = (int)(nb - j0 < (size_t)p + 1 ? nb - j0 : (size_t)p + 1);
  double *t[ROW_MAX], dummy = 0.0;
  if (k == 0) return;
  for (c = 0; c < bandcols; c++) { /* column j0 + c, against row j0 + c of R */
    size_t row = j0 + (size_t)c;
    double *Ri = S->R + row * (size_t)(p + 1); /* Ri[e] = R(row, row + e) */
    double **tc = t; /* tc[i] is the target of block column c + 1 + i */
    for (j = c + 1; j <= p; j++) *tc++ = j < bandcols ? Ri + (j - c) : &dummy;
    for (j = 0; j < q; j++) *tc++ = S->B + row + (size_t)j * nb;
    for (j = 0; j < d; j++) *tc++ = S->z + row + (size_t)j * S->ld;
    reflect(Ri, blk->x, k, W, c, t);
  }
  for (c = 0; c < q; c++) { /* border column c, against row c of R22 */
    double **tc = t;
    for (j = c + 1; j < q; j++) *tc++ = S->R22 + c + j * q;
    for (j = 0; j < d; j++) *tc++ = S->z + nb + (size_t)c + (size_t)j * S->ld;
    reflect(S->R22 + c + c * q, blk->x, k, W, p + 1 + c, t);
  }
  blk->k = 0;
}

static void flush_block(qr_sys *S, row_block *blk) {
  switch (blk->width) {
    case 6: flush_width(S, blk, 6); break; /* cubic 2D, open */
    case 7: flush_width(S, blk, 7); break; /* cubic 3D, open */
    case 9: flush_width(S, blk, 9); break; /* cubic 2D, periodic */
    default: flush_width(S, blk, blk->width);
  }
}

/* }====================================================================== */

/* {======================================================================
** The order of the rows
** ======================================================================= */

static double row_param(const bsfit_fitter *f, const double *u, size_t k) {
  return f->periodic ? bsfit__wrap_param(u[k], f->U[f->p], f->U[f->nraw]) : u[k];
}

/* Rows in span order: *rot when the (wrapped) parameters are sorted from index *rot on,
** cyclically (order stays NULL), else a counting sort by span into f->order. */
static bsfit_err row_order(bsfit_fitter *f, const double *u, size_t m, const size_t **order,
                           size_t *rot, bsfit_status *st) {
  size_t k, descents = 0, at = 0, nsp = f->nraw - (size_t)f->p, need, *cnt, *ord;
  double prev = row_param(f, u, 0);
  *order = NULL;
  *rot = 0;
  for (k = 1; k < m; k++) {
    double x = row_param(f, u, k);
    if (x < prev) descents++, at = k;
    prev = x;
  }
  if (descents == 0) return BSFIT_OK;
  if (f->periodic && descents == 1 && row_param(f, u, m - 1) <= row_param(f, u, 0)) {
    *rot = at;
    return BSFIT_OK;
  }
  need = m + nsp + 1;
  if (need > f->order_cap) {
    size_t bytes = bsfit__mulsize(need, sizeof(size_t));
    size_t *g = bytes ? bsfit__alloc(&f->alloc, bytes) : NULL;
    if (g == NULL)
      return bsfit__fail(st, BSFIT_ENOMEM, "out of memory sorting %zu points by span", m);
    bsfit__free(&f->alloc, f->order, f->order_cap * sizeof(size_t));
    f->order = g;
    f->order_cap = need;
  }
  ord = f->order;
  cnt = ord + m;
  memset(cnt, 0, (nsp + 1) * sizeof(size_t));
  for (k = 0; k < m; k++)
    cnt[bsfit_knots_find_span(f->U, f->nraw, f->p, row_param(f, u, k)) - (size_t)f->p + 1]++;
  for (k = 1; k <= nsp; k++) cnt[k] += cnt[k - 1];
  for (k = 0; k < m; k++)
    ord[cnt[bsfit_knots_find_span(f->U, f->nraw, f->p, row_param(f, u, k)) - (size_t)f->p]++] = k;
  *order = ord;
  return BSFIT_OK;
}

/* }====================================================================== */

/* {======================================================================
** The factorisation
** ======================================================================= */

/* The p+1 non-zero basis functions at x on span s: degrees 1..3 from the span polynomials
** the assembly uses (fit_assembly.c), higher degrees by NURBS Book A2.2. */
static inline void span_basis(const bsfit_fitter *f, size_t s, double x, const int p,
                              double *N) {
  size_t stride = bsfit__fit_poly_stride(p), P = (size_t)p + 1, i, a;
  const double *C;
  double t;
  if (stride == 0) {
    bsfit_basis_funs(s, x, p, f->U, N);
    return;
  }
  C = f->poly + (s - (size_t)p) * stride;
  t = (x - C[P * P]) * C[P * P + 1];
  for (i = 0; i < P; i++) {
    double v = C[(P - 1) * P + i];
    for (a = P - 1; a-- > 0;) v = v * t + C[a * P + i];
    N[i] = v;
  }
}

/* Are the p+1 columns of span s all band unknowns (no border, none fixed)? */
static int plain_span(const bsfit_fitter *f, const bsfit__fixed_set *fx, size_t s) {
  size_t p = (size_t)f->p;
  return f->periodic ? s >= 2 * p && s < f->count : s - p >= fx->lo && s < fx->hi;
}

/* make_row for a plain span: band part from column j0, no border, no fixed columns. */
static inline void plain_row(const double *Q, const double *N, const int p, const int q,
                             const int dim, double wk, size_t j0, double *row,
                             double *colsum) {
  double sw = sqrt(wk), sum = 0.0;
  int i;
  for (i = 0; i <= p; i++) row[i] = sw * N[i], sum += N[i];
  for (i = 0; i < q; i++) row[p + 1 + i] = 0.0;
  for (i = 0; i < dim; i++) row[p + 1 + q + i] = sw * Q[i];
  for (i = 0; i <= p; i++) colsum[j0 + (size_t)i] += fabs(wk * N[i] * sum);
}

static const double *fixed_value(const bsfit__fixed_set *fx, size_t j) {
  size_t t;
  for (t = 0; t < fx->count; t++)
    if (fx->idx[t] == j) return fx->val[t];
  return NULL; /* not reached: every column outside lo..hi-1 is fixed */
}

/* The weighted row of point Q with basis values N on span s, into `row`: its band part
** (p+1 entries from band column *j0), border part (q) and right-hand sides (dim). Adds its
** share of the normal matrix's column sums (every product is >= 0 inside the domain: the
** sums are the 1-norm's). Returns 0 when the row has no free column. */
static int make_row(const bsfit_fitter *f, const qr_sys *S, const bsfit__fixed_set *fx,
                    const double *Q, const double *N, size_t s, double wk, double *row,
                    size_t *j0, double *colsum) {
  size_t p = (size_t)f->p, N_ = f->count, i, unk[BSFIT_MAX_DEGREE + 1];
  double sw = sqrt(wk), free_sum = 0.0, *a = row, *b = row + p + 1, *y = b + S->q;
  int c, nfree = 0, is_free[BSFIT_MAX_DEGREE + 1];
  memset(row, 0, (p + 1 + (size_t)S->q) * sizeof(double));
  for (c = 0; c < S->dim; c++) y[c] = Q[c];
  *j0 = SIZE_MAX;
  for (i = 0; i <= p; i++) {
    size_t j = s - p + i, col;
    is_free[i] = 1;
    if (f->periodic) {
      col = j >= N_ ? j - N_ : j;
      unk[i] = col < p ? S->nb + col : col - p;
    } else if (j < fx->lo || j >= fx->hi) {
      const double *v = fixed_value(fx, j);
      for (c = 0; c < S->dim && v; c++) y[c] -= N[i] * v[c];
      is_free[i] = 0;
      continue;
    } else {
      unk[i] = j - fx->lo;
    }
    if (unk[i] >= S->nb) b[unk[i] - S->nb] = sw * N[i];
    else {
      if (*j0 == SIZE_MAX) *j0 = unk[i]; /* band columns come in increasing order */
      a[unk[i] - *j0] = sw * N[i];
    }
    free_sum += N[i];
    nfree++;
  }
  for (c = 0; c < S->dim; c++) y[c] *= sw;
  for (i = 0; i <= p; i++)
    if (is_free[i]) colsum[unk[i]] += fabs(wk * N[i] * free_sum);
  if (*j0 == SIZE_MAX) *j0 = S->nb; /* border only */
  return nfree > 0;
}

bsfit_err bsfit__qr_factor(bsfit_fitter *f, const double *pts, size_t m, int dim,
                           const double *u, const double *w, const bsfit__fixed_set *fx,
                           int *badw, bsfit_status *st) {
  size_t p = (size_t)f->p, rot, t, s = p, d = (size_t)dim, blk_span = SIZE_MAX;
  const size_t *order;
  double N[BSFIT_MAX_DEGREE + 1], *row;
  row_block blk;
  qr_sys S;
  bsfit_err e;
  f->qr_q = f->periodic ? f->p : 0;
  f->qr_nb = f->periodic ? f->count - p : (fx->hi > fx->lo ? fx->hi - fx->lo : 0);
  S = qr_view(f, dim);
  memset(S.R, 0, S.nb * (p + 1) * sizeof(double));
  memset(S.B, 0, S.nb * (size_t)S.q * sizeof(double));
  memset(S.R22, 0, (size_t)(S.q * S.q) * sizeof(double));
  memset(S.z, 0, S.ld * d * sizeof(double));
  memset(f->occ, 0, f->nraw);
  memset(f->work, 0, (S.nb + (size_t)S.q) * sizeof(double)); /* the normal matrix's column sums */
  *badw = 0;
  e = row_order(f, u, m, &order, &rot, st);
  if (e != BSFIT_OK) return e;
  blk.k = 0;
  blk.j0 = 0;
  blk.width = (int)p + 1 + S.q + dim;
  for (t = 0; t < m; t++) {
    size_t k = order ? order[t] : (rot + t < m ? rot + t : rot + t - m), j0;
    double x = row_param(f, u, k), wk = w ? w[k] : 1.0;
    *badw |= !(wk >= DBL_MIN); /* as the assembly: see fit.c's input_error */
    if (!(x >= f->U[s] && x < f->U[s + 1])) s = bsfit_knots_find_span(f->U, f->nraw, f->p, x);
    f->occ[s - p] = 1;
    if (f->p == 3) span_basis(f, s, x, 3, N);
    else span_basis(f, s, x, f->p, N);
    if (s != blk_span || blk.k == CHUNK) {
      if (bsfit__interrupted(&f->alloc)) /* the host's stop, at each block */
        return bsfit__fail(st, BSFIT_EINTR, "fit of %zu points interrupted", m);
      flush_block(&S, &blk);
    }
    blk_span = s;
    row = blk.x + blk.k * blk.width;
    if (plain_span(f, fx, s)) {
      j0 = f->periodic ? s - 2 * p : s - p - fx->lo;
      if (f->p == 3 && dim == 2) plain_row(pts + k * d, N, 3, S.q, 2, wk, j0, row, f->work);
      else plain_row(pts + k * d, N, f->p, S.q, dim, wk, j0, row, f->work);
    } else if (!make_row(f, &S, fx, pts + k * d, N, s, wk, row, &j0, f->work)) {
      continue; /* no free column */
    }
    blk.j0 = j0; /* the same for every row of the span */
    blk.k++;
  }
  flush_block(&S, &blk);
  return bsfit__ok(st);
}

int bsfit__qr_finite(const bsfit_fitter *f, int dim) {
  qr_sys S = qr_view(f, dim);
  size_t c;
  if (!bsfit__all_finite(S.R, S.nb * (size_t)(S.p + 1)) ||
      !bsfit__all_finite(S.B, S.nb * (size_t)S.q) ||
      !bsfit__all_finite(S.R22, (size_t)(S.q * S.q)))
    return 0;
  for (c = 0; c < (size_t)dim; c++)
    if (!bsfit__all_finite(S.z + c * S.ld, S.nb + (size_t)S.q)) return 0;
  return 1;
}

/* }====================================================================== */

/* {======================================================================
** Back substitution and the condition number
** ======================================================================= */

/* x <- R^-T x (nrhs columns of nb+q rows, leading dimension ld) */
static bsfit_err solve_rt(const qr_sys *S, double *x, size_t ld, size_t nrhs, bsfit_status *st) {
  size_t i, j, c, q = (size_t)S->q;
  bsfit_err e = BSFIT_OK;
  if (S->nb > 0) e = bsfit__tb_solve(S->nb, S->p, 0, S->R, (size_t)S->p + 1, nrhs, x, ld, st);
  if (e != BSFIT_OK || q == 0) return e;
  for (c = 0; c < nrhs; c++)
    for (j = 0; j < q; j++) {
      double v = 0.0;
      for (i = 0; i < S->nb; i++) v += S->B[i + j * S->nb] * x[i + c * ld];
      x[S->nb + j + c * ld] -= v;
    }
  return bsfit__tr_solve(q, 1, S->R22, q, nrhs, x + S->nb, ld, st);
}

/* x <- R^-1 x */
static bsfit_err solve_r(const qr_sys *S, double *x, size_t ld, size_t nrhs, bsfit_status *st) {
  size_t i, j, c, q = (size_t)S->q;
  bsfit_err e;
  if (q > 0) {
    e = bsfit__tr_solve(q, 0, S->R22, q, nrhs, x + S->nb, ld, st);
    if (e != BSFIT_OK) return e;
    for (c = 0; c < nrhs; c++)
      for (j = 0; j < q; j++) {
        double v = x[S->nb + j + c * ld];
        for (i = 0; i < S->nb; i++) x[i + c * ld] -= S->B[i + j * S->nb] * v;
      }
  }
  if (S->nb == 0) return BSFIT_OK;
  return bsfit__tb_solve(S->nb, S->p, 1, S->R, (size_t)S->p + 1, nrhs, x, ld, st);
}

/* x <- A^-1 x, A = R^T R the normal matrix */
static int normal_solve(const qr_sys *S, double *x, size_t n) {
  return solve_rt(S, x, n, 1, NULL) == BSFIT_OK && solve_r(S, x, n, 1, NULL) == BSFIT_OK;
}

static double norm1(const double *x, size_t n) {
  double s = 0.0;
  size_t i;
  for (i = 0; i < n; i++) s += fabs(x[i]);
  return s;
}

/* |A^-1|_1 by Hager's method as refined by Higham (LAPACK dlacon): a lower bound, usually
** exact; v: n doubles of scratch. 0 on failure. */
static double inverse_norm1_estimate(const qr_sys *S, size_t n, double *v) {
  double est, alt;
  size_t i, j, jx = SIZE_MAX; /* x = e/n until a unit vector e_jx replaces it */
  int it;
  for (i = 0; i < n; i++) v[i] = 1.0 / (double)n;
  if (!normal_solve(S, v, n)) return 0.0;
  est = norm1(v, n);
  for (it = 0; it < 5; it++) {
    double ztx = 0.0, best = -1.0;
    for (i = 0; i < n; i++) v[i] = v[i] >= 0.0 ? 1.0 : -1.0;
    if (!normal_solve(S, v, n)) return 0.0; /* z = A^-T sign(y); A is symmetric */
    for (i = 0, j = 0; i < n; i++) {
      ztx += jx == SIZE_MAX ? v[i] / (double)n : 0.0;
      if (fabs(v[i]) > best) best = fabs(v[i]), j = i;
    }
    if (jx != SIZE_MAX) ztx = v[jx];
    if (best <= ztx) break;
    jx = j;
    for (i = 0; i < n; i++) v[i] = i == jx ? 1.0 : 0.0;
    if (!normal_solve(S, v, n)) return 0.0;
    if (norm1(v, n) <= est) break;
    est = norm1(v, n);
  }
  /* Higham's extra test vector guards against the cases the iteration misses */
  for (i = 0; i < n; i++)
    v[i] = (i % 2 ? -1.0 : 1.0) * (1.0 + (n > 1 ? (double)i / (double)(n - 1) : 0.0));
  if (!normal_solve(S, v, n)) return 0.0;
  alt = 2.0 * norm1(v, n) / (3.0 * (double)n);
  return alt > est ? alt : est;
}

/* 1 / (|A|_1 |A^-1|_1): open fits exact (A totally nonnegative, see linalg.c), periodic
** fits Hager's estimate. The column sums of A came with the factorisation. */
static double qr_rcond(const bsfit_fitter *f, const qr_sys *S) {
  size_t n = S->nb + (size_t)S->q, i;
  double anorm = 0.0, inv = 0.0, *v = f->work + f->nraw;
  if (n == 0) return 1.0;
  for (i = 0; i < n; i++)
    if (f->work[i] > anorm) anorm = f->work[i];
  if (S->q == 0) {
    for (i = 0; i < n; i++) v[i] = i % 2 ? -1.0 : 1.0;
    if (normal_solve(S, v, n))
      for (i = 0; i < n; i++)
        if (fabs(v[i]) > inv) inv = fabs(v[i]);
  } else {
    inv = inverse_norm1_estimate(S, n, v);
  }
  return inv > 0.0 && anorm > 0.0 && isfinite(inv) ? 1.0 / (inv * anorm) : 0.0;
}

bsfit_err bsfit__qr_solve(bsfit_fitter *f, int dim, const bsfit__fixed_set *fx, double *ctrl,
                          double *rcond, bsfit_status *st) {
  qr_sys S = qr_view(f, dim);
  size_t i, c, d = (size_t)dim, p = (size_t)f->p, q = (size_t)S.q;
  bsfit_err e = solve_r(&S, S.z, S.ld, d, st);
  if (e != BSFIT_OK) return e;
  for (i = 0; i < S.nb; i++) {
    size_t row = f->periodic ? p + i : fx->lo + i;
    for (c = 0; c < d; c++) ctrl[row * d + c] = S.z[i + c * S.ld];
  }
  for (i = 0; i < q; i++)
    for (c = 0; c < d; c++) ctrl[i * d + c] = S.z[S.nb + i + c * S.ld];
  for (i = 0; !f->periodic && i < fx->count; i++)
    for (c = 0; c < d; c++) ctrl[fx->idx[i] * d + c] = fx->val[i][c];
  if (rcond) *rcond = qr_rcond(f, &S);
  return BSFIT_OK;
}

/* }====================================================================== */
