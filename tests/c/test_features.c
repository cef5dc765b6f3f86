/*
** test_features.c
** The sharp-feature kernels (bsfit_features.h) from C: segmentation of exact polygons
** with random vertices and sample counts (corners at the true vertices, lines exact), the
** exact rational arc against the circle, the join of parts, the self-intersection sweep
** against a brute-force count, scratch memory through the caller's allocator and the
** interrupt flag (corner detection and segmentation).
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

/* a convex polygon of nv random vertices (angles sorted), each side sampled at k points
** at fractions (j + 1/2)/k: the vertices lie between samples */
static size_t random_polygon(test_rng *r, int nv, size_t k, double *V, double *xy) {
  double ang[16];
  int i, j;
  size_t n = 0, q;
  for (i = 0; i < nv; i++) ang[i] = 2 * PI * (i + rng_range(r, 0.15, 0.85)) / nv;
  for (i = 0; i < nv; i++) {
    double rad = rng_range(r, 2.0, 3.0);
    V[2 * i] = rad * cos(ang[i]);
    V[2 * i + 1] = rad * sin(ang[i]);
  }
  for (i = 0; i < nv; i++) {
    j = (i + 1) % nv;
    for (q = 0; q < k; q++) {
      double f = ((double)q + 0.5) / (double)k;
      xy[2 * n] = V[2 * i] + f * (V[2 * j] - V[2 * i]);
      xy[2 * n + 1] = V[2 * i + 1] + f * (V[2 * j + 1] - V[2 * i + 1]);
      n++;
    }
  }
  return n;
}

static void test_polygons_segment_into_lines_meeting_at_the_vertices(void **state) {
  static double xy[2 * 200], V[32];
  static bsfit_piece p[402];
  test_rng r = {7};
  int trial;
  (void)state;
  for (trial = 0; trial < 60; trial++) {
    int nv = 3 + trial % 6, i, c;
    size_t k = 3 + (size_t)(trial % 8), m = random_polygon(&r, nv, k, V, xy), np = 0;
    bsfit_segment_opts o;
    memset(&o, 0, sizeof o);
    o.closed = 1;
    assert_int_equal(bsfit_segment(xy, m, 2, &o, p, 402, &np, NULL, NULL), BSFIT_OK);
    assert_int_equal((int)np, nv);
    for (i = 0; i < (int)np; i++) {
      double best = HUGE_VAL;
      assert_int_equal(p[i].kind, BSFIT_PIECE_LINE);
      assert_int_equal(p[i].join, BSFIT_JOIN_CORNER);
      assert_int_equal((int)p[i].count, (int)k);
      for (c = 0; c < nv; c++)
        best = fmin(best, hypot(p[i].start[0] - V[2 * c], p[i].start[1] - V[2 * c + 1]));
      assert_true(best <= 1e-12 * 6);
      assert_true(p[i].max <= 1e-13 * 6);
    }
  }
}

static void test_arc_is_the_circle(void **state) {
  bsfit_curve c;
  double ctr[2] = {0.5, -1.5}, x[2];
  int s, k;
  (void)state;
  bsfit_curve_init(&c);
  for (s = 0; s < 8; s++) {
    double sweep = (s % 2 ? -1 : 1) * (0.2 + 0.85 * s), a0 = 0.3 * s;
    assert_int_equal(bsfit_curve_arc(ctr, 2.0, a0, sweep, &c, NULL, NULL), BSFIT_OK);
    assert_int_equal(c.degree, 3);
    assert_non_null(c.weights);
    for (k = 0; k <= 200; k++) {
      assert_int_equal(bsfit_curve_eval(&c, k / 200.0, x, NULL), BSFIT_OK);
      assert_float_equal(hypot(x[0] - ctr[0], x[1] - ctr[1]), 2.0, 1e-14);
    }
    /* the end lands at a0 + sweep */
    assert_float_equal(x[0], ctr[0] + 2 * cos(a0 + sweep), 1e-14);
    assert_float_equal(x[1], ctr[1] + 2 * sin(a0 + sweep), 1e-14);
  }
  assert_int_equal(bsfit_curve_arc(ctr, 0.0, 0, 1, &c, NULL, NULL), BSFIT_EINVAL);
  assert_int_equal(bsfit_curve_arc(ctr, 1.0, 0, 7, &c, NULL, NULL), BSFIT_EINVAL);
  bsfit_curve_free(&c);
}

