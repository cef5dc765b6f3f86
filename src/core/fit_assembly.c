/*
** fit_assembly.c
** The fitter's two passes over the points, span by span (docs/method.md §5): the banded normal
** equations N^T W N P = N^T W Q, and the residuals |Q_k - C(u_k)| of the solved curve.
**
** Degrees 1..3 (nearly every fit) work with power moments. On span s the p+1 non-zero
** basis functions are polynomials in the local variable t = (u - mid) / half, |t| <= 1
** inside the span: N_i = sum_a C_ia t^a. Hence
**   sum_k w_k N_i(t_k) N_j(t_k) = sum_ab C_ia C_jb M_{a+b},   M_c = sum_k w_k t_k^c,
**   sum_k w_k N_i(t_k) Q_k      = sum_a  C_ia R_a,            R_a = sum_k w_k t_k^a Q_k,
** so a point costs its 2p powers of t and (p+1) dim products instead of a basis
** evaluation and (p+1)^2 products; C comes once per span (Cox-de Boor run on linear
** polynomials). The residual pass evaluates each span's curve as a polynomial in t by
** Horner. Accuracy: a cubic bounded by 1 on [-1, 1] has power coefficients no larger than
** the Chebyshev ones (4), so forming C H C^T loses at most a few hundred ulps relative to
** the matrix norm; the test suite's 1e-10 reproduction and 1e-9 dense agreement hold.
** Higher degrees evaluate the basis point by point (NURBS Book A2.2).
**
** Neither pass validates its input: NaN or Inf in a point, parameter or weight reaches the
** band or the right-hand sides, which fit.c checks once (O(n), not O(m)); non-positive
** weights are flagged here because they would pass unnoticed.
*/
#include "fit_internal.h"

#include <math.h>
#include <string.h>

#if defined(__GNUC__)
#  define FIT_INLINE static inline __attribute__((always_inline))
/* Pairs of doubles (GCC/Clang vector extensions: SSE2 on x86-64, NEON on arm64, plain
** pairs elsewhere) for the hot kernels; other compilers take the scalar code. */
#  define FIT_PAIRS 1
typedef double pair __attribute__((vector_size(16)));
typedef long long pair_mask __attribute__((vector_size(16)));
#else
#  define FIT_INLINE static inline
#  define FIT_PAIRS 0
#endif

#define MOMENT_MAX_DEGREE 3

/* {======================================================================
** Per-span preparation: reciprocal knot differences and polynomial coefficients
** ======================================================================= */

size_t bsfit__fit_poly_stride(int p) {
  return p <= MOMENT_MAX_DEGREE ? (size_t)(p + 1) * (size_t)(p + 1) + 2 : 0;
}

/* Power coefficients of the basis functions N_{s-p+i} in t, u = mid + half t, stored
** power-major: C[a*(p+1) + i] is the t^a coefficient of N_{s-p+i} (the layout the
** kernels read: for a power a, the p+1 functions side by side). Cox-de Boor on
** polynomials: left_{j-r} = (mid - U[s+1-j+r]) + half t and right_{r+1} = (U[s+r+1] - mid)
** - half t. Every polynomial is kept as 4 coefficients, zero above its degree, so each step
** is the same branch-free arithmetic and a constant p unrolls completely. */
FIT_INLINE void span_poly(const double *U, size_t s, const int p, double *C) {
  double N[MOMENT_MAX_DEGREE + 1][4] = {{1.0, 0.0, 0.0, 0.0}};
  double mid = 0.5 * (U[s] + U[s + 1]), half = 0.5 * (U[s + 1] - U[s]);
  int i, j, r, a;
  for (j = 1; j <= p; j++) {
    double saved[4] = {0.0, 0.0, 0.0, 0.0};
    for (r = 0; r < j; r++) {
      double lo = U[s + 1 - (size_t)(j - r)], hi = U[s + (size_t)r + 1], den = hi - lo;
      double iv = den != 0.0 ? 1.0 / den : 0.0; /* 0/0 = 0 at repeated knots */
      double lc = mid - lo, rc = hi - mid, tmp[4], sh[4];
      for (a = 0; a < 4; a++) tmp[a] = N[r][a] * iv;
      sh[0] = 0.0; /* sh = t * tmp */
      for (a = 1; a < 4; a++) sh[a] = tmp[a - 1];
      for (a = 0; a < 4; a++) {
        N[r][a] = saved[a] + rc * tmp[a] - half * sh[a];
        saved[a] = lc * tmp[a] + half * sh[a];
      }
    }
    for (a = 0; a < 4; a++) N[j][a] = saved[a];
  }
  for (a = 0; a <= p; a++)
    for (i = 0; i <= p; i++) C[a * (p + 1) + i] = N[i][a];
  C[(p + 1) * (p + 1)] = mid;
  C[(p + 1) * (p + 1) + 1] = half > 0.0 ? 1.0 / half : 0.0; /* empty spans get no points */
}

