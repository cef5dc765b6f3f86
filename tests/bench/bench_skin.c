/*
** bench_skin.c
** Time of skinning and of the exchange writers: K closed cubic sections of N control
** points each, either sharing their knots (uniform: the surface keeps N + 3 columns) or
** each with its own knots (independently fitted sections: the union of the knots makes
** up to K*N columns), skinned by bsfit_surface_skin, then written as STEP, IGES, OBJ
** (200 x 200 mesh) and, for the sections, STEP and DXF, into memory.
** Usage: bench_skin [K] [N]
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

/* K sections of a vase; own_knots: jittered period knots per section */
static int make_sections(bsfit_curve *C, size_t K, size_t N, int own_knots) {
  double *P = malloc(N * 3 * sizeof(double)), *t = malloc((N + 1) * sizeof(double));
  size_t k, i;
  if (!P || !t) return 1;
  srand(7);
  for (k = 0; k < K; k++) {
    double z = 10.0 * (double)k / (double)K, r = 5 + sin(z);
    for (i = 0; i <= N; i++)
      t[i] = (double)i +
             (own_knots && i > 0 && i < N ? 0.4 * (rand() / (double)RAND_MAX - 0.5) : 0);
    for (i = 0; i < N; i++) {
      double a = 2 * 3.141592653589793 * (double)i / (double)N;
      P[i * 3] = r * cos(a) * (1 + 0.1 * cos(3 * a));
      P[i * 3 + 1] = r * sin(a);
      P[i * 3 + 2] = z;
    }
    bsfit_curve_init(&C[k]);
    if (bsfit_curve_new_periodic(&C[k], 3, 3, N, t, P, NULL, NULL, NULL) != BSFIT_OK) return 1;
  }
  free(P);
  free(t);
  return 0;
}

static void run(size_t K, size_t N, int own_knots) {
  bsfit_curve *C = malloc(K * sizeof *C);
  const bsfit_curve **ptr = malloc(K * sizeof *ptr);
  bsfit_surface S;
  bsfit_status st;
  char *text;
  size_t len, k, total = 0;
  double t0, t1, t2, t3, t4, t5, t6;
  if (!C || !ptr || make_sections(C, K, N, own_knots)) exit(1);
  for (k = 0; k < K; k++) ptr[k] = &C[k];
  bsfit_surface_init(&S);
  t0 = now();
  if (bsfit_surface_skin(ptr, K, NULL, &S, NULL, NULL, &st) != BSFIT_OK) {
    fprintf(stderr, "bench_skin: %s\n", st.msg);
    exit(1);
  }
  t1 = now();
  bsfit_surface_to_step(&S, NULL, &text, &len, NULL, NULL), total += len, free(text);
  t2 = now();
  bsfit_surface_to_iges(&S, &text, &len, NULL, NULL), total += len, free(text);
  t3 = now();
  bsfit_surface_to_obj(&S, 200, 200, &text, &len, NULL, NULL), total += len, free(text);
  t4 = now();
  bsfit_curves_to_step(ptr, K, NULL, &text, &len, NULL, NULL), total += len, free(text);
  t5 = now();
  bsfit_curves_to_dxf(ptr, K, &text, &len, NULL, NULL), total += len, free(text);
  t6 = now();
  printf("%zu sections x %zu points, %s knots: surface %zu x %zu control points\n", K, N,
         own_knots ? "own" : "shared", S.nu, S.nv);
  printf("  skin %.2f ms | surface STEP %.2f ms, IGES %.2f ms, OBJ 200x200 %.2f ms | "
         "sections STEP %.2f ms, DXF %.2f ms (%zu bytes)\n",
         1e3 * (t1 - t0), 1e3 * (t2 - t1), 1e3 * (t3 - t2), 1e3 * (t4 - t3), 1e3 * (t5 - t4),
         1e3 * (t6 - t5), total);
  bsfit_surface_free(&S);
  for (k = 0; k < K; k++) bsfit_curve_free(&C[k]);
  free(C);
  free(ptr);
}

int main(int argc, char **argv) {
  size_t K = argc > 1 ? (size_t)atol(argv[1]) : 50;
  size_t N = argc > 2 ? (size_t)atol(argv[2]) : 64;
  (void)bsfit_blas_single_thread();
  if (K < 2 || N < 4) return 1;
  run(K, N, 0);
  run(K, N, 1);
  return 0;
}
