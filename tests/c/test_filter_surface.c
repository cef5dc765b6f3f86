/*
** test_filter_surface.c
** Degree reduction of surfaces and the certified distance bounds (issue 17):
**   - the bound of two curves, and of two surfaces, is never below the largest difference
**     found by dense sampling (it is certified) and not far above it (it is useful), over
**     random degrees, knots (repeated ones included), open and closed curves;
**   - a surface elevated (row by row, then column by column, with bsfit_curve_elevate: an
**     independent construction) and reduced comes back to its control net (1e-12), open
**     and closed around u; the result of a closed surface stays closed;
**   - reduction with a tolerance: the bound reported is at least the dense-sampled
**     difference and at most tol, knots are added when needed;
**   - smoothing of a noisy surface: the bound it reports holds against dense sampling;
**   - bad input: clear errors.
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
#include "core/filter_internal.h"

#define EPS_BACK 1e-12 /* elevated then reduced */
#define DENSE 64       /* samples per knot span (curves) / per direction (surfaces) */

/* {====================================================================
** Dense sampling: the largest |A - B| at equal parameters
** ===================================================================== */

static double curve_sampled(const bsfit_curve *A, const bsfit_curve *B) {
  double a, b, x[4], y[4], worst = 0.0;
  size_t i, m = DENSE * A->n;
  bsfit_status st;
  int k;
  bsfit_curve_domain(A, &a, &b);
  for (i = 0; i <= m; i++) {
    double t = a + (b - a) * (double)i / (double)m, s = 0.0;
    assert_int_equal(bsfit_curve_eval(A, t, x, &st), BSFIT_OK);
    assert_int_equal(bsfit_curve_eval(B, t, y, &st), BSFIT_OK);
    for (k = 0; k < A->dim; k++) s += (x[k] - y[k]) * (x[k] - y[k]);
    worst = fmax(worst, sqrt(s));
  }
  return worst;
}

static double surface_sampled(const bsfit_surface *A, const bsfit_surface *B, size_t m) {
  double ua, ub, va, vb, x[4], y[4], worst = 0.0;
  bsfit_status st;
  size_t i, j;
  int k;
  bsfit_surface_domain(A, &ua, &ub, &va, &vb);
  for (i = 0; i <= m; i++)
    for (j = 0; j <= m; j++) {
      double u = ua + (ub - ua) * (double)i / (double)m, v = va + (vb - va) * (double)j / (double)m;
      double s = 0.0;
      assert_int_equal(bsfit_surface_eval(A, u, v, x, &st), BSFIT_OK);
      assert_int_equal(bsfit_surface_eval(B, u, v, y, &st), BSFIT_OK);
      for (k = 0; k < A->dim; k++) s += (x[k] - y[k]) * (x[k] - y[k]);
      worst = fmax(worst, sqrt(s));
    }
  return worst;
}

/* }==================================================================== */

/* {====================================================================
** Random surfaces, and elevation by curves
** ===================================================================== */

/* A random surface of degrees (pu, pv), nu x nv points, random clamped knots (repeated
** interior ones included), or closed around u (expanded periodic form, N = nu - pu). */
static void random_surface(test_rng *r, int pu, int pv, size_t nu, size_t nv, int closed,
                           bsfit_surface *s) {
  double Uu[64], Uv[64], per[32];
  double *P = malloc(nu * nv * 3 * sizeof(double));
  bsfit_status st;
  size_t i, j, N = nu - (size_t)pu;
  assert_non_null(P);
  random_knots(r, pv, nv, 1, Uv);
  if (closed) {
    per[0] = 0.0;
    for (i = 1; i <= N; i++) per[i] = per[i - 1] + rng_range(r, 0.3, 1.0);
    assert_int_equal(bsfit_knots_periodic(pu, N, per, Uu, &st), BSFIT_OK);
  } else {
    random_knots(r, pu, nu, 1, Uu);
  }
  for (i = 0; i < nu; i++)
    for (j = 0; j < nv; j++) {
      size_t src = closed && i >= N ? i - N : i; /* the wrapped rows repeat the first ones */
      double ang = 6.283185307179586 * (double)src / (double)(closed ? N : nu);
      double *p = P + (i * nv + j) * 3;
      p[0] = (2.0 + 0.3 * rng_uniform(r)) * cos(ang);
      p[1] = (2.0 + 0.3 * rng_uniform(r)) * sin(ang);
      p[2] = (double)j + 0.2 * rng_uniform(r);
      if (closed && i >= N) memcpy(p, P + (src * nv + j) * 3, 3 * sizeof(double));
    }
  bsfit_surface_init(s);
  assert_int_equal(bsfit_surface_new(s, pu, pv, 3, nu, nv, Uu, Uv, P, NULL, NULL, &st), BSFIT_OK);
  if (closed) {
    s->periodic_u = 1;
    assert_int_equal(bsfit_surface_validate(s, &st), BSFIT_OK);
  }
  free(P);
}

