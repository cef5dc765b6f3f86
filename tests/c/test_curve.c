/*
** test_curve.c
** Curve operations (bsfit_curve_ops.h) checked against mathematics: derivatives against
** central finite differences, batch evaluation against single evaluation, knot insertion,
** refinement, elevation, splitting and reversal against the original curve, arc length
** against exact and polyline lengths, closest points against points placed at known
** normal offsets, periodic seam continuity, and every invalid input's status code.
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
#include "testutil.h"

#define EPS_SHAPE 1e-12 /* an operation that must not change the curve */
#define NPAR 1000       /* parameters per comparison */

/* {====================================================================
** Helpers
** ===================================================================== */

/* Random curve: open (clamped or not, random knots with repeats) or periodic, 2D/3D,
** polynomial or rational. Returns 0 when the shape is not possible (skipped). */
static int random_curve(test_rng *r, bsfit_curve *c, int p, size_t n, int dim, int kind,
                        int rational) {
  double U[128], P[128 * 3], W[128], t[128];
  size_t i;
  bsfit_curve_init(c);
  for (i = 0; i < n * (size_t)dim; i++) P[i] = rng_range(r, -1.0, 1.0);
  for (i = 0; i < n; i++) W[i] = rng_range(r, 0.3, 3.0);
  if (kind == 2) { /* periodic with n distinct points */
    if (p < 1 || n < (size_t)p + 1 || n < 2) return 0;
    t[0] = rng_range(r, -1.0, 1.0);
    for (i = 1; i <= n; i++) t[i] = t[i - 1] + rng_range(r, 0.2, 1.0);
    assert_int_equal(bsfit_curve_new_periodic(c, p, dim, n, t, P, rational ? W : NULL, NULL, NULL),
                     BSFIT_OK);
    return 1;
  }
  random_knots(r, p, n, kind == 0, U);
  assert_int_equal(bsfit_curve_new(c, p, dim, n, U, P, rational ? W : NULL, 0, NULL, NULL),
                   BSFIT_OK);
  return 1;
}

/* max over NPAR+1 parameters of [lo, hi] of |f(u) - g(map(u))|, map(u) = u or lo+hi-u */
static double max_dev(const bsfit_curve *f, const bsfit_curve *g, double lo, double hi,
                      int mirrored) {
  double worst = 0.0, x[4], y[4];
  int i, k;
  for (i = 0; i <= NPAR; i++) {
    double u = lo + (hi - lo) * (double)i / NPAR, v = mirrored ? lo + (hi - u) : u;
    if (i == NPAR) u = hi;
    if (mirrored && i == NPAR) v = lo;
    assert_int_equal(bsfit_curve_eval(f, u, x, NULL), BSFIT_OK);
    assert_int_equal(bsfit_curve_eval(g, v, y, NULL), BSFIT_OK);
    for (k = 0; k < f->dim; k++) worst = fmax(worst, fabs(x[k] - y[k]));
  }
  return worst;
}

static double dom_a(const bsfit_curve *c) {
  double a, b;
  bsfit_curve_domain(c, &a, &b);
  return a;
}

static double dom_b(const bsfit_curve *c) {
  double a, b;
  bsfit_curve_domain(c, &a, &b);
  return b;
}

/* }==================================================================== */

/* {====================================================================
** Derivatives and batch evaluation
** ===================================================================== */

static void test_derivs_vs_finite_differences(void **state) {
  test_rng r = {20240601};
  int trial;
  (void)state;
  for (trial = 0; trial < 120; trial++) {
    int p = 1 + trial % 5, k, i, q, rational = trial % 4 == 3;
    size_t n = (size_t)p + 2 + (size_t)(trial % 7);
    bsfit_curve c;
    if (!random_curve(&r, &c, p, n, 2, trial % 2, rational)) continue;
    for (i = 0; i < 10; i++) {
      /* u well inside a non-empty span, h small against the span */
      size_t s;
      double lo, hi, u, h, Dm[5 * 2], Dp[5 * 2], D[5 * 2];
      do {
        s = (size_t)p + (size_t)(rng_uniform(&r) * (double)(n - (size_t)p));
      } while (s >= n || c.knots[s + 1] == c.knots[s]);
      lo = c.knots[s];
      hi = c.knots[s + 1];
      u = lo + (hi - lo) * rng_range(&r, 0.2, 0.8);
      h = 1e-5 * (hi - lo);
      assert_int_equal(bsfit_curve_derivs(&c, u, 4, D, NULL), BSFIT_OK);
      assert_int_equal(bsfit_curve_derivs(&c, u - h, 4, Dm, NULL), BSFIT_OK);
      assert_int_equal(bsfit_curve_derivs(&c, u + h, 4, Dp, NULL), BSFIT_OK);
      /* order 0 is the point itself */
      {
        double C[2];
        bsfit_curve_eval(&c, u, C, NULL);
        assert_float_equal(D[0], C[0], EPS_EXACT * 10);
        assert_float_equal(D[1], C[1], EPS_EXACT * 10);
      }
      for (k = 1; k <= 3; k++)
        for (q = 0; q < 2; q++) {
          double fd = (Dp[(k - 1) * 2 + q] - Dm[(k - 1) * 2 + q]) / (2 * h);
          double scale = 1.0 + fabs(D[k * 2 + q]) + fabs(D[(k + 1) * 2 + q]) * h;
          assert_float_equal(fd, D[k * 2 + q], EPS_FD * scale);
        }
      /* a polynomial curve's derivatives above the degree vanish */
      if (!rational)
        for (k = p + 1; k <= 4; k++) assert_float_equal(D[k * 2], 0.0, 0.0);
    }
    bsfit_curve_free(&c);
  }
}