#if FIT_PAIRS
/* span_poly for two spans at once, one per lane: the recurrence is a chain of dependent
** products, so two independent spans side by side keep the pipeline full. Same
** arithmetic, so the same results, as span_poly. */
FIT_INLINE void span_poly_pair(const double *U, size_t s0, size_t s1, const int p, double *C0,
                               double *C1) {
  const pair zero = {0.0, 0.0}, one = {1.0, 1.0}, ends0 = {U[s0], U[s1]},
             ends1 = {U[s0 + 1], U[s1 + 1]};
  pair N[MOMENT_MAX_DEGREE + 1][4], mid = 0.5 * (ends0 + ends1), half = 0.5 * (ends1 - ends0);
  int i, j, r, a;
  for (i = 0; i <= p; i++)
    for (a = 0; a < 4; a++) N[i][a] = zero;
  N[0][0] = one;
  for (j = 1; j <= p; j++) {
    pair saved[4] = {zero, zero, zero, zero};
    for (r = 0; r < j; r++) {
      size_t l = (size_t)(j - r) - 1, h = (size_t)r + 1;
      pair lo = {U[s0 - l], U[s1 - l]}, hi = {U[s0 + h], U[s1 + h]}, den = hi - lo;
      pair_mask nz = (pair_mask)(den != zero);
      pair iv = one / (pair)(((pair_mask)den & nz) | ((pair_mask)one & ~nz));
      pair lc = mid - lo, rc = hi - mid, tmp[4], sh[4];
      iv = (pair)((pair_mask)iv & nz); /* 0/0 = 0 at repeated knots */
      for (a = 0; a < 4; a++) tmp[a] = N[r][a] * iv;
      sh[0] = zero;
      for (a = 1; a < 4; a++) sh[a] = tmp[a - 1];
      for (a = 0; a < 4; a++) {
        N[r][a] = saved[a] + rc * tmp[a] - half * sh[a];
        saved[a] = lc * tmp[a] + half * sh[a];
      }
    }
    for (a = 0; a < 4; a++) N[j][a] = saved[a];
  }
  for (a = 0; a <= p; a++)
    for (i = 0; i <= p; i++) {
      C0[a * (p + 1) + i] = N[i][a][0];
      C1[a * (p + 1) + i] = N[i][a][1];
    }
  C0[(p + 1) * (p + 1)] = mid[0];
  C1[(p + 1) * (p + 1)] = mid[1];
  C0[(p + 1) * (p + 1) + 1] = half[0] > 0.0 ? 1.0 / half[0] : 0.0;
  C1[(p + 1) * (p + 1) + 1] = half[1] > 0.0 ? 1.0 / half[1] : 0.0;
}

