/*
** test_geom.c
** Geometry kernels of the strategies (docs/method.md §7-10) against mathematics: the
** circumradius of regular polygons (R = s / (2 sin(pi/m))) and of points on a circle,
** the paper's weights on a regular polygon and a rounded square, interior angles of
** regular polygons (180 (m-2)/m), inflections of stars, convex shapes and a sine
** wave, turning and spacing weights computed by hand, line projection, and every
** invalid input.
*/
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>
#include <string.h>

#include "bsfit.h"
#include "testutil.h"

#define PI 3.14159265358979323846
#define EPS_GEOM 1e-12 /* radii, angles and weights of exact constructions (relative) */
#define MAXPTS 512

static void expect_error(bsfit_err got, bsfit_err want, const bsfit_status *st) {
  assert_int_equal(got, want);
  assert_int_equal(st->code, want);
  assert_true(strlen(st->msg) > 0);
}

/* {======================================================================
** Point sets
** ====================================================================== */

/* Regular m-gon of circumradius R, centre (cx, cy), first vertex at angle phase. */
static void regular_polygon(size_t m, double R, double cx, double cy, double phase, double *pts) {
  size_t k;
  for (k = 0; k < m; k++) {
    double t = phase + 2.0 * PI * (double)k / (double)m;
    pts[2 * k] = cx + R * cos(t);
    pts[2 * k + 1] = cy + R * sin(t);
  }
}

/* Lifts 2D points into the tilted plane spanned by two orthonormal 3D vectors
** through origin o: an isometry, so radii, angles and turn signs are unchanged. */
static void lift_3d(const double *p2, size_t m, double *p3) {
  const double e1[3] = {2.0 / 3.0, 1.0 / 3.0, 2.0 / 3.0};  /* unit */
  const double e2[3] = {-1.0 / 3.0, -2.0 / 3.0, 2.0 / 3.0}; /* unit, orthogonal to e1 */
  const double o[3] = {0.5, -1.0, 2.0};
  size_t k;
  int i;
  for (k = 0; k < m; k++)
    for (i = 0; i < 3; i++) p3[3 * k + i] = o[i] + p2[2 * k] * e1[i] + p2[2 * k + 1] * e2[i];
}

/* m points on a circle of radius R centred at the origin, at sorted random angles
** (uneven spacing, each gap between 0.5 and 1.5 times the mean). Rounding the
** coordinates moves a radius by about eps |Q| R / gap^2, so gaps are kept above
** ~0.05 R for the 1e-12 check. */
static void uneven_circle(test_rng *r, size_t m, double R, double *pts) {
  double t[MAXPTS], total = 0.0, acc = 0.0;
  size_t k;
  for (k = 0; k < m; k++) total += (t[k] = rng_range(r, 0.5, 1.5));
  for (k = 0; k < m; k++) {
    double a = 2.0 * PI * acc / total;
    acc += t[k];
    pts[2 * k] = R * cos(a);
    pts[2 * k + 1] = R * sin(a);
  }
}

/* A star with s spikes: 2s vertices alternating between radii 1 and 0.4, each side
** subdivided into `sub` equal parts (the extra points are collinear). */
static size_t star(size_t s, size_t sub, double *pts) {
  size_t v, j, n = 0, nv = 2 * s;
  for (v = 0; v < nv; v++) {
    double a0 = 2.0 * PI * (double)v / (double)nv, a1 = 2.0 * PI * (double)(v + 1) / (double)nv;
    double r0 = (v % 2) ? 0.4 : 1.0, r1 = (v % 2) ? 1.0 : 0.4;
    double x0 = r0 * cos(a0), y0 = r0 * sin(a0), x1 = r1 * cos(a1), y1 = r1 * sin(a1);
    for (j = 0; j < sub; j++) {
      double f = (double)j / (double)sub;
      pts[2 * n] = x0 + f * (x1 - x0);
      pts[2 * n + 1] = y0 + f * (y1 - y0);
      n++;
    }
  }
  return n;
}

