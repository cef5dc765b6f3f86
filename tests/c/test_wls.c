/*
** test_wls.c
** Open weighted least squares: reproduction of splines from the same space, agreement
** with an independent dense normal-equation solve, weights pulling the curve, exact end
** constraints, interpolation, diagnostics, every invalid input, allocation failures and
** workspace reuse.
*/
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include "cmocka_double.h"
#include <stdlib.h>
#include <string.h>

#include "bsfit.h"
#include "testutil.h"
#include "fit_solvers.h"

#define EPS_REPRO 1e-10 /* reproduction of a spline from the same space */
#define EPS_DENSE 1e-9  /* against the dense normal equations */

/* {======================================================================
** Helpers: sampling, a dense reference solver
** ======================================================================= */

static void expect_error(bsfit_err got, bsfit_err want, const bsfit_status *st) {
  assert_int_equal(got, want);
  assert_int_equal(st->code, want);
  assert_true(strlen(st->msg) > 0);
}

/* m sorted parameters spread over [a, b], both ends included */
static void sorted_params(test_rng *r, size_t m, double a, double b, double *u) {
  size_t k;
  for (k = 0; k < m; k++) u[k] = a + (b - a) * ((double)k + rng_range(r, 0.05, 0.95)) / (double)m;
  u[0] = a;
  u[m - 1] = b;
}

static void sample(const bsfit_curve *c, const double *u, size_t m, double *pts) {
  size_t k;
  for (k = 0; k < m; k++)
    assert_int_equal(bsfit_curve_eval(c, u[k], pts + k * (size_t)c->dim, NULL), BSFIT_OK);
}

/* Gaussian elimination with partial pivoting on a dense n x n system, nrhs columns
** (row-major A, B n x nrhs row-major); independent of the library's LAPACK path. */
static void dense_solve(double *A, double *B, size_t n, size_t nrhs) {
  size_t i, j, k, c;
  for (k = 0; k < n; k++) {
    size_t piv = k;
    for (i = k + 1; i < n; i++)
      if (fabs(A[i * n + k]) > fabs(A[piv * n + k])) piv = i;
    for (j = 0; j < n; j++) {
      double t = A[k * n + j];
      A[k * n + j] = A[piv * n + j];
      A[piv * n + j] = t;
    }
    for (c = 0; c < nrhs; c++) {
      double t = B[k * nrhs + c];
      B[k * nrhs + c] = B[piv * nrhs + c];
      B[piv * nrhs + c] = t;
    }
    for (i = k + 1; i < n; i++) {
      double f = A[i * n + k] / A[k * n + k];
      for (j = k; j < n; j++) A[i * n + j] -= f * A[k * n + j];
      for (c = 0; c < nrhs; c++) B[i * nrhs + c] -= f * B[k * nrhs + c];
    }
  }
  for (k = n; k-- > 0;)
    for (c = 0; c < nrhs; c++) {
      double s = B[k * nrhs + c];
      for (j = k + 1; j < n; j++) s -= A[k * n + j] * B[j * nrhs + c];
      B[k * nrhs + c] = s / A[k * n + k];
    }
}

/* Dense reference: forms the full m x n collocation matrix N and solves
** (N^T W N) P = N^T W Q by elimination. P: n x dim row-major. */
static void dense_wls(const double *U, int p, size_t n, const double *pts, size_t m, int dim,
                      const double *u, const double *w, double *P) {
  double *Nm = calloc(m * n, sizeof(double)), *A = calloc(n * n, sizeof(double));
  double Nl[BSFIT_MAX_DEGREE + 1];
  size_t k, i, j, c, d = (size_t)dim;
  assert_non_null(Nm);
  assert_non_null(A);
  for (k = 0; k < m; k++) {
    size_t s = bsfit_knots_find_span(U, n, p, u[k]);
    bsfit_basis_funs(s, u[k], p, U, Nl);
    for (j = 0; j <= (size_t)p; j++) Nm[k * n + s - (size_t)p + j] = Nl[j];
  }
  memset(P, 0, n * d * sizeof(double));
  for (i = 0; i < n; i++) {
    for (j = 0; j < n; j++)
      for (k = 0; k < m; k++) A[i * n + j] += Nm[k * n + i] * w[k] * Nm[k * n + j];
    for (c = 0; c < d; c++)
      for (k = 0; k < m; k++) P[i * d + c] += Nm[k * n + i] * w[k] * pts[k * d + c];
  }
  dense_solve(A, P, n, d);
  free(Nm);
  free(A);
}

static void noisy_curve(test_rng *r, size_t m, double *pts, double *u, double *w) {
  size_t k;
  for (k = 0; k < m; k++) {
    double t = (double)k / (double)(m - 1);
    pts[2 * k] = cos(3.0 * t) * (1.0 + t) + rng_range(r, -0.02, 0.02);
    pts[2 * k + 1] = sin(5.0 * t) + rng_range(r, -0.02, 0.02);
    if (w) w[k] = rng_range(r, 0.2, 3.0);
  }
  assert_int_equal(bsfit_params(pts, m, 2, BSFIT_PARAM_CHORD, 0, u, NULL), BSFIT_OK);
}

/* }====================================================================== */

