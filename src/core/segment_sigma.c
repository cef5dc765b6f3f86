/*
** segment_sigma.c
** The noise of a section of lines and arcs, read off the models' own residuals
** (bsfit_segment_sigma, bsfit_features.h): the first segmentation level whose pooled
** residual matches the level.
*/
#include "features_internal.h"

#include <math.h>
#include <string.h>

/* the first guess of bsfit_segment_sigma: how far samples lie off their neighbours'
** chord, normalised by the spread that noise alone gives it; its lower quartile over
** that of |N(0, 1)| (0.3186): corners and arcs only add to it, and it must not start
** high (a high start lets one model take everything) */
static double chord_sigma(const double *pts, size_t m, int closed, double *d) {
  size_t i, n = 0;
  for (i = closed ? 0 : 1; i < (closed ? m : m - 1); i++) {
    const double *a = pts + 2 * ((i + m - 1) % m), *q = pts + 2 * i, *b = pts + 2 * ((i + 1) % m);
    double dx = b[0] - a[0], dy = b[1] - a[1], l2 = dx * dx + dy * dy, t;
    if (!(l2 > 0)) continue;
    t = ((q[0] - a[0]) * dx + (q[1] - a[1]) * dy) / l2;
    d[n++] = fabs((q[0] - a[0]) * dy - (q[1] - a[1]) * dx) / sqrt(l2) /
             sqrt(1 + t * t + (1 - t) * (1 - t));
  }
  return n ? bsfit__select(d, n, n / 4) / 0.3186 : 0.0;
}

/* what a segmentation at one level shows: the pooled residual of its lines and arcs (sum
** of squares over degrees of freedom; -1 without any), the same from the lower quartile of
** their samples' distances (robust), the samples they hold */
typedef struct level {
  double pooled, robust;
  size_t held;
} level;

/* d: room for the samples of every piece (2 m) */
static level level_of(const double *pts, size_t m, const bsfit_piece *p, size_t np, double *d) {
  double rss = 0, dof = 0;
  level l = {-1.0, -1.0, 0};
  size_t i, j, n = 0;
  for (i = 0; i < np; i++) {
    double k = p[i].kind == BSFIT_PIECE_LINE ? 2 : 3;
    if (p[i].kind != BSFIT_PIECE_FREE) l.held += p[i].count;
    if (p[i].kind == BSFIT_PIECE_FREE || (double)p[i].count <= k) continue;
    rss += p[i].rms * p[i].rms * (double)p[i].count;
    dof += (double)p[i].count - k;
    for (j = 0; j < p[i].count && n < 2 * m; j++)
      d[n++] = bsfit__piece_dist(&p[i], pts + 2 * ((p[i].first + j) % m));
  }
  if (dof > 0) {
    l.pooled = sqrt(rss / dof);
    l.robust = bsfit__select(d, n, n / 4) / 0.3186 * sqrt((double)n / dof);
  }
  return l;
}

/* The levels rise by 10^(1/4) from s0 up to max_sigma (the last one max_sigma itself;
** and 5% of the size), by 10^(1/12) where the next step could match. Below the noise,
** runs stop short and their pooled residual exceeds the level they were cut at; at the
** noise the models are right and it matches: the first level whose pooled residual is at
** most 1.2 times the level gives the estimate (that residual). The window of levels that
** match is narrow on sparse sections (a side of 3 samples has one degree of freedom: its
** residual is far from steady; the level above already lets a short arc take a corner):
** steps of 10^(1/2), then 10^(1/4), stepped over it on 16 of the 390 sections of
** test_sharp_noisy; 10^(1/12) everywhere doubled the cost of a noisy 40-point section.
** The search weighs pieces by their parameters only (param_cost HUGE_VAL): weighed by
** their residuals too (tried), its estimates come lower and smooth shapes pass for lines
** and arcs (an ellipse at noise 1e-3 of its size as arcs, twice as far off as one smooth
** curve). */
#define LEVEL_STEP BSFIT_SEGMENT_SIGMA_STEP /* 10^(1/4) */
#define LEVEL_FINE 1.2115276586285884 /* 10^(1/12) */
/* A level matches only where its lines and arcs hold HELD_MATCH of the samples: below,
** its pooled residual is read off a minority of them (a D of 10 uneven samples per side at
** noise 1e-3 matched at 0.08 of its noise a line of 5 samples and 15 free ones, held 5 of
** 20; its line and arc, the same from 0.33 to 25 times the noise, were never reached: 24
** times the floor, 0.12 now). Three other draws of the sweep: with 0.5, +2 within the floor
** and none farther; 0.75: +5 and 2 farther (a keyhole of 4 uneven samples per side at
** 3e-3 from 3.5 to 14 times the floor); 0.9, what the pieces must hold to be used: +7 and
** 7 farther. */
#define HELD_MATCH 0.5

/* the search's scratch: the options, room for the pieces (twice) and for their samples'
** distances */
typedef struct level_scratch {
  bsfit_segment_opts *o;
  bsfit_piece *p, *q;
  double *d;
} level_scratch;

