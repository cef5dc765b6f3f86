/*
** test_filter.c
** Box filtering (Persiano): the filtered curve must equal the window average
** 1/(2 delta) * integral of C over [t - delta, t + delta], computed here by adaptive
** Gauss-Legendre quadrature split at the knots, for uniform open curves (moving
** average with the end rule), closed curves, clamped and non-uniform curves (exact
** filter) and surfaces; k = 1 keeps the control polygon; smoothing lowers turning and
** bending energy; the shape measures on curves whose values are known; every error.
**
** The end rule is checked from its definition: an open curve is extended by padding
** its control polygon with copies of V^0 and V^{n-1} (on extra knots, whose values do
** not matter), and a clamped curve also by the constant C(a), C(b) directly.
*/
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "bsfit.h"
#include "cmocka_double.h"
#include "testutil.h"
#include "filter_testutil.h"

#define EPS_FILTER 1e-10 /* filtered curve vs numerical window average */
#define EPS_POINT 1e-12  /* control points that must be copies */
#define NT 1000          /* parameters checked per curve */

static const double PI = 3.14159265358979323846;

/* {====================================================================
** Quadrature: adaptive Gauss-Legendre between break points
** ===================================================================== */

/* 5-point rule (the surface test's tensor rule) */
static const double GL_X[5] = {-0.9061798459386640, -0.5384693101056831, 0.0, 0.5384693101056831,
                               0.9061798459386640};
static const double GL_W[5] = {0.2369268850561891, 0.4786286704993665, 0.5688888888888889,
                               0.4786286704993665, 0.2369268850561891};
/* 3-point (exact to degree 5) and 4-point (exact to degree 7) rules */
static const double G3_X[3] = {-0.7745966692414834, 0.0, 0.7745966692414834};
static const double G3_W[3] = {0.5555555555555556, 0.8888888888888889, 0.5555555555555556};
static const double G4_X[4] = {-0.8611363115940526, -0.3399810435848563, 0.3399810435848563,
                               0.8611363115940526};
static const double G4_W[4] = {0.3478548451374538, 0.6521451548625461, 0.6521451548625461,
                               0.3478548451374538};

static void gauss(vec_fn f, const void *ctx, const double *X, const double *W, int npt, double x0,
                  double x1, int dim, double *acc) {
  double half = 0.5 * (x1 - x0), mid = 0.5 * (x0 + x1), y[4];
  int i, k;
  for (k = 0; k < dim; k++) acc[k] = 0.0;
  for (i = 0; i < npt; i++) {
    f(ctx, mid + half * X[i], y);
    for (k = 0; k < dim; k++) acc[k] += half * W[i] * y[k];
  }
}

/* Accepts the 4-point value where the 3-point rule agrees with it (always, on a
** polynomial piece of degree <= 5); otherwise halves the interval. */
static void adaptive(vec_fn f, const void *ctx, double x0, double x1, int dim, int depth,
                     double *out) {
  double g4[4], g3[4], left[4], right[4], mid = 0.5 * (x0 + x1), err = 0.0;
  int k;
  gauss(f, ctx, G4_X, G4_W, 4, x0, x1, dim, g4);
  gauss(f, ctx, G3_X, G3_W, 3, x0, x1, dim, g3);
  for (k = 0; k < dim; k++) err = fmax(err, fabs(g4[k] - g3[k]));
  if (err <= 1e-14 * (1.0 + fabs(x1 - x0)) || depth >= 30) {
    for (k = 0; k < dim; k++) out[k] = g4[k];
    return;
  }
  adaptive(f, ctx, x0, mid, dim, depth + 1, left);
  adaptive(f, ctx, mid, x1, dim, depth + 1, right);
  for (k = 0; k < dim; k++) out[k] = left[k] + right[k];
}

/* 1/(2 delta) * integral of f over [t - delta, t + delta], split at the sorted breaks */
static void window_average(vec_fn f, const void *ctx, const double *brk, size_t nb, double t,
                           double delta, int dim, double *out) {
  double x0 = t - delta, x1 = t + delta, piece[4];
  size_t i;
  int k;
  for (k = 0; k < dim; k++) out[k] = 0.0;
  for (i = 0; i <= nb; i++) {
    double end = i < nb ? brk[i] : x1;
    if (end <= x0) continue;
    if (end > x1) end = x1;
    adaptive(f, ctx, x0, end, dim, 0, piece);
    for (k = 0; k < dim; k++) out[k] += piece[k];
    x0 = end;
    if (x0 >= x1) break;
  }
  for (k = 0; k < dim; k++) out[k] /= 2.0 * delta;
}

/* }==================================================================== */

/* {====================================================================
** Curves under test and their extensions
** ===================================================================== */

/* Checks |F(t) - window average of f| <= EPS_FILTER at NT parameters of F's domain. */
static void check_against_integral(const bsfit_curve *F, vec_fn f, const void *ctx,
                                   const double *brk, size_t nb, double delta) {
  double a, b, got[4], want[4];
  size_t i;
  int k;
  bsfit_curve_domain(F, &a, &b);
  for (i = 0; i < NT; i++) {
    double t = a + (b - a) * (double)i / (double)(NT - 1);
    bsfit_status st;
    assert_int_equal(bsfit_curve_eval(F, t, got, &st), BSFIT_OK);
    window_average(f, ctx, brk, nb, t, delta, F->dim, want);
    for (k = 0; k < F->dim; k++) assert_float_equal(got[k], want[k], EPS_FILTER);
  }
}

/* uniform unclamped curve on [0, 1] */
static void uniform_curve(test_rng *r, int p, size_t n, int dim, bsfit_curve *c) {
  double U[64], P[256];
  bsfit_status st;
  assert_int_equal(bsfit_knots_uniform(p, n, 0.0, 1.0, U, &st), BSFIT_OK);
  random_points(r, n, dim, P);
  bsfit_curve_init(c);
  assert_int_equal(bsfit_curve_new(c, p, dim, n, U, P, NULL, 0, NULL, &st), BSFIT_OK);
}

