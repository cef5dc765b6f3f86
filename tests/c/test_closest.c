/*
** test_closest.c
** bsfit_curve_closest_many against references that decide the same thing by brute force:
** its nearest-sample index (nearest_sample.c) against a linear scan with the first-index
** tie rule, on sample sets full of exact ties; and its results, bit for bit, against
** bsfit_curve_closest (whose own linear scan over the same samples defines the answer),
** on random open and periodic curves of degrees 1..5 with a C0 corner, for points near,
** far, on samples, repeated, equidistant from two samples and large enough to overflow.
*/
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

#include "bsfit.h"
#include "cmocka_double.h"
#include "core/curve_ops_internal.h"
#include "testutil.h"

#define SAMPLES_PER_SPAN 8 /* bsfit_curve_closest's coarse samples (curve_geom.c) */
#define MAXN 96            /* control points at most */
#define MAXM 1200          /* points per curve at most */
#define MAXK 2048          /* samples per direct index test at most */
#define MAXQ 1000          /* queries per direct index test at most */
#define HUGE_SAFE 1e154    /* (1e154)^2 is finite, so all distances tie after rounding */
#define HUGE_OVER 1.5e154  /* (1.5e154)^2 overflows: every distance is +inf */

/* {====================================================================
** References
** ===================================================================== */

/* The nearest of K samples by the linear scan that defines the answer: the same sum in
** the same order, the first index of the smallest. */
static size_t scan_nearest(const double *smp, size_t K, size_t d, const double *P) {
  double best = INFINITY;
  size_t k, q, kb = 0;
  for (k = 0; k < K; k++) {
    double dd = 0.0;
    for (q = 0; q < d; q++) dd += (smp[k * d + q] - P[q]) * (smp[k * d + q] - P[q]);
    if (dd < best) {
      best = dd;
      kb = k;
    }
  }
  return kb;
}

/* Bitwise equality of doubles (a NaN equals the same NaN; -0 differs from +0). */
static void assert_same_bits(const double *x, const double *y, size_t n, const char *what,
                             size_t curve) {
  size_t i;
  for (i = 0; i < n; i++)
    if (memcmp(x + i, y + i, sizeof(double)) != 0) {
      print_error("curve %zu, %s %zu: %.17g != %.17g\n", curve, what, i, x[i], y[i]);
      fail();
    }
}

/* }==================================================================== */

/* {====================================================================
** The nearest-sample index against the scan
** ===================================================================== */

/* Queries for a sample set: every sample itself, midpoints of pairs (exactly equidistant
** when the coordinates are small dyadic numbers), random points inside and far outside,
** and huge points whose distances all round to one value or all overflow. */
static size_t make_queries(test_rng *r, const double *smp, size_t K, size_t d, double *Q,
                           size_t maxq) {
  size_t n = 0, i, q, every = K / 200 + 1; /* about 200 samples and 200 midpoints */
  for (i = 0; i < K && n < maxq; i += every, n++)
    memcpy(Q + n * d, smp + i * d, d * sizeof(double));
  for (i = 0; i < K && n < maxq; i += every, n++) {
    size_t j = (size_t)(rng_uniform(r) * (double)K);
    for (q = 0; q < d; q++) Q[n * d + q] = 0.5 * (smp[i * d + q] + smp[j * d + q]);
  }
  for (i = 0; i < 200 && n < maxq; i++, n++)
    for (q = 0; q < d; q++) Q[n * d + q] = rng_range(r, -12.0, 12.0);
  for (i = 0; i < 50 && n < maxq; i++, n++)
    for (q = 0; q < d; q++) Q[n * d + q] = rng_range(r, -1e6, 1e6);
  for (i = 0; i < 4 && n < maxq; i++, n++)
    for (q = 0; q < d; q++)
      Q[n * d + q] = (q == 0 ? (i & 1 ? HUGE_OVER : HUGE_SAFE) : 0.0) * (i & 2 ? -1.0 : 1.0);
  return n;
}

static void check_index(test_rng *r, const double *smp, size_t K, size_t d, size_t queries) {
  static double Q[MAXQ * 4];
  bsfit__nearest nn;
  bsfit_status st;
  size_t nq = make_queries(r, smp, K, d, Q, MAXQ), i;
  assert_int_equal(bsfit__nearest_init(&nn, smp, K, d, queries, NULL, &st), BSFIT_OK);
  if (K >= 1000 && queries >= 1000) assert_true(nn.depth > 0); /* not only scans tested */
  for (i = 0; i < nq; i++) {
    size_t got = bsfit__nearest_find(&nn, Q + i * d), want = scan_nearest(smp, K, d, Q + i * d);
    if (got != want) {
      print_error("K = %zu, d = %zu, depth %d, query %zu: sample %zu, the scan says %zu\n", K, d,
                  nn.depth, i, got, want);
      fail();
    }
  }
  bsfit__nearest_free(&nn);
  bsfit__nearest_free(&nn); /* idempotent */
}

