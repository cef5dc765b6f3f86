/*
** curve_eval.c
** Derivatives of any order (NURBS Book A3.2 on the basis derivatives of A2.3; rational
** curves by A4.2 on the homogeneous derivatives) and batch evaluation at many parameters,
** with an incremental span search for sorted input and an inlined cubic basis for the
** hot case (polynomial, degree 3, dimension 2 or 3).
*/
#include "curve_ops_internal.h"

#include <math.h>
#include <string.h>

#if defined(__GNUC__)
#  define BSFIT_INLINE static inline __attribute__((always_inline))
#else
#  define BSFIT_INLINE static inline
#endif

/* {====================================================================
** Derivatives
** ===================================================================== */

/* Rational derivatives from homogeneous ones (A4.2): C^(j) = (A^(j) - sum_{i=1..j}
** binom(j,i) w^(i) C^(j-i)) / w. A and w hold orders 0..top; higher orders are 0. */
static void rational_ders(const double *A, const double *w, int top, int k, size_t d,
                          double *out) {
  int j, i;
  size_t q;
  for (j = 0; j <= k; j++) {
    double *Cj = out + (size_t)j * d, binom = 1.0;
    for (q = 0; q < d; q++) Cj[q] = j <= top ? A[(size_t)j * d + q] : 0.0;
    for (i = 1; i <= j && i <= top; i++) {
      binom = binom * (double)(j - i + 1) / (double)i;
      for (q = 0; q < d; q++) Cj[q] -= binom * w[i] * out[(size_t)(j - i) * d + q];
    }
    for (q = 0; q < d; q++) Cj[q] /= w[0];
  }
}

void bsfit__curve_derivs_span(const bsfit_curve *c, size_t s, double u, int k, double *out) {
  double ders[(BSFIT_MAX_DEGREE + 1) * (BSFIT_MAX_DEGREE + 1)];
  double A[(BSFIT_MAX_DEGREE + 1) * 4], w[BSFIT_MAX_DEGREE + 1] = {0};
  int p = c->degree, top = k < p ? k : p, j, r;
  size_t d = (size_t)c->dim, q, first = s - (size_t)p;
  /* A3.2: orders above p vanish for the polynomial (or homogeneous) curve */
  bsfit_basis_ders(s, u, p, top, c->knots, ders);
  for (j = 0; j <= top; j++) {
    const double *Nj = ders + (size_t)j * (size_t)(p + 1);
    double *Aj = A + (size_t)j * d;
    w[j] = 0.0;
    for (q = 0; q < d; q++) Aj[q] = 0.0;
    for (r = 0; r <= p; r++) {
      const double *P = c->ctrl + (first + (size_t)r) * d;
      double f = c->weights ? Nj[r] * c->weights[first + (size_t)r] : Nj[r];
      for (q = 0; q < d; q++) Aj[q] += f * P[q];
      w[j] += f;
    }
  }
  if (c->weights) {
    rational_ders(A, w, top, k, d, out);
    return;
  }
  memcpy(out, A, (size_t)(top + 1) * d * sizeof(double));
  if (k > top) memset(out + (size_t)(top + 1) * d, 0, (size_t)(k - top) * d * sizeof(double));
}

bsfit_err bsfit_curve_derivs(const bsfit_curve *c, double u, int k, double *out,
                             bsfit_status *st) {
  size_t s;
  bsfit_err e = bsfit__curve_check(c, st);
  if (e != BSFIT_OK) return e;
  if (k < 0) return bsfit__fail(st, BSFIT_EINVAL, "derivative order k = %d is negative", k);
  if (out == NULL) return bsfit__fail(st, BSFIT_EINVAL, "no output array");
  if (!isfinite(u)) return bsfit__fail(st, BSFIT_ENONFINITE, "parameter u is not finite");
  if (!bsfit__curve_reach(c, u))
    return bsfit__fail(st, BSFIT_EDOMAIN,
                       "parameter %g is more than one domain length outside the domain", u);
  u = bsfit__curve_wrap(c, u);
  s = bsfit_knots_find_span(c->knots, c->n, c->degree, u);
  bsfit__curve_derivs_span(c, s, u, k, out);
  /* the k-th derivative grows like 1 / span^k: over knots 1e-15 apart it can pass
  ** DBL_MAX even for bounded control points */
  if (!bsfit__all_finite(out, (size_t)(k + 1) * (size_t)c->dim))
    return bsfit__fail(st, BSFIT_ERANGE, "derivative of order <= %d at u = %g overflows", k, u);
  return bsfit__ok(st);
}

