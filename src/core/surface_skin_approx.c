/*
** surface_skin_approx.c
** Skinning within a tolerance: the sections (normalised and aligned) are replaced by
** periodic cubics on one knot vector, each the weighted least-squares fit of its section,
** with the smallest count N found that keeps every section within tol. The knots are
** uniform, but for the corners (C0 knots) at least half the sections share once lined up:
** those are C0 knots of every fit, so a prism or a wing's trailing edge keeps its edge
** instead of needing thousands of knots to round it within tol. The sections then are
** compatible as they are, and the surface has N + 3 columns, however many knots the
** sections had (sections of exact mesh loops carry a C0 knot at every mesh edge: hundreds
** each, and their union thousands).
** Each section is fitted at chord-length parameters, piece by piece between the shared
** corners (which keep their parameters, so they line up across the sections), not at its
** own: `auto` gives every piece of a mesh loop its own parameter speed, and no cubic
** follows those jumps (at equal parameters the fits stayed 1e-3 of the size away at any
** count, though a few micrometres away as curves). The distance checked is the Hausdorff
** distance between a section and its cubic (surface_skin_distance.c).
** The search keeps one running count: each section is tried at it and raises it (doubling,
** then bisection) when it fails; the sections fitted at a smaller count are fitted again
** until all pass at one count: about two fits per section, not two per count tried.
*/
#include "skin_internal.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#define APPROX_DEGREE 3
#define SPAN_SAMPLES 4 /* samples per span of a section (its knot, then inside) */
#define FIT_SAMPLES 8  /* samples per span of a fit, uniform in chord length */
#define SLIVER 1e-9    /* a span this short (fraction of the period) is a sliver */
#define LAWSON_ROUNDS 2 /* reweighted refits of a fit that misses tol by less than half */

static int cmp_double(const void *x, const void *y) {
  double a = *(const double *)x, b = *(const double *)y;
  return (a > b) - (a < b);
}

typedef struct approx {
  bsfit_fitter *f;
  double *knots;
  double *corners; /* the C0 knots most sections share: kept in every fit */
  size_t ncorners;
  /* one section's samples: base (its spans and the corners), then with the uniform ones
  ** merged in: parameters on the section t, chord-length parameters s, points, weights */
  double *bt, *bs, *bp, *t, *s, *pts, *wt;
  double *tau; /* this section's parameters that go to the shared corners */
  double *res; /* the fit's residuals at the samples */
  size_t nb, m;
} approx;

/* Cyclic distance between parameters of the period [0, 1). */
static double cyclic(double x, double y) {
  double d = fabs(x - y);
  return d < 1.0 - d ? d : 1.0 - d;
}

/* The period knots of a fit of about N spans into t: the uniform knots i / N farther than
** half a span from the shared corners (so no sliver), and each corner three times (a C0
** knot: the fit may turn there as the sections do), however near each other or the seam
** (a wing's trailing edge has two corners 1e-4 of the period apart, both needed) but for
** one a sliver from the seam (0 is always a knot). Returns the count of control points. */
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
    if (copies == 3 && cyclic(ap->corners[j], 0.0) <= SLIVER) continue;
    while (at > 0 && t[at - 1] > ap->corners[j]) at--;
    memmove(t + at + copies, t + at, (n - at) * sizeof(double));
    for (r = 0; r < copies; r++) t[at + r] = ap->corners[j];
    n += copies;
  }
  t[n] = 1.0;
  return n;
}

/* {====================================================================
** Samples at chord-length parameters
** ===================================================================== */

static double dist3(const double *x, const double *y) {
  return sqrt((x[0] - y[0]) * (x[0] - y[0]) + (x[1] - y[1]) * (x[1] - y[1]) +
              (x[2] - y[2]) * (x[2] - y[2]));
}