static void prepare_polys(bsfit_fitter *f, const int p) {
  size_t s, P = (size_t)p, stride = bsfit__fit_poly_stride(p), last = f->nraw - 1;
  double *C = f->poly;
  for (s = P; s + 1 <= last; s += 2, C += 2 * stride) span_poly_pair(f->U, s, s + 1, p, C, C + stride);
  if (s == last) span_poly(f->U, s, p, C);
}
#else
static void prepare_polys(bsfit_fitter *f, const int p) {
  size_t s, P = (size_t)p, stride = bsfit__fit_poly_stride(p);
  for (s = P; s < f->nraw; s++) span_poly(f->U, s, p, f->poly + (s - P) * stride);
}
#endif

void bsfit__fit_prepare_spans(bsfit_fitter *f) {
  size_t s, p = (size_t)f->p;
  const double *U = f->U;
  double *inv = f->inv;
  if (bsfit__fit_poly_stride(f->p) > 0) {
    if (p == 3) prepare_polys(f, 3); /* the common degree, unrolled */
    else prepare_polys(f, f->p);
    return;
  }
  /* higher degrees: the Cox-de Boor denominators U[s+r+1] - U[s+1-j+r] of each span */
  for (s = p; s < f->nraw; s++) {
    size_t j, r;
    for (j = 1; j <= p; j++)
      for (r = 0; r < j; r++) {
        double den = U[s + r + 1] - U[s + 1 - j + r];
        *inv++ = den != 0.0 ? 1.0 / den : 0.0; /* 0/0 = 0 at repeated knots */
      }
  }
}

/* }====================================================================== */

/* {======================================================================
** Span search
** ======================================================================= */

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

/* The next group of consecutive points in one span: its span and bounds. A NaN parameter
** forms a group of its own (no comparison holds), and poisons the sums as it should. */
typedef struct span_walk {
  const double *U;
  size_t n, last, s;
  double a, b;
  int p, periodic;
} span_walk;

FIT_INLINE void walk_init(span_walk *sw, const bsfit_fitter *f) {
  sw->U = f->U;
  sw->n = f->nraw;
  sw->p = f->p;
  sw->s = (size_t)f->p;
  sw->last = last_span(f->U, f->nraw, f->p);
  sw->a = f->U[f->p];
  sw->b = f->U[f->nraw];
  sw->periodic = f->periodic;
}

FIT_INLINE double walk_param(const span_walk *sw, const double *u, size_t k) {
  return sw->periodic ? bsfit__wrap_param(u[k], sw->a, sw->b) : u[k];
}

FIT_INLINE void walk_to(span_walk *sw, double x, double *lo, double *hi) {
  sw->s = next_span(sw->U, sw->n, sw->p, sw->s, x);
  span_bounds(sw->U, sw->p, sw->last, sw->s, lo, hi);
}

/* }====================================================================== */

/* {======================================================================
** Degrees 1..3: power moments
** ======================================================================= */

/* pw[a] = w t^a, a = 0..2p, by a shallow product tree (no serial chain of 2p products) */
FIT_INLINE void moment_powers(double w, double t, const int p, double *pw) {
  double t2 = t * t, wt = w * t;
  int a;
  if (p == 3) {
    double t4 = t2 * t2;
    pw[0] = w, pw[1] = wt, pw[2] = w * t2, pw[3] = wt * t2;
    pw[4] = w * t4, pw[5] = wt * t4, pw[6] = pw[2] * t4;
    return;
  }
  pw[0] = w;
  for (a = 1; a <= 2 * p; a++) pw[a] = pw[a - 1] * t;
  (void)t2, (void)wt;
}

