/*
** test_segment_start.c
** bsfit_segment_start: where a closed 2D section is read from, whichever sample its data
** start at. Random closed polygons (3 to 9 vertices, 8 to 200 samples, some repeated, some
** steps equal by construction: a regular polygon sampled evenly), each read from every
** start: the sample returned is the same point every time, and it follows a longest step
** (to 1e-12, measured here with hypot; the function compares squared steps, and ties are
** ties of those); among equal longest steps, the one of lowest x, then y. And its errors.
*/
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>
#include <math.h>
#include <string.h>

#include "bsfit.h"
#include "testutil.h"

#define PI 3.14159265358979323846
#define MAXPTS 200

/* m samples of a closed polygon: random (regular = 0) or regular and evenly sampled */
static size_t polygon(test_rng *r, int regular, double *pts) {
  int n = 3 + (int)(rng_uniform(r) * 7), k;
  size_t per = 1 + (size_t)(rng_uniform(r) * 20), m = 0, j;
  double v[2 * 10];
  for (k = 0; k < n; k++) {
    double a = 2 * PI * (k + (regular ? 0 : 0.8 * rng_uniform(r))) / n;
    v[2 * k] = cos(a), v[2 * k + 1] = sin(a);
  }
  for (k = 0; k < n && m + per <= MAXPTS; k++)
    for (j = 0; j < per; j++, m++) {
      const double *a = v + 2 * k, *b = v + 2 * ((k + 1) % n);
      double f = regular ? (double)j / (double)per : rng_uniform(r);
      pts[2 * m] = a[0] + f * (b[0] - a[0]), pts[2 * m + 1] = a[1] + f * (b[1] - a[1]);
      if (!regular && j > 0 && rng_uniform(r) < 0.1) /* a repeated sample */
        pts[2 * m] = pts[2 * m - 2], pts[2 * m + 1] = pts[2 * m - 1];
    }
  return m;
}

/* the step into sample i */
static double step_into(const double *pts, size_t m, size_t i) {
  const double *a = pts + 2 * ((i + m - 1) % m), *b = pts + 2 * i;
  return hypot(b[0] - a[0], b[1] - a[1]);
}

/* its square, as the function compares steps (ties are ties of these) */
static double square_into(const double *pts, size_t m, size_t i) {
  const double *a = pts + 2 * ((i + m - 1) % m), *b = pts + 2 * i;
  return (b[0] - a[0]) * (b[0] - a[0]) + (b[1] - a[1]) * (b[1] - a[1]);
}

static void test_same_point_from_every_start(void **state) {
  test_rng r = {77};
  double pts[2 * MAXPTS], q[2 * MAXPTS];
  int trial;
  (void)state;
  for (trial = 0; trial < 300; trial++) {
    size_t m = polygon(&r, trial % 3 == 0, pts), first = 0, shift, i;
    double longest = 0, x0, y0;
    bsfit_status st;
    assert_int_equal(bsfit_segment_start(pts, m, 2, &first, &st), BSFIT_OK);
    assert_true(first < m);
    for (i = 0; i < m; i++) longest = fmax(longest, step_into(pts, m, i));
    assert_true(step_into(pts, m, first) >= longest * (1 - 1e-12));
    for (i = 0; i < m; i++) /* no other longest step's sample lies lower in x, then y */
      if (square_into(pts, m, i) == square_into(pts, m, first) && i != first)
        assert_true(pts[2 * i] > pts[2 * first] ||
                    (pts[2 * i] == pts[2 * first] && pts[2 * i + 1] >= pts[2 * first + 1]));
    x0 = pts[2 * first], y0 = pts[2 * first + 1];
    for (shift = 1; shift < m; shift++) {
      size_t f = 0;
      for (i = 0; i < m; i++) memcpy(q + 2 * i, pts + 2 * ((i + shift) % m), 2 * sizeof *q);
      assert_int_equal(bsfit_segment_start(q, m, 2, &f, &st), BSFIT_OK);
      assert_float_equal(q[2 * f], x0, 0.0);
      assert_float_equal(q[2 * f + 1], y0, 0.0);
    }
  }
}

/* Exact ties: a unit square's four steps are equal and two corners share the lowest x, so
** y decides: (0, 0) from every start; a rectangle's two long steps tie, and x decides. */
static void test_ties(void **state) {
  double square[8] = {1, 1, 0, 1, 0, 0, 1, 0}, rect[8] = {0, 2, 0, 0, 1, 0, 1, 2}, q[8];
  const double *shapes[2] = {square, rect}, want[2][2] = {{0, 0}, {0, 0}};
  int k;
  size_t shift, i, f;
  bsfit_status st;
  (void)state;
  for (k = 0; k < 2; k++)
    for (shift = 0; shift < 4; shift++) {
      for (i = 0; i < 4; i++) memcpy(q + 2 * i, shapes[k] + 2 * ((i + shift) % 4), 2 * sizeof *q);
      assert_int_equal(bsfit_segment_start(q, 4, 2, &f, &st), BSFIT_OK);
      assert_float_equal(q[2 * f], want[k][0], 0.0);
      assert_float_equal(q[2 * f + 1], want[k][1], 0.0);
    }
}

static void test_errors(void **state) {
  double pts[6] = {0, 0, 1, 0, 0, 1};
  size_t first = 7;
  bsfit_status st;
  (void)state;
  assert_int_equal(bsfit_segment_start(pts, 2, 3, &first, &st), BSFIT_EDIM);
  assert_int_equal(first, 0);
  assert_int_equal(bsfit_segment_start(pts, 0, 2, &first, &st), BSFIT_ETOOFEW);
  assert_int_equal(bsfit_segment_start(NULL, 3, 2, &first, &st), BSFIT_ETOOFEW);
  assert_int_equal(bsfit_segment_start(pts, 3, 2, NULL, &st), BSFIT_EINVAL);
  pts[3] = NAN;
  assert_int_equal(bsfit_segment_start(pts, 3, 2, &first, &st), BSFIT_ENONFINITE);
  assert_non_null(strstr(st.msg, "NaN"));
  pts[3] = 0;
  assert_int_equal(bsfit_segment_start(pts, 1, 2, &first, &st), BSFIT_OK);
  assert_int_equal(first, 0);
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_same_point_from_every_start),
      cmocka_unit_test(test_ties),
      cmocka_unit_test(test_errors),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
