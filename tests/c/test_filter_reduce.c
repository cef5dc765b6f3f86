/*
** test_filter_reduce.c
** Degree reduction (bsfit_filter_reduce_curve) and the curve distance, checked against
** mathematics and independent computations:
**   - a curve that already is of degree q (elevated by 1 or 2, open with repeated knots
**     or closed) comes back unchanged (1e-12 at 1000 parameters);
**   - the result is the L2 projection: its error S - C is orthogonal to every basis
**     function of the target space (the basis by the Cox-de Boor recursion written here,
**     integrals by Gauss-Legendre on every piece between the two curves' knots);
**   - the deviation reported is the true distance: dense samples of each curve, nearest
**     dense sample of the other by brute force, refined by golden-section search; it is
**     within tol, knots are added when needed;
**   - closed curves stay closed and C^{q-1} (derivatives across every knot and the seam);
**   - a rational circle is approximated within tol of the exact circle;
**   - every error.
*/
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "bsfit.h"
#include "cmocka_double.h"
#include "testutil.h"

#define NT 1000

static void expect_error(bsfit_err got, bsfit_err want, const bsfit_status *st) {
  assert_int_equal(got, want);
  assert_int_equal(st->code, want);
  assert_true(strlen(st->msg) > 0);
}

static void random_points(test_rng *r, size_t n, int dim, double *P) {
  size_t i;
  for (i = 0; i < n * (size_t)dim; i++) P[i] = rng_range(r, -1.0, 1.0);
}

/* open clamped (random knots, some repeated) or closed (random spans) */
static void make_curve(test_rng *r, int closed, int p, size_t n, int dim, bsfit_curve *c) {
  double U[128], P[384], per[64];
  size_t i;
  bsfit_status st;
  bsfit_curve_init(c);
  random_points(r, n, dim, P);
  if (!closed) {
    random_knots(r, p, n, 1, U);
    assert_int_equal(bsfit_curve_new(c, p, dim, n, U, P, NULL, 0, NULL, &st), BSFIT_OK);
    return;
  }
  per[0] = 0.0;
  for (i = 1; i <= n; i++) per[i] = per[i - 1] + rng_range(r, 0.2, 1.0);
  assert_int_equal(bsfit_curve_new_periodic(c, p, dim, n, per, P, NULL, NULL, &st), BSFIT_OK);
}

/* A section-like curve: control points on an ellipse of random axes, each moved by up
** to `rough` of the size (closed, or an open arc of 3/4 turn with clamped knots). */
static void make_section(test_rng *r, int closed, int p, size_t n, double rough, bsfit_curve *c) {
  double U[128], P[256], per[64], ax = rng_range(r, 1.0, 2.0), ay = rng_range(r, 0.5, 1.0);
  size_t i;
  bsfit_status st;
  for (i = 0; i < n; i++) {
    double th = (closed ? 2.0 : 1.5) * 3.14159265358979 * (double)i / (double)(n - !closed);
    double f = 1.0 + rng_range(r, -rough, rough);
    P[2 * i] = ax * f * cos(th);
    P[2 * i + 1] = ay * f * sin(th);
  }
  bsfit_curve_init(c);
  if (!closed) {
    random_knots(r, p, n, 1, U);
    assert_int_equal(bsfit_curve_new(c, p, 2, n, U, P, NULL, 0, NULL, &st), BSFIT_OK);
    return;
  }
  per[0] = 0.0;
  for (i = 1; i <= n; i++) per[i] = per[i - 1] + rng_range(r, 0.5, 1.0);
  assert_int_equal(bsfit_curve_new_periodic(c, p, 2, n, per, P, NULL, NULL, &st), BSFIT_OK);
}

static double dist2(const double *x, const double *y, int d) {
  double s = 0.0;
  int k;
  for (k = 0; k < d; k++) s += (x[k] - y[k]) * (x[k] - y[k]);
  return s;
}

/* }==================================================================== */

/* {====================================================================
** Reproduction
** ===================================================================== */

static void check_same_curve(const bsfit_curve *A, const bsfit_curve *B, double eps) {
  double a, b;
  size_t i;
  int k;
  bsfit_curve_domain(A, &a, &b);
  for (i = 0; i < NT; i++) {
    double t = a + (b - a) * (double)i / (double)(NT - 1), x[4], y[4];
    assert_int_equal(bsfit_curve_eval(A, t, x, NULL), BSFIT_OK);
    assert_int_equal(bsfit_curve_eval(B, t, y, NULL), BSFIT_OK);
    for (k = 0; k < A->dim; k++) assert_float_equal(x[k], y[k], eps);
  }
}