/* Adds one span's moments to the band (lower storage) and the right-hand sides:
** A += C H C^T with H_ab = M_{a+b}, rhs += C R. */
FIT_INLINE void flush_moments(bsfit_fitter *f, size_t s, const int p, const int dim,
                              const double *C, const double *M, const double *R) {
  size_t ldab = (size_t)p + 1, first = s - (size_t)p, n = f->nraw;
  double T[(MOMENT_MAX_DEGREE + 1) * (MOMENT_MAX_DEGREE + 1)];
  int i, j, a, b, c;
  for (a = 0; a <= p; a++) /* T = H C^T */
    for (j = 0; j <= p; j++) {
      double v = 0.0;
      for (b = 0; b <= p; b++) v += M[a + b] * C[b * (p + 1) + j];
      T[a * (p + 1) + j] = v;
    }
  for (i = 0; i <= p; i++)
    for (j = 0; j <= i; j++) {
      double v = 0.0;
      for (a = 0; a <= p; a++) v += C[a * (p + 1) + i] * T[a * (p + 1) + j];
      f->band[(size_t)(i - j) + (first + (size_t)j) * ldab] += v;
    }
  for (i = 0; i <= p; i++)
    for (c = 0; c < dim; c++) {
      double v = 0.0;
      for (a = 0; a <= p; a++) v += C[a * (p + 1) + i] * R[a * 4 + c];
      f->rhs[(size_t)c * n + first + (size_t)i] += v;
    }
  f->occ[first] = 1;
}

FIT_INLINE int moment_assemble(bsfit_fitter *f, const double *pts, size_t m, const int dim,
                               const double *u, const double *w, const int p) {
  size_t k = 0, stride = bsfit__fit_poly_stride(p);
  span_walk sw;
  double wmin = 1.0; /* NaN is caught by the sums' finiteness check; subnormal: fit.c */
  int a, c;
  walk_init(&sw, f);
  while (k < m) {
    double x = walk_param(&sw, u, k), lo, hi, mid, scale;
    double M[2 * MOMENT_MAX_DEGREE + 1] = {0.0}, R[(MOMENT_MAX_DEGREE + 1) * 4] = {0.0};
    const double *C;
    walk_to(&sw, x, &lo, &hi);
    C = f->poly + (sw.s - (size_t)p) * stride;
    mid = C[(p + 1) * (p + 1)];
    scale = C[(p + 1) * (p + 1) + 1];
    do {
      const double *q = pts + k * (size_t)dim;
      double wk = w ? w[k] : 1.0, t = (x - mid) * scale, pw[2 * MOMENT_MAX_DEGREE + 1];
      wmin = wk < wmin ? wk : wmin;
      moment_powers(wk, t, p, pw);
      for (a = 0; a <= 2 * p; a++) M[a] += pw[a];
      for (a = 0; a <= p; a++)
        for (c = 0; c < dim; c++) R[a * 4 + c] += pw[a] * q[c];
      if (++k == m) break;
      x = walk_param(&sw, u, k);
    } while (x >= lo && x < hi);
    flush_moments(f, sw.s, p, dim, C, M, R);
  }
  return !(wmin >= DBL_MIN);
}

typedef struct resid_acc {
  double wss, wsum, max; /* max starts below 0: no point yet */
  size_t imax;
} resid_acc;

/* One point's squared distance dd into the sums (and its distance into res). */
FIT_INLINE void resid_add(resid_acc *a, size_t k, double dd, double wk, double *res) {
  double r = sqrt(dd);
  if (res) res[k] = r;
  a->wss += wk * dd;
  a->wsum += wk;
  if (r > a->max) a->max = r, a->imax = k;
}

FIT_INLINE void moment_residuals(const bsfit_fitter *f, const double *ctrl, const double *pts,
                                 size_t m, const int dim, const double *u, const double *w,
                                 const int p, double *res, resid_acc *out) {
  size_t k = 0, stride = bsfit__fit_poly_stride(p);
  resid_acc acc = {0.0, 0.0, -1.0, 0};
  span_walk sw;
  int i, a, c;
  walk_init(&sw, f);
  while (k < m) {
    double x = walk_param(&sw, u, k), lo, hi, mid, scale;
    double D[(MOMENT_MAX_DEGREE + 1) * 4];
    const double *C, *P;
    walk_to(&sw, x, &lo, &hi);
    C = f->poly + (sw.s - (size_t)p) * stride;
    P = ctrl + (sw.s - (size_t)p) * (size_t)dim;
    mid = C[(p + 1) * (p + 1)];
    scale = C[(p + 1) * (p + 1) + 1];
    for (a = 0; a <= p; a++) /* the span's curve: D_a = sum_i C_ia P_i */
      for (c = 0; c < dim; c++) {
        double v = 0.0;
        for (i = 0; i <= p; i++) v += C[a * (p + 1) + i] * P[i * dim + c];
        D[a * 4 + c] = v;
      }
    do {
      const double *q = pts + k * (size_t)dim;
      double wk = w ? w[k] : 1.0, t = (x - mid) * scale, dd = 0.0;
      for (c = 0; c < dim; c++) {
        double v = D[p * 4 + c], d;
        for (a = p - 1; a >= 0; a--) v = v * t + D[a * 4 + c];
        d = q[c] - v;
        dd += d * d;
      }
      resid_add(&acc, k, dd, wk, res);
      if (++k == m) break;
      x = walk_param(&sw, u, k);
    } while (x >= lo && x < hi);
  }
  *out = acc;
}