static void periodic_curve(test_rng *r, int p, size_t N, int dim, int uniform, bsfit_curve *c) {
  double per[64], P[256];
  size_t i;
  bsfit_status st;
  per[0] = 0.0;
  for (i = 1; i <= N; i++) per[i] = per[i - 1] + (uniform ? 1.0 / (double)N : rng_range(r, 0.2, 1.0));
  random_points(r, N, dim, P);
  bsfit_curve_init(c);
  assert_int_equal(bsfit_curve_new_periodic(c, p, dim, N, per, P, NULL, NULL, &st), BSFIT_OK);
}

static void check_domain(const bsfit_curve *F, double lo, double hi) {
  double a, b;
  bsfit_curve_domain(F, &a, &b);
  assert_float_equal(a, lo, EPS_KNOT);
  assert_float_equal(b, hi, EPS_KNOT);
}

/* the open filtered curve starts at V^0 and ends at V^{n-1} */
static void check_end_points(const bsfit_curve *F, const bsfit_curve *c) {
  double a, b, x[4];
  int k;
  bsfit_curve_domain(F, &a, &b);
  bsfit_curve_eval(F, a, x, NULL);
  for (k = 0; k < c->dim; k++) assert_float_equal(x[k], c->ctrl[k], EPS_FILTER);
  bsfit_curve_eval(F, b, x, NULL);
  for (k = 0; k < c->dim; k++) assert_float_equal(x[k], c->ctrl[(c->n - 1) * (size_t)c->dim + k], EPS_FILTER);
}

/* }==================================================================== */

/* {====================================================================
** Curves: the filter equals the window average
** ===================================================================== */

static void test_uniform_open_matches_integral(void **state) {
  test_rng r = {0x5eed0001};
  int p, k;
  (void)state;
  for (p = 1; p <= 5; p++)
    for (k = 1; k <= 6; k++) {
      /* given a uniform unclamped curve and its end-rule extension */
      bsfit_curve c, F, pad;
      size_t n = (size_t)p + 8;
      double h = 1.0 / (double)(n - (size_t)p), delta = 0.5 * k * h;
      bsfit_status st;
      uniform_curve(&r, p, n, 2, &c);
      pad_curve(&c, (size_t)p + 8, h, &pad);
      /* when filtered over k spans */
      bsfit_curve_init(&F);
      assert_int_equal(bsfit_filter_box_curve(&c, k, &F, &st), BSFIT_OK);
      /* then degree p+1, n+2p+k-1 points, domain [U_1 - delta, U_{n+p-1} + delta] */
      assert_int_equal(F.degree, p + 1);
      assert_int_equal(F.n, n + 2 * (size_t)p + (size_t)k - 1);
      check_domain(&F, c.knots[1] - delta, c.knots[n + (size_t)p - 1] + delta);
      check_end_points(&F, &c);
      check_against_integral(&F, curve_fn, &pad, pad.knots, pad.n + (size_t)p + 1, delta);
      bsfit_curve_free(&c);
      bsfit_curve_free(&F);
      bsfit_curve_free(&pad);
    }
}

static void test_uniform_closed_matches_integral(void **state) {
  test_rng r = {0x5eed0002};
  int p, k;
  (void)state;
  for (p = 1; p <= 5; p++)
    for (k = 1; k <= 6; k++) {
      bsfit_curve c, F;
      size_t N = 9;
      double delta = 0.5 * k / (double)N, brk[64], a, b;
      size_t nb = 0, i;
      int m;
      bsfit_status st;
      periodic_curve(&r, p, N, 2, 1, &c);
      bsfit_curve_domain(&c, &a, &b);
      for (m = -1; m <= 1; m++)
        for (i = 0; i < N; i++) brk[nb++] = c.knots[(size_t)p + i] + m * (b - a);
      bsfit_curve_init(&F);
      assert_int_equal(bsfit_filter_box_curve(&c, k, &F, &st), BSFIT_OK);
      /* then periodic, N distinct points, period [a, b] shifted by 0 or half a span */
      assert_true(F.periodic);
      assert_int_equal(F.degree, p + 1);
      assert_int_equal(bsfit_curve_distinct(&F), N);
      assert_int_equal(bsfit_curve_validate(&F, &st), BSFIT_OK);
      check_domain(&F, a + (k % 2) * 0.5 / (double)N, b + (k % 2) * 0.5 / (double)N);
      check_against_integral(&F, curve_fn, &c, brk, nb, delta);
      bsfit_curve_free(&c);
      bsfit_curve_free(&F);
    }
}

static void test_exact_nonuniform_open_matches_integral(void **state) {
  test_rng r = {0x5eed0003};
  const double frac[] = {0.013, 0.11, 0.29, 0.47};
  int p, clamped;
  size_t f;
  (void)state;
  for (clamped = 0; clamped <= 1; clamped++)
    for (p = 1; p <= 5; p++)
      for (f = 0; f < sizeof frac / sizeof frac[0]; f++) {
        /* given a random non-uniform curve (repeated interior knots included) */
        bsfit_curve c, F, pad;
        size_t n = (size_t)p + 7, nk = n + (size_t)p + 1;
        double U[64], P[64], a, b, delta;
        bsfit_status st;
        random_knots(&r, p, n, clamped, U);
        random_points(&r, n, 2, P);
        bsfit_curve_init(&c);
        assert_int_equal(bsfit_curve_new(&c, p, 2, n, U, P, NULL, 0, NULL, &st), BSFIT_OK);
        bsfit_curve_domain(&c, &a, &b);
        delta = frac[f] * (b - a);
        /* when filtered exactly over [t - delta, t + delta] */
        bsfit_curve_init(&F);
        assert_int_equal(bsfit_filter_box_curve_delta(&c, delta, &F, &st), BSFIT_OK);
        assert_int_equal(F.degree, p + 1);
        check_domain(&F, U[1] - delta, U[nk - 2] + delta);
        check_end_points(&F, &c);
        if (clamped) {
          /* then, clamped: the average of C extended as the constants C(a), C(b) */
          check_against_integral(&F, clamped_fn, &c, U, nk, delta);
        } else {
          /* then, unclamped: the average of the end-rule extension */
          pad_curve(&c, (size_t)p + 6, b - a, &pad);
          check_against_integral(&F, curve_fn, &pad, pad.knots, pad.n + (size_t)p + 1, delta);
          bsfit_curve_free(&pad);
        }
        bsfit_curve_free(&c);
        bsfit_curve_free(&F);
      }
}