/* A square [0,side]^2 traversed counter-clockwise, each side cut into `sub` equal
** parts; the corners are points 0, sub, 2 sub, 3 sub. */
static size_t subdivided_square(double side, size_t sub, double *pts) {
  const double cx[4] = {0, 1, 1, 0}, cy[4] = {0, 0, 1, 1};
  size_t c, j, n = 0;
  for (c = 0; c < 4; c++) {
    size_t d = (c + 1) % 4;
    for (j = 0; j < sub; j++) {
      double f = (double)j / (double)sub;
      pts[2 * n] = side * (cx[c] + f * (cx[d] - cx[c]));
      pts[2 * n + 1] = side * (cy[c] + f * (cy[d] - cy[c]));
      n++;
    }
  }
  return n;
}

/* The square [0,10]^2 with corners rounded by quarter circles of radius 1. Per side:
** the points 1, 2, ..., 9 along it (1 and 9 are where the arcs start: the
** transitions); per corner: the arc's midpoint. 40 points, kind[k] = 0 straight
** (interior of a side), 1 transition, 2 arc midpoint. */
static size_t rounded_square(double *pts, int *kind) {
  /* side c runs from corner c to corner c+1; arc c+1 sits at corner c+1 */
  const double ox[4] = {0, 10, 10, 0}, oy[4] = {0, 0, 10, 10};
  const double dx[4] = {1, 0, -1, 0}, dy[4] = {0, 1, 0, -1};
  size_t c, j, n = 0;
  for (c = 0; c < 4; c++) {
    size_t d = (c + 1) % 4;
    /* centre of the arc at corner d: 1 unit inside along both sides */
    double ccx = ox[d] - dx[c] + dx[d], ccy = oy[d] - dy[c] + dy[d];
    double mx = -dx[c] + dx[d], my = -dy[c] + dy[d]; /* from the centre towards... */
    for (j = 1; j <= 9; j++) {
      pts[2 * n] = ox[c] + (double)j * dx[c];
      pts[2 * n + 1] = oy[c] + (double)j * dy[c];
      kind[n++] = (j == 1 || j == 9) ? 1 : 0;
    }
    /* the arc midpoint lies from its centre towards the corner, at distance 1 */
    pts[2 * n] = ccx - mx / sqrt(2.0);
    pts[2 * n + 1] = ccy - my / sqrt(2.0);
    kind[n++] = 2;
  }
  return n;
}

/* }====================================================================== */

/* {======================================================================
** Circumradius
** ====================================================================== */

static void test_regular_polygon_radii_equal_circumradius(void **state) {
  /* given regular m-gons of side s, then every triple's circle is the circumcircle,
  ** R = s / (2 sin(pi/m)), in the plane and in a tilted 3D plane, for both triples */
  double pts[2 * 64], p3[3 * 64], r[64];
  size_t m, k;
  (void)state;
  for (m = 3; m <= 64; m += 7) {
    double Rc = 2.5, s = 2.0 * Rc * sin(PI / (double)m), R = s / (2.0 * sin(PI / (double)m));
    int centered;
    regular_polygon(m, Rc, 3.0, -1.0, 0.3, pts);
    lift_3d(pts, m, p3);
    for (centered = 0; centered <= 1; centered++) {
      assert_int_equal(bsfit_geom_circumradius(pts, m, 2, 1, centered, r, NULL), BSFIT_OK);
      for (k = 0; k < m; k++) assert_float_equal(r[k], R, EPS_GEOM * R);
      assert_int_equal(bsfit_geom_circumradius(p3, m, 3, 1, centered, r, NULL), BSFIT_OK);
      for (k = 0; k < m; k++) assert_float_equal(r[k], R, EPS_GEOM * R);
    }
  }
}

static void test_uneven_circle_radii(void **state) {
  /* given points on a circle of radius 1 with uneven spacing, open or closed, 2D or
  ** lifted to 3D, then every radius is 1 within 1e-12 */
  test_rng rg = {42};
  double pts[2 * 60], p3[3 * 60], r[60];
  size_t m = 60, k;
  int closed;
  (void)state;
  uneven_circle(&rg, m, 1.0, pts);
  lift_3d(pts, m, p3);
  for (closed = 0; closed <= 1; closed++) {
    assert_int_equal(bsfit_geom_circumradius(pts, m, 2, closed, 1, r, NULL), BSFIT_OK);
    for (k = 0; k < m; k++) assert_float_equal(r[k], 1.0, 1e-12);
    assert_int_equal(bsfit_geom_circumradius(p3, m, 3, closed, 0, r, NULL), BSFIT_OK);
    for (k = 0; k < m; k++) assert_float_equal(r[k], 1.0, 1e-12);
  }
}

