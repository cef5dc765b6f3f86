/*
** segment_runs.c
** The maximal runs of a segmentation: for each start, the most samples from there that
** one model of each kind (a line, a circle) explains within the tolerance, found by two
** pointers in O(m) fits' worth of work, and the fits of a model to a run that the rest of
** the segmentation shares (bsfit__fit_model_from, segment_internal.h).
*/
#include "segment_internal.h"

#include <float.h>
#include <math.h>

/* Whether a circle's distances are computed to far better than tol: their rounding is
** about DBL_EPSILON r, and an exact line's samples, collinear to rounding, fit circles of
** radius 1e12 whose distances are noise (they took in the next sides of a gear, 7% of its
** size off, once short dense arcs could be fitted). (A rule that the run must bow away
** from its chord by more than tol was tried too: it lost 4 noisy sections of 390 to the
** smooth path, the arcs of sparse noisy D shapes among them.) */
static int arc_resolved(const seg_section *s, const bsfit__circle *C) {
  return 16.0 * DBL_EPSILON * C->r <= s->tol;
}

/* fits a model of `kind` to n samples from `first`; its largest distance (HUGE_VAL
** when it cannot be fitted) */
double bsfit__fit_model_from(const seg_section *s, int kind, size_t first, size_t n,
                             const seg_model *warm, seg_model *md, double *rms) {
  bsfit__run r = run_of(s, first, n);
  double turn = 0;
  size_t k;
  md->kind = kind;
  if (kind == LINE) {
    if (!bsfit__fit_line(&r, &md->line)) return HUGE_VAL;
    return bsfit__line_max(&md->line, &r, rms);
  }
  /* an arc that cannot be fitted keeps a defined model, since the joins of its neighbours
  ** read it (they read the scratch memory's old contents: test_segment_determinism): the
  ** fit's start circle, or where that is not made (the three samples it starts from are
  ** collinear or repeated), a nearly straight circle along the run's chord */
  md->orient = 1.0;
  if (warm != md) {
    const double *a = bsfit__run_at(&r, 0), *b = bsfit__run_at(&r, n - 1);
    double dx = b[0] - a[0], dy = b[1] - a[1], len = hypot(dx, dy);
    if (!(len > 0)) dx = 1, dy = 0, len = 1;
    md->circle.r = 1e8 * len;
    md->circle.c[0] = 0.5 * (a[0] + b[0]) - dy / len * md->circle.r;
    md->circle.c[1] = 0.5 * (a[1] + b[1]) + dx / len * md->circle.r;
  }
  if (!bsfit__fit_circle(&r, warm && warm->kind == ARC ? &warm->circle : NULL, 1e-3 * s->tol,
                         &md->circle))
    return HUGE_VAL;
  /* the direction the samples go round the centre: the sign of the sum of their steps'
  ** turns, each step's by its cross product (r^2 times the sine of its angle, the samples
  ** all near the circle; a run's steps turn by far less than a half turn: atan2 per step
  ** cost a tenth of the noise search) */
  for (k = 0; k + 1 < n; k++) {
    const double *p = bsfit__run_at(&r, k), *q = bsfit__run_at(&r, k + 1);
    double ax = p[0] - md->circle.c[0], ay = p[1] - md->circle.c[1];
    double bx = q[0] - md->circle.c[0], by = q[1] - md->circle.c[1];
    turn += ax * by - ay * bx;
  }
  md->orient = turn >= 0 ? 1.0 : -1.0;
  if (!arc_resolved(s, &md->circle)) return HUGE_VAL;
  return bsfit__circle_max(&md->circle, &r, rms);
}

