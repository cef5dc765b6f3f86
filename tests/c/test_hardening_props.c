/*
** test_hardening_props.c
** Property tests of every curve operation over random valid curves: degrees 1-7, open
** (clamped or not) and closed, polynomial and rational, knots clustered down to 1e-15,
** coordinates from 1e-98 to 1e99. The contract (docs/robustness-core.md): an operation
** that answers OK returns a curve that passes bsfit_curve_validate and whose numbers are
** finite, and which is mathematically right where a reference exists (the independent
** evaluator of hardening.h: insertion, refinement, elevation, splitting and reversal
** keep the curve; sampling, length and closest points agree with it); otherwise it
** answers with an error code, never a crash.
*/
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>
#include <float.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "bsfit.h"
#include "hardening.h"

#define NCURVES 350 /* random curves per run */
#define NPAR 64     /* parameters compared per operation */

/* {====================================================================
** Random curves
** ===================================================================== */

typedef struct gen {
  test_rng r;
  double U[128], P[512], W[128];
} gen;

/* A random valid curve into c (kind from the counter i, the rest random). */
static void random_curve(gen *g, int i, bsfit_curve *c) {
  int p = 1 + i % 7, periodic = (i / 7) % 3 == 2, rational = (i / 21) % 2, clamped = (i / 42) % 2;
  double scale = pow(10.0, rng_range(&g->r, -98.0, 99.0));
  size_t N = (size_t)p + 1 + (size_t)(rng_uniform(&g->r) * 10), n, k;
  bsfit_status st;
  bsfit_err e;
  n = periodic ? N : N + 1;
  for (k = 0; k < (n + (size_t)p) * 4; k++) g->P[k] = scale * rng_range(&g->r, -1.0, 1.0);
  for (k = 0; k < n + (size_t)p; k++)
    g->W[k] = (i / 84) % 2 ? pow(10.0, rng_range(&g->r, -3.0, 3.0)) : rng_range(&g->r, 0.2, 5.0);
  bsfit_curve_init(c);
  if (periodic) {
    /* period knots with clusters, multiplicity <= p inside; drawn again while the seam
    ** (the runs at both ends together) passes p, which the library refuses */
    do {
      clustered_knots(&g->r, p, N - (size_t)p, 0, p, g->U);
      e = bsfit_curve_new_periodic(c, p, 2, N, g->U, g->P, rational ? g->W : NULL, NULL, &st);
    } while (e == BSFIT_EMULT);
  } else {
    clustered_knots(&g->r, p, n, clamped, p, g->U);
    e = bsfit_curve_new(c, p, 2, n, g->U, g->P, rational ? g->W : NULL, 0, NULL, &st);
  }
  if (e != BSFIT_OK) fail_msg("generator: curve %d refused: %s", i, st.msg);
}

/* Tolerance of a comparison of two evaluations of the curve: relative to its control
** points, and to how much rounding of the knots moves it (eps |U| / the smallest span). */
static double curve_tol(const bsfit_curve *c, double rel) {
  size_t i, nk = c->n + (size_t)c->degree + 1;
  double umax = 0.0, hmin = HUGE_VAL, wr = 1.0;
  for (i = 0; i < nk; i++) umax = fmax(umax, fabs(c->knots[i]));
  for (i = (size_t)c->degree; i < c->n; i++)
    if (c->knots[i + 1] > c->knots[i]) hmin = fmin(hmin, c->knots[i + 1] - c->knots[i]);
  if (c->weights) {
    double lo = HUGE_VAL, hi = 0.0;
    for (i = 0; i < c->n; i++) {
      lo = fmin(lo, c->weights[i]);
      hi = fmax(hi, c->weights[i]);
    }
    wr = hi / lo;
  }
  return ctrl_scale(c) * wr * (rel + 64.0 * DBL_EPSILON * umax / hmin);
}

/* parameters spread over the domain, and u_i at random */
static double param_at(const bsfit_curve *c, test_rng *r, int i) {
  double a, b;
  bsfit_curve_domain(c, &a, &b);
  if (i % 2) return a + (b - a) * rng_uniform(r);
  return a + (b - a) * (double)i / (double)(NPAR - 1);
}