static void test_reproduces_elevated_curves(void **state) {
  test_rng rng = {0x7265640001};
  int q, t, closed, rep;
  (void)state;
  for (q = 1; q <= 4; q++)
    for (t = 1; t <= 2; t++)
      for (closed = 0; closed <= 1; closed++)
        for (rep = 0; rep < 3; rep++) {
          bsfit_curve c, E, R;
          bsfit_reduce_opts o;
          bsfit_reduce_report r;
          bsfit_status st;
          make_curve(&rng, closed, q, (size_t)q + 3 + (size_t)rep * 4, 2 + rep % 2, &c);
          bsfit_curve_init(&E);
          bsfit_curve_init(&R);
          assert_int_equal(bsfit_curve_elevate(&c, t, &E, &st), BSFIT_OK);
          memset(&o, 0, sizeof o);
          o.degree = q;
          o.tol = INFINITY;
          assert_int_equal(bsfit_filter_reduce_curve(&E, &o, &R, &r, &st), BSFIT_OK);
          assert_int_equal(R.degree, q);
          assert_int_equal(R.periodic, closed);
          assert_int_equal(bsfit_curve_distinct(&R), bsfit_curve_distinct(&c));
          assert_int_equal((int)r.knots_added, 0);
          assert_true(r.max_deviation <= 1e-12);
          check_same_curve(&R, &c, 1e-12);
          bsfit_curve_free(&c);
          bsfit_curve_free(&E);
          bsfit_curve_free(&R);
        }
}

/* A curve of lower degree p < q lies in the target space too: reproduced (the Gram
** matrix needs the 2q-degree rule then, the mixed one only q + p: a polyline raised to
** a cubic with C^0 knots once came back ENOTSPD). */
static void test_reproduces_lower_degrees(void **state) {
  test_rng rng = {0x7265640008};
  int p, q, closed;
  (void)state;
  for (closed = 0; closed <= 1; closed++)
    for (p = 1; p <= 3; p++)
      for (q = p + 1; q <= 5; q++) {
        bsfit_curve c, R;
        bsfit_reduce_opts o;
        bsfit_reduce_report r;
        bsfit_status st;
        make_curve(&rng, closed, p, (size_t)p + 5 + (size_t)q, 2, &c);
        bsfit_curve_init(&R);
        memset(&o, 0, sizeof o);
        o.degree = q;
        o.tol = 1e-9;
        assert_int_equal(bsfit_filter_reduce_curve(&c, &o, &R, &r, &st), BSFIT_OK);
        assert_int_equal(R.degree, q);
        assert_int_equal((int)r.knots_added, 0);
        check_same_curve(&R, &c, 1e-12);
        bsfit_curve_free(&c);
        bsfit_curve_free(&R);
      }
}

/* }==================================================================== */

/* {====================================================================
** Least squares over the whole curve: the error is orthogonal to the target space
** ===================================================================== */

/* N_{i,p}(t) by the Cox-de Boor recursion (right-open spans; the last non-empty span
** closed at b so that the end of a clamped curve has its value). */
static double coxdeboor(const double *U, size_t nk, size_t i, int p, double t, double b) {
  double v = 0.0;
  if (p == 0) {
    if (U[i] <= t && t < U[i + 1]) return 1.0;
    if (t == b && U[i] < U[i + 1] && U[i + 1] == b) return 1.0;
    return 0.0;
  }
  if (U[i + (size_t)p] > U[i])
    v += (t - U[i]) / (U[i + (size_t)p] - U[i]) * coxdeboor(U, nk, i, p - 1, t, b);
  if (U[i + (size_t)p + 1] > U[i + 1])
    v += (U[i + (size_t)p + 1] - t) / (U[i + (size_t)p + 1] - U[i + 1]) *
         coxdeboor(U, nk, i + 1, p - 1, t, b);
  return v;
}

static int cmp_double(const void *a, const void *b) {
  double x = *(const double *)a, y = *(const double *)b;
  return x < y ? -1 : (x > y ? 1 : 0);
}

static const double G8_X[8] = {-0.9602898564975363, -0.7966664774136267, -0.5255324099163290,
                               -0.1834346424956498, 0.1834346424956498,  0.5255324099163290,
                               0.7966664774136267,  0.9602898564975363};
