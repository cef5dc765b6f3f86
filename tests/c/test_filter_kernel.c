/*
** test_filter_kernel.c
** Kernel filters (issue 17): the filter of order r must equal
**   - r applications of the box filter (1e-12), and
**   - the convolution of the extended curve with the cardinal B-spline kernel of degree
**     r - 1 on [-r delta, r delta], computed here from the kernel's own formula
**       K(x) = M_r((x + r delta) / (2 delta)) / (2 delta),
**       M_r(y) = 1/(r-1)! sum_{j=0..r} (-1)^j binom(r, j) (y - j)_+^{r-1},
**     by adaptive Gauss-Legendre quadrature split at the kernel's and the curve's knots
**     (1e-10), at 1000 parameters,
** for degrees 1-5 and orders 1-4 on open uniform (moving average), open clamped
** non-uniform and closed (uniform and non-uniform) curves, and for surfaces. Then every
** error.
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

#define EPS_CONV 1e-10 /* filtered curve vs numerical convolution */
#define EPS_PASS 1e-12 /* kernel vs r box passes */
#define NT 1000        /* parameters checked per curve */
#define MAXB 4096      /* break points of one convolution */

/* {====================================================================
** The kernel and the convolution, by quadrature
** ===================================================================== */

static double binom(int n, int k) {
  double b = 1.0;
  int i;
  for (i = 1; i <= k; i++) b = b * (double)(n - k + i) / (double)i;
  return b;
}

/* Cardinal B-spline of order r (degree r - 1) on [0, r], integer knots: the truncated
** power form. Only called inside a piece (y never an integer). */
static double cardinal(int r, double y) {
  double s = 0.0, fact = 1.0;
  int j;
  for (j = 1; j < r; j++) fact *= (double)j;
  for (j = 0; j <= r; j++)
    if (y - j > 0) s += (j % 2 ? -1.0 : 1.0) * binom(r, j) * pow(y - j, r - 1);
  return s / fact;
}

static double kernel(int r, double delta, double x) {
  return cardinal(r, (x + r * delta) / (2.0 * delta)) / (2.0 * delta);
}

/* 6-point rule (exact to degree 11) and 5-point rule (exact to degree 9) */
static const double G6_X[6] = {-0.9324695142031521, -0.6612093864662645, -0.2386191860831969,
                               0.2386191860831969,  0.6612093864662645,  0.9324695142031521};
static const double G6_W[6] = {0.1713244923791704, 0.3607615730481386, 0.4679139345726910,
                               0.4679139345726910, 0.3607615730481386, 0.1713244923791704};
static const double G5_X[5] = {-0.9061798459386640, -0.5384693101056831, 0.0, 0.5384693101056831,
                               0.9061798459386640};
static const double G5_W[5] = {0.2369268850561891, 0.4786286704993665, 0.5688888888888889,
                               0.4786286704993665, 0.2369268850561891};

typedef struct conv_ctx {
  vec_fn f;
  const void *fctx;
  int r, dim;
  double delta, t;
} conv_ctx;

/* integrand C_ext(t - x) K(x) at x */
static void integrand(const conv_ctx *c, double x, double *out) {
  double w = kernel(c->r, c->delta, x);
  int k;
  c->f(c->fctx, c->t - x, out);
  for (k = 0; k < c->dim; k++) out[k] *= w;
}

static void rule(const conv_ctx *c, const double *X, const double *W, int n, double x0,
                 double x1, double *acc) {
  double half = 0.5 * (x1 - x0), mid = 0.5 * (x0 + x1), y[4];
  int i, k;
  for (k = 0; k < c->dim; k++) acc[k] = 0.0;
  for (i = 0; i < n; i++) {
    integrand(c, mid + half * X[i], y);
    for (k = 0; k < c->dim; k++) acc[k] += half * W[i] * y[k];
  }
}

/* The 6-point value where the 5-point rule agrees with it, else the halves. */
static void adaptive(const conv_ctx *c, double x0, double x1, int depth, double *out) {
  double g6[4], g5[4], l[4], rr[4], err = 0.0;
  int k;
  rule(c, G6_X, G6_W, 6, x0, x1, g6);
  rule(c, G5_X, G5_W, 5, x0, x1, g5);
  for (k = 0; k < c->dim; k++) err = fmax(err, fabs(g6[k] - g5[k]));
  if (err <= 1e-14 * (x1 - x0) || depth >= 40) {
    memcpy(out, g6, (size_t)c->dim * sizeof(double));
    return;
  }
  adaptive(c, x0, 0.5 * (x0 + x1), depth + 1, l);
  adaptive(c, 0.5 * (x0 + x1), x1, depth + 1, rr);
  for (k = 0; k < c->dim; k++) out[k] = l[k] + rr[k];
}

