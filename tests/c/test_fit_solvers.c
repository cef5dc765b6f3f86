/*
** test_fit_solvers.c
** The fitter's solvers side by side (bsfit_solver): QR keeps the digits the normal
** equations lose on an ill-conditioned problem and AUTO switches to it; rows out of order
** (shuffled, or a closed section starting anywhere) give the sorted result; the QR's index
** array is allocated once and its failure is clean; an unknown solver is refused.
** (test_wls.c and test_periodic_fit.c run all their properties with each solver.)
*/
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>
#include "cmocka_double.h"
#include <stdlib.h>
#include <string.h>

#include "bsfit.h"
#include "testutil.h"

/* Largest |a_i - b_i|. */
static double max_diff(const double *a, const double *b, size_t n) {
  double mx = 0.0;
  size_t i;
  for (i = 0; i < n; i++)
    if (fabs(a[i] - b[i]) > mx) mx = fabs(a[i] - b[i]);
  return mx;
}

/* Fits with one solver; returns the report, the control points in ctrl (n*dim). */
static bsfit_fit_report fit_with(bsfit_solver solver, const bsfit_fit_opts *base,
                                 const double *pts, size_t m, const double *u, const double *w,
                                 double *ctrl) {
  bsfit_fit_opts o = *base;
  bsfit_fitter *f;
  bsfit_curve out;
  bsfit_fit_report rep;
  bsfit_status st;
  o.solver = solver;
  bsfit_curve_init(&out);
  assert_int_equal(bsfit_fitter_new(&f, &o, NULL, &st), BSFIT_OK);
  assert_int_equal(bsfit_fitter_fit(f, pts, m, 2, u, w, &out, &rep, NULL, &st), BSFIT_OK);
  memcpy(ctrl, out.ctrl, out.n * 2 * sizeof(double));
  bsfit_fitter_free(f);
  bsfit_curve_free(&out);
  return rep;
}

static void test_qr_keeps_the_accuracy_cholesky_loses(void **state) {
  /* given exact samples of a cubic spline (12 control points, uniform knots) taken in tight
  ** clusters, one per span: the collocation matrix is ill-conditioned, the normal matrix
  ** (its square) far more so */
  enum { n = 12, p = 3, per = 7, m = (n - p) * per };
  double U[n + p + 1], ctrl[n * 2], u[m], pts[m * 2], w[m], got[n * 2], delta = 1e-5;
  double err_chol, err_qr;
  bsfit_curve src;
  bsfit_fit_opts o;
  bsfit_fit_report chol, qr, aut;
  size_t i, s, k;
  (void)state;
  for (i = 0; i < n + p + 1; i++)
    U[i] = i <= p ? 0.0 : i >= n ? 1.0 : (double)(i - p) / (double)(n - p);
  for (i = 0; i < n; i++) ctrl[2 * i] = cos((double)i), ctrl[2 * i + 1] = sin(1.3 * (double)i);
  bsfit_curve_init(&src);
  assert_int_equal(bsfit_curve_new(&src, p, 2, n, U, ctrl, NULL, 0, NULL, NULL), BSFIT_OK);
  for (s = 0, k = 0; s < n - p; s++)
    for (i = 0; i < per; i++, k++) {
      u[k] = ((double)s + 0.5 + delta * ((double)i - 3.0)) / (double)(n - p);
      w[k] = 1.0;
      assert_int_equal(bsfit_curve_eval(&src, u[k], pts + 2 * k, NULL), BSFIT_OK);
    }
  bsfit_fit_opts_init(&o);
  o.degree = p;
  o.knots = U;
  o.nknots = n + p + 1;
  o.count = n;
  /* when fitted by each solver */
  chol = fit_with(BSFIT_SOLVER_CHOLESKY, &o, pts, m, u, w, got);
  err_chol = max_diff(got, ctrl, n * 2);
  qr = fit_with(BSFIT_SOLVER_QR, &o, pts, m, u, w, got);
  err_qr = max_diff(got, ctrl, n * 2);
  aut = fit_with(BSFIT_SOLVER_AUTO, &o, pts, m, u, w, got);
  print_message("rcond %.2g: control points off by %.2g (Cholesky), %.2g (QR)\n", chol.rcond,
                err_chol, err_qr); /* the README quotes these */
  /* then QR's error follows eps / sqrt(rcond), Cholesky's eps / rcond: QR is far closer */
  assert_true(chol.rcond < BSFIT_SOLVER_AUTO_RCOND);
  assert_float_equal(qr.rcond, chol.rcond, 1e-6 * chol.rcond);
  assert_true(err_qr < 1e-9);
  assert_true(err_chol > 1e3 * err_qr);
  /* and AUTO saw the condition number and used QR */
  assert_int_equal(chol.solver, BSFIT_SOLVER_CHOLESKY);
  assert_int_equal(qr.solver, BSFIT_SOLVER_QR);
  assert_int_equal(aut.solver, BSFIT_SOLVER_QR);
  assert_true(max_diff(got, ctrl, n * 2) == err_qr);
  bsfit_curve_free(&src);
}