static void test_eval_many_matches_eval(void **state) {
  test_rng r = {777};
  int trial;
  (void)state;
  for (trial = 0; trial < 40; trial++) {
    /* half the trials hit the cubic 2D/3D fast path */
    int p = trial % 2 ? 3 : 1 + trial % 5, dim = 2 + trial % 2, kind = trial % 3;
    int rational = trial % 5 == 4;
    size_t n = 12 + (size_t)trial, m = 500, i, j;
    double *u = malloc(m * sizeof(double)), *out = malloc(m * 3 * sizeof(double)), x[3];
    bsfit_curve c;
    assert_non_null(u);
    assert_non_null(out);
    if (!random_curve(&r, &c, p, n, dim, kind, rational)) continue;
    /* sorted, then shuffled; a few parameters outside the domain */
    for (i = 0; i < m; i++)
      u[i] = dom_a(&c) + (dom_b(&c) - dom_a(&c)) * ((double)i / (double)(m - 1) * 1.2 - 0.1);
    for (j = 0; j < 2; j++) {
      assert_int_equal(bsfit_curve_eval_many(&c, u, m, out, NULL), BSFIT_OK);
      for (i = 0; i < m; i++) {
        int k;
        bsfit_curve_eval(&c, u[i], x, NULL);
        for (k = 0; k < dim; k++)
          assert_float_equal(out[i * (size_t)dim + (size_t)k], x[k], 1e-12 * (1 + fabs(x[k])));
      }
      for (i = m - 1; i > 0; i--) {
        size_t jj = (size_t)(rng_uniform(&r) * (double)(i + 1));
        double t = u[i];
        u[i] = u[jj];
        u[jj] = t;
      }
    }
    free(u);
    free(out);
    bsfit_curve_free(&c);
  }
}

/* }==================================================================== */

/* {====================================================================
** Shape-preserving operations
** ===================================================================== */

static void test_insert_and_refine_preserve_curve(void **state) {
  test_rng r = {4242};
  int trial;
  (void)state;
  for (trial = 0; trial < 90; trial++) {
    int p = 1 + trial % 5, kind = trial % 3, rational = trial % 2;
    size_t n = (size_t)p + 1 + (size_t)(trial % 8), nx = 1 + (size_t)trial % 6, i;
    double X[8], a, b, u;
    bsfit_curve c, o;
    bsfit_status st;
    if (!random_curve(&r, &c, p, n, 2, kind, rational)) continue;
    bsfit_curve_init(&o);
    a = dom_a(&c);
    b = dom_b(&c);
    for (i = 0; i < nx; i++) X[i] = a + (b - a) * ((double)i + rng_uniform(&r)) / (double)nx;
    assert_int_equal(bsfit_curve_refine(&c, X, nx, &o, &st), BSFIT_OK);
    assert_int_equal(bsfit_curve_validate(&o, NULL), BSFIT_OK);
    assert_int_equal(o.n, c.n + nx);
    assert_int_equal(o.periodic, c.periodic);
    assert_true(max_dev(&c, &o, a, b, 0) < EPS_SHAPE);
    /* one knot p times (multiplicity 0 -> p is always allowed at a fresh value) */
    u = a + (b - a) * rng_range(&r, 0.1, 0.9);
    if (bsfit_knots_multiplicity(c.knots, c.n + (size_t)p + 1, u) == 0) {
      assert_int_equal(bsfit_curve_insert_knot(&c, u, p, &o, &st), BSFIT_OK);
      assert_int_equal(bsfit_knots_multiplicity(o.knots, o.n + (size_t)p + 1, u), p);
      assert_int_equal(bsfit_curve_validate(&o, NULL), BSFIT_OK);
      assert_true(max_dev(&c, &o, a, b, 0) < EPS_SHAPE);
      /* one more copy breaks the limit p */
      assert_int_equal(bsfit_curve_insert_knot(&o, u, 1, &o, &st), BSFIT_EMULT);
      assert_true(st.msg[0] != '\0');
    }
    /* in place: out == c */
    assert_int_equal(bsfit_curve_insert_knot(&c, X[0], 1, &c, NULL), BSFIT_OK);
    assert_true(max_dev(&c, &o, a, b, 0) < EPS_SHAPE);
    bsfit_curve_free(&c);
    bsfit_curve_free(&o);
  }
}