static void test_reproduces_spline_same_space(void **state) {
  /* given a random cubic (and quintic) spline and data sampled from it, random weights */
  test_rng r = {12345};
  int p;
  (void)state;
  for (p = 1; p <= 5; p += 2) {
    size_t n = 14, m = 300, k, d;
    double U[14 + 6], ctrl[14 * 3], *u = malloc(m * sizeof(double));
    double *pts = malloc(m * 3 * sizeof(double)), *w = malloc(m * sizeof(double)), a, b;
    bsfit_curve src, out;
    bsfit_fitter *f;
    bsfit_fit_opts o;
    bsfit_fit_report rep;
    bsfit_status st;
    for (d = 2; d <= 3; d++) {
      /* clamped, simple interior knots so every span is wide enough to hold data */
      for (k = 0; k < n + (size_t)p + 1; k++)
        U[k] = k <= (size_t)p ? 0.0 : k >= n ? (double)(n - (size_t)p) : (double)(k - (size_t)p) + rng_range(&r, -0.3, 0.3);
      for (k = 0; k < n * d; k++) ctrl[k] = rng_range(&r, -5, 5);
      bsfit_curve_init(&src);
      bsfit_curve_init(&out);
      assert_int_equal(bsfit_curve_new(&src, p, (int)d, n, U, ctrl, NULL, 0, NULL, NULL), BSFIT_OK);
      bsfit_curve_domain(&src, &a, &b);
      sorted_params(&r, m, a, b, u);
      sample(&src, u, m, pts);
      for (k = 0; k < m; k++) w[k] = rng_range(&r, 0.1, 10.0);
      opts_init(&o);
      o.degree = p;
      o.count = n;
      o.knots = U;
      o.nknots = n + (size_t)p + 1;
      assert_int_equal(bsfit_fitter_new(&f, &o, NULL, &st), BSFIT_OK);
      /* when fitted */
      assert_int_equal(bsfit_fitter_fit(f, pts, m, (int)d, u, w, &out, &rep, NULL, &st), BSFIT_OK);
      /* then the control points are recovered */
      for (k = 0; k < n * d; k++) assert_float_equal(out.ctrl[k], ctrl[k], EPS_REPRO);
      assert_true(rep.max < EPS_REPRO);
      assert_true(rep.rcond > 0.0 && rep.rcond <= 1.0);
      assert_int_equal(rep.n_empty_spans, 0);
      bsfit_fitter_free(f);
      bsfit_curve_free(&src);
      bsfit_curve_free(&out);
    }
    free(u);
    free(pts);
    free(w);
  }
}

static void test_matches_dense_normal_equations(void **state) {
  /* given noisy weighted data, averaging knots, degrees 2..4 */
  test_rng r = {777};
  size_t m = 90, n = 11, k;
  double pts[90 * 2], u[90], w[90], P[11 * 2];
  int p;
  (void)state;
  noisy_curve(&r, m, pts, u, w);
  for (p = 2; p <= 4; p++) {
    bsfit_fit_opts o;
    bsfit_fitter *f;
    bsfit_curve out;
    size_t nk;
    const double *U;
    opts_init(&o);
    o.degree = p;
    o.count = n;
    bsfit_curve_init(&out);
    assert_int_equal(bsfit_fitter_new(&f, &o, NULL, NULL), BSFIT_OK);
    assert_int_equal(bsfit_fitter_fit(f, pts, m, 2, u, w, &out, NULL, NULL, NULL), BSFIT_OK);
    U = bsfit_fitter_knots(f, &nk);
    assert_non_null(U);
    assert_int_equal(nk, n + (size_t)p + 1);
    /* then the coefficients agree with the dense solve */
    dense_wls(U, p, n, pts, m, 2, u, w, P);
    for (k = 0; k < n * 2; k++) assert_float_equal(out.ctrl[k], P[k], EPS_DENSE);
    bsfit_fitter_free(f);
    bsfit_curve_free(&out);
  }
}

/* The exact reciprocal 1-norm condition number of rows/columns lo..hi-1 of the dense
** normal matrix N^T W N, through a dense inverse (dense_solve on the identity). */
static double exact_rcond(const double *U, int p, size_t n, const double *u, const double *w,
                          size_t m, size_t lo, size_t hi) {
  size_t nf = hi - lo, i, j, k;
  double *A = calloc(nf * nf, sizeof(double)), *I = calloc(nf * nf, sizeof(double));
  double Nl[BSFIT_MAX_DEGREE + 1], an = 0.0, in = 0.0;
  assert_non_null(A);
  assert_non_null(I);
  for (k = 0; k < m; k++) {
    size_t s = bsfit_knots_find_span(U, n, p, u[k]);
    bsfit_basis_funs(s, u[k], p, U, Nl);
    for (i = 0; i <= (size_t)p; i++)
      for (j = 0; j <= (size_t)p; j++) {
        size_t a = s - (size_t)p + i, b = s - (size_t)p + j;
        if (a >= lo && a < hi && b >= lo && b < hi) A[(a - lo) * nf + (b - lo)] += w[k] * Nl[i] * Nl[j];
      }
  }
  for (j = 0; j < nf; j++) {
    double cs = 0.0;
    for (i = 0; i < nf; i++) cs += fabs(A[i * nf + j]);
    if (cs > an) an = cs;
    I[j * nf + j] = 1.0;
  }
  dense_solve(A, I, nf, nf);
  for (j = 0; j < nf; j++) {
    double cs = 0.0;
    for (i = 0; i < nf; i++) cs += fabs(I[i * nf + j]);
    if (cs > in) in = cs;
  }
  free(A);
  free(I);
  return 1.0 / (an * in);
}

