/*
** surface_skin_approx.c
** Skinning within a tolerance: the sections (normalised and aligned) are replaced by
** periodic cubics on one knot vector, each the least-squares fit of its section at the
** section's own parameters, with the smallest count N that keeps every section within
** tol. The knots are uniform, but for the corners (C0 knots) at least half the sections
** share once lined up: those are C0 knots of every fit, so a prism or a wing's trailing
** edge keeps its edge instead of needing thousands of knots to round it within tol. The sections then are compatible as they are, and the surface has N + 3 columns,
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
  double *corners; /* the C0 knots most sections share: kept in every fit */
  size_t ncorners;
} approx;

/* Cyclic distance between parameters of the period [0, 1). */
static double cyclic(double x, double y) {
  double d = fabs(x - y);
  return d < 1.0 - d ? d : 1.0 - d;
}

/* The period knots of a fit of about N spans into t: the uniform knots i / N farther than
** half a span from the shared corners (so no sliver), and each corner three times (a C0
** knot: the fit may turn there as the sections do), other corners within a quarter span of
** the seam left out (0 is always a knot). Returns the count of control points. */
static size_t fit_knots(const approx *ap, size_t N, double *t) {
  size_t i, j = 0, n = 0;
  double h = 1.0 / (double)N;
  for (i = 0; i < N; i++) {
    double x = (double)i * h;
    while (j < ap->ncorners && ap->corners[j] < x - 0.5 * h) j++;
    if (i > 0 && j < ap->ncorners && cyclic(ap->corners[j], x) <= 0.5 * h) continue;
    if (i > 0 && ap->ncorners > 0 && cyclic(ap->corners[ap->ncorners - 1], x) <= 0.5 * h)
      continue;
    t[n++] = x;
  }
  for (j = 0; j < ap->ncorners; j++) { /* merge the corners in, three times each */
    size_t at = n, r, copies = ap->corners[j] == 0.0 ? 2 : 3; /* 0 is there already */
    if (copies == 3 && cyclic(ap->corners[j], 0.0) <= 0.25 * h) continue;
    while (at > 0 && t[at - 1] > ap->corners[j]) at--;
    memmove(t + at + copies, t + at, (n - at) * sizeof(double));
    for (r = 0; r < copies; r++) t[at + r] = ap->corners[j];
    n += copies;
  }
  t[n] = 1.0;
  return n;
}

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
  size_t i, m = sample_params(c, 8 * N, ap->u), n = fit_knots(ap, N, ap->knots);
  bsfit_err e;
  bsfit_fit_opts_init(&o);
  o.degree = APPROX_DEGREE;
  o.count = n;
  o.periodic = 1;
  o.knots = ap->knots;
  o.nknots = n + 1;
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

/* The merge tolerance for the cubics: BSFIT__SKIN_MERGE_APPROX, but at most a quarter of the
** gap between the closest two corners of any one section (the loops of a mesh have a corner
** per facet, 1% of the period apart: a wider merge would pair a facet's corner with its
** neighbour's in the next section). */
static double merge_tol(const bsfit_curve *w, size_t K) {
  double gap = 1.0;
  size_t k, i, j;
  for (k = 0; k < K; k++) {
    size_t p = (size_t)w[k].degree, N = w[k].n - p;
    const double *t = w[k].knots + p;
    double first = -1, prev = -1;
    for (i = 0; i < N; i = j) {
      for (j = i + 1; j < N && t[j] == t[i]; j++) continue;
      if (j - i < p) continue;
      if (prev >= 0 && t[i] - prev < gap) gap = t[i] - prev;
      if (first < 0) first = t[i];
      prev = t[i];
    }
    if (first >= 0 && prev > first && 1.0 + first - prev < gap) gap = 1.0 + first - prev;
  }
  return fmax(BSFIT__SKIN_MERGE, fmin(BSFIT__SKIN_MERGE_APPROX, 0.25 * gap));
}

/* The search on copies of the sections (corners lined up by a wider merge); *N: the count
** found (0: none), then the copies hold the fits. */
static bsfit_err approximate_copies(approx *ap, bsfit_curve *c, size_t K, double tol, size_t lo,
                                    size_t hi, size_t *N, double *dev,
                                    const bsfit_allocator *a, bsfit_status *st) {
  int ok;
  bsfit_err e = bsfit__skin_merge_corners(c, K, merge_tol(c, K), a, st);
  if (e != BSFIT_OK) return e;
  ap->ncorners = bsfit__skin_shared_corners(c, K, ap->corners);
  e = search_count(ap, c, K, lo, hi, tol, N, a, st);
  if (e == BSFIT_OK && *N > 0) e = try_count(ap, c, K, *N, tol, 1, &ok, dev, a, st);
  return e;
}

bsfit_err bsfit__skin_approximate(bsfit_curve *w, size_t K, double tol, size_t *count,
                                  double *dev, const bsfit_allocator *a, bsfit_status *st) {
  size_t k, Nmax = 0, hi, lo = 2 * APPROX_DEGREE + 2, N = 0, cap, kcap;
  approx ap;
  bsfit_fit_opts o;
  bsfit_curve *c;
  bsfit_err e = BSFIT_OK;
  *count = 0;
  *dev = 0;
  for (k = 0; k < K; k++) {
    size_t Nk = w[k].n - (size_t)w[k].degree;
    Nmax = Nk > Nmax ? Nk : Nmax;
  }
  hi = 4 * Nmax > lo ? 4 * Nmax : lo; /* beyond that the exact union is the lighter one */
  memset(&ap, 0, sizeof ap);
  cap = 8 * hi + 4 * Nmax;
  kcap = hi + 1 + 3 * K * Nmax; /* a fit's knots, and room for every section's corners */
  ap.u = bsfit__alloc(a, (cap * 4 + 2 * kcap) * sizeof(double));
  c = bsfit__alloc(a, K * sizeof *c);
  if (ap.u == NULL || c == NULL) e = bsfit__fail(st, BSFIT_ENOMEM, "out of memory for samples");
  for (k = 0; c != NULL && k < K; k++) bsfit_curve_init(&c[k]);
  for (k = 0; e == BSFIT_OK && k < K; k++) e = bsfit_curve_copy(&w[k], &c[k], a, st);
  if (e == BSFIT_OK) {
    ap.pts = ap.u + cap;
    ap.knots = ap.pts + 3 * cap;
    ap.corners = ap.knots + kcap;
    bsfit_fit_opts_init(&o);
    o.degree = APPROX_DEGREE, o.count = lo, o.periodic = 1;
    e = bsfit_fitter_new(&ap.f, &o, a, st);
  }
  if (e == BSFIT_OK) e = approximate_copies(&ap, c, K, tol, lo, hi, &N, dev, a, st);
  for (k = 0; e == BSFIT_OK && N > 0 && k < K; k++) bsfit_curve_move(&c[k], &w[k]);
  if (e == BSFIT_OK && N > 0) *count = w[0].n - (size_t)w[0].degree; /* N and the corners */
  for (k = 0; c != NULL && k < K; k++) bsfit_curve_free(&c[k]);
  bsfit_fitter_free(ap.f);
  bsfit__free(a, c, K * sizeof *c);
  bsfit__free(a, ap.u, (cap * 4 + 2 * kcap) * sizeof(double));
  return e;
}