/* the same cover: as many pieces, each of the same kind on the same samples */
static int same_cover(const bsfit_piece *p, size_t np, const bsfit_piece *q, size_t nq) {
  size_t i;
  if (np != nq) return 0;
  for (i = 0; i < np; i++)
    if (p[i].kind != q[i].kind || p[i].first != q[i].first || p[i].count != q[i].count) return 0;
  return 1;
}

/* A level whose pooled residual matches it but not its robust one (more than 3 times it)
** matches when its lines and arcs hold 90% of the samples and the next level up makes the
** very same cover: the robust residual reads the lower quartile of the samples' distances,
** which on sides of 3 samples (one degree of freedom each: the middle one's distance twice
** its ends') falls on ends and reads a third of the noise (a star of 3 samples per side at
** noise 1e-4, its 8 lines' pooled residual the noise to 4%, matched no level: 29 times the
** floor). The check is kept for covers that change with the level: at low levels it refuses
** wrong covers whose residual happens to match (a filleted hexagon of 3 samples per side,
** a keyhole of 4: reading the quartile studentised lost them). */
static bsfit_err stable_match(const double *pts, size_t m, double s, size_t np, level_scratch *w,
                              int *match, const bsfit_allocator *a, bsfit_status *st) {
  size_t nq = 0;
  bsfit_err e;
  w->o->sigma = s * LEVEL_STEP;
  if ((e = bsfit_segment(pts, m, 2, w->o, w->q, 2 * m + 2, &nq, a, st)) != BSFIT_OK) return e;
  *match = same_cover(w->p, np, w->q, nq);
  return BSFIT_OK;
}

/* Segments at level s; *l what it shows, *match whether its pooled residual matches it */
static bsfit_err try_level(const double *pts, size_t m, double s, level_scratch *w, level *l,
                           int *match, const bsfit_allocator *a, bsfit_status *st) {
  size_t np = 0;
  bsfit_err e;
  w->o->sigma = s;
  if ((e = bsfit_segment(pts, m, 2, w->o, w->p, 2 * m + 2, &np, a, st)) != BSFIT_OK) return e;
  *l = level_of(pts, m, w->p, np, w->d);
  *match = l->pooled >= 0 && l->pooled <= 1.2 * s && l->pooled <= 3.0 * l->robust &&
           (double)l->held >= HELD_MATCH * (double)m;
  if (!*match && l->pooled >= 0 && l->pooled <= 1.2 * s && (double)l->held >= 0.9 * (double)m)
    return stable_match(pts, m, s, np, w, match, a, st);
  return BSFIT_OK;
}

/* the estimate of a level that matches: its pooled residual; 0 for exact data */
static double estimate_of(const level *l, double size) {
  return l->pooled <= 1e-10 * size ? 0.0 : l->pooled;
}

/* *least_robust: the least robust residual of the levels tried (search_below; -1 when no
** level left one, and then the levels below are tried too) */
static bsfit_err search_levels(const double *pts, size_t m, double s0, double max_sigma,
                               level_scratch *w, double *sigma, double *least_robust,
                               const bsfit_allocator *a, bsfit_status *st) {
  double size = bsfit__segment_size(pts, m);
  int round, match;
  level l;
  bsfit_err e;
  for (round = 0; round < 64 && s0 < 0.05 * size && s0 <= max_sigma; round++) {
    if ((round & 7) == 7 && bsfit__interrupted(a))
      return bsfit__fail(st, BSFIT_EINTR, "segmentation noise interrupted");
    if ((e = try_level(pts, m, s0, w, &l, &match, a, st)) != BSFIT_OK) return e;
    if (l.robust >= 0 && (*least_robust < 0 || l.robust < *least_robust)) *least_robust = l.robust;
    if (match) {
      *sigma = estimate_of(&l, size);
      return BSFIT_OK;
    }
    {
      /* finely where a level up to the next step would take this residual (the window of
      ** levels that match can be narrower than a step), else by whole steps; the last
      ** level is max_sigma itself */
      double step = l.pooled >= 0 && l.pooled <= 1.2 * s0 * LEVEL_STEP ? LEVEL_FINE : LEVEL_STEP;
      s0 = s0 < max_sigma && s0 * step > max_sigma ? max_sigma : s0 * step;
    }
  }
  return BSFIT_OK;
}

/* No level from the start up matched, and at some level the models' robust residual was
** below the start: the start was above the noise (on sparse sections the chords' lower quartile
** can fall on samples next to corners and arcs: a slot of 4 samples per side at noise 1e-4
** of its size starts at 11 times the noise, where an arc takes a line's samples). Then the
** levels below the start, by whole steps down to a sixteenth of it: the first that
** matches. Not first: from a low start, early levels match by chance (a sixteenth of the
** start lost 25 of the 390 sections of test_sharp_noisy). Where the robust residual stayed
** above the start (a smooth curve, whose arcs leave residuals of the bend), the levels
** below are not tried: they cost a noisy 40-point star 0.1 ms and found nothing. */
static bsfit_err search_below(const double *pts, size_t m, double s0, level_scratch *w,
                              double *sigma, const bsfit_allocator *a, bsfit_status *st) {
  double size = bsfit__segment_size(pts, m), lowest = fmax(s0 / 16.0, 1e-9 * size), s;
  int match;
  level l;
  bsfit_err e;
  for (s = s0 / LEVEL_STEP; s >= lowest; s /= LEVEL_STEP) {
    if ((e = try_level(pts, m, s, w, &l, &match, a, st)) != BSFIT_OK) return e;
    if (match) {
      *sigma = estimate_of(&l, size);
      return BSFIT_OK;
    }
  }
  return BSFIT_OK;
}

