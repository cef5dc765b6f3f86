/*
** test_analysis.c
** Noise estimate and corner detection on synthetic sections with known truth.
*/
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>
#include <stdlib.h>
#include <string.h>

#include "bsfit.h"
#include "shapes.h"

#define NMAX 4000

static void check_sigma(const double *xy, size_t m, int closed, double truth) {
  double est;
  bsfit_status st;
  assert_int_equal(bsfit_noise_sigma(xy, m, 2, closed, &est, NULL, &st), BSFIT_OK);
  if (fabs(est - truth) > 0.2 * truth)
    fail_msg("sigma estimate %.4g vs truth %.4g (m = %zu)", est, truth, m);
}

static void test_noise_smooth_closed_shapes(void **state) {
  static double xy[2 * NMAX];
  const double sigmas[] = {1e-4, 1e-3, 1e-2};
  test_rng r = {2024};
  int s, i, uneven;
  (void)state;
  for (s = SHAPE_CIRCLE; s <= SHAPE_SUPERELLIPSE; s++)
    for (i = 0; i < 3; i++)
      for (uneven = 0; uneven <= 1; uneven++) {
        size_t m = 2000;
        make_shape(&r, (smooth_shape)s, m, uneven, sigmas[i], xy);
        check_sigma(xy, m, 1, sigmas[i]);
      }
}

static void test_noise_open_arc(void **state) {
  static double xy[2 * NMAX];
  test_rng r = {77};
  size_t m = 1500, k;
  int i;
  (void)state;
  for (i = 0; i < 3; i++) {
    double sigma = pow(10.0, -4 + i);
    for (k = 0; k < m; k++) { /* a parabola-like open arc, uneven spacing */
      double t = -1.0 + 2.0 * pow((double)k / (double)(m - 1), 1.3);
      xy[2 * k] = t + sigma * rng_gauss(&r);
      xy[2 * k + 1] = 0.5 * t * t + sigma * rng_gauss(&r);
    }
    check_sigma(xy, m, 0, sigma);
  }
}

static void test_noise_errors(void **state) {
  double xy[20] = {0}, s;
  bsfit_status st;
  (void)state;
  assert_int_equal(bsfit_noise_sigma(xy, 5, 2, 1, &s, NULL, &st), BSFIT_ETOOFEW);
  assert_int_equal(bsfit_noise_sigma(xy, 8, 4, 1, &s, NULL, &st), BSFIT_EDIM);
  assert_int_equal(bsfit_noise_sigma(xy, 8, 2, 1, &s, NULL, &st), BSFIT_EDEGENERATE);
  xy[3] = NAN;
  assert_int_equal(bsfit_noise_sigma(xy, 8, 2, 1, &s, NULL, &st), BSFIT_ENONFINITE);
  assert_true(strlen(st.msg) > 0);
}

/* sparse polygons with many corners: a third of the windows straddle one (the L at
** noise 3e-3, nine samples on its short sides, may still read 30% high) */
static void test_noise_sparse_polygons(void **state) {
  static double xy[2 * NMAX];
  const double ell[] = {0, 0, 1, 0, 1, 0.3, 0.3, 0.3, 0.3, 1, 0, 1};
  const double sigmas[] = {1e-4, 1e-3, 3e-3};
  double star[24];
  test_rng r = {41};
  int i, k, seed;
  (void)state;
  for (k = 0; k < 12; k++) { /* a 6-pointed star polygon, radii 1 and 0.6 */
    double rad = k % 2 == 0 ? 1.0 : 0.6;
    star[2 * k] = rad * cos(SHAPE_PI * k / 6.0);
    star[2 * k + 1] = rad * sin(SHAPE_PI * k / 6.0);
  }
  for (i = 0; i < 3; i++)
    for (seed = 0; seed < 3; seed++) {
      make_polygon(&r, ell, 6, 150, sigmas[i], xy);
      if (i < 2) check_sigma(xy, 150, 1, sigmas[i]);
      make_polygon(&r, star, 12, 250, sigmas[i], xy);
      check_sigma(xy, 250, 1, sigmas[i]);
    }
}

static size_t detect(const double *xy, size_t m, int closed, size_t *idx, size_t cap) {
  bsfit_corner_opts o;
  bsfit_corner found[64];
  size_t count, k;
  bsfit_status st;
  memset(&o, 0, sizeof o);
  o.closed = closed;
  assert_true(cap <= 64);
  assert_int_equal(bsfit_corners_detect(xy, m, 2, &o, found, cap, &count, NULL, &st), BSFIT_OK);
  for (k = 0; k < count && k < cap; k++) {
    idx[k] = found[k].index;
    /* the corner point lies within one edge of its sample */
    assert_true(fabs(found[k].position - (double)found[k].index) <= 1.0 ||
                fabs(found[k].position - (double)found[k].index) >= (double)m - 1.0);
  }
  return count;
}

