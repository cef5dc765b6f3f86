/*
** test_hardening_core.c
** Regression tests of issue 13's findings in the core, each over random inputs:
** the exact filter with windows down to 1e-15 (it read past a buffer and returned
** garbage), periodic knot vectors with a knot of multiplicity p+1 (elevation wrote
** before its buffer), ... Every OK result is checked against mathematics (quadrature of
** the window average, an independent evaluator), every refusal for its code.
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

/* {====================================================================
** Finding 4: the exact filter for any window, any knots
** ===================================================================== */

#define GLN 12 /* exact to degree 23 */

/* C extended by its end values outside [a, b] (the end rule of a clamped curve); a
** closed curve repeats (ref_eval wraps) */
static void ext_eval(const bsfit_curve *c, double u, double *out) {
  double a, b;
  bsfit_curve_domain(c, &a, &b);
  if (!c->periodic) u = u < a ? a : (u > b ? b : u);
  ref_eval(c, u, out);
}

static int cmp_dbl(const void *x, const void *y) {
  double a = *(const double *)x, b = *(const double *)y;
  return (a > b) - (a < b);
}

/* (1 / 2 delta) * integral of the extended C over [t - delta, t + delta], by
** Gauss-Legendre between the knots (the integrand is a polynomial between them) */
static void window_average(const bsfit_curve *c, double t, double delta, double *out) {
  double x[GLN], w[GLN], lo = t - delta, hi = t + delta, v[4], brk[128];
  size_t nk = c->n + (size_t)c->degree + 1, nb = 0, i, j;
  int k, g;
  gl_nodes(GLN, x, w);
  double a, b, T;
  int sh;
  bsfit_curve_domain(c, &a, &b);
  T = b - a;
  brk[nb++] = lo;
  /* knots of the periods around (closed curves): the integrand is a polynomial between */
  for (sh = c->periodic ? -2 : 0; sh <= (c->periodic ? 2 : 0); sh++)
    for (i = 0; i < nk && nb < 126; i++) {
      double kv = c->knots[i] + sh * T;
      if (kv > lo && kv < hi) brk[nb++] = kv;
    }
  brk[nb++] = hi;
  qsort(brk, nb, sizeof(double), cmp_dbl);
  for (k = 0; k < c->dim; k++) out[k] = 0.0;
  for (j = 0; j + 1 < nb; j++) {
    double m = 0.5 * (brk[j] + brk[j + 1]), h = 0.5 * (brk[j + 1] - brk[j]);
    for (g = 0; g < GLN; g++) {
      ext_eval(c, m + h * x[g], v);
      for (k = 0; k < c->dim; k++) out[k] += w[g] * h * v[k];
    }
  }
  for (k = 0; k < c->dim; k++) out[k] /= 2.0 * delta;
}

/* Given random clamped curves (degrees 1-5, knots clustered down to 1e-15) and windows
** from 1e-15 to a quarter of the domain, when filtered exactly, then either the result
** is valid and equals the window average to 1e-8 of the control points' extent, or the
** window is below the documented resolution and the answer is BSFIT_EDOMAIN. */
static void test_filter_any_delta(void **state) {
  test_rng r = {0x5eed4u};
  int trial, ok = 0, refused = 0;
  (void)state;
  for (trial = 0; trial < 60; trial++) {
    int p = 1 + trial % 5, dim = 2, e10, closed = trial % 3 == 2;
    size_t n = (size_t)p + 1 + (size_t)(rng_uniform(&r) * 8), i;
    double U[64], P[64], a, b, len, unwrapped;
    bsfit_curve c, f;
    bsfit_status st;
    bsfit_err e0;
    for (i = 0; i < n * 2; i++) P[i] = rng_range(&r, -5.0, 5.0);
    bsfit_curve_init(&c);
    bsfit_curve_init(&f);
    do { /* closed: the period's knots, drawn again while the seam passes p */
      clustered_knots(&r, p, closed ? n - (size_t)p : n, !closed, closed ? p - 1 : p, U);
      e0 = closed ? bsfit_curve_new_periodic(&c, p, dim, n, U, P, NULL, NULL, &st)
                  : bsfit_curve_new(&c, p, dim, n, U, P, NULL, 0, NULL, &st);
    } while (closed && e0 == BSFIT_EMULT);
    assert_int_equal(e0, BSFIT_OK);
    bsfit_curve_domain(&c, &a, &b);
    len = b - a;
    /* a closed curve is filtered unwrapped over 2M + 1 periods, M = 3 + (p + 1) / N */
    unwrapped = closed ? len * (double)(2 * (3 + (size_t)(p + 1) / n) + 1) : len;
    for (e10 = -15; e10 <= 0; e10 += 3) {
      /* the curve is known to its knots' rounding, eps |a| / len of the domain */
      double delta = len * (e10 == 0 ? 0.25 : pow(10.0, e10));
      double tol = 10.0 * (1e-8 + 1e4 * DBL_EPSILON * (fabs(a) + fabs(b)) / len);
      bsfit_err e = bsfit_filter_box_curve_delta(&c, delta, &f, &st);
      if (e != BSFIT_OK && closed && e == BSFIT_EMULT) { /* clusters below the rounding */
        assert_non_null(strstr(st.msg, "they would merge"));
        refused++;
        continue;
      }
      if (e != BSFIT_OK) {
        assert_int_equal(e, BSFIT_EDOMAIN);
        if (!(delta < 2.0 * BSFIT_FILTER_MIN_DELTA * unwrapped + 1e-8 * (fabs(a) + fabs(b) + len)))
          fail_msg("delta %g refused: %s", delta, st.msg);
        refused++;
        continue;
      }
      ok++;
      assert_true(curve_sound(&f));
      for (i = 0; i < 40; i++) {
        double t = a - delta + (len + 2.0 * delta) * ((double)i + 0.5) / 40.0, got[4], want[4];
        ref_eval(&f, t, got);
        window_average(&c, t, delta, want);
        if (pt_dist(got, want, dim) > tol)
          fail_msg("p=%d n=%zu [%g, %g] delta=%g t=%.17g: off by %.3g", p, n, a, b, delta, t,
                   pt_dist(got, want, dim));
      }
    }
    bsfit_curve_free(&c);
    bsfit_curve_free(&f);
  }
  assert_true(ok > 100);
  assert_true(refused > 100);
}