/* c and d agree at NPAR parameters of c's domain (d evaluated at map(u)) */
static void expect_same(const bsfit_curve *c, const bsfit_curve *d, test_rng *r, double rel,
                        const char *op, int curve) {
  double tol = curve_tol(c, rel);
  int i;
  for (i = 0; i < NPAR; i++) {
    double u = param_at(c, r, i), y1[2], y2[2];
    ref_eval(c, u, y1);
    ref_eval(d, u, y2);
    if (!(pt_dist(y1, y2, 2) <= tol))
      fail_msg("%s, curve %d (p=%d n=%zu%s%s): at u=%.17g off by %g (tol %g)", op, curve, c->degree,
               c->n, c->periodic ? " periodic" : "", c->weights ? " rational" : "", u,
               pt_dist(y1, y2, 2), tol);
  }
}

/* OK => sound; not OK => an error code with a message */
static int check_result(bsfit_err e, const bsfit_status *st, const bsfit_curve *d, const char *op,
                        int curve) {
  if (e != BSFIT_OK) {
    if (!(e < 0 && strlen(st->msg) > 0)) fail_msg("%s, curve %d: error without message", op, curve);
    return 0;
  }
  if (!curve_sound(d)) fail_msg("%s, curve %d: OK with an invalid or non-finite curve", op, curve);
  return 1;
}

/* }==================================================================== */

/* {====================================================================
** Operations that keep the curve
** ===================================================================== */

/* Given random curves, when a knot is inserted 1..p times, several knots refined in,
** the degree raised by 1..(7-p), the curve reversed or split, then OK results are sound
** and trace the same curve (to 1e-12 of the control points, 1e-10 when rational). */
static void test_shape_preserving_ops(void **state) {
  gen g;
  int i, counts[5] = {0, 0, 0, 0, 0};
  (void)state;
  memset(&g, 0, sizeof g);
  g.r.s = 0x6a11u;
  for (i = 0; i < NCURVES; i++) {
    bsfit_curve c, d, l, rr;
    bsfit_status st;
    double rel, a, b, X[8];
    int t, k;
    size_t nx;
    random_curve(&g, i, &c);
    rel = c.weights ? 1e-10 : 1e-12;
    bsfit_curve_init(&d);
    bsfit_curve_init(&l);
    bsfit_curve_init(&rr);
    bsfit_curve_domain(&c, &a, &b);
    /* insertion */
    k = 1 + (int)(rng_uniform(&g.r) * c.degree);
    if (check_result(bsfit_curve_insert_knot(&c, a + (b - a) * rng_uniform(&g.r), k, &d, &st), &st,
                     &d, "insert", i)) {
      expect_same(&c, &d, &g.r, rel, "insert", i);
      counts[0]++;
    }
    /* refinement */
    for (nx = 0; nx < 5; nx++) X[nx] = a + (b - a) * rng_uniform(&g.r);
    for (nx = 1; nx < 5; nx++) /* sort */
      for (k = (int)nx; k > 0 && X[k] < X[k - 1]; k--) {
        double tmp = X[k];
        X[k] = X[k - 1];
        X[k - 1] = tmp;
      }
    if (check_result(bsfit_curve_refine(&c, X, 5, &d, &st), &st, &d, "refine", i)) {
      expect_same(&c, &d, &g.r, rel, "refine", i);
      counts[1]++;
    }
    /* elevation */
    for (t = 1; t + c.degree <= 7; t++)
      if (check_result(bsfit_curve_elevate(&c, t, &d, &st), &st, &d, "elevate", i)) {
        expect_same(&c, &d, &g.r, rel, "elevate", i);
        counts[2]++;
      } else {
        fail_msg("elevate by %d, curve %d: %s", t, i, st.msg); /* every valid curve elevates */
      }
    /* reversal: C_r(a + b - u) = C(u), a + b - u taken from the nearer end */
    if (check_result(bsfit_curve_reverse(&c, &d, &st), &st, &d, "reverse", i)) {
      double tol = curve_tol(&c, rel);
      for (k = 0; k < NPAR; k++) {
        double u = param_at(&c, &g.r, k), y1[2], y2[2];
        ref_eval(&c, u, y1);
        ref_eval(&d, u - a <= b - u ? b - (u - a) : a + (b - u), y2);
        if (!(pt_dist(y1, y2, 2) <= tol)) fail_msg("reverse, curve %d: off at u=%g", i, u);
      }
      counts[3]++;
    }
    /* splitting */
    {
      double u = a + (b - a) * rng_range(&g.r, 0.05, 0.95);
      if (check_result(bsfit_curve_split(&c, u, &l, &rr, &st), &st, &l, "split", i)) {
        double tol = curve_tol(&c, rel), y1[2], y2[2], la, lb;
        bsfit_curve_domain(&l, &la, &lb);
        for (k = 0; k < NPAR; k++) {
          double v = la + (lb - la) * (double)k / (NPAR - 1);
          ref_eval(&c, v, y1);
          ref_eval(&l, v, y2);
          if (!(pt_dist(y1, y2, 2) <= tol)) fail_msg("split, curve %d: off at u=%g", i, v);
        }
        if (!c.periodic) assert_true(curve_sound(&rr));
        counts[4]++;
      }
    }
    bsfit_curve_free(&c);
    bsfit_curve_free(&d);
    bsfit_curve_free(&l);
    bsfit_curve_free(&rr);
  }
  for (i = 0; i < 5; i++)
    if (counts[i] < NCURVES / 2) fail_msg("operation %d answered OK only %d times", i, counts[i]);
}

