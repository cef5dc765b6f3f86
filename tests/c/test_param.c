/*
** test_param.c
** Parameters for ordered points: hand-computed chord, centripetal and uniform values
** (open and closed, the closing chord counted), coincident points, invalid inputs.
*/
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include "cmocka_double.h"
#include <string.h>

#include "bsfit.h"
#include "testutil.h"

static void expect_error(bsfit_err got, bsfit_err want, const bsfit_status *st) {
  assert_int_equal(got, want);
  assert_int_equal(st->code, want);
  assert_true(strlen(st->msg) > 0);
}

/* the 3-4-5 triangle: chords 3 and 4, closing chord 5 */
static const double tri[] = {0, 0, 3, 0, 3, 4};

static void test_chord_open_and_closed(void **state) {
  double u[3];
  (void)state;
  assert_int_equal(bsfit_params(tri, 3, 2, BSFIT_PARAM_CHORD, 0, u, NULL), BSFIT_OK);
  assert_float_equal(u[0], 0.0, 0);
  assert_float_equal(u[1], 3.0 / 7.0, EPS_EXACT);
  assert_float_equal(u[2], 1.0, 0);
  assert_int_equal(bsfit_params(tri, 3, 2, BSFIT_PARAM_CHORD, 1, u, NULL), BSFIT_OK);
  assert_float_equal(u[0], 0.0, 0);
  assert_float_equal(u[1], 3.0 / 12.0, EPS_EXACT);
  assert_float_equal(u[2], 7.0 / 12.0, EPS_EXACT);
}

static void test_centripetal_and_uniform(void **state) {
  double u[3], s3 = sqrt(3.0);
  (void)state;
  assert_int_equal(bsfit_params(tri, 3, 2, BSFIT_PARAM_CENTRIPETAL, 0, u, NULL), BSFIT_OK);
  assert_float_equal(u[1], s3 / (s3 + 2.0), EPS_EXACT);
  assert_float_equal(u[2], 1.0, 0);
  assert_int_equal(bsfit_params(tri, 3, 2, BSFIT_PARAM_CENTRIPETAL, 1, u, NULL), BSFIT_OK);
  assert_float_equal(u[1], s3 / (s3 + 2.0 + sqrt(5.0)), EPS_EXACT);
  assert_float_equal(u[2], (s3 + 2.0) / (s3 + 2.0 + sqrt(5.0)), EPS_EXACT);
  assert_int_equal(bsfit_params(tri, 3, 2, BSFIT_PARAM_UNIFORM, 0, u, NULL), BSFIT_OK);
  assert_float_equal(u[1], 0.5, EPS_EXACT);
  assert_int_equal(bsfit_params(tri, 3, 2, BSFIT_PARAM_UNIFORM, 1, u, NULL), BSFIT_OK);
  assert_float_equal(u[1], 1.0 / 3.0, EPS_EXACT);
  assert_float_equal(u[2], 2.0 / 3.0, EPS_EXACT);
}

static void test_3d_and_coincident_points(void **state) {
  /* a 3D polyline with a repeated point: it shares its parameter, nothing is NaN */
  const double pts[] = {0, 0, 0, 1, 2, 2, 1, 2, 2, 1, 2, 4};
  double u[4];
  int kind;
  (void)state;
  for (kind = 0; kind < 3; kind++) {
    size_t k;
    assert_int_equal(bsfit_params(pts, 4, 3, (bsfit_param_kind)kind, 0, u, NULL), BSFIT_OK);
    for (k = 0; k < 4; k++) assert_true(isfinite(u[k]));
    for (k = 1; k < 4; k++) assert_true(u[k] >= u[k - 1]);
  }
  assert_int_equal(bsfit_params(pts, 4, 3, BSFIT_PARAM_CHORD, 0, u, NULL), BSFIT_OK);
  assert_float_equal(u[1], 3.0 / 5.0, EPS_EXACT);
  assert_true(u[2] == u[1]);
}

static void test_invalid_inputs(void **state) {
  const double same[] = {1, 1, 1, 1, 1, 1};
  double bad[] = {0, 0, 1, NAN, 2, 2}, u[3];
  const double loop[] = {0, 0, 1, 0, 1, 1, 0, 0};
  bsfit_status st;
  (void)state;
  expect_error(bsfit_params(same, 3, 2, BSFIT_PARAM_CHORD, 0, u, &st), BSFIT_EDEGENERATE, &st);
  expect_error(bsfit_params(same, 3, 2, BSFIT_PARAM_UNIFORM, 0, u, &st), BSFIT_EDEGENERATE, &st);
  expect_error(bsfit_params(bad, 3, 2, BSFIT_PARAM_CHORD, 0, u, &st), BSFIT_ENONFINITE, &st);
  bad[3] = INFINITY;
  expect_error(bsfit_params(bad, 3, 2, BSFIT_PARAM_CENTRIPETAL, 0, u, &st), BSFIT_ENONFINITE, &st);
  expect_error(bsfit_params(tri, 1, 2, BSFIT_PARAM_CHORD, 0, u, &st), BSFIT_ETOOFEW, &st);
  expect_error(bsfit_params(tri, 3, 0, BSFIT_PARAM_CHORD, 0, u, &st), BSFIT_EDIM, &st);
  expect_error(bsfit_params(tri, 3, 5, BSFIT_PARAM_CHORD, 0, u, &st), BSFIT_EDIM, &st);
  expect_error(bsfit_params(NULL, 3, 2, BSFIT_PARAM_CHORD, 0, u, &st), BSFIT_EINVAL, &st);
  expect_error(bsfit_params(tri, 3, 2, BSFIT_PARAM_CHORD, 0, NULL, &st), BSFIT_EINVAL, &st);
  expect_error(bsfit_params(tri, 3, 2, (bsfit_param_kind)7, 0, u, &st), BSFIT_EINVAL, &st);
  /* closed data repeating its first point at the end */
  {
    double u4[4];
    expect_error(bsfit_params(loop, 4, 2, BSFIT_PARAM_CHORD, 1, u4, &st), BSFIT_EINVAL, &st);
  }
}

int main(void) {
  const struct CMUnitTest tests[] = {
    cmocka_unit_test(test_chord_open_and_closed),
    cmocka_unit_test(test_centripetal_and_uniform),
    cmocka_unit_test(test_3d_and_coincident_points),
    cmocka_unit_test(test_invalid_inputs),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