/* Given uniform curves and delta = k h / 2 (the knots u_i + delta and u_j - delta
** coincide in exact arithmetic and are merged), the exact filter equals the moving
** average and is a valid curve, for open and closed curves. */
static void test_filter_uniform_merge(void **state) {
  test_rng r = {0x77u};
  int p, k;
  (void)state;
  for (p = 1; p <= 5; p++)
    for (k = 1; k <= 6; k++) {
      size_t n = (size_t)p + 8, i;
      double P[64], a, b, h;
      int per;
      for (i = 0; i < 2 * n; i++) P[i] = rng_range(&r, -1e3, 1e3);
      for (per = 0; per <= 1; per++) {
        bsfit_curve c, f1, f2;
        bsfit_status st;
        bsfit_curve_init(&c);
        bsfit_curve_init(&f1);
        bsfit_curve_init(&f2);
        if (per)
          assert_int_equal(bsfit_curve_new_periodic(&c, p, 2, n, NULL, P, NULL, NULL, &st), 0);
        else {
          double U[64];
          assert_int_equal(bsfit_knots_uniform(p, n, 0.3, 7.1, U, &st), BSFIT_OK);
          assert_int_equal(bsfit_curve_new(&c, p, 2, n, U, P, NULL, 0, NULL, &st), BSFIT_OK);
        }
        bsfit_curve_domain(&c, &a, &b);
        h = c.knots[p + 1] - c.knots[p];
        assert_int_equal(bsfit_filter_box_curve(&c, k, &f1, &st), BSFIT_OK);
        assert_int_equal(bsfit_filter_box_curve_delta(&c, 0.5 * k * h, &f2, &st), BSFIT_OK);
        assert_true(curve_sound(&f2));
        for (i = 0; i <= 50; i++) {
          double t = a + (b - a) * (double)i / 50.0, y1[2], y2[2];
          ref_eval(&f1, t, y1);
          ref_eval(&f2, t, y2);
          assert_true(pt_dist(y1, y2, 2) <= 1e-9 * 1e3);
        }
        bsfit_curve_free(&c);
        bsfit_curve_free(&f1);
        bsfit_curve_free(&f2);
      }
    }
}

/* }==================================================================== */

/* {====================================================================
** Finding 5: periodic knot vectors with a knot of multiplicity p + 1
** ===================================================================== */

/* Given closed curves of degree 1-6 whose period has one knot (the seam or an
** interior one) of multiplicity p + 1, when built, then they are refused with
** BSFIT_EMULT; with multiplicity p they are accepted, and elevating them gives a curve
** equal to the original. */
static void test_periodic_multiplicity(void **state) {
  int p, where;
  (void)state;
  for (p = 1; p <= 6; p++)
    for (where = 0; where < 3; where++) {
      size_t N = (size_t)p + 4, i, j;
      double t[32], P[64];
      int mult;
      for (i = 0; i < 2 * N; i++) P[i] = sin(1.7 * (double)i) * 3.0;
      for (mult = p; mult <= p + 1; mult++) {
        bsfit_curve c, e2;
        bsfit_status st;
        bsfit_err e;
        /* t[0..N]: spans of 1, and `mult` equal knots at the seam's end (where 0),
        ** its start (1) or inside (2) */
        for (i = 0; i <= N; i++) t[i] = (double)i;
        if (where == 0)
          for (j = 1; j < (size_t)mult; j++) t[N - j] = t[N];
        if (where == 1)
          for (j = 1; j < (size_t)mult; j++) t[j] = t[0];
        if (where == 2)
          for (j = 1; j < (size_t)mult; j++) t[2 + j] = t[2];
        bsfit_curve_init(&c);
        bsfit_curve_init(&e2);
        e = bsfit_curve_new_periodic(&c, p, 2, N, t, P, NULL, NULL, &st);
        if (mult > p) {
          assert_int_equal(e, BSFIT_EMULT);
          continue;
        }
        assert_int_equal(e, BSFIT_OK);
        assert_int_equal(bsfit_curve_elevate(&c, 2, &e2, &st), BSFIT_OK);
        assert_true(curve_sound(&e2));
        for (i = 0; i < 64; i++) {
          double u = t[0] + (t[N] - t[0]) * (double)i / 64.0, y1[2], y2[2];
          ref_eval(&c, u, y1);
          ref_eval(&e2, u, y2);
          assert_true(pt_dist(y1, y2, 2) <= 1e-12 * 3.0);
        }
        bsfit_curve_free(&c);
        bsfit_curve_free(&e2);
      }
    }
}

