/*
** surface_skin_approx.c
** Skinning within a tolerance: the sections (normalised and aligned) are replaced by
** periodic cubics on one uniform knot vector, each the least-squares fit of its section at
** the section's own parameters, with the smallest count N that keeps every section within
** tol. The sections then are compatible as they are, and the surface has N + 3 columns,
** however many knots the sections had (sections of exact mesh loops carry a C0 knot at
** every mesh edge: hundreds each, and their union thousands).
** The distance checked is parametric, |C_k(t) - A_k(t)|, which bounds the distance between
** the curves from above: at the fit's samples (8 per span of the fit and 4 per span of the
** section, so no span of either goes unseen) and at 32 points per span of
** the fit and 16 per span of the section.
*/
#include "skin_internal.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#define APPROX_DEGREE 3

static int cmp_double(const void *x, const void *y) {
  double a = *(const double *)x, b = *(const double *)y;
  return (a > b) - (a < b);
}

/* The sample parameters of section c: M uniform ones and 4 inside each of its spans,
** sorted, into u; returns their count (at most M + 4 N_c). */
static size_t sample_params(const bsfit_curve *c, size_t M, double *u) {
  size_t p = (size_t)c->degree, N = c->n - p, i, j, m = 0;
  for (i = 0; i < M; i++) u[m++] = ((double)i + 0.5) / (double)M;
  for (i = 0; i < N; i++) {
    double a = c->knots[p + i], b = c->knots[p + i + 1];
    if (!(b > a)) continue;
    for (j = 0; j < 4; j++) u[m++] = a + (b - a) * ((double)j + 0.5) / 4.0;
  }
  qsort(u, m, sizeof(double), cmp_double);
  return m;
}

typedef struct approx {
  bsfit_fitter *f;
  double *u, *pts, *knots;
} approx;

/* The largest |c(t) - f(t)| at 32 points in each span of f and 16 in each span of c: the
** fit's residuals at its own samples would miss peaks between them. */
static double deviation(const bsfit_curve *c, const bsfit_curve *f) {
  const bsfit_curve *g[2] = {f, c};
  double worst = 0, x[3], y[3];
  int s, j, per[2] = {32, 16};
  for (s = 0; s < 2; s++) {
    size_t p = (size_t)g[s]->degree, N = g[s]->n - p, i;
    for (i = 0; i < N; i++) {
      double a = g[s]->knots[p + i], b = g[s]->knots[p + i + 1];
      for (j = 0; b > a && j < per[s]; j++) {
        double t = a + (b - a) * (j + 0.5) / per[s];
        bsfit__curve_eval_unchecked(c, t, x);
        bsfit__curve_eval_unchecked(f, t, y);
        worst = fmax(worst, sqrt((x[0] - y[0]) * (x[0] - y[0]) + (x[1] - y[1]) * (x[1] - y[1]) +
                                 (x[2] - y[2]) * (x[2] - y[2])));
      }
    }
  }
  return worst;
}

/* Fits section c with N uniform knots into out; *dev: the largest parametric distance. */
static bsfit_err fit_one(approx *ap, const bsfit_curve *c, size_t N, bsfit_curve *out,
                         double *dev, bsfit_status *st) {
  bsfit_fit_opts o;
  bsfit_fit_report r;
  size_t i, m = sample_params(c, 8 * N, ap->u);
  bsfit_err e;
  for (i = 0; i <= N; i++) ap->knots[i] = (double)i / (double)N;
  bsfit_fit_opts_init(&o);
  o.degree = APPROX_DEGREE;
  o.count = N;
  o.periodic = 1;
  o.knots = ap->knots;
  o.nknots = N + 1;
  o.solver = BSFIT_SOLVER_AUTO;
  if ((e = bsfit_fitter_configure(ap->f, &o, st)) != BSFIT_OK) return e;
  for (i = 0; i < m; i++) bsfit__curve_eval_unchecked(c, ap->u[i], ap->pts + i * 3);
  e = bsfit_fitter_fit(ap->f, ap->pts, m, 3, ap->u, NULL, out, &r, NULL, st);
  *dev = e == BSFIT_OK ? fmax(r.max, deviation(c, out)) : HUGE_VAL;
  return e;
}