/* The piece ends of section c (ap->tau, increasing, in its parameters): for each shared
** corner kappa_j, the section's own C0 knot nearest to it (within half the gap to the
** neighbouring shared corners and BSFIT__SKIN_MERGE_APPROX), else kappa_j itself. Its
** corner then maps onto kappa_j even where the merge did not line it up. */
static void piece_ends(approx *ap, const bsfit_curve *c) {
  size_t p = (size_t)c->degree, N = c->n - p, i = 0, j, r;
  const double *k = ap->corners, *t = c->knots + p;
  for (j = 0; j < ap->ncorners; j++) {
    double w = BSFIT__SKIN_MERGE_APPROX, best = k[j], d = HUGE_VAL;
    if (j > 0) w = fmin(w, 0.5 * (k[j] - k[j - 1]));
    if (j + 1 < ap->ncorners) w = fmin(w, 0.5 * (k[j + 1] - k[j]));
    while (i < N && t[i] < k[j] - w) i++;
    for (r = i; k[j] > 0 && r < N && t[r] <= k[j] + w; r++) {
      size_t run = 1;
      while (r + run < N && t[r + run] == t[r]) run++;
      if (run >= p && fabs(t[r] - k[j]) < d) d = fabs(t[r] - k[j]), best = t[r];
      r += run - 1;
    }
    ap->tau[j] = j > 0 && !(best > ap->tau[j - 1]) ? k[j] : best;
    if (j > 0 && !(ap->tau[j] > ap->tau[j - 1])) ap->tau[j] = ap->tau[j - 1]; /* merged away */
  }
}

/* The base parameters of section c: SPAN_SAMPLES in each span (its knot first), 0 and the
** piece ends, sorted, repeats dropped, into ap->bt; their points into ap->bp. */
static void base_params(approx *ap, const bsfit_curve *c) {
  size_t p = (size_t)c->degree, N = c->n - p, i, j, m = 0;
  piece_ends(ap, c);
  ap->bt[m++] = 0.0;
  for (i = 0; i < ap->ncorners; i++) ap->bt[m++] = ap->tau[i];
  for (i = 0; i < N; i++) {
    double lo = c->knots[p + i], hi = c->knots[p + i + 1];
    for (j = 0; hi > lo && j < SPAN_SAMPLES; j++)
      ap->bt[m++] = lo + (hi - lo) * (double)j / SPAN_SAMPLES;
  }
  qsort(ap->bt, m, sizeof(double), cmp_double);
  for (i = 0, j = 0; i < m; i++)
    if ((j == 0 || ap->bt[i] != ap->bt[j - 1]) && ap->bt[i] >= 0.0 && ap->bt[i] < 1.0)
      ap->bt[j++] = ap->bt[i];
  ap->nb = j;
  for (i = 0; i < j; i++) bsfit__curve_eval_unchecked(c, ap->bt[i], ap->bp + 3 * i);
}

/* ap->bs: the base samples' chord length, mapped affinely onto each piece between the
** piece ends (tau_j onto the shared corner kappa_j; 0 and 1 stay), so the corners of every
** section land on the same parameters. */
static void chord_params(approx *ap) {
  size_t i, nb = ap->nb, j = 0, start = 0;
  double *L = ap->bs, total;
  for (i = 1, L[0] = 0; i < nb; i++) L[i] = L[i - 1] + dist3(ap->bp + 3 * i, ap->bp + 3 * i - 3);
  total = L[nb - 1] + dist3(ap->bp, ap->bp + 3 * (nb - 1));
  while (start < nb) { /* the piece from sample start (a piece end or 0) to the next end */
    double ta = ap->bt[start], tb = 1.0, sa = 0.0, sb = 1.0, La = L[start], Lb = total;
    size_t end = start + 1;
    while (j < ap->ncorners && ap->tau[j] <= ta) sa = ap->corners[j++];
    if (j < ap->ncorners) tb = ap->tau[j], sb = ap->corners[j];
    while (end < nb && ap->bt[end] < tb) end++;
    if (end < nb) Lb = L[end];
    for (i = start; i < end; i++)
      L[i] = Lb > La ? sa + (sb - sa) * (L[i] - La) / (Lb - La) : ap->bt[i];
    start = end;
  }
}

/* The section's parameter at chord-length parameter x (the base pairs interpolated
** linearly; *i: the base sample at or before x, advanced from its value). */
static double param_at(const approx *ap, double x, size_t *i) {
  size_t nb = ap->nb;
  double t1, s1;
  while (*i + 1 < nb && ap->bs[*i + 1] <= x) (*i)++;
  t1 = *i + 1 < nb ? ap->bt[*i + 1] : 1.0;
  s1 = *i + 1 < nb ? ap->bs[*i + 1] : 1.0;
  return s1 > ap->bs[*i] ? ap->bt[*i] + (t1 - ap->bt[*i]) * (x - ap->bs[*i]) / (s1 - ap->bs[*i])
                         : ap->bt[*i];
}