static void test_auto_keeps_cholesky_when_well_conditioned(void **state) {
  test_rng r = {31};
  enum { m = 200 };
  double pts[m * 2], u[m], w[m], a[(20 + 3) * 2], b[(20 + 3) * 2]; /* expanded form: N + p */
  bsfit_fit_opts o;
  bsfit_fit_report ra, rb;
  size_t k;
  (void)state;
  for (k = 0; k < m; k++) {
    double t = (double)k / (double)m;
    pts[2 * k] = cos(6.283185307179586 * t) + rng_range(&r, -0.01, 0.01);
    pts[2 * k + 1] = sin(6.283185307179586 * t);
    w[k] = rng_range(&r, 0.5, 2.0);
  }
  assert_int_equal(bsfit_params(pts, m, 2, BSFIT_PARAM_CHORD, 1, u, NULL), BSFIT_OK);
  bsfit_fit_opts_init(&o);
  o.count = 20;
  o.periodic = 1;
  ra = fit_with(BSFIT_SOLVER_AUTO, &o, pts, m, u, w, a);
  rb = fit_with(BSFIT_SOLVER_CHOLESKY, &o, pts, m, u, w, b);
  assert_int_equal(ra.solver, BSFIT_SOLVER_CHOLESKY);
  assert_memory_equal(a, b, sizeof a);
  assert_true(ra.rcond == rb.rcond);
}

static void test_rows_out_of_order(void **state) {
  /* given a closed section fitted with its points in order, then starting elsewhere on
  ** the curve (parameters sorted up to a rotation), then shuffled */
  test_rng r = {57};
  enum { m = 150, N = 16 };
  double pts[m * 2], u[m], w[m], sp[m * 2], su[m], sw[m], ref[(N + 3) * 2], got[(N + 3) * 2];
  size_t k, perm[m], calls;
  bsfit_fit_opts o;
  bsfit_fitter *f;
  bsfit_curve out;
  bsfit_status st;
  counting ca = {0, 0, 0};
  bsfit_allocator al = {counting_alloc, &ca, NULL};
  (void)state;
  for (k = 0; k < m; k++) {
    double t = 6.283185307179586 * (double)k / (double)m;
    pts[2 * k] = (1.0 + 0.2 * cos(3.0 * t)) * cos(t) + rng_range(&r, -0.01, 0.01);
    pts[2 * k + 1] = (1.0 + 0.2 * cos(3.0 * t)) * sin(t);
    w[k] = rng_range(&r, 0.2, 5.0);
  }
  assert_int_equal(bsfit_params(pts, m, 2, BSFIT_PARAM_CHORD, 1, u, NULL), BSFIT_OK);
  bsfit_fit_opts_init(&o);
  o.count = N;
  o.periodic = 1;
  o.solver = BSFIT_SOLVER_QR;
  bsfit_curve_init(&out);
  assert_int_equal(bsfit_fitter_new(&f, &o, &al, &st), BSFIT_OK);
  assert_int_equal(bsfit_fitter_fit(f, pts, m, 2, u, w, &out, NULL, NULL, &st), BSFIT_OK);
  memcpy(ref, out.ctrl, sizeof ref);
  /* knots come from the rule, which needs sorted parameters: keep these knots */
  {
    double period[N + 1];
    size_t nk;
    const double *U = bsfit_fitter_knots(f, &nk);
    memcpy(period, U + 3, sizeof period);
    o.knots = period;
    o.nknots = N + 1;
    assert_int_equal(bsfit_fitter_configure(f, &o, &st), BSFIT_OK);
  }
  /* rotated: start at point 40, the parameters shifted by one period where they wrap */
  for (k = 0; k < m; k++) {
    size_t j = (k + 40) % m;
    sp[2 * k] = pts[2 * j], sp[2 * k + 1] = pts[2 * j + 1], sw[k] = w[j];
    su[k] = u[j] + (k + 40 >= m ? 1.0 : 0.0);
  }
  calls = (size_t)ca.calls;
  assert_int_equal(bsfit_fitter_fit(f, sp, m, 2, su, sw, &out, NULL, NULL, &st), BSFIT_OK);
  assert_int_equal((size_t)ca.calls, calls); /* a rotation needs no index array */
  memcpy(got, out.ctrl, sizeof got);
  assert_true(max_diff(got, ref, (N + 3) * 2) < 1e-12);
  /* shuffled: sorted by span through the index array, allocated once */
  for (k = 0; k < m; k++) perm[k] = k;
  for (k = m - 1; k > 0; k--) {
    size_t j = (size_t)(rng_uniform(&r) * (double)(k + 1)), t = perm[k];
    perm[k] = perm[j], perm[j] = t;
  }
  for (k = 0; k < m; k++) {
    sp[2 * k] = pts[2 * perm[k]], sp[2 * k + 1] = pts[2 * perm[k] + 1];
    su[k] = u[perm[k]], sw[k] = w[perm[k]];
  }
  ca.fail_at = ca.calls + 1; /* the index array's allocation fails: ENOMEM, nothing leaks */
  assert_int_equal(bsfit_fitter_fit(f, sp, m, 2, su, sw, &out, NULL, NULL, &st), BSFIT_ENOMEM);
  assert_null(out.ctrl);
  ca.fail_at = 0;
  assert_int_equal(bsfit_fitter_fit(f, sp, m, 2, su, sw, &out, NULL, NULL, &st), BSFIT_OK);
  calls = (size_t)ca.calls;
  assert_int_equal(bsfit_fitter_fit(f, sp, m, 2, su, sw, &out, NULL, NULL, &st), BSFIT_OK);
  assert_int_equal((size_t)ca.calls, calls); /* reused */
  memcpy(got, out.ctrl, sizeof got);
  assert_true(max_diff(got, ref, (N + 3) * 2) < 1e-12);
  bsfit_curve_free(&out);
  bsfit_fitter_free(f);
  assert_int_equal(ca.live, 0);
}