/* Given n samples evenly round a circle and a noise sigma, when segmented, then the one arc's
** radius_se is sigma / sqrt(n): J^T J is diag(n/2, n/2, n) there (the u vectors sum to 0).
** On exact data (sigma 0) it is 0. */
static void test_radius_se_of_a_whole_circle(void **state) {
  double xy[2 * 96];
  bsfit_segment_opts o;
  bsfit_piece p[200];
  size_t np, n, k;
  (void)state;
  for (n = 24; n <= 96; n += 24) {
    for (k = 0; k < n; k++) {
      xy[2 * k] = 3.0 + 2.0 * cos(2 * PI * (double)k / (double)n);
      xy[2 * k + 1] = -1.0 + 2.0 * sin(2 * PI * (double)k / (double)n);
    }
    memset(&o, 0, sizeof o);
    o.closed = 1;
    o.sigma = 1e-3;
    assert_int_equal(bsfit_segment(xy, n, 2, &o, p, 200, &np, NULL, NULL), BSFIT_OK);
    assert_int_equal((int)np, 1);
    assert_int_equal(p[0].kind, BSFIT_PIECE_ARC);
    assert_float_equal(p[0].radius_se, 1e-3 / sqrt((double)n), 1e-9 * 1e-3);
    o.sigma = 0;
    assert_int_equal(bsfit_segment(xy, n, 2, &o, p, 200, &np, NULL, NULL), BSFIT_OK);
    assert_int_equal((int)np, 1);
    assert_true(p[0].radius_se == 0.0);
  }
}

static void test_join_keeps_each_part(void **state) {
  bsfit_curve a, b, j;
  const bsfit_curve *parts[2];
  double p0[2] = {0, 0}, p1[2] = {2, 0}, ctr[2] = {2, 1}, len[2] = {2, PI}, x[2], y[2];
  int k;
  (void)state;
  bsfit_curve_init(&a), bsfit_curve_init(&b), bsfit_curve_init(&j);
  assert_int_equal(bsfit_curve_line(p0, p1, 2, &a, NULL, NULL), BSFIT_OK);
  assert_int_equal(bsfit_curve_arc(ctr, 1.0, -PI / 2, PI, &b, NULL, NULL), BSFIT_OK);
  parts[0] = &a, parts[1] = &b;
  assert_int_equal(bsfit_curve_join(parts, 2, len, &j, NULL, NULL), BSFIT_OK);
  assert_non_null(j.weights);
  for (k = 0; k <= 50; k++) {
    double t = k / 50.0, s0 = 2 / (2 + PI);
    assert_int_equal(bsfit_curve_eval(&j, t * s0, x, NULL), BSFIT_OK);
    assert_int_equal(bsfit_curve_eval(&a, t, y, NULL), BSFIT_OK);
    assert_float_equal(x[0], y[0], 1e-14);
    assert_float_equal(x[1], y[1], 1e-14);
    assert_int_equal(bsfit_curve_eval(&j, s0 + t * (1 - s0), x, NULL), BSFIT_OK);
    assert_int_equal(bsfit_curve_eval(&b, t, y, NULL), BSFIT_OK);
    assert_float_equal(x[0], y[0], 1e-13);
    assert_float_equal(x[1], y[1], 1e-13);
  }
  len[1] = 0;
  assert_int_equal(bsfit_curve_join(parts, 2, len, &j, NULL, NULL), BSFIT_EINVAL);
  bsfit_curve_free(&a), bsfit_curve_free(&b), bsfit_curve_free(&j);
}