/* }==================================================================== */

/* {====================================================================
** Batch evaluation
** ===================================================================== */

/* Span search that remembers the last span: sorted parameters advance it by a few
** steps, anything else falls back to the binary search. */
typedef struct span_cursor {
  const double *U;
  size_t n, s, s_last;
  int p;
  double b;
} span_cursor;

static void cursor_init(span_cursor *k, const bsfit_curve *c) {
  k->U = c->knots;
  k->n = c->n;
  k->p = c->degree;
  k->b = c->knots[c->n];
  k->s_last = bsfit_knots_find_span(c->knots, c->n, c->degree, k->b);
  k->s = bsfit_knots_find_span(c->knots, c->n, c->degree, c->knots[c->degree]);
}

BSFIT_INLINE size_t cursor_find(span_cursor *k, double u) {
  const double *U = k->U;
  size_t s = k->s;
  if (u >= U[s + 1]) {
    int steps = 8;
    if (u >= k->b) {
      s = k->s_last;
    } else {
      while (u >= U[s + 1] && steps-- > 0) s++;
      if (u >= U[s + 1]) s = bsfit_knots_find_span(U, k->n, k->p, u);
    }
  } else if (u < U[s]) {
    s = bsfit_knots_find_span(U, k->n, k->p, u);
  }
  k->s = s;
  return s;
}

/* The reciprocals of the six knot differences the cubic basis divides by; they depend
** on the span only, so sorted input pays for them once per span. */
typedef struct cubic_span {
  size_t s;
  double r[6];
} cubic_span;

BSFIT_INLINE void cubic_prepare(cubic_span *cs, const double *U, size_t s) {
  cs->s = s;
  cs->r[0] = 1.0 / (U[s + 1] - U[s]);
  cs->r[1] = 1.0 / (U[s + 1] - U[s - 1]);
  cs->r[2] = 1.0 / (U[s + 2] - U[s]);
  cs->r[3] = 1.0 / (U[s + 1] - U[s - 2]);
  cs->r[4] = 1.0 / (U[s + 2] - U[s - 1]);
  cs->r[5] = 1.0 / (U[s + 3] - U[s]);
}

/* A2.2 unrolled for p = 3; every denominator contains the non-empty span, so none is 0 */
BSFIT_INLINE void cubic_basis(const cubic_span *cs, const double *U, double u, double *N) {
  size_t s = cs->s;
  const double *r = cs->r;
  double L1 = u - U[s], R1 = U[s + 1] - u, L2 = u - U[s - 1], R2 = U[s + 2] - u;
  double L3 = u - U[s - 2], R3 = U[s + 3] - u;
  double a0 = R1 * r[0], a1 = L1 * r[0], t, sv, b0, b1, b2;
  t = a0 * r[1];
  b0 = R1 * t;
  sv = L2 * t;
  t = a1 * r[2];
  b1 = sv + R2 * t;
  b2 = L1 * t;
  t = b0 * r[3];
  N[0] = R1 * t;
  sv = L3 * t;
  t = b1 * r[4];
  N[1] = sv + R2 * t;
  sv = L2 * t;
  t = b2 * r[5];
  N[2] = sv + R3 * t;
  N[3] = L1 * t;
}

/* The span's polynomial in the local variable t = (u - U[s]) / (U[s+1] - U[s]) in [0, 1]:
** coefficients C^(j)(U[s]) h^j / j!, j = 0..3, from the exact derivatives. */
void bsfit__cubic_span_poly(const bsfit_curve *c, size_t s, double *coef) {
  double h = c->knots[s + 1] - c->knots[s], f = 1.0;
  size_t j, q, d = (size_t)c->dim;
  bsfit__curve_derivs_span(c, s, c->knots[s], 3, coef);
  for (j = 1; j <= 3; j++) {
    f *= h / (double)j;
    for (q = 0; q < d; q++) coef[j * d + q] *= f;
  }
}