/* One direction of s elevated by t: each line of the net along u (the columns j) elevated
** as a curve; the result's u knots from the first one. */
static void elevate_u(const bsfit_surface *s, int t, bsfit_surface *out) {
  bsfit_status st;
  bsfit_curve c, e;
  size_t i, j, nu2 = 0;
  double *P = NULL, *U = NULL;
  for (j = 0; j < s->nv; j++) {
    double *col = malloc(s->nu * 3 * sizeof(double));
    assert_non_null(col);
    for (i = 0; i < s->nu; i++) memcpy(col + i * 3, s->ctrl + (i * s->nv + j) * 3, 24);
    bsfit_curve_init(&c);
    bsfit_curve_init(&e);
    if (s->periodic_u)
      assert_int_equal(bsfit_curve_new_periodic(&c, s->degree_u, 3, s->nu - (size_t)s->degree_u,
                                                s->knots_u + s->degree_u, col, NULL, NULL, &st),
                       BSFIT_OK);
    else
      assert_int_equal(bsfit_curve_new(&c, s->degree_u, 3, s->nu, s->knots_u, col, NULL, 0, NULL,
                                       &st), BSFIT_OK);
    assert_int_equal(bsfit_curve_elevate(&c, t, &e, &st), BSFIT_OK);
    if (P == NULL) {
      nu2 = e.n;
      P = malloc(nu2 * s->nv * 3 * sizeof(double));
      U = malloc((nu2 + (size_t)e.degree + 1) * sizeof(double));
      assert_non_null(P);
      assert_non_null(U);
      memcpy(U, e.knots, (nu2 + (size_t)e.degree + 1) * sizeof(double));
    }
    assert_int_equal(e.n, nu2);
    for (i = 0; i < nu2; i++) memcpy(P + (i * s->nv + j) * 3, e.ctrl + i * 3, 24);
    bsfit_curve_free(&c);
    bsfit_curve_free(&e);
    free(col);
  }
  bsfit_surface_init(out);
  assert_int_equal(bsfit_surface_new(out, s->degree_u + t, s->degree_v, 3, nu2, s->nv, U,
                                     s->knots_v, P, NULL, NULL, &st), BSFIT_OK);
  out->periodic_u = s->periodic_u;
  assert_int_equal(bsfit_surface_validate(out, &st), BSFIT_OK);
  free(P);
  free(U);
}

/* s with u and v swapped (the net transposed): elevation along v through elevate_u. */
static void swap_uv(const bsfit_surface *s, bsfit_surface *out) {
  double *P = malloc(s->nu * s->nv * 3 * sizeof(double));
  bsfit_status st;
  size_t i, j;
  assert_non_null(P);
  for (i = 0; i < s->nu; i++)
    for (j = 0; j < s->nv; j++) memcpy(P + (j * s->nu + i) * 3, s->ctrl + (i * s->nv + j) * 3, 24);
  bsfit_surface_init(out);
  assert_int_equal(bsfit_surface_new(out, s->degree_v, s->degree_u, 3, s->nv, s->nu, s->knots_v,
                                     s->knots_u, P, NULL, NULL, &st), BSFIT_OK);
  free(P);
}

static void elevate(const bsfit_surface *s, int tu, int tv, bsfit_surface *out) {
  bsfit_surface a, b, c;
  elevate_u(s, tu, &a);
  if (s->periodic_u) { /* a periodic direction cannot be swapped into v: v is left alone */
    assert_int_equal(tv, 0);
    bsfit_surface_move(&a, out);
    return;
  }
  swap_uv(&a, &b);
  elevate_u(&b, tv, &c);
  swap_uv(&c, out);
  bsfit_surface_free(&a);
  bsfit_surface_free(&b);
  bsfit_surface_free(&c);
}