static void test_exact_closed_matches_integral(void **state) {
  test_rng r = {0x5eed0004};
  const double frac[] = {0.021, 0.17, 0.5};
  int p;
  size_t f;
  (void)state;
  for (p = 1; p <= 5; p++)
    for (f = 0; f < sizeof frac / sizeof frac[0]; f++) {
      bsfit_curve c, F;
      size_t N = 8, nb = 0, i;
      double brk[64], a, b, delta;
      int m;
      bsfit_status st;
      periodic_curve(&r, p, N, 2, 0, &c);
      bsfit_curve_domain(&c, &a, &b);
      for (m = -1; m <= 1; m++)
        for (i = 0; i < N; i++) brk[nb++] = c.knots[(size_t)p + i] + m * (b - a);
      delta = frac[f] * (b - a);
      bsfit_curve_init(&F);
      assert_int_equal(bsfit_filter_box_curve_delta(&c, delta, &F, &st), BSFIT_OK);
      /* then a periodic curve of the same period, the average of the closed curve */
      assert_true(F.periodic);
      assert_int_equal(F.degree, p + 1);
      assert_int_equal(bsfit_curve_validate(&F, &st), BSFIT_OK);
      {
        double fa, fb;
        bsfit_curve_domain(&F, &fa, &fb);
        assert_float_equal(fb - fa, b - a, EPS_KNOT);
      }
      check_against_integral(&F, curve_fn, &c, brk, nb, delta);
      bsfit_curve_free(&c);
      bsfit_curve_free(&F);
    }
}

static void check_same_function(const bsfit_curve *A, const bsfit_curve *B) {
  double a0, a1, b0, b1, x[4], y[4];
  size_t i;
  int k;
  bsfit_curve_domain(A, &a0, &a1);
  bsfit_curve_domain(B, &b0, &b1);
  assert_float_equal(a0, b0, EPS_KNOT);
  assert_float_equal(a1, b1, EPS_KNOT);
  for (i = 0; i < NT; i++) {
    double t = a0 + (a1 - a0) * (double)i / (double)(NT - 1);
    bsfit_curve_eval(A, t, x, NULL);
    bsfit_curve_eval(B, t, y, NULL);
    for (k = 0; k < A->dim; k++) assert_float_equal(x[k], y[k], EPS_FILTER);
  }
}

static void test_exact_agrees_with_moving_average(void **state) {
  test_rng r = {0x5eed0005};
  int p, k, closed;
  (void)state;
  for (closed = 0; closed <= 1; closed++)
    for (p = closed ? 1 : 0; p <= 4; p++) /* degree 0: a step function becomes a polygon */
      for (k = 1; k <= 5; k++) {
        bsfit_curve c, M, E;
        size_t n = (size_t)p + 9;
        double a, b, h;
        bsfit_status st;
        if (closed) periodic_curve(&r, p, 9, 2, 1, &c);
        else uniform_curve(&r, p, n, 2, &c);
        bsfit_curve_domain(&c, &a, &b);
        h = (b - a) / (double)(closed ? 9 : n - (size_t)p);
        bsfit_curve_init(&M);
        bsfit_curve_init(&E);
        assert_int_equal(bsfit_filter_box_curve(&c, k, &M, &st), BSFIT_OK);
        assert_int_equal(bsfit_filter_box_curve_delta(&c, 0.5 * k * h, &E, &st), BSFIT_OK);
        check_same_function(&M, &E);
        bsfit_curve_free(&c);
        bsfit_curve_free(&M);
        bsfit_curve_free(&E);
      }
}

static void test_k1_keeps_the_control_polygon(void **state) {
  test_rng r = {0x5eed0006};
  int p;
  (void)state;
  for (p = 1; p <= 5; p++) {
    /* given uniform open and closed curves */
    bsfit_curve c, F, z, G;
    size_t n = (size_t)p + 6, i, N = 7;
    int k;
    bsfit_status st;
    uniform_curve(&r, p, n, 2, &c);
    periodic_curve(&r, p, N, 2, 1, &z);
    bsfit_curve_init(&F);
    bsfit_curve_init(&G);
    /* when filtered with k = 1 */
    assert_int_equal(bsfit_filter_box_curve(&c, 1, &F, &st), BSFIT_OK);
    assert_int_equal(bsfit_filter_box_curve(&z, 1, &G, &st), BSFIT_OK);
    /* then only the degree rises: the control polygon is the original one (open:
    ** padded by p copies of each end point; closed: the same points) */
    assert_int_equal(F.degree, p + 1);
    assert_int_equal(G.degree, p + 1);
    for (i = 0; i < F.n; i++) {
      size_t j = i < (size_t)p ? 0 : (i - (size_t)p >= n ? n - 1 : i - (size_t)p);
      for (k = 0; k < 2; k++) assert_float_equal(F.ctrl[i * 2 + (size_t)k], c.ctrl[j * 2 + (size_t)k], EPS_POINT);
    }
    for (i = 0; i < G.n; i++)
      for (k = 0; k < 2; k++) assert_float_equal(G.ctrl[i * 2 + (size_t)k], z.ctrl[(i % N) * 2 + (size_t)k], EPS_POINT);
    bsfit_curve_free(&c);
    bsfit_curve_free(&F);
    bsfit_curve_free(&z);
    bsfit_curve_free(&G);
  }
}

static void test_polyline_corner_is_cut(void **state) {
  /* The curve itself is not the original one: the degree-1 closed square with
  ** corners (+-1, +-1), filtered with k = 1, is the quadratic through the edge
  ** midpoints; at the old corner's parameter it sits at (3/4, 3/4) by the integral
  ** 1/h * int_{-h/2}^{h/2} of the two edges meeting at the corner. */
  const double P[] = {1, 1, -1, 1, -1, -1, 1, -1};
  bsfit_curve c, F;
  double x[2];
  bsfit_status st;
  (void)state;
  bsfit_curve_init(&c);
  bsfit_curve_init(&F);
  assert_int_equal(bsfit_curve_new_periodic(&c, 1, 2, 4, NULL, P, NULL, NULL, &st), BSFIT_OK);
  assert_int_equal(bsfit_filter_box_curve(&c, 1, &F, &st), BSFIT_OK);
  bsfit_curve_eval(&F, c.knots[1], x, NULL); /* parameter of the corner (1, 1) */
  assert_float_equal(x[0], 0.75, EPS_EXACT);
  assert_float_equal(x[1], 0.75, EPS_EXACT);
  bsfit_curve_free(&c);
  bsfit_curve_free(&F);
}