/* Sorted input: a span that holds the next parameter too is converted once to its
** polynomial (Horner: 3 multiply-adds per coordinate); a span visited by one parameter
** (shuffled input) is evaluated by the basis, with its reciprocals cached. */
BSFIT_INLINE bsfit_err eval_cubic(const bsfit_curve *c, const double *u, size_t m, double *out,
                                  const size_t d, bsfit_status *st) {
  span_cursor k;
  cubic_span cs;
  size_t i, q;
  const double *U = c->knots, *ctrl = c->ctrl;
  const double a = U[3], b = U[c->n];
  const int periodic = c->periodic;
  double coef[4 * 3], u0 = 0.0, hinv = 0.0;
  int poly = 0;
  cursor_init(&k, c);
  cubic_prepare(&cs, U, k.s);
  for (i = 0; i < m; i++) {
    double x = u[i], N[4];
    const double *P;
    if (!(x >= a && x < b)) { /* rare: NaN, the end b, outside the domain */
      if (!isfinite(x))
        return bsfit__fail(st, BSFIT_ENONFINITE, "parameter u[%zu] is not finite", i);
      if (periodic) x = bsfit__curve_wrap(c, x);
    }
    if (cursor_find(&k, x) != cs.s) {
      size_t s = k.s;
      poly = i + 1 < m && u[i + 1] >= U[s] && u[i + 1] < U[s + 1];
      cubic_prepare(&cs, U, s);
      if (poly) {
        bsfit__cubic_span_poly(c, s, coef);
        u0 = U[s];
        hinv = cs.r[0];
      }
    }
    if (poly) {
      double t = (x - u0) * hinv;
      for (q = 0; q < d; q++)
        out[i * d + q] = ((coef[3 * d + q] * t + coef[2 * d + q]) * t + coef[d + q]) * t + coef[q];
      continue;
    }
    cubic_basis(&cs, U, x, N);
    P = ctrl + (cs.s - 3) * d;
    for (q = 0; q < d; q++)
      out[i * d + q] = N[0] * P[q] + N[1] * P[d + q] + N[2] * P[2 * d + q] + N[3] * P[3 * d + q];
  }
  return bsfit__ok(st);
}

static bsfit_err eval_general(const bsfit_curve *c, const double *u, size_t m, double *out,
                              bsfit_status *st) {
  span_cursor k;
  size_t i, j, q, d = (size_t)c->dim, p = (size_t)c->degree;
  double a = c->knots[p], b = c->knots[c->n];
  cursor_init(&k, c);
  for (i = 0; i < m; i++) {
    double x = u[i], N[BSFIT_MAX_DEGREE + 1], acc[4] = {0, 0, 0, 0}, wsum = 0.0;
    size_t s;
    if (!isfinite(x)) return bsfit__fail(st, BSFIT_ENONFINITE, "parameter u[%zu] is not finite", i);
    if (c->periodic && (x < a || x >= b)) x = bsfit__curve_wrap(c, x);
    s = cursor_find(&k, x);
    bsfit_basis_funs(s, x, c->degree, c->knots, N);
    for (j = 0; j <= p; j++) {
      const double *P = c->ctrl + (s - p + j) * d;
      double f = c->weights ? N[j] * c->weights[s - p + j] : N[j];
      for (q = 0; q < d; q++) acc[q] += f * P[q];
      wsum += f;
    }
    if (!c->weights) wsum = 1.0;
    for (q = 0; q < d; q++) out[i * d + q] = acc[q] / wsum;
  }
  return bsfit__ok(st);
}

bsfit_err bsfit_curve_eval_many(const bsfit_curve *c, const double *u, size_t m, double *out,
                                bsfit_status *st) {
  bsfit_err e = bsfit__curve_check(c, st);
  if (e != BSFIT_OK) return e;
  size_t i;
  if (m > 0 && (u == NULL || out == NULL))
    return bsfit__fail(st, BSFIT_EINVAL, "no parameter or output array");
  for (i = 0; !c->periodic && i < m; i++) /* NaN passes here: the evaluators name it */
    if (isfinite(u[i]) && !bsfit__curve_reach(c, u[i]))
      return bsfit__fail(st, BSFIT_EDOMAIN,
                         "parameter u[%zu] = %g is more than one domain length outside the "
                         "domain", i, u[i]);
  if (c->degree == 3 && c->weights == NULL && c->dim == 2) e = eval_cubic(c, u, m, out, 2, st);
  else if (c->degree == 3 && c->weights == NULL && c->dim == 3) e = eval_cubic(c, u, m, out, 3, st);
  else e = eval_general(c, u, m, out, st);
  if (e == BSFIT_OK && !bsfit__all_finite(out, m * (size_t)c->dim))
    return bsfit__fail(st, BSFIT_ERANGE, "an extrapolated point overflows");
  return e;
}

/* }==================================================================== */
