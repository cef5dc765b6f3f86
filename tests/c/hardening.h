/*
** hardening.h
** What the hardening tests share: an evaluator of curves written here from the
** definition (de Boor's algorithm on homogeneous points, independent of the library's
** basis code), Gauss-Legendre nodes computed by Newton's method, random curves with
** clustered knots, and the post-condition every operation must meet (OK => valid and
** finite).
*/
#ifndef BSFIT_TEST_HARDENING_H
#define BSFIT_TEST_HARDENING_H

#include <math.h>
#include <string.h>

#include "bsfit.h"
#include "testutil.h"

#define REF_MAXP 8 /* degrees the reference evaluator handles */

/* C(u) of the stored arrays by de Boor's algorithm; periodic curves: u wrapped into
** the period first. Span: the last s with U[s] <= u < U[s+1] inside [U[p], U[n]]. */
static inline void ref_eval(const bsfit_curve *c, double u, double *out) {
  size_t p = (size_t)c->degree, n = c->n, d = (size_t)c->dim, s, j, r, k;
  double a = c->knots[p], b = c->knots[n], q[REF_MAXP + 1][5];
  const double *U = c->knots;
  if (c->periodic) {
    u = a + fmod(u - a, b - a);
    if (u < a) u += b - a;
  }
  if (u < a) u = a;
  if (u > b) u = b;
  for (s = n - 1; s > p && !(U[s] <= u && U[s] < U[s + 1]); s--) {
  }
  for (j = 0; j <= p; j++) {
    double w = c->weights ? c->weights[s - p + j] : 1.0;
    for (k = 0; k < d; k++) q[j][k] = w * c->ctrl[(s - p + j) * d + k];
    q[j][d] = w;
  }
  for (r = 1; r <= p; r++)
    for (j = p; j >= r; j--) {
      size_t i = s - p + j;
      double al = (u - U[i]) / (U[i + p + 1 - r] - U[i]);
      for (k = 0; k <= d; k++) q[j][k] = (1.0 - al) * q[j - 1][k] + al * q[j][k];
    }
  for (k = 0; k < d; k++) out[k] = q[p][k] / q[p][d];
}

/* n-point Gauss-Legendre nodes and weights on [-1, 1] (n <= 32), Newton on P_n */
static inline void gl_nodes(int n, double *x, double *w) {
  int i, j, it;
  for (i = 0; i < n; i++) {
    double z = cos(3.14159265358979323846 * (i + 0.75) / (n + 0.5)), p1, p2, p3, dp = 1.0;
    for (it = 0; it < 100; it++) {
      double z1 = z;
      p1 = 1.0;
      p2 = 0.0;
      for (j = 0; j < n; j++) {
        p3 = p2;
        p2 = p1;
        p1 = ((2.0 * j + 1.0) * z * p2 - j * p3) / (j + 1.0);
      }
      dp = n * (z * p1 - p2) / (z * z - 1.0);
      z = z1 - p1 / dp;
      if (fabs(z - z1) < 1e-16) break;
    }
    x[i] = z;
    w[i] = 2.0 / ((1.0 - z * z) * dp * dp);
  }
}

/* Knots with clusters: spans drawn from [0.1, 1], some replaced by 10^-e with e drawn
** from [6, 15] (clusters at 1e-15..1e-6), interior multiplicity <= maxmult. Clamped
** ends (p+1 copies) when `clamped`. */
static inline void clustered_knots(test_rng *r, int p, size_t n, int clamped, int maxmult,
                                   double *U) {
  size_t nk = n + (size_t)p + 1, i, run = 1;
  for (i = 0; i < nk; i++) {
    double x = rng_uniform(r), step;
    if (x < 0.25)
      step = pow(10.0, -rng_range(r, 6.0, 15.0));
    else
      step = rng_range(r, 0.1, 1.0);
    if (i == 0)
      U[0] = rng_range(r, -1.0, 1.0);
    else if (clamped && (i <= (size_t)p || i >= n + 1))
      U[i] = U[i - 1];
    else if (run < (size_t)maxmult && i != n && i != (size_t)p + 1 && rng_uniform(r) < 0.1)
      U[i] = U[i - 1];
    else
      U[i] = U[i - 1] + step;
    run = (i > 0 && U[i] == U[i - 1]) ? run + 1 : 1;
  }
}

/* OK => the curve passes the library's validation and every number in it is finite */
static inline int curve_sound(const bsfit_curve *c) {
  size_t i;
  if (bsfit_curve_validate(c, NULL) != BSFIT_OK) return 0;
  for (i = 0; i < c->n * (size_t)c->dim; i++)
    if (!isfinite(c->ctrl[i])) return 0;
  for (i = 0; c->weights && i < c->n; i++)
    if (!(c->weights[i] > 0) || !isfinite(c->weights[i])) return 0;
  return 1;
}

/* every one of the n doubles is finite */
static inline int all_finite(const double *x, size_t n) {
  size_t i;
  for (i = 0; i < n; i++)
    if (!isfinite(x[i])) return 0;
  return 1;
}

/* max |a - b| over the coordinates of two points of dimension d */
static inline double pt_dist(const double *a, const double *b, int d) {
  double m = 0.0;
  int k;
  for (k = 0; k < d; k++) m = fmax(m, fabs(a[k] - b[k]));
  return m;
}

/* max |coordinate| of the control points (the scale errors are measured against) */
static inline double ctrl_scale(const bsfit_curve *c) {
  double m = 0.0;
  size_t i;
  for (i = 0; i < c->n * (size_t)c->dim; i++) m = fmax(m, fabs(c->ctrl[i]));
  return m > 0 ? m : 1.0;
}

#endif