static int cmp_double(const void *a, const void *b) {
  double x = *(const double *)a, y = *(const double *)b;
  return x < y ? -1 : (x > y ? 1 : 0);
}

/* (C_ext * K)(t): the kernel's knots and t - (each curve knot) cut [-r delta, r delta]. */
static void convolve(conv_ctx *c, const double *knots, size_t nk, double t, double *out) {
  double cut[MAXB], piece[4];
  size_t n = 0, i;
  int j, k;
  c->t = t;
  for (j = 0; j <= c->r; j++) cut[n++] = -c->r * c->delta + 2.0 * j * c->delta;
  for (i = 0; i < nk && n < MAXB; i++) {
    double x = t - knots[i];
    if (x > -c->r * c->delta && x < c->r * c->delta) cut[n++] = x;
  }
  qsort(cut, n, sizeof(double), cmp_double);
  for (k = 0; k < c->dim; k++) out[k] = 0.0;
  for (i = 0; i + 1 < n; i++) {
    if (!(cut[i + 1] > cut[i])) continue;
    adaptive(c, cut[i], cut[i + 1], 0, piece);
    for (k = 0; k < c->dim; k++) out[k] += piece[k];
  }
}

/* }==================================================================== */

/* {====================================================================
** Curves under test, their extensions and knots
** ===================================================================== */

enum kind { OPEN_UNIFORM, OPEN_CLAMPED, CLOSED_UNIFORM, CLOSED_NONUNIFORM };

/* A random curve of the kind, degree p, dimension 2 or 3. */
static void make_curve(test_rng *r, enum kind kd, int p, bsfit_curve *c) {
  double U[64], P[192], per[32];
  size_t n = (size_t)p + 6 + (size_t)(rng_uniform(r) * 5), i;
  int dim = rng_uniform(r) < 0.5 ? 2 : 3;
  bsfit_status st;
  bsfit_curve_init(c);
  random_points(r, n, dim, P);
  if (kd == OPEN_UNIFORM || kd == OPEN_CLAMPED) {
    if (kd == OPEN_UNIFORM) assert_int_equal(bsfit_knots_uniform(p, n, 0.0, 1.0, U, &st), BSFIT_OK);
    else random_knots(r, p, n, 1, U);
    assert_int_equal(bsfit_curve_new(c, p, dim, n, U, P, NULL, 0, NULL, &st), BSFIT_OK);
    return;
  }
  per[0] = 0.0;
  for (i = 1; i <= n; i++)
    per[i] = per[i - 1] + (kd == CLOSED_UNIFORM ? 1.0 / (double)n : rng_range(r, 0.2, 1.0));
  assert_int_equal(bsfit_curve_new_periodic(c, p, dim, n, per, P, NULL, NULL, &st), BSFIT_OK);
}

/* The extension to integrate (ext receives the padded curve for OPEN_UNIFORM) and the
** knots where it breaks, into K (room for 1024). */
static vec_fn extension(const bsfit_curve *c, enum kind kd, bsfit_curve *ext, const void **ctx,
                        double *K, size_t *nk) {
  size_t i, m = c->n + (size_t)c->degree + 1;
  int j;
  *nk = 0;
  bsfit_curve_init(ext);
  if (kd == OPEN_UNIFORM) {
    double h = c->knots[1] - c->knots[0];
    pad_curve(c, (size_t)c->degree + 40, h, ext);
    for (i = 0; i < ext->n + (size_t)ext->degree + 1; i++) K[(*nk)++] = ext->knots[i];
    *ctx = ext;
    return curve_fn;
  }
  *ctx = c;
  if (kd == OPEN_CLAMPED) {
    for (i = 0; i < m; i++) K[(*nk)++] = c->knots[i];
    return clamped_fn;
  }
  {
    double a, b;
    bsfit_curve_domain(c, &a, &b);
    for (j = -4; j <= 4; j++)
      for (i = (size_t)c->degree; i < m - (size_t)c->degree; i++)
        K[(*nk)++] = c->knots[i] + j * (b - a);
  }
  return curve_fn;
}

/* }==================================================================== */

/* {====================================================================
** Curves: kernel = r box passes = convolution with the B-spline kernel
** ===================================================================== */