static void test_elevate_preserves_curve(void **state) {
  test_rng r = {99};
  int trial;
  (void)state;
  for (trial = 0; trial < 90; trial++) {
    int p = 1 + trial % 4, kind = trial % 3, t = 1 + trial % 3;
    size_t n = (size_t)p + 1 + (size_t)(trial % 7), i, runs = 1, nkc;
    bsfit_curve c, o;
    if (!random_curve(&r, &c, p, n, 3, kind, trial % 2)) continue;
    bsfit_curve_init(&o);
    assert_int_equal(bsfit_curve_elevate(&c, t, &o, NULL), BSFIT_OK);
    assert_int_equal(bsfit_curve_validate(&o, NULL), BSFIT_OK);
    assert_int_equal(o.degree, p + t);
    assert_int_equal(o.periodic, c.periodic);
    assert_true(max_dev(&c, &o, dom_a(&c), dom_b(&c), 0) < EPS_SHAPE);
    if (kind == 0) { /* clamped: every distinct knot gains exactly t copies */
      nkc = c.n + (size_t)p + 1;
      for (i = 1; i < nkc; i++) runs += c.knots[i] != c.knots[i - 1];
      assert_int_equal(o.n + (size_t)o.degree + 1, nkc + runs * (size_t)t);
    }
    if (kind == 2) /* periodic, distinct knots: N grows by t per knot of the period */
      assert_int_equal(bsfit_curve_distinct(&o), n * (size_t)(1 + t));
    bsfit_curve_free(&c);
    bsfit_curve_free(&o);
  }
}

static void test_split_halves_reproduce(void **state) {
  test_rng r = {31337};
  int trial;
  (void)state;
  for (trial = 0; trial < 60; trial++) {
    int p = 1 + trial % 5, kind = trial % 3;
    size_t n = (size_t)p + 1 + (size_t)(trial % 6);
    double a, b, u, C[3], L[3];
    bsfit_curve c, left, right;
    if (!random_curve(&r, &c, p, n, 2, kind, trial % 2)) continue;
    bsfit_curve_init(&left);
    bsfit_curve_init(&right);
    a = dom_a(&c);
    b = dom_b(&c);
    u = a + (b - a) * rng_range(&r, 0.05, 0.95);
    assert_int_equal(bsfit_curve_split(&c, u, &left, &right, NULL), BSFIT_OK);
    if (kind == 2) {
      /* one open curve over [u, u+T], closed at C(u), equal to c (wrapped) */
      double T = b - a, y[2];
      int i;
      assert_false(left.periodic);
      assert_null(right.ctrl);
      assert_float_equal(dom_a(&left), u, EPS_KNOT);
      assert_float_equal(dom_b(&left), u + T, EPS_KNOT);
      for (i = 0; i <= NPAR; i++) {
        double v = u + T * (double)i / NPAR;
        bsfit_curve_eval(&c, v, C, NULL);
        bsfit_curve_eval(&left, fmin(v, dom_b(&left)), y, NULL);
        assert_float_equal(C[0], y[0], EPS_SHAPE);
        assert_float_equal(C[1], y[1], EPS_SHAPE);
      }
      assert_memory_equal(left.ctrl, left.ctrl + (left.n - 1) * 2, 2 * sizeof(double));
    } else {
      assert_int_equal(bsfit_curve_validate(&left, NULL), BSFIT_OK);
      assert_int_equal(bsfit_curve_validate(&right, NULL), BSFIT_OK);
      assert_float_equal(dom_b(&left), u, 0.0);
      assert_float_equal(dom_a(&right), u, 0.0);
      assert_true(max_dev(&c, &left, a, u, 0) < EPS_SHAPE);
      assert_true(max_dev(&c, &right, u, b, 0) < EPS_SHAPE);
      /* clamped pieces interpolate their end control points: C(u) */
      bsfit_curve_eval(&c, u, C, NULL);
      memcpy(L, left.ctrl + (left.n - 1) * 2, 2 * sizeof(double));
      assert_float_equal(L[0], C[0], EPS_SHAPE);
      assert_float_equal(right.ctrl[1], C[1], EPS_SHAPE);
    }
    bsfit_curve_free(&c);
    bsfit_curve_free(&left);
    bsfit_curve_free(&right);
  }
}

