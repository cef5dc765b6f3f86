/*
** test_filter_smooth.c
** Smoothing to a tolerance (bsfit_filter_smooth_curve) on noisy fitted sections: ellipses
** of random proportions, five-lobed stars and symmetric airfoils with a sharp trailing
** edge, noise 0.1% to 1% of the size, several seeds; each closed cubic fitted by the
** periodic least-squares fitter. The result must be cubic and closed; within tol of the
** input everywhere, checked by brute force (every sample of each curve against every
** segment of a dense polyline of the other: no closest-point code of the library); its
** bending energy lower than that of one box pass moved as far; the bound it reports at
** least the sampled parametric difference. Then an already smooth curve with a tiny tol,
** and bad input.
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
#include "cmocka_double.h"
#include "testutil.h"
#include "filter_testutil.h"

#define M_PTS 400     /* points of a section */
#define NPOLY 6000    /* vertices of a dense polyline */
#define NPROBE 1500   /* samples checked against the other curve's polyline */
#define ENERGY_N 3000 /* samples of the energies compared */

static const double TWO_PI = 6.283185307179586;

/* {====================================================================
** Sections
** ===================================================================== */

enum shape { ELLIPSE, STAR, AIRFOIL };

/* Point of the shape at t in [0, 1): size about 2. */
static void shape_at(enum shape s, double aspect, double t, double *p) {
  double th = TWO_PI * t;
  if (s == ELLIPSE) {
    p[0] = cos(th);
    p[1] = aspect * sin(th);
  } else if (s == STAR) {
    double r = 1.0 + 0.15 * cos(5.0 * th);
    p[0] = r * cos(th);
    p[1] = r * sin(th);
  } else { /* NACA 00xx thickness, chord 2: upper side, then lower, sharp at x = 2 */
    double x = t < 0.5 ? 1.0 - cos(TWO_PI * t) : 1.0 - cos(TWO_PI * (1.0 - t)), xc = x / 2.0;
    double y = 5.0 * 0.12 * (0.2969 * sqrt(xc) - 0.1260 * xc - 0.3516 * xc * xc +
                             0.2843 * xc * xc * xc - 0.1036 * xc * xc * xc * xc) * 2.0;
    p[0] = 2.0 - x;
    p[1] = t < 0.5 ? y : -y;
  }
}

/* Gaussian noise (Box-Muller) */
static double gauss(test_rng *r) {
  double u = rng_range(r, 1e-12, 1.0), v = rng_uniform(r);
  return sqrt(-2.0 * log(u)) * cos(TWO_PI * v);
}

/* A closed cubic of M_PTS / 5 control points fitted to M_PTS noisy points of the shape. */
static void fitted_section(enum shape s, double noise, test_rng *r, bsfit_curve *c) {
  double pts[2 * M_PTS], u[M_PTS], aspect = rng_range(r, 0.3, 0.8);
  bsfit_fit_opts o;
  bsfit_fitter *f = NULL;
  bsfit_status st;
  size_t i;
  for (i = 0; i < M_PTS; i++) {
    shape_at(s, aspect, (double)i / M_PTS, pts + 2 * i);
    pts[2 * i] += noise * gauss(r);
    pts[2 * i + 1] += noise * gauss(r);
  }
  bsfit_fit_opts_init(&o);
  o.count = M_PTS / 5;
  o.periodic = 1;
  bsfit_curve_init(c);
  assert_int_equal(bsfit_params(pts, M_PTS, 2, BSFIT_PARAM_CHORD, 1, u, &st), BSFIT_OK);
  assert_int_equal(bsfit_fitter_new(&f, &o, NULL, &st), BSFIT_OK);
  assert_int_equal(bsfit_fitter_fit(f, pts, M_PTS, 2, u, NULL, c, NULL, NULL, &st), BSFIT_OK);
  bsfit_fitter_free(f);
}

/* }==================================================================== */

/* {====================================================================
** Brute-force distance: samples against every segment of a dense closed polyline
** ===================================================================== */

static void closed_polyline(const bsfit_curve *c, size_t n, double *P) {
  double a, b;
  bsfit_status st;
  size_t i;
  bsfit_curve_domain(c, &a, &b);
  for (i = 0; i < n; i++)
    assert_int_equal(bsfit_curve_eval(c, a + (b - a) * (double)i / (double)n, P + 2 * i, &st),
                     BSFIT_OK);
}