static const double G8_W[8] = {0.1012285362903763, 0.2223810344533745, 0.3137066458778873,
                               0.3626837833783620, 0.3626837833783620, 0.3137066458778873,
                               0.2223810344533745, 0.1012285362903763};

/* max_i |int phi_i (S - C)| / max_i int phi_i |S - C|-ish scale, phi_i the target's basis
** functions (folded for a closed curve: N_j + N_{j+N}). */
static void check_orthogonal(const bsfit_curve *S, const bsfit_curve *C) {
  size_t nkS = S->n + (size_t)S->degree + 1, nkC = C->n + (size_t)C->degree + 1, nc = 0, i, j;
  size_t N = bsfit_curve_distinct(S);
  double a, b, cut[512], *ip = calloc(N * 4, sizeof(double)), scale = 0.0;
  int g, k;
  assert_non_null(ip);
  bsfit_curve_domain(S, &a, &b);
  for (i = 0; i < nkS; i++) if (S->knots[i] > a && S->knots[i] < b) cut[nc++] = S->knots[i];
  for (i = 0; i < nkC; i++) if (C->knots[i] > a && C->knots[i] < b) cut[nc++] = C->knots[i];
  cut[nc++] = a;
  cut[nc++] = b;
  qsort(cut, nc, sizeof(double), cmp_double);
  for (i = 0; i + 1 < nc; i++)
    for (g = 0; g < 8 && cut[i + 1] > cut[i]; g++) {
      double h = 0.5 * (cut[i + 1] - cut[i]), t = 0.5 * (cut[i] + cut[i + 1]) + h * G8_X[g];
      double w = h * G8_W[g], x[4], y[4];
      bsfit_curve_eval(S, t, x, NULL);
      bsfit_curve_eval(C, t, y, NULL);
      for (j = 0; j < S->n; j++) {
        double phi = coxdeboor(S->knots, nkS, j, S->degree, t, b);
        if (phi == 0.0) continue;
        for (k = 0; k < S->dim; k++) ip[(j % N) * 4 + (size_t)k] += w * phi * (x[k] - y[k]);
        scale += w * phi * sqrt(dist2(x, y, S->dim));
      }
    }
  for (j = 0; j < N * 4; j++) assert_true(fabs(ip[j]) <= 1e-11 * (scale + 1e-300) + 1e-15);
  assert_true(scale > 0); /* the error is not zero: the check means something */
  free(ip);
}

static void test_projection_is_least_squares(void **state) {
  test_rng rng = {0x7265640002};
  int p, q, closed;
  (void)state;
  for (closed = 0; closed <= 1; closed++)
    for (p = 2; p <= 6; p++)
      for (q = 1; q < p; q++) {
        bsfit_curve c, R;
        bsfit_reduce_opts o;
        bsfit_status st;
        make_curve(&rng, closed, p, (size_t)p + 6, 2 + p % 2, &c);
        bsfit_curve_init(&R);
        memset(&o, 0, sizeof o);
        o.degree = q;
        o.tol = INFINITY;
        assert_int_equal(bsfit_filter_reduce_curve(&c, &o, &R, NULL, &st), BSFIT_OK);
        check_orthogonal(&R, &c);
        bsfit_curve_free(&c);
        bsfit_curve_free(&R);
      }
}

/* }==================================================================== */

/* {====================================================================
** The deviation is the true distance, within tol
** ===================================================================== */

#define DENSE 2000

typedef struct dense {
  const bsfit_curve *c;
  double a, b, t[DENSE], x[DENSE * 4];
} dense;

static void dense_init(dense *D, const bsfit_curve *c) {
  size_t i;
  D->c = c;
  bsfit_curve_domain(c, &D->a, &D->b);
  for (i = 0; i < DENSE; i++) {
    D->t[i] = D->a + (D->b - D->a) * (double)i / (double)(DENSE - 1);
    bsfit_curve_eval(c, D->t[i], D->x + i * 4, NULL);
  }
}

static double dist_at(const dense *D, const double *P, double t) {
  double x[4];
  bsfit_curve_eval(D->c, t, x, NULL);
  return sqrt(dist2(x, P, D->c->dim));
}