/* A quick no for a seed of minl samples: the line through its ends (the circle through
** its ends and middle) misses one of them by far more than any least-squares model
** could spread (3 tol for a line, 8 for a circle). */
static int seed_misses(const seg_section *s, int kind, size_t i, size_t n) {
  const double *a = sample(s, i), *b = sample(s, i + n - 1);
  size_t k;
  if (kind == LINE) {
    double dx = b[0] - a[0], dy = b[1] - a[1], l = hypot(dx, dy);
    if (!(l > 0)) return 0;
    for (k = 1; k + 1 < n; k++) {
      const double *q = sample(s, i + k);
      if (fabs((q[0] - a[0]) * dy - (q[1] - a[1]) * dx) / l > 3 * s->tol) return 1;
    }
  } else {
    /* the circle through first, middle and last: a 3-sample run of them */
    const double *mid = sample(s, i + n / 2);
    double tri[6] = {a[0], a[1], mid[0], mid[1], b[0], b[1]};
    bsfit__run t = {tri, 3, 0, 3};
    bsfit__circle C;
    if (!bsfit__fit_circle(&t, NULL, 0.0, &C)) return 0;
    for (k = 1; k + 1 < n; k++)
      if (bsfit__circle_dist(&C, sample(s, i + k)) > 8 * s->tol) return 1;
  }
  return 0;
}

/* Runs up to this length are refitted at every start and confirmed by a whole fit at
** their end (a few hundred operations each); longer ones keep the model they inherit and
** refit only when worth_refit says so, so that a section's long sides cost O(m) in all. */
#define SHORT_RUN 64

/* The last refit tried (successful or not): samples [start, start + len). A refit costs
** O(len), so on a long run another is tried only when the run differs from that one by
** an eighth of its samples (dropped at the front by later starts, or added at the back).
** The samples that change between tries number at most 2m in all, so refits cost O(m)
** over the section, whatever the length of its runs (each start used to refit its whole
** run: quadratic, 2 s for 5000 samples of one circle, 6.5 s for a square of 64000). */
typedef struct refit_mark {
  size_t start, len;
} refit_mark;

static int worth_refit(const seg_section *s, const refit_mark *t, size_t i, size_t n) {
  /* starts go round a closed section from s->start: i may have passed m - 1 to 0 since
  ** the mark */
  size_t dropped = (i + s->m - t->start) % s->m;
  size_t added = dropped + n > t->len ? dropped + n - t->len : 0;
  return 8 * (dropped + added) >= n;
}

/* the run from i (its first n samples explained by md) grown sample by sample while md
** explains each; a sample it misses triggers a refit when worth_refit says so (else the
** run ends there). A short run whose last samples were judged by an older model is
** confirmed by a whole fit, or falls back to the last length a fit confirmed. Returns
** its length; md explains all of it. */
static size_t grow_run(const seg_section *s, int kind, size_t i, size_t n, size_t limit,
                       seg_model *md, refit_mark *tried) {
  size_t good = n;
  seg_model next;
  while (n < limit) {
    if (model_dist(md, sample(s, i + n)) <= s->tol) {
      n++;
      continue;
    }
    if (!worth_refit(s, tried, i, n + 1)) break;
    tried->start = i, tried->len = n + 1;
    if (!fit_explains(s, kind, i, n + 1, md, &next)) break;
    *md = next;
    good = ++n;
  }
  if (n > good && n <= SHORT_RUN) {
    if (fit_explains(s, kind, i, n, md, &next)) *md = next;
    else if (fit_explains(s, kind, i, good, md, &next)) *md = next, n = good;
  }
  return n;
}

/* A first model for the run from i: n samples fitted (warm-started from warm), else its
** minl samples. Returns the samples it explains, 0 when none. */
static size_t seed_run(const seg_section *s, int kind, size_t i, size_t n, const seg_model *warm,
                       seg_model *md, refit_mark *tried) {
  size_t minl = s->min_len[kind];
  tried->start = i, tried->len = n;
  if (n > minl && fit_explains(s, kind, i, n, warm, md)) return n;
  tried->len = minl;
  if (seed_misses(s, kind, i, minl)) return 0;
  warm = n > minl ? NULL : warm;
  if (fit_explains(s, kind, i, minl, warm, md)) return minl;
  /* on exact data afresh where the warm start failed: a circle warm-started from the run
  ** before, which bent from a line into the fillet after it, failed on the fillet's first
  ** samples crowded into a few degrees (a rounded rectangle of 30000 uneven exact samples:
  ** the fillet's run started a sample late and a line of 3 samples took its first, 2e-5 of
  ** the size off the outline). Not under noise: there the fresh circles of 4 samples are
  ** arcs across the corners of sparse sections, which the cover then took (the sparse sets
  ** of test_segment_sigma_sparse: 219 -> 215 of 416 within the floor). */
  return warm && !s->noisy && fit_explains(s, kind, i, minl, NULL, md) ? minl : 0;
}

