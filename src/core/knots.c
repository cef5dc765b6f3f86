/*
** knots.c
** Knot vectors: validation, span search, multiplicity, and the standard kinds
** (uniform, open-uniform/clamped, expanded periodic).
*/
#include "internal.h"

#include <math.h>

static bsfit_err check_degree(int p, size_t n, bsfit_status *st) {
  if (p < 0 || p > BSFIT_MAX_DEGREE)
    return bsfit__fail(st, BSFIT_EDEGREE, "degree %d out of range 0..%d", p, BSFIT_MAX_DEGREE);
  if (n < (size_t)p + 1)
    return bsfit__fail(st, BSFIT_EDEGREE, "degree %d needs at least %d control points, got %zu",
                       p, p + 1, n);
  return BSFIT_OK;
}

bsfit_err bsfit_knots_validate(const double *U, size_t nknots, int p, size_t n,
                               bsfit_status *st) {
  size_t i, run = 1;
  bsfit_err e = check_degree(p, n, st);
  if (e != BSFIT_OK) return e;
  if (U == NULL || nknots != n + (size_t)p + 1)
    return bsfit__fail(st, BSFIT_ENKNOTS,
                       "degree %d with %zu control points needs %zu knots, got %zu", p, n,
                       n + (size_t)p + 1, U == NULL ? (size_t)0 : nknots);
  for (i = 0; i < nknots; i++)
    if (!isfinite(U[i])) return bsfit__fail(st, BSFIT_ENONFINITE, "knot %zu is not finite", i);
  for (i = 1; i < nknots; i++) {
    if (U[i] < U[i - 1])
      return bsfit__fail(st, BSFIT_EKNOTS_DECR, "knots decrease at index %zu (%g < %g)", i, U[i],
                         U[i - 1]);
    run = (U[i] == U[i - 1]) ? run + 1 : 1;
    if (run > (size_t)p + 1)
      return bsfit__fail(st, BSFIT_EMULT, "knot %g has multiplicity above degree+1 = %d", U[i],
                         p + 1);
  }
  if (!(U[p] < U[n]))
    return bsfit__fail(st, BSFIT_EDOMAIN, "empty domain [U[%d], U[%zu]] = [%g, %g]", p, n, U[p],
                       U[n]);
  return bsfit__ok(st);
}

size_t bsfit_knots_find_span(const double *U, size_t n, int p, double u) {
  size_t lo = (size_t)p, hi = n;
  if (u >= U[n]) {
    /* last non-empty span, so that the domain's end evaluates from the left */
    size_t s = n - 1;
    while (s > (size_t)p && U[s] == U[n]) s--;
    return s;
  }
  if (u <= U[p]) {
    size_t s = (size_t)p;
    while (s + 1 < n && U[s + 1] == U[p]) s++;
    return s;
  }
  /* invariant: U[lo] <= u < U[hi] */
  while (hi - lo > 1) {
    size_t mid = lo + (hi - lo) / 2;
    if (u < U[mid]) hi = mid;
    else lo = mid;
  }
  return lo;
}

int bsfit_knots_multiplicity(const double *U, size_t nknots, double u) {
  size_t lo = 0, hi = nknots;
  int m = 0;
  while (lo < hi) { /* the first knot >= u (none for a NaN u: then m stays 0) */
    size_t mid = lo + (hi - lo) / 2;
    if (U[mid] < u) lo = mid + 1;
    else hi = mid;
  }
  for (; lo < nknots && U[lo] == u; lo++) m++;
  return m;
}

void bsfit_knots_domain(const double *U, size_t n, int p, double *a, double *b) {
  if (a) *a = U[p];
  if (b) *b = U[n];
}

static bsfit_err check_interval(double a, double b, bsfit_status *st) {
  if (!isfinite(a) || !isfinite(b) || !(a < b))
    return bsfit__fail(st, BSFIT_EDOMAIN, "domain [%g, %g] must be finite with a < b", a, b);
  return BSFIT_OK;
}

bsfit_err bsfit_knots_uniform(int p, size_t n, double a, double b, double *U, bsfit_status *st) {
  size_t i, nk = n + (size_t)p + 1;
  double h;
  bsfit_err e = check_degree(p, n, st);
  if (e == BSFIT_OK) e = check_interval(a, b, st);
  if (e != BSFIT_OK) return e;
  h = (b - a) / (double)(n - (size_t)p);
  for (i = 0; i < nk; i++) U[i] = a + ((double)i - p) * h;
  U[p] = a;
  U[n] = b; /* exact ends despite rounding */
  return bsfit__ok(st);
}

bsfit_err bsfit_knots_clamped(int p, size_t n, double a, double b, double *U, bsfit_status *st) {
  size_t i, nk = n + (size_t)p + 1, spans;
  bsfit_err e = check_degree(p, n, st);
  if (e == BSFIT_OK) e = check_interval(a, b, st);
  if (e != BSFIT_OK) return e;
  spans = n - (size_t)p;
  for (i = 0; i < nk; i++) {
    if (i <= (size_t)p) U[i] = a;
    else if (i >= n) U[i] = b;
    else U[i] = a + (b - a) * (double)(i - (size_t)p) / (double)spans;
  }
  return bsfit__ok(st);
}

bsfit_err bsfit_knots_periodic(int p, size_t N, const double *period, double *U,
                               bsfit_status *st) {
  size_t i;
  double T;
  if (p < 1 || p > BSFIT_MAX_DEGREE)
    return bsfit__fail(st, BSFIT_EDEGREE, "periodic degree %d out of range 1..%d", p,
                       BSFIT_MAX_DEGREE);
  if (N < 2 || N < (size_t)p + 1)
    return bsfit__fail(st, BSFIT_EDEGREE,
                       "periodic curve of degree %d needs at least %d distinct control points, got %zu",
                       p, p + 1 > 2 ? p + 1 : 2, N);
  if (!bsfit__all_finite(period, N + 1))
    return bsfit__fail(st, BSFIT_ENONFINITE, "periodic knots are not all finite");
  for (i = 1; i <= N; i++)
    if (period[i] < period[i - 1])
      return bsfit__fail(st, BSFIT_EKNOTS_DECR, "periodic knots decrease at index %zu", i);
  T = period[N] - period[0];
  if (!(T > 0)) return bsfit__fail(st, BSFIT_EDOMAIN, "periodic knots span an empty period");
  for (i = 0; i <= N; i++) U[(size_t)p + i] = period[i];
  for (i = 0; i < (size_t)p; i++) {
    /* spans before the period repeat its last spans; spans after repeat its first.
    ** Measured from the period's ends (not t[i] +- T) so rounding cannot put a
    ** shifted knot on the wrong side of an end knot. */
    U[(size_t)p - 1 - i] = period[0] - (period[N] - period[N - 1 - i]);
    U[(size_t)p + N + 1 + i] = period[N] + (period[1 + i] - period[0]);
  }
  return bsfit__ok(st);
}
