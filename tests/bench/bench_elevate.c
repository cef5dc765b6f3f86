/*
** bench_elevate.c
** Timing of degree elevation against the number of control points (10^4 .. 10^6):
** a clamped cubic with random knots raised by 1 and by 3, polynomial and rational.
** Elevation runs one degree at a time by blossoms (curve_elevate.c), O(p^3) per control
** point and degree; linear time shows as a constant time per control point (about 290 ns
** for +1 on the shared build machine). Times are process CPU time, the best of a few
** runs.
** Usage: bench_elevate [max_n]   (default 1000000)
*/
#define _POSIX_C_SOURCE 199309L /* clock_gettime under -std=c11 */
#include <stdio.h>
#include <stdlib.h>
#include <time.h>

#include "bsfit.h"

static double cpu_s(void) {
  struct timespec ts;
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
  return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

/* a clamped cubic with n control points on random knots; rational: weights in [0.5, 2] */
static int make_curve(size_t n, int rational, bsfit_curve *c) {
  double *U = malloc((n + 4) * sizeof(double)), *P = malloc(2 * n * sizeof(double));
  double *W = malloc(n * sizeof(double)), t = 0.0;
  size_t i;
  bsfit_status st;
  int ok;
  if (!U || !P || !W) return 0;
  srand(7);
  for (i = 0; i < n + 4; i++) {
    if (i > 3 && i <= n) t += 0.5 + (double)rand() / RAND_MAX;
    U[i] = t;
  }
  for (i = 0; i < n; i++) {
    P[2 * i] = (double)i + (double)rand() / RAND_MAX;
    P[2 * i + 1] = (double)rand() / RAND_MAX;
    W[i] = 0.5 + 1.5 * (double)rand() / RAND_MAX;
  }
  bsfit_curve_init(c);
  ok = bsfit_curve_new(c, 3, 2, n, U, P, rational ? W : NULL, 0, NULL, &st) == BSFIT_OK;
  free(U);
  free(P);
  free(W);
  return ok;
}

/* best of 3 runs of elevating c by t, in milliseconds; -1 on error */
static double best_ms(const bsfit_curve *c, int t) {
  double best = 1e30;
  int r;
  for (r = 0; r < 3; r++) {
    bsfit_curve out;
    bsfit_status st;
    double t0 = cpu_s(), dt;
    bsfit_curve_init(&out);
    if (bsfit_curve_elevate(c, t, &out, &st) != BSFIT_OK) {
      fprintf(stderr, "bench_elevate: %s\n", st.msg);
      return -1.0;
    }
    dt = cpu_s() - t0;
    if (dt < best) best = dt;
    bsfit_curve_free(&out);
  }
  return best * 1e3;
}

int main(int argc, char **argv) {
  size_t maxn = argc > 1 ? (size_t)strtoul(argv[1], NULL, 10) : 1000000, n;
  printf("%10s %12s %12s %14s %14s\n", "n", "+1 ms", "+3 ms", "+1 rat. ms", "ns/pt (+1)");
  for (n = 10000; n <= maxn; n *= 10) {
    bsfit_curve c, cr;
    double t1, t3, tr;
    if (!make_curve(n, 0, &c) || !make_curve(n, 1, &cr)) return 1;
    t1 = best_ms(&c, 1);
    t3 = best_ms(&c, 3);
    tr = best_ms(&cr, 1);
    printf("%10zu %12.3f %12.3f %14.3f %14.1f\n", n, t1, t3, tr, t1 * 1e6 / (double)n);
    bsfit_curve_free(&c);
    bsfit_curve_free(&cr);
  }
  return 0;
}