/* The issue's cases: a cubic with a knot at 1e-12 and a quintic with a knot at 1e-8,
** polynomial and rational, elevated by 1..2: the same curve, positive weights. */
static void test_elevate_issue_cases(void **state) {
  int p;
  (void)state;
  for (p = 3; p <= 5; p += 2) {
    double tiny = p == 3 ? 1e-12 : 1e-8, U[32], P[32], W[16];
    size_t n = (size_t)p + 3, i;
    int rational, t;
    for (i = 0; i <= (size_t)p; i++) {
      U[i] = 0.0;
      U[n + i] = 1.0;
    }
    U[p + 1] = tiny;
    U[p + 2] = 0.5;
    for (i = 0; i < n; i++) {
      P[2 * i] = (double)i;
      P[2 * i + 1] = (double)(i % 3);
      W[i] = 1.0 + (double)(i % 2) * 3.0;
    }
    for (rational = 0; rational <= 1; rational++)
      for (t = 1; t <= 2; t++) {
        bsfit_curve c, d;
        bsfit_status st;
        test_rng r = {1};
        bsfit_curve_init(&c);
        bsfit_curve_init(&d);
        assert_int_equal(bsfit_curve_new(&c, p, 2, n, U, P, rational ? W : NULL, 0, NULL, &st), 0);
        assert_int_equal(bsfit_curve_elevate(&c, t, &d, &st), BSFIT_OK);
        assert_true(curve_sound(&d));
        expect_same(&c, &d, &r, 1e-12, "elevate (issue case)", p);
        bsfit_curve_free(&c);
        bsfit_curve_free(&d);
      }
  }
}