static void test_output_may_be_the_input(void **state) {
  test_rng r = {0x5eed0007};
  bsfit_curve c, copy, F;
  bsfit_status st;
  (void)state;
  uniform_curve(&r, 3, 10, 2, &c);
  bsfit_curve_init(&copy);
  bsfit_curve_init(&F);
  assert_int_equal(bsfit_curve_copy(&c, &copy, NULL, &st), BSFIT_OK);
  assert_int_equal(bsfit_filter_box_curve(&copy, 3, &F, &st), BSFIT_OK);
  assert_int_equal(bsfit_filter_box_curve(&c, 3, &c, &st), BSFIT_OK);
  check_same_function(&c, &F);
  assert_int_equal(bsfit_filter_box_curve_delta(&copy, 0.1, &copy, &st), BSFIT_OK);
  assert_int_equal(copy.degree, 4);
  bsfit_curve_free(&c);
  bsfit_curve_free(&copy);
  bsfit_curve_free(&F);
}

/* }==================================================================== */

/* {====================================================================
** Shape measures
** ===================================================================== */

static void test_measures_of_known_curves(void **state) {
  /* The NURBS Book's 9-point circle (degree 2, radius 2): turning 2 pi and bending
  ** energy 2 pi / r, up to the half step lost at each open end (~1/samples). */
  const double s = sqrt(0.5), R = 2.0;
  const double U[] = {0, 0, 0, 0.25, 0.25, 0.5, 0.5, 0.75, 0.75, 1, 1, 1};
  const double P[] = {R, 0, R, R, 0, R, -R, R, -R, 0, -R, -R, 0, -R, R, -R, R, 0};
  const double W[] = {1, s, 1, s, 1, s, 1, s, 1};
  const double hex[] = {1, 0, 0.5, 0.8660254037844386, -0.5, 0.8660254037844386,
                        -1, 0, -0.5, -0.8660254037844386, 0.5, -0.8660254037844386};
  const double line[] = {0, 0, 1, 2, 2, 4, 3, 6};
  const size_t samples = 4000;
  bsfit_curve c;
  double v, moved[18];
  size_t i;
  bsfit_status st;
  (void)state;
  bsfit_curve_init(&c);
  assert_int_equal(bsfit_curve_new(&c, 2, 2, 9, U, P, W, 0, NULL, &st), BSFIT_OK);
  assert_int_equal(bsfit_curve_total_turning(&c, samples, &v, &st), BSFIT_OK);
  assert_float_equal(v, 2 * PI, 8 * PI / (double)samples);
  assert_int_equal(bsfit_curve_bending_energy(&c, samples, &v, &st), BSFIT_OK);
  assert_float_equal(v, 2 * PI / R, 8 * PI / (double)samples);
  /* the same circle moved by (3, 4) is 5 away at every parameter */
  {
    bsfit_curve m;
    bsfit_curve_init(&m);
    for (i = 0; i < 9; i++) {
      moved[2 * i] = P[2 * i] + 3;
      moved[2 * i + 1] = P[2 * i + 1] + 4;
    }
    assert_int_equal(bsfit_curve_new(&m, 2, 2, 9, U, moved, W, 0, NULL, &st), BSFIT_OK);
    assert_int_equal(bsfit_curve_max_deviation(&c, &m, 101, &v, &st), BSFIT_OK);
    assert_float_equal(v, 5.0, 1e-12);
    assert_int_equal(bsfit_curve_max_deviation(&c, &c, 101, &v, &st), BSFIT_OK);
    assert_float_equal(v, 0.0, 0.0);
    bsfit_curve_free(&m);
  }
  bsfit_curve_free(&c);
  /* a closed convex polygon turns by exactly 2 pi, however it is sampled */
  assert_int_equal(bsfit_curve_new_periodic(&c, 1, 2, 6, NULL, hex, NULL, NULL, &st), BSFIT_OK);
  assert_int_equal(bsfit_curve_total_turning(&c, 97, &v, &st), BSFIT_OK);
  assert_float_equal(v, 2 * PI, 1e-12);
  bsfit_curve_free(&c);
  /* a straight line does not turn */
  assert_int_equal(bsfit_curve_new(&c, 3, 2, 4, NULL, line, NULL, 0, NULL, &st), BSFIT_OK);
  assert_int_equal(bsfit_curve_total_turning(&c, 50, &v, &st), BSFIT_OK);
  assert_float_equal(v, 0.0, 1e-12);
  assert_int_equal(bsfit_curve_bending_energy(&c, 50, &v, &st), BSFIT_OK);
  assert_float_equal(v, 0.0, 1e-12);
  bsfit_curve_free(&c);
}

static void test_smoothing_reduces_oscillation(void **state) {
  /* given a circle-like closed uniform cubic whose control points carry noise */
  test_rng r = {0x5eed0008};
  const size_t N = 64, samples = 2000;
  double P[128], t0, e0, t1, e1, dev;
  bsfit_curve c, F;
  size_t i;
  int k;
  bsfit_status st;
  (void)state;
  for (i = 0; i < N; i++) {
    double ang = 2 * PI * (double)i / (double)N, rad = 1.0 + rng_range(&r, -0.08, 0.08);
    P[2 * i] = rad * cos(ang);
    P[2 * i + 1] = rad * sin(ang);
  }
  bsfit_curve_init(&c);
  bsfit_curve_init(&F);
  assert_int_equal(bsfit_curve_new_periodic(&c, 3, 2, N, NULL, P, NULL, NULL, &st), BSFIT_OK);
  assert_int_equal(bsfit_curve_total_turning(&c, samples, &t0, &st), BSFIT_OK);
  assert_int_equal(bsfit_curve_bending_energy(&c, samples, &e0, &st), BSFIT_OK);
  for (k = 2; k <= 4; k++) {
    /* when smoothed over k spans */
    assert_int_equal(bsfit_filter_box_curve(&c, k, &F, &st), BSFIT_OK);
    assert_int_equal(bsfit_curve_total_turning(&F, samples, &t1, &st), BSFIT_OK);
    assert_int_equal(bsfit_curve_bending_energy(&F, samples, &e1, &st), BSFIT_OK);
    assert_int_equal(bsfit_curve_max_deviation(&c, &F, 500, &dev, &st), BSFIT_OK);
    /* then both measures drop (a convex curve turns by 2 pi, the least possible),
    ** and the curve moved by less than the noise plus the shrinking of the circle */
    assert_true(t1 < t0);
    assert_true(e1 < e0);
    assert_true(t1 >= 2 * PI - 1e-9);
    assert_true(dev > 0 && dev < 0.2);
  }
  bsfit_curve_free(&c);
  bsfit_curve_free(&F);
}