static void test_reverse(void **state) {
  test_rng r = {5};
  int trial;
  (void)state;
  for (trial = 0; trial < 45; trial++) {
    int p = 1 + trial % 5, kind = trial % 3;
    size_t n = (size_t)p + 1 + (size_t)(trial % 6);
    bsfit_curve c, o;
    if (!random_curve(&r, &c, p, n, 2, kind, trial % 2)) continue;
    bsfit_curve_init(&o);
    assert_int_equal(bsfit_curve_reverse(&c, &o, NULL), BSFIT_OK);
    assert_int_equal(bsfit_curve_validate(&o, NULL), BSFIT_OK);
    assert_float_equal(dom_a(&o), dom_a(&c), 0.0);
    assert_float_equal(dom_b(&o), dom_b(&c), 0.0);
    /* reverse(t) = original(a + b - t) */
    assert_true(max_dev(&o, &c, dom_a(&c), dom_b(&c), 1) < EPS_SHAPE);
    /* twice gives back the original, in place */
    assert_int_equal(bsfit_curve_reverse(&o, &o, NULL), BSFIT_OK);
    assert_true(max_dev(&o, &c, dom_a(&c), dom_b(&c), 0) < EPS_SHAPE);
    bsfit_curve_free(&c);
    bsfit_curve_free(&o);
  }
}

/* }==================================================================== */

/* {====================================================================
** Geometry
** ===================================================================== */

static void test_length_straight_line(void **state) {
  /* control points on a line with increasing abscissa: the curve runs monotonically
  ** along the segment from P0 to Pn-1, so its length is the distance between them */
  double P[7 * 3], len, dx = 3.0, dy = -1.0, dz = 2.0, x = 0.0;
  size_t i;
  bsfit_curve c;
  (void)state;
  bsfit_curve_init(&c);
  for (i = 0; i < 7; i++) {
    P[3 * i] = 1 + dx * x;
    P[3 * i + 1] = 2 + dy * x;
    P[3 * i + 2] = -1 + dz * x;
    x += 0.1 + 0.3 * (double)(i % 3);
  }
  assert_int_equal(bsfit_curve_new(&c, 3, 3, 7, NULL, P, NULL, 0, NULL, NULL), BSFIT_OK);
  assert_int_equal(bsfit_curve_length(&c, 0.0, 1.0, &len, NULL), BSFIT_OK);
  x = sqrt((P[18] - P[0]) * (P[18] - P[0]) + (P[19] - P[1]) * (P[19] - P[1]) +
           (P[20] - P[2]) * (P[20] - P[2]));
  assert_float_equal(len, x, 1e-12 * x);
  assert_int_equal(bsfit_curve_length(&c, 0.5, 0.5, &len, NULL), BSFIT_OK);
  assert_float_equal(len, 0.0, 0.0);
  bsfit_curve_free(&c);
}

static void test_length_vs_polyline(void **state) {
  /* a dense polyline inscribed in the curve converges to its length from below with an
  ** error O(h^2): with 2^18 chords the gap is far below 1e-8 */
  test_rng r = {8};
  size_t m = (size_t)1 << 18, i;
  double *u = malloc(m * sizeof(double)), *pts = malloc(m * 2 * sizeof(double));
  double poly = 0.0, len, a, b, half1, half2;
  bsfit_curve c;
  (void)state;
  assert_non_null(u);
  assert_non_null(pts);
  random_curve(&r, &c, 3, 10, 2, 1, 1);
  a = dom_a(&c);
  b = dom_b(&c);
  for (i = 0; i < m; i++) u[i] = a + (b - a) * (double)i / (double)(m - 1);
  u[m - 1] = b;
  assert_int_equal(bsfit_curve_eval_many(&c, u, m, pts, NULL), BSFIT_OK);
  for (i = 1; i < m; i++)
    poly += hypot(pts[2 * i] - pts[2 * i - 2], pts[2 * i + 1] - pts[2 * i - 1]);
  assert_int_equal(bsfit_curve_length(&c, a, b, &len, NULL), BSFIT_OK);
  assert_true(len >= poly);
  assert_float_equal(len, poly, 1e-8 * len);
  /* additivity over a cut inside a span */
  assert_int_equal(bsfit_curve_length(&c, a, 0.3 * a + 0.7 * b, &half1, NULL), BSFIT_OK);
  assert_int_equal(bsfit_curve_length(&c, 0.3 * a + 0.7 * b, b, &half2, NULL), BSFIT_OK);
  assert_float_equal(half1 + half2, len, 1e-12 * len);
  free(u);
  free(pts);
  bsfit_curve_free(&c);
}