#if FIT_PAIRS
/* Cubic 2D, the shape of nearly every section, in pairs: the 15 running sums fit in 8
** registers instead of spilling to the stack, and a point is 16 pair operations. */

/* An unaligned pair in memory (the band and right-hand sides have no 16-byte alignment). */
typedef double pair_u __attribute__((vector_size(16), aligned(8)));

FIT_INLINE void add_pair(double *dst, pair v) {
  *(pair_u *)(void *)dst += v;
}

/* flush_moments for cubic 2D in pairs. With C power-major, T_a = sum_b M_{a+b} C_b (C_b:
** the four functions' t^b coefficients) is the row a of H C^T, and row i of C H C^T is
** sum_a C_ai T_a; the band takes row i from column i on (lower storage, by symmetry). */
FIT_INLINE void cubic2_flush(bsfit_fitter *f, size_t s, const double *C, const double *M,
                             const double *Rx, const double *Ry) {
  size_t first = s - 3, n = f->nraw;
  double *band = f->band + 4 * first;
  pair Tlo[4], Thi[4], lo, hi;
  int a, b;
  for (a = 0; a < 4; a++) {
    pair tl = {0.0, 0.0}, th = tl;
    for (b = 0; b < 4; b++) {
      pair cl = {C[4 * b], C[4 * b + 1]}, ch = {C[4 * b + 2], C[4 * b + 3]};
      tl += M[a + b] * cl, th += M[a + b] * ch;
    }
    Tlo[a] = tl, Thi[a] = th;
  }
  lo = (pair){0.0, 0.0}, hi = lo; /* row 0: columns 0..3 */
  for (a = 0; a < 4; a++) lo += C[4 * a] * Tlo[a], hi += C[4 * a] * Thi[a];
  add_pair(band, lo), add_pair(band + 2, hi);
  lo = (pair){0.0, 0.0}, hi = lo; /* row 1: columns 1..3 */
  for (a = 0; a < 4; a++) lo += C[4 * a + 1] * Tlo[a], hi += C[4 * a + 1] * Thi[a];
  band[4] += lo[1], add_pair(band + 5, hi);
  lo = (pair){0.0, 0.0}, hi = lo; /* rows 2 and 3: columns 2..3 and 3 */
  for (a = 0; a < 4; a++) lo += C[4 * a + 2] * Thi[a], hi += C[4 * a + 3] * Thi[a];
  add_pair(band + 8, lo), band[12] += hi[1];
  lo = (pair){0.0, 0.0}, hi = lo; /* right-hand sides: rhs_i += sum_a C_ai R_a */
  for (a = 0; a < 4; a++) {
    pair cl = {C[4 * a], C[4 * a + 1]}, ch = {C[4 * a + 2], C[4 * a + 3]};
    lo += Rx[a] * cl, hi += Rx[a] * ch;
  }
  add_pair(f->rhs + first, lo), add_pair(f->rhs + first + 2, hi);
  lo = (pair){0.0, 0.0}, hi = lo;
  for (a = 0; a < 4; a++) {
    pair cl = {C[4 * a], C[4 * a + 1]}, ch = {C[4 * a + 2], C[4 * a + 3]};
    lo += Ry[a] * cl, hi += Ry[a] * ch;
  }
  add_pair(f->rhs + n + first, lo), add_pair(f->rhs + n + first + 2, hi);
  f->occ[first] = 1;
}