static void test_index_matches_scan_on_ties(void **state) {
  /* given sample sets of every dimension and size where exact ties abound (small integer
  ** coordinates with repeats, one point repeated, collinear points) and random ones,
  ** when the nearest sample of each query is looked up through the index, then it is the
  ** scan's: the same index, the first among equals, with a tree and without */
  static double smp[MAXK * 4];
  static const size_t sizes[] = {1, 2, 3, 17, 47, 48, 49, 100, 333, 2000};
  test_rng r = {4242};
  size_t d, si, k, q;
  int kind;
  (void)state;
  for (d = 1; d <= 4; d++)
    for (si = 0; si < sizeof sizes / sizeof sizes[0]; si++)
      for (kind = 0; kind < 4; kind++) {
        size_t K = sizes[si];
        for (k = 0; k < K; k++)
          for (q = 0; q < d; q++) {
            double x;
            if (kind == 0) x = (double)(int)rng_range(&r, -4.0, 5.0); /* a lattice, repeats */
            else if (kind == 1) x = 0.25;                            /* one point K times */
            else if (kind == 2) x = q == 0 ? (double)(k % 37) / 8.0 : 1.0; /* a line */
            else x = rng_range(&r, -3.0, 3.0);
            smp[k * d + q] = x;
          }
        check_index(&r, smp, K, d, 1000); /* a tree, when K is large enough */
        if (K < 400) check_index(&r, smp, K, d, 1); /* the scan */
      }
}

static void test_index_matches_scan_on_large_curve_like_sets(void **state) {
  /* given large sample sets laid out as a curve's are (a closed loop sampled in order,
  ** smooth or zigzagging across a band as a fit through noise does, with each run's end
  ** repeated as the next one's start; and the same coordinates rounded to a coarse
  ** lattice, full of ties), of sizes where the build samples its pivots and partitions by
  ** blocks, when the nearest sample of each query is looked up, then it is the scan's */
  static double smp[120000 * 3];
  static const size_t sizes[] = {5000, 40000, 120000};
  test_rng r = {777};
  size_t si, k, d;
  int kind;
  (void)state;
  for (d = 2; d <= 3; d++)
    for (si = 0; si < sizeof sizes / sizeof sizes[0]; si++)
      for (kind = 0; kind < 3; kind++) {
        size_t K = sizes[si];
        for (k = 0; k < K; k++) {
          size_t run = k / 9, i = k % 9, q;
          double t = 6.283185307179586 * ((double)run + (double)i / 8.0) / (double)(K / 9 + 1);
          double zig = kind >= 1 ? 0.01 * (double)(i & 1 ? 1 : -1) * (double)(i % 4) : 0.0;
          double x[3];
          x[0] = (1.0 + zig) * cos(t) * (1.0 + 0.2 * cos(5.0 * t));
          x[1] = (1.0 + zig) * sin(t) * (1.0 + 0.2 * cos(5.0 * t));
          x[2] = 0.1 * sin(3.0 * t);
          for (q = 0; q < d; q++)
            smp[k * d + q] = kind == 2 ? floor(x[q] * 64.0) / 64.0 : x[q];
        }
        check_index(&r, smp, K, d, K);
      }
}

/* }==================================================================== */

/* {====================================================================
** closest_many against closest
** ===================================================================== */

/* A random curve with a C0 corner: open (clamped) or periodic, degree p, dim 2 or 3, n
** control points (periodic: n distinct), uneven spans, one interior knot of multiplicity
** p, rational when asked. `dyadic` makes degree-1 curves whose samples are exact: integer
** knots and control points, so that points on samples and midpoints between them are
** exactly on and exactly equidistant. */
static void random_curve(test_rng *r, bsfit_curve *c, int p, int dim, size_t n, int periodic,
                         int rational, int dyadic) {
  double U[MAXN + 8], t[MAXN + 1], P[MAXN * 3], W[MAXN];
  size_t i, nk = n + (size_t)p + 1, corner;
  bsfit_status st;
  for (i = 0; i < n * (size_t)dim; i++)
    P[i] = dyadic ? (double)(int)rng_range(r, -6.0, 7.0) : rng_range(r, -1.0, 1.0);
  for (i = 0; i < n; i++) W[i] = rng_range(r, 0.4, 2.5);
  bsfit_curve_init(c);
  if (periodic) {
    corner = 1 + (size_t)(rng_uniform(r) * (double)(n - (size_t)p - 1));
    t[0] = dyadic ? 0.0 : rng_range(r, -1.0, 1.0);
    for (i = 1; i <= n; i++) {
      int in_corner = i > corner && i < corner + (size_t)p; /* p equal knots from t[corner] */
      t[i] = in_corner ? t[i - 1]
                       : t[i - 1] + (dyadic ? (double)(1 + (i % 3)) : rng_range(r, 0.2, 1.0));
    }
    assert_int_equal(bsfit_curve_new_periodic(c, p, dim, n, t, P, rational ? W : NULL, NULL, &st),
                     BSFIT_OK);
    return;
  }
  corner = (size_t)p + 1 + (size_t)(rng_uniform(r) * (double)(n - 2 * (size_t)p - 1));
  for (i = 0; i < nk; i++) {
    if (i <= (size_t)p) U[i] = 0.0;
    else if (i >= n + 1) U[i] = U[n];
    else if (i > corner && i < corner + (size_t)p) U[i] = U[i - 1];
    else U[i] = U[i - 1] + (dyadic ? (double)(1 + (i % 3)) : rng_range(r, 0.2, 1.0));
  }
  assert_int_equal(bsfit_curve_new(c, p, dim, n, U, P, rational ? W : NULL, 0, NULL, &st),
                   BSFIT_OK);
}