static void test_rcond_is_exact(void **state) {
  /* given weighted data, degrees 1..5, sorted or shuffled parameters, free or fixed ends,
  ** when fitted, then the reported rcond is the exact 1-norm reciprocal condition number of
  ** the normal matrix of the free unknowns (the matrix is totally nonnegative, so one solve
  ** gives |A^-1|_1 exactly; see linalg.c) */
  test_rng r = {1357};
  size_t m = 120, n = 14, k;
  double pts[120 * 2], u[120], w[120];
  int p, shuffled, fixed;
  (void)state;
  noisy_curve(&r, m, pts, u, w);
  for (p = 1; p <= 5; p++)
    for (shuffled = 0; shuffled <= 1; shuffled++)
      for (fixed = 0; fixed <= 1; fixed++) {
        bsfit_fit_opts o;
        bsfit_fitter *f;
        bsfit_curve out;
        bsfit_fit_report rep;
        double spts[120 * 2], su[120], sw[120], want;
        const double *U;
        if (shuffled) { /* the same points in another order: the same normal matrix */
          for (k = 0; k < m; k++) {
            size_t j = (k * 37) % m; /* 37 is prime to 120: a permutation */
            spts[2 * k] = pts[2 * j], spts[2 * k + 1] = pts[2 * j + 1];
            su[k] = u[j], sw[k] = w[j];
          }
        } else {
          memcpy(spts, pts, sizeof pts), memcpy(su, u, sizeof u), memcpy(sw, w, sizeof w);
        }
        opts_init(&o);
        o.degree = p;
        o.count = n;
        o.fix_ends = fixed;
        bsfit_curve_init(&out);
        assert_int_equal(bsfit_fitter_new(&f, &o, NULL, NULL), BSFIT_OK);
        if (shuffled) { /* knots from the sorted parameters, fixed for the shuffled fit */
          bsfit_fitter *g;
          size_t nk;
          bsfit_curve tmp;
          bsfit_curve_init(&tmp);
          assert_int_equal(bsfit_fitter_new(&g, &o, NULL, NULL), BSFIT_OK);
          assert_int_equal(bsfit_fitter_fit(g, pts, m, 2, u, w, &tmp, NULL, NULL, NULL), BSFIT_OK);
          o.knots = bsfit_fitter_knots(g, &nk);
          o.nknots = nk;
          o.fix_ends = 0; /* fixed ends take the first and last point: not permutable */
          assert_int_equal(bsfit_fitter_configure(f, &o, NULL), BSFIT_OK);
          bsfit_fitter_free(g);
          bsfit_curve_free(&tmp);
        }
        assert_int_equal(bsfit_fitter_fit(f, spts, m, 2, su, sw, &out, &rep, NULL, NULL), BSFIT_OK);
        U = out.knots;
        want = exact_rcond(U, p, n, su, sw, m, o.fix_ends ? 1 : 0, o.fix_ends ? n - 1 : n);
        assert_float_equal(rep.rcond, want, 1e-9 * want);
        bsfit_fitter_free(f);
        bsfit_curve_free(&out);
      }
}

static void test_weight_pulls_curve(void **state) {
  test_rng r = {99};
  size_t m = 60, k, idx[] = {7, 30, 52}, t;
  double pts[60 * 2], u[60], w[60], res0[60], res1[60];
  bsfit_fit_opts o;
  bsfit_fitter *f;
  bsfit_curve out;
  (void)state;
  noisy_curve(&r, m, pts, u, w);
  for (k = 0; k < m; k++) pts[2 * k + 1] += (k % 5 == 0) ? 0.2 : 0.0; /* outliers */
  opts_init(&o);
  o.count = 8;
  bsfit_curve_init(&out);
  assert_int_equal(bsfit_fitter_new(&f, &o, NULL, NULL), BSFIT_OK);
  for (t = 0; t < 3; t++) {
    size_t i = idx[t];
    double keep = w[i];
    assert_int_equal(bsfit_fitter_fit(f, pts, m, 2, u, w, &out, NULL, res0, NULL), BSFIT_OK);
    /* when one point's weight grows */
    w[i] *= 100.0;
    assert_int_equal(bsfit_fitter_fit(f, pts, m, 2, u, w, &out, NULL, res1, NULL), BSFIT_OK);
    /* then its residual drops */
    assert_true(res1[i] < res0[i]);
    w[i] = keep;
  }
  bsfit_fitter_free(f);
  bsfit_curve_free(&out);
}