/* An upward match FAR_ABOVE times the least robust residual of the levels below it, where
** that residual also fell below the start, is taken only when no level below the start
** matches: the levels between read the noise off most samples (their lower quartile) and
** a few models wrong, and the match came where the tolerance let a coarse cover hold
** everything (a slot of 4 samples per side at noise 1e-4, whose lines took its end arcs'
** samples at 230 times its noise once a side could be found between two lines that do not
** meet; 1.2 times it below the start). Refusing such matches outright (at 8 times) lost 16
** of the 390 sections of test_sharp_noisy within the floor and 77 of 2340 on other draws of
** them: a sparse level's lower quartile can be a tenth of the noise. */
#define FAR_ABOVE 20.0

/* search_below, the upward match (*sigma, -1 when none) kept when it finds nothing */
static bsfit_err search_below_first(const double *pts, size_t m, double s0, level_scratch *w,
                                    double *sigma, const bsfit_allocator *a, bsfit_status *st) {
  double up = *sigma;
  bsfit_err e;
  *sigma = -1.0;
  e = search_below(pts, m, s0, w, sigma, a, st);
  if (*sigma < 0) *sigma = up;
  return e;
}

/* A dense section's noise is read off every k-th sample: the search segments it a dozen
** times or more (0.9 s for 40000 samples), and every k-th sample has each sample's noise
** (within a few percent of the full search on dense letters, rounded rectangles and
** filleted polygons). */
static bsfit_err spread_sigma(const double *pts, size_t m, int closed, double max_sigma,
                              double *sigma, const bsfit_allocator *a, bsfit_status *st) {
  size_t msub, k;
  size_t first = closed ? bsfit__closed_start(pts, m) : 0;
  double *sub = bsfit__spread(pts, m, first, BSFIT__DENSE_MOST, a, &msub, &k);
  bsfit_err e;
  if (!sub) return bsfit__fail(st, BSFIT_ENOMEM, "out of memory for the noise of %zu points", m);
  e = bsfit_segment_sigma(sub, msub, 2, closed, max_sigma, sigma, a, st);
  bsfit__free(a, sub, 2 * msub * sizeof *sub);
  return e;
}

bsfit_err bsfit_segment_sigma(const double *pts, size_t m, int dim, int closed, double max_sigma,
                              double *sigma, const bsfit_allocator *a, bsfit_status *st) {
  bsfit_segment_opts o;
  bsfit_piece *p, *q;
  level_scratch w;
  size_t bytes;
  double *d, s0, size, least_robust = -1.0;
  bsfit_err e;
  memset(&o, 0, sizeof o);
  o.closed = closed;
  o.param_cost = HUGE_VAL; /* the levels' pooled residuals (above) */
  if (sigma) *sigma = 0;
  if (sigma == NULL) return bsfit__fail(st, BSFIT_EINVAL, "segmentation noise: sigma required");
  if ((e = bsfit__segment_check(pts, m, dim, &o, st)) != BSFIT_OK) return e;
  if (m > BSFIT__DENSE_MOST) return spread_sigma(pts, m, closed, max_sigma, sigma, a, st);
  bytes = bsfit__mulsize(2 * m + 2, sizeof *p);
  p = bsfit__alloc(a, bytes);
  q = bsfit__alloc(a, bytes);
  d = bsfit__alloc(a, 2 * m * sizeof *d);
  if (!p || !q || !d) {
    e = bsfit__fail(st, BSFIT_ENOMEM, "out of memory for the noise of %zu points", m);
    goto done;
  }
  size = bsfit__segment_size(pts, m);
  s0 = fmax(chord_sigma(pts, m, closed, d) / 16.0, 1e-9 * size);
  if (!(max_sigma > 0)) max_sigma = 0.05 * size;
  w.o = &o, w.p = p, w.q = q, w.d = d;
  *sigma = -1.0; /* until a level matches */
  e = search_levels(pts, m, s0, max_sigma, &w, sigma, &least_robust, a, st);
  if (e == BSFIT_OK && least_robust < s0 &&
      (*sigma < 0 || (least_robust >= 0 && *sigma > FAR_ABOVE * least_robust)))
    e = search_below_first(pts, m, s0, &w, sigma, a, st);
  if (*sigma < 0) *sigma = 0.0;
  if (e == BSFIT_OK) e = bsfit__ok(st);
done:
  bsfit__free(a, p, p ? bytes : 0);
  bsfit__free(a, q, q ? bytes : 0);
  bsfit__free(a, d, d ? 2 * m * sizeof *d : 0);
  return e;
}