static int cubic2_assemble(bsfit_fitter *f, const double *pts, size_t m, const double *u,
                           const double *w) {
  size_t k = 0, stride = bsfit__fit_poly_stride(3);
  span_walk sw;
  double wmin = 1.0; /* NaN is caught by the sums' finiteness check; subnormal: fit.c */
  walk_init(&sw, f);
  while (k < m) {
    double x = walk_param(&sw, u, k), lo, hi, mid, scale, M[7], Rx[4], Ry[4];
    pair m01 = {0.0, 0.0}, m23 = m01, m45 = m01, m6 = m01, x01 = m01, x23 = m01, y01 = m01,
         y23 = m01;
    const double *C;
    walk_to(&sw, x, &lo, &hi);
    C = f->poly + (sw.s - 3) * stride;
    mid = C[16];
    scale = C[17];
    do {
      double wk = w ? w[k] : 1.0, t = (x - mid) * scale, t2 = t * t, t4 = t2 * t2;
      pair e01 = {wk, wk * t}, e23 = e01 * t2, e45 = e01 * t4, t4z = {t4, 0.0};
      pair qx = {pts[2 * k], pts[2 * k]}, qy = {pts[2 * k + 1], pts[2 * k + 1]};
      wmin = wk < wmin ? wk : wmin;
      m01 += e01, m23 += e23, m45 += e45, m6 += e23 * t4z;
      x01 += e01 * qx, x23 += e23 * qx, y01 += e01 * qy, y23 += e23 * qy;
      if (++k == m) break;
      x = walk_param(&sw, u, k);
    } while (x >= lo && x < hi);
    M[0] = m01[0], M[1] = m01[1], M[2] = m23[0], M[3] = m23[1], M[4] = m45[0], M[5] = m45[1];
    M[6] = m6[0];
    Rx[0] = x01[0], Rx[1] = x01[1], Rx[2] = x23[0], Rx[3] = x23[1];
    Ry[0] = y01[0], Ry[1] = y01[1], Ry[2] = y23[0], Ry[3] = y23[1];
    cubic2_flush(f, sw.s, C, M, Rx, Ry);
  }
  return !(wmin >= DBL_MIN);
}

static void cubic2_residuals(const bsfit_fitter *f, const double *ctrl, const double *pts,
                             size_t m, const double *u, const double *w, double *res,
                             resid_acc *out) {
  size_t k = 0, stride = bsfit__fit_poly_stride(3);
  resid_acc acc = {0.0, 0.0, -1.0, 0};
  span_walk sw;
  int i, a;
  walk_init(&sw, f);
  while (k < m) {
    double x = walk_param(&sw, u, k), lo, hi, mid, scale;
    pair D[4];
    const double *C, *P;
    walk_to(&sw, x, &lo, &hi);
    C = f->poly + (sw.s - 3) * stride;
    P = ctrl + (sw.s - 3) * 2;
    mid = C[16];
    scale = C[17];
    for (a = 0; a <= 3; a++) { /* the span's curve: D_a = sum_i C_ia P_i */
      pair v = {0.0, 0.0};
      for (i = 0; i <= 3; i++) {
        pair pi = {P[2 * i], P[2 * i + 1]};
        v += C[a * 4 + i] * pi;
      }
      D[a] = v;
    }
    do {
      double wk = w ? w[k] : 1.0, t = (x - mid) * scale, dd;
      pair q = {pts[2 * k], pts[2 * k + 1]}, d = ((D[3] * t + D[2]) * t + D[1]) * t + D[0];
      d = q - d;
      d *= d;
      dd = d[0] + d[1];
      resid_add(&acc, k, dd, wk, res);
      if (++k == m) break;
      x = walk_param(&sw, u, k);
    } while (x >= lo && x < hi);
  }
  *out = acc;
}
#endif