/* }==================================================================== */

/* {====================================================================
** Tests
** ===================================================================== */

/* Given random curve pairs A (degree q, A's knots) and B (B's own), when their
** difference is bounded, then the bound is >= every sampled difference and, refined, close
** to the largest (plus rounding). */
static void test_curve_bound_is_certified_and_tight(void **state) {
  test_rng rng = {0x626f756e64};
  int it;
  (void)state;
  for (it = 0; it < 60; it++) {
    int p = 1 + it % 5, q = 1 + (it / 5) % 4, closed = it % 3 == 0;
    size_t n = (size_t)p + 4 + (size_t)(it % 7);
    bsfit_curve B, A;
    bsfit_reduce_opts o;
    bsfit_reduce_report rep;
    bsfit_status st;
    double P[3 * 32], U[64], per[32], sampled;
    bsfit__bound bd;
    size_t i;
    random_points(&rng, n, 2, P);
    bsfit_curve_init(&B);
    bsfit_curve_init(&A);
    if (closed) {
      per[0] = 0.0;
      for (i = 1; i <= n; i++) per[i] = per[i - 1] + rng_range(&rng, 0.2, 1.0);
      assert_int_equal(bsfit_curve_new_periodic(&B, p, 2, n, per, P, NULL, NULL, &st), BSFIT_OK);
    } else {
      random_knots(&rng, p, n, 1, U);
      assert_int_equal(bsfit_curve_new(&B, p, 2, n, U, P, NULL, 0, NULL, &st), BSFIT_OK);
    }
    /* A: the projection of B on degree q (a curve near B, on other knots when q != p) */
    memset(&o, 0, sizeof o);
    o.degree = q;
    o.tol = INFINITY;
    assert_int_equal(bsfit_filter_reduce_curve(&B, &o, &A, &rep, &st), BSFIT_OK);
    sampled = curve_sampled(&A, &B);
    assert_true(rep.bound >= sampled - 1e-13);
    assert_true(rep.max_deviation <= rep.bound + 1e-13);
    /* refined where above 1.2 times the sampled maximum, it comes down to about that */
    assert_int_equal(bsfit__curve_diff_bound(&A, &B, 1.2 * sampled, NULL, NULL, NULL, &bd, &st),
                     BSFIT_OK);
    assert_true(bd.bound >= sampled - 1e-13);
    assert_true(bd.bound <= 1.3 * sampled + 1e-11); /* + the rounding slack of the bound */
    bsfit_curve_free(&A);
    bsfit_curve_free(&B);
  }
}

/* Given random surfaces elevated by (tu, tv), when reduced back to their degrees with a
** tiny tol, then the control net comes back (1e-12), no knot is added, and a closed
** surface stays closed. */
static void test_elevated_surface_comes_back(void **state) {
  test_rng rng = {0x73757266};
  int it;
  (void)state;
  for (it = 0; it < 12; it++) {
    int pu = 1 + it % 3, pv = 1 + (it / 3) % 3, closed = it % 4 == 3;
    int tu = 1 + it % 2, tv = closed ? 0 : 1 + (it / 2) % 2;
    bsfit_surface s, e, r;
    bsfit_reduce_surface_opts o;
    bsfit_reduce_report rep;
    bsfit_status st;
    size_t i;
    random_surface(&rng, pu, pv, (size_t)pu + 4 + (size_t)(it % 3), (size_t)pv + 3, closed, &s);
    elevate(&s, tu, tv, &e);
    memset(&o, 0, sizeof o);
    o.degree_u = pu;
    o.degree_v = pv;
    o.tol = 1e-9;
    bsfit_surface_init(&r);
    assert_int_equal(bsfit_filter_reduce_surface(&e, &o, &r, &rep, &st), BSFIT_OK);
    assert_int_equal(r.degree_u, pu);
    assert_int_equal(r.degree_v, pv);
    assert_int_equal(r.periodic_u, closed);
    assert_int_equal((int)rep.knots_added, 0);
    assert_int_equal(r.nu, s.nu);
    assert_int_equal(r.nv, s.nv);
    for (i = 0; i < s.nu * s.nv * 3; i++) assert_float_equal(r.ctrl[i], s.ctrl[i], EPS_BACK);
    assert_true(surface_sampled(&r, &s, 40) <= EPS_BACK);
    bsfit_surface_free(&s);
    bsfit_surface_free(&e);
    bsfit_surface_free(&r);
  }
}