static void test_fixed_ends_and_tangents(void **state) {
  test_rng r = {4242};
  size_t m = 80, k;
  double pts[80 * 2], u[80], w[80], T0[2] = {1.5, -2.0}, T1[2] = {-0.5, 3.0}, x[2], a, b;
  double ders[2 * 4];
  bsfit_fit_opts o;
  bsfit_fitter *f;
  bsfit_curve out;
  bsfit_fit_report rep, free_rep;
  (void)state;
  noisy_curve(&r, m, pts, u, w);
  bsfit_curve_init(&out);
  opts_init(&o);
  o.count = 10;
  /* unconstrained reference: its weighted error can only be lower */
  assert_int_equal(bsfit_fitter_new(&f, &o, NULL, NULL), BSFIT_OK);
  assert_int_equal(bsfit_fitter_fit(f, pts, m, 2, u, w, &out, &free_rep, NULL, NULL), BSFIT_OK);
  bsfit_fitter_free(f);
  /* given fixed ends */
  o.fix_ends = 1;
  assert_int_equal(bsfit_fitter_new(&f, &o, NULL, NULL), BSFIT_OK);
  assert_int_equal(bsfit_fitter_fit(f, pts, m, 2, u, w, &out, &rep, NULL, NULL), BSFIT_OK);
  /* then the curve's ends are the data's ends, exactly */
  bsfit_curve_domain(&out, &a, &b);
  assert_int_equal(bsfit_curve_eval(&out, a, x, NULL), BSFIT_OK);
  assert_true(x[0] == pts[0] && x[1] == pts[1]);
  assert_int_equal(bsfit_curve_eval(&out, b, x, NULL), BSFIT_OK);
  assert_true(x[0] == pts[2 * (m - 1)] && x[1] == pts[2 * (m - 1) + 1]);
  assert_true(rep.rms >= free_rep.rms);
  bsfit_fitter_free(f);
  /* given end tangents (derivative vectors) */
  o.tangent_start = T0;
  o.tangent_end = T1;
  o.tangent_dim = 2;
  assert_int_equal(bsfit_fitter_new(&f, &o, NULL, NULL), BSFIT_OK);
  assert_int_equal(bsfit_fitter_fit(f, pts, m, 2, u, w, &out, &rep, NULL, NULL), BSFIT_OK);
  /* then C'(a) = T0 and C'(b) = T1 (derivatives from bsfit_basis_ders) */
  {
    size_t s0 = bsfit_knots_find_span(out.knots, out.n, 3, a);
    size_t s1 = bsfit_knots_find_span(out.knots, out.n, 3, b);
    double d0[2] = {0, 0}, d1[2] = {0, 0};
    bsfit_basis_ders(s0, a, 3, 1, out.knots, ders);
    for (k = 0; k < 4; k++) {
      d0[0] += ders[4 + k] * out.ctrl[(s0 - 3 + k) * 2];
      d0[1] += ders[4 + k] * out.ctrl[(s0 - 3 + k) * 2 + 1];
    }
    bsfit_basis_ders(s1, b, 3, 1, out.knots, ders);
    for (k = 0; k < 4; k++) {
      d1[0] += ders[4 + k] * out.ctrl[(s1 - 3 + k) * 2];
      d1[1] += ders[4 + k] * out.ctrl[(s1 - 3 + k) * 2 + 1];
    }
    assert_float_equal(d0[0], T0[0], 1e-12);
    assert_float_equal(d0[1], T0[1], 1e-12);
    assert_float_equal(d1[0], T1[0], 1e-12);
    assert_float_equal(d1[1], T1[1], 1e-12);
  }
  assert_true(out.ctrl[0] == pts[0] && out.ctrl[1] == pts[1]);
  bsfit_fitter_free(f);
  bsfit_curve_free(&out);
}

static void test_constraints_keep_exact_spline(void **state) {
  /* given data from a cubic spline and its true end points and derivatives, the
  ** constrained fit still reproduces it (the constraints are consistent with the data) */
  test_rng r = {31};
  const size_t n = 9, m = 120;
  double U[13], ctrl[18], u[120], pts[240], T0[2], T1[2], a, b, ders[8];
  size_t k, s;
  bsfit_curve src, out;
  bsfit_fit_opts o;
  bsfit_fitter *f;
  (void)state;
  bsfit_curve_init(&src);
  bsfit_curve_init(&out);
  for (k = 0; k < 18; k++) ctrl[k] = rng_range(&r, -3, 3);
  assert_int_equal(bsfit_curve_new(&src, 3, 2, n, NULL, ctrl, NULL, 0, NULL, NULL), BSFIT_OK);
  memcpy(U, src.knots, sizeof U);
  bsfit_curve_domain(&src, &a, &b);
  sorted_params(&r, m, a, b, u);
  sample(&src, u, m, pts);
  s = bsfit_knots_find_span(U, n, 3, a);
  bsfit_basis_ders(s, a, 3, 1, U, ders);
  T0[0] = T0[1] = T1[0] = T1[1] = 0.0;
  for (k = 0; k < 4; k++) {
    T0[0] += ders[4 + k] * ctrl[(s - 3 + k) * 2];
    T0[1] += ders[4 + k] * ctrl[(s - 3 + k) * 2 + 1];
  }
  s = bsfit_knots_find_span(U, n, 3, b);
  bsfit_basis_ders(s, b, 3, 1, U, ders);
  for (k = 0; k < 4; k++) {
    T1[0] += ders[4 + k] * ctrl[(s - 3 + k) * 2];
    T1[1] += ders[4 + k] * ctrl[(s - 3 + k) * 2 + 1];
  }
  opts_init(&o);
  o.count = n;
  o.knots = U;
  o.nknots = 13;
  o.fix_ends = 1;
  o.tangent_start = T0;
  o.tangent_end = T1;
  o.tangent_dim = 2;
  assert_int_equal(bsfit_fitter_new(&f, &o, NULL, NULL), BSFIT_OK);
  assert_int_equal(bsfit_fitter_fit(f, pts, m, 2, u, NULL, &out, NULL, NULL, NULL), BSFIT_OK);
  for (k = 0; k < 18; k++) assert_float_equal(out.ctrl[k], ctrl[k], EPS_REPRO);
  bsfit_fitter_free(f);
  bsfit_curve_free(&src);
  bsfit_curve_free(&out);
}