static void test_closest_known_offsets(void **state) {
  /* a gently curved cubic: points at distance delta along the normal of C(u0), delta
  ** below the radius of curvature, have C(u0) as their foot */
  double P[8 * 2];
  size_t i;
  int trial;
  test_rng r = {2718};
  bsfit_curve c;
  (void)state;
  bsfit_curve_init(&c);
  for (i = 0; i < 8; i++) {
    double th = 0.25 * (double)i;
    P[2 * i] = 10.0 * cos(th);
    P[2 * i + 1] = 8.0 * sin(th);
  }
  assert_int_equal(bsfit_curve_new(&c, 3, 2, 8, NULL, P, NULL, 0, NULL, NULL), BSFIT_OK);
  for (trial = 0; trial < 50; trial++) {
    double u0 = rng_range(&r, 0.05, 0.95), D[3 * 2], nrm[2], Q[2], u, dist, delta, sp;
    double ustart, dd;
    bsfit_curve_derivs(&c, u0, 1, D, NULL);
    sp = hypot(D[2], D[3]);
    nrm[0] = -D[3] / sp;
    nrm[1] = D[2] / sp;
    delta = rng_range(&r, -1.0, 1.0);
    Q[0] = D[0] + delta * nrm[0];
    Q[1] = D[1] + delta * nrm[1];
    assert_int_equal(bsfit_curve_closest(&c, Q, &u, &dist, NULL, NULL), BSFIT_OK);
    assert_float_equal(u, u0, 1e-9);
    assert_float_equal(dist, fabs(delta), 1e-12);
    /* the vectorised projection from a nearby start */
    ustart = u0 + rng_range(&r, -0.02, 0.02);
    assert_int_equal(bsfit_curve_project_many(&c, Q, 1, &ustart, &dd, 20, NULL, NULL), BSFIT_OK);
    assert_float_equal(ustart, u0, 1e-9);
    assert_float_equal(dd, fabs(delta), 1e-12);
  }
  /* on the end tangent, beyond the end: the foot is the end point (clamped), at the
  ** distance travelled along the tangent */
  {
    double D[2 * 2], Q[2], u, dist, sp;
    bsfit_curve_derivs(&c, 1.0, 1, D, NULL);
    sp = hypot(D[2], D[3]);
    Q[0] = D[0] + D[2] / sp;
    Q[1] = D[1] + D[3] / sp;
    assert_int_equal(bsfit_curve_closest(&c, Q, &u, &dist, NULL, NULL), BSFIT_OK);
    assert_float_equal(u, 1.0, 0.0);
    assert_float_equal(dist, 1.0, 1e-12);
  }
  bsfit_curve_free(&c);
}

static void test_sample(void **state) {
  test_rng r = {1};
  double out[5 * 2], x[2], a, b;
  size_t i;
  bsfit_curve c;
  (void)state;
  random_curve(&r, &c, 3, 6, 2, 2, 0); /* periodic: k points over [a, b) */
  a = dom_a(&c);
  b = dom_b(&c);
  assert_int_equal(bsfit_curve_sample(&c, 5, out, NULL, NULL), BSFIT_OK);
  for (i = 0; i < 5; i++) {
    bsfit_curve_eval(&c, a + (b - a) * (double)i / 5.0, x, NULL);
    assert_float_equal(out[2 * i], x[0], 1e-14);
  }
  bsfit_curve_free(&c);
  random_curve(&r, &c, 2, 6, 2, 1, 0); /* open: both ends included */
  assert_int_equal(bsfit_curve_sample(&c, 5, out, NULL, NULL), BSFIT_OK);
  bsfit_curve_eval(&c, dom_b(&c), x, NULL);
  assert_float_equal(out[8], x[0], 0.0);
  assert_float_equal(out[9], x[1], 0.0);
  bsfit_curve_free(&c);
}

/* }==================================================================== */

/* {====================================================================
** Periodic curves
** ===================================================================== */

/* Derivatives of orders 0..top from the right at a equal those from the left at b:
** the left side is read from the same arrays taken as an open curve. */
static void assert_seam_continuous(const bsfit_curve *c, int top) {
  bsfit_curve open;
  double Dl[(BSFIT_MAX_DEGREE + 1) * 3], Dr[(BSFIT_MAX_DEGREE + 1) * 3];
  int k, q, p = c->degree;
  bsfit_curve_init(&open);
  assert_int_equal(bsfit_curve_new(&open, p, c->dim, c->n, c->knots, c->ctrl, c->weights, 0, NULL,
                                   NULL),
                   BSFIT_OK);
  assert_int_equal(bsfit_curve_derivs(&open, dom_a(c), top, Dr, NULL), BSFIT_OK);
  assert_int_equal(bsfit_curve_derivs(&open, dom_b(c), top, Dl, NULL), BSFIT_OK);
  for (k = 0; k <= top; k++)
    for (q = 0; q < c->dim; q++) {
      double v = Dr[k * c->dim + q];
      assert_float_equal(Dl[k * c->dim + q], v, 1e-9 * (1.0 + fabs(v)));
    }
  bsfit_curve_free(&open);
}