/* The issue's case, through the expanded form: degree 1, knots {0,0,1,1,2}. */
static void test_periodic_issue_case(void **state) {
  double U[5] = {0, 0, 1, 1, 2}, P[6] = {0, 0, 1, 0, 0, 0};
  bsfit_curve c;
  bsfit_status st;
  (void)state;
  bsfit_curve_init(&c);
  assert_int_equal(bsfit_curve_new(&c, 1, 2, 3, U, P, NULL, 1, NULL, &st), BSFIT_EMULT);
  assert_non_null(strstr(st.msg, "multiplicity 2"));
}

/* }==================================================================== */

/* {====================================================================
** Finding 7: both solvers check every input, even with no free unknown
** ===================================================================== */

/* Given fits of degree 1-3 with fixed ends, fixed clamped knots and as few control
** points as the constraints fix (no free unknown) or a few more, when one point
** coordinate or one parameter is NaN, +Inf or -Inf at a random place, then every
** solver answers BSFIT_ENONFINITE; the clean data fit OK with a finite rms equal to
** the one computed here from the curve. */
static void test_fit_nonfinite_no_free(void **state) {
  static const bsfit_solver solvers[3] = {BSFIT_SOLVER_CHOLESKY, BSFIT_SOLVER_QR,
                                          BSFIT_SOLVER_AUTO};
  const double bad[3] = {NAN, INFINITY, -INFINITY};
  test_rng r = {0x7u};
  int trial;
  (void)state;
  for (trial = 0; trial < 90; trial++) {
    int p = 1 + trial % 3, sv = (trial / 3) % 3, extra = trial % 2 ? 0 : 1;
    size_t count = (size_t)p + 1 + (size_t)extra, m = 8 + (size_t)(rng_uniform(&r) * 40), k, i;
    double U[16], pts[200], u[100], rms = 0.0, y[2];
    bsfit_fit_opts o;
    bsfit_fitter *f = NULL;
    bsfit_fit_report rep;
    bsfit_curve c;
    bsfit_status st;
    assert_int_equal(bsfit_knots_clamped(p, count, 0.0, 1.0, U, &st), BSFIT_OK);
    for (k = 0; k < m; k++) {
      u[k] = (double)k / (double)(m - 1);
      pts[2 * k] = u[k] * 3.0 + rng_range(&r, -0.1, 0.1);
      pts[2 * k + 1] = sin(3.0 * u[k]) + rng_range(&r, -0.1, 0.1);
    }
    bsfit_fit_opts_init(&o);
    o.degree = p;
    o.count = count;
    o.knots = U;
    o.nknots = count + (size_t)p + 1;
    o.fix_ends = 1;
    o.solver = solvers[sv];
    assert_int_equal(bsfit_fitter_new(&f, &o, NULL, &st), BSFIT_OK);
    bsfit_curve_init(&c);
    assert_int_equal(bsfit_fitter_fit(f, pts, m, 2, u, NULL, &c, &rep, NULL, &st), BSFIT_OK);
    for (k = 0; k < m; k++) {
      ref_eval(&c, u[k], y);
      rms += (y[0] - pts[2 * k]) * (y[0] - pts[2 * k]) +
             (y[1] - pts[2 * k + 1]) * (y[1] - pts[2 * k + 1]);
    }
    assert_true(fabs(rep.rms - sqrt(rms / (double)m)) <= 1e-12);
    for (i = 0; i < 3; i++) {
      size_t at = (size_t)(rng_uniform(&r) * (double)m);
      double keep;
      int which = (int)(rng_uniform(&r) * 3.0); /* x, y or the parameter */
      double *slot = which == 2 ? &u[at] : &pts[2 * at + (size_t)which];
      keep = *slot;
      *slot = bad[i];
      assert_int_equal(bsfit_fitter_fit(f, pts, m, 2, u, NULL, &c, &rep, NULL, &st),
                       BSFIT_ENONFINITE);
      *slot = keep;
    }
    bsfit_curve_free(&c);
    bsfit_fitter_free(f);
  }
}