/* The samples of section c for a fit of N spans: the base ones merged with FIT_SAMPLES N
** uniform in chord length, into ap->t, s, pts, m; weights: the chord length each stands
** for (the fit then weighs the curve, not where samples crowd). */
static void fit_samples(approx *ap, const bsfit_curve *c, size_t N) {
  size_t M = FIT_SAMPLES * N, q = 0, i = 0, k = 0, m = 0;
  while (i < ap->nb || q < M) {
    double x = ((double)q + 0.5) / (double)M;
    if (q < M && (i == ap->nb || x < ap->bs[i])) {
      ap->s[m] = x;
      ap->t[m] = param_at(ap, x, &k);
      bsfit__curve_eval_unchecked(c, ap->t[m], ap->pts + 3 * m);
      q++;
    } else {
      ap->s[m] = ap->bs[i], ap->t[m] = ap->bt[i];
      memcpy(ap->pts + 3 * m, ap->bp + 3 * i, 3 * sizeof(double));
      i++;
    }
    m++;
  }
  for (i = 0; i < m; i++) {
    double lo = i > 0 ? ap->s[i - 1] : ap->s[m - 1] - 1.0;
    double hi = i + 1 < m ? ap->s[i + 1] : ap->s[0] + 1.0;
    ap->wt[i] = fmax(0.5 * (hi - lo), 1e-3 / (double)m);
  }
  ap->m = m;
}

/* }==================================================================== */

/* {====================================================================
** The count
** ===================================================================== */

/* Lawson's step towards the minimax fit: each weight scaled by its sample's residual (the
** largest residuals gain, the rest give up), floored and renormalised. */
static void lawson_weights(approx *ap) {
  size_t i;
  double rmax = 0, sum = 0;
  for (i = 0; i < ap->m; i++) rmax = fmax(rmax, ap->res[i]);
  if (!(rmax > 0)) return;
  for (i = 0; i < ap->m; i++) sum += ap->wt[i] *= ap->res[i] / rmax + 1e-3;
  for (i = 0; i < ap->m; i++) ap->wt[i] = fmax(ap->wt[i] / sum, 1e-9 / (double)ap->m);
}

/* Fits section c (its base samples ready) with N uniform knots into out; *dev: the
** Hausdorff distance between them (above tol: at least that). A least-squares fit misses
** tol where the minimax one would not (a polygon's vertices out, its chords in: 2/3 of the
** sagitta against 1/2), so a fit that misses by less than half of tol is refitted with
** Lawson's weights, LAWSON_ROUNDS times at most, before the count is raised. */
static bsfit_err fit_one(approx *ap, const bsfit_curve *c, size_t N, double tol,
                         bsfit_curve *out, double *dev, const bsfit_allocator *a,
                         bsfit_status *st) {
  bsfit_fit_opts o;
  size_t n = fit_knots(ap, N, ap->knots);
  int round;
  bsfit_err e;
  *dev = HUGE_VAL;
  if (bsfit__interrupted(a)) return bsfit__fail(st, BSFIT_EINTR, "skinning interrupted");
  fit_samples(ap, c, N);
  bsfit_fit_opts_init(&o);
  o.degree = APPROX_DEGREE;
  o.count = n;
  o.periodic = 1;
  o.knots = ap->knots;
  o.nknots = n + 1;
  o.solver = BSFIT_SOLVER_AUTO;
  if ((e = bsfit_fitter_configure(ap->f, &o, st)) != BSFIT_OK) return e;
  for (round = 0; e == BSFIT_OK && round <= LAWSON_ROUNDS && *dev > tol; round++) {
    if (round > 0 && !(*dev < 1.5 * tol)) break;
    if (round > 0) lawson_weights(ap);
    e = bsfit_fitter_fit(ap->f, ap->pts, ap->m, 3, ap->s, ap->wt, out, NULL, ap->res, st);
    if (e == BSFIT_OK)
      e = bsfit__skin_distance(c, out, ap->t, ap->s, ap->pts, ap->m, tol, dev, a, st);
  }
  return e;
}