/* Periodic curves whose knots sit far from zero (a scanner's time stamps, a CAD file's
** absolute positions): elevating or inserting must give the curve it gives at the
** origin. Spans are multiples of 1/64, so the shifted knots are exact and the shifted
** curve is the same curve; the rebuilt period once matched its knots at the wrong offset
** (a tolerance of 1e-10 of the knots' magnitude, 86 at 4.3e11 > the spans of 3) and came
** back 62% off (fuzz input tests/fuzz/regressions/curve/item6-...-3-moves). */
static void test_periodic_far_knots(void **state) {
  test_rng r = {7};
  int trial;
  (void)state;
  for (trial = 0; trial < 120; trial++) {
    int p = 1 + trial % 5, op = (trial / 5) % 2, rational = (trial / 10) % 2;
    double offset = trial < 12 ? 0.0 : pow(10.0, (double)(trial % 13)) * 4.3, U[32], V[32];
    double P[64], W[32];
    size_t N = (size_t)p + 2 + (size_t)(rng_uniform(&r) * 6), i;
    bsfit_curve c, c0, d, d0;
    bsfit_status st;
    U[0] = 0.0;
    for (i = 1; i <= N; i++) U[i] = U[i - 1] + (double)(1 + (int)(rng_uniform(&r) * 256)) / 64.0;
    for (i = 0; i <= N; i++) V[i] = U[i] + offset;
    for (i = 0; i < 2 * N; i++) P[i] = rng_range(&r, -100.0, 100.0);
    for (i = 0; i < N; i++) W[i] = rng_range(&r, 0.5, 2.0);
    bsfit_curve_init(&c);
    bsfit_curve_init(&c0);
    bsfit_curve_init(&d);
    bsfit_curve_init(&d0);
    assert_int_equal(bsfit_curve_new_periodic(&c0, p, 2, N, U, P, rational ? W : NULL, NULL, &st), 0);
    assert_int_equal(bsfit_curve_new_periodic(&c, p, 2, N, V, P, rational ? W : NULL, NULL, &st), 0);
    if (op == 0) {
      int t = 1 + trial % 3;
      assert_int_equal(bsfit_curve_elevate(&c0, t, &d0, &st), BSFIT_OK);
      assert_int_equal(bsfit_curve_elevate(&c, t, &d, &st), BSFIT_OK);
    } else {
      double u = U[1] + (U[2] - U[1]) * 0.25; /* a multiple of 1/256: exact when shifted */
      assert_int_equal(bsfit_curve_insert_knot(&c0, u, 1, &d0, &st), BSFIT_OK);
      assert_int_equal(bsfit_curve_insert_knot(&c, u + offset, 1, &d, &st), BSFIT_OK);
    }
    assert_true(curve_sound(&d));
    for (i = 0; i <= 64; i++) {
      /* a multiple of 1/64, so that u + offset is exact too */
      double u = floor((U[N] - U[0]) * (double)i) / 64.0, x[2], y[2];
      assert_int_equal(bsfit_curve_eval(&d0, u, x, NULL), BSFIT_OK);
      assert_int_equal(bsfit_curve_eval(&d, u + offset, y, NULL), BSFIT_OK);
      if (pt_dist(x, y, 2) > 1e-9 * 100.0)
        fail_msg("trial %d (degree %d, %s, offset %g): %g apart at u = %g", trial, p,
                 op ? "insert" : "elevate", offset, pt_dist(x, y, 2), u);
    }
    bsfit_curve_free(&c);
    bsfit_curve_free(&c0);
    bsfit_curve_free(&d);
    bsfit_curve_free(&d0);
  }
}

/* A periodic knot vector whose spans do not repeat is refused even far from zero: the
** validator's tolerance is a few ulps of the knots' magnitude, not 1e-12 of it (0.86 at
** 4.3e11, which let spans of 3 and 3.5 pass as one period's copy). */
static void test_periodic_spans_checked_far_from_zero(void **state) {
  /* degree 3, N = 5: period [0, 15]; the span after the seam's copy is 3.5, not 3 */
  double K[12] = {-9, -6, -3, 0, 3, 6, 9, 12, 15, 18.5, 21, 24}, P[16] = {0};
  bsfit_curve c;
  bsfit_status st;
  size_t i;
  (void)state;
  for (i = 0; i < 5; i++) P[2 * i] = (double)(i % 5), P[2 * i + 1] = (double)(i % 3);
  for (i = 0; i < 3 * 2; i++) P[2 * 5 + i] = P[i];
  bsfit_curve_init(&c);
  assert_int_equal(bsfit_curve_new(&c, 3, 2, 8, K, P, NULL, 1, NULL, &st), BSFIT_ENOTPERIODIC);
  for (i = 0; i < 12; i++) K[i] += 4.3e11;
  assert_int_equal(bsfit_curve_new(&c, 3, 2, 8, K, P, NULL, 1, NULL, &st), BSFIT_ENOTPERIODIC);
  bsfit_curve_free(&c);
}