/* Given random surfaces of degrees 4..6, when reduced to bicubic within tol, then the bound
** reported is >= the dense-sampled difference and <= tol, and tight tols add knots. */
static void test_surface_reduce_within_tol(void **state) {
  test_rng rng = {0x746f6c};
  int it, added = 0;
  (void)state;
  for (it = 0; it < 8; it++) {
    int pu = 4 + it % 3, pv = 4 + (it + 1) % 3, closed = it % 4 == 1;
    bsfit_surface s, r;
    bsfit_reduce_surface_opts o;
    bsfit_reduce_report rep;
    bsfit_status st;
    double sampled;
    random_surface(&rng, pu, pv, (size_t)pu + 7, (size_t)pv + 4, closed, &s);
    memset(&o, 0, sizeof o);
    o.tol = it < 4 ? 1e-2 : 1e-4;
    bsfit_surface_init(&r);
    assert_int_equal(bsfit_filter_reduce_surface(&s, &o, &r, &rep, &st), BSFIT_OK);
    assert_int_equal(r.degree_u, 3);
    assert_int_equal(r.degree_v, 3);
    assert_int_equal(r.periodic_u, closed);
    sampled = surface_sampled(&r, &s, 80);
    assert_true(rep.bound >= sampled - 1e-13);
    assert_true(rep.bound <= o.tol);
    added += (int)rep.knots_added;
    bsfit_surface_free(&s);
    bsfit_surface_free(&r);
  }
  assert_true(added > 0);
}

/* Given noisy height fields, when smoothed to tol, then the bound reported holds against
** dense sampling and meets tol. */
static void test_surface_smooth_bound_holds(void **state) {
  test_rng rng = {0x736d6f};
  int it;
  (void)state;
  for (it = 0; it < 3; it++) {
    bsfit_surface s, r;
    bsfit_smooth_opts o;
    bsfit_smooth_report rep;
    bsfit_status st;
    double U[32], *P = malloc(12 * 12 * 3 * sizeof(double));
    size_t i, j;
    assert_non_null(P);
    random_knots(&rng, 3, 12, 1, U);
    for (i = 0; i < 12; i++)
      for (j = 0; j < 12; j++) {
        double *p = P + (i * 12 + j) * 3;
        p[0] = (double)i / 11.0;
        p[1] = (double)j / 11.0;
        p[2] = 0.3 * sin(3.0 * p[0]) * cos(2.0 * p[1]) + 0.01 * (it + 1) * rng_range(&rng, -1, 1);
      }
    bsfit_surface_init(&s);
    bsfit_surface_init(&r);
    assert_int_equal(bsfit_surface_new(&s, 3, 3, 3, 12, 12, U, U, P, NULL, NULL, &st), BSFIT_OK);
    memset(&o, 0, sizeof o);
    o.tol = 0.05 * (it + 1);
    assert_int_equal(bsfit_filter_smooth_surface(&s, &o, &r, &rep, &st), BSFIT_OK);
    assert_true(rep.changed);
    assert_true(rep.bound <= o.tol);
    assert_true(surface_sampled(&r, &s, 90) <= rep.bound + 1e-13);
    bsfit_surface_free(&s);
    bsfit_surface_free(&r);
    free(P);
  }
}

/* The box filter of a surface closed around u against the mathematics: the mean of S over
** [u - du, u + du] x [v - dv, v + dv], u wrapped round the period (Gauss-Legendre between the
** knots, exact for the polynomial pieces), at v whose window stays inside the domain. The kernel
** filters once refused closed surfaces (the skinned ones); smooth then works on them too:
** bicubic, still closed, within tol at a dense grid (the parametric difference, which the
** certified bound holds). */
static double wrapped(double u, double ua, double ub) {
  double t = fmod(u - ua, ub - ua);
  return ua + (t < 0 ? t + (ub - ua) : t);
}