/* }==================================================================== */

/* {====================================================================
** Surfaces
** ===================================================================== */

typedef struct raw_surface {
  int pu, pv, dim;
  size_t nu, nv;
  const double *Uu, *Uv, *P;
} raw_surface;

/* S(u, v) from the public basis functions only, independent of surface.c */
static void raw_eval(const raw_surface *s, double u, double v, double *out) {
  double Nu[8], Nv[8];
  size_t su = bsfit_knots_find_span(s->Uu, s->nu, s->pu, u);
  size_t sv = bsfit_knots_find_span(s->Uv, s->nv, s->pv, v), i, j;
  int k;
  bsfit_basis_funs(su, u, s->pu, s->Uu, Nu);
  bsfit_basis_funs(sv, v, s->pv, s->Uv, Nv);
  for (k = 0; k < s->dim; k++) out[k] = 0.0;
  for (i = 0; i <= (size_t)s->pu; i++)
    for (j = 0; j <= (size_t)s->pv; j++) {
      const double *V = s->P + ((su - (size_t)s->pu + i) * s->nv + sv - (size_t)s->pv + j) * (size_t)s->dim;
      for (k = 0; k < s->dim; k++) out[k] += Nu[i] * Nv[j] * V[k];
    }
}

static raw_surface raw_of(const bsfit_surface *s) {
  raw_surface r;
  r.pu = s->degree_u;
  r.pv = s->degree_v;
  r.dim = s->dim;
  r.nu = s->nu;
  r.nv = s->nv;
  r.Uu = s->knots_u;
  r.Uv = s->knots_v;
  r.P = s->ctrl;
  return r;
}

/* the extended surface: padded net (end rule) or clamped parameters (constants) */
typedef struct ext_surface {
  raw_surface s;
  int clamp;
} ext_surface;

static void ext_eval(const ext_surface *e, double u, double v, double *out) {
  if (e->clamp) {
    double ua = e->s.Uu[e->s.pu], ub = e->s.Uu[e->s.nu], va = e->s.Uv[e->s.pv], vb = e->s.Uv[e->s.nv];
    u = u < ua ? ua : (u > ub ? ub : u);
    v = v < va ? va : (v > vb ? vb : v);
  }
  raw_eval(&e->s, u, v, out);
}

static void pad_knots(const double *U, size_t nk, size_t K, double h, double *out) {
  size_t i;
  for (i = 0; i < nk + 2 * K; i++) {
    if (i < K) out[i] = U[0] - (double)(K - i) * h;
    else if (i < K + nk) out[i] = U[i - K];
    else out[i] = U[nk - 1] + (double)(i - K - nk + 1) * h;
  }
}

static size_t pad_index(size_t i, size_t K, size_t n) {
  return i < K ? 0 : (i - K >= n ? n - 1 : i - K);
}

/* window average over [u-du, u+du] x [v-dv, v+dv], 5x5 Gauss per knot cell */
static void surface_average(const ext_surface *e, double u, double v, double du, double dv,
                            double *out) {
  double bu[40], bv[40], y[4];
  size_t nbu = 0, nbv = 0, i, j, a, b;
  int k;
  bu[nbu++] = u - du;
  for (i = 0; i < e->s.nu + (size_t)e->s.pu + 1; i++)
    if (e->s.Uu[i] > u - du && e->s.Uu[i] < u + du) bu[nbu++] = e->s.Uu[i];
  bu[nbu++] = u + du;
  bv[nbv++] = v - dv;
  for (i = 0; i < e->s.nv + (size_t)e->s.pv + 1; i++)
    if (e->s.Uv[i] > v - dv && e->s.Uv[i] < v + dv) bv[nbv++] = e->s.Uv[i];
  bv[nbv++] = v + dv;
  for (k = 0; k < e->s.dim; k++) out[k] = 0.0;
  for (i = 0; i + 1 < nbu; i++)
    for (j = 0; j + 1 < nbv; j++) {
      double hu = 0.5 * (bu[i + 1] - bu[i]), mu = 0.5 * (bu[i + 1] + bu[i]);
      double hv = 0.5 * (bv[j + 1] - bv[j]), mv = 0.5 * (bv[j + 1] + bv[j]);
      for (a = 0; a < 5; a++)
        for (b = 0; b < 5; b++) {
          ext_eval(e, mu + hu * GL_X[a], mv + hv * GL_X[b], y);
          for (k = 0; k < e->s.dim; k++) out[k] += hu * hv * GL_W[a] * GL_W[b] * y[k];
        }
    }
  for (k = 0; k < e->s.dim; k++) out[k] /= 4.0 * du * dv;
}

static void check_surface_against_integral(const bsfit_surface *F, const ext_surface *e,
                                           double du, double dv) {
  raw_surface f = raw_of(F);
  double ua = F->knots_u[F->degree_u], ub = F->knots_u[F->nu];
  double va = F->knots_v[F->degree_v], vb = F->knots_v[F->nv], got[4], want[4];
  size_t i, j;
  int k;
  for (i = 0; i < 15; i++)
    for (j = 0; j < 15; j++) {
      double u = ua + (ub - ua) * (double)i / 14.0, v = va + (vb - va) * (double)j / 14.0;
      raw_eval(&f, u, v, got);
      surface_average(e, u, v, du, dv, want);
      for (k = 0; k < F->dim; k++) assert_float_equal(got[k], want[k], EPS_FILTER);
    }
}