static void test_report_matches_residuals(void **state) {
  test_rng r = {5};
  size_t m = 70, k, imax = 0;
  double pts[140], u[70], w[70], res[70], x[2], ss = 0, ws = 0, mx = -1;
  bsfit_fit_opts o;
  bsfit_fitter *f;
  bsfit_curve out;
  bsfit_fit_report rep;
  (void)state;
  noisy_curve(&r, m, pts, u, w);
  opts_init(&o);
  o.count = 9;
  bsfit_curve_init(&out);
  assert_int_equal(bsfit_fitter_new(&f, &o, NULL, NULL), BSFIT_OK);
  assert_int_equal(bsfit_fitter_fit(f, pts, m, 2, u, w, &out, &rep, res, NULL), BSFIT_OK);
  /* then each residual is the distance to the curve evaluated independently */
  for (k = 0; k < m; k++) {
    double d;
    assert_int_equal(bsfit_curve_eval(&out, u[k], x, NULL), BSFIT_OK);
    d = hypot(pts[2 * k] - x[0], pts[2 * k + 1] - x[1]);
    assert_float_equal(res[k], d, 1e-13);
    ss += w[k] * d * d;
    ws += w[k];
    if (d > mx) mx = d, imax = k;
  }
  assert_float_equal(rep.rms, sqrt(ss / ws), 1e-13);
  assert_float_equal(rep.max, mx, 1e-13);
  assert_int_equal(rep.max_index, imax);
  assert_int_equal(rep.m, m);
  assert_true(rep.rcond > 0.0 && rep.rcond < 1.0);
  bsfit_fitter_free(f);
  bsfit_curve_free(&out);
}

