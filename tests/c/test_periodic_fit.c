/*
** test_periodic_fit.c
** Periodic weighted least squares: reproduction of periodic splines, agreement with a
** dense normal-equation solve over the folded collocation matrix, C^{p-1} continuity at
** the seam, comparison with the paper's open-fit-then-wrap closing, periodic
** interpolation and invalid inputs.
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

#define EPS_REPRO 1e-10
#define EPS_DENSE 1e-9

static void expect_error(bsfit_err got, bsfit_err want, const bsfit_status *st) {
  assert_int_equal(got, want);
  assert_int_equal(st->code, want);
  assert_true(strlen(st->msg) > 0);
}

/* Dense Cholesky solve of an SPD n x n system (row-major), nrhs columns in B. */
static void dense_chol_solve(double *A, double *B, size_t n, size_t nrhs) {
  size_t i, j, k, c;
  for (j = 0; j < n; j++) {
    double s = A[j * n + j];
    for (k = 0; k < j; k++) s -= A[j * n + k] * A[j * n + k];
    assert_true(s > 0.0);
    A[j * n + j] = sqrt(s);
    for (i = j + 1; i < n; i++) {
      double t = A[i * n + j];
      for (k = 0; k < j; k++) t -= A[i * n + k] * A[j * n + k];
      A[i * n + j] = t / A[j * n + j];
    }
  }
  for (c = 0; c < nrhs; c++) {
    for (i = 0; i < n; i++) {
      double t = B[i * nrhs + c];
      for (k = 0; k < i; k++) t -= A[i * n + k] * B[k * nrhs + c];
      B[i * nrhs + c] = t / A[i * n + i];
    }
    for (i = n; i-- > 0;) {
      double t = B[i * nrhs + c];
      for (k = i + 1; k < n; k++) t -= A[k * n + i] * B[k * nrhs + c];
      B[i * nrhs + c] = t / A[i * n + i];
    }
  }
}

/* Dense reference for a periodic fit on the expanded knots U (N distinct control points):
** collocation columns of wrapped control points are folded (column j+N onto j). */
/* The folded m x N collocation matrix (row-major, calloc'ed) and, in A (N x N, zeroed by
** the caller), the normal matrix N^T W N. */
static double *folded_collocation(const double *U, int p, size_t N, const double *u, size_t m,
                                  const double *w, double *A) {
  double *Nm = calloc(m * N, sizeof(double)), Nl[BSFIT_MAX_DEGREE + 1], a = U[p],
         b = U[N + (size_t)p];
  size_t k, i, j;
  assert_non_null(Nm);
  for (k = 0; k < m; k++) {
    double x = u[k];
    size_t s;
    while (x < a) x += b - a;
    while (x >= b) x -= b - a;
    s = bsfit_knots_find_span(U, N + (size_t)p, p, x);
    bsfit_basis_funs(s, x, p, U, Nl);
    for (j = 0; j <= (size_t)p; j++) Nm[k * N + (s - (size_t)p + j) % N] += Nl[j];
  }
  for (i = 0; i < N; i++)
    for (j = 0; j < N; j++)
      for (k = 0; k < m; k++) A[i * N + j] += Nm[k * N + i] * w[k] * Nm[k * N + j];
  return Nm;
}

static void dense_periodic(const double *U, int p, size_t N, const double *pts, size_t m,
                           const double *u, const double *w, double *P) {
  double *A = calloc(N * N, sizeof(double)), *Nm = folded_collocation(U, p, N, u, m, w, A);
  size_t k, i, c;
  memset(P, 0, N * 2 * sizeof(double));
  for (i = 0; i < N; i++) {
    for (c = 0; c < 2; c++)
      for (k = 0; k < m; k++) P[i * 2 + c] += Nm[k * N + i] * w[k] * pts[k * 2 + c];
  }
  dense_chol_solve(A, P, N, 2);
  free(Nm);
  free(A);
}

/* A noisy closed shape (a lobed ellipse), closed chord parameters, random weights. */
static void noisy_closed(test_rng *r, size_t m, double noise, double *pts, double *u, double *w) {
  size_t k;
  for (k = 0; k < m; k++) {
    double t = 6.283185307179586 * (double)k / (double)m, rad = 1.0 + 0.3 * cos(3.0 * t);
    pts[2 * k] = 2.0 * rad * cos(t) + rng_range(r, -noise, noise);
    pts[2 * k + 1] = rad * sin(t) + rng_range(r, -noise, noise);
    if (w) w[k] = rng_range(r, 0.5, 2.0);
  }
  assert_int_equal(bsfit_params(pts, m, 2, BSFIT_PARAM_CHORD, 1, u, NULL), BSFIT_OK);
}