/* r box passes of the same width, by the public box filter */
static void box_passes(const bsfit_curve *c, int r, int k, double delta, bsfit_curve *out) {
  bsfit_status st;
  int i;
  bsfit_curve_init(out);
  assert_int_equal(bsfit_curve_copy(c, out, NULL, &st), BSFIT_OK);
  for (i = 0; i < r; i++)
    assert_int_equal(k > 0 ? bsfit_filter_box_curve(out, k, out, &st)
                           : bsfit_filter_box_curve_delta(out, delta, out, &st),
                     BSFIT_OK);
}

static void check_one(test_rng *rng, enum kind kd, int p, int r) {
  bsfit_curve c, F, B, ext;
  double K[1024], a, b, lo, hi, delta;
  size_t nk, i;
  int k = 0, d;
  const void *ctx;
  vec_fn f;
  conv_ctx cc;
  bsfit_status st;
  make_curve(rng, kd, p, &c);
  bsfit_curve_domain(&c, &lo, &hi);
  bsfit_curve_init(&F);
  if (kd == OPEN_UNIFORM || kd == CLOSED_UNIFORM) {
    double h = c.knots[p + 1] - c.knots[p];
    k = 1 + (int)(rng_uniform(rng) * 3);
    delta = 0.5 * k * h;
    assert_int_equal(bsfit_filter_kernel_curve(&c, r, k, &F, &st), BSFIT_OK);
  } else {
    delta = rng_range(rng, 0.02, 0.45) * (hi - lo);
    assert_int_equal(bsfit_filter_kernel_curve_delta(&c, r, delta, &F, &st), BSFIT_OK);
  }
  assert_int_equal(F.degree, p + r);
  assert_int_equal(F.periodic, c.periodic);
  box_passes(&c, r, k, delta, &B);
  f = extension(&c, kd, &ext, &ctx, K, &nk);
  cc.f = f;
  cc.fctx = ctx;
  cc.r = r;
  cc.dim = c.dim;
  cc.delta = delta;
  bsfit_curve_domain(&F, &a, &b);
  for (i = 0; i < NT; i++) {
    double t = a + (b - a) * (double)i / (double)(NT - 1), got[4], box[4], want[4];
    assert_int_equal(bsfit_curve_eval(&F, t, got, &st), BSFIT_OK);
    assert_int_equal(bsfit_curve_eval(&B, t, box, &st), BSFIT_OK);
    convolve(&cc, K, nk, t, want);
    for (d = 0; d < c.dim; d++) {
      assert_float_equal(got[d], box[d], EPS_PASS);
      assert_float_equal(got[d], want[d], EPS_CONV);
    }
  }
  bsfit_curve_free(&c);
  bsfit_curve_free(&F);
  bsfit_curve_free(&B);
  bsfit_curve_free(&ext);
}

static void run_kind(enum kind kd, uint64_t seed) {
  test_rng rng;
  int p, r;
  rng.s = seed;
  for (p = 1; p <= 5; p++)
    for (r = 1; r <= 4; r++) check_one(&rng, kd, p, r);
}

static void test_open_uniform(void **state) {
  (void)state;
  run_kind(OPEN_UNIFORM, 0x6b65726e01);
}

static void test_open_clamped_nonuniform(void **state) {
  (void)state;
  run_kind(OPEN_CLAMPED, 0x6b65726e02);
}

static void test_closed_uniform(void **state) {
  (void)state;
  run_kind(CLOSED_UNIFORM, 0x6b65726e03);
}

static void test_closed_nonuniform(void **state) {
  (void)state;
  run_kind(CLOSED_NONUNIFORM, 0x6b65726e04);
}

/* On uniform knots the moving-average form and the exact form give one curve. */
static void test_moving_average_equals_exact(void **state) {
  test_rng rng = {0x6b65726e05};
  int p, r;
  (void)state;
  for (p = 1; p <= 4; p++)
    for (r = 1; r <= 4; r++) {
      bsfit_curve c, A, E;
      double h, a, b;
      int k = 1 + (int)(rng_uniform(&rng) * 3), i, d;
      bsfit_status st;
      make_curve(&rng, CLOSED_UNIFORM, p, &c);
      h = c.knots[p + 1] - c.knots[p];
      bsfit_curve_init(&A);
      bsfit_curve_init(&E);
      assert_int_equal(bsfit_filter_kernel_curve(&c, r, k, &A, &st), BSFIT_OK);
      assert_int_equal(bsfit_filter_kernel_curve_delta(&c, r, 0.5 * k * h, &E, &st), BSFIT_OK);
      bsfit_curve_domain(&A, &a, &b);
      for (i = 0; i < 200; i++) {
        double t = a + (b - a) * i / 199.0, x[4], y[4];
        bsfit_curve_eval(&A, t, x, NULL);
        bsfit_curve_eval(&E, t, y, NULL);
        for (d = 0; d < c.dim; d++) assert_float_equal(x[d], y[d], EPS_PASS);
      }
      bsfit_curve_free(&c);
      bsfit_curve_free(&A);
      bsfit_curve_free(&E);
    }
}