static void test_weights_scale_freely(void **state) {
  /* given noisy open and closed data, when every weight is multiplied by 1e-300 or 1e306
  ** (QR's rows then hold entries whose squares underflow or overflow), then each solver
  ** fits the same curve as with unit weights */
  test_rng r = {73};
  enum { m = 120, N = 14 };
  double pts[m * 2], u[m], w[m], ref[(N + 3) * 2], got[(N + 3) * 2];
  const double scales[] = {1e-300, 1e306};
  const bsfit_solver solvers[] = {BSFIT_SOLVER_CHOLESKY, BSFIT_SOLVER_QR};
  bsfit_fit_opts o;
  size_t k, i, j;
  int periodic;
  (void)state;
  for (k = 0; k < m; k++) {
    double t = 6.283185307179586 * (double)k / (double)m;
    pts[2 * k] = 2.0 * cos(t) + rng_range(&r, -0.01, 0.01);
    pts[2 * k + 1] = sin(t) * (1.0 + 0.3 * cos(3.0 * t));
  }
  for (periodic = 0; periodic <= 1; periodic++) {
    size_t n = (size_t)N + (periodic ? 3 : 0);
    assert_int_equal(bsfit_params(pts, m, 2, BSFIT_PARAM_CHORD, periodic, u, NULL), BSFIT_OK);
    bsfit_fit_opts_init(&o);
    o.count = N;
    o.periodic = periodic;
    for (j = 0; j < 2; j++) {
      for (k = 0; k < m; k++) w[k] = 1.0;
      (void)fit_with(solvers[j], &o, pts, m, u, w, ref);
      for (i = 0; i < 2; i++) {
        for (k = 0; k < m; k++) w[k] = scales[i];
        (void)fit_with(solvers[j], &o, pts, m, u, w, got);
        assert_true(max_diff(got, ref, n * 2) < 1e-12);
      }
    }
  }
}

static void test_unknown_solver_is_refused(void **state) {
  bsfit_fit_opts o;
  bsfit_fitter *f;
  bsfit_status st;
  (void)state;
  bsfit_fit_opts_init(&o);
  o.count = 8;
  o.solver = (bsfit_solver)7;
  assert_int_equal(bsfit_fitter_new(&f, &o, NULL, &st), BSFIT_EINVAL);
  assert_null(f);
  assert_non_null(strstr(st.msg, "solver"));
}

int main(void) {
  const struct CMUnitTest tests[] = {
    cmocka_unit_test(test_qr_keeps_the_accuracy_cholesky_loses),
    cmocka_unit_test(test_auto_keeps_cholesky_when_well_conditioned),
    cmocka_unit_test(test_rows_out_of_order),
    cmocka_unit_test(test_weights_scale_freely),
    cmocka_unit_test(test_unknown_solver_is_refused),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
