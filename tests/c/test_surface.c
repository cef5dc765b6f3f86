/*
** test_surface.c
** Tensor-product surfaces checked against mathematics: partition of unity, linear
** precision (Marsden), the bilinear interpolant, Bernstein tensor products, finite
** differences, exact NURBS cylinder and sphere patches, normals, and every error code.
*/
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#include <math.h>
#include <cmocka.h>

#include "bsfit.h"
#include "testutil.h"

#define POINT_EPS 1e-14 /* exact geometry, a few roundings */
#define FD_EPS 1e-6     /* relative error of central differences with h = 1e-5 */

/* {====================================================================
** Helpers
** ===================================================================== */


static double lcg(unsigned *state) {
  *state = *state * 1664525u + 1013904223u;
  return (double)(*state >> 8) / 16777216.0;
}

/* A 3D bicubic-by-quadratic non-uniform surface with random control points. */
static void make_surface(bsfit_surface *s, int rational, unsigned seed) {
  static const double U[] = {0, 0, 0, 0, 0.3, 0.45, 1, 1, 1, 1};      /* p = 3, n = 6 */
  static const double V[] = {-1, -1, -1, 0.2, 0.5, 0.5, 2, 2, 2};      /* p = 2, n = 6 */
  double ctrl[6 * 6 * 3], w[36];
  size_t i;
  for (i = 0; i < 108; i++) ctrl[i] = 2 * lcg(&seed) - 1;
  for (i = 0; i < 36; i++) w[i] = 0.5 + lcg(&seed);
  assert_int_equal(bsfit_surface_new(s, 3, 2, 3, 6, 6, U, V, ctrl, rational ? w : NULL, NULL, NULL),
                   BSFIT_OK);
}

/* Quarter cylinder x^2 + y^2 = 1, 0 <= z <= 2: quarter circle (degree 2) x line. */
static void make_cylinder(bsfit_surface *s) {
  const double r = sqrt(0.5);
  const double ctrl[] = {1, 0, 0, 1, 0, 2, 1, 1, 0, 1, 1, 2, 0, 1, 0, 0, 1, 2};
  const double w[] = {1, 1, r, r, 1, 1};
  assert_int_equal(bsfit_surface_new(s, 2, 1, 3, 3, 2, NULL, NULL, ctrl, w, NULL, NULL), BSFIT_OK);
}

/* Octant of the unit sphere: a quarter meridian (degree 2) revolved by a quarter turn
** (degree 2); the row i = 2 of meridian points collapses to the pole (0, 0, 1). */
static void make_sphere(bsfit_surface *s) {
  const double r = sqrt(0.5);
  const double mr[3] = {1, 1, 0}, mz[3] = {0, 1, 1}, mw[3] = {1, r, 1};  /* meridian */
  const double cx[3] = {1, 1, 0}, cy[3] = {0, 1, 1}, cw[3] = {1, r, 1};  /* quarter circle */
  double ctrl[27], w[9];
  size_t i, j;
  for (i = 0; i < 3; i++)
    for (j = 0; j < 3; j++) {
      double *P = ctrl + (i * 3 + j) * 3;
      P[0] = mr[i] * cx[j];
      P[1] = mr[i] * cy[j];
      P[2] = mz[i];
      w[i * 3 + j] = mw[i] * cw[j];
    }
  assert_int_equal(bsfit_surface_new(s, 2, 2, 3, 3, 3, NULL, NULL, ctrl, w, NULL, NULL), BSFIT_OK);
}

/* }==================================================================== */

/* {====================================================================
** Evaluation
** ===================================================================== */