static double wsse(const bsfit_curve *c, const double *pts, const double *u, const double *w,
                   size_t m) {
  size_t k;
  double s = 0.0, x[2];
  for (k = 0; k < m; k++) {
    assert_int_equal(bsfit_curve_eval(c, u[k], x, NULL), BSFIT_OK);
    s += w[k] * ((pts[2 * k] - x[0]) * (pts[2 * k] - x[0]) +
                 (pts[2 * k + 1] - x[1]) * (pts[2 * k + 1] - x[1]));
  }
  return s;
}

static void test_reproduces_periodic_spline(void **state) {
  test_rng r = {2024};
  int p;
  size_t Ns[] = {4, 5, 7, 12, 30}, t;
  (void)state;
  for (p = 1; p <= 4; p++)
    for (t = 0; t < 5; t++) {
      size_t N = Ns[t], m = 12 * N, k;
      double period[31], ctrl[60], *u = malloc(m * sizeof(double));
      double *pts = malloc(2 * m * sizeof(double)), *w = malloc(m * sizeof(double));
      bsfit_curve src, out;
      bsfit_fit_opts o;
      bsfit_fitter *f;
      bsfit_fit_report rep;
      if (N < (size_t)p + 1) {
        free(u), free(pts), free(w);
        continue;
      }
      /* given a random periodic spline (uneven period knots starting at 0.3) */
      period[0] = 0.3;
      for (k = 1; k <= N; k++) period[k] = period[k - 1] + rng_range(&r, 0.5, 1.5);
      for (k = 0; k < 2 * N; k++) ctrl[k] = rng_range(&r, -4, 4);
      bsfit_curve_init(&src);
      bsfit_curve_init(&out);
      assert_int_equal(bsfit_curve_new_periodic(&src, p, 2, N, period, ctrl, NULL, NULL, NULL),
                       BSFIT_OK);
      /* sampled at parameters over more than one period (they wrap) */
      for (k = 0; k < m; k++) {
        u[k] = period[0] + (period[N] - period[0]) * ((double)k + rng_uniform(&r)) / (double)m;
        if (k % 7 == 3) u[k] += period[N] - period[0];
        w[k] = rng_range(&r, 0.1, 10.0);
      }
      for (k = 0; k < m; k++)
        assert_int_equal(bsfit_curve_eval(&src, u[k], pts + 2 * k, NULL), BSFIT_OK);
      opts_init(&o);
      o.degree = p;
      o.count = N;
      o.periodic = 1;
      o.knots = period;
      o.nknots = N + 1;
      assert_int_equal(bsfit_fitter_new(&f, &o, NULL, NULL), BSFIT_OK);
      assert_int_equal(bsfit_fitter_fit(f, pts, m, 2, u, w, &out, &rep, NULL, NULL), BSFIT_OK);
      /* then the N distinct control points are recovered, and the form is periodic */
      assert_int_equal(bsfit_curve_distinct(&out), N);
      assert_int_equal(bsfit_curve_validate(&out, NULL), BSFIT_OK);
      for (k = 0; k < 2 * N; k++) assert_float_equal(out.ctrl[k], ctrl[k], EPS_REPRO);
      assert_true(rep.max < EPS_REPRO);
      assert_true(rep.rcond > 0.0 && rep.rcond <= 1.0);
      bsfit_fitter_free(f);
      bsfit_curve_free(&src);
      bsfit_curve_free(&out);
      free(u), free(pts), free(w);
    }
}

static void test_matches_dense_periodic(void **state) {
  test_rng r = {55};
  size_t m = 80, N, k;
  double pts[160], u[80], w[80], P[2 * 20];
  int p;
  (void)state;
  noisy_closed(&r, m, 0.05, pts, u, w);
  for (p = 2; p <= 3; p++)
    for (N = (size_t)p + 1; N <= 20; N += 5) {
      bsfit_knot_rule rules[] = {BSFIT_KNOTS_PERIODIC_AVERAGING, BSFIT_KNOTS_CARVALHO_CLOSED};
      size_t q;
      for (q = 0; q < 2; q++) {
        bsfit_fit_opts o;
        bsfit_fitter *f;
        bsfit_curve out;
        const double *U;
        opts_init(&o);
        o.degree = p;
        o.count = N;
        o.periodic = 1;
        o.rule = rules[q];
        bsfit_curve_init(&out);
        assert_int_equal(bsfit_fitter_new(&f, &o, NULL, NULL), BSFIT_OK);
        assert_int_equal(bsfit_fitter_fit(f, pts, m, 2, u, w, &out, NULL, NULL, NULL), BSFIT_OK);
        U = bsfit_fitter_knots(f, NULL);
        dense_periodic(U, p, N, pts, m, u, w, P);
        for (k = 0; k < 2 * N; k++) assert_float_equal(out.ctrl[k], P[k], EPS_DENSE);
        bsfit_fitter_free(f);
        bsfit_curve_free(&out);
      }
    }
}