static void test_invalid_inputs(void **state) {
  test_rng r = {8};
  size_t m = 40, k;
  double pts[80], u[40], w[40], keep;
  bsfit_fit_opts o;
  bsfit_fitter *f;
  bsfit_curve out;
  bsfit_status st;
  (void)state;
  noisy_curve(&r, m, pts, u, w);
  bsfit_curve_init(&out);
  opts_init(&o);
  /* fitter settings */
  o.count = 3;
  expect_error(bsfit_fitter_new(&f, &o, NULL, &st), BSFIT_EDEGREE, &st); /* degree >= count */
  assert_null(f);
  o.count = 8;
  o.degree = 0;
  expect_error(bsfit_fitter_new(&f, &o, NULL, &st), BSFIT_EDEGREE, &st);
  o.degree = 3;
  o.rule = (bsfit_knot_rule)99;
  expect_error(bsfit_fitter_new(&f, &o, NULL, &st), BSFIT_EINVAL, &st);
  o.rule = BSFIT_KNOTS_AVERAGING;
  o.periodic = 1;
  o.fix_ends = 1;
  expect_error(bsfit_fitter_new(&f, &o, NULL, &st), BSFIT_EINVAL, &st);
  o.periodic = 0;
  o.count = 3;
  o.degree = 2;
  o.tangent_start = w;
  o.tangent_end = w;
  o.tangent_dim = 2;
  expect_error(bsfit_fitter_new(&f, &o, NULL, &st), BSFIT_EINVAL, &st); /* 4 fixed > 3 */
  o.tangent_dim = 7;
  o.count = 8;
  expect_error(bsfit_fitter_new(&f, &o, NULL, &st), BSFIT_EINVAL, &st);
  expect_error(bsfit_fitter_new(&f, NULL, NULL, &st), BSFIT_EINVAL, &st);
  expect_error(bsfit_fitter_new(NULL, &o, NULL, &st), BSFIT_EINVAL, &st);
  {
    /* unclamped fixed knots with fixed ends; wrong knot count; decreasing knots */
    double U[12];
    opts_init(&o);
    o.count = 8;
    o.fix_ends = 1;
    for (k = 0; k < 12; k++) U[k] = (double)k;
    o.knots = U;
    o.nknots = 12;
    expect_error(bsfit_fitter_new(&f, &o, NULL, &st), BSFIT_EINVAL, &st);
    o.nknots = 11;
    expect_error(bsfit_fitter_new(&f, &o, NULL, &st), BSFIT_ENKNOTS, &st);
    o.nknots = 12;
    o.fix_ends = 0;
    U[5] = 1.0;
    expect_error(bsfit_fitter_new(&f, &o, NULL, &st), BSFIT_EKNOTS_DECR, &st);
  }
  opts_init(&o);
  o.count = 8;
  o.tangent_start = w;
  o.tangent_dim = 3;
  assert_int_equal(bsfit_fitter_new(&f, &o, NULL, &st), BSFIT_OK);
  expect_error(bsfit_fitter_fit(f, pts, m, 2, u, w, &out, NULL, NULL, &st), BSFIT_EDIM, &st);
  bsfit_fitter_free(f);
  o.tangent_start = NULL;
  assert_int_equal(bsfit_fitter_new(&f, &o, NULL, &st), BSFIT_OK);
  /* fit inputs */
  expect_error(bsfit_fitter_fit(f, NULL, m, 2, u, w, &out, NULL, NULL, &st), BSFIT_EINVAL, &st);
  expect_error(bsfit_fitter_fit(f, pts, m, 2, NULL, w, &out, NULL, NULL, &st), BSFIT_EINVAL, &st);
  expect_error(bsfit_fitter_fit(f, pts, m, 2, u, w, NULL, NULL, NULL, &st), BSFIT_EINVAL, &st);
  expect_error(bsfit_fitter_fit(f, pts, m, 5, u, w, &out, NULL, NULL, &st), BSFIT_EDIM, &st);
  expect_error(bsfit_fitter_fit(f, pts, m, 0, u, w, &out, NULL, NULL, &st), BSFIT_EDIM, &st);
  expect_error(bsfit_fitter_fit(f, pts, 7, 2, u, w, &out, NULL, NULL, &st), BSFIT_ETOOFEW, &st);
  keep = pts[33];
  pts[33] = NAN;
  expect_error(bsfit_fitter_fit(f, pts, m, 2, u, w, &out, NULL, NULL, &st), BSFIT_ENONFINITE, &st);
  pts[33] = INFINITY;
  expect_error(bsfit_fitter_fit(f, pts, m, 2, u, w, &out, NULL, NULL, &st), BSFIT_ENONFINITE, &st);
  pts[33] = keep;
  /* a non-finite parameter: rule-based knots reject it first */
  keep = u[20];
  u[20] = NAN;
  expect_error(bsfit_fitter_fit(f, pts, m, 2, u, w, &out, NULL, NULL, &st), BSFIT_ENONFINITE, &st);
  u[20] = keep;
  { /* with fixed knots the parameter reaches the fitter's own pass: NaN, +-Inf */
    bsfit_fit_opts fo = o;
    bsfit_fitter *g;
    double U[12], bad[] = {NAN, INFINITY, -INFINITY};
    assert_int_equal(bsfit_fitter_fit(f, pts, m, 2, u, w, &out, NULL, NULL, &st), BSFIT_OK);
    memcpy(U, bsfit_fitter_knots(f, NULL), sizeof U);
    fo.knots = U;
    fo.nknots = 12;
    assert_int_equal(bsfit_fitter_new(&g, &fo, NULL, &st), BSFIT_OK);
    for (k = 0; k < 3; k++) {
      u[20] = bad[k];
      expect_error(bsfit_fitter_fit(g, pts, m, 2, u, w, &out, NULL, NULL, &st), BSFIT_ENONFINITE,
                   &st);
      assert_non_null(strstr(st.msg, "parameter 20"));
    }
    u[20] = keep;
    bsfit_fitter_free(g);
  }
  for (k = 0; k < 5; k++) { /* 1e-320: subnormal, the sums would keep too few of its digits */
    const double bad[] = {0.0, -1.0, NAN, INFINITY, 1e-320};
    keep = w[11];
    w[11] = bad[k];
    expect_error(bsfit_fitter_fit(f, pts, m, 2, u, w, &out, NULL, NULL, &st), BSFIT_EWEIGHT, &st);
    assert_null(out.ctrl); /* nothing half-written is left behind */
    w[11] = keep;
  }
  {
    double same[80];
    for (k = 0; k < 80; k++) same[k] = (k % 2) ? 2.5 : -1.0;
    expect_error(bsfit_fitter_fit(f, same, m, 2, u, w, &out, NULL, NULL, &st), BSFIT_EDEGENERATE,
                 &st);
  }
  /* after failures, a good fit works and is finite */
  assert_int_equal(bsfit_fitter_fit(f, pts, m, 2, u, w, &out, NULL, NULL, &st), BSFIT_OK);
  for (k = 0; k < out.n * 2; k++) assert_true(isfinite(out.ctrl[k]));
  bsfit_fitter_free(f);
  bsfit_curve_free(&out);
}