static void test_periodic_seam_kept_by_operations(void **state) {
  test_rng r = {606};
  int trial;
  (void)state;
  for (trial = 0; trial < 30; trial++) {
    int p = 1 + trial % 4;
    size_t N = (size_t)p + 1 + (size_t)(trial % 5);
    double X[2];
    bsfit_curve c, o;
    random_curve(&r, &c, p, N, 2, 2, trial % 2);
    bsfit_curve_init(&o);
    assert_seam_continuous(&c, p - 1); /* C^{p-1}: simple knots */
    X[0] = dom_a(&c) + 0.3 * (dom_b(&c) - dom_a(&c));
    X[1] = dom_b(&c); /* the seam itself (multiplicity 1), wrapped to a */
    assert_int_equal(bsfit_curve_refine(&c, X, p >= 2 ? 2 : 1, &o, NULL), BSFIT_OK);
    assert_true(o.periodic);
    assert_int_equal(bsfit_curve_distinct(&o), N + (p >= 2 ? 2 : 1));
    assert_seam_continuous(&o, p - 1); /* the same curve: still C^{p-1} */
    assert_int_equal(bsfit_curve_elevate(&c, 1, &o, NULL), BSFIT_OK);
    assert_true(o.periodic);
    assert_int_equal(o.degree, p + 1);
    assert_seam_continuous(&o, p - 1); /* the same curve: C^{p-1}, not C^p */
    bsfit_curve_free(&c);
    bsfit_curve_free(&o);
  }
}

/* }==================================================================== */

/* {====================================================================
** Invalid input
** ===================================================================== */

#define EXPECT(call, want)                      \
  do {                                          \
    memset(&st, 0, sizeof st);                  \
    assert_int_equal((call), (want));           \
    assert_int_equal(st.code, (want));          \
    assert_true(strlen(st.msg) > 0);            \
  } while (0)