static void test_partition_of_unity(void **state) {
  /* given: surfaces whose control points all equal P (polynomial and rational) */
  static const double U[] = {0, 0, 0, 0.1, 0.1, 0.7, 1, 1, 1};
  static const double V[] = {0, 0, 0, 0, 0.25, 0.5, 0.75, 1, 1, 1, 1};
  const double P[3] = {1.5, -2.25, 7.0};
  double ctrl[6 * 7 * 3], w[42], out[3];
  unsigned seed = 7;
  size_t i;
  int rational;
  (void)state;
  for (i = 0; i < 42; i++) {
    memcpy(ctrl + 3 * i, P, sizeof P);
    w[i] = 0.1 + 3 * lcg(&seed);
  }
  for (rational = 0; rational <= 1; rational++) {
    bsfit_surface s;
    bsfit_surface_init(&s);
    assert_int_equal(bsfit_surface_new(&s, 2, 3, 3, 6, 7, U, V, ctrl, rational ? w : NULL, NULL,
                                       NULL), BSFIT_OK);
    /* when/then: every point is P, because the basis sums to one */
    for (i = 0; i <= 40; i++) {
      double u = (double)i / 40, v = lcg(&seed);
      assert_int_equal(bsfit_surface_eval(&s, u, v, out, NULL), BSFIT_OK);
      assert_float_equal(out[0], P[0], POINT_EPS * 8);
      assert_float_equal(out[1], P[1], POINT_EPS * 8);
      assert_float_equal(out[2], P[2], POINT_EPS * 8);
    }
    bsfit_surface_free(&s);
  }
}

static void test_linear_precision(void **state) {
  /* given: control points at the Greville abscissae (xi_i, eta_j, xi_i * eta_j) */
  static const double U[] = {0, 0, 0, 0, 0.2, 0.3, 0.8, 1, 1, 1, 1}; /* p = 3, n = 7 */
  static const double V[] = {0, 0, 0, 0.5, 0.6, 1, 1, 1};            /* p = 2, n = 5 */
  double ctrl[7 * 5 * 3], out[3];
  size_t i, j;
  bsfit_surface s;
  (void)state;
  for (i = 0; i < 7; i++)
    for (j = 0; j < 5; j++) {
      double xi = (U[i + 1] + U[i + 2] + U[i + 3]) / 3, eta = (V[j + 1] + V[j + 2]) / 2;
      double *P = ctrl + (i * 5 + j) * 3;
      P[0] = xi;
      P[1] = eta;
      P[2] = xi * eta;
    }
  bsfit_surface_init(&s);
  assert_int_equal(bsfit_surface_new(&s, 3, 2, 3, 7, 5, U, V, ctrl, NULL, NULL, NULL), BSFIT_OK);
  /* then: S(u, v) = (u, v, u v) (Marsden's identity in each direction) */
  for (i = 0; i <= 20; i++)
    for (j = 0; j <= 20; j++) {
      double u = i / 20.0, v = j / 20.0;
      assert_int_equal(bsfit_surface_eval(&s, u, v, out, NULL), BSFIT_OK);
      assert_float_equal(out[0], u, POINT_EPS * 4);
      assert_float_equal(out[1], v, POINT_EPS * 4);
      assert_float_equal(out[2], u * v, POINT_EPS * 4);
    }
  bsfit_surface_free(&s);
}

static void test_bilinear(void **state) {
  const double c[] = {0, 0, 1, /* (0,0) */ 2, 0.5, 3, /* (0,1) */ 1, 3, -1, /* (1,0) */ 4, 4, 0};
  const double U[] = {0, 0, 2, 2}, V[] = {1, 1, 5, 5};
  bsfit_surface s;
  double out[3];
  int i, j, k;
  (void)state;
  bsfit_surface_init(&s);
  assert_int_equal(bsfit_surface_new(&s, 1, 1, 3, 2, 2, U, V, c, NULL, NULL, NULL), BSFIT_OK);
  for (i = 0; i <= 10; i++)
    for (j = 0; j <= 10; j++) {
      double a = i / 10.0, b = j / 10.0;
      assert_int_equal(bsfit_surface_eval(&s, 2 * a, 1 + 4 * b, out, NULL), BSFIT_OK);
      for (k = 0; k < 3; k++) {
        double want = (1 - a) * (1 - b) * c[k] + (1 - a) * b * c[3 + k] + a * (1 - b) * c[6 + k] +
                      a * b * c[9 + k];
        assert_float_equal(out[k], want, POINT_EPS * 8);
      }
    }
  bsfit_surface_free(&s);
}