static void test_surface_uniform_matches_integral(void **state) {
  test_rng r = {0x5eed0009};
  const int cases[][4] = {{1, 1, 1, 4}, {2, 3, 2, 3}, {3, 2, 5, 2}};
  size_t c;
  (void)state;
  for (c = 0; c < sizeof cases / sizeof cases[0]; c++) {
    /* given a uniform surface and its net padded by the end rule */
    int pu = cases[c][0], pv = cases[c][1], k = cases[c][2], l = cases[c][3];
    size_t nu = (size_t)pu + 7, nv = (size_t)pv + 6, K = 8, i, j;
    double Uu[32], Uv[32], P[400 * 3], Pu[64], Pv[64], *Pp;
    double hu = 1.0 / (double)(nu - (size_t)pu), hv = 1.0 / (double)(nv - (size_t)pv);
    bsfit_surface s, F;
    ext_surface e;
    bsfit_status st;
    assert_int_equal(bsfit_knots_uniform(pu, nu, 0, 1, Uu, &st), BSFIT_OK);
    assert_int_equal(bsfit_knots_uniform(pv, nv, 0, 1, Uv, &st), BSFIT_OK);
    random_points(&r, nu * nv, 3, P);
    bsfit_surface_init(&s);
    bsfit_surface_init(&F);
    assert_int_equal(bsfit_surface_new(&s, pu, pv, 3, nu, nv, Uu, Uv, P, NULL, NULL, &st), BSFIT_OK);
    pad_knots(Uu, nu + (size_t)pu + 1, K, 1.0, Pu);
    pad_knots(Uv, nv + (size_t)pv + 1, K, 1.0, Pv);
    Pp = malloc((nu + 2 * K) * (nv + 2 * K) * 3 * sizeof(double));
    assert_non_null(Pp);
    for (i = 0; i < nu + 2 * K; i++)
      for (j = 0; j < nv + 2 * K; j++)
        memcpy(Pp + (i * (nv + 2 * K) + j) * 3, P + (pad_index(i, K, nu) * nv + pad_index(j, K, nv)) * 3,
               3 * sizeof(double));
    e.clamp = 0;
    e.s.pu = pu;
    e.s.pv = pv;
    e.s.dim = 3;
    e.s.nu = nu + 2 * K;
    e.s.nv = nv + 2 * K;
    e.s.Uu = Pu;
    e.s.Uv = Pv;
    e.s.P = Pp;
    /* when filtered over a k x l window */
    assert_int_equal(bsfit_filter_box_surface(&s, k, l, &F, &st), BSFIT_OK);
    /* then degrees (pu+1, pv+1), sizes as open curves', and the window average */
    assert_int_equal(F.degree_u, pu + 1);
    assert_int_equal(F.degree_v, pv + 1);
    assert_int_equal(F.nu, nu + 2 * (size_t)pu + (size_t)k - 1);
    assert_int_equal(F.nv, nv + 2 * (size_t)pv + (size_t)l - 1);
    check_surface_against_integral(&F, &e, 0.5 * k * hu, 0.5 * l * hv);
    free(Pp);
    bsfit_surface_free(&s);
    bsfit_surface_free(&F);
  }
}

static void test_surface_exact_clamped_matches_integral(void **state) {
  /* given a clamped non-uniform surface, extended as constant beyond its edges */
  test_rng r = {0x5eed000a};
  const int pu = 2, pv = 3;
  const size_t nu = 7, nv = 8;
  double Uu[32], Uv[32], P[7 * 8 * 3], du, dv;
  bsfit_surface s, F;
  ext_surface e;
  bsfit_status st;
  (void)state;
  random_knots(&r, pu, nu, 1, Uu);
  random_knots(&r, pv, nv, 1, Uv);
  random_points(&r, nu * nv, 3, P);
  bsfit_surface_init(&s);
  bsfit_surface_init(&F);
  assert_int_equal(bsfit_surface_new(&s, pu, pv, 3, nu, nv, Uu, Uv, P, NULL, NULL, &st), BSFIT_OK);
  e.clamp = 1;
  e.s = raw_of(&s);
  du = 0.23 * (Uu[nu] - Uu[pu]);
  dv = 0.09 * (Uv[nv] - Uv[pv]);
  /* when filtered exactly */
  assert_int_equal(bsfit_filter_box_surface_delta(&s, du, dv, &F, &st), BSFIT_OK);
  /* then the window average, on [a - du, b + du] x [c - dv, d + dv] */
  assert_float_equal(F.knots_u[F.degree_u], Uu[pu] - du, EPS_KNOT);
  assert_float_equal(F.knots_v[F.nv], Uv[nv] + dv, EPS_KNOT);
  check_surface_against_integral(&F, &e, du, dv);
  bsfit_surface_free(&s);
  bsfit_surface_free(&F);
}

/* }==================================================================== */

/* {====================================================================
** Errors
** ===================================================================== */

