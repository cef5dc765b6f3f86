/*
** test_segment_moments.c
** The residuals of lines and circles from prefix sums of moments (segment_moments.c),
** against the direct fits of side_models.c: the line's to rounding, the circle's (Taubin)
** to first order in the noise, on many runs (lengths, sweeps, radii, noise levels, far
** from the origin and near it, wrapping round a closed section).
*/
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>
#include <math.h>
#include <string.h>
#include "bsfit.h"
#include "core/features_internal.h"
#include "testutil.h"

#define PI 3.14159265358979323846
#define MAXM 400

static double gauss(test_rng *r) {
  double u = rng_range(r, 1e-300, 1.0), v = rng_uniform(r);
  return sqrt(-2 * log(u)) * cos(2 * PI * v);
}

/* a closed section of m samples: a circle of radius R round (cx, cy), noise sigma */
static void circle_section(test_rng *r, double *pts, size_t m, double cx, double cy, double R,
                           double sigma) {
  size_t i;
  for (i = 0; i < m; i++) {
    double t = 2 * PI * (double)i / (double)m;
    pts[2 * i] = cx + R * cos(t) + sigma * gauss(r);
    pts[2 * i + 1] = cy + R * sin(t) + sigma * gauss(r);
  }
}

/* The line's residual is the total least-squares one: equal to the direct fit's to
** rounding, wherever the run lies and however far the section is from the origin. */
static void test_line_rss_is_the_fits(void **state) {
  test_rng r = {0x5eed1234abcdULL};
  double pts[2 * MAXM];
  int trial;
  (void)state;
  for (trial = 0; trial < 200; trial++) {
    size_t m = 20 + (size_t)(rng_uniform(&r) * 300), k;
    double off = trial % 3 == 0 ? 0.0 : pow(10.0, rng_range(&r, 0, 4));
    double R = pow(10.0, rng_range(&r, -2, 3)), sigma = R * pow(10.0, rng_range(&r, -6, -1));
    bsfit__moments mo;
    circle_section(&r, pts, m, off, -off, R, sigma);
    assert_int_equal(bsfit__moments_init(&mo, pts, m, NULL), BSFIT_OK);
    for (k = 0; k < 10; k++) {
      size_t first = (size_t)(rng_uniform(&r) * (double)m), n = 2 + (size_t)(rng_uniform(&r) * 30);
      bsfit__run run = {pts, m, first, n};
      bsfit__line L;
      double rms = 0, direct;
      if (n > m) n = m, run.n = n;
      assert_true(bsfit__fit_line(&run, &L));
      bsfit__line_max(&L, &run, &rms);
      direct = rms * rms * (double)n;
      /* rounding: of the squares of coordinates up to off + R, over n samples */
      assert_float_equal(bsfit__moments_line_rss(&mo, first, n), direct,
                          1e-9 * direct + 1e-13 * (double)n * (off + R) * (off + R));
    }
    bsfit__moments_free(&mo, NULL);
  }
}

/* The circle's residual: at most the line's (a line is a circle of infinite radius, and
** Taubin's fit is near the best circle), and the geometric one to first order in the
** noise (within 20% when the noise is below a thousandth of the radius and the run
** sweeps at least 0.2 radians), against Gauss-Newton started from the true circle. */
static void test_arc_rss_is_geometric_to_first_order(void **state) {
  test_rng r = {0xc1c1e5ULL};
  double pts[2 * MAXM];
  int trial, checked = 0;
  (void)state;
  for (trial = 0; trial < 200; trial++) {
    size_t m = 40 + (size_t)(rng_uniform(&r) * 350), k;
    double off = trial % 2 ? 0.0 : pow(10.0, rng_range(&r, 0, 3));
    double R = pow(10.0, rng_range(&r, -1, 2)), sigma = R * pow(10.0, rng_range(&r, -6, -3));
    bsfit__moments mo;
    circle_section(&r, pts, m, off, off, R, sigma);
    assert_int_equal(bsfit__moments_init(&mo, pts, m, NULL), BSFIT_OK);
    for (k = 0; k < 8; k++) {
      size_t n = 5 + (size_t)(rng_uniform(&r) * 40), first = (size_t)(rng_uniform(&r) * (double)m);
      bsfit__run run = {pts, m, first, n};
      bsfit__circle truth = {{off, off}, R}, C;
      bsfit__line L;
      double rms = 0, geo, line, mom;
      if (2 * PI * (double)(n - 1) / (double)m < 0.2 || n > m) continue;
      assert_true(bsfit__fit_circle(&run, &truth, 1e-15 * R, &C));
      bsfit__circle_max(&C, &run, &rms);
      geo = rms * rms * (double)n;
      assert_true(bsfit__fit_line(&run, &L));
      bsfit__line_max(&L, &run, &rms);
      line = rms * rms * (double)n;
      mom = bsfit__moments_arc_rss(&mo, first, n);
      assert_true(mom <= line * (1 + 1e-9) + 1e-20);
      assert_true(mom >= 0.8 * geo && mom <= 1.2 * geo + 1e-12 * R * R * (double)n);
      checked++;
    }
    bsfit__moments_free(&mo, NULL);
  }
  assert_true(checked > 500);
}

/* Collinear samples and too few: no circle (HUGE_VAL), a line of zero residual. */
static void test_degenerate_runs(void **state) {
  double pts[2 * 8];
  size_t i;
  bsfit__moments mo;
  (void)state;
  for (i = 0; i < 8; i++) pts[2 * i] = (double)i, pts[2 * i + 1] = 2.0 * (double)i + 1;
  assert_int_equal(bsfit__moments_init(&mo, pts, 8, NULL), BSFIT_OK);
  assert_float_equal(bsfit__moments_line_rss(&mo, 0, 8), 0.0, 1e-20);
  assert_true(bsfit__moments_arc_rss(&mo, 0, 2) == HUGE_VAL);
  assert_true(bsfit__moments_line_rss(&mo, 12, 8) == HUGE_VAL); /* past the 2m unwrapped */
  bsfit__moments_free(&mo, NULL);
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_line_rss_is_the_fits),
      cmocka_unit_test(test_arc_rss_is_geometric_to_first_order),
      cmocka_unit_test(test_degenerate_runs),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
