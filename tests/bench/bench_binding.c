/*
** bench_binding.c
** The C side of the binding's cost: bsfit_curve_sample of 10^6 points and a weighted
** open fit of 10^6 points with 2000 control points (report and residuals, as F:fit
** returns them), on the same data as
** tests/bench/bench_binding.lua builds, so the two outputs compare line by line.
*/
#define _POSIX_C_SOURCE 200809L /* clock_gettime */

#include "bsfit.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <time.h>

static double now(void) {
  struct timespec ts;
  clock_gettime(CLOCK_MONOTONIC, &ts);
  return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

int main(void) {
  (void)bsfit_blas_single_thread(); /* see bsfit_fit.h: idle BLAS workers spin */
  const size_t m = 1000000, n = 2000;
  double *xy = malloc(m * 2 * sizeof(double)), *u = malloc(m * sizeof(double));
  double *w = malloc(m * sizeof(double)), *out = malloc(m * 2 * sizeof(double));
  double *res = malloc(m * sizeof(double)); /* F:fit returns the residuals too */
  double best_sample = 1e300, best_fit = 1e300;
  bsfit_fit_opts o;
  bsfit_fitter *f = NULL;
  bsfit_curve c;
  bsfit_fit_report rep;
  size_t i;
  int r;
  if (!xy || !u || !w || !out || !res) return 1;
  for (i = 0; i < m; i++) { /* the same section as bench_binding.lua */
    double t = (double)i / (double)(m - 1);
    xy[2 * i] = cos(6.0 * t) + 0.001 * sin(977.0 * t);
    xy[2 * i + 1] = sin(5.0 * t);
    u[i] = t;
    w[i] = 1.0 + 0.5 * sin(31.0 * t);
  }
  bsfit_fit_opts_init(&o);
  o.degree = 3;
  o.count = n;
  if (bsfit_fitter_new(&f, &o, NULL, NULL) != BSFIT_OK) return 1;
  bsfit_curve_init(&c);
  free(res);
  free(out);
  /* each call gets fresh memory for its results, as the Lua calls do */
  for (r = 0; r < 5; r++) {
    double t0 = now();
    res = malloc(m * sizeof(double));
    if (!res || bsfit_fitter_fit(f, xy, m, 2, u, w, &c, &rep, res, NULL) != BSFIT_OK) return 1;
    best_fit = fmin(best_fit, now() - t0);
    free(res);
    t0 = now();
    out = malloc(m * 2 * sizeof(double));
    if (!out || bsfit_curve_sample(&c, m, out, NULL, NULL) != BSFIT_OK) return 1;
    best_sample = fmin(best_sample, now() - t0);
    free(out);
  }
  printf("C   : sample 10^6 points %8.2f ms   fit 10^6 points, 2000 control points %8.2f ms\n",
         best_sample * 1e3, best_fit * 1e3);
  bsfit_curve_free(&c);
  bsfit_fitter_free(f);
  free(xy);
  free(u);
  free(w);
  return 0;
}
