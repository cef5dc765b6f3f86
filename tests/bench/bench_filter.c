/*
** bench_filter.c
** Timing of box filtering against the number of control points (10^4 .. 10^6): the
** moving average of a uniform open curve and of a closed one, and the exact filter
** of a clamped curve. Each figure is the best of a few runs; linear time shows as a
** constant time per control point. Times are process CPU time (the machine may be
** shared: wall-clock time then also counts the waits for a core); the last column is
** the wall-clock time of the uniform case.
** Usage: bench_filter [max_n]   (default 1000000)
*/
#define _POSIX_C_SOURCE 199309L /* clock_gettime under -std=c11 */
#include <stdio.h>
#include <stdlib.h>
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

int main(int argc, char **argv) {
  (void)bsfit_blas_single_thread(); /* see bsfit_fit.h: idle BLAS workers spin */
  size_t max_n = argc > 1 ? (size_t)strtoul(argv[1], NULL, 10) : 1000000, n;
  printf("%10s %12s %12s %12s %14s %14s\n", "n", "uniform ms", "closed ms", "exact ms",
         "ns/pt uniform", "uniform wall");
  for (n = 10000; n <= max_n; n *= 10) {
    bsfit_curve u, z, cl;
    double tu, tz, te, wall;
    if (make_curve(n, 0, &u) || make_curve(n, 1, &z) || make_curve(n, 2, &cl)) return 1;
    tu = best_ms(&u, ma5, 5, &wall);
    tz = best_ms(&z, ma5, 5, NULL);
    te = best_ms(&cl, exact, 3, NULL);
    printf("%10zu %12.3f %12.3f %12.3f %14.1f %14.3f\n", n, tu, tz, te, tu * 1e6 / (double)n,
           wall);
    bsfit_curve_free(&u);
    bsfit_curve_free(&z);
    bsfit_curve_free(&cl);
  }
  return 0;
}