static void test_curve_bad_input(void **state) {
  test_rng r = {0x5eed000b};
  const double W[] = {1, 2, 1, 1};
  const double P[] = {0, 0, 1, 0, 1, 1, 0, 1};
  bsfit_curve c, out, z, rat, cl;
  double v;
  bsfit_status st;
  (void)state;
  uniform_curve(&r, 2, 6, 2, &c); /* 4 domain spans */
  periodic_curve(&r, 2, 5, 2, 1, &z);
  bsfit_curve_init(&out);
  bsfit_curve_init(&rat);
  bsfit_curve_init(&cl);
  /* k < 1, k wider than the curve */
  expect_error(bsfit_filter_box_curve(&c, 0, &out, &st), BSFIT_EINVAL, &st);
  expect_error(bsfit_filter_box_curve(&c, -3, &out, &st), BSFIT_EINVAL, &st);
  expect_error(bsfit_filter_box_curve(&c, 5, &out, &st), BSFIT_EINVAL, &st);
  expect_error(bsfit_filter_box_curve(&z, 6, &out, &st), BSFIT_EINVAL, &st);
  assert_null(out.ctrl); /* untouched on error */
  /* a clamped curve is not uniform: the message points to the exact filter */
  assert_int_equal(bsfit_curve_new(&cl, 2, 2, 4, NULL, P, NULL, 0, NULL, &st), BSFIT_OK);
  assert_false(bsfit_curve_is_uniform(&cl));
  assert_true(bsfit_curve_is_uniform(&c));
  expect_error(bsfit_filter_box_curve(&cl, 1, &out, &st), BSFIT_EINVAL, &st);
  assert_non_null(strstr(st.msg, "bsfit_filter_box_curve_delta"));
  /* delta <= 0, NaN, Inf, wider than the domain (open [0,1], closed period 1) */
  expect_error(bsfit_filter_box_curve_delta(&c, 0.0, &out, &st), BSFIT_EINVAL, &st);
  expect_error(bsfit_filter_box_curve_delta(&c, -0.1, &out, &st), BSFIT_EINVAL, &st);
  expect_error(bsfit_filter_box_curve_delta(&c, NAN, &out, &st), BSFIT_ENONFINITE, &st);
  expect_error(bsfit_filter_box_curve_delta(&c, INFINITY, &out, &st), BSFIT_ENONFINITE, &st);
  expect_error(bsfit_filter_box_curve_delta(&c, 0.51, &out, &st), BSFIT_EINVAL, &st);
  expect_error(bsfit_filter_box_curve_delta(&z, 0.51, &out, &st), BSFIT_EINVAL, &st);
  /* rational curves */
  assert_int_equal(bsfit_curve_new(&rat, 2, 2, 4, NULL, P, W, 0, NULL, &st), BSFIT_OK);
  expect_error(bsfit_filter_box_curve_delta(&rat, 0.1, &out, &st), BSFIT_EINVAL, &st);
  expect_error(bsfit_filter_box_curve(&rat, 1, &out, &st), BSFIT_EINVAL, &st);
  /* NULL and empty curves, NULL output */
  expect_error(bsfit_filter_box_curve(NULL, 1, &out, &st), BSFIT_EINVAL, &st);
  expect_error(bsfit_filter_box_curve_delta(&out, 0.1, &out, &st), BSFIT_EINVAL, &st);
  expect_error(bsfit_filter_box_curve(&c, 1, NULL, &st), BSFIT_EINVAL, &st);
  expect_error(bsfit_filter_box_curve_delta(&c, 0.1, NULL, &st), BSFIT_EINVAL, &st);
  /* NaN in the control points */
  c.ctrl[3] = NAN;
  expect_error(bsfit_filter_box_curve(&c, 1, &out, &st), BSFIT_ENONFINITE, &st);
  expect_error(bsfit_filter_box_curve_delta(&c, 0.1, &out, &st), BSFIT_ENONFINITE, &st);
  c.ctrl[3] = 0.0;
  /* an unused end control point (knot of multiplicity p+1 at U_1) */
  {
    const double U[] = {0, 1, 1, 1, 2, 3, 4};
    bsfit_curve m;
    bsfit_curve_init(&m);
    assert_int_equal(bsfit_curve_new(&m, 2, 2, 4, U, P, NULL, 0, NULL, &st), BSFIT_OK);
    expect_error(bsfit_filter_box_curve_delta(&m, 0.2, &out, &st), BSFIT_EMULT, &st);
    bsfit_curve_free(&m);
  }
  /* the degree may not rise above BSFIT_MAX_DEGREE */
  {
    double Pm[2 * (BSFIT_MAX_DEGREE + 1)];
    bsfit_curve b;
    memset(Pm, 0, sizeof Pm);
    bsfit_curve_init(&b);
    assert_int_equal(bsfit_curve_new_bezier(&b, 2, BSFIT_MAX_DEGREE + 1, Pm, NULL, NULL, &st), BSFIT_OK);
    expect_error(bsfit_filter_box_curve_delta(&b, 0.1, &out, &st), BSFIT_EDEGREE, &st);
    bsfit_curve_free(&b);
  }
  /* measures: samples, dimension, NULLs, disjoint domains */
  expect_error(bsfit_curve_total_turning(&c, 2, &v, &st), BSFIT_EINVAL, &st);
  expect_error(bsfit_curve_bending_energy(&c, 2, &v, &st), BSFIT_EINVAL, &st);
  expect_error(bsfit_curve_total_turning(NULL, 10, &v, &st), BSFIT_EINVAL, &st);
  expect_error(bsfit_curve_bending_energy(&c, 10, NULL, &st), BSFIT_EINVAL, &st);
  expect_error(bsfit_curve_max_deviation(&c, &z, 1, &v, &st), BSFIT_EINVAL, &st);
  expect_error(bsfit_curve_max_deviation(&c, NULL, 10, &v, &st), BSFIT_EINVAL, &st);
  {
    const double x1[] = {0, 1, 2};
    bsfit_curve one, far;
    double U[] = {5, 5, 6, 6};
    bsfit_curve_init(&one);
    bsfit_curve_init(&far);
    assert_int_equal(bsfit_curve_new(&one, 1, 1, 3, NULL, x1, NULL, 0, NULL, &st), BSFIT_OK);
    expect_error(bsfit_curve_total_turning(&one, 10, &v, &st), BSFIT_EDIM, &st);
    expect_error(bsfit_curve_bending_energy(&one, 10, &v, &st), BSFIT_EDIM, &st);
    expect_error(bsfit_curve_max_deviation(&c, &one, 10, &v, &st), BSFIT_EDIM, &st);
    assert_int_equal(bsfit_curve_new(&far, 1, 2, 2, U, P, NULL, 0, NULL, &st), BSFIT_OK);
    expect_error(bsfit_curve_max_deviation(&c, &far, 10, &v, &st), BSFIT_EDOMAIN, &st);
    bsfit_curve_free(&one);
    bsfit_curve_free(&far);
  }
  bsfit_curve_free(&c);
  bsfit_curve_free(&z);
  bsfit_curve_free(&rat);
  bsfit_curve_free(&cl);
}