/* Golden-section search for the nearest point of the curve to P on [lo, hi]. */
static double golden(const dense *D, const double *P, double lo, double hi) {
  double g = 0.5 * (sqrt(5.0) - 1.0), x1 = hi - g * (hi - lo), x2 = lo + g * (hi - lo);
  double f1 = dist_at(D, P, x1), f2 = dist_at(D, P, x2);
  int it;
  for (it = 0; it < 80; it++) {
    if (f1 < f2) hi = x2, x2 = x1, f2 = f1, x1 = hi - g * (hi - lo), f1 = dist_at(D, P, x1);
    else lo = x1, x1 = x2, f1 = f2, x2 = lo + g * (hi - lo), f2 = dist_at(D, P, x2);
  }
  return fmin(f1, f2);
}

/* Distance from P to the curve: around each of the NEAR nearest dense samples (brute
** force), golden-section search over the sample's two neighbouring intervals. */
#define NEAR 4
static double point_distance(const dense *D, const double *P) {
  size_t i, j, best[NEAR];
  double bd[NEAR], out = INFINITY;
  for (j = 0; j < NEAR; j++) bd[j] = INFINITY, best[j] = 0;
  for (i = 0; i < DENSE; i++) {
    double d = dist2(D->x + i * 4, P, D->c->dim);
    for (j = NEAR; j > 0 && d < bd[j - 1]; j--) {
      if (j < NEAR) bd[j] = bd[j - 1], best[j] = best[j - 1];
    }
    if (j < NEAR) bd[j] = d, best[j] = i;
  }
  for (j = 0; j < NEAR; j++) {
    size_t b = best[j];
    out = fmin(out, sqrt(bd[j]));
    out = fmin(out, golden(D, P, D->t[b > 0 ? b - 1 : 0], D->t[b + 1 < DENSE ? b + 1 : DENSE - 1]));
  }
  return out;
}

/* max over the dense samples of each curve of the distance to the other */
static double hausdorff(const bsfit_curve *A, const bsfit_curve *B) {
  static dense DA, DB;
  double worst = 0.0;
  size_t i;
  dense_init(&DA, A);
  dense_init(&DB, B);
  for (i = 0; i < DENSE; i++) {
    double d1 = point_distance(&DB, DA.x + i * 4), d2 = point_distance(&DA, DB.x + i * 4);
    worst = fmax(worst, fmax(d1, d2));
  }
  return worst;
}

static void test_deviation_is_true_and_within_tol(void **state) {
  test_rng rng = {0x7265640003};
  int c, added = 0;
  (void)state;
  for (c = 0; c < 12; c++) {
    bsfit_curve base, F, R;
    bsfit_reduce_opts o;
    bsfit_reduce_report r;
    bsfit_status st;
    double a, b, truth, tols[3] = {1e-2, 1e-3, 1e-4};
    int closed = c % 2;
    /* a quintic curve as filtering leaves it: a rough cubic section filtered twice */
    make_section(&rng, closed, 3, 12 + (size_t)c * 3, 0.02 + 0.01 * c, &base);
    bsfit_curve_domain(&base, &a, &b);
    bsfit_curve_init(&F);
    bsfit_curve_init(&R);
    assert_int_equal(bsfit_filter_kernel_curve_delta(&base, 2, rng_range(&rng, 0.01, 0.05) * (b - a),
                                                     &F, &st),
                     BSFIT_OK);
    memset(&o, 0, sizeof o);
    o.tol = tols[c % 3];
    assert_int_equal(bsfit_filter_reduce_curve(&F, &o, &R, &r, &st), BSFIT_OK);
    assert_int_equal(R.degree, 3);
    assert_true(r.max_deviation <= o.tol);
    truth = hausdorff(&R, &F);
    /* the reported distance is the true one, up to what lies between samples (1%) */
    assert_true(fabs(r.max_deviation - truth) <= 0.01 * truth);
    assert_true(truth <= 1.01 * o.tol);
    added += (int)r.knots_added;
    bsfit_curve_free(&base);
    bsfit_curve_free(&F);
    bsfit_curve_free(&R);
  }
  assert_true(added > 0); /* tight tolerances needed knots */
}

/* bsfit_curve_distance against the same independent computation, for unrelated curves */
static void test_distance_is_true(void **state) {
  test_rng rng = {0x7265640004};
  int c;
  (void)state;
  for (c = 0; c < 8; c++) {
    bsfit_curve A, B;
    bsfit_status st;
    double d, truth;
    make_curve(&rng, c % 2, 1 + c % 4, 8, 2, &A);
    make_curve(&rng, c % 2, 2 + c % 3, 9, 2, &B);
    assert_int_equal(bsfit_curve_distance(&A, &B, 16, &d, &st), BSFIT_OK);
    truth = hausdorff(&A, &B);
    assert_true(fabs(d - truth) <= 0.01 * truth);
    bsfit_curve_free(&A);
    bsfit_curve_free(&B);
  }
}