static void test_invalid_inputs(void **state) {
  test_rng r = {3};
  bsfit_curve c, empty, o, o2;
  bsfit_status st;
  double out[64], u = 0.5, len, X[3] = {0.7, 0.2, 0.9}, nan = NAN, P[2] = {0, 0}, b;
  (void)state;
  bsfit_curve_init(&empty);
  bsfit_curve_init(&o);
  bsfit_curve_init(&o2);
  random_curve(&r, &c, 3, 8, 2, 0, 0); /* clamped, domain [0, b] with b > 1 */
  b = dom_b(&c);
  EXPECT(bsfit_curve_derivs(NULL, 0.5, 1, out, &st), BSFIT_EINVAL);
  EXPECT(bsfit_curve_derivs(&empty, 0.5, 1, out, &st), BSFIT_EINVAL);
  EXPECT(bsfit_curve_derivs(&c, 0.5, -1, out, &st), BSFIT_EINVAL);
  EXPECT(bsfit_curve_derivs(&c, nan, 1, out, &st), BSFIT_ENONFINITE);
  EXPECT(bsfit_curve_eval_many(&c, &nan, 1, out, &st), BSFIT_ENONFINITE);
  EXPECT(bsfit_curve_eval_many(&c, NULL, 3, out, &st), BSFIT_EINVAL);
  EXPECT(bsfit_curve_insert_knot(&c, b + 0.5, 1, &o, &st), BSFIT_EDOMAIN);
  EXPECT(bsfit_curve_insert_knot(&c, nan, 1, &o, &st), BSFIT_ENONFINITE);
  EXPECT(bsfit_curve_insert_knot(&c, 0.5, -1, &o, &st), BSFIT_EINVAL);
  EXPECT(bsfit_curve_insert_knot(&c, 0.5, 4, &o, &st), BSFIT_EMULT);
  EXPECT(bsfit_curve_insert_knot(&c, 0.0, 1, &o, &st), BSFIT_EMULT); /* clamped end: p+1 */
  EXPECT(bsfit_curve_insert_knot(&empty, 0.5, 1, &o, &st), BSFIT_EINVAL);
  EXPECT(bsfit_curve_refine(&c, X, 3, &o, &st), BSFIT_EKNOTS_DECR);
  EXPECT(bsfit_curve_refine(&c, NULL, 3, &o, &st), BSFIT_EINVAL);
  X[1] = nan;
  EXPECT(bsfit_curve_refine(&c, X, 2, &o, &st), BSFIT_ENONFINITE);
  X[0] = -0.1;
  EXPECT(bsfit_curve_refine(&c, X, 1, &o, &st), BSFIT_EDOMAIN);
  EXPECT(bsfit_curve_split(&c, 0.0, &o, &o2, &st), BSFIT_EDOMAIN);
  EXPECT(bsfit_curve_split(&c, b, &o, &o2, &st), BSFIT_EDOMAIN);
  EXPECT(bsfit_curve_split(&c, nan, &o, &o2, &st), BSFIT_ENONFINITE);
  EXPECT(bsfit_curve_split(&c, 0.5, &o, &o, &st), BSFIT_EINVAL);
  EXPECT(bsfit_curve_split(&c, 0.5, &o, NULL, &st), BSFIT_EINVAL);
  EXPECT(bsfit_curve_reverse(&empty, &o, &st), BSFIT_EINVAL);
  EXPECT(bsfit_curve_elevate(&c, -1, &o, &st), BSFIT_EINVAL);
  EXPECT(bsfit_curve_elevate(&c, BSFIT_MAX_DEGREE, &o, &st), BSFIT_EDEGREE);
  EXPECT(bsfit_curve_length(&c, 0.6, 0.4, &len, &st), BSFIT_EDOMAIN);
  EXPECT(bsfit_curve_length(&c, -0.1, 0.4, &len, &st), BSFIT_EDOMAIN);
  EXPECT(bsfit_curve_length(&c, 0.1, nan, &len, &st), BSFIT_ENONFINITE);
  EXPECT(bsfit_curve_length(&c, 0.1, b + 1.0, &len, &st), BSFIT_EDOMAIN);
  EXPECT(bsfit_curve_length(&c, 0.1, 0.2, NULL, &st), BSFIT_EINVAL);
  P[1] = nan;
  EXPECT(bsfit_curve_closest(&c, P, &u, NULL, NULL, &st), BSFIT_ENONFINITE);
  EXPECT(bsfit_curve_closest(&c, NULL, &u, NULL, NULL, &st), BSFIT_EINVAL);
  EXPECT(bsfit_curve_project_many(&c, P, 1, &u, NULL, 5, NULL, &st), BSFIT_ENONFINITE);
  P[1] = 0.0;
  EXPECT(bsfit_curve_project_many(&c, P, 1, &u, NULL, -1, NULL, &st), BSFIT_EINVAL);
  EXPECT(bsfit_curve_project_many(&c, P, 1, &nan, NULL, 5, NULL, &st), BSFIT_ENONFINITE);
  EXPECT(bsfit_curve_sample(&c, 1, out, NULL, &st), BSFIT_EINVAL);
  EXPECT(bsfit_curve_sample(&empty, 3, out, NULL, &st), BSFIT_EINVAL);
  /* a discontinuous curve (interior knot of multiplicity p+1) cannot be elevated */
  {
    double U[] = {0, 0, 0, 0.5, 0.5, 0.5, 1, 1, 1}, Q[12] = {0};
    bsfit_curve d;
    bsfit_curve_init(&d);
    assert_int_equal(bsfit_curve_new(&d, 2, 2, 6, U, Q, NULL, 0, NULL, NULL), BSFIT_OK);
    EXPECT(bsfit_curve_elevate(&d, 1, &o, &st), BSFIT_EMULT);
    bsfit_curve_free(&d);
  }
  /* errors leave the output untouched */
  assert_null(o.ctrl);
  bsfit_curve_free(&c);
}

/* }==================================================================== */

static void test_project_many_batch_finds_feet(void **state) {
  /* given random cubic curves (open, periodic) and points put at a known distance along
  ** the normal of known feet, when all are projected in one call from nearby starts (the
  ** per-span polynomial path), then the feet and distances are recovered */
  test_rng r = {31415};
  int kind;
  (void)state;
  for (kind = 0; kind <= 2; kind += 2) { /* clamped, periodic */
    bsfit_curve c;
    double Q[40 * 2], u[40], u0[40], dd[40], a, b;
    size_t i;
    if (!random_curve(&r, &c, 3, 9, 2, kind, 0)) continue;
    bsfit_curve_domain(&c, &a, &b);
    for (i = 0; i < 40; i++) {
      double D[3 * 2], k[1], sp, nx, ny, delta, x = a + (b - a) * (0.05 + 0.9 * (double)i / 40.0);
      bsfit_curve_derivs(&c, x, 2, D, NULL);
      sp = hypot(D[2], D[3]);
      nx = -D[3] / sp, ny = D[2] / sp;
      /* stay inside the radius of curvature, so the foot is the nearest point locally */
      k[0] = fabs(D[2] * D[5] - D[3] * D[4]) / (sp * sp * sp);
      delta = rng_range(&r, -0.3, 0.3) / (1.0 + k[0]);
      Q[2 * i] = D[0] + delta * nx;
      Q[2 * i + 1] = D[1] + delta * ny;
      u0[i] = x;
      u[i] = x + rng_range(&r, -0.002, 0.002) * (b - a);
      dd[i] = fabs(delta);
    }
    {
      double got[40];
      assert_int_equal(bsfit_curve_project_many(&c, Q, 40, u, got, 30, NULL, NULL), BSFIT_OK);
      for (i = 0; i < 40; i++) {
        assert_float_equal(u[i], u0[i], 1e-8 * (b - a));
        assert_float_equal(got[i], dd[i], 1e-11);
      }
    }
    bsfit_curve_free(&c);
  }
}