static void test_surface_bad_input(void **state) {
  test_rng r = {0x5eed000c};
  double Uu[16], Uv[16], P[6 * 5 * 3], W[30];
  bsfit_surface s, cl, rat, out;
  bsfit_status st;
  size_t i;
  (void)state;
  bsfit_knots_uniform(2, 6, 0, 1, Uu, NULL);
  bsfit_knots_uniform(1, 5, 0, 1, Uv, NULL);
  random_points(&r, 30, 3, P);
  for (i = 0; i < 30; i++) W[i] = 1.0 + (double)i;
  bsfit_surface_init(&s);
  bsfit_surface_init(&cl);
  bsfit_surface_init(&rat);
  bsfit_surface_init(&out);
  assert_int_equal(bsfit_surface_new(&s, 2, 1, 3, 6, 5, Uu, Uv, P, NULL, NULL, &st), BSFIT_OK);
  assert_int_equal(bsfit_surface_new(&cl, 2, 1, 3, 6, 5, NULL, NULL, P, NULL, NULL, &st), BSFIT_OK);
  assert_int_equal(bsfit_surface_new(&rat, 2, 1, 3, 6, 5, Uu, Uv, P, W, NULL, &st), BSFIT_OK);
  expect_error(bsfit_filter_box_surface(&s, 0, 1, &out, &st), BSFIT_EINVAL, &st);
  expect_error(bsfit_filter_box_surface(&s, 1, 0, &out, &st), BSFIT_EINVAL, &st);
  expect_error(bsfit_filter_box_surface(&s, 5, 1, &out, &st), BSFIT_EINVAL, &st);
  expect_error(bsfit_filter_box_surface(&s, 1, 5, &out, &st), BSFIT_EINVAL, &st);
  expect_error(bsfit_filter_box_surface(&cl, 1, 1, &out, &st), BSFIT_EINVAL, &st);
  expect_error(bsfit_filter_box_surface(&rat, 1, 1, &out, &st), BSFIT_EINVAL, &st);
  expect_error(bsfit_filter_box_surface(NULL, 1, 1, &out, &st), BSFIT_EINVAL, &st);
  expect_error(bsfit_filter_box_surface(&s, 1, 1, NULL, &st), BSFIT_EINVAL, &st);
  expect_error(bsfit_filter_box_surface_delta(&s, 0.0, 0.1, &out, &st), BSFIT_EINVAL, &st);
  expect_error(bsfit_filter_box_surface_delta(&s, 0.1, NAN, &out, &st), BSFIT_ENONFINITE, &st);
  expect_error(bsfit_filter_box_surface_delta(&s, 0.6, 0.1, &out, &st), BSFIT_EINVAL, &st);
  expect_error(bsfit_filter_box_surface_delta(&rat, 0.1, 0.1, &out, &st), BSFIT_EINVAL, &st);
  assert_null(out.ctrl);
  /* the exact filter takes the clamped surface the moving average refused */
  assert_int_equal(bsfit_filter_box_surface_delta(&cl, 0.1, 0.2, &out, &st), BSFIT_OK);
  assert_int_equal(out.degree_u, 3);
  assert_int_equal(out.degree_v, 2);
  bsfit_surface_free(&s);
  bsfit_surface_free(&cl);
  bsfit_surface_free(&rat);
  bsfit_surface_free(&out);
}

/* An allocator that fails from the n-th allocation on (frees always work). */
typedef struct failing {
  int left;
} failing;

static void *failing_alloc(void *ud, void *p, size_t osz, size_t nsz) {
  failing *f = ud;
  (void)osz;
  if (nsz == 0) {
    free(p);
    return NULL;
  }
  if (f->left-- <= 0) return NULL;
  return realloc(p, nsz);
}

typedef bsfit_err (*curve_filter)(const bsfit_curve *c, bsfit_curve *out, bsfit_status *st);

static bsfit_err ma3(const bsfit_curve *c, bsfit_curve *out, bsfit_status *st) {
  return bsfit_filter_box_curve(c, 3, out, st);
}

static bsfit_err exact01(const bsfit_curve *c, bsfit_curve *out, bsfit_status *st) {
  return bsfit_filter_box_curve_delta(c, 0.1, out, st);
}

/* Fails every allocation in turn: ENOMEM each time, out untouched, nothing leaked
** (the sanitizer build checks the leaks), then success. c gets its own allocator back
** at the end: the failing one points at f, which dies with this call. */
static void exhaust(bsfit_curve *c, curve_filter fn) {
  failing f;
  bsfit_allocator a, own = c->alloc;
  bsfit_curve out;
  bsfit_status st;
  int n;
  a.fn = failing_alloc;
  a.ud = &f;
  a.interrupt = NULL;
  c->alloc = a;
  bsfit_curve_init(&out);
  for (n = 0; n < 100; n++) {
    bsfit_err e;
    f.left = n;
    e = fn(c, &out, &st);
    if (e == BSFIT_OK) break;
    expect_error(e, BSFIT_ENOMEM, &st);
    assert_null(out.ctrl);
  }
  assert_true(n > 0 && n < 100);
  f.left = 1 << 30;
  bsfit_curve_free(&out); /* out was made with the failing allocator: freed while f lives */
  c->alloc = own;
}

static void test_out_of_memory(void **state) {
  test_rng r = {0x5eed000d};
  bsfit_curve c, z;
  (void)state;
  uniform_curve(&r, 3, 9, 2, &c);
  periodic_curve(&r, 2, 6, 2, 0, &z);
  exhaust(&c, ma3);
  exhaust(&c, exact01);
  exhaust(&z, exact01);
  bsfit_curve_free(&c);
  bsfit_curve_free(&z);
  periodic_curve(&r, 2, 6, 2, 1, &z);
  exhaust(&z, ma3);
  bsfit_curve_free(&z);
}

/* }==================================================================== */

int main(void) {
  const struct CMUnitTest tests[] = {
    cmocka_unit_test(test_uniform_open_matches_integral),
    cmocka_unit_test(test_uniform_closed_matches_integral),
    cmocka_unit_test(test_exact_nonuniform_open_matches_integral),
    cmocka_unit_test(test_exact_closed_matches_integral),
    cmocka_unit_test(test_exact_agrees_with_moving_average),
    cmocka_unit_test(test_k1_keeps_the_control_polygon),
    cmocka_unit_test(test_polyline_corner_is_cut),
    cmocka_unit_test(test_output_may_be_the_input),
    cmocka_unit_test(test_measures_of_known_curves),
    cmocka_unit_test(test_smoothing_reduces_oscillation),
    cmocka_unit_test(test_surface_uniform_matches_integral),
    cmocka_unit_test(test_surface_exact_clamped_matches_integral),
    cmocka_unit_test(test_curve_bad_input),
    cmocka_unit_test(test_surface_bad_input),
    cmocka_unit_test(test_out_of_memory),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