static void test_empty_span_is_reported(void **state) {
  /* given fixed linear knots whose last two spans hold no data */
  const double U[] = {0, 0, 1, 2, 3, 3};
  double pts[20], u[10], w[10];
  size_t k;
  bsfit_fit_opts o;
  bsfit_fitter *f;
  bsfit_curve out;
  bsfit_status st;
  (void)state;
  for (k = 0; k < 10; k++) {
    u[k] = 0.1 * (double)k;
    pts[2 * k] = u[k];
    pts[2 * k + 1] = u[k] * u[k];
    w[k] = 1.0;
  }
  opts_init(&o);
  o.degree = 1;
  o.count = 4;
  o.knots = U;
  o.nknots = 6;
  bsfit_curve_init(&out);
  assert_int_equal(bsfit_fitter_new(&f, &o, NULL, NULL), BSFIT_OK);
  expect_error(bsfit_fitter_fit(f, pts, 10, 2, u, w, &out, NULL, NULL, &st), BSFIT_EEMPTYSPAN, &st);
  assert_non_null(strstr(st.msg, "span 2"));
  assert_null(out.ctrl);
  {
    size_t spans[4], count;
    assert_int_equal(bsfit_knots_empty_spans(U, 6, 1, 0, u, 10, spans, 4, &count, NULL), BSFIT_OK);
    assert_int_equal(count, 2);
    assert_int_equal(spans[0], 2);
    assert_int_equal(spans[1], 3);
  }
  bsfit_fitter_free(f);
}

static void test_reused_fitter_matches_fresh(void **state) {
  /* given one fitter refitting with parameters whose knots differ, the same again, and
  ** parameters it rejects in between, when each fit is compared with a fresh fitter's,
  ** then they are identical: the per-span data kept while the knots do not move is
  ** never stale (open and periodic) */
  test_rng r = {4711};
  size_t m = 100, k;
  double pts[200], u[3][100], w[100], bad[100];
  int periodic, i;
  (void)state;
  noisy_curve(&r, m, pts, u[0], w);
  for (periodic = 0; periodic <= 1; periodic++) {
    bsfit_fit_opts o;
    bsfit_fitter *f;
    bsfit_curve out;
    bsfit_param_kind kinds[3] = {BSFIT_PARAM_CHORD, BSFIT_PARAM_CENTRIPETAL, BSFIT_PARAM_CHORD};
    int order[5] = {0, 1, 1, 2, 0};
    for (i = 0; i < 3; i++)
      assert_int_equal(bsfit_params(pts, m, 2, kinds[i], periodic, u[i], NULL), BSFIT_OK);
    memcpy(bad, u[0], sizeof bad);
    bad[50] = bad[10]; /* decreasing: the knot placement rejects it */
    opts_init(&o);
    o.count = 12;
    o.periodic = periodic;
    bsfit_curve_init(&out);
    assert_int_equal(bsfit_fitter_new(&f, &o, NULL, NULL), BSFIT_OK);
    for (i = 0; i < 5; i++) {
      bsfit_fitter *g;
      bsfit_curve ref;
      const double *uu = u[order[i]];
      if (i == 3)
        assert_int_not_equal(bsfit_fitter_fit(f, pts, m, 2, bad, w, &out, NULL, NULL, NULL), BSFIT_OK);
      assert_int_equal(bsfit_fitter_fit(f, pts, m, 2, uu, w, &out, NULL, NULL, NULL), BSFIT_OK);
      bsfit_curve_init(&ref);
      assert_int_equal(bsfit_fitter_new(&g, &o, NULL, NULL), BSFIT_OK);
      assert_int_equal(bsfit_fitter_fit(g, pts, m, 2, uu, w, &ref, NULL, NULL, NULL), BSFIT_OK);
      assert_int_equal(out.n, ref.n);
      for (k = 0; k < ref.n * 2; k++) assert_float_equal(out.ctrl[k], ref.ctrl[k], 0.0);
      bsfit_curve_free(&ref);
      bsfit_fitter_free(g);
    }
    bsfit_curve_free(&out);
    bsfit_fitter_free(f);
  }
}

static void test_reconfigure_and_reuse(void **state) {
  test_rng r = {61};
  size_t m = 100;
  long before;
  double pts[200], u[100], w[100];
  counting ca = {0, 0, 0};
  bsfit_allocator al = {counting_alloc, &ca, NULL};
  bsfit_fit_opts o;
  bsfit_fitter *f;
  bsfit_curve out;
  bsfit_status st;
  (void)state;
  noisy_curve(&r, m, pts, u, w);
  bsfit_curve_init(&out);
  opts_init(&o);
  o.count = 10;
  assert_int_equal(bsfit_fitter_new(&f, &o, &al, &st), BSFIT_OK);
  assert_int_equal(bsfit_fitter_fit(f, pts, m, 2, u, w, &out, NULL, NULL, &st), BSFIT_OK);
  /* when refitted with the same shape: no allocation at all */
  before = ca.calls;
  assert_int_equal(bsfit_fitter_fit(f, pts, m, 2, u, w, &out, NULL, NULL, &st), BSFIT_OK);
  assert_int_equal(ca.calls, before);
  /* a failed reconfiguration keeps the old settings */
  o.count = 2;
  expect_error(bsfit_fitter_configure(f, &o, &st), BSFIT_EDEGREE, &st);
  assert_int_equal(bsfit_fitter_fit(f, pts, m, 2, u, w, &out, NULL, NULL, &st), BSFIT_OK);
  assert_int_equal(out.n, 10);
  /* reconfigured with another count, and to a periodic fit */
  o.count = 17;
  assert_int_equal(bsfit_fitter_configure(f, &o, &st), BSFIT_OK);
  assert_int_equal(bsfit_fitter_fit(f, pts, m, 2, u, w, &out, NULL, NULL, &st), BSFIT_OK);
  assert_int_equal(out.n, 17);
  o.periodic = 1;
  assert_int_equal(bsfit_fitter_configure(f, &o, &st), BSFIT_OK);
  {
    double uc[100];
    assert_int_equal(bsfit_params(pts, m, 2, BSFIT_PARAM_CHORD, 1, uc, NULL), BSFIT_OK);
    assert_int_equal(bsfit_fitter_fit(f, pts, m, 2, uc, w, &out, NULL, NULL, &st), BSFIT_OK);
  }
  assert_int_equal(bsfit_curve_distinct(&out), 17);
  bsfit_curve_free(&out);
  bsfit_fitter_free(f);
  assert_int_equal(ca.live, 0);
}