/* }==================================================================== */

/* {====================================================================
** Surfaces
** ===================================================================== */

/* Sorted cuts of [-r delta, r delta]: the kernel's knots and t - (each knot). */
static size_t cuts(int r, double delta, double t, const double *U, size_t nk, double *cut) {
  size_t n = 0, i;
  int j;
  for (j = 0; j <= r; j++) cut[n++] = -r * delta + 2.0 * j * delta;
  for (i = 0; i < nk; i++) {
    double x = t - U[i];
    if (x > -r * delta && x < r * delta) cut[n++] = x;
  }
  qsort(cut, n, sizeof(double), cmp_double);
  return n;
}

/* (S_ext * K_u K_v)(u, v), S_ext the clamped surface extended as constant, by the
** 5-point Gauss rule on every piece of the two cut sets (exact: each piece's integrand
** is a polynomial of degree <= 9 in each variable here). */
static void convolve2(const bsfit_surface *s, int ru, int rv, double du, double dv, double u,
                      double v, double *out) {
  double cu[256], cv[256], ua, ub, va, vb, x[3];
  size_t nu = cuts(ru, du, u, s->knots_u, s->nu + (size_t)s->degree_u + 1, cu);
  size_t nv = cuts(rv, dv, v, s->knots_v, s->nv + (size_t)s->degree_v + 1, cv), i, j;
  int g, h, k;
  bsfit_surface_domain(s, &ua, &ub, &va, &vb);
  for (k = 0; k < s->dim; k++) out[k] = 0.0;
  for (i = 0; i + 1 < nu; i++)
    for (g = 0; g < 5 && cu[i + 1] > cu[i]; g++) {
      double hx = 0.5 * (cu[i + 1] - cu[i]), px = 0.5 * (cu[i] + cu[i + 1]) + hx * G5_X[g];
      double wx = hx * G5_W[g] * kernel(ru, du, px), uu = fmin(fmax(u - px, ua), ub);
      for (j = 0; j + 1 < nv; j++)
        for (h = 0; h < 5 && cv[j + 1] > cv[j]; h++) {
          double hy = 0.5 * (cv[j + 1] - cv[j]), py = 0.5 * (cv[j] + cv[j + 1]) + hy * G5_X[h];
          double w = wx * hy * G5_W[h] * kernel(rv, dv, py), vv = fmin(fmax(v - py, va), vb);
          assert_int_equal(bsfit_surface_eval(s, uu, vv, x, NULL), BSFIT_OK);
          for (k = 0; k < s->dim; k++) out[k] += w * x[k];
        }
    }
}

static void random_surface(test_rng *r, int pu, int pv, int clamped, bsfit_surface *s) {
  size_t nu = (size_t)pu + 4, nv = (size_t)pv + 5;
  double Uu[32], Uv[32], P[12 * 12 * 3];
  bsfit_status st;
  if (clamped) {
    random_knots(r, pu, nu, 1, Uu);
    random_knots(r, pv, nv, 1, Uv);
  } else {
    bsfit_knots_uniform(pu, nu, 0.0, 1.0, Uu, NULL);
    bsfit_knots_uniform(pv, nv, 0.0, 2.0, Uv, NULL);
  }
  random_points(r, nu * nv, 3, P);
  bsfit_surface_init(s);
  assert_int_equal(bsfit_surface_new(s, pu, pv, 3, nu, nv, Uu, Uv, P, NULL, NULL, &st), BSFIT_OK);
}

static void check_surfaces_equal(const bsfit_surface *A, const bsfit_surface *B, double eps) {
  double ua, ub, va, vb, x[3], y[3];
  int i, j, k;
  bsfit_surface_domain(A, &ua, &ub, &va, &vb);
  for (i = 0; i < 20; i++)
    for (j = 0; j < 20; j++) {
      double u = ua + (ub - ua) * i / 19.0, v = va + (vb - va) * j / 19.0;
      bsfit_surface_eval(A, u, v, x, NULL);
      bsfit_surface_eval(B, u, v, y, NULL);
      for (k = 0; k < 3; k++) assert_float_equal(x[k], y[k], eps);
    }
}

