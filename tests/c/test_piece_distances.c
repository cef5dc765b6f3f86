/*
** test_piece_distances.c
** bsfit_curve_piece_distances from C: on random polygons joined from exact lines (the curve
** of auto's pieces), the distances of points near them against the distance to the
** polygon computed directly (point to segment, every side) when they are given to their
** own pieces; given to other pieces, never farther than bsfit_curve_closest puts them (the
** certificate must refuse a foot on the wrong side) nor nearer than the polygon. The
** scratch through the caller's allocator, the interrupt flag, and bad pieces.
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
#include "testutil.h"

#define PI 3.14159265358979323846
#define NPTS 600

/* the distance from x to the segment a b */
static double seg_dist(const double *x, const double *a, const double *b) {
  double dx = b[0] - a[0], dy = b[1] - a[1], t = ((x[0] - a[0]) * dx + (x[1] - a[1]) * dy) /
                                                  (dx * dx + dy * dy);
  t = t < 0 ? 0 : (t > 1 ? 1 : t);
  return hypot(x[0] - a[0] - t * dx, x[1] - a[1] - t * dy);
}

/* a star-shaped polygon of nv vertices (random radii: thin spikes and notches), joined
** from exact lines into c, each side's length its parameter share */
static void random_polygon(test_rng *r, int nv, double *V, bsfit_curve *c) {
  bsfit_curve parts[16];
  const bsfit_curve *pp[16] = {NULL};
  double len[16] = {0};
  int i;
  for (i = 0; i < nv; i++) {
    double ang = 2 * PI * (i + rng_range(r, 0.1, 0.9)) / nv, rad = rng_range(r, 0.3, 3.0);
    V[2 * i] = rad * cos(ang), V[2 * i + 1] = rad * sin(ang);
  }
  for (i = 0; i < nv; i++) {
    const double *a = V + 2 * i, *b = V + 2 * ((i + 1) % nv);
    bsfit_curve_init(&parts[i]);
    assert_int_equal(bsfit_curve_line(a, b, 2, &parts[i], NULL, NULL), BSFIT_OK);
    pp[i] = &parts[i];
    len[i] = hypot(b[0] - a[0], b[1] - a[1]);
  }
  assert_int_equal(bsfit_curve_join(pp, (size_t)nv, len, c, NULL, NULL), BSFIT_OK);
  for (i = 0; i < nv; i++) bsfit_curve_free(&parts[i]);
}

static void test_distances_are_the_polygon_distances(void **state) {
  static double xy[2 * NPTS], d[NPTS];
  test_rng r = {4242};
  int trial;
  double worst = 0;
  (void)state;
  for (trial = 0; trial < 120; trial++) {
    int nv = 3 + trial % 10, i, j;
    double V[32], range[32], acc = 0, total = 0;
    size_t first[16], count[16], m = 0, k;
    bsfit_curve c;
    bsfit_curve_init(&c);
    random_polygon(&r, nv, V, &c);
    for (i = 0; i < nv; i++)
      total += hypot(V[2 * ((i + 1) % nv)] - V[2 * i], V[2 * ((i + 1) % nv) + 1] - V[2 * i + 1]);
    for (i = 0; i < nv; i++) { /* 30 points near each side, off by 1e-9 .. 0.3 */
      const double *a = V + 2 * i, *b = V + 2 * ((i + 1) % nv);
      double l = hypot(b[0] - a[0], b[1] - a[1]);
      range[2 * i] = acc / total;
      acc += l;
      range[2 * i + 1] = acc / total;
      for (k = 0; k < 30; k++, m++) {
        double f = rng_uniform(&r), off = pow(10, rng_range(&r, -9, trial % 3 ? -0.5 : -3));
        if (rng_uniform(&r) < 0.5) off = -off;
        xy[2 * m] = a[0] + f * (b[0] - a[0]) - off * (b[1] - a[1]) / l;
        xy[2 * m + 1] = a[1] + f * (b[1] - a[1]) + off * (b[0] - a[0]) / l;
      }
    }
    /* the points of side i said to be piece (i + shift) % nv's: shift 0 is the truth. Given
    ** to other pieces, or farther off than 1e-3, the distance is held to the global
    ** search's, which is the polygon's distance itself (it once missed a thin spike's other
    ** side: a point 2.4e-8 off read as 0.12) */
    for (i = 0; i < nv; i++) {
      first[i] = (size_t)(30 * ((i + trial % 3) % nv)), count[i] = 30;
    }
    range[2 * nv - 1] = 1;
    assert_int_equal(bsfit_curve_piece_distances(&c, xy, m, first, count, range, (size_t)nv, 8, d,
                                                 NULL, NULL),
                     BSFIT_OK);
    for (k = 0; k < m; k++) {
      double truth = INFINITY, u1, g;
      for (j = 0; j < nv; j++)
        truth = fmin(truth, seg_dist(xy + 2 * k, V + 2 * j, V + 2 * ((j + 1) % nv)));
      assert_int_equal(bsfit_curve_closest(&c, xy + 2 * k, &u1, &g, NULL, NULL), BSFIT_OK);
      assert_true(fabs(g - truth) <= 1e-9 * truth + 1e-12);
      assert_true(isfinite(d[k]) && d[k] >= truth - 1e-12 && d[k] <= g + 1e-14);
      if (trial % 3 == 0) { /* their own pieces, within 1e-3: the true distance */
        worst = fmax(worst, fabs(d[k] - truth));
        assert_true(fabs(d[k] - truth) <= 1e-12);
      }
    }
    bsfit_curve_free(&c);
  }
  print_message("worst |distance - polygon distance| %.3g\n", worst);
}