/* }==================================================================== */

/* {====================================================================
** Finding 8: chord parameters never underflow
** ===================================================================== */

/* Chords computed here after scaling by an exact power of two (frexp/ldexp), so that
** neither squares nor sums leave the normal range. */
static double scaled_chord(const double *a, const double *b, int dim, int centripetal) {
  double big = 0.0, s = 0.0, c;
  int k, ex;
  for (k = 0; k < dim; k++) big = fmax(big, fabs(a[k] - b[k]));
  if (big == 0.0) return 0.0;
  (void)frexp(big, &ex);
  for (k = 0; k < dim; k++) {
    double t = ldexp(a[k] - b[k], -ex);
    s += t * t;
  }
  c = ldexp(sqrt(s), ex);
  return centripetal ? sqrt(c) : c;
}

/* Given random polylines of 3-40 points of dimension 1-4 at scales 1e-320..1e100
** (subnormal coordinates included), with repeated points, when parameterised by chord
** or centripetal length, open or closed, then the answer is OK with finite, non-
** decreasing parameters in [0, 1] equal to the scaled reference to 1e-12, or an error
** that the data explains (all points equal; a closed section ending on its start). */
static void test_params_no_underflow(void **state) {
  test_rng r = {0x8u};
  int trial;
  (void)state;
  for (trial = 0; trial < 3000; trial++) {
    int dim = 1 + trial % 4, kind = trial % 2 ? BSFIT_PARAM_CHORD : BSFIT_PARAM_CENTRIPETAL;
    int closed = (trial / 2) % 2;
    size_t m = 3 + (size_t)(rng_uniform(&r) * 38), k, c;
    double scale = pow(10.0, rng_range(&r, -320.0, 100.0)), pts[4 * 41], u[41], ref[41], tot;
    bsfit_status st;
    bsfit_err e;
    for (k = 0; k < m; k++)
      for (c = 0; c < (size_t)dim; c++)
        pts[k * (size_t)dim + c] = k > 0 && rng_uniform(&r) < 0.2 ? pts[(k - 1) * (size_t)dim + c]
                                                                  : scale * rng_range(&r, -1, 1);
    if (trial % 7 == 0) /* the issue's case, scaled: one point apart, the rest equal */
      for (k = 1; k < m; k++)
        for (c = 0; c < (size_t)dim; c++) pts[k * (size_t)dim + c] = 0.0;
    e = bsfit_params(pts, m, dim, (bsfit_param_kind)kind, closed, u, &st);
    ref[0] = 0.0;
    for (k = 1; k < m; k++)
      ref[k] = ref[k - 1] + scaled_chord(pts + (k - 1) * (size_t)dim, pts + k * (size_t)dim, dim,
                                         kind == BSFIT_PARAM_CENTRIPETAL);
    tot = ref[m - 1] + (closed ? scaled_chord(pts + (m - 1) * (size_t)dim, pts, dim,
                                              kind == BSFIT_PARAM_CENTRIPETAL)
                               : 0.0);
    if (e != BSFIT_OK) {
      assert_true(tot == 0.0 ? e == BSFIT_EDEGENERATE : (closed && e == BSFIT_EINVAL));
      continue;
    }
    assert_true(tot > 0.0);
    for (k = 0; k < m; k++) {
      assert_true(isfinite(u[k]) && u[k] >= 0.0 && u[k] <= 1.0);
      if (k > 0) assert_true(u[k] >= u[k - 1]);
      if (!(fabs(u[k] - ref[k] / tot) <= 1e-12))
        fail_msg("trial %d k %zu: %.17g vs %.17g", trial, k, u[k], ref[k] / tot);
    }
  }
}

/* }==================================================================== */

/* {====================================================================
** Finding 9: values beyond the documented range
** ===================================================================== */