/* The break points of [lo, hi]: its ends and the knots inside it (with their copies one
** period away when T > 0), sorted. Between two, S is one polynomial of degree <= 3 in
** that direction, which 4-point Gauss-Legendre integrates exactly. */
static size_t breaks_in(const double *U, size_t nk, double T, double lo, double hi, double *out) {
  size_t n = 0, i, j;
  int c;
  out[n++] = lo;
  for (i = 0; i < nk; i++)
    for (c = -1; c <= 1; c++) {
      double x = U[i] + (T > 0 ? c * T : 0.0);
      if ((c == 0 || T > 0) && x > lo && x < hi) out[n++] = x;
    }
  out[n++] = hi;
  for (i = 1; i < n; i++) /* insertion sort: a few dozen values */
    for (j = i; j > 0 && out[j] < out[j - 1]; j--) {
      double t = out[j];
      out[j] = out[j - 1], out[j - 1] = t;
    }
  return n;
}

static void window_mean(const bsfit_surface *s, double u, double v, double du, double dv,
                        double *out) {
  static const double x[4] = {-0.8611363115940526, -0.3399810435848563, 0.3399810435848563,
                              0.8611363115940526};
  static const double w[4] = {0.3478548451374538, 0.6521451548625461, 0.6521451548625461,
                              0.3478548451374538};
  double ua, ub, va, vb, p[3], bu[256], bv[256];
  size_t nu, nv, i, j;
  int a, b, k;
  bsfit_surface_domain(s, &ua, &ub, &va, &vb);
  nu = breaks_in(s->knots_u, s->nu + (size_t)s->degree_u + 1, ub - ua, u - du, u + du, bu);
  nv = breaks_in(s->knots_v, s->nv + (size_t)s->degree_v + 1, 0.0, v - dv, v + dv, bv);
  out[0] = out[1] = out[2] = 0.0;
  for (i = 0; i + 1 < nu; i++)
    for (a = 0; a < 4; a++)
      for (j = 0; j + 1 < nv; j++)
        for (b = 0; b < 4; b++) {
          double hu = bu[i + 1] - bu[i], hv = bv[j + 1] - bv[j];
          double uu = bu[i] + 0.5 * hu * (1 + x[a]), vv = bv[j] + 0.5 * hv * (1 + x[b]);
          assert_int_equal(bsfit_surface_eval(s, wrapped(uu, ua, ub), vv, p, NULL), BSFIT_OK);
          for (k = 0; k < 3; k++) out[k] += p[k] * w[a] * w[b] * 0.25 * hu * hv;
        }
  for (k = 0; k < 3; k++) out[k] /= 4.0 * du * dv;
}

static void test_closed_surfaces(void **state) {
  test_rng rng = {0x636c6f73};
  int trial;
  (void)state;
  for (trial = 0; trial < 3; trial++) {
    bsfit_surface s, f, r;
    bsfit_smooth_opts so;
    bsfit_smooth_report rep;
    bsfit_status st;
    double ua, ub, va, vb, du, dv, q[3], p[3], worst = 0.0;
    int i, j, k;
    random_surface(&rng, 3, 2 + trial % 2, 10 + (size_t)trial, 6, 1, &s);
    bsfit_surface_domain(&s, &ua, &ub, &va, &vb);
    du = (0.03 + 0.03 * trial) * (ub - ua);
    dv = 0.05 * (vb - va);
    bsfit_surface_init(&f);
    bsfit_surface_init(&r);
    assert_int_equal(bsfit_filter_kernel_surface_delta(&s, 1, 1, du, dv, &f, &st), BSFIT_OK);
    assert_int_equal(f.periodic_u, 1);
    for (i = 0; i < 12; i++) {
      double u = ua + (ub - ua) * rng_uniform(&rng);
      double v = va + dv + (vb - va - 2.0 * dv) * rng_uniform(&rng);
      window_mean(&s, u, v, du, dv, q);
      assert_int_equal(bsfit_surface_eval(&f, u, v, p, NULL), BSFIT_OK);
      for (k = 0; k < 3; k++) worst = fmax(worst, fabs(p[k] - q[k]));
    }
    if (worst > 1e-9) fail_msg("closed box filter off the window mean by %g", worst);
    memset(&so, 0, sizeof so);
    so.tol = 0.05;
    assert_int_equal(bsfit_filter_smooth_surface(&s, &so, &r, &rep, &st), BSFIT_OK);
    assert_true(rep.changed);
    assert_int_equal(r.periodic_u, 1);
    assert_int_equal(r.degree_u, 3);
    assert_int_equal(r.degree_v, 3);
    worst = 0.0;
    for (i = 0; i <= 40; i++)
      for (j = 0; j <= 40; j++) {
        double u = ua + (ub - ua) * i / 40.0, v = va + (vb - va) * j / 40.0;
        assert_int_equal(bsfit_surface_eval(&r, u, v, p, NULL), BSFIT_OK);
        assert_int_equal(bsfit_surface_eval(&s, u, v, q, NULL), BSFIT_OK);
        worst = fmax(worst, sqrt((p[0] - q[0]) * (p[0] - q[0]) + (p[1] - q[1]) * (p[1] - q[1]) +
                                 (p[2] - q[2]) * (p[2] - q[2])));
      }
    if (worst > so.tol * (1 + 1e-9)) fail_msg("smoothed closed surface %g from the input", worst);
    bsfit_surface_free(&s);
    bsfit_surface_free(&f);
    bsfit_surface_free(&r);
  }
}