/* 1-norm of the inverse of the leading k x k block of the N x N row-major A (dense
** Gaussian elimination on the identity, independent of LAPACK) */
static double inv_norm1(const double *A, size_t N, size_t k) {
  double *B = calloc(k * k, sizeof(double)), *I = calloc(k * k, sizeof(double)), mx = 0.0;
  size_t i, j, c, r;
  for (i = 0; i < k; i++)
    for (j = 0; j < k; j++) B[i * k + j] = A[i * N + j], I[i * k + j] = i == j;
  for (c = 0; c < k; c++) { /* SPD: no pivoting needed */
    for (r = c + 1; r < k; r++) {
      double f = B[r * k + c] / B[c * k + c];
      for (j = 0; j < k; j++) B[r * k + j] -= f * B[c * k + j], I[r * k + j] -= f * I[c * k + j];
    }
  }
  for (c = k; c-- > 0;)
    for (j = 0; j < k; j++) {
      double s = I[c * k + j];
      for (r = c + 1; r < k; r++) s -= B[c * k + r] * I[r * k + j];
      I[c * k + j] = s / B[c * k + c];
    }
  for (j = 0; j < k; j++) {
    double s = 0.0;
    for (i = 0; i < k; i++) s += fabs(I[i * k + j]);
    if (s > mx) mx = s;
  }
  free(B);
  free(I);
  return mx;
}

static void test_periodic_rcond(void **state) {
  /* given noisy closed data, when fitted periodically, then the reported rcond is the
  ** leading block's exact value (its inverse is computed from one solve, the block being
  ** totally nonnegative) unless the Schur block's is smaller: exact_r1 >= rcond >=
  ** min(exact_r1, exact_r2); with QR, Hager's estimate of the whole A^-1 */
  test_rng r = {99};
  size_t m = 80, N, i, j;
  double pts[160], u[80], w[80];
  int p;
  (void)state;
  noisy_closed(&r, m, 0.05, pts, u, w);
  for (p = 2; p <= 3; p++)
    for (N = (size_t)p + 4; N <= 24; N += 5) {
      bsfit_fit_opts o;
      bsfit_fitter *f;
      bsfit_curve out;
      bsfit_fit_report rep;
      double *A = calloc(N * N, sizeof(double)), *Nm, anorm = 0.0, r1, r2, S[9], Sinv = 0.0;
      const double *U;
      size_t n1 = N - (size_t)p;
      opts_init(&o);
      o.degree = p;
      o.count = N;
      o.periodic = 1;
      bsfit_curve_init(&out);
      assert_int_equal(bsfit_fitter_new(&f, &o, NULL, NULL), BSFIT_OK);
      assert_int_equal(bsfit_fitter_fit(f, pts, m, 2, u, w, &out, &rep, NULL, NULL), BSFIT_OK);
      U = bsfit_fitter_knots(f, NULL);
      Nm = folded_collocation(U, p, N, u, m, w, A);
      for (j = 0; j < N; j++) {
        double s = 0.0;
        for (i = 0; i < N; i++) s += fabs(A[i * N + j]);
        if (s > anorm) anorm = s;
      }
      r1 = 1.0 / (anorm * inv_norm1(A, N, n1));
      { /* S = A22 - A21 A11^-1 A12 = inverse of the trailing block of A^-1 */
        double *Ainv = calloc(N * N, sizeof(double)), *B = calloc(N * N, sizeof(double));
        memcpy(B, A, N * N * sizeof(double));
        for (i = 0; i < N; i++) Ainv[i * N + i] = 1.0;
        dense_chol_solve(B, Ainv, N, N);
        for (i = 0; i < (size_t)p; i++) /* S^-1 is that trailing block */
          for (j = 0; j < (size_t)p; j++) S[i * 3 + j] = Ainv[(n1 + i) * N + n1 + j];
        for (j = 0; j < (size_t)p; j++) {
          double s = 0.0;
          for (i = 0; i < (size_t)p; i++) s += fabs(S[i * 3 + j]);
          if (s > Sinv) Sinv = s;
        }
        free(Ainv);
        free(B);
      }
      r2 = 1.0 / (anorm * Sinv);
      if (solver_under_test == BSFIT_SOLVER_QR) {
        /* Hager's estimate: |A^-1|_1 from below, within its usual factor */
        double exact = 1.0 / (anorm * inv_norm1(A, N, N));
        assert_true(rep.rcond >= exact * (1.0 - 1e-9));
        assert_true(rep.rcond <= 3.0 * exact);
      } else {
        assert_true(rep.rcond <= r1 * (1.0 + 1e-9));
        assert_true(rep.rcond >= (r1 < r2 ? r1 : r2) * (1.0 - 1e-9));
      }
      free(A);
      free(Nm);
      bsfit_fitter_free(f);
      bsfit_curve_free(&out);
    }
}