/* The fits so far: fit[k] made with made[k] spans (0: none yet), dev[k] its distance. */
typedef struct fits {
  bsfit_curve *fit, tmp;
  size_t *made;
  double *dev;
} fits;

/* Tries section k at N: on success (*ok) its fit is kept. */
static bsfit_err try_section(approx *ap, const bsfit_curve *c, size_t k, size_t N, double tol,
                             fits *F, int *ok, const bsfit_allocator *a, bsfit_status *st) {
  double d;
  bsfit_err e = fit_one(ap, c, N, tol, &F->tmp, &d, a, st);
  *ok = e == BSFIT_OK && d <= tol;
  if (*ok) {
    bsfit_curve_move(&F->tmp, &F->fit[k]);
    bsfit_curve_init(&F->tmp);
    F->made[k] = N, F->dev[k] = d;
  }
  return e;
}

/* Section k fails at *N: the count raised (doubling, then bisection) to the smallest found
** that it passes, its fit kept; *N = 0 when it fails at hi too. */
static bsfit_err raise_count(approx *ap, const bsfit_curve *c, size_t k, size_t *N, size_t hi,
                             double tol, fits *F, const bsfit_allocator *a, bsfit_status *st) {
  size_t fail = *N, pass = 0, n = *N;
  int ok = 0;
  bsfit_err e = BSFIT_OK;
  while (!ok && n < hi && e == BSFIT_OK) {
    n = 2 * n < hi ? 2 * n : hi;
    e = try_section(ap, c, k, n, tol, F, &ok, a, st);
    if (!ok) fail = n;
  }
  pass = ok ? n : 0;
  while (e == BSFIT_OK && pass > 0 && pass - fail > 1) {
    size_t mid = fail + (pass - fail) / 2;
    e = try_section(ap, c, k, mid, tol, F, &ok, a, st);
    if (ok) pass = mid;
    else fail = mid;
  }
  if (pass > 0) F->made[k] = pass; /* the fit kept is the one made at pass */
  *N = pass;
  return e;
}