/* Given data at |x| from 1e90 to 1e308, when fitted (both solvers), then the answer is
** OK with a finite rms (|x| <= 1e100) or BSFIT_ERANGE; a finite tangent beyond 1e100
** is refused at configuration. */
static void test_fit_huge_coordinates(void **state) {
  test_rng r = {0x9u};
  int e10;
  (void)state;
  for (e10 = 90; e10 <= 308; e10 += 4) {
    int sv;
    for (sv = 0; sv < 2; sv++) {
      size_t m = 40, k;
      double pts[80], u[40], s = pow(10.0, e10);
      bsfit_fit_opts o;
      bsfit_fitter *f = NULL;
      bsfit_fit_report rep;
      bsfit_curve c;
      bsfit_status st;
      bsfit_err e;
      for (k = 0; k < m; k++) {
        u[k] = (double)k / (double)(m - 1);
        pts[2 * k] = s * cos(u[k]) * rng_range(&r, 0.9, 1.0);
        pts[2 * k + 1] = s * sin(u[k]) * rng_range(&r, 0.9, 1.0);
      }
      bsfit_fit_opts_init(&o);
      o.count = 8;
      o.solver = sv ? BSFIT_SOLVER_QR : BSFIT_SOLVER_CHOLESKY;
      assert_int_equal(bsfit_fitter_new(&f, &o, NULL, &st), BSFIT_OK);
      bsfit_curve_init(&c);
      e = bsfit_fitter_fit(f, pts, m, 2, u, NULL, &c, &rep, NULL, &st);
      if (s <= BSFIT_COORD_MAX) {
        assert_int_equal(e, BSFIT_OK);
        assert_true(isfinite(rep.rms) && isfinite(rep.max) && curve_sound(&c));
      } else {
        assert_int_equal(e, BSFIT_ERANGE);
        assert_int_equal(bsfit_params(pts, m, 2, BSFIT_PARAM_CHORD, 0, u, &st), BSFIT_ERANGE);
      }
      bsfit_curve_free(&c);
      bsfit_fitter_free(f);
    }
  }
  {
    double T[2] = {1e308, 0.0};
    bsfit_fit_opts o;
    bsfit_fitter *f = NULL;
    bsfit_status st;
    bsfit_fit_opts_init(&o);
    o.count = 8;
    o.tangent_start = T;
    o.tangent_dim = 2;
    assert_int_equal(bsfit_fitter_new(&f, &o, NULL, &st), BSFIT_ERANGE);
    assert_null(f);
  }
}

/* Given curves with a weight below DBL_MIN or above 1e100, or a control point beyond
** 1e100, when built, then they are refused (BSFIT_EWEIGHT, BSFIT_ERANGE); at the limits
** they are accepted and insertion and elevation return finite, valid curves equal to
** the original. */
static void test_curve_ranges(void **state) {
  const double wbad[4] = {4e-320, 1e-101, 1e101, 1e300};
  double P[8] = {0, 0, 1, 2, 3, 1, 4, 0}, W[4] = {1, 1, 1, 1}, U[7] = {0, 0, 0, 0.5, 1, 1, 1};
  bsfit_curve c, d;
  bsfit_status st;
  int i;
  (void)state;
  bsfit_curve_init(&c);
  bsfit_curve_init(&d);
  for (i = 0; i < 4; i++) {
    W[1] = wbad[i];
    assert_int_equal(bsfit_curve_new(&c, 2, 2, 4, U, P, W, 0, NULL, &st), BSFIT_EWEIGHT);
  }
  W[1] = 1.0;
  P[3] = 1e300;
  assert_int_equal(bsfit_curve_new(&c, 2, 2, 4, U, P, W, 0, NULL, &st), BSFIT_ERANGE);
  /* at the limits: weights 1e-100 and 1e100, coordinates 1e100 */
  P[3] = 1e100;
  P[4] = -1e100;
  W[1] = 1e-100;
  W[2] = 1e100;
  assert_int_equal(bsfit_curve_new(&c, 2, 2, 4, U, P, W, 0, NULL, &st), BSFIT_OK);
  for (i = 0; i < 2; i++) {
    int k;
    bsfit_err e =
        i == 0 ? bsfit_curve_insert_knot(&c, 0.3, 2, &d, &st) : bsfit_curve_elevate(&c, 3, &d, &st);
    assert_int_equal(e, BSFIT_OK);
    assert_true(curve_sound(&d));
    for (k = 0; k <= 20; k++) {
      double y1[2], y2[2];
      ref_eval(&c, k / 20.0, y1);
      ref_eval(&d, k / 20.0, y2);
      assert_true(pt_dist(y1, y2, 2) <= 1e-9 * 1e100);
    }
  }
  bsfit_curve_free(&c);
  bsfit_curve_free(&d);
}