static void test_paper_triple_is_shifted_centred_triple(void **state) {
  /* the paper's triple (Q_k, Q_k+1, Q_k+2) is the centred triple of Q_k+1; open data
  ** take the nearest full triple at the ends */
  test_rng rg = {7};
  double pts[2 * 30], rc[30], rp[30];
  size_t m = 30, k;
  (void)state;
  for (k = 0; k < 2 * m; k++) pts[k] = rng_range(&rg, -5.0, 5.0);
  assert_int_equal(bsfit_geom_circumradius(pts, m, 2, 1, 1, rc, NULL), BSFIT_OK);
  assert_int_equal(bsfit_geom_circumradius(pts, m, 2, 1, 0, rp, NULL), BSFIT_OK);
  for (k = 0; k < m; k++) assert_float_equal(rp[k], rc[(k + 1) % m], 0.0);
  assert_int_equal(bsfit_geom_circumradius(pts, m, 2, 0, 1, rc, NULL), BSFIT_OK);
  assert_int_equal(bsfit_geom_circumradius(pts, m, 2, 0, 0, rp, NULL), BSFIT_OK);
  assert_float_equal(rc[0], rc[1], 0.0);
  assert_float_equal(rc[m - 1], rc[m - 2], 0.0);
  for (k = 0; k + 2 < m; k++) assert_float_equal(rp[k], rc[k + 1], 0.0);
  assert_float_equal(rp[m - 2], rc[m - 2], 0.0);
  assert_float_equal(rp[m - 1], rc[m - 2], 0.0);
}

static void test_collinear_threshold(void **state) {
  /* triangle (0,0), (1,h), (2,0): twice the area is 2h, the longest side 2, so it is
  ** collinear when 2h <= 4e-12; otherwise R = (1 + h^2) / (2h) */
  double r[3];
  double a[6] = {0, 0, 1, 1e-12, 2, 0};
  double b[6] = {0, 0, 1, 1e-9, 2, 0};
  double c[6] = {0, 0, 0, 0, 3, 4}; /* two coincident points */
  double d[6] = {1, 1, 1, 1, 1, 1}; /* three coincident points */
  double e[6] = {0, 0, 1, 0.5, 2, 0};
  (void)state;
  assert_int_equal(bsfit_geom_circumradius(a, 3, 2, 0, 1, r, NULL), BSFIT_OK);
  assert_true(isinf(r[0]) && isinf(r[1]) && isinf(r[2]));
  assert_int_equal(bsfit_geom_circumradius(b, 3, 2, 0, 1, r, NULL), BSFIT_OK);
  assert_float_equal(r[1], (1.0 + 1e-18) / 2e-9, 1e-12 * r[1]);
  assert_int_equal(bsfit_geom_circumradius(c, 3, 2, 1, 1, r, NULL), BSFIT_OK);
  assert_true(isinf(r[0]) && isinf(r[1]) && isinf(r[2]));
  assert_int_equal(bsfit_geom_circumradius(d, 3, 2, 1, 1, r, NULL), BSFIT_OK);
  assert_true(isinf(r[0]) && isinf(r[1]) && isinf(r[2]));
  assert_int_equal(bsfit_geom_circumradius(e, 3, 2, 1, 1, r, NULL), BSFIT_OK);
  assert_float_equal(r[0], 1.25 / 1.0, EPS_GEOM); /* (1 + 0.25) / (2 * 0.5) */
}

/* }====================================================================== */

/* {======================================================================
** The paper's weights
** ====================================================================== */

static double max_of(const double *w, size_t m) {
  double x = w[0];
  size_t k;
  for (k = 1; k < m; k++) x = w[k] > x ? w[k] : x;
  return x;
}

