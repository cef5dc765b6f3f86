/*
** bench_filter.c
** Timing of box filtering against the number of control points (10^4 .. 10^6): the
** moving average of a uniform open curve and of a closed one, and the exact filter
** of a clamped curve, and the kernel filter of order 3 (three moving averages of 5
** points) of the uniform curve. Each figure is the best of a few runs; linear time shows
** as a constant time per control point. Times are process CPU time (the machine may be
** shared: wall-clock time then also counts the waits for a core); the last column is
** the wall-clock time of the uniform case.
** Then smoothing to a tolerance (bsfit_filter_smooth_curve) of fitted sections: noisy
** ellipses (1% noise) of 1000 points fitted by closed cubics of 50..400 control points,
** tol twice the noise, kernel order searched and given; then the searched run's order,
** widths tried, measured distance and certified bound (as fractions of tol).
** Usage: bench_filter [max_n]   (default 1000000)
*/
#define _POSIX_C_SOURCE 199309L /* clock_gettime under -std=c11 */
#include <stdio.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "bsfit.h"

static double clock_s(clockid_t id) {
  struct timespec ts;
  clock_gettime(id, &ts);
  return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

typedef bsfit_err (*filter_fn)(const bsfit_curve *c, bsfit_curve *out, bsfit_status *st);

static bsfit_err ma5(const bsfit_curve *c, bsfit_curve *out, bsfit_status *st) {
  return bsfit_filter_box_curve(c, 5, out, st);
}

static bsfit_err kernel3(const bsfit_curve *c, bsfit_curve *out, bsfit_status *st) {
  return bsfit_filter_kernel_curve(c, 3, 5, out, st);
}

static bsfit_err exact(const bsfit_curve *c, bsfit_curve *out, bsfit_status *st) {
  double a, b;
  bsfit_curve_domain(c, &a, &b);
  /* about 3.7 knot spans, not a multiple of the spacing */
  return bsfit_filter_box_curve_delta(c, 1.85 * (b - a) / (double)c->n, out, st);
}

/* best of `runs` timings (CPU, and wall in *wall), in milliseconds; -1 on error */
static double best_ms(const bsfit_curve *c, filter_fn fn, int runs, double *wall) {
  double best = 1e30, best_wall = 1e30;
  int i;
  for (i = 0; i < runs; i++) {
    bsfit_curve out;
    bsfit_status st;
    double t0, t1, w0, w1;
    bsfit_curve_init(&out);
    w0 = clock_s(CLOCK_MONOTONIC);
    t0 = clock_s(CLOCK_PROCESS_CPUTIME_ID);
    if (fn(c, &out, &st) != BSFIT_OK) {
      fprintf(stderr, "bench_filter: %s\n", st.msg);
      return -1;
    }
    t1 = clock_s(CLOCK_PROCESS_CPUTIME_ID);
    w1 = clock_s(CLOCK_MONOTONIC);
    bsfit_curve_free(&out);
    if (t1 - t0 < best) best = t1 - t0;
    if (w1 - w0 < best_wall) best_wall = w1 - w0;
  }
  if (wall) *wall = best_wall * 1e3;
  return best * 1e3;
}

static int make_curve(size_t n, int kind, bsfit_curve *c) {
  double *P = malloc(n * 2 * sizeof(double)), *U = malloc((n + 4) * sizeof(double));
  bsfit_status st;
  size_t i;
  int e = 1;
  if (P == NULL || U == NULL) goto done;
  for (i = 0; i < 2 * n; i++) P[i] = (double)((i * 2654435761u) % 1000) / 1000.0;
  bsfit_curve_init(c);
  if (kind == 0) {
    if (bsfit_knots_uniform(3, n, 0.0, 1.0, U, &st) != BSFIT_OK) goto done;
    e = bsfit_curve_new(c, 3, 2, n, U, P, NULL, 0, NULL, &st);
  } else if (kind == 1) {
    e = bsfit_curve_new_periodic(c, 3, 2, n, NULL, P, NULL, NULL, &st);
  } else {
    e = bsfit_curve_new(c, 3, 2, n, NULL, P, NULL, 0, NULL, &st);
  }
  if (e != BSFIT_OK) fprintf(stderr, "bench_filter: %s\n", st.msg);
done:
  free(P);
  free(U);
  return e;
}

/* A closed cubic of N control points fitted to 1000 points of an ellipse (axes 2 and 1)
** with deterministic noise of amplitude 0.02 (1% of the size). */
static int fitted_section(size_t N, bsfit_curve *c) {
  enum { M = 1000 };
  double pts[2 * M], u[M];
  bsfit_fit_opts o;
  bsfit_fitter *f = NULL;
  bsfit_status st;
  size_t i;
  int e;
  for (i = 0; i < M; i++) {
    double t = 6.283185307179586 * (double)i / M;
    double nz = 0.02 * ((double)((i * 2654435761u) % 1000) / 500.0 - 1.0);
    pts[2 * i] = (2.0 + nz) * cos(t);
    pts[2 * i + 1] = (1.0 + nz) * sin(t);
  }
  bsfit_fit_opts_init(&o);
  o.count = N;
  o.periodic = 1;
  bsfit_curve_init(c);
  e = bsfit_params(pts, M, 2, BSFIT_PARAM_CHORD, 1, u, &st);
  if (e == BSFIT_OK) e = bsfit_fitter_new(&f, &o, NULL, &st);
  if (e == BSFIT_OK) e = bsfit_fitter_fit(f, pts, M, 2, u, NULL, c, NULL, NULL, &st);
  if (e != BSFIT_OK) fprintf(stderr, "bench_filter: %s\n", st.msg);
  bsfit_fitter_free(f);
  return e;
}

static int smooth_order; /* 0: searched */

static bsfit_err smooth(const bsfit_curve *c, bsfit_curve *out, bsfit_status *st) {
  bsfit_smooth_opts o;
  memset(&o, 0, sizeof o);
  o.tol = 0.04;
  o.order = smooth_order;
  return bsfit_filter_smooth_curve(c, &o, out, NULL, st);
}

/* The search's outcome on c (searched orders): order, widths tried, distance / tol. */
static void smooth_outcome(const bsfit_curve *c, int *order, int *evals, double *dev,
                           double *bound) {
  bsfit_smooth_opts o;
  bsfit_smooth_report r;
  bsfit_curve out;
  bsfit_status st;
  memset(&o, 0, sizeof o);
  o.tol = 0.04;
  bsfit_curve_init(&out);
  if (bsfit_filter_smooth_curve(c, &o, &out, &r, &st) != BSFIT_OK) {
    fprintf(stderr, "bench_filter: %s\n", st.msg);
    memset(&r, 0, sizeof r);
  }
  *order = r.order;
  *evals = r.evaluations;
  *dev = r.max_deviation / o.tol;
  *bound = r.bound / o.tol;
  bsfit_curve_free(&out);
}

static int bench_smooth(void) {
  size_t N;
  printf("\nsmooth to tol 0.04 (noise 0.02) of a fitted closed cubic section\n");
  printf("%10s %14s %14s %14s %6s %6s %10s %10s\n", "control", "searched ms", "order 2 ms",
         "order 3 ms", "order", "evals", "dist/tol", "bound/tol");
  for (N = 50; N <= 400; N *= 2) {
    bsfit_curve c;
    double t0, t2, t3, dev, bound;
    int order, evals;
    if (fitted_section(N, &c) != BSFIT_OK) return 1;
    smooth_order = 0;
    t0 = best_ms(&c, smooth, 5, NULL);
    smooth_order = 2;
    t2 = best_ms(&c, smooth, 5, NULL);
    smooth_order = 3;
    t3 = best_ms(&c, smooth, 5, NULL);
    smooth_outcome(&c, &order, &evals, &dev, &bound);
    printf("%10zu %14.3f %14.3f %14.3f %6d %6d %10.3f %10.3f\n", N, t0, t2, t3, order, evals, dev,
           bound);
    bsfit_curve_free(&c);
  }
  return 0;
}

int main(int argc, char **argv) {
  (void)bsfit_blas_single_thread(); /* see bsfit_fit.h: idle BLAS workers spin */
  size_t max_n = argc > 1 ? (size_t)strtoul(argv[1], NULL, 10) : 1000000, n;
  printf("%10s %12s %12s %12s %14s %14s %12s %14s\n", "n", "uniform ms", "closed ms",
         "exact ms", "ns/pt uniform", "uniform wall", "kernel3 ms", "ns/pt kernel3");
  for (n = 10000; n <= max_n; n *= 10) {
    bsfit_curve u, z, cl;
    double tu, tz, te, tk, wall;
    if (make_curve(n, 0, &u) || make_curve(n, 1, &z) || make_curve(n, 2, &cl)) return 1;
    tu = best_ms(&u, ma5, 5, &wall);
    tz = best_ms(&z, ma5, 5, NULL);
    te = best_ms(&cl, exact, 3, NULL);
    tk = best_ms(&u, kernel3, 5, NULL);
    printf("%10zu %12.3f %12.3f %12.3f %14.1f %14.3f %12.3f %14.1f\n", n, tu, tz, te,
           tu * 1e6 / (double)n, wall, tk, tk * 1e6 / (double)n);
    bsfit_curve_free(&u);
    bsfit_curve_free(&z);
    bsfit_curve_free(&cl);
  }
  return bench_smooth();
}