/* brute force: proper crossings among the edges of the closed polyline of k samples */
static size_t brute_crossings(const double *S, size_t k) {
  size_t i, j, n = 0;
  for (i = 0; i < k; i++)
    for (j = i + 2; j < k; j++) {
      const double *a = S + 2 * i, *b = S + 2 * ((i + 1) % k), *c = S + 2 * j,
                   *d = S + 2 * ((j + 1) % k);
      double d1 = (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]);
      double d2 = (b[0] - a[0]) * (d[1] - a[1]) - (b[1] - a[1]) * (d[0] - a[0]);
      double d3 = (d[0] - c[0]) * (a[1] - c[1]) - (d[1] - c[1]) * (a[0] - c[0]);
      double d4 = (d[0] - c[0]) * (b[1] - c[1]) - (d[1] - c[1]) * (b[0] - c[0]);
      if (i == 0 && j == k - 1) continue;
      if (((d1 > 0 && d2 < 0) || (d1 < 0 && d2 > 0)) && ((d3 > 0 && d4 < 0) || (d3 < 0 && d4 > 0)))
        n++;
    }
  return n;
}

static void test_self_intersections_match_brute_force(void **state) {
  static double ctrl[2 * 12], S[2 * 300];
  test_rng r = {11};
  int trial, i;
  (void)state;
  for (trial = 0; trial < 40; trial++) {
    bsfit_curve c;
    size_t n = 0;
    double where;
    bsfit_curve_init(&c);
    /* a random closed cubic: wild control points make loops */
    for (i = 0; i < 12; i++) {
      double a = 2 * PI * i / 12, rad = 1 + rng_range(&r, -0.9, 0.9) * (trial % 3);
      ctrl[2 * i] = rad * cos(a);
      ctrl[2 * i + 1] = rad * sin(a);
    }
    assert_int_equal(bsfit_curve_new_periodic(&c, 3, 2, 12, NULL, ctrl, NULL, NULL, NULL),
                     BSFIT_OK);
    assert_int_equal(bsfit_curve_self_intersections(&c, 300, &n, &where, NULL, NULL), BSFIT_OK);
    assert_int_equal(bsfit_curve_sample(&c, 300, S, NULL, NULL), BSFIT_OK);
    assert_int_equal((int)n, (int)brute_crossings(S, 300));
    bsfit_curve_free(&c);
  }
}

/* Random closed polygons as degree-1 curves (every vertex a corner, each edge sampled
** many times): the crossings are the polygon's own, counted pair by pair. Their edges run
** every way, so the sweep's sort meets many short runs to merge (and long ones, on the
** polygons of few vertices), up to hundreds of crossings. */
static void test_self_intersections_of_random_polygons(void **state) {
  static double V[2 * 41], knots[44];
  test_rng r = {13};
  int trial;
  (void)state;
  for (trial = 0; trial < 300; trial++) {
    size_t nv = 4 + (size_t)(rng_uniform(&r) * 37), i, n = 0;
    bsfit_curve c;
    double where;
    bsfit_curve_init(&c);
    for (i = 0; i < nv; i++) {
      V[2 * i] = rng_uniform(&r) * (1 + trial % 7);
      V[2 * i + 1] = rng_uniform(&r);
    }
    V[2 * nv] = V[0], V[2 * nv + 1] = V[1]; /* closed: the last control point is the first */
    knots[0] = 0;
    for (i = 0; i <= nv; i++) knots[i + 1] = (double)i / (double)nv;
    knots[nv + 2] = 1;
    assert_int_equal(bsfit_curve_new(&c, 1, 2, nv + 1, knots, V, NULL, 0, NULL, NULL), BSFIT_OK);
    assert_int_equal(bsfit_curve_self_intersections(&c, 50 * nv, &n, &where, NULL, NULL), BSFIT_OK);
    assert_int_equal((int)n, (int)brute_crossings(V, nv));
    bsfit_curve_free(&c);
  }
}