static void test_weights_regular_polygon_all_equal(void **state) {
  /* all radii equal: std = 0, r_max = r, every weight is 1 */
  double pts[2 * 50], w[50];
  size_t m, k;
  (void)state;
  for (m = 3; m <= 50; m += 11) {
    regular_polygon(m, 7.0, -2.0, 1.0, 1.1, pts);
    assert_int_equal(bsfit_weights_circumradius(pts, m, 2, 1, 1, w, NULL), BSFIT_OK);
    for (k = 0; k < m; k++) assert_float_equal(w[k], 1.0, EPS_GEOM);
  }
}

static void test_weights_circle_and_line(void **state) {
  /* points on a circle (uneven spacing): all weights 1; all collinear: all 1 */
  test_rng rg = {99};
  double pts[2 * 60], w[60], line[2 * 10];
  size_t k;
  (void)state;
  uneven_circle(&rg, 60, 3.0, pts);
  assert_int_equal(bsfit_weights_circumradius(pts, 60, 2, 1, 1, w, NULL), BSFIT_OK);
  for (k = 0; k < 60; k++) assert_float_equal(w[k], 1.0, 1e-11);
  for (k = 0; k < 10; k++) {
    line[2 * k] = 1.0 + 2.0 * (double)k;
    line[2 * k + 1] = -3.0 + 0.5 * (double)k;
  }
  assert_int_equal(bsfit_weights_circumradius(line, 10, 2, 0, 1, w, NULL), BSFIT_OK);
  for (k = 0; k < 10; k++) assert_float_equal(w[k], 1.0, 0.0);
}

static void test_weights_subdivided_square(void **state) {
  /* sharp square, sides cut in 5: the 4 corners have the only finite radius
  ** (h sqrt(2) / 2), so w = 1 there, and the straight runs get w_max = 1 too */
  double pts[2 * 20], w[20], r[20];
  size_t m = subdivided_square(5.0, 5, pts), k;
  (void)state;
  assert_int_equal(bsfit_geom_circumradius(pts, m, 2, 1, 1, r, NULL), BSFIT_OK);
  for (k = 0; k < m; k++) {
    if (k % 5 == 0) assert_float_equal(r[k], sqrt(2.0) / 2.0, EPS_GEOM);
    else assert_true(isinf(r[k]));
  }
  assert_int_equal(bsfit_weights_circumradius(pts, m, 2, 1, 1, w, NULL), BSFIT_OK);
  for (k = 0; k < m; k++) assert_float_equal(w[k], max_of(w, m), 1e-12);
}

static void test_weights_rounded_square(void **state) {
  /* rounded square: arc midpoints have the smallest radius (1, exactly the arc's)
  ** and straight runs r = Inf: both get w_max; the 8 transition points have a
  ** larger finite radius r_t below r_max = mean + std (4 radii 1 and 8 radii r_t:
  ** r_max = 1 + (2/3 + sqrt(2)/3)(r_t - 1) > r_t), so 1 < w < w_max there */
  double pts[2 * 40], w[40], r[40], rt;
  int kind[40];
  size_t m = rounded_square(pts, kind), k;
  (void)state;
  assert_int_equal(m, 40);
  assert_int_equal(bsfit_geom_circumradius(pts, m, 2, 1, 1, r, NULL), BSFIT_OK);
  rt = r[0]; /* point 0 is a transition */
  for (k = 0; k < m; k++) {
    if (kind[k] == 0) assert_true(isinf(r[k]));
    if (kind[k] == 1) assert_float_equal(r[k], rt, 1e-12 * rt);
    if (kind[k] == 2) assert_float_equal(r[k], 1.0, EPS_GEOM);
  }
  assert_true(rt > 1.0);
  assert_int_equal(bsfit_weights_circumradius(pts, m, 2, 1, 1, w, NULL), BSFIT_OK);
  {
    double rmax = 1.0 + (2.0 / 3.0 + sqrt(2.0) / 3.0) * (rt - 1.0), wmax = max_of(w, m);
    assert_float_equal(wmax, rmax, 1e-12 * rmax);
    for (k = 0; k < m; k++) {
      if (kind[k] != 1) assert_float_equal(w[k], wmax, 1e-12 * wmax);
      else {
        assert_float_equal(w[k], rmax / rt, 1e-12);
        assert_true(w[k] > 1.0 && w[k] < wmax);
      }
    }
  }
}

/* }====================================================================== */

/* {======================================================================
** Angles and inflections
** ====================================================================== */