static void test_surface_matches_convolution(void **state) {
  test_rng rng = {0x6b65726e06};
  int c;
  (void)state;
  for (c = 0; c < 6; c++) {
    int pu = 1 + c % 3, pv = 1 + (c + 1) % 3, ru = 1 + c % 3, rv = 1 + (c / 2) % 3, i, j, k;
    bsfit_surface s, F;
    double ua, ub, va, vb, du, dv;
    bsfit_status st;
    random_surface(&rng, pu, pv, 1, &s);
    bsfit_surface_domain(&s, &ua, &ub, &va, &vb);
    du = rng_range(&rng, 0.05, 0.4) * (ub - ua);
    dv = rng_range(&rng, 0.05, 0.4) * (vb - va);
    bsfit_surface_init(&F);
    assert_int_equal(bsfit_filter_kernel_surface_delta(&s, ru, rv, du, dv, &F, &st), BSFIT_OK);
    assert_int_equal(F.degree_u, pu + ru);
    assert_int_equal(F.degree_v, pv + rv);
    bsfit_surface_domain(&F, &ua, &ub, &va, &vb);
    for (i = 0; i < 12; i++)
      for (j = 0; j < 12; j++) {
        double u = ua + (ub - ua) * i / 11.0, v = va + (vb - va) * j / 11.0, x[3], y[3];
        assert_int_equal(bsfit_surface_eval(&F, u, v, x, &st), BSFIT_OK);
        convolve2(&s, ru, rv, du, dv, u, v, y);
        for (k = 0; k < 3; k++) assert_float_equal(x[k], y[k], EPS_CONV);
      }
    bsfit_surface_free(&s);
    bsfit_surface_free(&F);
  }
}

static void test_surface_equals_box_passes(void **state) {
  test_rng rng = {0x6b65726e07};
  int r, uniform;
  (void)state;
  for (uniform = 0; uniform <= 1; uniform++)
    for (r = 1; r <= 3; r++) {
      bsfit_surface s, F, B;
      double ua, ub, va, vb, du, dv;
      bsfit_status st;
      int i;
      random_surface(&rng, 1 + r % 3, 2, !uniform, &s);
      bsfit_surface_domain(&s, &ua, &ub, &va, &vb);
      du = 0.2 * (ub - ua);
      dv = 0.13 * (vb - va);
      bsfit_surface_init(&F);
      bsfit_surface_init(&B);
      assert_int_equal(bsfit_surface_copy(&s, &B, NULL, &st), BSFIT_OK);
      if (uniform) {
        assert_int_equal(bsfit_filter_kernel_surface(&s, r, r, 2, 1, &F, &st), BSFIT_OK);
        for (i = 0; i < r; i++)
          assert_int_equal(bsfit_filter_box_surface(&B, 2, 1, &B, &st), BSFIT_OK);
      } else {
        assert_int_equal(bsfit_filter_kernel_surface_delta(&s, r, r, du, dv, &F, &st), BSFIT_OK);
        for (i = 0; i < r; i++)
          assert_int_equal(bsfit_filter_box_surface_delta(&B, du, dv, &B, &st), BSFIT_OK);
      }
      check_surfaces_equal(&F, &B, EPS_PASS);
      bsfit_surface_free(&s);
      bsfit_surface_free(&F);
      bsfit_surface_free(&B);
    }
}

/* }==================================================================== */

/* {====================================================================
** Errors
** ===================================================================== */