/* }==================================================================== */

/* {====================================================================
** Closed curves stay closed and C^{q-1}; a rational circle
** ===================================================================== */

/* derivatives 0..q-1 just left and right of u agree (a jump would be of the size of the
** derivative; 2h times the next derivative is far below the tolerance) */
static void check_smooth_at(const bsfit_curve *S, double u, double scale) {
  double L[4 * 8], R[4 * 8], h = 1e-9 * scale;
  int k, d;
  assert_int_equal(bsfit_curve_derivs(S, u - h, S->degree - 1, L, NULL), BSFIT_OK);
  assert_int_equal(bsfit_curve_derivs(S, u + h, S->degree - 1, R, NULL), BSFIT_OK);
  for (k = 0; k < S->degree; k++)
    for (d = 0; d < S->dim; d++) {
      double l = L[k * S->dim + d], r = R[k * S->dim + d];
      assert_true(fabs(l - r) <= 1e-4 * (fabs(l) + fabs(r)) + 1e-9);
    }
}

static void test_closed_stays_closed_and_smooth(void **state) {
  test_rng rng = {0x7265640005};
  int c;
  (void)state;
  for (c = 0; c < 8; c++) {
    bsfit_curve base, R;
    bsfit_reduce_opts o;
    bsfit_status st;
    double a, b;
    size_t i;
    make_curve(&rng, 1, 5 + c % 2, 12, 2, &base);
    bsfit_curve_init(&R);
    memset(&o, 0, sizeof o);
    o.degree = 2 + c % 3;
    o.tol = 1e-3;
    assert_int_equal(bsfit_filter_reduce_curve(&base, &o, &R, NULL, &st), BSFIT_OK);
    assert_true(R.periodic);
    assert_int_equal(R.degree, o.degree);
    bsfit_curve_domain(&R, &a, &b);
    check_smooth_at(&R, a, b - a); /* the seam: u - h wraps to the period's end */
    for (i = (size_t)R.degree + 1; i < R.n; i++) check_smooth_at(&R, R.knots[i], b - a);
    bsfit_curve_free(&base);
    bsfit_curve_free(&R);
  }
}

static void test_rational_circle(void **state) {
  /* the unit circle as a closed quadratic NURBS of 4 arcs */
  const double s = sqrt(0.5);
  double P[8 * 2] = {1, -1, 1, 0, 1, 1, 0, 1, -1, 1, -1, 0, -1, -1, 0, -1};
  double w[8] = {s, 1, s, 1, s, 1, s, 1}, t[9] = {0, 0, 1, 1, 2, 2, 3, 3, 4}, a, b, worst = 0.0;
  bsfit_curve c, R;
  bsfit_reduce_opts o;
  bsfit_reduce_report r;
  bsfit_status st;
  int i;
  (void)state;
  bsfit_curve_init(&c);
  bsfit_curve_init(&R);
  /* one period of knots 0,0,1,1,2,2,3,3 | 4: the quadratic arcs meet at double knots */
  assert_int_equal(bsfit_curve_new_periodic(&c, 2, 2, 8, t, P, w, NULL, &st), BSFIT_OK);
  for (i = 0; i < 400; i++) { /* the input is the circle (a check of this test) */
    double x[2];
    bsfit_curve_eval(&c, 4.0 * i / 400.0, x, NULL);
    assert_float_equal(x[0] * x[0] + x[1] * x[1], 1.0, 1e-14);
  }
  memset(&o, 0, sizeof o);
  o.tol = 1e-5;
  assert_int_equal(bsfit_filter_reduce_curve(&c, &o, &R, &r, &st), BSFIT_OK);
  assert_true(R.periodic);
  assert_true(r.max_deviation <= 1e-5);
  bsfit_curve_domain(&R, &a, &b);
  for (i = 0; i < 4000; i++) {
    double x[2];
    bsfit_curve_eval(&R, a + (b - a) * i / 4000.0, x, NULL);
    worst = fmax(worst, fabs(sqrt(x[0] * x[0] + x[1] * x[1]) - 1.0));
  }
  assert_true(worst <= 1e-5 * 1.05);
  bsfit_curve_free(&c);
  bsfit_curve_free(&R);
}

/* }==================================================================== */

/* {====================================================================
** Errors
** ===================================================================== */