/* }====================================================================== */

/* {======================================================================
** Any degree: basis functions point by point
** ======================================================================= */

/* The p+1 non-zero basis functions at u in span s (NURBS Book A2.2 with the divisions
** replaced by the span's precomputed reciprocals; keep in step with basis.c). */
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

/* Adds one span's local sums to the band (lower storage) and the right-hand sides. */
static void flush_basis(bsfit_fitter *f, size_t s, int p, int dim, const double *acc,
                        const double *racc) {
  size_t ldab = (size_t)p + 1, first = s - (size_t)p, n = f->nraw;
  int i, j, c;
  for (i = 0; i <= p; i++)
    for (j = 0; j <= i; j++)
      f->band[(size_t)(i - j) + (first + (size_t)j) * ldab] += acc[i * (p + 1) + j];
  for (i = 0; i <= p; i++)
    for (c = 0; c < dim; c++) f->rhs[(size_t)c * n + first + (size_t)i] += racc[i * dim + c];
  f->occ[first] = 1;
}

static int basis_assemble(bsfit_fitter *f, const double *pts, size_t m, int dim,
                          const double *u, const double *w) {
  double acc[(BSFIT_MAX_DEGREE + 1) * (BSFIT_MAX_DEGREE + 1)];
  double racc[(BSFIT_MAX_DEGREE + 1) * 4];
  double N[BSFIT_MAX_DEGREE + 1], wN[BSFIT_MAX_DEGREE + 1];
  size_t k = 0;
  span_walk sw;
  int p = f->p, badw = 0, i, j, c;
  walk_init(&sw, f);
  while (k < m) {
    double x = walk_param(&sw, u, k), lo, hi;
    const double *inv;
    walk_to(&sw, x, &lo, &hi);
    inv = f->inv + (sw.s - (size_t)p) * f->tri;
    memset(acc, 0, (size_t)((p + 1) * (p + 1)) * sizeof(double));
    memset(racc, 0, (size_t)((p + 1) * dim) * sizeof(double));
    do {
      const double *q = pts + k * (size_t)dim;
      double wk = w ? w[k] : 1.0;
      badw |= !(wk >= DBL_MIN);
      basis_inv(sw.U, inv, sw.s, x, p, N);
      for (i = 0; i <= p; i++) wN[i] = wk * N[i];
      for (i = 0; i <= p; i++)
        for (j = 0; j <= i; j++) acc[i * (p + 1) + j] += wN[i] * N[j];
      for (i = 0; i <= p; i++)
        for (c = 0; c < dim; c++) racc[i * dim + c] += wN[i] * q[c];
      if (++k == m) break;
      x = walk_param(&sw, u, k);
    } while (x >= lo && x < hi);
    flush_basis(f, sw.s, p, dim, acc, racc);
  }
  return badw;
}

static void basis_residuals(const bsfit_fitter *f, const double *ctrl, const double *pts,
                            size_t m, int dim, const double *u, const double *w, double *res,
                            resid_acc *out) {
  double N[BSFIT_MAX_DEGREE + 1];
  size_t k = 0;
  resid_acc acc = {0.0, 0.0, -1.0, 0};
  span_walk sw;
  int p = f->p, i, c;
  walk_init(&sw, f);
  while (k < m) {
    double x = walk_param(&sw, u, k), lo, hi;
    const double *inv, *P;
    walk_to(&sw, x, &lo, &hi);
    inv = f->inv + (sw.s - (size_t)p) * f->tri;
    P = ctrl + (sw.s - (size_t)p) * (size_t)dim;
    do {
      const double *q = pts + k * (size_t)dim;
      double wk = w ? w[k] : 1.0, dd = 0.0;
      basis_inv(sw.U, inv, sw.s, x, p, N);
      for (c = 0; c < dim; c++) {
        double v = q[c];
        for (i = 0; i <= p; i++) v -= N[i] * P[i * dim + c];
        dd += v * v;
      }
      resid_add(&acc, k, dd, wk, res);
      if (++k == m) break;
      x = walk_param(&sw, u, k);
    } while (x >= lo && x < hi);
  }
  *out = acc;
}