/* Tensor de Casteljau written out here, independently of the library. */
static void casteljau2(const double *ctrl, const double *w, int nu, int nv, double u, double v,
                       double *out) {
  double row[8][4], q[8][4];
  int i, j, r, k;
  for (i = 0; i < nu; i++) {
    for (j = 0; j < nv; j++) {
      double wt = w ? w[i * nv + j] : 1;
      for (k = 0; k < 3; k++) q[j][k] = wt * ctrl[(i * nv + j) * 3 + k];
      q[j][3] = wt;
    }
    for (r = 1; r < nv; r++)
      for (j = 0; j < nv - r; j++)
        for (k = 0; k < 4; k++) q[j][k] = (1 - v) * q[j][k] + v * q[j + 1][k];
    memcpy(row[i], q[0], sizeof row[i]);
  }
  for (r = 1; r < nu; r++)
    for (i = 0; i < nu - r; i++)
      for (k = 0; k < 4; k++) row[i][k] = (1 - u) * row[i][k] + u * row[i + 1][k];
  for (k = 0; k < 3; k++) out[k] = row[0][k] / row[0][3];
}

static void test_bezier_equals_bspline(void **state) {
  double ctrl[4 * 3 * 3], w[12], a[3], b[3], c[3];
  unsigned seed = 11;
  int i, k, rational;
  (void)state;
  for (i = 0; i < 36; i++) ctrl[i] = lcg(&seed) * 4 - 2;
  for (i = 0; i < 12; i++) w[i] = 0.3 + lcg(&seed);
  for (rational = 0; rational <= 1; rational++) {
    bsfit_surface bz, bs;
    bsfit_surface_init(&bz);
    bsfit_surface_init(&bs);
    /* given: the same net as a Bézier surface and as a clamped one-span B-spline */
    assert_int_equal(bsfit_surface_new_bezier(&bz, 3, 4, 3, ctrl, rational ? w : NULL, NULL, NULL),
                     BSFIT_OK);
    assert_int_equal(bz.degree_u, 3);
    assert_int_equal(bz.degree_v, 2);
    assert_int_equal(bsfit_surface_new(&bs, 3, 2, 3, 4, 3, NULL, NULL, ctrl, rational ? w : NULL,
                                       NULL, NULL), BSFIT_OK);
    for (i = 0; i < 50; i++) {
      double u = lcg(&seed), v = lcg(&seed);
      assert_int_equal(bsfit_surface_eval(&bz, u, v, a, NULL), BSFIT_OK);
      assert_int_equal(bsfit_surface_eval(&bs, u, v, b, NULL), BSFIT_OK);
      casteljau2(ctrl, rational ? w : NULL, 4, 3, u, v, c);
      for (k = 0; k < 3; k++) {
        assert_float_equal(a[k], c[k], POINT_EPS * 16);
        assert_float_equal(b[k], c[k], POINT_EPS * 16);
      }
    }
    /* corners are interpolated */
    assert_int_equal(bsfit_surface_eval(&bz, 1, 0, a, NULL), BSFIT_OK);
    for (k = 0; k < 3; k++) assert_float_equal(a[k], ctrl[9 * 3 + k], POINT_EPS * 4);
    bsfit_surface_free(&bz);
    bsfit_surface_free(&bs);
  }
}

static void test_exact_cylinder_and_sphere(void **state) {
  bsfit_surface cyl, sph;
  double P[3];
  int i, j;
  (void)state;
  bsfit_surface_init(&cyl);
  bsfit_surface_init(&sph);
  make_cylinder(&cyl);
  make_sphere(&sph);
  for (i = 0; i <= 30; i++)
    for (j = 0; j <= 30; j++) {
      double u = i / 30.0, v = j / 30.0;
      assert_int_equal(bsfit_surface_eval(&cyl, u, v, P, NULL), BSFIT_OK);
      assert_float_equal(sqrt(P[0] * P[0] + P[1] * P[1]), 1.0, POINT_EPS);
      assert_float_equal(P[2], 2 * v, POINT_EPS);
      assert_int_equal(bsfit_surface_eval(&sph, u, v, P, NULL), BSFIT_OK);
      assert_float_equal(sqrt(P[0] * P[0] + P[1] * P[1] + P[2] * P[2]), 1.0, POINT_EPS);
      assert_true(P[0] >= -POINT_EPS && P[1] >= -POINT_EPS && P[2] >= -POINT_EPS);
    }
  bsfit_surface_free(&cyl);
  bsfit_surface_free(&sph);
}

/* }==================================================================== */

/* {====================================================================
** Derivatives and normals
** ===================================================================== */