/* }==================================================================== */

/* {====================================================================
** Operations that measure the curve or build a new one
** ===================================================================== */

/* Given random curves, then: derivatives are finite or BSFIT_ERANGE; samples equal the
** evaluator's values; the arc length lies between the chord and (polynomial curves) the
** control polygon's length; the closest point's distance is that of its foot; the exact filter
** and (uniform curves) the moving average are sound or refused; JSON round-trips
** exactly. */
static void test_measuring_ops(void **state) {
  gen g;
  int i;
  (void)state;
  memset(&g, 0, sizeof g);
  g.r.s = 0xbeefu;
  for (i = 0; i < NCURVES; i++) {
    bsfit_curve c, d;
    bsfit_status st;
    double a, b, der[8 * 2], smp[33 * 2], len, tol, Q[2], u, dist, y[2];
    size_t k;
    char *js = NULL;
    size_t jlen = 0;
    bsfit_err e;
    random_curve(&g, i, &c);
    bsfit_curve_init(&d);
    bsfit_curve_domain(&c, &a, &b);
    tol = curve_tol(&c, c.weights ? 1e-10 : 1e-12);
    e = bsfit_curve_derivs(&c, a + (b - a) * rng_uniform(&g.r), 3, der, &st);
    assert_true(e == BSFIT_OK ? all_finite(der, 8) : e == BSFIT_ERANGE);
    assert_int_equal(bsfit_curve_sample(&c, 33, smp, NULL, &st), BSFIT_OK);
    for (k = 0; k < 33; k++) {
      double uu = a + (b - a) * (double)k / (c.periodic ? 33.0 : 32.0);
      ref_eval(&c, uu, y);
      assert_true(pt_dist(y, smp + 2 * k, 2) <= tol);
    }
    assert_int_equal(bsfit_curve_length(&c, a, b, &len, &st), BSFIT_OK);
    assert_true(isfinite(len));
    if (!c.periodic) {
      ref_eval(&c, a, y);
      ref_eval(&c, b, Q);
      /* near a cusp |C'| has a kink and the adaptive quadrature stops at 2^12 pieces a
      ** span with a few 1e-9 (bsfit_curve_length's documented limit) */
      if (!(len >= hypot(Q[0] - y[0], Q[1] - y[1]) * (1 - 1e-7)))
        fail_msg("length, curve %d (p=%d n=%zu%s): %.17g below the chord %.17g", i, c.degree, c.n,
                 c.weights ? " rational" : "", len, hypot(Q[0] - y[0], Q[1] - y[1]));
    }
    if (!c.weights) {
      double poly = 0.0;
      for (k = 1; k < c.n; k++)
        poly += hypot(c.ctrl[2 * k] - c.ctrl[2 * k - 2], c.ctrl[2 * k + 1] - c.ctrl[2 * k - 1]);
      assert_true(len <= poly * (1 + 1e-7) + 1e-300);
    }
    /* closest: a random point near the curve, against NPAR points of the curve */
    Q[0] = smp[0] + ctrl_scale(&c) * rng_range(&g.r, -0.3, 0.3);
    Q[1] = smp[1] + ctrl_scale(&c) * rng_range(&g.r, -0.3, 0.3);
    assert_int_equal(bsfit_curve_closest(&c, Q, &u, &dist, NULL, &st), BSFIT_OK);
    assert_true(isfinite(u) && isfinite(dist) && u >= a && u <= b);
    /* the search is local between samples (bsfit_curve_closest's documented limit):
    ** check the foot, not that it is global */
    ref_eval(&c, u, y);
    if (!(fabs(hypot(y[0] - Q[0], y[1] - Q[1]) - dist) <= tol))
      fail_msg("closest, curve %d: dist %g but |C(u) - Q| = %g", i, dist,
               hypot(y[0] - Q[0], y[1] - Q[1]));
    /* filters: polynomial curves only */
    if (!c.weights) {
      e = bsfit_filter_box_curve_delta(&c, (b - a) * rng_range(&g.r, 1e-4, 0.3), &d, &st);
      (void)check_result(e, &st, &d, "exact filter", i);
      if (bsfit_curve_is_uniform(&c)) {
        e = bsfit_filter_box_curve(&c, 1 + (int)(rng_uniform(&g.r) * 3), &d, &st);
        (void)check_result(e, &st, &d, "moving average", i);
      }
    }
    /* JSON round trip, exact */
    assert_int_equal(bsfit_curve_to_json(&c, &js, &jlen, NULL, &st), BSFIT_OK);
    assert_int_equal(bsfit_curve_from_json(js, jlen, &d, NULL, &st), BSFIT_OK);
    assert_int_equal(d.n, c.n);
    assert_memory_equal(d.knots, c.knots, (c.n + (size_t)c.degree + 1) * sizeof(double));
    assert_memory_equal(d.ctrl, c.ctrl, c.n * 2 * sizeof(double));
    free(js);
    bsfit_curve_free(&c);
    bsfit_curve_free(&d);
  }
}