/* }====================================================================== */

/* {======================================================================
** Entry points: the common shapes get their own instances of the kernels
** ======================================================================= */

/* The points go through the kernels in chunks of CHUNK_POINTS, and the host's
** interrupt (bsfit_allocator.interrupt) is read between chunks: the kernels' inner
** loops stay as they are (a check inside them cost 8% of the assembly, in register
** pressure), and a stop is seen within a fraction of a millisecond. A span cut by a
** chunk boundary simply gets its sums in two parts. */
#define CHUNK_POINTS 16384

static int assemble_chunk(bsfit_fitter *f, const double *pts, size_t m, int dim, const double *u,
                          const double *w) {
  int p = f->p;
#if FIT_PAIRS
  if (p == 3 && dim == 2) return cubic2_assemble(f, pts, m, u, w);
#endif
  if (p == 3 && dim == 3) return moment_assemble(f, pts, m, 3, u, w, 3);
  if (p <= MOMENT_MAX_DEGREE) return moment_assemble(f, pts, m, dim, u, w, p);
  return basis_assemble(f, pts, m, dim, u, w);
}

int bsfit__fit_assemble(bsfit_fitter *f, const double *pts, size_t m, int dim, const double *u,
                        const double *w) {
  size_t k, len, d = (size_t)dim;
  int badw = 0;
  memset(f->band, 0, (size_t)(f->p + 1) * f->nraw * sizeof(double));
  memset(f->rhs, 0, d * f->nraw * sizeof(double));
  memset(f->occ, 0, f->nraw);
  for (k = 0; k < m; k += len) {
    if (k > 0 && bsfit__interrupted(&f->alloc)) return -1;
    len = m - k < CHUNK_POINTS ? m - k : CHUNK_POINTS;
    badw |= assemble_chunk(f, pts + k * d, len, dim, u + k, w ? w + k : NULL);
  }
  return badw;
}

static void residuals_chunk(const bsfit_fitter *f, const double *ctrl, const double *pts,
                            size_t m, int dim, const double *u, const double *w, double *res,
                            resid_acc *acc) {
  int p = f->p;
#if FIT_PAIRS
  if (p == 3 && dim == 2) cubic2_residuals(f, ctrl, pts, m, u, w, res, acc);
  else
#endif
  if (p == 3 && dim == 3) moment_residuals(f, ctrl, pts, m, 3, u, w, 3, res, acc);
  else if (p <= MOMENT_MAX_DEGREE) moment_residuals(f, ctrl, pts, m, dim, u, w, p, res, acc);
  else basis_residuals(f, ctrl, pts, m, dim, u, w, res, acc);
}

int bsfit__fit_residuals(const bsfit_fitter *f, const double *ctrl, const double *pts,
                         size_t m, int dim, const double *u, const double *w, double *res,
                         double *wrms, double *max, size_t *imax) {
  resid_acc all = {0.0, 0.0, -1.0, 0}, acc;
  size_t k, len, d = (size_t)dim;
  for (k = 0; k < m; k += len) {
    if (k > 0 && bsfit__interrupted(&f->alloc)) return -1;
    len = m - k < CHUNK_POINTS ? m - k : CHUNK_POINTS;
    residuals_chunk(f, ctrl, pts + k * d, len, dim, u + k, w ? w + k : NULL, res ? res + k : NULL,
                    &acc);
    all.wss += acc.wss;
    all.wsum += acc.wsum;
    if (acc.max > all.max) all.max = acc.max, all.imax = k + acc.imax;
  }
  *wrms = all.wsum > 0.0 ? sqrt(all.wss / all.wsum) : 0.0;
  *max = all.max < 0.0 ? 0.0 : all.max;
  *imax = all.imax;
  return 0;
}

/* }====================================================================== */