/* every vertex has a detected corner within tol, and there are no others */
static void check_corners(const double *xy, size_t m, const double *v, size_t nv, double tol) {
  size_t idx[64], n = detect(xy, m, 1, idx, 64), i, j;
  if (n != nv) fail_msg("found %zu corners, expected %zu", n, nv);
  for (i = 0; i < nv; i++) {
    double best = 1e300;
    for (j = 0; j < n; j++) best = fmin(best, hypot(xy[2 * idx[j]] - v[2 * i], xy[2 * idx[j] + 1] - v[2 * i + 1]));
    if (best > tol) fail_msg("vertex %zu: nearest corner %.3g away", i, best);
  }
}

static void test_corners_of_polygons(void **state) {
  static double xy[2 * NMAX];
  const double square[] = {0, 0, 1, 0, 1, 1, 0, 1};
  const double ell[] = {0, 0, 1, 0, 1, 0.3, 0.3, 0.3, 0.3, 1, 0, 1};
  const double sigmas[] = {1e-4, 1e-3, 5e-3};
  test_rng r = {5};
  int i;
  (void)state;
  for (i = 0; i < 3; i++) {
    make_polygon(&r, square, 4, 800, sigmas[i], xy);
    check_corners(xy, 800, square, 4, 0.02);
    make_polygon(&r, ell, 6, 900, sigmas[i], xy);
    check_corners(xy, 900, ell, 6, 0.02);
  }
}

/* a D shape: a half-disc, corners where the diameter meets the arc */
static size_t make_dshape(test_rng *r, size_t m, double sigma, double *xy) {
  size_t i, n_line = (size_t)((double)m * 2.0 / (2.0 + SHAPE_PI)), n_arc = m - n_line;
  for (i = 0; i < n_line; i++) {
    xy[2 * i] = -1.0 + 2.0 * (double)i / (double)n_line;
    xy[2 * i + 1] = 0.0;
  }
  for (i = 0; i < n_arc; i++) {
    double t = SHAPE_PI * (double)i / (double)n_arc;
    xy[2 * (n_line + i)] = cos(t);
    xy[2 * (n_line + i) + 1] = sin(t);
  }
  for (i = 0; i < 2 * m; i++) xy[i] += sigma * rng_gauss(r);
  return m;
}

/* a symmetric NACA-like airfoil with a sharp trailing edge at (1, 0) */
static size_t make_airfoil(test_rng *r, size_t m, double sigma, double *xy) {
  size_t i;
  for (i = 0; i < m; i++) {
    double t = 2.0 * SHAPE_PI * (double)i / (double)m;
    double x = 0.5 * (1.0 + cos(t)); /* 1 -> 0 -> 1: trailing edge first */
    double y = 0.6 * (0.2969 * sqrt(x) - 0.1260 * x - 0.3516 * x * x + 0.2843 * x * x * x - 0.1036 * x * x * x * x);
    xy[2 * i] = x + sigma * rng_gauss(r);
    xy[2 * i + 1] = (t < SHAPE_PI ? y : -y) + sigma * rng_gauss(r);
  }
  return m;
}

static void test_corners_of_d_shape_and_airfoil(void **state) {
  static double xy[2 * NMAX];
  const double dcorners[] = {-1, 0, 1, 0}, te[] = {1, 0};
  const double sigmas[] = {1e-4, 1e-3, 3e-3};
  test_rng r = {11};
  int i;
  (void)state;
  for (i = 0; i < 3; i++) {
    make_dshape(&r, 800, sigmas[i], xy);
    check_corners(xy, 800, dcorners, 2, 0.03);
    make_airfoil(&r, 400, sigmas[i] * 0.3, xy);
    check_corners(xy, 400, te, 1, 0.02);
  }
}

/* corners with few samples per side, and on curved sides: all found, at their place */
static void test_corners_sparse_and_curved(void **state) {
  static double xy[2 * NMAX];
  const double square[] = {0, 0, 1, 0, 1, 1, 0, 1};
  const double ell[] = {0, 0, 1, 0, 1, 0.3, 0.3, 0.3, 0.3, 1, 0, 1};
  const double dcorners[] = {-1, 0, 1, 0};
  const double sigmas[] = {1e-4, 1e-3, 3e-3};
  test_rng r = {17};
  int i, seed;
  (void)state;
  for (i = 0; i < 3; i++)
    for (seed = 0; seed < 3; seed++) {
      make_polygon(&r, square, 4, 300, sigmas[i], xy);
      check_corners(xy, 300, square, 4, 0.02);
      make_polygon(&r, ell, 6, 400, sigmas[i], xy);
      check_corners(xy, 400, ell, 6, 0.02);
      make_dshape(&r, 400, 2.0 * sigmas[i], xy);
      check_corners(xy, 400, dcorners, 2, 0.03);
    }
}

