/*
** knot_placement.c
** Knot vectors placed on the data's parameters: averaging for open fits (NURBS Book
** 9.68-9.69 = P-10/P-11), the paper's closed rule (P-12/P-13 as read in docs/method.md §3-4), a
** consistent periodic averaging, uniform; and the Schoenberg-Whitney check (which knot
** spans hold no parameter).
*/
#include "fit_internal.h"

#include <math.h>

/* {======================================================================
** Empty spans
** ======================================================================= */

/* first index i with u[i] >= x (m if none) */
static size_t lower_bound(const double *u, size_t m, double x) {
  size_t lo = 0, hi = m;
  while (lo < hi) {
    size_t mid = lo + (hi - lo) / 2;
    if (u[mid] < x) lo = mid + 1;
    else hi = mid;
  }
  return lo;
}

static int holds(const double *u, size_t m, double lo, double hi, int closed_right) {
  size_t i = lower_bound(u, m, lo);
  return i < m && (u[i] < hi || (closed_right && u[i] <= hi));
}

/* A periodic span holds data when any shifted copy [lo + jP, hi + jP) does; the copies
** worth trying are those overlapping [u[0], u[m-1]]. */
static int holds_periodic(const double *u, size_t m, double lo, double hi, double P) {
  double j = floor((u[0] - hi) / P), jmax = ceil((u[m - 1] - lo) / P);
  for (; j <= jmax; j += 1.0)
    if (holds(u, m, lo + j * P, hi + j * P, 0)) return 1;
  return 0;
}

size_t bsfit__count_empty(const double *T, size_t K, const double *u, size_t m, int periodic,
                          size_t *first) {
  size_t k, count = 0;
  double P = T[K] - T[0];
  for (k = 0; k < K; k++) {
    int ok;
    if (!(T[k + 1] > T[k])) continue; /* zero-length spans hold nothing by construction */
    ok = periodic ? holds_periodic(u, m, T[k], T[k + 1], P)
                  : holds(u, m, T[k], T[k + 1], k + 1 == K);
    if (!ok && count++ == 0 && first) *first = k;
  }
  return count;
}

static bsfit_err check_sorted(const double *u, size_t m, bsfit_status *st) {
  size_t k;
  int ok = m == 0 || (isfinite(u[0]) && isfinite(u[m - 1]));
  /* one branch-free sweep (a NaN fails its comparisons; sorted with finite ends means all
  ** finite); the precise scan below only runs when something is wrong */
  for (k = 1; k < m; k++) ok &= u[k] >= u[k - 1];
  if (ok) return BSFIT_OK;
  for (k = 0; k < m; k++)
    if (!isfinite(u[k])) return bsfit__fail(st, BSFIT_ENONFINITE, "parameter %zu is not finite", k);
  for (k = 1; k < m; k++)
    if (u[k] < u[k - 1]) break;
  return bsfit__fail(st, BSFIT_EINVAL, "parameters decrease at index %zu (%g < %g)", k, u[k],
                     u[k - 1]);
}

bsfit_err bsfit_knots_empty_spans(const double *U, size_t nknots, int p, int periodic,
                                  const double *u, size_t m, size_t *spans, size_t cap,
                                  size_t *count, bsfit_status *st) {
  size_t n, s, found = 0;
  bsfit_err e;
  if (U == NULL || (u == NULL && m > 0) || count == NULL || (cap > 0 && spans == NULL))
    return bsfit__fail(st, BSFIT_EINVAL, "knots, parameters, spans or count is NULL");
  if (p < 0 || nknots < 2 * (size_t)p + 2)
    return bsfit__fail(st, BSFIT_ENKNOTS, "%zu knots are too few for degree %d", nknots, p);
  n = nknots - (size_t)p - 1;
  e = bsfit_knots_validate(U, nknots, p, n, st);
  if (e == BSFIT_OK) e = check_sorted(u, m, st);
  if (e != BSFIT_OK) return e;
  for (s = (size_t)p; s < n; s++) {
    /* one span at a time, so the list comes out increasing without scratch memory */
    int filled;
    if (!(U[s + 1] > U[s])) continue;
    if (m == 0) filled = 0;
    else if (periodic) filled = holds_periodic(u, m, U[s], U[s + 1], U[n] - U[(size_t)p]);
    else filled = holds(u, m, U[s], U[s + 1], s + 1 == n);
    if (filled) continue;
    if (found < cap) spans[found] = s;
    found++;
  }
  *count = found;
  return bsfit__ok(st);
}