static void test_angles_regular_polygon(void **state) {
  /* interior angle of a regular m-gon: 180 (m - 2) / m, closed; in 3D the same */
  double pts[2 * 40], p3[3 * 40], ang[40];
  size_t m, k;
  (void)state;
  for (m = 3; m <= 40; m++) {
    double want = 180.0 * (double)(m - 2) / (double)m;
    regular_polygon(m, 1.5, 0.2, 0.1, 0.7, pts);
    lift_3d(pts, m, p3);
    assert_int_equal(bsfit_geom_angles(pts, m, 2, 1, ang, NULL), BSFIT_OK);
    for (k = 0; k < m; k++) assert_float_equal(ang[k], want, 1e-11);
    assert_int_equal(bsfit_geom_angles(p3, m, 3, 1, ang, NULL), BSFIT_OK);
    for (k = 0; k < m; k++) assert_float_equal(ang[k], want, 1e-11);
  }
}

static void test_angles_straight_coincident_open(void **state) {
  /* subdivided square: 90 at corners, 180 on the sides; a point repeated: 180;
  ** open data: the ends copy their neighbours */
  double pts[2 * 12], ang[12];
  double dup[2 * 4] = {0, 0, 1, 0, 1, 0, 1, 1};
  double open[2 * 4] = {0, 0, 1, 0, 1, 1, 2, 1};
  size_t m = subdivided_square(2.0, 3, pts), k;
  (void)state;
  assert_int_equal(bsfit_geom_angles(pts, m, 2, 1, ang, NULL), BSFIT_OK);
  for (k = 0; k < m; k++) assert_float_equal(ang[k], (k % 3 == 0) ? 90.0 : 180.0, 1e-12);
  assert_int_equal(bsfit_geom_angles(dup, 4, 2, 0, ang, NULL), BSFIT_OK);
  assert_float_equal(ang[1], 180.0, 0.0);
  assert_float_equal(ang[2], 180.0, 0.0);
  assert_int_equal(bsfit_geom_angles(open, 4, 2, 0, ang, NULL), BSFIT_OK);
  assert_float_equal(ang[1], 90.0, 1e-12);
  assert_float_equal(ang[2], 90.0, 1e-12);
  assert_float_equal(ang[0], ang[1], 0.0);
  assert_float_equal(ang[3], ang[2], 0.0);
}

static void test_inflections_star_and_convex(void **state) {
  /* a star with 5 spikes turns left and right alternately at its 10 vertices: 10
  ** inflections (collinear subdivision points are skipped; 3D the same); a convex
  ** polygon: 0, clockwise or counter-clockwise */
  double pts[2 * 40], p3[3 * 40], rev[2 * 40];
  size_t count = 99, m, k, sub;
  (void)state;
  for (sub = 1; sub <= 4; sub++) {
    m = star(5, sub, pts);
    assert_int_equal(bsfit_geom_inflections(pts, m, 2, 1, &count, NULL), BSFIT_OK);
    assert_int_equal(count, 10);
    lift_3d(pts, m, p3);
    assert_int_equal(bsfit_geom_inflections(p3, m, 3, 1, &count, NULL), BSFIT_OK);
    assert_int_equal(count, 10);
  }
  m = 24;
  regular_polygon(m, 2.0, 0.0, 0.0, 0.0, pts);
  assert_int_equal(bsfit_geom_inflections(pts, m, 2, 1, &count, NULL), BSFIT_OK);
  assert_int_equal(count, 0);
  for (k = 0; k < m; k++) {
    rev[2 * k] = pts[2 * (m - 1 - k)];
    rev[2 * k + 1] = pts[2 * (m - 1 - k) + 1];
  }
  assert_int_equal(bsfit_geom_inflections(rev, m, 2, 1, &count, NULL), BSFIT_OK);
  assert_int_equal(count, 0);
  m = subdivided_square(1.0, 4, pts);
  assert_int_equal(bsfit_geom_inflections(pts, m, 2, 1, &count, NULL), BSFIT_OK);
  assert_int_equal(count, 0);
}