/* The count every section passes at: each section tried at the running count, which it
** raises when it fails, until K in a row pass at one count (*N = 0: none up to hi). */
static bsfit_err search_count(approx *ap, const bsfit_curve *c, size_t K, size_t lo, size_t hi,
                              double tol, fits *F, size_t *N, const bsfit_allocator *a,
                              bsfit_status *st) {
  size_t k = 0, clean = 0;
  int ok;
  bsfit_err e = BSFIT_OK;
  *N = lo;
  while (clean < K && e == BSFIT_OK) {
    if (F->made[k] != *N) {
      base_params(ap, &c[k]);
      chord_params(ap);
      e = try_section(ap, &c[k], k, *N, tol, F, &ok, a, st);
      if (e == BSFIT_OK && !ok) {
        e = raise_count(ap, &c[k], k, N, hi, tol, F, a, st);
        if (*N == 0) return e;
        clean = 0;
      }
    }
    clean++;
    k = (k + 1) % K;
  }
  return e;
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

/* The search on copies of the sections: slivers dropped (by at most *moved), corners lined
** up by a wider merge (an exact reparametrisation: the same curves); *N: the count found
** (0: none), F the fits, each within tol - *moved of its copy. */
static bsfit_err approximate_copies(approx *ap, bsfit_curve *c, size_t K, double tol, size_t lo,
                                    size_t hi, fits *F, size_t *N, double *moved,
                                    const bsfit_allocator *a, bsfit_status *st) {
  size_t k;
  bsfit_err e = BSFIT_OK;
  for (k = 0; k < K && e == BSFIT_OK; k++)
    e = bsfit__skin_drop_slivers(&c[k], 1e-3 * tol, moved, a, st);
  if (e == BSFIT_OK) e = bsfit__skin_merge_corners(c, K, merge_tol(c, K), a, st);
  if (e != BSFIT_OK) return e;
  ap->ncorners = bsfit__skin_shared_corners(c, K, ap->corners);
  return search_count(ap, c, K, lo, hi, tol - *moved, F, N, a, st);
}

/* The scratch: the sections' copies, the fits, the samples; NULL on ENOMEM. */
typedef struct scratch {
  bsfit_curve *c;
  double *buf;
  size_t K, bytes, doubles;
} scratch;

static bsfit_err scratch_new(scratch *S, approx *ap, fits *F, const bsfit_curve *w, size_t K,
                             size_t Nmax, size_t hi, const bsfit_allocator *a,
                             bsfit_status *st) {
  size_t capb = (SPAN_SAMPLES + 2) * Nmax + 2, cap = capb + FIT_SAMPLES * hi + 1;
  size_t kcap = hi + 1 + 3 * K * Nmax, k; /* a fit's knots, and every section's corners */
  bsfit_err e = BSFIT_OK;
  S->K = K;
  S->doubles = 6 * capb + 7 * cap + 2 * kcap;
  S->bytes = K * (2 * sizeof(bsfit_curve) + sizeof(size_t) + sizeof(double));
  S->buf = bsfit__alloc(a, S->doubles * sizeof(double));
  S->c = bsfit__alloc(a, S->bytes);
  if (S->c != NULL) { /* scratch_free frees these whatever fails next */
    F->fit = S->c + K;
    F->dev = (double *)(F->fit + K);
    F->made = (size_t *)(F->dev + K);
    bsfit_curve_init(&F->tmp);
    for (k = 0; k < K; k++)
      bsfit_curve_init(&S->c[k]), bsfit_curve_init(&F->fit[k]), F->made[k] = 0;
  }
  if (S->buf == NULL || S->c == NULL)
    return bsfit__fail(st, BSFIT_ENOMEM, "out of memory for samples");
  for (k = 0; e == BSFIT_OK && k < K; k++) e = bsfit_curve_copy(&w[k], &S->c[k], a, st);
  ap->bt = S->buf, ap->bs = ap->bt + capb, ap->bp = ap->bs + capb;
  ap->t = ap->bp + 3 * capb, ap->s = ap->t + cap;
  ap->pts = ap->s + cap, ap->wt = ap->pts + 3 * cap;
  ap->knots = ap->wt + cap, ap->corners = ap->knots + kcap, ap->tau = ap->corners + kcap;
  ap->res = ap->tau + capb;
  return e;
}

static void scratch_free(scratch *S, fits *F, const bsfit_allocator *a) {
  size_t k;
  for (k = 0; S->c != NULL && k < S->K; k++)
    bsfit_curve_free(&S->c[k]), bsfit_curve_free(&F->fit[k]);
  if (S->c != NULL) bsfit_curve_free(&F->tmp);
  bsfit__free(a, S->c, S->bytes);
  bsfit__free(a, S->buf, S->doubles * sizeof(double));
}

bsfit_err bsfit__skin_approximate(bsfit_curve *w, size_t K, double tol, size_t *count,
                                  double *dev, const bsfit_allocator *a, bsfit_status *st) {
  size_t k, Nmax = 0, hi, lo = 2 * APPROX_DEGREE + 2, N = 0;
  double moved = 0;
  approx ap;
  fits F;
  scratch S;
  bsfit_fit_opts o;
  bsfit_err e;
  *count = 0;
  *dev = 0;
  for (k = 0; k < K; k++) {
    size_t Nk = w[k].n - (size_t)w[k].degree;
    Nmax = Nk > Nmax ? Nk : Nmax;
  }
  hi = 4 * Nmax > lo ? 4 * Nmax : lo; /* beyond that the exact union is the lighter one */
  memset(&ap, 0, sizeof ap);
  e = scratch_new(&S, &ap, &F, w, K, Nmax, hi, a, st);
  if (e == BSFIT_OK) {
    bsfit_fit_opts_init(&o);
    o.degree = APPROX_DEGREE, o.count = lo, o.periodic = 1;
    e = bsfit_fitter_new(&ap.f, &o, a, st);
  }
  if (e == BSFIT_OK) e = approximate_copies(&ap, S.c, K, tol, lo, hi, &F, &N, &moved, a, st);
  for (k = 0; e == BSFIT_OK && N > 0 && k < K; k++) {
    *dev = fmax(*dev, F.dev[k] + moved);
    bsfit_curve_move(&F.fit[k], &w[k]);
    bsfit_curve_init(&F.fit[k]);
  }
  if (e == BSFIT_OK && N > 0) *count = w[0].n - (size_t)w[0].degree; /* N and the corners */
  scratch_free(&S, &F, a);
  bsfit_fitter_free(ap.f);
  return e;
}
