/*
** bench_surface.c
** Points per second of grid evaluation: a bicubic 3D surface on a 100 x 100 control
** net sampled on a 1000 x 1000 grid, by bsfit_surface_sample_grid (spans and v basis
** cached, one net contraction per row) and, for comparison, by bsfit_surface_eval at
** every point. Usage: bench_surface [grid_side] [net_side] [rational 0|1]
*/
#define _POSIX_C_SOURCE 200809L

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <time.h>

#include "bsfit.h"

static double now(void) {
  struct timespec t;
  clock_gettime(CLOCK_MONOTONIC, &t);
  return (double)t.tv_sec + 1e-9 * (double)t.tv_nsec;
}

int main(int argc, char **argv) {
  (void)bsfit_blas_single_thread(); /* see bsfit_fit.h: idle BLAS workers spin */
  size_t k = argc > 1 ? (size_t)atol(argv[1]) : 1000;
  size_t n = argc > 2 ? (size_t)atol(argv[2]) : 100;
  int rational = argc > 3 ? atoi(argv[3]) : 0;
  double *ctrl = malloc(n * n * 3 * sizeof(double)), *w = malloc(n * n * sizeof(double));
  double *grid = malloc(k * k * 3 * sizeof(double)), t0, t1, t2, check = 0, maxdiff = 0;
  bsfit_surface s;
  bsfit_status st;
  size_t i, j;
  if (!ctrl || !w || !grid || k < 2 || n < 4) return 1;
  for (i = 0; i < n; i++)
    for (j = 0; j < n; j++) {
      double *P = ctrl + (i * n + j) * 3;
      P[0] = (double)i;
      P[1] = (double)j;
      P[2] = sin(0.3 * (double)i) * cos(0.2 * (double)j);
      w[i * n + j] = 1.0 + 0.5 * sin((double)(i + j));
    }
  bsfit_surface_init(&s);
  if (bsfit_surface_new(&s, 3, 3, 3, n, n, NULL, NULL, ctrl, rational ? w : NULL, NULL, &st)) {
    fprintf(stderr, "bench_surface: %s\n", st.msg);
    return 1;
  }
  t0 = now();
  if (bsfit_surface_sample_grid(&s, k, k, grid, &st) != BSFIT_OK) {
    fprintf(stderr, "bench_surface: %s\n", st.msg);
    return 1;
  }
  t1 = now();
  /* the same points one by one, and the largest disagreement between the two paths */
  for (i = 0; i < k; i++)
    for (j = 0; j < k; j++) {
      double P[3], u = (double)i / (double)(k - 1), v = (double)j / (double)(k - 1);
      const double *G = grid + (i * k + j) * 3;
      bsfit_surface_eval(&s, u, v, P, NULL);
      maxdiff = fmax(maxdiff, fabs(P[0] - G[0]) + fabs(P[1] - G[1]) + fabs(P[2] - G[2]));
      check += P[2];
    }
  t2 = now();
  printf("bicubic %s, %zux%zu net, %zux%zu grid\n", rational ? "NURBS" : "B-spline", n, n, k, k);
  printf("  sample_grid: %.3f s, %.1f Mpoints/s\n", t1 - t0, (double)(k * k) / (t1 - t0) / 1e6);
  printf("  eval loop  : %.3f s, %.1f Mpoints/s\n", t2 - t1, (double)(k * k) / (t2 - t1) / 1e6);
  printf("  max |grid - eval| = %.3g (checksum %.6f)\n", maxdiff, check);
  bsfit_surface_free(&s);
  free(ctrl);
  free(w);
  free(grid);
  return 0;
}
