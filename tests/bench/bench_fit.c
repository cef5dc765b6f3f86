/*
** bench_fit.c
** Timing of the weighted least-squares fitter: 10^6 2D points / 2000 cubic control
** points (open and periodic, assembly + solve + residuals), 1000 points / 100 control
** points with a reused fitter, the same with the QR solver, the growth with m, and the peak
** memory of the big fit.
** Times are CPU time of the process (best of `repeats`), so a loaded machine inflates them
** less than wall time would. Usage: bench_fit [repeats]   (short by design)
*/
#define _POSIX_C_SOURCE 200809L
#include "bsfit.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <sys/resource.h>
#include <time.h>

typedef struct peak_alloc {
  size_t live, peak;
} peak_alloc;

static void *peak_fn(void *ud, void *p, size_t osz, size_t nsz) {
  peak_alloc *a = ud;
  if (nsz == 0) {
    if (p) a->live -= osz;
    free(p);
    return NULL;
  }
  p = realloc(p, nsz);
  if (p) {
    a->live += nsz - osz;
    if (a->live > a->peak) a->peak = a->live;
  }
  return p;
}

static double now(void) {
  struct timespec ts;
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts); /* CPU time: the machine is shared */
  return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

/* a noisy closed-ish curve with weights; params chord length (open or closed) */
static int make_data(size_t m, int closed, double *pts, double *u, double *w) {
  size_t k;
  unsigned s = 12345u;
  for (k = 0; k < m; k++) {
    double t = 6.283185307179586 * (double)k / (double)m, r = 1.0 + 0.3 * cos(5.0 * t);
    s = s * 1103515245u + 12345u;
    pts[2 * k] = 2.0 * r * cos(t) + 1e-3 * ((double)(s >> 16) / 65536.0 - 0.5);
    pts[2 * k + 1] = r * sin(t);
    w[k] = 0.5 + (double)(k % 7) / 7.0;
  }
  return bsfit_params(pts, m, 2, BSFIT_PARAM_CHORD, closed, u, NULL) == BSFIT_OK;
}

/* best time of `reps` fits (seconds); -1 on error */
static double time_fit(size_t m, size_t count, int periodic, bsfit_solver solver, int reps,
                       const bsfit_allocator *al, bsfit_fit_report *rep) {
  double *pts = malloc(2 * m * sizeof(double)), *u = malloc(m * sizeof(double));
  double *w = malloc(m * sizeof(double)), *res = malloc(m * sizeof(double)), best = 1e30;
  bsfit_fit_opts o;
  bsfit_fitter *f = NULL;
  bsfit_curve out;
  bsfit_status st;
  int i, batch = m <= 10000 ? 50 : 1;
  bsfit_curve_init(&out);
  if (!pts || !u || !w || !res || !make_data(m, periodic, pts, u, w)) best = -1;
  bsfit_fit_opts_init(&o);
  o.count = count;
  o.periodic = periodic;
  o.solver = solver;
  if (best > 0 && bsfit_fitter_new(&f, &o, al, &st) != BSFIT_OK) {
    fprintf(stderr, "fitter: %s\n", st.msg);
    best = -1;
  }
  /* small fits are timed in batches: one fit is too short for the process clock */
  for (i = 0; best > 0 && i < reps; i += batch) {
    double t0 = now(), t;
    int j;
    for (j = 0; j < batch && best > 0; j++)
      if (bsfit_fitter_fit(f, pts, m, 2, u, w, &out, rep, res, &st) != BSFIT_OK) {
        fprintf(stderr, "fit: %s\n", st.msg);
        best = -1;
      }
    t = (now() - t0) / batch;
    if (best > 0 && t < best) best = t;
  }
  bsfit_fitter_free(f);
  bsfit_curve_free(&out);
  free(pts), free(u), free(w), free(res);
  return best;
}

int main(int argc, char **argv) {
  (void)bsfit_blas_single_thread(); /* see bsfit_fit.h: idle BLAS workers spin */
  int reps = argc > 1 ? atoi(argv[1]) : 5;
  size_t m;
  double t_open, t_per, t_small, t;
  bsfit_fit_report rep;
  peak_alloc pa = {0, 0};
  bsfit_allocator al = {peak_fn, &pa, NULL};
  struct rusage ru;
  if (reps < 1) reps = 1;

  t_open = time_fit(1000000, 2000, 0, BSFIT_SOLVER_CHOLESKY, reps, &al, &rep);
  printf("open     m=1e6 n=2000 cubic weighted: %8.2f ms  (rms %.3g, max %.3g, rcond %.2g)\n",
         1e3 * t_open, rep.rms, rep.max, rep.rcond);
  t_per = time_fit(1000000, 2000, 1, BSFIT_SOLVER_CHOLESKY, reps, &al, &rep);
  printf("periodic m=1e6 N=2000 cubic weighted: %8.2f ms  (rms %.3g, max %.3g, rcond %.2g)"
         "  ratio %.2f\n", 1e3 * t_per, rep.rms, rep.max, rep.rcond, t_per / t_open);
  t_small = time_fit(1000, 100, 0, BSFIT_SOLVER_CHOLESKY, 200 * reps, NULL, &rep);
  printf("open     m=1e3 n=100 reused fitter:   %8.2f us per fit\n", 1e6 * t_small);
  t_small = time_fit(1000, 100, 0, BSFIT_SOLVER_CHOLESKY, 200 * reps, NULL, NULL);
  printf("open     m=1e3 n=100, no report:      %8.2f us per fit (no residual pass, no rcond)\n",
         1e6 * t_small);
  t_small = time_fit(1000, 100, 1, BSFIT_SOLVER_CHOLESKY, 200 * reps, NULL, &rep);
  printf("periodic m=1e3 N=100 reused fitter:   %8.2f us per fit\n", 1e6 * t_small);
  printf("QR solver (solver = BSFIT_SOLVER_QR), with the full report:\n");
  t = time_fit(1000000, 2000, 0, BSFIT_SOLVER_QR, reps, NULL, &rep);
  printf("  open     m=1e6 n=2000: %8.2f ms (%.2fx Cholesky)\n", 1e3 * t, t / t_open);
  t = time_fit(1000000, 2000, 1, BSFIT_SOLVER_QR, reps, NULL, &rep);
  printf("  periodic m=1e6 N=2000: %8.2f ms (%.2fx Cholesky)\n", 1e3 * t, t / t_per);
  t = time_fit(1000, 100, 0, BSFIT_SOLVER_QR, 200 * reps, NULL, &rep);
  printf("  open     m=1e3 n=100:  %8.2f us per fit\n", 1e6 * t);
  t = time_fit(1000, 100, 1, BSFIT_SOLVER_QR, 200 * reps, NULL, &rep);
  printf("  periodic m=1e3 N=100:  %8.2f us per fit\n", 1e6 * t);
  printf("growth (open, n=100, cubic):\n");
  for (m = 1000; m <= 1000000; m *= 10) {
    t = time_fit(m, 100, 0, BSFIT_SOLVER_CHOLESKY, m < 100000 ? 50 * reps : reps, NULL, &rep);
    printf("  m=%8zu  %10.3f ms  %6.2f ns/point\n", m, 1e3 * t, 1e9 * t / (double)m);
  }
  getrusage(RUSAGE_SELF, &ru);
  printf("memory: input of the 1e6 fit (points+params+weights) %.1f MB, residuals %.1f MB, "
         "library peak %.2f MB, process max RSS %.1f MB\n",
         32.0, 8.0, (double)pa.peak / 1e6, (double)ru.ru_maxrss / 1e3);
  return 0;
}