/* the corner point where a line meets an arc is where they meet, not where the arc's
** secant would meet the line (that is 0.009 off for a half disc sampled at 150) */
static void test_corner_point_on_curved_side(void **state) {
  static double xy[2 * NMAX];
  const double sigmas[] = {0.0, 1e-4};
  test_rng r = {23};
  int i, k;
  (void)state;
  for (i = 0; i < 2; i++) {
    bsfit_corner_opts o;
    bsfit_corner found[8];
    size_t count;
    bsfit_status st;
    make_dshape(&r, 150, sigmas[i], xy);
    memset(&o, 0, sizeof o);
    o.closed = 1;
    assert_int_equal(bsfit_corners_detect(xy, 150, 2, &o, found, 8, &count, NULL, &st), BSFIT_OK);
    assert_int_equal(count, 2);
    for (k = 0; k < 2; k++) {
      double d = fmin(hypot(found[k].point[0] - 1.0, found[k].point[1]),
                      hypot(found[k].point[0] + 1.0, found[k].point[1]));
      if (d > 3.0 * sigmas[i] + 1e-3) fail_msg("sigma %g: corner point %.4g from the vertex", sigmas[i], d);
    }
  }
}

/* a 5-lobed star's valleys (radius 0.25) are smooth bends, however sparse the samples
** (with 150, a valley turns at five samples in a row) */
static void test_no_corners_on_star_valleys(void **state) {
  static double xy[2 * NMAX];
  const double sigmas[] = {1e-4, 1e-3, 3e-3};
  const size_t sizes[] = {150, 200, 400, 1000};
  test_rng r = {8};
  size_t idx[64];
  int i, j, seed, uneven;
  (void)state;
  for (i = 0; i < 3; i++)
    for (j = 0; j < 4; j++)
      for (seed = 0; seed < 2; seed++)
        for (uneven = 0; uneven <= 1; uneven++) {
          size_t n, m = sizes[j];
          make_shape(&r, SHAPE_STAR, m, uneven, 2.0 * sigmas[i], xy);
          n = detect(xy, m, 1, idx, 64);
          if (n != 0) fail_msg("star m %zu sigma %g uneven %d: %zu false corners", m, sigmas[i], uneven, n);
        }
}

static void test_no_corners_on_smooth_shapes(void **state) {
  static double xy[2 * NMAX];
  const double sigmas[] = {0.0, 1e-4, 1e-3, 1e-2};
  test_rng r = {99};
  size_t idx[64];
  int s, i, uneven;
  (void)state;
  for (s = SHAPE_CIRCLE; s <= SHAPE_SUPERELLIPSE; s++)
    for (i = 0; i < 4; i++)
      for (uneven = 0; uneven <= 1; uneven++) {
        size_t n;
        make_shape(&r, (smooth_shape)s, 600, uneven, sigmas[i], xy);
        n = detect(xy, 600, 1, idx, 64);
        if (n != 0) fail_msg("shape %d sigma %g uneven %d: %zu false corners (first at %zu)", s, sigmas[i], uneven, n, idx[0]);
      }
}

static void test_dense_clusters_are_not_corners(void **state) {
  static double xy[2 * NMAX];
  test_rng r = {3};
  size_t m = 0, i, idx[16];
  (void)state;
  /* a circle sampled at 300 points with 5 bursts of 40 nearly coincident points */
  for (i = 0; i < 300; i++) {
    double t = 2.0 * SHAPE_PI * (double)i / 300.0;
    size_t burst = (i % 60 == 0) ? 40 : 1, b;
    for (b = 0; b < burst; b++) {
      double tt = t + 1e-4 * (double)b / 40.0;
      xy[2 * m] = cos(tt) + 1e-4 * rng_gauss(&r);
      xy[2 * m + 1] = sin(tt) + 1e-4 * rng_gauss(&r);
      m++;
    }
  }
  assert_int_equal(detect(xy, m, 1, idx, 16), 0);
}

int main(void) {
  const struct CMUnitTest tests[] = {
    cmocka_unit_test(test_noise_smooth_closed_shapes),
    cmocka_unit_test(test_noise_open_arc),
    cmocka_unit_test(test_noise_errors),
    cmocka_unit_test(test_noise_sparse_polygons),
    cmocka_unit_test(test_corners_of_polygons),
    cmocka_unit_test(test_corners_of_d_shape_and_airfoil),
    cmocka_unit_test(test_corners_sparse_and_curved),
    cmocka_unit_test(test_corner_point_on_curved_side),
    cmocka_unit_test(test_no_corners_on_star_valleys),
    cmocka_unit_test(test_no_corners_on_smooth_shapes),
    cmocka_unit_test(test_dense_clusters_are_not_corners),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