/* Points for a curve: on the samples (evaluated at the sample parameters), midway between
** consecutive samples, near the curve, far from it, repeats of earlier points, then
** HUGE_SAFE and, last, HUGE_OVER. Returns how many. */
static size_t curve_points(test_rng *r, const bsfit_curve *c, double *pts, size_t maxm) {
  size_t d = (size_t)c->dim, m = 0, s, i, q;
  double a, b, x[4], y[4];
  bsfit_curve_domain(c, &a, &b);
  for (s = (size_t)c->degree; s < c->n && m + 2 < maxm; s++) {
    double h = (c->knots[s + 1] - c->knots[s]) / SAMPLES_PER_SPAN;
    for (i = 0; h > 0 && i < SAMPLES_PER_SPAN && m + 2 < maxm; i++) {
      if (rng_uniform(r) < 0.9) continue; /* a tenth of them: the reference is slow */
      assert_int_equal(bsfit_curve_eval(c, c->knots[s] + h * (double)i, x, NULL), BSFIT_OK);
      assert_int_equal(bsfit_curve_eval(c, c->knots[s] + h * (double)(i + 1), y, NULL), BSFIT_OK);
      memcpy(pts + m++ * d, x, d * sizeof(double));
      for (q = 0; q < d; q++) pts[m * d + q] = 0.5 * (x[q] + y[q]);
      m++;
    }
  }
  for (i = 0; i < 80 && m < maxm; i++, m++) { /* near */
    assert_int_equal(bsfit_curve_eval(c, rng_range(r, a, b), x, NULL), BSFIT_OK);
    for (q = 0; q < d; q++) pts[m * d + q] = x[q] + rng_range(r, -0.05, 0.05);
  }
  for (i = 0; i < 30 && m < maxm; i++, m++) /* far */
    for (q = 0; q < d; q++) pts[m * d + q] = rng_range(r, -30.0, 30.0);
  for (i = 0; i < 30 && m < maxm; i++, m++) { /* repeats */
    size_t j = (size_t)(rng_uniform(r) * (double)m);
    memcpy(pts + m * d, pts + j * d, d * sizeof(double));
  }
  if (m + 2 > maxm) m = maxm - 2;
  for (i = 0; i < 2; i++, m++) /* HUGE_OVER last: see check_curve */
    for (q = 0; q < d; q++) pts[m * d + q] = q == 0 ? (i ? HUGE_OVER : HUGE_SAFE) : 0.0;
  return m;
}

/* closest_many on all the points (the index) and in small batches (the scan), against
** bsfit_curve_closest point by point: the same u and distance, bit for bit. The last
** point is HUGE_OVER, whose distance to every sample overflows: both start from the
** first sample (bsfit_curve_closest keeps it when no sample beats +inf). */
static void check_curve(const bsfit_curve *c, const double *pts, size_t m, size_t curve) {
  static double u[MAXM], dist[MAXM], ub[MAXM], db[MAXM], u1[MAXM], d1[MAXM], un[MAXM];
  size_t d = (size_t)c->dim, i, j;
  bsfit_status st;
  assert_int_equal(bsfit_curve_closest_many(c, pts, m, u, dist, NULL, &st), BSFIT_OK);
  for (i = 0; i < m; i += 7) { /* batches of 7: too few for a tree */
    size_t nb = m - i < 7 ? m - i : 7;
    assert_int_equal(bsfit_curve_closest_many(c, pts + i * d, nb, ub + i, db + i, NULL, NULL), BSFIT_OK);
  }
  for (j = 0; j < m; j++)
    assert_int_equal(bsfit_curve_closest(c, pts + j * d, u1 + j, d1 + j, NULL, NULL), BSFIT_OK);
  /* no distances asked for: the same parameters */
  assert_int_equal(bsfit_curve_closest_many(c, pts, m, un, NULL, NULL, NULL), BSFIT_OK);
  assert_same_bits(u, u1, m, "u", curve);
  assert_same_bits(dist, d1, m, "dist", curve);
  assert_same_bits(ub, u1, m, "u (batches)", curve);
  assert_same_bits(db, d1, m, "dist (batches)", curve);
  assert_same_bits(un, u1, m, "u (no dist)", curve);
}