static void test_inflections_open_sine(void **state) {
  /* y = sin x sampled on [0.3, 3 pi - 0.3]: curvature changes sign at pi and 2 pi;
  ** no sample lies near them, so the open polygon has exactly 2 inflections */
  double pts[2 * 61];
  size_t k, m = 61, count = 0;
  double h = (3.0 * PI - 0.6) / 60.0;
  (void)state;
  for (k = 0; k < m; k++) {
    double x = 0.3 + h * (double)k;
    assert_true(fabs(x - PI) > 0.2 * h && fabs(x - 2.0 * PI) > 0.2 * h);
    pts[2 * k] = x;
    pts[2 * k + 1] = sin(x);
  }
  assert_int_equal(bsfit_geom_inflections(pts, m, 2, 0, &count, NULL), BSFIT_OK);
  assert_int_equal(count, 2);
}

/* }====================================================================== */

/* {======================================================================
** Turning and spacing weights
** ====================================================================== */

static void test_turning_weights(void **state) {
  /* square with sides cut in `sub`: turns are 90 at the 4 corners, 0 elsewhere, so
  ** mean |turn| = 360 / m and the corners get 1 + m / 4, the rest 1; a regular
  ** polygon: all 2; a straight line: all 1 */
  double pts[2 * 24], w[24];
  size_t m = subdivided_square(3.0, 6, pts), k;
  (void)state;
  assert_int_equal(bsfit_weights_turning(pts, m, 2, 1, w, NULL), BSFIT_OK);
  for (k = 0; k < m; k++)
    assert_float_equal(w[k], (k % 6 == 0) ? 1.0 + (double)m / 4.0 : 1.0, 1e-12);
  regular_polygon(17, 1.0, 0.0, 0.0, 0.0, pts);
  assert_int_equal(bsfit_weights_turning(pts, 17, 2, 1, w, NULL), BSFIT_OK);
  for (k = 0; k < 17; k++) assert_float_equal(w[k], 2.0, 1e-12);
  for (k = 0; k < 5; k++) {
    pts[2 * k] = (double)k;
    pts[2 * k + 1] = 2.0 * (double)k;
  }
  assert_int_equal(bsfit_weights_turning(pts, 5, 2, 0, w, NULL), BSFIT_OK);
  for (k = 0; k < 5; k++) assert_float_equal(w[k], 1.0, 0.0);
}

static void test_spacing_weights(void **state) {
  /* closed: (0,0) (1,0) (2,0) (3,0) (4,0) (4,4) (0,4): chords 1,1,1,1,4,4,4, so the
  ** local spacings are 2.5,1,1,1,2.5,4,4 (mean 16/7) and w = 7 s / 16 */
  const double cl[] = {0, 0, 1, 0, 2, 0, 3, 0, 4, 0, 4, 4, 0, 4};
  const double s[] = {2.5, 1, 1, 1, 2.5, 4, 4};
  /* open: (0,0) (1,0) (3,0): spacings 1, 1.5, 2 (ends use their one chord) */
  const double op[] = {0, 0, 1, 0, 3, 0};
  /* a point repeated three times: the middle copy gets the floor */
  const double dup[] = {0, 0, 1, 0, 1, 0, 1, 0, 1, 1};
  const double same[] = {2, 2, 2, 2, 2, 2};
  double w[7];
  size_t k;
  (void)state;
  assert_int_equal(bsfit_weights_spacing(cl, 7, 2, 1, w, NULL), BSFIT_OK);
  for (k = 0; k < 7; k++) assert_float_equal(w[k], 7.0 * s[k] / 16.0, 1e-15);
  assert_int_equal(bsfit_weights_spacing(op, 3, 2, 0, w, NULL), BSFIT_OK);
  assert_float_equal(w[0], 2.0 / 3.0, 1e-15);
  assert_float_equal(w[1], 1.0, 1e-15);
  assert_float_equal(w[2], 4.0 / 3.0, 1e-15);
  assert_int_equal(bsfit_weights_spacing(dup, 5, 2, 0, w, NULL), BSFIT_OK);
  assert_float_equal(w[2], BSFIT_GEOM_SPACING_FLOOR, 0.0);
  assert_int_equal(bsfit_weights_spacing(same, 3, 2, 1, w, NULL), BSFIT_OK);
  for (k = 0; k < 3; k++) assert_float_equal(w[k], 1.0, 0.0);
}

/* }====================================================================== */

/* {======================================================================
** Lines
** ====================================================================== */