/* Whether every section fits within tol with N knots; *dev: the largest deviation. With
** keep, the fits replace the sections. */
static bsfit_err try_count(approx *ap, bsfit_curve *w, size_t K, size_t N, double tol, int keep,
                           int *ok, double *dev, const bsfit_allocator *a, bsfit_status *st) {
  size_t k;
  bsfit_curve out;
  bsfit_err e = BSFIT_OK;
  *ok = 1;
  *dev = 0;
  bsfit_curve_init(&out);
  for (k = 0; k < K && e == BSFIT_OK && (*ok || keep); k++) {
    double d;
    if (bsfit__interrupted(a)) e = bsfit__fail(st, BSFIT_EINTR, "skinning interrupted");
    if (e == BSFIT_OK) e = fit_one(ap, &w[k], N, &out, &d, st);
    if (e != BSFIT_OK) break;
    *dev = d > *dev ? d : *dev;
    *ok &= d <= tol;
    if (keep) bsfit_curve_move(&out, &w[k]), bsfit_curve_init(&out);
  }
  bsfit_curve_free(&out);
  return e;
}

/* The smallest N in [lo, hi] that passes (doubling, then bisection); 0 when hi fails. */
static bsfit_err search_count(approx *ap, bsfit_curve *w, size_t K, size_t lo, size_t hi,
                              double tol, size_t *best, const bsfit_allocator *a,
                              bsfit_status *st) {
  size_t fail = lo - 1, N = lo;
  double dev;
  int ok = 0;
  bsfit_err e;
  *best = 0;
  for (;;) { /* doubling: fail < N, N passes or N == hi */
    if ((e = try_count(ap, w, K, N, tol, 0, &ok, &dev, a, st)) != BSFIT_OK) return e;
    if (ok || N == hi) break;
    fail = N;
    N = 2 * N < hi ? 2 * N : hi;
  }
  if (!ok) return BSFIT_OK;
  while (N - fail > 1) { /* bisection: fail fails, N passes */
    size_t mid = fail + (N - fail) / 2;
    if ((e = try_count(ap, w, K, mid, tol, 0, &ok, &dev, a, st)) != BSFIT_OK) return e;
    if (ok) N = mid;
    else fail = mid;
  }
  *best = N;
  return BSFIT_OK;
}

bsfit_err bsfit__skin_approximate(bsfit_curve *w, size_t K, double tol, size_t *count,
                                  double *dev, const bsfit_allocator *a, bsfit_status *st) {
  size_t k, Nmax = 0, hi, lo = 2 * APPROX_DEGREE + 2, N, cap;
  approx ap;
  bsfit_fit_opts o;
  int ok;
  bsfit_err e;
  *count = 0;
  *dev = 0;
  for (k = 0; k < K; k++) {
    size_t Nk = w[k].n - (size_t)w[k].degree;
    Nmax = Nk > Nmax ? Nk : Nmax;
  }
  hi = 4 * Nmax > lo ? 4 * Nmax : lo; /* beyond that the exact union is the lighter one */
  memset(&ap, 0, sizeof ap);
  cap = 8 * hi + 4 * Nmax;
  ap.u = bsfit__alloc(a, cap * 4 * sizeof(double) + (hi + 1) * sizeof(double));
  if (ap.u == NULL) return bsfit__fail(st, BSFIT_ENOMEM, "out of memory for %zu samples", cap);
  ap.pts = ap.u + cap;
  ap.knots = ap.pts + 3 * cap;
  bsfit_fit_opts_init(&o);
  o.degree = APPROX_DEGREE, o.count = lo, o.periodic = 1;
  e = bsfit_fitter_new(&ap.f, &o, a, st);
  if (e == BSFIT_OK) e = search_count(&ap, w, K, lo, hi, tol, &N, a, st);
  if (e == BSFIT_OK && N > 0) e = try_count(&ap, w, K, N, tol, 1, &ok, dev, a, st);
  if (e == BSFIT_OK) *count = N;
  bsfit_fitter_free(ap.f);
  bsfit__free(a, ap.u, cap * 4 * sizeof(double) + (hi + 1) * sizeof(double));
  return e;
}
