/*
** bench_eval.c
** Batch evaluation speed (bsfit_curve_eval_many): points per second for a cubic curve
** with 2000 control points at 10^6 parameters, sorted and shuffled, in 2D and 3D, and
** for a cubic NURBS; then closest points (bsfit_curve_closest_many) of 10^3, 10^4 and 10^5
** points near a closed cubic with 2000 and with 100 spans. Best of several runs, timed with
** clock_gettime(CLOCK_MONOTONIC).
** Usage: bench_eval [runs]   (default 5). Build in Release (the default build type).
*/
#define _POSIX_C_SOURCE 199309L /* clock_gettime under -std=c11 */

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <time.h>

#include "bsfit.h"

#define NCTRL 2000
#define NPAR 1000000

static double now(void) {
  struct timespec ts;
  clock_gettime(CLOCK_MONOTONIC, &ts);
  return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

/* deterministic pseudo-random numbers in [0, 1) */
static double next_uniform(unsigned long long *s) {
  *s = *s * 6364136223846793005ULL + 1442695040888963407ULL;
  return (double)(*s >> 11) * (1.0 / 9007199254740992.0);
}

static int build(bsfit_curve *c, int dim, int rational) {
  static double ctrl[NCTRL * 3], w[NCTRL];
  unsigned long long s = 42;
  size_t i;
  bsfit_status st;
  for (i = 0; i < (size_t)NCTRL * (size_t)dim; i++) ctrl[i] = next_uniform(&s);
  for (i = 0; i < NCTRL; i++) w[i] = 0.5 + next_uniform(&s);
  if (bsfit_curve_new(c, 3, dim, NCTRL, NULL, ctrl, rational ? w : NULL, 0, NULL, &st)) {
    fprintf(stderr, "bench_eval: %s\n", st.msg);
    return 1;
  }
  return 0;
}

static double best_rate(const bsfit_curve *c, const double *u, double *out, int runs) {
  double best = 0.0;
  int r;
  for (r = 0; r < runs; r++) {
    double t0 = now(), dt;
    if (bsfit_curve_eval_many(c, u, NPAR, out, NULL) != BSFIT_OK) return -1.0;
    dt = now() - t0;
    if (dt > 0 && NPAR / dt > best) best = NPAR / dt;
  }
  return best;
}

/* A closed cubic through a wobbly circle of N control points (N spans), and m points
** moved off it by up to 0.05 in x and in y (a section's data around its fitted curve). */
static int closed_section(bsfit_curve *c, size_t N, double *pts, size_t m) {
  static double ctrl[NCTRL * 2];
  unsigned long long s = 11;
  double a, b, xy[2];
  size_t i;
  bsfit_status st;
  for (i = 0; i < N; i++) {
    double t = 6.283185307179586 * (double)i / (double)N, r = 1.0 + 0.2 * sin(5.0 * t);
    ctrl[2 * i] = r * cos(t);
    ctrl[2 * i + 1] = r * sin(t);
  }
  if (bsfit_curve_new_periodic(c, 3, 2, N, NULL, ctrl, NULL, NULL, &st)) {
    fprintf(stderr, "bench_eval: %s\n", st.msg);
    return 1;
  }
  bsfit_curve_domain(c, &a, &b);
  for (i = 0; i < m; i++) {
    if (bsfit_curve_eval(c, a + (b - a) * next_uniform(&s), xy, &st)) return 1;
    pts[2 * i] = xy[0] + 0.1 * (next_uniform(&s) - 0.5);
    pts[2 * i + 1] = xy[1] + 0.1 * (next_uniform(&s) - 0.5);
  }
  return 0;
}

/* best time in seconds of closest_many for the first m of pts */
static double best_closest(const bsfit_curve *c, const double *pts, size_t m, double *u,
                           double *d, int runs) {
  double best = INFINITY;
  int r;
  for (r = 0; r < runs; r++) {
    double t0 = now(), dt;
    if (bsfit_curve_closest_many(c, pts, m, u, d, NULL, NULL) != BSFIT_OK) return -1.0;
    dt = now() - t0;
    if (dt < best) best = dt;
  }
  return best;
}

static int bench_closest(int runs, double *sink) {
  static const size_t spans[] = {2000, 100}, ms[] = {1000, 10000, 100000};
  double *pts = malloc(100000 * 2 * sizeof(double)), *u = malloc(100000 * sizeof(double));
  double *d = malloc(100000 * sizeof(double));
  size_t j, k;
  if (!pts || !u || !d) return 1;
  printf("closest_many, closed cubic 2D, points up to 0.05 off it in x and y, best of %d runs\n",
         runs);
  for (j = 0; j < 2; j++) {
    bsfit_curve c;
    bsfit_curve_init(&c);
    if (closed_section(&c, spans[j], pts, 100000)) return 1;
    for (k = 0; k < 3; k++) {
      double t = best_closest(&c, pts, ms[k], u, d, runs);
      if (t < 0) return 1;
      *sink += d[0];
      printf("%5zu spans  %6zu points  %9.3f ms  %7.2f us/point\n", spans[j], ms[k], 1e3 * t,
             1e6 * t / (double)ms[k]);
    }
    bsfit_curve_free(&c);
  }
  free(pts);
  free(u);
  free(d);
  return 0;
}

int main(int argc, char **argv) {
  (void)bsfit_blas_single_thread(); /* see bsfit_fit.h: idle BLAS workers spin */
  int runs = argc > 1 ? atoi(argv[1]) : 5, dim, rational;
  double *sorted = malloc(NPAR * sizeof(double)), *shuffled = malloc(NPAR * sizeof(double));
  double *out = malloc((size_t)NPAR * 3 * sizeof(double)), sink = 0.0;
  unsigned long long s = 7;
  size_t i;
  if (!sorted || !shuffled || !out || runs < 1) return 1;
  for (i = 0; i < NPAR; i++) sorted[i] = shuffled[i] = (double)i / (double)(NPAR - 1);
  for (i = NPAR - 1; i > 0; i--) { /* Fisher-Yates */
    size_t j = (size_t)(next_uniform(&s) * (double)(i + 1));
    double t = shuffled[i];
    shuffled[i] = shuffled[j];
    shuffled[j] = t;
  }
  printf("bsfit %s, cubic curve, %d control points, %d parameters, best of %d runs\n",
         bsfit_version(), NCTRL, NPAR, runs);
  for (rational = 0; rational <= 1; rational++)
    for (dim = 2; dim <= 3; dim++) {
      bsfit_curve c;
      double rs, ru;
      bsfit_curve_init(&c);
      if (build(&c, dim, rational)) return 1;
      rs = best_rate(&c, sorted, out, runs);
      sink += out[0];
      ru = best_rate(&c, shuffled, out, runs);
      sink += out[0];
      printf("%-10s %dD  sorted %7.1f Mpoints/s   shuffled %7.1f Mpoints/s\n",
             rational ? "NURBS" : "B-spline", dim, rs / 1e6, ru / 1e6);
      bsfit_curve_free(&c);
    }
  if (bench_closest(runs, &sink)) return 1;
  free(sorted);
  free(shuffled);
  free(out);
  return sink == 12345.678; /* keeps the results alive */
}