static void test_tangent_project_and_distance(void **state) {
  /* P = (3, 4) onto the x axis through the origin: (3, 0), distance 4. 3D: the foot
  ** F satisfies (P - F) . dir = 0 and F - O parallel to dir, and the distance equals
  ** |(P - O) x dir| / |dir| */
  double P[3] = {3, 4, 0}, O[3] = {0, 0, 0}, D[3] = {2, 0, 0}, out[3], d;
  double P3[3] = {1.0, -2.0, 3.5}, O3[3] = {0.5, 0.25, -1.0}, D3[3] = {1.0, 2.0, -2.0}, F[3];
  (void)state;
  assert_int_equal(bsfit_geom_tangent_project(P, O, D, 2, out, NULL), BSFIT_OK);
  assert_float_equal(out[0], 3.0, 0.0);
  assert_float_equal(out[1], 0.0, 0.0);
  assert_int_equal(bsfit_geom_line_distance(P, O, D, 2, &d, NULL), BSFIT_OK);
  assert_float_equal(d, 4.0, 1e-15);
  assert_int_equal(bsfit_geom_tangent_project(P3, O3, D3, 3, F, NULL), BSFIT_OK);
  {
    double pf[3], fo[3], po[3], cr[3], dot = 0.0;
    int i;
    for (i = 0; i < 3; i++) {
      pf[i] = P3[i] - F[i];
      fo[i] = F[i] - O3[i];
      po[i] = P3[i] - O3[i];
      dot += pf[i] * D3[i];
    }
    assert_float_equal(dot, 0.0, 1e-14);
    assert_float_equal(fo[0] * D3[1] - fo[1] * D3[0], 0.0, 1e-14);
    assert_float_equal(fo[1] * D3[2] - fo[2] * D3[1], 0.0, 1e-14);
    cr[0] = po[1] * D3[2] - po[2] * D3[1];
    cr[1] = po[2] * D3[0] - po[0] * D3[2];
    cr[2] = po[0] * D3[1] - po[1] * D3[0];
    assert_int_equal(bsfit_geom_line_distance(P3, O3, D3, 3, &d, NULL), BSFIT_OK);
    assert_float_equal(d, sqrt(cr[0] * cr[0] + cr[1] * cr[1] + cr[2] * cr[2]) / 3.0, 1e-14);
  }
  /* out may be P itself */
  assert_int_equal(bsfit_geom_tangent_project(P3, O3, D3, 3, P3, NULL), BSFIT_OK);
  assert_memory_equal(P3, F, sizeof F);
}

static void test_line_errors(void **state) {
  double P[3] = {1, 2, 3}, O[3] = {0, 0, 0}, D[3] = {1, 1, 1}, Z[3] = {0, 0, 0}, out[3], d;
  double N[3] = {NAN, 0, 0};
  bsfit_status st;
  (void)state;
  expect_error(bsfit_geom_tangent_project(P, O, Z, 3, out, &st), BSFIT_EDEGENERATE, &st);
  expect_error(bsfit_geom_line_distance(P, O, Z, 2, &d, &st), BSFIT_EDEGENERATE, &st);
  expect_error(bsfit_geom_tangent_project(P, O, D, 4, out, &st), BSFIT_EDIM, &st);
  expect_error(bsfit_geom_line_distance(P, O, D, 1, &d, &st), BSFIT_EDIM, &st);
  expect_error(bsfit_geom_tangent_project(N, O, D, 3, out, &st), BSFIT_ENONFINITE, &st);
  expect_error(bsfit_geom_line_distance(P, O, N, 3, &d, &st), BSFIT_ENONFINITE, &st);
  expect_error(bsfit_geom_tangent_project(NULL, O, D, 3, out, &st), BSFIT_EINVAL, &st);
  expect_error(bsfit_geom_line_distance(P, O, D, 3, NULL, &st), BSFIT_EINVAL, &st);
  assert_int_equal(bsfit_geom_tangent_project(P, NULL, D, 3, out, NULL), BSFIT_EINVAL);
}

/* }====================================================================== */

/* {======================================================================
** Invalid sequences
** ====================================================================== */

typedef bsfit_err (*seq_kernel)(const double *pts, size_t m, int dim, int closed, double *out,
                                bsfit_status *st);