/* Each derivative (a, b) against central differences of (a-1, b) in u or (a, b-1) in v. */
static void check_derivs_fd(const bsfit_surface *s, double u, double v, int k) {
  const double h = 1e-5;
  size_t K = (size_t)k + 1, d = (size_t)s->dim, a, b, t;
  double D[4 * 4 * 3], Dp[4 * 4 * 3], Dm[4 * 4 * 3], P[3];
  assert_int_equal(bsfit_surface_derivs(s, u, v, k, D, NULL), BSFIT_OK);
  assert_int_equal(bsfit_surface_eval(s, u, v, P, NULL), BSFIT_OK);
  for (t = 0; t < d; t++) assert_float_equal(D[t], P[t], POINT_EPS * 16);
  for (a = 0; a < K; a++)
    for (b = 0; b < K; b++) {
      int in_u = a > 0;
      if (a == 0 && b == 0) continue;
      if (in_u) {
        assert_int_equal(bsfit_surface_derivs(s, u + h, v, k, Dp, NULL), BSFIT_OK);
        assert_int_equal(bsfit_surface_derivs(s, u - h, v, k, Dm, NULL), BSFIT_OK);
      } else {
        assert_int_equal(bsfit_surface_derivs(s, u, v + h, k, Dp, NULL), BSFIT_OK);
        assert_int_equal(bsfit_surface_derivs(s, u, v - h, k, Dm, NULL), BSFIT_OK);
      }
      for (t = 0; t < d; t++) {
        size_t lower = (in_u ? ((a - 1) * K + b) : (a * K + b - 1)) * d + t;
        double fd = (Dp[lower] - Dm[lower]) / (2 * h), got = D[(a * K + b) * d + t];
        assert_float_equal(got, fd, FD_EPS * (1 + fabs(fd) + fabs(D[lower])));
      }
    }
}

static void test_derivs_finite_differences(void **state) {
  bsfit_surface s;
  int rational;
  (void)state;
  for (rational = 0; rational <= 1; rational++) {
    bsfit_surface_init(&s);
    make_surface(&s, rational, 5u + (unsigned)rational);
    /* points inside spans (finite differences straddling a knot would see a kink) */
    check_derivs_fd(&s, 0.2, -0.5, 2);
    check_derivs_fd(&s, 0.37, 0.3, 2);
    check_derivs_fd(&s, 0.8, 1.5, 3);
    check_derivs_fd(&s, 0.05, 0.9, 1);
    bsfit_surface_free(&s);
  }
  /* the sphere: rational with non-zero derivatives above the degree */
  bsfit_surface_init(&s);
  make_sphere(&s);
  check_derivs_fd(&s, 0.3, 0.6, 3);
  bsfit_surface_free(&s);
}

static void test_derivs_polynomial_degree(void **state) {
  /* derivatives above the degree of a polynomial surface are zero */
  bsfit_surface s;
  double D[5 * 5 * 3];
  int t;
  (void)state;
  bsfit_surface_init(&s);
  make_surface(&s, 0, 3);
  assert_int_equal(bsfit_surface_derivs(&s, 0.5, 0.1, 4, D, NULL), BSFIT_OK);
  for (t = 0; t < 3; t++) {
    assert_float_equal(D[(4 * 5 + 0) * 3 + t], 0.0, 0.0); /* (4, 0): pu = 3 */
    assert_float_equal(D[(0 * 5 + 3) * 3 + t], 0.0, 0.0); /* (0, 3): pv = 2 */
  }
  bsfit_surface_free(&s);
}