/* d^k C at u from span s (left or right limit chosen by the span) */
static void ders_at(const bsfit_curve *c, size_t s, double u, int nd, double *out) {
  double ders[(BSFIT_MAX_DEGREE + 1) * (BSFIT_MAX_DEGREE + 1)];
  int k;
  size_t j, p = (size_t)c->degree;
  bsfit_basis_ders(s, u, c->degree, nd, c->knots, ders);
  for (k = 0; k <= nd; k++) {
    out[2 * k] = out[2 * k + 1] = 0.0;
    for (j = 0; j <= p; j++) {
      out[2 * k] += ders[(size_t)k * (p + 1) + j] * c->ctrl[(s - p + j) * 2];
      out[2 * k + 1] += ders[(size_t)k * (p + 1) + j] * c->ctrl[(s - p + j) * 2 + 1];
    }
  }
}

static void test_seam_is_smooth_and_beats_wrap_closing(void **state) {
  test_rng r = {909};
  size_t m = 200, N = 16;
  double pts[400], u[200], uo[200], w[200];
  bsfit_fit_opts o;
  bsfit_fitter *f;
  bsfit_curve open, wrap, per, per2;
  (void)state;
  noisy_closed(&r, m, 0.03, pts, u, w);
  bsfit_curve_init(&open);
  bsfit_curve_init(&wrap);
  bsfit_curve_init(&per);
  bsfit_curve_init(&per2);
  /* the paper: open fit with averaging knots on open parameters, then wrap closing */
  assert_int_equal(bsfit_params(pts, m, 2, BSFIT_PARAM_CHORD, 0, uo, NULL), BSFIT_OK);
  opts_init(&o);
  o.count = N;
  assert_int_equal(bsfit_fitter_new(&f, &o, NULL, NULL), BSFIT_OK);
  assert_int_equal(bsfit_fitter_fit(f, pts, m, 2, uo, w, &open, NULL, NULL, NULL), BSFIT_OK);
  bsfit_fitter_free(f);
  assert_int_equal(bsfit_curve_wrap_closed(&open, u, m, &wrap, NULL, NULL), BSFIT_OK);
  assert_int_equal(bsfit_curve_distinct(&wrap), N);
  /* the true periodic fit on the same (carvalho-closed) space, and with periodic averaging */
  o.periodic = 1;
  o.rule = BSFIT_KNOTS_CARVALHO_CLOSED;
  assert_int_equal(bsfit_fitter_new(&f, &o, NULL, NULL), BSFIT_OK);
  assert_int_equal(bsfit_fitter_fit(f, pts, m, 2, u, w, &per, NULL, NULL, NULL), BSFIT_OK);
  bsfit_fitter_free(f);
  o.rule = BSFIT_KNOTS_PERIODIC_AVERAGING;
  assert_int_equal(bsfit_fitter_new(&f, &o, NULL, NULL), BSFIT_OK);
  assert_int_equal(bsfit_fitter_fit(f, pts, m, 2, u, w, &per2, NULL, NULL, NULL), BSFIT_OK);
  bsfit_fitter_free(f);
  /* then the periodic fits' weighted residual is never worse than the wrap closing's */
  assert_true(wsse(&per, pts, u, w, m) <= wsse(&wrap, pts, u, w, m));
  assert_true(wsse(&per2, pts, u, w, m) <= wsse(&wrap, pts, u, w, m));
  /* and the curve is C^{p-1} at the seam: left limit at b equals right limit at a */
  {
    double L[8], R[8], a, b;
    int k;
    bsfit_curve_domain(&per2, &a, &b);
    ders_at(&per2, bsfit_knots_find_span(per2.knots, per2.n, 3, b), b, 2, L);
    ders_at(&per2, 3, a, 2, R);
    for (k = 0; k < 6; k++) assert_float_equal(L[k], R[k], 1e-9 * (1.0 + fabs(R[k])));
  }
  bsfit_curve_free(&open);
  bsfit_curve_free(&wrap);
  bsfit_curve_free(&per);
  bsfit_curve_free(&per2);
}