/* A corner (a triple knot) whose second side leaves it back along the first, just above
** it, and turns down across it: a loop 1.5e-5 wide and 2.5e-4 of the domain long, within
** one step of 2000 even samples (which missed it). Leaving just below the first side, or
** at a right angle, there is no crossing. */
static void test_self_intersections_next_to_a_corner(void **state) {
  static const double knots[] = {0, 0, 0, 0, 0.5, 0.5, 0.5, 1, 1, 1, 1};
  static const double lift[] = {0.0005, -0.0005, -0.3};
  double ctrl[] = {-1, 0, -0.66, 0, -0.33, 0, 0, 0, -0.01, 0, -0.01, -1, 1, -1};
  int k;
  (void)state;
  for (k = 0; k < 3; k++) {
    bsfit_curve c;
    size_t n = 0;
    double where = -1;
    bsfit_curve_init(&c);
    ctrl[9] = lift[k];
    if (k == 2) ctrl[8] = 0;
    assert_int_equal(bsfit_curve_new(&c, 3, 2, 7, knots, ctrl, NULL, 0, NULL, NULL), BSFIT_OK);
    assert_int_equal(bsfit_curve_self_intersections(&c, 2000, &n, &where, NULL, NULL), BSFIT_OK);
    assert_int_equal((int)n, k == 0 ? 1 : 0);
    if (k == 0) assert_true(where >= 0.4995 && where <= 0.5005);
    bsfit_curve_free(&c);
  }
}

/* a counting allocator with an interrupt flag */
typedef struct alloc_count {
  size_t live, peak, calls;
} alloc_count;

static void *cap_alloc(void *ud, void *p, size_t osz, size_t nsz) {
  alloc_count *c = ud;
  c->calls++;
  if (nsz == 0) {
    c->live -= osz;
    free(p);
    return NULL;
  }
  p = realloc(p, nsz);
  if (p) {
    c->live += nsz - osz;
    if (c->live > c->peak) c->peak = c->live;
  }
  return p;
}

static void test_scratch_through_the_allocator_and_interrupts(void **state) {
  static double xy[2 * 6000];
  static bsfit_corner found[6000];
  static bsfit_piece p[12002];
  alloc_count cnt = {0, 0, 0};
  volatile int stop = 0;
  bsfit_allocator a;
  bsfit_corner_opts co;
  bsfit_segment_opts so;
  size_t i, n = 0;
  (void)state;
  for (i = 0; i < 6000; i++) {
    double t = 2 * PI * (double)i / 6000;
    xy[2 * i] = cos(t) + 0.3 * (fabs(cos(t)) > 0.7 ? 1 : 0);
    xy[2 * i + 1] = 0.6 * sin(t);
  }
  a.fn = cap_alloc, a.ud = &cnt, a.interrupt = &stop;
  memset(&co, 0, sizeof co), memset(&so, 0, sizeof so);
  co.closed = so.closed = 1;
  co.sigma = 1e-3;
  assert_int_equal(bsfit_corners_detect(xy, 6000, 2, &co, found, 6000, &n, &a, NULL), BSFIT_OK);
  assert_true(cnt.calls > 0 && cnt.peak >= 6000 * 10 * sizeof(double));
  assert_int_equal((int)cnt.live, 0);
  cnt.calls = cnt.peak = 0;
  assert_int_equal(bsfit_segment(xy, 6000, 2, &so, p, 12002, &n, &a, NULL), BSFIT_OK);
  assert_true(cnt.calls > 0);
  assert_int_equal((int)cnt.live, 0);
  stop = 1;
  assert_int_equal(bsfit_corners_detect(xy, 6000, 2, &co, found, 6000, &n, &a, NULL), BSFIT_EINTR);
  assert_int_equal(bsfit_segment(xy, 6000, 2, &so, p, 12002, &n, &a, NULL), BSFIT_EINTR);
  assert_int_equal((int)cnt.live, 0);
}

/* an allocator that fails its n-th allocation (counting live bytes) */
typedef struct alloc_failing {
  long calls, fail_at;
  size_t live;
} alloc_failing;