static double point_segment(const double *p, const double *a, const double *b) {
  double dx = b[0] - a[0], dy = b[1] - a[1], l2 = dx * dx + dy * dy, t = 0.0, x, y;
  if (l2 > 0) t = fmin(1.0, fmax(0.0, ((p[0] - a[0]) * dx + (p[1] - a[1]) * dy) / l2));
  x = a[0] + t * dx - p[0];
  y = a[1] + t * dy - p[1];
  return sqrt(x * x + y * y);
}

/* max over NPROBE samples of A of the distance to B's polyline. */
static double one_way(const bsfit_curve *A, const double *poly) {
  double *S = malloc(2 * NPROBE * sizeof(double)), worst = 0.0;
  size_t i, j;
  assert_non_null(S);
  closed_polyline(A, NPROBE, S);
  for (i = 0; i < NPROBE; i++) {
    double best = INFINITY;
    for (j = 0; j < NPOLY; j++)
      best = fmin(best, point_segment(S + 2 * i, poly + 2 * j, poly + 2 * ((j + 1) % NPOLY)));
    worst = fmax(worst, best);
  }
  free(S);
  return worst;
}

static double hausdorff(const bsfit_curve *A, const bsfit_curve *B) {
  double *PA = malloc(2 * NPOLY * sizeof(double)), *PB = malloc(2 * NPOLY * sizeof(double)), d;
  assert_non_null(PA);
  assert_non_null(PB);
  closed_polyline(A, NPOLY, PA);
  closed_polyline(B, NPOLY, PB);
  d = fmax(one_way(A, PB), one_way(B, PA));
  free(PA);
  free(PB);
  return d;
}

/* The largest |A(t) - B(t)| at ENERGY_N parameters of A's period (B wraps). */
static double parametric(const bsfit_curve *A, const bsfit_curve *B) {
  double a, b, x[2], y[2], worst = 0.0;
  bsfit_status st;
  size_t i;
  bsfit_curve_domain(A, &a, &b);
  for (i = 0; i < ENERGY_N; i++) {
    double t = a + (b - a) * (double)i / ENERGY_N;
    assert_int_equal(bsfit_curve_eval(A, t, x, &st), BSFIT_OK);
    assert_int_equal(bsfit_curve_eval(B, t, y, &st), BSFIT_OK);
    worst = fmax(worst, hypot(x[0] - y[0], x[1] - y[1]));
  }
  return worst;
}

static double energy(const bsfit_curve *c) {
  double e;
  bsfit_status st;
  assert_int_equal(bsfit_curve_bending_energy(c, ENERGY_N, &e, &st), BSFIT_OK);
  return e;
}

/* The energy of one box pass (order 1) whose distance to C is dev: bisection on delta. */
static double box_energy_at(const bsfit_curve *c, double dev) {
  double a, b, lo = 0.0, hi, e;
  bsfit_curve F;
  bsfit_status st;
  int i;
  bsfit_curve_domain(c, &a, &b);
  hi = 0.5 * (b - a);
  bsfit_curve_init(&F);
  for (i = 0; i < 18; i++) {
    double mid = 0.5 * (lo + hi), d;
    assert_int_equal(bsfit_filter_box_curve_delta(c, mid, &F, &st), BSFIT_OK);
    assert_int_equal(bsfit_curve_distance(&F, c, 8, &d, &st), BSFIT_OK);
    if (d <= dev) lo = mid;
    else hi = mid;
  }
  assert_true(lo > 0.0);
  assert_int_equal(bsfit_filter_box_curve_delta(c, lo, &F, &st), BSFIT_OK);
  e = energy(&F);
  bsfit_curve_free(&F);
  return e;
}

/* }==================================================================== */

/* {====================================================================
** Tests
** ===================================================================== */

static void check_section(enum shape s, double level, test_rng *rng) {
  bsfit_curve c, r;
  bsfit_smooth_opts o;
  bsfit_smooth_report rep;
  bsfit_status st;
  double tol = 4.0 * level * 2.0, d, eb;
  fitted_section(s, level * 2.0, rng, &c);
  memset(&o, 0, sizeof o);
  o.tol = tol;
  bsfit_curve_init(&r);
  assert_int_equal(bsfit_filter_smooth_curve(&c, &o, &r, &rep, &st), BSFIT_OK);
  assert_int_equal(r.degree, 3);
  assert_true(r.periodic);
  assert_true(rep.changed);
  assert_true(rep.max_deviation <= tol);
  d = hausdorff(&r, &c);
  /* the polylines cut the curves' wiggles by (chord^2 curvature / 8): far below 1% of tol */
  assert_true(d <= 1.01 * tol);
  assert_true(fabs(d - rep.max_deviation) <= 0.05 * tol);
  if (rep.bound <= tol) assert_true(parametric(&r, &c) <= rep.bound + 1e-12);
  assert_true(energy(&r) < energy(&c));
  eb = box_energy_at(&c, rep.max_deviation);
  /* at the lowest noise the deviation is mostly the shape's own shrinking, and every
  ** kernel order gives the same energy to about 1e-4: there, no more than the box's */
  assert_true(energy(&r) < (level < 0.002 ? 1.001 : 1.0) * eb);
  bsfit_curve_free(&c);
  bsfit_curve_free(&r);
}