static void test_normals(void **state) {
  /* given: the plane z = 2x + 3y as a bilinear patch with u along x and v along y */
  const double c[] = {0, 0, 0, 0, 1, 3, 1, 0, 2, 1, 1, 5};
  const double k = 1 / sqrt(14.0);
  bsfit_surface plane, sph;
  bsfit_status st;
  double n[3], P[3];
  int i;
  (void)state;
  bsfit_surface_init(&plane);
  bsfit_surface_init(&sph);
  assert_int_equal(bsfit_surface_new(&plane, 1, 1, 3, 2, 2, NULL, NULL, c, NULL, NULL, NULL),
                   BSFIT_OK);
  for (i = 0; i < 5; i++) {
    assert_int_equal(bsfit_surface_normal(&plane, i / 4.0, 1 - i / 4.0, n, &st), BSFIT_OK);
    assert_float_equal(n[0], -2 * k, POINT_EPS);
    assert_float_equal(n[1], -3 * k, POINT_EPS);
    assert_float_equal(n[2], k, POINT_EPS);
  }
  /* the sphere's normal is the radius direction, and its pole is degenerate */
  make_sphere(&sph);
  assert_int_equal(bsfit_surface_normal(&sph, 0.4, 0.7, n, NULL), BSFIT_OK);
  assert_int_equal(bsfit_surface_eval(&sph, 0.4, 0.7, P, NULL), BSFIT_OK);
  assert_float_equal(fabs(n[0] * P[0] + n[1] * P[1] + n[2] * P[2]), 1.0, 1e-13);
  assert_int_equal(bsfit_surface_normal(&sph, 1.0, 0.3, n, &st), BSFIT_EDEGENERATE);
  assert_int_equal(st.code, BSFIT_EDEGENERATE);
  assert_true(n[0] == 0 && n[1] == 0 && n[2] == 0);
  bsfit_surface_free(&plane);
  bsfit_surface_free(&sph);
}

/* }==================================================================== */

/* {====================================================================
** Grid, copy, memory, errors
** ===================================================================== */

static void test_sample_grid(void **state) {
  bsfit_surface s;
  double *grid, P[3];
  size_t ku = 17, kv = 23, a, b, t;
  int rational;
  (void)state;
  grid = malloc(ku * kv * 3 * sizeof(double));
  assert_non_null(grid);
  for (rational = 0; rational <= 1; rational++) {
    double ua, ub, va, vb;
    bsfit_surface_init(&s);
    make_surface(&s, rational, 9);
    bsfit_surface_domain(&s, &ua, &ub, &va, &vb);
    assert_int_equal(bsfit_surface_sample_grid(&s, ku, kv, grid, NULL), BSFIT_OK);
    /* each grid point is S at the documented parameters */
    for (a = 0; a < ku; a++)
      for (b = 0; b < kv; b++) {
        double u = ua + (ub - ua) * (double)a / (double)(ku - 1);
        double v = va + (vb - va) * (double)b / (double)(kv - 1);
        assert_int_equal(bsfit_surface_eval(&s, u, v, P, NULL), BSFIT_OK);
        for (t = 0; t < 3; t++) assert_float_equal(grid[(a * kv + b) * 3 + t], P[t], POINT_EPS * 16);
      }
    bsfit_surface_free(&s);
  }
  /* a sphere grid stays on the sphere, the Bézier path included */
  bsfit_surface_init(&s);
  make_sphere(&s);
  assert_int_equal(bsfit_surface_sample_grid(&s, ku, kv, grid, NULL), BSFIT_OK);
  for (a = 0; a < ku * kv; a++) {
    const double *Q = grid + a * 3;
    assert_float_equal(sqrt(Q[0] * Q[0] + Q[1] * Q[1] + Q[2] * Q[2]), 1.0, POINT_EPS);
  }
  bsfit_surface_free(&s);
  free(grid);
}

static void test_copy_move(void **state) {
  bsfit_surface s, c, m;
  double P[3], Q[3];
  (void)state;
  bsfit_surface_init(&s);
  bsfit_surface_init(&c);
  bsfit_surface_init(&m);
  make_surface(&s, 1, 4);
  assert_int_equal(bsfit_surface_copy(&s, &c, NULL, NULL), BSFIT_OK);
  assert_ptr_not_equal(c.ctrl, s.ctrl);
  assert_memory_equal(c.ctrl, s.ctrl, 6 * 6 * 3 * sizeof(double));
  assert_memory_equal(c.weights, s.weights, 36 * sizeof(double));
  assert_memory_equal(c.knots_v, s.knots_v, 9 * sizeof(double));
  bsfit_surface_move(&c, &m);
  assert_null(c.ctrl);
  assert_int_equal(bsfit_surface_eval(&s, 0.3, 0.3, P, NULL), BSFIT_OK);
  assert_int_equal(bsfit_surface_eval(&m, 0.3, 0.3, Q, NULL), BSFIT_OK);
  assert_memory_equal(P, Q, sizeof P);
  bsfit_surface_free(&s);
  bsfit_surface_free(&m);
  bsfit_surface_free(&m); /* idempotent */
  bsfit_surface_free(NULL);
}