/* the most samples a run from i can hold: the section's, or those left before an open end */
static size_t run_limit(const seg_section *s, size_t i) { return s->closed ? s->m : s->m - i; }

/* An arc's run from i that stops far short of where the run from i + 1 ends is tried
** once on the samples from i to that end, and made that long when one circle explains
** them all. The start's model is fitted to its first few samples only; where they bow
** less than the noise (the first samples of an arc after a sampling gap at its corner)
** the circle goes astray, the refits it is allowed (worth_refit) start from it and fail,
** and the run ends: a keyhole of 100 uneven samples per side at noise 1e-3 then covered
** the arc's first samples with a line across its corner, 3.4 times the floor off. Only
** where the run from i + 1 is long (FAR_SHORT x 2 samples) and the run from i shorter by
** FAR_SHORT and a quarter: on sparse sections a run found so (an arc round a serif's
** three short sides) is one the cover then takes for the serif's lines, and the
** condition keeps the fits few (about one per corner). Lines are not extended: a line's
** fit does not go astray so (tried: sparse letters lost). Noisy sections only (the
** weighed cover): the noise search's cover by parameters alone moved its levels. */
#define FAR_SHORT 8
static void extend_arc_runs(const seg_section *s, size_t *len, size_t first) {
  size_t t, m = s->m, minl = s->min_len[ARC];
  seg_model md;
  for (t = s->closed ? 1 : 2; t <= m; t++) { /* back from the start before `first` */
    size_t i = (first + m - t) % m, next = len[(i + 1) % m], want = next + 1;
    if (next == 0 || want > run_limit(s, i) || want < 2 * FAR_SHORT ||
        want < len[i] + FAR_SHORT || 4 * (want - len[i]) < want)
      continue;
    if (fit_model(s, ARC, i, want, &md, NULL) <= s->tol && distinct(s, ARC, i, want) >= minl)
      len[i] = want;
  }
}

/* len[i] = the most samples from i that one model of `kind` explains (0 when fewer than
** its minimum; a long run may stop short of the most by under an eighth where a refit
** was not worth trying). Two pointers: the run from i - 1 less its first sample is a run
** from i, so each start resumes where the previous stopped: a short run refitted
** (warm-started from the previous model), a long one with the previous model, which
** explains it. O(m) fits' worth of work; then, on noisy sections, the arcs' runs that
** went astray at their start (extend_arc_runs).
** So the runs depend a little on where the scan of a closed section's starts begins (a fit
** warm-started from the previous run's model, a run taken to hold what the run before it
** held past its first sample): begun at the data's first sample, a rounded rectangle of 6
** samples per side at noise 1e-3 had another cover at some levels for each sample its data
** began at. It begins at s->start (bsfit__closed_start: after the longest step, as the
** cover chooses where to cut), so the runs are the data's own. */
bsfit_err bsfit__maximal_runs(const seg_section *s, int kind, size_t *len) {
  size_t t, prev = 0, minl = s->min_len[kind], first = s->start;
  seg_model md;
  refit_mark tried = {first, 0};
  for (t = 0; t < s->m; t++) {
    size_t i = (first + t) % s->m, limit = run_limit(s, i);
    size_t n = prev > minl ? prev - 1 : minl;
    if ((t & 255) == 0 && bsfit__interrupted(s->a)) return BSFIT_EINTR;
    len[i] = 0;
    if (n > limit || minl > limit) {
      prev = 0;
      continue;
    }
    if (prev <= minl || n <= SHORT_RUN) n = seed_run(s, kind, i, n, prev ? &md : NULL, &md, &tried);
    if (n == 0) {
      prev = 0;
      continue;
    }
    n = grow_run(s, kind, i, n, limit, &md, &tried);
    len[i] = distinct(s, kind, i, n) >= minl ? n : 0;
    prev = n;
  }
  if (s->mom && kind == ARC) extend_arc_runs(s, len, first);
  return BSFIT_OK;
}