/* Given noisy sections of three shapes at three noise levels, two seeds each, when
** smoothed to four times the noise, then cubic, within tol, smoother than a box pass. */
static void test_noisy_sections(void **state) {
  static const double levels[3] = {0.001, 0.003, 0.01};
  test_rng rng = {0x736d6f6f7468};
  int s, l, seed;
  (void)state;
  for (s = ELLIPSE; s <= AIRFOIL; s++)
    for (l = 0; l < 3; l++)
      for (seed = 0; seed < 2; seed++) check_section((enum shape)s, levels[l], &rng);
}

/* Given a smooth section (no noise) and a tol far below anything a filter moves, then the
** curve comes back as it was (unchanged, reported so), or at most that far. */
static void test_smooth_curve_small_tol(void **state) {
  test_rng rng = {0x736d616c6c};
  int s;
  (void)state;
  for (s = ELLIPSE; s <= AIRFOIL; s++) {
    bsfit_curve c, r;
    bsfit_smooth_opts o;
    bsfit_smooth_report rep;
    bsfit_status st;
    fitted_section((enum shape)s, 0.0, &rng, &c);
    memset(&o, 0, sizeof o);
    o.tol = 1e-6;
    bsfit_curve_init(&r);
    assert_int_equal(bsfit_filter_smooth_curve(&c, &o, &r, &rep, &st), BSFIT_OK);
    assert_true(rep.max_deviation <= o.tol);
    assert_true(hausdorff(&r, &c) <= 1.01 * o.tol + 1e-9);
    assert_float_equal(energy(&r), energy(&c), 0.01 * energy(&c));
    bsfit_curve_free(&c);
    bsfit_curve_free(&r);
  }
}

static void test_bad_input(void **state) {
  test_rng rng = {0x626164};
  bsfit_curve c, r;
  bsfit_smooth_opts o;
  bsfit_smooth_report rep;
  bsfit_status st;
  size_t i;
  (void)state;
  fitted_section(STAR, 0.01, &rng, &c);
  bsfit_curve_init(&r);
  memset(&o, 0, sizeof o);
  expect_error(bsfit_filter_smooth_curve(&c, &o, &r, NULL, &st), BSFIT_EINVAL, &st); /* tol 0 */
  o.tol = -1.0;
  expect_error(bsfit_filter_smooth_curve(&c, &o, &r, NULL, &st), BSFIT_EINVAL, &st);
  o.tol = NAN;
  expect_error(bsfit_filter_smooth_curve(&c, &o, &r, NULL, &st), BSFIT_ENONFINITE, &st);
  o.tol = INFINITY;
  expect_error(bsfit_filter_smooth_curve(&c, &o, &r, NULL, &st), BSFIT_ENONFINITE, &st);
  o.tol = 0.1;
  o.order = -1;
  expect_error(bsfit_filter_smooth_curve(&c, &o, &r, NULL, &st), BSFIT_EINVAL, &st);
  assert_non_null(strstr(st.msg, "order"));
  o.order = 0;
  o.degree = -2;
  expect_error(bsfit_filter_smooth_curve(&c, &o, &r, NULL, &st), BSFIT_EDEGREE, &st);
  o.degree = 0;
  expect_error(bsfit_filter_smooth_curve(NULL, &o, &r, NULL, &st), BSFIT_EINVAL, &st);
  expect_error(bsfit_filter_smooth_curve(&c, &o, NULL, NULL, &st), BSFIT_EINVAL, &st);
  /* a tol no filter can meet: nothing changed, and the report says so */
  o.tol = 1e-14;
  assert_int_equal(bsfit_filter_smooth_curve(&c, &o, &r, &rep, &st), BSFIT_OK);
  assert_false(rep.changed);
  assert_int_equal(rep.order, 0);
  assert_int_equal(r.n, c.n);
  for (i = 0; i < c.n * 2; i++) assert_float_equal(r.ctrl[i], c.ctrl[i], 0.0);
  bsfit_curve_free(&c);
  bsfit_curve_free(&r);
}

/* }==================================================================== */

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_noisy_sections),
      cmocka_unit_test(test_smooth_curve_small_tol),
      cmocka_unit_test(test_bad_input),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