static void test_bad_input(void **state) {
  test_rng rng = {0x7265640006};
  bsfit_curve c, R;
  bsfit_reduce_opts o;
  bsfit_status st;
  double brk[3], d;
  (void)state;
  make_curve(&rng, 0, 5, 10, 2, &c);
  bsfit_curve_init(&R);
  memset(&o, 0, sizeof o);
  o.tol = 0.0;
  expect_error(bsfit_filter_reduce_curve(&c, &o, &R, NULL, &st), BSFIT_EINVAL, &st);
  o.tol = -1.0;
  expect_error(bsfit_filter_reduce_curve(&c, &o, &R, NULL, &st), BSFIT_EINVAL, &st);
  o.tol = NAN;
  expect_error(bsfit_filter_reduce_curve(&c, &o, &R, NULL, &st), BSFIT_ENONFINITE, &st);
  o.tol = 1e-3;
  o.degree = -1;
  expect_error(bsfit_filter_reduce_curve(&c, &o, &R, NULL, &st), BSFIT_EDEGREE, &st);
  o.degree = BSFIT_MAX_DEGREE + 1;
  expect_error(bsfit_filter_reduce_curve(&c, &o, &R, NULL, &st), BSFIT_EDEGREE, &st);
  o.degree = 3;
  brk[0] = c.knots[5];
  brk[1] = 0.5 * (c.knots[5] + c.knots[10]);
  brk[2] = c.knots[10] + 1.0; /* not the domain's end */
  o.breaks = brk;
  o.nbreaks = 3;
  expect_error(bsfit_filter_reduce_curve(&c, &o, &R, NULL, &st), BSFIT_EINVAL, &st);
  brk[2] = c.knots[10];
  brk[1] = brk[0]; /* not increasing */
  expect_error(bsfit_filter_reduce_curve(&c, &o, &R, NULL, &st), BSFIT_EINVAL, &st);
  o.breaks = NULL;
  /* a tolerance out of reach within the knots allowed */
  o.tol = 1e-14;
  o.max_added = 2;
  expect_error(bsfit_filter_reduce_curve(&c, &o, &R, NULL, &st), BSFIT_ENOCONV, &st);
  expect_error(bsfit_filter_reduce_curve(NULL, &o, &R, NULL, &st), BSFIT_EINVAL, &st);
  expect_error(bsfit_filter_reduce_curve(&c, NULL, &R, NULL, &st), BSFIT_EINVAL, &st);
  expect_error(bsfit_filter_reduce_curve(&c, &o, NULL, NULL, &st), BSFIT_EINVAL, &st);
  assert_null(R.ctrl);
  expect_error(bsfit_curve_distance(&c, NULL, 16, &d, &st), BSFIT_EINVAL, &st);
  expect_error(bsfit_curve_distance(&c, &c, 0, &d, &st), BSFIT_EINVAL, &st);
  bsfit_curve_free(&c);
}

/* An interrupted host gets EINTR from reduce and smooth, and its output is untouched. */
static void test_interrupt(void **state) {
  test_rng rng = {0x7265640007};
  bsfit_curve c, R;
  bsfit_reduce_opts o;
  bsfit_smooth_opts so;
  bsfit_status st;
  volatile int stop = 1;
  (void)state;
  make_section(&rng, 1, 3, 30, 0.05, &c);
  bsfit_curve_init(&R);
  c.alloc.interrupt = &stop;
  memset(&o, 0, sizeof o);
  o.tol = 1e-3;
  expect_error(bsfit_filter_reduce_curve(&c, &o, &R, NULL, &st), BSFIT_EINTR, &st);
  memset(&so, 0, sizeof so);
  so.tol = 1e-2;
  expect_error(bsfit_filter_smooth_curve(&c, &so, &R, NULL, &st), BSFIT_EINTR, &st);
  assert_null(R.ctrl);
  c.alloc.interrupt = NULL;
  bsfit_curve_free(&c);
}

/* }==================================================================== */

int main(void) {
  const struct CMUnitTest tests[] = {
    cmocka_unit_test(test_reproduces_elevated_curves),
    cmocka_unit_test(test_reproduces_lower_degrees),
    cmocka_unit_test(test_projection_is_least_squares),
    cmocka_unit_test(test_deviation_is_true_and_within_tol),
    cmocka_unit_test(test_distance_is_true),
    cmocka_unit_test(test_closed_stays_closed_and_smooth),
    cmocka_unit_test(test_rational_circle),
    cmocka_unit_test(test_bad_input),
    cmocka_unit_test(test_interrupt),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