/* }==================================================================== */

/* {====================================================================
** Surfaces
** ===================================================================== */

/* S(u, v) from the definition: de Boor along v for each of the (pu + 1) rows of the
** u span, then along u (homogeneous coordinates, wrapped in a 1 x n curve view). */
static void ref_surface(const bsfit_surface *s, double u, double v, double *out) {
  size_t pu = (size_t)s->degree_u, pv = (size_t)s->degree_v, d = (size_t)s->dim, i, j, k, su;
  double rowpts[REF_MAXP + 1][5], U[64], Pt[64 * 5], W[64];
  bsfit_curve col, row;
  for (su = s->nu - 1; su > pu && !(s->knots_u[su] <= u && s->knots_u[su] < s->knots_u[su + 1]);
       su--) {
  }
  for (i = 0; i <= pu; i++) { /* row su - pu + i, as a curve in v, evaluated at v */
    size_t r = su - pu + i;
    for (j = 0; j < s->nv; j++) {
      double w = s->weights ? s->weights[r * s->nv + j] : 1.0;
      for (k = 0; k < d; k++) Pt[j * d + k] = s->ctrl[(r * s->nv + j) * d + k];
      W[j] = w;
    }
    bsfit_curve_init(&row);
    row.degree = (int)pv;
    row.dim = (int)d;
    row.n = s->nv;
    row.knots = (double *)s->knots_v;
    row.ctrl = Pt;
    row.weights = s->weights ? W : NULL;
    ref_eval(&row, v, rowpts[i]);
    /* the homogeneous weight of the row at v: the same evaluation of the weights alone */
    if (s->weights) {
      double one[64];
      for (j = 0; j < s->nv; j++) one[j] = W[j];
      row.dim = 1;
      row.ctrl = one;
      row.weights = NULL;
      ref_eval(&row, v, &rowpts[i][d]);
    } else {
      rowpts[i][d] = 1.0;
    }
  }
  /* along u: the rows' points and weights as a rational curve on knots_u */
  for (i = 0; i <= pu; i++) {
    for (k = 0; k < d; k++) Pt[i * d + k] = rowpts[i][k];
    W[i] = rowpts[i][d];
  }
  bsfit_curve_init(&col);
  col.degree = (int)pu;
  col.dim = (int)d;
  col.n = pu + 1;
  for (i = 0; i < 2 * pu + 2; i++) U[i] = s->knots_u[su - pu + i];
  col.knots = U;
  col.ctrl = Pt;
  col.weights = s->weights ? W : NULL;
  ref_eval(&col, u, out);
}