static void test_many_equals_closest_bitwise(void **state) {
  /* given random open and periodic curves of degrees 1..5 in 2D and 3D, polynomial and
  ** rational, with many uneven spans and a C0 corner, and points of every kind around
  ** them, when their closest points are found all at once, then every parameter and
  ** distance is bsfit_curve_closest's, bit for bit */
  static double pts[MAXM * 3];
  test_rng r = {31337};
  size_t curve = 0;
  int p, dim, periodic, rational;
  (void)state;
  for (p = 1; p <= 5; p++)
    for (dim = 2; dim <= 3; dim++)
      for (periodic = 0; periodic <= 1; periodic++)
        for (rational = 0; rational <= 1; rational++, curve++) {
          bsfit_curve c;
          size_t n = 12 + (size_t)(rng_uniform(&r) * 30.0), m; /* 108..378 samples */
          random_curve(&r, &c, p, dim, n, periodic, rational, 0);
          m = curve_points(&r, &c, pts, MAXM);
          check_curve(&c, pts, m, curve);
          bsfit_curve_free(&c);
        }
}

static void test_exact_ties_on_a_polyline(void **state) {
  /* given degree-1 curves with integer knots of uneven gaps and integer control points,
  ** whose samples are exact, so that a point on a knot's sample ties with its twin (the
  ** last sample of one span, the first of the next, with different steps) and a midpoint
  ** ties with both ends, when their closest points are found all at once, then the first
  ** sample of each tie was taken, as bsfit_curve_closest takes it */
  static double pts[MAXM * 3];
  test_rng r = {99};
  size_t curve = 100;
  int dim, periodic, rep;
  (void)state;
  for (rep = 0; rep < 4; rep++)
    for (dim = 2; dim <= 3; dim++)
      for (periodic = 0; periodic <= 1; periodic++, curve++) {
        bsfit_curve c;
        size_t m;
        random_curve(&r, &c, 1, dim, 40 + (size_t)rep * 10, periodic, 0, 1);
        m = curve_points(&r, &c, pts, MAXM);
        check_curve(&c, pts, m, curve);
        bsfit_curve_free(&c);
      }
}

static void test_errors(void **state) {
  /* given a valid curve, when closest_many gets a NaN, an infinity, NULL arrays or no
  ** points, then it reports ENONFINITE, EINVAL or success with nothing written */
  test_rng r = {7};
  bsfit_curve c;
  bsfit_status st;
  double pts[64 * 2], u[64], dist[64];
  size_t i;
  (void)state;
  random_curve(&r, &c, 3, 2, 30, 1, 0, 0);
  for (i = 0; i < 64 * 2; i++) pts[i] = rng_range(&r, -2.0, 2.0);
  pts[77] = NAN;
  assert_int_equal(bsfit_curve_closest_many(&c, pts, 64, u, dist, NULL, &st), BSFIT_ENONFINITE);
  assert_int_equal(st.code, BSFIT_ENONFINITE);
  pts[77] = -INFINITY;
  assert_int_equal(bsfit_curve_closest_many(&c, pts, 64, u, dist, NULL, NULL), BSFIT_ENONFINITE);
  pts[77] = 0.5;
  assert_int_equal(bsfit_curve_closest_many(&c, NULL, 64, u, dist, NULL, &st), BSFIT_EINVAL);
  assert_int_equal(bsfit_curve_closest_many(&c, pts, 64, NULL, dist, NULL, &st), BSFIT_EINVAL);
  u[0] = dist[0] = 12345.0;
  assert_int_equal(bsfit_curve_closest_many(&c, pts, 0, u, dist, NULL, &st), BSFIT_OK);
  assert_int_equal(bsfit_curve_closest_many(&c, NULL, 0, NULL, NULL, NULL, &st), BSFIT_OK);
  assert_float_equal(u[0], 12345.0, 0.0);
  assert_float_equal(dist[0], 12345.0, 0.0);
  assert_int_equal(bsfit_curve_closest_many(NULL, pts, 64, u, dist, NULL, &st) != BSFIT_OK, 1);
  bsfit_curve_free(&c);
}

/* }==================================================================== */

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_index_matches_scan_on_ties),
      cmocka_unit_test(test_index_matches_scan_on_large_curve_like_sets),
      cmocka_unit_test(test_many_equals_closest_bitwise),
      cmocka_unit_test(test_exact_ties_on_a_polyline),
      cmocka_unit_test(test_errors),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