static void test_allocation_failures(void **state) {
  /* every allocation of new, copy and sample_grid may fail: ENOMEM and no leak */
  static const double U[] = {0, 0, 0, 1, 1, 1}, V[] = {0, 0, 1, 1};
  double ctrl[3 * 2 * 3] = {0, 0, 0, 1, 0, 0, 0, 1, 0, 1, 1, 0, 0, 2, 1, 2, 2, 1};
  double w[6] = {1, 2, 1, 1, 2, 1}, grid[5 * 5 * 3];
  long n;
  (void)state;
  for (n = 1; n < 20; n++) {
    counting c = {0, n, 0};
    bsfit_allocator a = {counting_alloc, &c, NULL};
    bsfit_surface s, d;
    bsfit_err e;
    bsfit_surface_init(&s);
    bsfit_surface_init(&d);
    e = bsfit_surface_new(&s, 2, 1, 3, 3, 2, U, V, ctrl, w, &a, NULL);
    if (e == BSFIT_OK) e = bsfit_surface_copy(&s, &d, NULL, NULL);
    if (e == BSFIT_OK) e = bsfit_surface_sample_grid(&s, 5, 5, grid, NULL);
    assert_true(e == BSFIT_OK || e == BSFIT_ENOMEM);
    bsfit_surface_free(&s);
    bsfit_surface_free(&d);
    assert_int_equal(c.live, 0);
    if (e == BSFIT_OK) break;
  }
  assert_true(n > 1 && n < 20);
}