/* Given random surfaces (degrees 1-4 each way, knots clustered down to 1e-15, rational
** or not, coordinates 1e-98..1e99), then: points equal the reference; derivatives and
** normals are finite or an error; grids are finite; the exact filter of a polynomial
** surface is valid or refused; JSON round-trips exactly. */
static void test_surface_ops(void **state) {
  test_rng r = {0x5u};
  int i;
  (void)state;
  for (i = 0; i < 150; i++) {
    int pu = 1 + i % 4, pv = 1 + (i / 4) % 4, rational = (i / 16) % 2;
    size_t nu = (size_t)pu + 1 + (size_t)(rng_uniform(&r) * 4),
           nv = (size_t)pv + 1 + (size_t)(rng_uniform(&r) * 4), k;
    double U[32], V[32], P[3 * 64], W[64], scale = pow(10.0, rng_range(&r, -98.0, 99.0));
    double ua, ub, va, vb, D[4 * 3], grid[5 * 5 * 3], y1[3], y2[3], tol;
    bsfit_surface s, f;
    bsfit_status st;
    bsfit_err e;
    char *js = NULL;
    size_t jlen;
    clustered_knots(&r, pu, nu, 1, pu, U);
    clustered_knots(&r, pv, nv, 1, pv, V);
    for (k = 0; k < nu * nv * 3; k++) P[k] = scale * rng_range(&r, -1, 1);
    for (k = 0; k < nu * nv; k++) W[k] = rng_range(&r, 0.3, 3.0);
    bsfit_surface_init(&s);
    bsfit_surface_init(&f);
    assert_int_equal(
        bsfit_surface_new(&s, pu, pv, 3, nu, nv, U, V, P, rational ? W : NULL, NULL, &st),
        BSFIT_OK);
    bsfit_surface_domain(&s, &ua, &ub, &va, &vb);
    tol = scale * 1e-9;
    for (k = 0; k < 20; k++) {
      double u = ua + (ub - ua) * rng_uniform(&r), v = va + (vb - va) * rng_uniform(&r);
      assert_int_equal(bsfit_surface_eval(&s, u, v, y1, &st), BSFIT_OK);
      ref_surface(&s, u, v, y2);
      if (!(pt_dist(y1, y2, 3) <= tol))
        fail_msg("surface %d: S(%g, %g) off by %g", i, u, v, pt_dist(y1, y2, 3));
      e = bsfit_surface_derivs(&s, u, v, 1, D, &st);
      assert_true(e == BSFIT_OK ? all_finite(D, 12) : e == BSFIT_ERANGE);
      e = bsfit_surface_normal(&s, u, v, y1, &st);
      if (e == BSFIT_OK)
        assert_true(all_finite(y1, 3) && fabs(hypot(hypot(y1[0], y1[1]), y1[2]) - 1) < 1e-12);
      else
        assert_true(e == BSFIT_ERANGE || e == BSFIT_EDEGENERATE);
    }
    /* farther out than one domain length: refused, not a point of cancelled sums */
    assert_int_equal(bsfit_surface_eval(&s, ua - 3.0 * (ub - ua), va, y1, &st), BSFIT_EDOMAIN);
    assert_int_equal(bsfit_surface_eval(&s, ua, vb + 1e300, y1, &st), BSFIT_EDOMAIN);
    assert_int_equal(bsfit_surface_sample_grid(&s, 5, 5, grid, &st), BSFIT_OK);
    assert_true(all_finite(grid, 75));
    if (!rational) {
      e = bsfit_filter_box_surface_delta(&s, (ub - ua) * 0.1, (vb - va) * 0.1, &f, &st);
      if (e == BSFIT_OK)
        assert_int_equal(bsfit_surface_validate(&f, &st), BSFIT_OK);
      else
        assert_true(e < 0 && strlen(st.msg) > 0);
    }
    assert_int_equal(bsfit_surface_to_json(&s, &js, &jlen, NULL, &st), BSFIT_OK);
    assert_int_equal(bsfit_surface_from_json(js, jlen, &f, NULL, &st), BSFIT_OK);
    assert_memory_equal(f.ctrl, s.ctrl, nu * nv * 3 * sizeof(double));
    free(js);
    bsfit_surface_free(&s);
    bsfit_surface_free(&f);
  }
}

/* }==================================================================== */

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_elevate_issue_cases),
      cmocka_unit_test(test_periodic_far_knots),
      cmocka_unit_test(test_periodic_spans_checked_far_from_zero),
      cmocka_unit_test(test_shape_preserving_ops),
      cmocka_unit_test(test_measuring_ops),
      cmocka_unit_test(test_surface_ops),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