static void test_periodic_interpolation(void **state) {
  test_rng r = {17};
  size_t m = 21, k;
  double pts[42], u[21], x[2];
  int p;
  bsfit_curve out;
  (void)state;
  noisy_closed(&r, m, 0.1, pts, u, NULL);
  bsfit_curve_init(&out);
  for (p = 2; p <= 5; p++) {
    assert_int_equal(bsfit_interpolate(pts, m, 2, u, p, 1, &out, NULL, NULL), BSFIT_OK);
    assert_int_equal(bsfit_curve_distinct(&out), m);
    assert_true(out.periodic);
    for (k = 0; k < m; k++) {
      assert_int_equal(bsfit_curve_eval(&out, u[k], x, NULL), BSFIT_OK);
      assert_float_equal(x[0], pts[2 * k], 1e-9);
      assert_float_equal(x[1], pts[2 * k + 1], 1e-9);
    }
  }
  bsfit_curve_free(&out);
}

static void test_periodic_invalid_inputs(void **state) {
  test_rng r = {18};
  size_t m = 30;
  double pts[60], u[30], w[30], period[6] = {0, 1, 2, 3, 2.5, 5};
  bsfit_fit_opts o;
  bsfit_fitter *f;
  bsfit_curve out, open;
  bsfit_status st;
  (void)state;
  noisy_closed(&r, m, 0.01, pts, u, w);
  bsfit_curve_init(&out);
  bsfit_curve_init(&open);
  opts_init(&o);
  o.periodic = 1;
  o.count = 5;
  o.knots = period;
  o.nknots = 5;
  expect_error(bsfit_fitter_new(&f, &o, NULL, &st), BSFIT_ENKNOTS, &st);
  o.nknots = 6;
  expect_error(bsfit_fitter_new(&f, &o, NULL, &st), BSFIT_EKNOTS_DECR, &st);
  o.knots = NULL;
  o.count = 3; /* cubic needs 4 distinct control points */
  expect_error(bsfit_fitter_new(&f, &o, NULL, &st), BSFIT_EDEGREE, &st);
  o.count = 8;
  assert_int_equal(bsfit_fitter_new(&f, &o, NULL, &st), BSFIT_OK);
  expect_error(bsfit_fitter_fit(f, pts, 7, 2, u, w, &out, NULL, NULL, &st), BSFIT_ETOOFEW, &st);
  w[3] = -2.0;
  expect_error(bsfit_fitter_fit(f, pts, m, 2, u, w, &out, NULL, NULL, &st), BSFIT_EWEIGHT, &st);
  w[3] = 1.0;
  pts[7] = NAN;
  expect_error(bsfit_fitter_fit(f, pts, m, 2, u, w, &out, NULL, NULL, &st), BSFIT_ENONFINITE, &st);
  assert_null(out.ctrl);
  pts[7] = 0.5;
  {
    /* open parameters spanning [0, 1] are not one period for the closed rules */
    double uo[30];
    assert_int_equal(bsfit_params(pts, m, 2, BSFIT_PARAM_CHORD, 0, uo, NULL), BSFIT_OK);
    expect_error(bsfit_fitter_fit(f, pts, m, 2, uo, w, &out, NULL, NULL, &st), BSFIT_EINVAL, &st);
  }
  assert_int_equal(bsfit_fitter_fit(f, pts, m, 2, u, w, &out, NULL, NULL, &st), BSFIT_OK);
  /* wrap closing rejects periodic input and the output aliasing its input */
  expect_error(bsfit_curve_wrap_closed(&out, u, m, &open, NULL, &st), BSFIT_EINVAL, &st);
  expect_error(bsfit_curve_wrap_closed(NULL, u, m, &open, NULL, &st), BSFIT_EINVAL, &st);
  bsfit_fitter_free(f);
  bsfit_curve_free(&out);
}

int main(void) {
  const struct CMUnitTest tests[] = {
    cmocka_unit_test(test_reproduces_periodic_spline),
    cmocka_unit_test(test_matches_dense_periodic),
    cmocka_unit_test(test_periodic_rcond),
    cmocka_unit_test(test_seam_is_smooth_and_beats_wrap_closing),
    cmocka_unit_test(test_periodic_interpolation),
    cmocka_unit_test(test_periodic_invalid_inputs),
  };
  return run_with_each_solver(tests);
}