/* Given random curves whose inner knots crowd an end to within 1e-99..1e-12 (they
** mirror onto the end), when reversed, then the answer is OK with a valid curve that
** runs backwards (C_r(a + b - u) = C(u)), or BSFIT_EMULT / BSFIT_ENOTPERIODIC. */
static void test_reverse_valid(void **state) {
  test_rng r = {0x99u};
  int trial, ok = 0, refused = 0;
  (void)state;
  for (trial = 0; trial < 400; trial++) {
    int p = 1 + trial % 4, j;
    size_t n = (size_t)p + 2 + (size_t)(rng_uniform(&r) * 4), i;
    double U[32], P[32], a, b;
    bsfit_curve c, v;
    bsfit_status st;
    bsfit_err e;
    clustered_knots(&r, p, n, 1, 1, U);
    /* start at 0 and move the first inner knot next to it: representable there, it
    ** mirrors onto b - 1e-99, which rounds to b */
    for (i = n + (size_t)p; i + 1 > 0; i--) U[i] -= U[0];
    U[p + 1] = U[p + 2] * pow(10.0, -rng_range(&r, 2.0, 40.0));
    for (i = 0; i < 2 * n; i++) P[i] = rng_range(&r, -1, 1);
    bsfit_curve_init(&c);
    bsfit_curve_init(&v);
    e = bsfit_curve_new(&c, p, 2, n, U, P, NULL, 0, NULL, &st);
    if (e != BSFIT_OK) fail_msg("%s", st.msg);
    e = bsfit_curve_reverse(&c, &v, &st);
    if (e != BSFIT_OK) {
      assert_true(e == BSFIT_EMULT);
      refused++;
      bsfit_curve_free(&c);
      continue;
    }
    ok++;
    assert_true(curve_sound(&v));
    bsfit_curve_domain(&c, &a, &b);
    for (j = 0; j <= 20; j++) {
      double u = a + (b - a) * j / 20.0, y1[2], y2[2];
      ref_eval(&c, u, y1);
      /* a + b - u from the nearer end, so that the ends map exactly onto each other */
      ref_eval(&v, u - a <= b - u ? b - (u - a) : a + (b - u), y2);
      if (!(pt_dist(y1, y2, 2) <= 1e-9))
        fail_msg("p %d n %zu u %.17g [%.17g %.17g] U[p+1] %.17g: off by %g", p, n, u, a, b,
                 U[p + 1], pt_dist(y1, y2, 2));
    }
    bsfit_curve_free(&c);
    bsfit_curve_free(&v);
  }
  if (!(ok > 50 && refused > 10)) fail_msg("ok %d refused %d", ok, refused);
}

/* The moving average of a closed curve with N = p + 1 distinct control points would be
** a closed curve of degree p + 1 with too few points: refused, for every p. */
static void test_ma_minimal_periodic(void **state) {
  int p;
  (void)state;
  for (p = 1; p <= 6; p++) {
    size_t N;
    for (N = (size_t)p + 1; N <= (size_t)p + 3; N++) {
      double P[32];
      size_t i;
      int k;
      bsfit_curve c, f;
      bsfit_status st;
      for (i = 0; i < 2 * N; i++) P[i] = cos((double)i);
      bsfit_curve_init(&c);
      bsfit_curve_init(&f);
      assert_int_equal(bsfit_curve_new_periodic(&c, p, 2, N, NULL, P, NULL, NULL, &st), 0);
      for (k = 1; k <= (int)N; k++) {
        bsfit_err e = bsfit_filter_box_curve(&c, k, &f, &st);
        if (N < (size_t)p + 2)
          assert_int_equal(e, BSFIT_ENOTPERIODIC);
        else {
          assert_int_equal(e, BSFIT_OK);
          assert_true(curve_sound(&f));
        }
      }
      bsfit_curve_free(&c);
      bsfit_curve_free(&f);
    }
  }
}

/* }==================================================================== */

/* {====================================================================
** Geometry kernels at every scale
** ===================================================================== */

/* Given random polylines of dimension 2 and 3 at scales 1e-320..1e100 (subnormal
** included), with repeated and collinear points, when measured by the geometry kernels,
** then an OK answer is finite where it promises finiteness (radii may be +Inf for
** collinear triples: never NaN), weights are finite and >= their floor, angles in
** [0, 180], and the other answers are error codes. */
static void test_geometry_any_scale(void **state) {
  test_rng r = {0x6e0u};
  int trial;
  (void)state;
  for (trial = 0; trial < 2000; trial++) {
    int dim = 2 + trial % 2, closed = (trial / 2) % 2;
    size_t m = 3 + (size_t)(rng_uniform(&r) * 30), k;
    double scale = pow(10.0, rng_range(&r, -320.0, 100.0)), pts[3 * 40], out[40], d;
    size_t cnt;
    bsfit_status st;
    bsfit_err e;
    for (k = 0; k < m * (size_t)dim; k++) {
      double x = rng_uniform(&r);
      pts[k] = x < 0.15 && k >= (size_t)dim ? pts[k - (size_t)dim]
               : x < 0.25                   ? 0.0
                                            : scale * rng_range(&r, -1, 1);
    }
    e = bsfit_geom_circumradius(pts, m, dim, closed, trial % 3 == 0, out, &st);
    for (k = 0; e == BSFIT_OK && k < m; k++) assert_true(!isnan(out[k]) && out[k] >= 0);
    e = bsfit_weights_circumradius(pts, m, dim, closed, trial % 3 == 0, out, &st);
    for (k = 0; e == BSFIT_OK && k < m; k++)
      if (!(isfinite(out[k]) && out[k] >= 1.0)) fail_msg("circumradius weight %g", out[k]);
    e = bsfit_geom_angles(pts, m, dim, closed, out, &st);
    for (k = 0; e == BSFIT_OK && k < m; k++) assert_true(out[k] >= 0.0 && out[k] <= 180.0);
    e = bsfit_weights_turning(pts, m, dim, closed, out, &st);
    for (k = 0; e == BSFIT_OK && k < m; k++)
      if (!(isfinite(out[k]) && out[k] >= 1.0)) fail_msg("turning weight %g", out[k]);
    e = bsfit_weights_spacing(pts, m, dim, closed, out, &st);
    for (k = 0; e == BSFIT_OK && k < m; k++)
      if (!(isfinite(out[k]) && out[k] >= BSFIT_GEOM_SPACING_FLOOR))
        fail_msg("spacing weight %g", out[k]);
    (void)bsfit_geom_inflections(pts, m, dim, closed, &cnt, &st);
    e = bsfit_geom_line_distance(pts, pts + dim, pts + 2 * dim, dim, &d, &st);
    if (e == BSFIT_OK) assert_true(isfinite(d) && d >= 0);
    e = bsfit_geom_tangent_project(pts, pts + dim, pts + 2 * dim, dim, out, &st);
    if (e == BSFIT_OK) assert_true(all_finite(out, (size_t)dim));
  }
}