static void test_bad_input(void **state) {
  test_rng rng = {0x6b65726e08};
  bsfit_curve c, F, R;
  bsfit_surface s, G;
  bsfit_status st;
  double w[16];
  int i;
  (void)state;
  make_curve(&rng, OPEN_CLAMPED, 3, &c);
  bsfit_curve_init(&F);
  expect_error(bsfit_filter_kernel_curve_delta(&c, 0, 0.1, &F, &st), BSFIT_EINVAL, &st);
  expect_error(bsfit_filter_kernel_curve_delta(&c, -2, 0.1, &F, &st), BSFIT_EINVAL, &st);
  expect_error(bsfit_filter_kernel_curve_delta(&c, BSFIT_MAX_DEGREE, 0.1, &F, &st),
               BSFIT_EDEGREE, &st);
  expect_error(bsfit_filter_kernel_curve_delta(&c, 2, NAN, &F, &st), BSFIT_ENONFINITE, &st);
  expect_error(bsfit_filter_kernel_curve_delta(&c, 2, -1.0, &F, &st), BSFIT_EINVAL, &st);
  expect_error(bsfit_filter_kernel_curve_delta(&c, 2, 1e6, &F, &st), BSFIT_EINVAL, &st);
  /* the moving average wants uniform knots */
  expect_error(bsfit_filter_kernel_curve(&c, 2, 1, &F, &st), BSFIT_EINVAL, &st);
  expect_error(bsfit_filter_kernel_curve_delta(NULL, 2, 0.1, &F, &st), BSFIT_EINVAL, &st);
  expect_error(bsfit_filter_kernel_curve_delta(&c, 2, 0.1, NULL, &st), BSFIT_EINVAL, &st);
  assert_null(F.ctrl); /* untouched */
  /* rational curves are refused */
  for (i = 0; i < 16; i++) w[i] = 1.0 + 0.1 * i;
  bsfit_curve_init(&R);
  assert_int_equal(bsfit_curve_new(&R, c.degree, c.dim, c.n, c.knots, c.ctrl, w, 0, NULL, &st),
                   BSFIT_OK);
  expect_error(bsfit_filter_kernel_curve_delta(&R, 2, 0.1, &F, &st), BSFIT_EINVAL, &st);
  random_surface(&rng, 2, 2, 1, &s);
  bsfit_surface_init(&G);
  expect_error(bsfit_filter_kernel_surface_delta(&s, 0, 1, 0.1, 0.1, &G, &st), BSFIT_EINVAL, &st);
  expect_error(bsfit_filter_kernel_surface_delta(&s, 1, 0, 0.1, 0.1, &G, &st), BSFIT_EINVAL, &st);
  expect_error(bsfit_filter_kernel_surface_delta(&s, 1, 1, -0.1, 0.1, &G, &st), BSFIT_EINVAL, &st);
  expect_error(bsfit_filter_kernel_surface_delta(&s, 1, 1, 0.1, NAN, &G, &st), BSFIT_ENONFINITE,
               &st);
  expect_error(bsfit_filter_kernel_surface(&s, 1, 1, 1, 1, &G, &st), BSFIT_EINVAL, &st);
  expect_error(bsfit_filter_kernel_surface_delta(NULL, 1, 1, 0.1, 0.1, &G, &st), BSFIT_EINVAL, &st);
  assert_null(G.ctrl);
  bsfit_curve_free(&c);
  bsfit_curve_free(&R);
  bsfit_surface_free(&s);
}

/* The output may be the input; an interrupted host gets EINTR between passes. */
static void test_in_place_and_interrupt(void **state) {
  test_rng rng = {0x6b65726e09};
  bsfit_curve c, F;
  bsfit_status st;
  volatile int stop = 1;
  double a, b;
  (void)state;
  make_curve(&rng, CLOSED_NONUNIFORM, 3, &c);
  bsfit_curve_domain(&c, &a, &b);
  bsfit_curve_init(&F);
  assert_int_equal(bsfit_filter_kernel_curve_delta(&c, 2, 0.1 * (b - a), &F, &st), BSFIT_OK);
  assert_int_equal(bsfit_filter_kernel_curve_delta(&c, 2, 0.1 * (b - a), &c, &st), BSFIT_OK);
  assert_int_equal(c.degree, 5);
  assert_int_equal(c.n, F.n);
  assert_memory_equal(c.ctrl, F.ctrl, c.n * (size_t)c.dim * sizeof(double));
  c.alloc.interrupt = &stop;
  expect_error(bsfit_filter_kernel_curve_delta(&c, 3, 0.1 * (b - a), &F, &st), BSFIT_EINTR, &st);
  c.alloc.interrupt = NULL;
  bsfit_curve_free(&c);
  bsfit_curve_free(&F);
}

/* }==================================================================== */

int main(void) {
  const struct CMUnitTest tests[] = {
    cmocka_unit_test(test_open_uniform),
    cmocka_unit_test(test_open_clamped_nonuniform),
    cmocka_unit_test(test_closed_uniform),
    cmocka_unit_test(test_closed_nonuniform),
    cmocka_unit_test(test_moving_average_equals_exact),
    cmocka_unit_test(test_surface_matches_convolution),
    cmocka_unit_test(test_surface_equals_box_passes),
    cmocka_unit_test(test_bad_input),
    cmocka_unit_test(test_in_place_and_interrupt),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