static void test_scratch_interrupt_and_errors(void **state) {
  static double xy[2 * 20000], d[20000];
  double V[8], range[8] = {0, 0.25, 0.25, 0.5, 0.5, 0.75, 0.75, 1};
  size_t first[4] = {0, 5000, 10000, 15000}, count[4] = {5000, 5000, 5000, 5000}, i;
  counting cnt = {0, 0, 0}; /* testutil.h's counting allocator */
  volatile int stop = 0;
  bsfit_allocator a;
  bsfit_status st;
  bsfit_curve c;
  test_rng r = {9};
  (void)state;
  bsfit_curve_init(&c);
  random_polygon(&r, 4, V, &c);
  for (i = 0; i < 20000; i++) {
    size_t s = i / 5000;
    double f = ((double)(i % 5000) + 0.5) / 5000;
    xy[2 * i] = V[2 * s] + f * (V[2 * ((s + 1) % 4)] - V[2 * s]);
    xy[2 * i + 1] = V[2 * s + 1] + f * (V[2 * ((s + 1) % 4) + 1] - V[2 * s + 1]);
  }
  a.fn = counting_alloc, a.ud = &cnt, a.interrupt = &stop;
  assert_int_equal(bsfit_curve_piece_distances(&c, xy, 20000, first, count, range, 4, 8, d, &a,
                                               NULL),
                   BSFIT_OK);
  assert_true(cnt.calls > 0);
  assert_int_equal((int)cnt.live, 0);
  for (i = 0; i < 20000; i++) assert_true(d[i] <= 1e-14);
  stop = 1;
  assert_int_equal(bsfit_curve_piece_distances(&c, xy, 20000, first, count, range, 4, 8, d, &a,
                                               &st),
                   BSFIT_EINTR);
  assert_int_equal((int)cnt.live, 0);
  first[2] = 20000;
  assert_int_equal(bsfit_curve_piece_distances(&c, xy, 20000, first, count, range, 4, 8, d, NULL,
                                               &st),
                   BSFIT_EINVAL);
  assert_non_null(strstr(st.msg, "piece 3"));
  first[2] = 10000, range[5] = NAN;
  assert_int_equal(bsfit_curve_piece_distances(&c, xy, 20000, first, count, range, 4, 8, d, NULL,
                                               &st),
                   BSFIT_ENONFINITE);
  assert_int_equal(bsfit_curve_piece_distances(&c, xy, 20000, NULL, count, range, 4, 8, d, NULL,
                                               &st),
                   BSFIT_EINVAL);
  bsfit_curve_free(&c);
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_distances_are_the_polygon_distances),
      cmocka_unit_test(test_scratch_interrupt_and_errors),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