static void test_closest_beside_a_corner(void **state) {
  /* given a cubic with a triple knot that is exactly an L (corner at (0,0), u = 0.5),
  ** when points lie on one leg near the corner (the corner is their nearest sample and
  ** the one-sided derivative there points along the other leg), then the closest point
  ** is still found on their own leg: distance to the leg, not to the corner */
  double U[] = {0, 0, 0, 0, 0.5, 0.5, 0.5, 1, 1, 1, 1};
  double P[] = {0, 1, 0, 2.0 / 3, 0, 1.0 / 3, 0, 0, 1.0 / 3, 0, 2.0 / 3, 0, 1, 0};
  double Q[] = {1e-4, 0.03, 0.03, -2e-4, -5e-4, 0.05, 0.06, 3e-4};
  double want[] = {1e-4, 2e-4, 5e-4, 3e-4}, u[4], d[4];
  bsfit_curve c;
  size_t i;
  (void)state;
  bsfit_curve_init(&c);
  assert_int_equal(bsfit_curve_new(&c, 3, 2, 7, U, P, NULL, 0, NULL, NULL), BSFIT_OK);
  for (i = 0; i < 4; i++) {
    double ui, di;
    assert_int_equal(bsfit_curve_closest(&c, Q + 2 * i, &ui, &di, NULL, NULL), BSFIT_OK);
    assert_float_equal(di, want[i], 1e-12);
  }
  assert_int_equal(bsfit_curve_closest_many(&c, Q, 4, u, d, NULL, NULL), BSFIT_OK);
  for (i = 0; i < 4; i++) assert_float_equal(d[i], want[i], 1e-12);
  bsfit_curve_free(&c);
}

static void test_closest_many_equals_closest(void **state) {
  /* given random curves of every kind and points scattered around them, when the
  ** closest points are found one by one and all at once, then they agree */
  test_rng r = {2718};
  int kind, rational;
  (void)state;
  for (kind = 0; kind <= 2; kind++)
    for (rational = 0; rational <= 1; rational++) {
      bsfit_curve c;
      double pts[60 * 3], u[60], d[60], ui, di;
      size_t i, n = 7;
      int dim = 2 + rational;
      if (!random_curve(&r, &c, 3, n, dim, kind, rational)) continue;
      for (i = 0; i < 60 * (size_t)dim; i++) pts[i] = rng_range(&r, -1.5, 1.5);
      assert_int_equal(bsfit_curve_closest_many(&c, pts, 60, u, d, NULL, NULL), BSFIT_OK);
      for (i = 0; i < 60; i++) {
        assert_int_equal(bsfit_curve_closest(&c, pts + i * (size_t)dim, &ui, &di, NULL, NULL), BSFIT_OK);
        assert_float_equal(d[i], di, 1e-12);
      }
      pts[1] = NAN;
      assert_int_equal(bsfit_curve_closest_many(&c, pts, 60, u, d, NULL, NULL), BSFIT_ENONFINITE);
      assert_int_equal(bsfit_curve_closest_many(&c, NULL, 60, u, d, NULL, NULL), BSFIT_EINVAL);
      bsfit_curve_free(&c);
    }
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_derivs_vs_finite_differences),
      cmocka_unit_test(test_eval_many_matches_eval),
      cmocka_unit_test(test_insert_and_refine_preserve_curve),
      cmocka_unit_test(test_elevate_preserves_curve),
      cmocka_unit_test(test_split_halves_reproduce),
      cmocka_unit_test(test_reverse),
      cmocka_unit_test(test_length_straight_line),
      cmocka_unit_test(test_length_vs_polyline),
      cmocka_unit_test(test_closest_known_offsets),
      cmocka_unit_test(test_sample),
      cmocka_unit_test(test_periodic_seam_kept_by_operations),
      cmocka_unit_test(test_invalid_inputs),
      cmocka_unit_test(test_closest_many_equals_closest),
      cmocka_unit_test(test_closest_beside_a_corner),
      cmocka_unit_test(test_project_many_batch_finds_feet),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