static void *failing_alloc(void *ud, void *p, size_t osz, size_t nsz) {
  alloc_failing *c = ud;
  if (nsz == 0) {
    c->live -= osz;
    free(p);
    return NULL;
  }
  if (++c->calls == c->fail_at) return NULL;
  p = realloc(p, nsz);
  if (p) c->live += nsz - osz;
  return p;
}

/* Each allocation of the crossing test failing in turn: BSFIT_ENOMEM, nothing left live;
** past the last one, the crossing found. */
static void test_self_intersections_out_of_memory(void **state) {
  static const double knots[] = {0, 0, 0, 0, 0.5, 0.5, 0.5, 1, 1, 1, 1};
  double ctrl[] = {-1, 0, -0.66, 0, -0.33, 0, 0, 0, -0.01, 0.0005, -0.01, -1, 1, -1};
  bsfit_curve c;
  long n, total;
  (void)state;
  bsfit_curve_init(&c);
  assert_int_equal(bsfit_curve_new(&c, 3, 2, 7, knots, ctrl, NULL, 0, NULL, NULL), BSFIT_OK);
  {
    alloc_failing f = {0, 0, 0};
    bsfit_allocator a = {failing_alloc, &f, NULL};
    size_t k = 0;
    assert_int_equal(bsfit_curve_self_intersections(&c, 2000, &k, NULL, &a, NULL), BSFIT_OK);
    assert_int_equal((int)k, 1);
    total = f.calls;
    assert_true(total >= 4);
  }
  for (n = 1; n <= total; n++) {
    alloc_failing f = {0, n, 0};
    bsfit_allocator a = {failing_alloc, &f, NULL};
    size_t k = 5;
    assert_int_equal(bsfit_curve_self_intersections(&c, 2000, &k, NULL, &a, NULL), BSFIT_ENOMEM);
    assert_int_equal((int)k, 0);
    assert_int_equal((int)f.live, 0);
  }
  bsfit_curve_free(&c);
}

static void test_segment_errors(void **state) {
  double xy[6] = {0, 0, 1, 0, 0, 1}, same[6] = {1, 1, 1, 1, 1, 1}, bad[6] = {0, 0, NAN, 0, 0, 1};
  bsfit_piece p[8];
  bsfit_segment_opts o;
  bsfit_status st;
  size_t n;
  (void)state;
  memset(&o, 0, sizeof o);
  assert_int_equal(bsfit_segment(xy, 3, 3, &o, p, 8, &n, NULL, &st), BSFIT_EDIM);
  assert_int_equal(bsfit_segment(xy, 2, 2, &o, p, 8, &n, NULL, &st), BSFIT_ETOOFEW);
  assert_int_equal(bsfit_segment(bad, 3, 2, &o, p, 8, &n, NULL, &st), BSFIT_ENONFINITE);
  assert_int_equal(bsfit_segment(same, 3, 2, &o, p, 8, &n, NULL, &st), BSFIT_EDEGENERATE);
  o.min_arc = 2;
  assert_int_equal(bsfit_segment(xy, 3, 2, &o, p, 8, &n, NULL, &st), BSFIT_EINVAL);
  assert_true(strlen(st.msg) > 0);
}

int main(void){
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_polygons_segment_into_lines_meeting_at_the_vertices),
      cmocka_unit_test(test_arc_is_the_circle),
      cmocka_unit_test(test_radius_se_of_a_whole_circle),
      cmocka_unit_test(test_join_keeps_each_part),
      cmocka_unit_test(test_self_intersections_match_brute_force),
      cmocka_unit_test(test_self_intersections_of_random_polygons),
      cmocka_unit_test(test_self_intersections_next_to_a_corner),
      cmocka_unit_test(test_self_intersections_out_of_memory),
      cmocka_unit_test(test_scratch_through_the_allocator_and_interrupts),
      cmocka_unit_test(test_segment_errors),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
