/*
** test_segment_determinism.c
** The segmentation depends on its input alone, not on what its scratch memory held: every
** block it allocates is filled with a different pattern in two runs (zeros, then 0xA5
** bytes), and the pieces must agree bit for bit. An arc whose circle fit fails (a noisy
** run of a few samples) used to keep the orientation (and, when its three-point start was
** collinear, the circle) the memory held before, and the join it meets its neighbours by
** read it: a filleted hexagon at noise 1e-3 came out with its joins corner or tangent by
** chance (valgrind: uninitialised reads in meet, from the model array).
** Sections: filleted polygons of 3 to 8 sides, sampled unevenly, noise 1e-4 to 3e-3 of
** their size, segmented with the noise as sigma and by bsfit_segment_sigma.
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
#define MAXPTS 400

/* an allocator that fills every new block (and a block's grown part) with its byte */
static void *pattern_alloc(void *ud, void *ptr, size_t osize, size_t nsize) {
  unsigned char *p;
  if (nsize == 0) {
    free(ptr);
    return NULL;
  }
  p = realloc(ptr, nsize);
  if (p != NULL && nsize > (ptr ? osize : 0))
    memset(p + (ptr ? osize : 0), *(const unsigned char *)ud, nsize - (ptr ? osize : 0));
  return p;
}

static double gauss(test_rng *r) {
  return sqrt(-2 * log(1 - rng_uniform(r))) * cos(2 * PI * rng_uniform(r));
}

/* a polygon of nv vertices on a circle of radius 5 whose corners are rounded by arcs of
** radius rf, each side and each arc sampled at k points at uneven fractions, with
** Gaussian noise of sd sigma; returns the number of samples */
static size_t filleted_polygon(test_rng *r, int nv, double rf, size_t k, double sigma,
                               double *xy) {
  size_t n = 0, q;
  int i;
  double turn = 2 * PI / nv, cut = rf * tan(turn / 2);
  for (i = 0; i < nv; i++) {
    double a0 = 2 * PI * i / nv, a1 = 2 * PI * (i + 1) / nv;
    double A[2] = {5 * cos(a0), 5 * sin(a0)}, B[2] = {5 * cos(a1), 5 * sin(a1)};
    double len = hypot(B[0] - A[0], B[1] - A[1]), d[2] = {(B[0] - A[0]) / len, (B[1] - A[1]) / len};
    double c[2] = {B[0] - cut * d[0] - rf * d[1], B[1] - cut * d[1] + rf * d[0]};
    double f[16];
    for (q = 0; q < k; q++) f[q] = rng_range(r, 0.05, 0.95);
    for (q = 0; q < k; q++) { /* the side, from A + cut d to B - cut d */
      double t = cut + f[q] * (len - 2 * cut);
      xy[2 * n] = A[0] + t * d[0] + sigma * gauss(r);
      xy[2 * n + 1] = A[1] + t * d[1] + sigma * gauss(r);
      n++;
    }
    for (q = 0; q < k; q++) { /* the fillet round B */
      double ang = atan2(d[0], -d[1]) + f[q] * turn;
      xy[2 * n] = c[0] + rf * cos(ang) + sigma * gauss(r);
      xy[2 * n + 1] = c[1] + rf * sin(ang) + sigma * gauss(r);
      n++;
    }
  }
  return n;
}

static int same_pieces(const bsfit_piece *a, const bsfit_piece *b, size_t n) {
  return memcmp(a, b, n * sizeof *a) == 0;
}

static void test_pieces_do_not_depend_on_scratch_contents(void **state) {
  static double xy[2 * MAXPTS];
  static bsfit_piece p0[2 * MAXPTS + 2], p1[2 * MAXPTS + 2];
  unsigned char fill[2] = {0x00, 0xA5};
  test_rng r = {20261124};
  int trial, differ = 0, cases = 0;
  (void)state;
  for (trial = 0; trial < 240; trial++) {
    static const double rel[4] = {1e-4, 3e-4, 1e-3, 3e-3};
    int nv = 3 + trial % 6;
    size_t k = 3 + (size_t)(trial % 5), m, n0 = 0, n1 = 0;
    double sigma = rel[trial % 4] * 10, s0 = 0, s1 = 0;
    bsfit_allocator a0 = {pattern_alloc, &fill[0], NULL}, a1 = {pattern_alloc, &fill[1], NULL};
    bsfit_segment_opts o;
    memset(p0, 0, sizeof p0), memset(p1, 0, sizeof p1);
    m = filleted_polygon(&r, nv, rng_range(&r, 0.5, 1.5), k, sigma, xy);
    memset(&o, 0, sizeof o);
    o.closed = 1;
    o.sigma = sigma;
    assert_int_equal(bsfit_segment(xy, m, 2, &o, p0, 2 * MAXPTS + 2, &n0, &a0, NULL), BSFIT_OK);
    assert_int_equal(bsfit_segment(xy, m, 2, &o, p1, 2 * MAXPTS + 2, &n1, &a1, NULL), BSFIT_OK);
    if (n0 != n1 || !same_pieces(p0, p1, n0)) differ++;
    assert_int_equal(bsfit_segment_sigma(xy, m, 2, 1, 0, &s0, &a0, NULL), BSFIT_OK);
    assert_int_equal(bsfit_segment_sigma(xy, m, 2, 1, 0, &s1, &a1, NULL), BSFIT_OK);
    if (memcmp(&s0, &s1, sizeof s0) != 0) differ++;
    cases++;
  }
  print_message("%d sections, %d segmentations differ with the scratch contents\n", cases, differ);
  assert_int_equal(differ, 0);
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_pieces_do_not_depend_on_scratch_contents),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