/* The kernels measure shapes: scaled by 2^e (exact), a polyline keeps its angles,
** weights and inflections bit for bit and its radii scale by 2^e, for e from -960 to 330
** (squares of differences underflowed below about 1e-154 and overflowed above 1e154). */
static void test_geometry_scale_invariant(void **state) {
  test_rng r = {0x6e1u};
  int trial;
  (void)state;
  for (trial = 0; trial < 400; trial++) {
    int dim = 2 + trial % 2, closed = (trial / 2) % 2, e = (int)rng_range(&r, -960.0, 330.0);
    size_t m = 3 + (size_t)(rng_uniform(&r) * 30), k, c1, c2;
    double P[3 * 40], S[3 * 40], a1[40], a2[40];
    bsfit_status st;
    for (k = 0; k < m * (size_t)dim; k++) {
      P[k] = floor(rng_range(&r, -1024.0, 1024.0)) / 1024.0; /* exact multiples of 2^-10 */
      S[k] = ldexp(P[k], e);
    }
    if (ldexp(1.0, e) > BSFIT_COORD_MAX) continue;
    assert_int_equal(bsfit_geom_circumradius(P, m, dim, closed, 1, a1, &st), BSFIT_OK);
    assert_int_equal(bsfit_geom_circumradius(S, m, dim, closed, 1, a2, &st), BSFIT_OK);
    for (k = 0; k < m; k++)
      if (!(a2[k] == ldexp(a1[k], e))) fail_msg("radius %zu: %g vs %g * 2^%d", k, a2[k], a1[k], e);
    assert_int_equal(bsfit_weights_circumradius(P, m, dim, closed, 0, a1, &st), BSFIT_OK);
    assert_int_equal(bsfit_weights_circumradius(S, m, dim, closed, 0, a2, &st), BSFIT_OK);
    assert_memory_equal(a1, a2, m * sizeof(double));
    assert_int_equal(bsfit_geom_angles(P, m, dim, closed, a1, &st), BSFIT_OK);
    assert_int_equal(bsfit_geom_angles(S, m, dim, closed, a2, &st), BSFIT_OK);
    assert_memory_equal(a1, a2, m * sizeof(double));
    assert_int_equal(bsfit_weights_spacing(P, m, dim, closed, a1, &st), BSFIT_OK);
    assert_int_equal(bsfit_weights_spacing(S, m, dim, closed, a2, &st), BSFIT_OK);
    for (k = 0; k < m; k++) assert_true(fabs(a1[k] - a2[k]) <= 1e-14 * a1[k]);
    assert_int_equal(bsfit_geom_inflections(P, m, dim, closed, &c1, &st), BSFIT_OK);
    assert_int_equal(bsfit_geom_inflections(S, m, dim, closed, &c2, &st), BSFIT_OK);
    assert_int_equal(c1, c2);
    if (m >= 6) { /* the noise level scales with the data */
      double s1 = -1.0, s2 = -1.0;
      bsfit_err e1 = bsfit_noise_sigma(P, m, dim, closed, &s1, NULL, &st);
      bsfit_err e2 = bsfit_noise_sigma(S, m, dim, closed, &s2, NULL, &st);
      assert_int_equal(e1, e2);
      if (e1 == BSFIT_OK && !(isfinite(s2) && fabs(s2 - ldexp(s1, e)) <= 1e-12 * ldexp(s1, e)))
        fail_msg("noise sigma %g vs %g * 2^%d", s2, s1, e);
    }
  }
}