static bsfit_err radius_centred(const double *p, size_t m, int dim, int closed, double *o,
                                bsfit_status *st) {
  return bsfit_geom_circumradius(p, m, dim, closed, 1, o, st);
}
static bsfit_err weights_paper(const double *p, size_t m, int dim, int closed, double *o,
                               bsfit_status *st) {
  return bsfit_weights_circumradius(p, m, dim, closed, 0, o, st);
}
static bsfit_err inflections_as_double(const double *p, size_t m, int dim, int closed, double *o,
                                       bsfit_status *st) {
  size_t c = 0;
  bsfit_err e = bsfit_geom_inflections(p, m, dim, closed, o ? &c : NULL, st);
  if (e == BSFIT_OK) o[0] = (double)c;
  return e;
}

static void test_sequence_errors(void **state) {
  /* every kernel: m < 3, dim not 2/3, NaN and Inf, NULL arrays; the output is left
  ** untouched on failure */
  const seq_kernel kernels[] = {radius_centred, weights_paper, bsfit_geom_angles,
                                bsfit_weights_turning, bsfit_weights_spacing,
                                inflections_as_double};
  double pts[2 * 6] = {0, 0, 1, 0, 1, 1, 0, 1, 0.5, 2, -1, 1};
  double out[6];
  bsfit_status st;
  size_t i, k;
  (void)state;
  for (i = 0; i < sizeof kernels / sizeof kernels[0]; i++) {
    for (k = 0; k < 6; k++) out[k] = -7.0;
    expect_error(kernels[i](pts, 2, 2, 1, out, &st), BSFIT_ETOOFEW, &st);
    expect_error(kernels[i](pts, 0, 2, 0, out, &st), BSFIT_ETOOFEW, &st);
    expect_error(kernels[i](pts, 4, 1, 1, out, &st), BSFIT_EDIM, &st);
    expect_error(kernels[i](pts, 4, 4, 1, out, &st), BSFIT_EDIM, &st);
    expect_error(kernels[i](NULL, 4, 2, 1, out, &st), BSFIT_EINVAL, &st);
    expect_error(kernels[i](pts, 4, 2, 1, NULL, &st), BSFIT_EINVAL, &st);
    pts[7] = NAN;
    expect_error(kernels[i](pts, 6, 2, 1, out, &st), BSFIT_ENONFINITE, &st);
    assert_non_null(strstr(st.msg, "point 3"));
    pts[7] = INFINITY;
    expect_error(kernels[i](pts, 4, 2, 0, out, &st), BSFIT_ENONFINITE, &st);
    assert_int_equal(kernels[i](pts, 4, 2, 0, out, NULL), BSFIT_ENONFINITE);
    pts[7] = 1.0;
    for (k = 0; k < 6; k++) assert_float_equal(out[k], -7.0, 0.0);
    /* and the fixed data succeed, with an OK status */
    assert_int_equal(kernels[i](pts, 6, 2, 1, out, &st), BSFIT_OK);
    assert_int_equal(st.code, BSFIT_OK);
  }
}

/* }====================================================================== */

int main(void) {
  const struct CMUnitTest tests[] = {
    cmocka_unit_test(test_regular_polygon_radii_equal_circumradius),
    cmocka_unit_test(test_uneven_circle_radii),
    cmocka_unit_test(test_paper_triple_is_shifted_centred_triple),
    cmocka_unit_test(test_collinear_threshold),
    cmocka_unit_test(test_weights_regular_polygon_all_equal),
    cmocka_unit_test(test_weights_circle_and_line),
    cmocka_unit_test(test_weights_subdivided_square),
    cmocka_unit_test(test_weights_rounded_square),
    cmocka_unit_test(test_angles_regular_polygon),
    cmocka_unit_test(test_angles_straight_coincident_open),
    cmocka_unit_test(test_inflections_star_and_convex),
    cmocka_unit_test(test_inflections_open_sine),
    cmocka_unit_test(test_turning_weights),
    cmocka_unit_test(test_spacing_weights),
    cmocka_unit_test(test_tangent_project_and_distance),
    cmocka_unit_test(test_line_errors),
    cmocka_unit_test(test_sequence_errors),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