static void test_invalid_inputs(void **state) {
  static const double U[] = {0, 0, 0, 1, 1, 1}, V[] = {0, 0, 1, 1};
  double ctrl[18] = {0}, w[6] = {1, 1, 1, 1, 1, 1}, out[3 * 4 * 4], bad[6];
  bsfit_surface s;
  bsfit_status st;
  (void)state;
  bsfit_surface_init(&s);
  assert_int_equal(bsfit_surface_new(&s, 2, 1, 0, 3, 2, U, V, ctrl, NULL, NULL, &st), BSFIT_EDIM);
  assert_int_equal(st.code, BSFIT_EDIM);
  assert_int_equal(bsfit_surface_new(&s, 2, 1, 5, 3, 2, U, V, ctrl, NULL, NULL, &st), BSFIT_EDIM);
  assert_int_equal(bsfit_surface_new(&s, 3, 1, 3, 3, 2, NULL, V, ctrl, NULL, NULL, &st),
                   BSFIT_EDEGREE);
  assert_int_equal(bsfit_surface_new(&s, -1, 1, 3, 3, 2, U, V, ctrl, NULL, NULL, &st),
                   BSFIT_EDEGREE);
  assert_int_equal(bsfit_surface_new(&s, 2, 1, 3, 0, 2, U, V, ctrl, NULL, NULL, &st), BSFIT_EINVAL);
  assert_int_equal(bsfit_surface_new(&s, 2, 1, 3, 3, 2, U, V, NULL, NULL, NULL, &st), BSFIT_EINVAL);
  memcpy(bad, U, sizeof bad);
  bad[3] = -1;
  assert_int_equal(bsfit_surface_new(&s, 2, 1, 3, 3, 2, bad, V, ctrl, NULL, NULL, &st),
                   BSFIT_EKNOTS_DECR);
  assert_non_null(strstr(st.msg, "u knots"));
  memcpy(bad, V, 4 * sizeof(double));
  bad[1] = NAN;
  assert_int_equal(bsfit_surface_new(&s, 2, 1, 3, 3, 2, U, bad, ctrl, NULL, NULL, &st),
                   BSFIT_ENONFINITE);
  assert_non_null(strstr(st.msg, "v knots"));
  bad[0] = bad[1] = bad[2] = bad[3] = 0;
  assert_int_equal(bsfit_surface_new(&s, 2, 1, 3, 3, 2, U, bad, ctrl, NULL, NULL, &st),
                   BSFIT_EMULT);
  ctrl[4] = INFINITY;
  assert_int_equal(bsfit_surface_new(&s, 2, 1, 3, 3, 2, U, V, ctrl, NULL, NULL, &st),
                   BSFIT_ENONFINITE);
  ctrl[4] = 0;
  w[2] = 0;
  assert_int_equal(bsfit_surface_new(&s, 2, 1, 3, 3, 2, U, V, ctrl, w, NULL, &st), BSFIT_EWEIGHT);
  w[2] = -1;
  assert_int_equal(bsfit_surface_new(&s, 2, 1, 3, 3, 2, U, V, ctrl, w, NULL, &st), BSFIT_EWEIGHT);
  w[2] = 1;
  assert_null(s.ctrl); /* left empty after every failure */
  assert_int_equal(bsfit_surface_new_bezier(&s, 3, 40, 2, ctrl, NULL, NULL, &st), BSFIT_EDEGREE);
  assert_int_equal(bsfit_surface_new_bezier(&s, 3, 0, 2, ctrl, NULL, NULL, &st), BSFIT_EDEGREE);
  assert_int_equal(bsfit_surface_validate(&s, &st), BSFIT_EINVAL);
  assert_int_equal(bsfit_surface_alloc(&s, 1, 1, 3, (size_t)-1, (size_t)-1, 0, NULL, &st),
                   BSFIT_EINVAL);

  /* a valid surface, then calls with bad arguments */
  assert_int_equal(bsfit_surface_new(&s, 2, 1, 3, 3, 2, U, V, ctrl, w, NULL, &st), BSFIT_OK);
  assert_int_equal(bsfit_surface_eval(&s, NAN, 0.5, out, &st), BSFIT_ENONFINITE);
  assert_int_equal(bsfit_surface_eval(&s, 0.5, INFINITY, out, &st), BSFIT_ENONFINITE);
  assert_int_equal(bsfit_surface_derivs(&s, 0.5, 0.5, -1, out, &st), BSFIT_EINVAL);
  assert_int_equal(bsfit_surface_derivs(&s, 0.5, 0.5, BSFIT_MAX_DEGREE + 1, out, &st),
                   BSFIT_EINVAL);
  assert_int_equal(bsfit_surface_derivs(&s, NAN, 0.5, 1, out, &st), BSFIT_ENONFINITE);
  assert_int_equal(bsfit_surface_sample_grid(&s, 1, 5, out, &st), BSFIT_EINVAL);
  assert_int_equal(bsfit_surface_normal(&s, 0.5, 0.5, out, &st), BSFIT_EDEGENERATE); /* flat net */
  bsfit_surface_free(&s);
  {
    /* a 4 x 2 net of degrees (2, 1) has two spans in u: not a Bézier surface */
    static const double U4[] = {0, 0, 0, 0.5, 1, 1, 1};
    double c4[24] = {0};
    assert_int_equal(bsfit_surface_new(&s, 2, 1, 3, 4, 2, U4, V, c4, NULL, NULL, &st), BSFIT_OK);
    s.bezier = 1;
    assert_int_equal(bsfit_surface_validate(&s, &st), BSFIT_EINVAL);
    bsfit_surface_free(&s);
  }
  {
    double c2[8] = {0, 0, 1, 0, 0, 1, 1, 1};
    assert_int_equal(bsfit_surface_new(&s, 1, 1, 2, 2, 2, NULL, NULL, c2, NULL, NULL, &st), BSFIT_OK);
    assert_int_equal(bsfit_surface_normal(&s, 0.5, 0.5, out, &st), BSFIT_EDIM);
    bsfit_surface_free(&s);
  }
}

/* }==================================================================== */

int main(void) {
  const struct CMUnitTest tests[] = {
    cmocka_unit_test(test_partition_of_unity),
    cmocka_unit_test(test_linear_precision),
    cmocka_unit_test(test_bilinear),
    cmocka_unit_test(test_bezier_equals_bspline),
    cmocka_unit_test(test_exact_cylinder_and_sphere),
    cmocka_unit_test(test_derivs_finite_differences),
    cmocka_unit_test(test_derivs_polynomial_degree),
    cmocka_unit_test(test_normals),
    cmocka_unit_test(test_sample_grid),
    cmocka_unit_test(test_copy_move),
    cmocka_unit_test(test_allocation_failures),
    cmocka_unit_test(test_invalid_inputs),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