/* }====================================================================== */

/* {======================================================================
** Rules
** ======================================================================= */

int bsfit_knot_rule_closed(bsfit_knot_rule rule) {
  return rule == BSFIT_KNOTS_CARVALHO_CLOSED || rule == BSFIT_KNOTS_PERIODIC_AVERAGING ||
         rule == BSFIT_KNOTS_PERIODIC_UNIFORM;
}

static int rule_known(bsfit_knot_rule rule) {
  return rule == BSFIT_KNOTS_AVERAGING || rule == BSFIT_KNOTS_UNIFORM ||
         bsfit_knot_rule_closed(rule);
}

size_t bsfit_knots_place_count(bsfit_knot_rule rule, int p, size_t n) {
  if (!rule_known(rule) || p < 0) return 0;
  return bsfit_knot_rule_closed(rule) ? n + 1 : n + (size_t)p + 1;
}

/* x + a (y - x): exactly x when y == x (repeated parameters: (1 - a) x + a x can be
** an ulp off x, and knots placed between repeats then decrease) */
static double lerp(double x, double y, double a) { return x + a * (y - x); }

/* NURBS Book eq. 9.68-9.69: interior knot j sits at fractional index j d - 1 */
static void place_averaging(const double *u, size_t m, int p, size_t n, double *U) {
  size_t j, P = (size_t)p;
  double d = (double)m / (double)(n - P);
  for (j = 0; j <= P; j++) {
    U[j] = u[0];
    U[n + j] = u[m - 1];
  }
  for (j = 1; j + P < n; j++) {
    double t = (double)j * d;
    size_t i = (size_t)t;
    double a = t - (double)i;
    U[P + j] = lerp(u[i - 1], u[i], a);
  }
}

static void place_uniform(const double *u, size_t m, int p, size_t n, double *U) {
  (void)bsfit_knots_clamped(p, n, u[0], u[m - 1], U, NULL);
}

/* docs/method.md §3-4, literal: t_k at fractional index k d - 1 for k = 1..N-1, ends at 0 and m */
static void place_carvalho(const double *u, size_t m, size_t N, double *T) {
  size_t k;
  double d = (double)m / (double)N;
  T[0] = u[0];
  for (k = 1; k < N; k++) {
    double t = (double)k * d;
    size_t i = (size_t)t;
    double a = t - (double)i;
    T[k] = lerp(u[i - 1], u[i], a);
  }
  T[N] = u[0] + 1.0;
}

/* ū continued around the circle: ū_{i+m} = ū_i + 1 (i >= 0) */
static double ucyc(const double *u, size_t m, size_t i) {
  return u[i % m] + (double)(i / m);
}

static void place_periodic_averaging(const double *u, size_t m, int p, size_t N, double *T) {
  size_t k;
  double d = (double)m / (double)N, c = (p % 2 == 1) ? 0.0 : 0.5 * d;
  for (k = 0; k < N; k++) {
    double t = (double)k * d + c;
    size_t i = (size_t)t;
    double a = t - (double)i;
    T[k] = a == 0.0 ? ucyc(u, m, i) : lerp(ucyc(u, m, i), ucyc(u, m, i + 1), a);
  }
  T[N] = T[0] + 1.0;
}

static void place_periodic_uniform(const double *u, size_t N, double *T) {
  size_t k;
  for (k = 0; k <= N; k++) T[k] = u[0] + (double)k / (double)N;
}