/* A curve scaled by 2^e keeps its length (scaled by 2^e, to 1e-12) at every e from
** -1000 to 330 (its squared speeds underflowed to a length 0 below about 1e-154); its
** closest points are the same feet while it is at least 1e-100 across, and below that
** the searches answer BSFIT_ERANGE instead of a foot at distance 0. */
static void test_curve_measures_any_scale(void **state) {
  test_rng r = {0x6e2u};
  int trial;
  (void)state;
  for (trial = 0; trial < 200; trial++) {
    int p = 1 + trial % 5, e = (int)rng_range(&r, -1000.0, 330.0);
    size_t n = (size_t)p + 1 + (size_t)(rng_uniform(&r) * 6), k;
    double P[32], S[32], l1, l2, u1, u2, d1, d2, Q[2], QS[2], ext = 0.0;
    bsfit_curve c1, c2;
    bsfit_status st;
    bsfit_err e2;
    for (k = 0; k < 2 * n; k++) {
      P[k] = floor(rng_range(&r, -1024.0, 1024.0)) / 1024.0;
      S[k] = ldexp(P[k], e);
      ext = fmax(ext, fabs(S[k] - S[k % 2]));
    }
    if (ldexp(1.0, e) > BSFIT_COORD_MAX) continue;
    bsfit_curve_init(&c1);
    bsfit_curve_init(&c2);
    assert_int_equal(bsfit_curve_new(&c1, p, 2, n, NULL, P, NULL, 0, NULL, &st), BSFIT_OK);
    assert_int_equal(bsfit_curve_new(&c2, p, 2, n, NULL, S, NULL, 0, NULL, &st), BSFIT_OK);
    assert_int_equal(bsfit_curve_length(&c1, 0.0, 1.0, &l1, &st), BSFIT_OK);
    assert_int_equal(bsfit_curve_length(&c2, 0.0, 1.0, &l2, &st), BSFIT_OK);
    if (!(fabs(l2 - ldexp(l1, e)) <= 1e-12 * ldexp(l1, e)))
      fail_msg("length %g vs %g * 2^%d", l2, l1, e);
    Q[0] = 0.3;
    Q[1] = -0.2;
    QS[0] = ldexp(Q[0], e);
    QS[1] = ldexp(Q[1], e);
    assert_int_equal(bsfit_curve_closest(&c1, Q, &u1, &d1, NULL, &st), BSFIT_OK);
    e2 = bsfit_curve_closest(&c2, QS, &u2, &d2, NULL, &st);
    if (ext > 0 && ext < 1e-100) {
      assert_int_equal(e2, BSFIT_ERANGE);
    } else {
      assert_int_equal(e2, BSFIT_OK);
      assert_true(u1 == u2 && d2 == ldexp(d1, e));
    }
    bsfit_curve_free(&c1);
    bsfit_curve_free(&c2);
  }
}

/* An open curve is extrapolated by its end polynomials up to one domain length beyond
** either end, exactly (a clamped cubic on [0, 1] with x control values 0, 1, 3, 4 is
** x(u) = 3u + 3u^2 - 2u^3 everywhere); farther out the answer is BSFIT_EDOMAIN (it was
** (0, 0) at u = 1e100: the basis divided cancelled sums), never a wrong point. */
static void test_eval_extrapolation(void **state) {
  const double P[8] = {0, 0, 1, 2, 3, 1, 4, 0};
  bsfit_curve c;
  bsfit_status st;
  double y[2], ys[4], us[2] = {0.5, 7.0};
  int i;
  (void)state;
  bsfit_curve_init(&c);
  assert_int_equal(bsfit_curve_new(&c, 3, 2, 4, NULL, P, NULL, 0, NULL, &st), BSFIT_OK);
  for (i = 0; i <= 300; i++) {
    double u = -1.0 + 3.0 * i / 300.0, x = 3 * u + 3 * u * u - 2 * u * u * u;
    assert_int_equal(bsfit_curve_eval(&c, u, y, &st), BSFIT_OK);
    assert_true(fabs(y[0] - x) <= 1e-12 * fmax(1.0, fabs(x)));
  }
  for (i = 0; i < 4; i++) {
    const double far[4] = {2.0000001, -1.0000001, 1e100, -1e300};
    double d[3 * 2];
    assert_int_equal(bsfit_curve_eval(&c, far[i], y, &st), BSFIT_EDOMAIN);
    assert_int_equal(bsfit_curve_derivs(&c, far[i], 2, d, &st), BSFIT_EDOMAIN);
  }
  assert_int_equal(bsfit_curve_eval_many(&c, us, 2, ys, &st), BSFIT_EDOMAIN);
  bsfit_curve_free(&c);
}

/* }==================================================================== */

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_filter_any_delta),
      cmocka_unit_test(test_filter_uniform_merge),
      cmocka_unit_test(test_periodic_multiplicity),
      cmocka_unit_test(test_periodic_issue_case),
      cmocka_unit_test(test_fit_nonfinite_no_free),
      cmocka_unit_test(test_params_no_underflow),
      cmocka_unit_test(test_fit_huge_coordinates),
      cmocka_unit_test(test_curve_ranges),
      cmocka_unit_test(test_reverse_valid),
      cmocka_unit_test(test_ma_minimal_periodic),
      cmocka_unit_test(test_geometry_any_scale),
      cmocka_unit_test(test_geometry_scale_invariant),
      cmocka_unit_test(test_curve_measures_any_scale),
      cmocka_unit_test(test_eval_extrapolation),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