static void test_bad_input(void **state) {
  test_rng rng = {0x626164};
  bsfit_surface s, r;
  bsfit_reduce_surface_opts o;
  bsfit_smooth_opts so;
  bsfit_status st;
  (void)state;
  random_surface(&rng, 3, 3, 7, 6, 0, &s);
  bsfit_surface_init(&r);
  memset(&o, 0, sizeof o);
  o.tol = -1.0;
  expect_error(bsfit_filter_reduce_surface(&s, &o, &r, NULL, &st), BSFIT_EINVAL, &st);
  o.tol = NAN;
  expect_error(bsfit_filter_reduce_surface(&s, &o, &r, NULL, &st), BSFIT_ENONFINITE, &st);
  o.tol = 1.0;
  o.degree_u = -1;
  expect_error(bsfit_filter_reduce_surface(&s, &o, &r, NULL, &st), BSFIT_EDEGREE, &st);
  o.degree_u = 3;
  o.degree_v = 13;
  expect_error(bsfit_filter_reduce_surface(&s, &o, &r, NULL, &st), BSFIT_EDEGREE, &st);
  expect_error(bsfit_filter_reduce_surface(NULL, &o, &r, NULL, &st), BSFIT_EINVAL, &st);
  o.degree_v = 3;
  expect_error(bsfit_filter_reduce_surface(&s, &o, NULL, NULL, &st), BSFIT_EINVAL, &st);
  /* tol 1e-300: nothing reaches it, within the knots allowed */
  o.tol = 1e-300;
  o.max_added = 20;
  bsfit_surface_free(&s);
  random_surface(&rng, 5, 5, 9, 8, 0, &s);
  expect_error(bsfit_filter_reduce_surface(&s, &o, &r, NULL, &st), BSFIT_ENOCONV, &st);
  memset(&so, 0, sizeof so);
  so.tol = 0.1;
  bsfit_surface_free(&s);
  /* closed around u with 4 distinct rows: a cubic filtered twice is of degree 5 and needs 6 */
  random_surface(&rng, 3, 3, 7, 6, 1, &s);
  expect_error(bsfit_filter_kernel_surface_delta(&s, 2, 1, 0.1, 0.1, &r, &st),
               BSFIT_ENOTPERIODIC, &st);
  assert_non_null(strstr(st.msg, "closed around u"));
  /* smoothing at an order that net cannot take is an error, not the surface unchanged;
  ** searched, no order is tried and the surface comes back unchanged */
  so.order = 2;
  expect_error(bsfit_filter_smooth_surface(&s, &so, &r, NULL, &st), BSFIT_ENOTPERIODIC, &st);
  assert_non_null(strstr(st.msg, "order = 2"));
  so.order = 0;
  {
    bsfit_smooth_report rep;
    assert_int_equal(bsfit_filter_smooth_surface(&s, &so, &r, &rep, &st), BSFIT_OK);
    assert_int_equal(rep.changed, 0);
    assert_int_equal(rep.evaluations, 0);
  }
  bsfit_surface_free(&s);
  bsfit_surface_free(&r);
}

/* }==================================================================== */

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_curve_bound_is_certified_and_tight),
      cmocka_unit_test(test_elevated_surface_comes_back),
      cmocka_unit_test(test_closed_surfaces),
      cmocka_unit_test(test_surface_reduce_within_tol),
      cmocka_unit_test(test_surface_smooth_bound_holds),
      cmocka_unit_test(test_bad_input),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