static bsfit_err check_place_args(bsfit_knot_rule rule, const double *u, size_t m, int p,
                                  size_t n, const double *U, bsfit_status *st) {
  bsfit_err e;
  int closed = bsfit_knot_rule_closed(rule);
  if (u == NULL || U == NULL) return bsfit__fail(st, BSFIT_EINVAL, "parameters or knots are NULL");
  if (!rule_known(rule)) return bsfit__fail(st, BSFIT_EINVAL, "unknown knot rule %d", (int)rule);
  if (p < 1 || p > BSFIT_MAX_DEGREE)
    return bsfit__fail(st, BSFIT_EDEGREE, "degree %d out of range 1..%d", p, BSFIT_MAX_DEGREE);
  if (n < (size_t)p + 1 || (closed && n < 2))
    return bsfit__fail(st, BSFIT_EDEGREE, "degree %d needs more than %zu control points", p, n);
  if (m < n)
    return bsfit__fail(st, BSFIT_ETOOFEW, "%zu parameters are fewer than %zu control points", m, n);
  e = check_sorted(u, m, st);
  if (e != BSFIT_OK) return e;
  if (!closed && !(u[0] < u[m - 1]))
    return bsfit__fail(st, BSFIT_EDEGENERATE, "all parameters equal %g", u[0]);
  if (closed && !(u[m - 1] < u[0] + 1.0))
    return bsfit__fail(st, BSFIT_EINVAL,
                       "closed parameters must lie in one period [u0, u0+1), got [%g, %g]", u[0],
                       u[m - 1]);
  return BSFIT_OK;
}

/* a closed period may hold repeated knots, but none above multiplicity p+1 */
static bsfit_err check_period_mult(const double *T, size_t N, int p, bsfit_status *st) {
  size_t k, run = 1;
  for (k = 1; k <= N; k++) {
    run = T[k] == T[k - 1] ? run + 1 : 1;
    if (run > (size_t)p + 1)
      return bsfit__fail(st, BSFIT_EMULT, "periodic knot %g has multiplicity above %d", T[k],
                         p + 1);
  }
  return BSFIT_OK;
}

bsfit_err bsfit__knots_place_rule(bsfit_knot_rule rule, const double *u, size_t m, int p,
                                  size_t n, double *U, bsfit_status *st) {
  size_t k;
  bsfit_err e = check_place_args(rule, u, m, p, n, U, st);
  if (e != BSFIT_OK) return e;
  switch (rule) {
    case BSFIT_KNOTS_AVERAGING: place_averaging(u, m, p, n, U); break;
    case BSFIT_KNOTS_UNIFORM: place_uniform(u, m, p, n, U); break;
    case BSFIT_KNOTS_CARVALHO_CLOSED: place_carvalho(u, m, n, U); break;
    case BSFIT_KNOTS_PERIODIC_AVERAGING: place_periodic_averaging(u, m, p, n, U); break;
    default: place_periodic_uniform(u, n, U); break;
  }
  for (k = 1; k < bsfit_knots_place_count(rule, p, n); k++) /* rounding never decreases */
    if (U[k] < U[k - 1]) U[k] = U[k - 1];
  if (bsfit_knot_rule_closed(rule)) return check_period_mult(U, n, p, st);
  return bsfit_knots_validate(U, n + (size_t)p + 1, p, n, st);
}

bsfit_err bsfit_knots_place(bsfit_knot_rule rule, const double *u, size_t m, int p, size_t n,
                            double *U, bsfit_status *st) {
  size_t first = 0, empty;
  bsfit_err e = bsfit__knots_place_rule(rule, u, m, p, n, U, st);
  if (e != BSFIT_OK) return e;
  if (bsfit_knot_rule_closed(rule)) {
    empty = bsfit__count_empty(U, n, u, m, 1, &first);
    if (empty > 0)
      return bsfit__fail(st, BSFIT_EEMPTYSPAN,
                         "periodic knot span %zu [%g, %g) holds no parameter (%zu empty)", first,
                         U[first], U[first + 1], empty);
    return bsfit__ok(st);
  }
  empty = bsfit__count_empty(U + p, n - (size_t)p, u, m, 0, &first);
  if (empty > 0)
    return bsfit__fail(st, BSFIT_EEMPTYSPAN, "knot span %zu [%g, %g) holds no parameter (%zu empty)",
                       first + (size_t)p, U[first + (size_t)p], U[first + (size_t)p + 1], empty);
  return bsfit__ok(st);
}

/* }====================================================================== */