static void test_allocation_failures(void **state) {
  test_rng r = {62};
  size_t m = 50, nth;
  double pts[100], u[50], w[50];
  (void)state;
  noisy_curve(&r, m, pts, u, w);
  /* every allocation of new + fit fails in turn: ENOMEM, nothing leaks */
  for (nth = 1;; nth++) {
    counting ca = {0, (long)nth, 0};
    bsfit_allocator al = {counting_alloc, &ca, NULL};
    bsfit_fit_opts o;
    bsfit_fitter *f = NULL;
    bsfit_curve out;
    bsfit_err e;
    opts_init(&o);
    o.count = 9;
    bsfit_curve_init(&out);
    e = bsfit_fitter_new(&f, &o, &al, NULL);
    if (e == BSFIT_OK) e = bsfit_fitter_fit(f, pts, m, 2, u, w, &out, NULL, NULL, NULL);
    bsfit_curve_free(&out);
    bsfit_fitter_free(f);
    assert_int_equal(ca.live, 0);
    if (e == BSFIT_OK) break;
    assert_int_equal(e, BSFIT_ENOMEM);
  }
  assert_true(nth > 2);
}

static void test_interpolation_open(void **state) {
  test_rng r = {3};
  size_t m = 25, k;
  double pts[75], u[25], x[3];
  int p;
  bsfit_curve out;
  bsfit_status st;
  (void)state;
  for (k = 0; k < m; k++) {
    pts[3 * k] = (double)k + rng_range(&r, -0.3, 0.3);
    pts[3 * k + 1] = rng_range(&r, -1, 1);
    pts[3 * k + 2] = rng_range(&r, -1, 1);
  }
  assert_int_equal(bsfit_params(pts, m, 3, BSFIT_PARAM_CENTRIPETAL, 0, u, NULL), BSFIT_OK);
  bsfit_curve_init(&out);
  for (p = 1; p <= 5; p++) {
    assert_int_equal(bsfit_interpolate(pts, m, 3, u, p, 0, &out, NULL, &st), BSFIT_OK);
    assert_int_equal(out.n, m);
    /* then the curve passes through every point at its parameter */
    for (k = 0; k < m; k++) {
      assert_int_equal(bsfit_curve_eval(&out, u[k], x, NULL), BSFIT_OK);
      assert_float_equal(x[0], pts[3 * k], 1e-11);
      assert_float_equal(x[1], pts[3 * k + 1], 1e-11);
      assert_float_equal(x[2], pts[3 * k + 2], 1e-11);
    }
    /* and its interior knots are the averages of eq. 9.8 */
    {
      double avg = 0.0;
      int i;
      for (i = 1; i <= p; i++) avg += u[i];
      assert_float_equal(out.knots[p + 1], avg / p, EPS_KNOT);
    }
  }
  /* invalid: repeated parameter, degree too high, NaN */
  u[4] = u[3];
  expect_error(bsfit_interpolate(pts, m, 3, u, 3, 0, &out, NULL, &st), BSFIT_EINVAL, &st);
  assert_null(out.ctrl);
  expect_error(bsfit_interpolate(pts, 3, 3, u, 3, 0, &out, NULL, &st), BSFIT_EDEGREE, &st);
  pts[5] = NAN;
  expect_error(bsfit_interpolate(pts, m, 3, u, 3, 0, &out, NULL, &st), BSFIT_ENONFINITE, &st);
  expect_error(bsfit_interpolate(pts, m, 0, u, 3, 0, &out, NULL, &st), BSFIT_EDIM, &st);
  expect_error(bsfit_interpolate(NULL, m, 3, u, 3, 0, &out, NULL, &st), BSFIT_EINVAL, &st);
}

int main(void) {
  const struct CMUnitTest tests[] = {
    cmocka_unit_test(test_reproduces_spline_same_space),
    cmocka_unit_test(test_matches_dense_normal_equations),
    cmocka_unit_test(test_rcond_is_exact),
    cmocka_unit_test(test_weight_pulls_curve),
    cmocka_unit_test(test_fixed_ends_and_tangents),
    cmocka_unit_test(test_constraints_keep_exact_spline),
    cmocka_unit_test(test_report_matches_residuals),
    cmocka_unit_test(test_invalid_inputs),
    cmocka_unit_test(test_empty_span_is_reported),
    cmocka_unit_test(test_reconfigure_and_reuse),
    cmocka_unit_test(test_reused_fitter_matches_fresh),
    cmocka_unit_test(test_allocation_failures),
    cmocka_unit_test(test_interpolation_open),
  };
  return run_with_each_solver(tests);
}
