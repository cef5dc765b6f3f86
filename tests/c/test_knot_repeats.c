/*
** test_knot_repeats.c
** Knot placement on parameters with repeats (scanners repeat points, and repeated
** points share a parameter): every averaging rule must give non-decreasing knots,
** on random parameter sets with runs of equal values, for every count and degree.
** (Interpolating between two equal parameters as (1 - a) x + a x could land an ulp
** off x, and the periodic knots then decreased: bsfit reconstruct failed on such
** files with "periodic knots decrease".)
*/

#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#include <cmocka.h>

#include "bsfit.h"
#include "testutil.h"

/* m sorted parameters in [0, 1) (closed) or [0, 1] (open) with random runs of
** repeats, at values with many significant bits. */
static void repeated_params(test_rng *r, size_t m, int closed, double *u) {
  size_t i = 0;
  double x = 0;
  while (i < m) {
    size_t run = rng_uniform(r) < 0.15 ? 2 + (size_t)(rng_uniform(r) * 3) : 1, k;
    for (k = 0; k < run && i < m; k++) u[i++] = x;
    x += rng_range(r, 0.1, 1.0) * (1.0 + 1e-7 * rng_uniform(r));
  }
  for (i = 0; i < m; i++) u[i] /= closed ? x : u[m - 1];
}

static void test_knots_never_decrease(void **state) {
  static const bsfit_knot_rule rules[] = {BSFIT_KNOTS_AVERAGING, BSFIT_KNOTS_CARVALHO_CLOSED,
                                          BSFIT_KNOTS_PERIODIC_AVERAGING};
  test_rng r = {0x9e3779b97f4a7c15ULL};
  double u[400], U[420];
  int trial, p;
  size_t ri, n;
  (void)state;
  for (trial = 0; trial < 60; trial++) {
    size_t m = 20 + (size_t)(rng_uniform(&r) * 380);
    for (ri = 0; ri < sizeof rules / sizeof rules[0]; ri++) {
      int closed = bsfit_knot_rule_closed(rules[ri]);
      repeated_params(&r, m, closed, u);
      for (p = 1; p <= 5; p++)
        for (n = (size_t)p + 1; n <= m; n += 1 + m / 40) {
          bsfit_status st;
          size_t k, nk = bsfit_knots_place_count(rules[ri], p, n);
          bsfit_err e = bsfit_knots_place(rules[ri], u, m, p, n, U, &st);
          /* an empty span or a knot repeated too often are fair answers; decreasing is not */
          if (e != BSFIT_OK && e != BSFIT_EEMPTYSPAN && e != BSFIT_EMULT)
            fail_msg("rule %d m %zu p %d n %zu: %s", (int)rules[ri], m, p, n, st.msg);
          for (k = 1; k < nk; k++) assert_true(U[k] >= U[k - 1]);
        }
    }
  }
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_knots_never_decrease),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
