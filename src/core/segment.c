/*
** segment.c
** Segmentation of an ordered 2D section into straight lines, circular arcs and
** free-form runs (bsfit_features.h): the maximal runs each model explains, the cover
** of least cost (dynamic programming), and where consecutive pieces meet.
*/
#include <float.h>
#include <math.h>
#include <string.h>

#include "segment_internal.h"

/* Whether a circle's distances are computed to far better than tol: their rounding is
** about DBL_EPSILON r, and an exact line's samples, collinear to rounding, fit circles of
** radius 1e12 whose distances are noise (they took in the next sides of a gear, 7% of its
** size off, once short dense arcs could be fitted). (A rule that the run must bow away
** from its chord by more than tol was tried too: it lost 4 noisy sections of 390 to the
** smooth path, the arcs of sparse noisy D shapes among them.) */
static int arc_resolved(const seg_section *s, const bsfit__circle *C) {
  return 16.0 * DBL_EPSILON * C->r <= s->tol;
}

/* The floor of the exact tolerance: 16 DBL_EPSILON times the largest coordinate, some 8
** units of its last place. Exact samples are their true positions rounded to half a unit
** (a fitted model misses them by a few units, however many they are: the rounding does not
** add up along a run, so the tolerance need not grow with its length or the number of
** samples); it matters only for sections farther from the origin than 10^4 times their
** size (a D of size 1e-2 at (1e4, -1e4), whose coordinates round to 9e-11 of its size,
** had its arc cut into arcs and free runs by the 1e-10 of the size). */
static double rounding_floor(const double *pts, size_t m) {
  double big = 0.0;
  size_t i;
  for (i = 0; i < 2 * m; i++) big = fmax(big, fabs(pts[i]));
  return 16.0 * DBL_EPSILON * big;
}

/* fits a model of `kind` to n samples from `first`; its largest distance (HUGE_VAL
** when it cannot be fitted) */
static double fit_model_from(const seg_section *s, int kind, size_t first, size_t n,
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

static double fit_model(const seg_section *s, int kind, size_t first, size_t n, seg_model *md,
                        double *rms) {
  return fit_model_from(s, kind, first, n, NULL, md, rms);
}

/* {====================================================================
** Maximal runs
** ===================================================================== */

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

/* A model explains its samples when every one lies within tol. (A chi-square test on
** their residual was tried as well: it turned fillets into corners; docs/auto.md.) This
** is what makes runs nest: a model that explains a run explains every part of it. */
static int fit_explains(const seg_section *s, int kind, size_t first, size_t n,
                        const seg_model *warm, seg_model *md) {
  return fit_model_from(s, kind, first, n, warm, md, NULL) <= s->tol;
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

static int worth_refit(const refit_mark *t, size_t i, size_t n) {
  size_t dropped = i - t->start, added = i + n > t->start + t->len ? i + n - t->start - t->len : 0;
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
    if (!worth_refit(tried, i, n + 1)) break;
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
  if (seed_misses(s, kind, i, minl) || !fit_explains(s, kind, i, minl, n > minl ? NULL : warm, md))
    return 0;
  return minl;
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
static void extend_arc_runs(const seg_section *s, size_t *len) {
  size_t i, m = s->m, minl = s->min_len[ARC];
  seg_model md;
  for (i = s->closed ? m : m - 1; i-- > 0;) {
    size_t next = len[(i + 1) % m], want = next + 1;
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
** went astray at their start (extend_arc_runs). */
static bsfit_err maximal_runs(const seg_section *s, int kind, size_t *len) {
  size_t i, prev = 0, minl = s->min_len[kind];
  seg_model md;
  refit_mark tried = {0, 0};
  for (i = 0; i < s->m; i++) {
    size_t limit = run_limit(s, i);
    size_t n = prev > minl ? prev - 1 : minl;
    if ((i & 255) == 0 && bsfit__interrupted(s->a)) return BSFIT_EINTR;
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
  if (s->mom && kind == ARC) extend_arc_runs(s, len);
  return BSFIT_OK;
}

/* }==================================================================== */

/* {====================================================================
** The cover of least cost
** ===================================================================== */

/* DP state: the cheapest cover of offsets [0, j] whose last piece ends at j */
typedef struct cell {
  double cost;
  size_t start; /* offset of the last piece's first sample */
  int kind;
  int shared;    /* the piece before ends at `start` too (a sampled corner) */
  int prev_free; /* the piece before is free */
} cell;

/* Costs, in parameters: a line has 2, an arc 3; a free sample costs 1.5 (the control
** point or so that follows it), a free run 1 more (its ends), so that three samples on a
** line (2) beat three free ones (5.5) and a side of lines between fillets too sparse
** to be arcs is still cut into lines. */
static const double COST[3] = {2.0, 3.0, 0.0};
#define FREE_SAMPLE 1.5
#define FREE_RUN 1.0

/* What a piece starting at offset a follows: the cheapest cover of [0, a - 1] (primitive
** or free), or of [0, a] ending in a primitive (the two share sample a: a sampled
** corner). Fields of c other than cost and start are set here. */
static double before_start(size_t a, const cell *prim, const cell *fr, cell *c) {
  double before = 0;
  c->shared = 0, c->prev_free = 0;
  if (a == 0) return 0;
  before = prim[a - 1].cost;
  if (fr[a - 1].cost < before) before = fr[a - 1].cost, c->prev_free = 1;
  if (prim[a].cost < before) before = prim[a].cost, c->shared = 1, c->prev_free = 0;
  return before;
}

/* The candidate starts of one kind's pieces: a binary heap of offsets, cheapest
** before_start first, the later start first among equals (the shortest piece, as the
** scan from the shortest piece up chose). Starts enter in increasing order once a piece
** from them to j has the kind's minimum of distinct samples (a condition that, once
** true, stays true as j grows); a start leaves when its run no longer reaches j (for
** good: j only grows). O(m log m) for the cover, where a scan over every length was
** O(m x longest run): quadratic on long sides. */
typedef struct start_heap {
  size_t *at;
  double *key;
  size_t *below; /* per start: the next older start of its group (NO_START: none) */
  size_t n, next;
  size_t last, last_pos; /* the start pushed last, and where it went */
} start_heap;

/* The heap orders groups of starts by their latest (top) start. A start whose key equals
** that of the start pushed just before it, still a group's top where it went, joins that
** group: it is later than all, so it becomes the top and moves up past older starts of
** its key only. Along a long run every start has one key (the run's first start, below
** them, has its own): each push then costs O(1) instead of a sift past all the others,
** and so does each removal at the run's end. Removals are at the top only, in both forms:
** the same tops in the same order as a heap of every start. */
#define NO_START ((size_t)-1)

static int heap_before(const start_heap *h, size_t x, size_t y) {
  return h->key[x] < h->key[y] || (h->key[x] == h->key[y] && x > y);
}

static void heap_push(start_heap *h, size_t a) {
  size_t i;
  if (h->last_pos < h->n && h->at[h->last_pos] == h->last && h->key[h->last] == h->key[a]) {
    h->below[a] = h->last;
    i = h->last_pos;
  } else {
    h->below[a] = NO_START;
    i = h->n++;
  }
  while (i > 0 && heap_before(h, a, h->at[(i - 1) / 2])) {
    h->at[i] = h->at[(i - 1) / 2];
    i = (i - 1) / 2;
  }
  h->at[i] = a;
  h->last = a, h->last_pos = i;
}

static void heap_pop(start_heap *h) {
  size_t i = 0, last;
  if (h->below[h->at[0]] != NO_START)
    last = h->below[h->at[0]];
  else
    last = h->at[--h->n];
  for (;;) {
    size_t c = 2 * i + 1;
    if (c >= h->n) break;
    if (c + 1 < h->n && heap_before(h, h->at[c + 1], h->at[c])) c++;
    if (!heap_before(h, h->at[c], last)) break;
    h->at[i] = h->at[c];
    i = c;
  }
  if (h->n > 0) h->at[i] = last;
}

/* best piece of `kind` ending at offset j: its cost (HUGE_VAL when none) and start */
static double best_of_kind(const seg_section *s, size_t origin, size_t j, int kind,
                           const size_t *len, const cell *prim, const cell *fr, start_heap *h,
                           size_t *start) {
  size_t minl = s->min_len[kind];
  while (h->next + minl <= j + 1 &&
         distinct(s, kind, (origin + h->next) % s->m, j + 1 - h->next) >= minl) {
    cell c;
    h->key[h->next] = before_start(h->next, prim, fr, &c);
    heap_push(h, h->next++);
  }
  while (h->n > 0 && len[(origin + h->at[0]) % s->m] < j + 1 - h->at[0]) heap_pop(h);
  if (h->n == 0) return HUGE_VAL;
  *start = h->at[0];
  return h->key[h->at[0]] + COST[kind];
}

/* On a noisy section a piece costs its residual as well, in sigma^2: a model that holds
** its samples within the tolerance (4 sigma) but explains them worse than two would (a
** line run on into the fillet after it, one side of a sparse corner) pays for it, and one
** more piece is worth RSS_PENALTY sigma^2 per parameter (about what chance gives a
** parameter that explains nothing; 2 is Akaike's, ln m Schwarz's). Every start is tried,
** O(m x run length): noisy sections of more than BSFIT__DENSE_MOST samples are covered on
** every k-th sample (segment_dense.c), so the weighing costs at most that x run length. */
#define RSS_PENALTY 32.0

static double piece_rss(const seg_section *s, int kind, size_t first, size_t n) {
  return kind == LINE ? bsfit__moments_line_rss(s->mom, first, n)
                      : bsfit__moments_arc_rss(s->mom, first, n);
}

static void best_primitive_weighed(const seg_section *s, size_t origin, size_t j,
                                   size_t *const len[2], const cell *prim, const cell *fr,
                                   cell *c) {
  int kind;
  double unit2 = s->unit * s->unit;
  c->cost = HUGE_VAL;
  for (kind = LINE; kind <= ARC; kind++) {
    size_t minl = s->min_len[kind], a;
    if (j + 1 < minl) continue;
    for (a = j + 1 - minl; j - a < s->longest[kind]; a--) {
      size_t n = j - a + 1;
      if (len[kind][(origin + a) % s->m] >= n &&
          distinct(s, kind, (origin + a) % s->m, n) >= minl) {
        cell t;
        double cost = before_start(a, prim, fr, &t) + s->penalty * COST[kind];
        if (cost < c->cost) { /* else no residual (>= 0) can make it the cheapest */
          cost += piece_rss(s, kind, origin + a, n) / unit2;
          if (cost < c->cost) *c = t, c->cost = cost, c->start = a, c->kind = kind;
        }
      }
      if (a == 0) break;
    }
  }
}

/* best primitive piece ending at offset j (into *c); a line wins a tie with an arc */
static void best_primitive(const seg_section *s, size_t origin, size_t j, size_t *const len[2],
                           const cell *prim, const cell *fr, start_heap heaps[2], cell *c) {
  int kind;
  c->cost = HUGE_VAL;
  for (kind = LINE; kind <= ARC; kind++) {
    size_t a = 0;
    double cost = best_of_kind(s, origin, j, kind, len[kind], prim, fr, &heaps[kind], &a);
    if (cost < c->cost) {
      before_start(a, prim, fr, c);
      c->cost = cost;
      c->start = a;
      c->kind = kind;
    }
  }
}

/* The pieces (first/last sample, kind) of the cheapest cover of the M samples from
** origin, written backwards into out; returns their number. */
static size_t cheapest_cover(const seg_section *s, size_t origin, size_t *const len[2],
                             start_heap heaps[2], cell *prim, cell *fr, bsfit_piece *out) {
  size_t M = s->m, j, np = 0;
  int in_free;
  heaps[0].n = heaps[0].next = heaps[1].n = heaps[1].next = 0;
  heaps[0].last_pos = heaps[1].last_pos = 0;
  for (j = 0; j < M; j++) {
    double unit = s->mom ? s->penalty : 1.0; /* a free sample explains itself exactly */
    double a = j > 0 ? fr[j - 1].cost + unit * FREE_SAMPLE : HUGE_VAL;
    double b = (j > 0 ? prim[j - 1].cost : 0) + unit * (FREE_SAMPLE + FREE_RUN);
    if (s->mom)
      best_primitive_weighed(s, origin, j, len, prim, fr, &prim[j]);
    else
      best_primitive(s, origin, j, len, prim, fr, heaps, &prim[j]);
    fr[j].kind = FREE;
    fr[j].shared = 0;
    if (a <= b)
      fr[j].cost = a, fr[j].start = fr[j - 1].start, fr[j].prev_free = fr[j - 1].prev_free;
    else
      fr[j].cost = b, fr[j].start = j, fr[j].prev_free = 0;
  }
  /* trace back from the end */
  j = M - 1;
  in_free = fr[j].cost < prim[j].cost;
  for (;;) {
    const cell *c = in_free ? &fr[j] : &prim[j];
    bsfit_piece *p = &out[np++];
    memset(p, 0, sizeof *p);
    p->kind = (bsfit_piece_kind)c->kind;
    p->first = (origin + c->start) % s->m;
    p->count = j - c->start + 1;
    if (c->start == 0) break;
    if (c->shared)
      j = c->start;
    else
      j = c->start - 1;
    in_free = c->prev_free;
  }
  return np;
}

/* }==================================================================== */

/* {====================================================================
** Where pieces meet
** ===================================================================== */

static size_t piece_count(const seg_section *s, const bsfit_piece *p) {
  (void)s;
  return p->count;
}

/* segment_internal.h */
void bsfit__segment_refit(const seg_section *s, bsfit_piece *p, seg_model *md) {
  double rms = 0;
  p->max = fit_model(s, p->kind, p->first, piece_count(s, p), md, &rms);
  p->rms = rms;
  if (p->kind == ARC) {
    memcpy(p->centre, md->circle.c, sizeof p->centre);
    p->radius = md->circle.r;
  }
}

/* features_internal.h */
double bsfit__piece_dist(const bsfit_piece *p, const double *q) {
  double dx, dy, l;
  if (p->kind == BSFIT_PIECE_ARC) return fabs(hypot(q[0] - p->centre[0], q[1] - p->centre[1]) - p->radius);
  if (p->kind == BSFIT_PIECE_FREE) return 0.0;
  dx = p->end[0] - p->start[0], dy = p->end[1] - p->start[1], l = hypot(dx, dy);
  return l > 0 ? fabs((q[0] - p->start[0]) * dy - (q[1] - p->start[1]) * dx) / l : 0.0;
}

/* segment_internal.h */
void bsfit__model_foot(const seg_model *md, const double *x, double *f, double *t) {
  if (md->kind == LINE) {
    double u = (x[0] - md->line.p[0]) * md->line.d[0] + (x[1] - md->line.p[1]) * md->line.d[1];
    f[0] = md->line.p[0] + u * md->line.d[0];
    f[1] = md->line.p[1] + u * md->line.d[1];
    t[0] = md->line.d[0];
    t[1] = md->line.d[1];
  } else {
    double dx = x[0] - md->circle.c[0], dy = x[1] - md->circle.c[1], d = hypot(dx, dy);
    f[0] = md->circle.c[0] + md->circle.r * dx / d;
    f[1] = md->circle.c[1] + md->circle.r * dy / d;
    t[0] = -md->orient * dy / d;
    t[1] = md->orient * dx / d;
  }
}

/* the largest spacing of a piece's samples; squared steps (coordinates are within
** BSFIT_COORD_MAX, their squares far from overflow) and one root: hypot per step was 13%
** of a 10^5-sample T's run, every join asking for it several times */
static double max_spacing(const seg_section *s, const bsfit_piece *p) {
  size_t k, n = piece_count(s, p);
  double h2 = 0;
  for (k = 0; k + 1 < n; k++) {
    const double *a = sample(s, p->first + k), *b = sample(s, p->first + k + 1);
    double dx = b[0] - a[0], dy = b[1] - a[1], d2 = dx * dx + dy * dy;
    if (d2 > h2) h2 = d2;
  }
  return sqrt(h2);
}

/* Do the models run on the same way at x (their tangents there, each in its samples'
** direction, not opposed)? Models that touch but run opposite ways meet in a cusp: a line
** into a circle of a serif's three sides that turns back along it (T_serif of 4 noisy
** samples per side: a "tangent" join that turned by 177 degrees, 5 times the floor off). */
static int same_way(const seg_model *ma, const seg_model *mb, const double *x) {
  double f[2], ta[2], tb[2];
  bsfit__model_foot(ma, x, f, ta);
  bsfit__model_foot(mb, x, f, tb);
  return ta[0] * tb[0] + ta[1] * tb[1] > 0;
}

/* Do the models touch, running on the same way? A line and a circle when the centre is r
** from the line, two circles when their centres are r1 + r2 or |r1 - r2| apart, within
** the tolerance (a tangent join meets at the touching point, which the intersection
** formulas find only to the square root of the rounding). Writes the touching point. */
static int touching(const seg_section *s, const seg_model *ma, const seg_model *mb, double *x) {
  double t[2];
  if (ma->kind == LINE && mb->kind == LINE) return 0;
  if (ma->kind == LINE || mb->kind == LINE) {
    const seg_model *ml = ma->kind == LINE ? ma : mb, *mc = ma->kind == LINE ? mb : ma;
    bsfit__model_foot(ml, mc->circle.c, x, t);
    return fabs(hypot(x[0] - mc->circle.c[0], x[1] - mc->circle.c[1]) - mc->circle.r) <=
               2 * s->tol &&
           same_way(ma, mb, x);
  } else {
    const bsfit__circle *A = &ma->circle, *B = &mb->circle;
    double d = hypot(B->c[0] - A->c[0], B->c[1] - A->c[1]), u;
    if (d <= s->tol) return 0;
    if (fabs(d - (A->r + B->r)) <= 2 * s->tol)
      u = A->r / d; /* outside each other */
    else if (fabs(d - fabs(A->r - B->r)) <= 2 * s->tol)
      u = A->r > B->r ? A->r / d : -A->r / d;
    else
      return 0;
    x[0] = A->c[0] + u * (B->c[0] - A->c[0]);
    x[1] = A->c[1] + u * (B->c[1] - A->c[1]);
    return same_way(ma, mb, x);
  }
}

/* The turn from a to b round an arc's centre, in its direction, in [0, 2 pi). */
static double turn_between(const seg_model *md, const double *a, const double *b) {
  double ax = a[0] - md->circle.c[0], ay = a[1] - md->circle.c[1];
  double bx = b[0] - md->circle.c[0], by = b[1] - md->circle.c[1];
  double t = md->orient * atan2(ax * by - ay * bx, ax * bx + ay * by);
  return t < 0 ? t + 2 * PI : t;
}

/* Does x lie back among p's samples from q (p's sample at its end, `end`, or its start),
** by more than `slack`? Along a line, by its direction. Round an arc, by the turn back
** from q when that is within the turn from its first sample to its last: the tangent at q
** tells only near q, and an arc sampled on a third of its circle meets its neighbour two
** thirds of the way round (a keyhole of 4 uneven samples per side was closed by the far
** intersection of a side with its circle, 121 times the floor off). */
static int behind(const seg_section *s, const bsfit_piece *p, const seg_model *md,
                  const double *q, const double *x, int end, double slack) {
  double span, turn, back;
  if (md->kind == LINE) { /* its direction is the samples' */
    double along = (x[0] - q[0]) * md->line.d[0] + (x[1] - q[1]) * md->line.d[1];
    return (end ? along : -along) < -slack;
  }
  span = turn_between(md, sample(s, p->first), sample(s, p->first + p->count - 1));
  turn = end ? turn_between(md, q, x) : turn_between(md, x, q);
  back = turn > 0 ? 2 * PI - turn : 0;
  return back < span && back * md->circle.r > slack;
}

/* Is x where A (last sample qa) may meet B (first sample qb)? Beyond qa along A, before
** qb along B (by `slack` at most), and within reach of both: as far as the pieces' own
** spacing, and `past` farther (a tangent join's, below). */
static int in_gap(const seg_section *s, const bsfit_piece *A, const seg_model *ma,
                  const bsfit_piece *B, const seg_model *mb, const double *x, double slack,
                  double past) {
  const double *qa = sample(s, A->first + A->count - 1), *qb = sample(s, B->first);
  double chord = hypot(qb[0] - qa[0], qb[1] - qa[1]);
  double reach_a = 1.5 * max_spacing(s, A) + 1.5 * chord + s->tol + past;
  double reach_b = 1.5 * max_spacing(s, B) + 1.5 * chord + s->tol + past;
  if (hypot(x[0] - qa[0], x[1] - qa[1]) > reach_a || hypot(x[0] - qb[0], x[1] - qb[1]) > reach_b)
    return 0;
  return !behind(s, A, ma, qa, x, 1, slack) && !behind(s, B, mb, qb, x, 0, slack);
}

/* Where A and B meet: their touching point (a tangent join), or the meeting point of
** their models that lies in the gap between them (nearest to both samples), a corner
** unless their directions there agree to what the tolerance lets them vary over the
** shorter piece. Returns 0 (no such point), BSFIT_JOIN_CORNER or BSFIT_JOIN_TANGENT. */
static int meet(const seg_section *s, const bsfit_piece *A, const seg_model *ma,
                const bsfit_piece *B, const seg_model *mb, double *x) {
  const double *qa = sample(s, A->first + A->count - 1), *qb = sample(s, B->first);
  double cand[2][2], best = HUGE_VAL, ta[2], tb[2], f[2], lim, angle;
  int nc = 0, k, found = 0;
  if (touching(s, ma, mb, x)) {
    /* models that touch stay within tol of each other for sqrt(2 r tol) on either side
    ** of the touching point: a sample that far past it fits either piece, and a line may
    ** end that far past it however densely the arc is sampled (before, a rounded rectangle
    ** of 200 noisy samples per side was bridged at its fillets). Two arcs are not given
    ** that reach: a smooth curve's arcs overlap that far, and were then read as tangent
    ** arcs (a cam of 200 samples 4 times farther from the truth). */
    double r = ma->kind == ARC ? ma->circle.r : mb->circle.r, slack;
    if (ma->kind == ARC && mb->kind == ARC && mb->circle.r < r) r = mb->circle.r;
    slack = fmax(2 * s->tol, sqrt(2 * r * s->tol));
    return in_gap(s, A, ma, B, mb, x, slack, ma->kind == ARC && mb->kind == ARC ? 0.0 : slack)
               ? BSFIT_JOIN_TANGENT
               : 0;
  }
  if (ma->kind == LINE && mb->kind == LINE)
    nc = bsfit__meet_lines(&ma->line, &mb->line, cand[0]);
  else if (ma->kind == LINE)
    nc = bsfit__meet_line_circle(&ma->line, &mb->circle, cand);
  else if (mb->kind == LINE)
    nc = bsfit__meet_line_circle(&mb->line, &ma->circle, cand);
  else
    nc = bsfit__meet_circles(&ma->circle, &mb->circle, cand);
  for (k = 0; k < nc; k++) {
    double *c = cand[k], d = hypot(c[0] - qa[0], c[1] - qa[1]) + hypot(c[0] - qb[0], c[1] - qb[1]);
    if (in_gap(s, A, ma, B, mb, c, 2 * s->tol, 0.0) && d < best)
      best = d, x[0] = c[0], x[1] = c[1], found = 1;
  }
  if (!found) return 0;
  bsfit__model_foot(ma, x, f, ta);
  bsfit__model_foot(mb, x, f, tb);
  angle = atan2(fabs(ta[0] * tb[1] - ta[1] * tb[0]), ta[0] * tb[0] + ta[1] * tb[1]);
  lim = 4.0 * s->tol / fmax(1.5 * fmin(max_spacing(s, A), max_spacing(s, B)), 1e-300);
  return angle <= fmin(lim, 0.1) ? BSFIT_JOIN_TANGENT : BSFIT_JOIN_CORNER;
}

/* segment_internal.h */
int bsfit__segment_meet(const seg_section *s, const bsfit_piece *A, const seg_model *ma,
                        const bsfit_piece *B, const seg_model *mb, double *x) {
  return meet(s, A, ma, B, mb, x);
}

/* }==================================================================== */

/* {====================================================================
** The pieces
** ===================================================================== */

static void set_line_ends(bsfit_piece *p, const seg_model *md) {
  memcpy(p->t_start, md->line.d, sizeof p->t_start);
  memcpy(p->t_end, md->line.d, sizeof p->t_end);
}

/* arcs: the sweep from start to end in the samples' direction (signed; a whole turn when
** they coincide) */
static void set_arc_sweep(bsfit_piece *p, const seg_model *md, int whole) {
  double turn = whole ? 0 : turn_between(md, p->start, p->end);
  p->sweep = md->orient * (turn > 0 ? turn : 2 * PI);
}

/* A meets B (both in the list, B after A): sets A's end, B's start, tangents and B's
** join. Returns 0 when two primitives' models do not meet between them. */
static int join_pieces(const seg_section *s, bsfit_piece *A, const seg_model *ma, bsfit_piece *B,
                       const seg_model *mb) {
  double x[2], f[2], t[2];
  int k;
  if (A->kind != FREE && B->kind != FREE) {
    k = meet(s, A, ma, B, mb, x);
    if (!k) return 0;
    memcpy(A->end, x, sizeof x);
    memcpy(B->start, x, sizeof x);
    bsfit__model_foot(ma, x, f, A->t_end);
    bsfit__model_foot(mb, x, f, B->t_start);
    B->join = (bsfit_join_kind)k;
    return 1;
  }
  /* a free run meets a primitive at the primitive's extreme sample, tangentially */
  if (A->kind != FREE)
    bsfit__model_foot(ma, sample(s, A->first + A->count - 1), f, t);
  else
    bsfit__model_foot(mb, sample(s, B->first), f, t);
  memcpy(A->end, f, sizeof f);
  memcpy(B->start, f, sizeof f);
  memcpy(A->t_end, t, sizeof t);
  memcpy(B->t_start, t, sizeof t);
  B->join = BSFIT_JOIN_TANGENT;
  return 1;
}

/* removes piece i (and its model) from the list of np; returns np - 1 */
static size_t drop_piece(bsfit_piece *p, seg_model *md, size_t np, size_t i) {
  memmove(&p[i], &p[i + 1], (np - i - 1) * sizeof *p);
  memmove(&md[i], &md[i + 1], (np - i - 1) * sizeof *md);
  return np - 1;
}

/* A free piece of 2 (3) samples between two primitives becomes the line (circle)
** through them when both its ends then meet the neighbours: a short side, or an arc
** sampled too sparsely to be told from a curve, that both neighbours confirm. */
static void short_runs(const seg_section *s, bsfit_piece *p, seg_model *md, size_t np) {
  size_t i;
  for (i = 0; i < np; i++) {
    size_t ia = (i + np - 1) % np, ib = (i + 1) % np;
    bsfit_piece trial = p[i];
    seg_model mt;
    double x[2];
    if (p[i].kind != FREE || (p[i].count != 2 && p[i].count != 3) || np < 2) continue;
    if (!s->closed && (i == 0 || i + 1 == np)) continue;
    if (p[ia].kind == FREE || p[ib].kind == FREE) continue;
    trial.kind = p[i].count == 2 ? LINE : ARC;
    if (fit_model(s, trial.kind, trial.first, trial.count, &mt, NULL) == HUGE_VAL) continue;
    if (!meet(s, &p[ia], &md[ia], &trial, &mt, x) || !meet(s, &trial, &mt, &p[ib], &md[ib], x))
      continue;
    p[i].kind = trial.kind;
    bsfit__segment_refit(s, &p[i], &md[i]);
  }
}

/* Under noise one or two samples next to a corner may miss both sides' models by a little
** more than the tolerance allows a run (the run's test is on all its samples at once): a
** free run of them between two primitives would round the corner. Each is given to the
** neighbour whose model it lies nearer, when within twice the tolerance of it, and the
** free run goes. Returns the new number of pieces. */
static size_t absorb_strays(const seg_section *s, bsfit_piece *p, seg_model *md, size_t np) {
  size_t i = 0;
  while (i < np && np > 2) {
    size_t ia = (i + np - 1) % np, ib = (i + 1) % np, k, n = p[i].count;
    int to[2] = {0, 0}, ok = 1;
    if (p[i].kind != FREE || n == 0 || n > 2 || p[ia].kind == FREE || p[ib].kind == FREE ||
        (!s->closed && (i == 0 || i + 1 == np))) {
      i++;
      continue;
    }
    for (k = 0; k < n; k++) {
      const double *q = sample(s, p[i].first + k);
      double da = model_dist(&md[ia], q), db = model_dist(&md[ib], q);
      to[k] = da <= db ? 0 : 1;
      ok = ok && fmin(da, db) <= 2 * s->tol;
    }
    if (!ok || (n == 2 && to[0] > to[1])) {
      i++;
      continue;
    }
    for (k = 0; k < n; k++)
      if (to[k] == 0) p[ia].count++;
    for (k = 0; k < n; k++)
      if (to[k] == 1) p[ib].first = (p[ib].first + s->m - 1) % s->m, p[ib].count++;
    bsfit__segment_refit(s, &p[ia], &md[ia]);
    bsfit__segment_refit(s, &p[ib], &md[ib]);
    np = drop_piece(p, md, np, i);
  }
  return np;
}

/* Under noise an arc's run may stop a few samples short of its end (one sample a little
** past the tolerance of the whole run's fit), and a short line then takes the arc's last
** samples and meets it tangentially: a D's corner moved out along the line by a third of
** the noise. A line is the arc's next to it when the arc, refitted with the line's samples,
** holds them within twice the tolerance (as absorb_strays allows a stray) and its
** residual grows by at most the line's own plus 9 sigma^2 (the chi-square at 99% of the
** line's two parameters: the samples tell the line from the arc no better than chance).
** Returns 1 when the arc took the line. */
static int arc_takes_line(const seg_section *s, bsfit_piece *L, bsfit_piece *A, seg_model *ma,
                          int line_first) {
  size_t nl = piece_count(s, L), na = piece_count(s, A);
  size_t first = line_first ? L->first : A->first;
  size_t end = line_first ? (A->first + na) : (L->first + nl); /* one past, unwrapped below */
  size_t n = (end + s->m - first) % s->m;
  double rms = 0, max;
  seg_model mt;
  if (n != na + nl && n + 1 != na + nl) return 0; /* not next to each other */
  max = fit_model_from(s, ARC, first, n, ma, &mt, &rms);
  if (!(max <= 2 * s->tol)) return 0;
  if (rms * rms * (double)n > L->rms * L->rms * (double)nl + A->rms * A->rms * (double)na +
                                  9.0 * s->unit * s->unit)
    return 0;
  A->first = first, A->count = n;
  bsfit__segment_refit(s, A, ma);
  return 1;
}

/* arc_takes_line over the section (noisy sections); returns the new number of pieces */
static size_t arcs_take_lines(const seg_section *s, bsfit_piece *p, seg_model *md, size_t np) {
  size_t i = 0;
  while (i < np && np > 2) {
    size_t ia = (i + np - 1) % np, ib = (i + 1) % np;
    int to_b = p[ib].kind == ARC && (s->closed || i + 1 < np);
    int to_a = p[ia].kind == ARC && (s->closed || i > 0);
    if (p[i].kind == LINE && ((to_b && arc_takes_line(s, &p[i], &p[ib], &md[ib], 1)) ||
                              (to_a && arc_takes_line(s, &p[i], &p[ia], &md[ia], 0))))
      np = drop_piece(p, md, np, i);
    else
      i++;
  }
  return np;
}

/* On exact data a model seeded on a few samples that crowd into a small part of an arc
** (uneven sampling: 4 samples within a fraction of a degree) is fitted to rounding by many
** circles, and the run from there may stop short: the first samples of the arc are left
** as a short free run between the arc and the line before it, which the curve then
** bends through (a filleted hexagon of 400 uneven samples per side: 1e-3 of its size off).
** A free run of up to ABSORB_MAX samples between two primitives is given to them when
** their models, refitted with its samples, still explain every one: all to the one after,
** all to the one before, or split between them. Returns the new number of pieces. */
#define ABSORB_MAX 8
static int absorb_split(const seg_section *s, bsfit_piece *A, seg_model *ma, bsfit_piece *F,
                        bsfit_piece *B, seg_model *mb) {
  size_t n = F->count, k;
  seg_model ta, tb;
  for (k = n + 1; k-- > 0;) { /* k samples to A, n - k to B; all to B first */
    size_t kk = n - k;
    int ok_a = kk == 0 || fit_explains(s, A->kind, A->first, A->count + kk, ma, &ta);
    int ok_b = ok_a && (k == 0 || fit_explains(s, B->kind, B->first + s->m - k, B->count + k, mb, &tb));
    if (!ok_a || !ok_b) continue;
    A->count += kk;
    B->first = (B->first + s->m - k) % s->m, B->count += k;
    bsfit__segment_refit(s, A, ma);
    bsfit__segment_refit(s, B, mb);
    return 1;
  }
  return 0;
}

static size_t absorb_free_runs(const seg_section *s, bsfit_piece *p, seg_model *md, size_t np) {
  size_t i = 0;
  while (i < np && np > 2) {
    size_t ia = (i + np - 1) % np, ib = (i + 1) % np;
    if (p[i].kind != FREE || p[i].count == 0 || p[i].count > ABSORB_MAX || p[ia].kind == FREE ||
        p[ib].kind == FREE || (!s->closed && (i == 0 || i + 1 == np)) ||
        !absorb_split(s, &p[ia], &md[ia], &p[i], &p[ib], &md[ib])) {
      i++;
      continue;
    }
    np = drop_piece(p, md, np, i);
  }
  return np;
}

/* The ends of every piece; a free bridge (no samples) is inserted where two primitives
** do not meet. p has room for 2 np pieces; returns the new count. */
static size_t place_ends(const seg_section *s, bsfit_piece *p, seg_model *md, size_t np) {
  size_t i, n = np;
  for (i = 0; i < n; i++) {
    size_t ib = i + 1;
    if (ib == n) {
      if (!s->closed) break;
      ib = 0;
    }
    if (join_pieces(s, &p[i], &md[i], &p[ib], &md[ib])) continue;
    /* bridge: from A's last sample (on A) to B's first (on B) */
    memmove(&p[i + 2], &p[i + 1], (n - i - 1) * sizeof *p);
    memmove(&md[i + 2], &md[i + 1], (n - i - 1) * sizeof *md);
    memset(&p[i + 1], 0, sizeof *p);
    p[i + 1].kind = FREE;
    p[i + 1].first = (p[ib == 0 ? 0 : i + 2].first);
    p[i + 1].count = 0;
    md[i + 1].kind = FREE;
    n++;
    join_pieces(s, &p[i], &md[i], &p[i + 1], &md[i + 1]);
    join_pieces(s, &p[i + 1], &md[i + 1], &p[(i + 2) % n], &md[(i + 2) % n]);
    i++;
  }
  return n;
}

/* The joins of lines again after the fillets' refits: a line that gave a fillet its
** samples is refitted (bsfit__refit_fillets), and its join at the other end was still where
** its old model met its neighbour's, so the line drawn between its ends left its model's
** direction (31 of 2741 lines of the sparse noisy sweep, by up to 1.3 degrees, 27 where a
** gear of 3 samples per side read its noise 30 times too high; 42 of 1422 dense ones, by
** up to 0.1): its reported tangent was not the curve's. A join whose models no longer meet
** so keeps its place. */
static void rejoin_lines(const seg_section *s, bsfit_piece *p, seg_model *md, size_t np) {
  size_t i;
  for (i = np < 2 ? np : 0; i < np; i++) {
    size_t ia = (i + np - 1) % np;
    bsfit_piece A, B;
    if ((!s->closed && i == 0) || p[ia].kind == FREE || p[i].kind == FREE) continue;
    if (p[ia].kind != LINE && p[i].kind != LINE) continue;
    A = p[ia], B = p[i];
    if (join_pieces(s, &A, &md[ia], &B, &md[i]) && B.join == p[i].join) {
      p[ia] = A;
      p[i] = B;
    }
  }
}

/* the first and last pieces of an open section end at its first and last samples */
static void open_ends(const seg_section *s, bsfit_piece *p, const seg_model *md, size_t n) {
  double t[2];
  bsfit_piece *z = &p[n - 1];
  p[0].join = BSFIT_JOIN_END;
  if (p[0].kind == FREE)
    memcpy(p[0].start, sample(s, 0), sizeof p[0].start);
  else
    bsfit__model_foot(&md[0], sample(s, 0), p[0].start, p[0].t_start);
  if (z->kind == FREE)
    memcpy(z->end, sample(s, s->m - 1), sizeof z->end);
  else
    bsfit__model_foot(&md[n - 1], sample(s, s->m - 1), z->end, t), memcpy(z->t_end, t, sizeof t);
}

/* }==================================================================== */

/* the bounding-box diagonal */
double bsfit__segment_size(const double *pts, size_t m) {
  double lo[2] = {pts[0], pts[1]}, hi[2] = {pts[0], pts[1]};
  size_t i;
  int d;
  for (i = 1; i < m; i++)
    for (d = 0; d < 2; d++) {
      if (pts[2 * i + d] < lo[d]) lo[d] = pts[2 * i + d];
      if (pts[2 * i + d] > hi[d]) hi[d] = pts[2 * i + d];
    }
  return hypot(hi[0] - lo[0], hi[1] - lo[1]);
}

bsfit_err bsfit__segment_check(const double *pts, size_t m, int dim, const bsfit_segment_opts *o,
                               bsfit_status *st) {
  if (dim != 2) return bsfit__fail(st, BSFIT_EDIM, "segmentation needs 2D points, got dim %d", dim);
  if (pts == NULL || m < 3)
    return bsfit__fail(st, BSFIT_ETOOFEW, "segmentation needs at least 3 points, got %zu", m);
  if (!bsfit__all_finite(pts, 2 * m))
    return bsfit__fail(st, BSFIT_ENONFINITE, "points contain NaN or Inf");
  if (!(o->sigma >= 0) || !isfinite(o->sigma) || !(o->tol_sigma >= 0) || !isfinite(o->tol_sigma) ||
      !(o->param_cost >= 0) ||
      !(o->exact >= 0) || !(o->exact < 1) || o->min_line == 1 || o->min_arc == 1 || o->min_arc == 2)
    return bsfit__fail(st, BSFIT_EINVAL,
                       "segmentation options out of range (sigma %g, tol_sigma %g, "
                       "exact %g, min_line %zu, min_arc %zu, param_cost %g)",
                       o->sigma, o->tol_sigma, o->exact, o->min_line, o->min_arc, o->param_cost);
  if (!(bsfit__segment_size(pts, m) > 0))
    return bsfit__fail(st, BSFIT_EDEGENERATE, "all %zu points coincide", m);
  return BSFIT_OK;
}

/* The longest run of each kind: its length (rmax) and where it starts (from[kind]). */
/* Among runs of equal length, the one that starts after the longer step, then the one
** whose first sample is lowest in x (then y): the choice, and so where a closed section
** is cut, does not depend on which sample the data happened to start at (a filleted
** pentagon of 6 samples per side at noise 1e-4, its equal sides cut at the first of
** them, was 1e-4 or 1.6e-2 of its size off by the start), and a run that holds every
** sample of an open run of an outline, tried as closed, starts after its gap. */
static double step_into(const seg_section *s, size_t i) {
  const double *a = sample(s, i + s->m - 1), *b = sample(s, i);
  return hypot(b[0] - a[0], b[1] - a[1]);
}

static int starts_before(const seg_section *s, size_t i, size_t j) {
  const double *a = sample(s, i), *b = sample(s, j);
  double hi = step_into(s, i), hj = step_into(s, j);
  if (hi != hj) return hi > hj;
  return a[0] < b[0] || (a[0] == b[0] && a[1] < b[1]);
}

static void longest_runs(const seg_section *s, size_t *const len[2], size_t rmax[2],
                         size_t from[2]) {
  size_t i;
  int k;
  rmax[0] = rmax[1] = from[0] = from[1] = 0;
  for (i = 0; i < s->m; i++)
    for (k = 0; k < 2; k++)
      if (len[k][i] > rmax[k] || (len[k][i] == rmax[k] && rmax[k] > 0 && starts_before(s, i, from[k])))
        rmax[k] = len[k][i], from[k] = i;
}

/* The cheapest cover (pieces in order into p, from p[m + 1] as scratch). A closed
** section is cut where a piece starts: tried at the starts of the longest line and arc
** and at the samples after them, the cheapest kept. Returns the number of pieces. */
static size_t cover(seg_section *s, size_t *const len[2], cell *prim, cell *fr, start_heap heaps[2],
                    bsfit_piece *p) {
  size_t rmax[2], from[2], origins[4], no = 0, k, i, best_np = 0;
  double best = HUGE_VAL;
  longest_runs(s, len, rmax, from);
  s->longest[0] = rmax[0], s->longest[1] = rmax[1];
  for (k = 0; s->closed && k < 2; k++)
    if (rmax[k] > 0) {
      origins[no++] = from[k];
      origins[no++] = (from[k] + rmax[k]) % s->m;
    }
  if (no == 0) origins[no++] = 0;
  for (k = 0; k < no; k++) {
    size_t np = cheapest_cover(s, origins[k], len, heaps, prim, fr, p + s->m + 1);
    double c = fr[s->m - 1].cost < prim[s->m - 1].cost ? fr[s->m - 1].cost : prim[s->m - 1].cost;
    if (c < best) {
      best = c;
      best_np = np;
      for (i = 0; i < np; i++) p[i] = p[s->m + 1 + np - 1 - i]; /* traced backwards */
    }
  }
  return best_np;
}

/* Under noise a line may take the first samples of the fillet after it (they lie within
** the tolerance of both): each boundary sample goes to the neighbour whose model it
** fits better, and both are refitted; a few rounds. A piece keeps the distinct samples
** its model needs (a line of a circle's samples given three times each gave up a position
** and held two). */
static void rebalance(const seg_section *s, bsfit_piece *p, seg_model *md, size_t np) {
  size_t i, round;
  for (round = 0; round < 3; round++) {
    int moved = 0;
    for (i = 0; i < np; i++) {
      size_t ib = (i + 1) % np;
      bsfit_piece *A = &p[i], *B = &p[ib];
      if ((!s->closed && ib == 0) || np < 2 || A->kind == FREE || B->kind == FREE) continue;
      if (B->first != (A->first + A->count) % s->m) continue; /* shared sample: a corner */
      while (A->count > s->min_len[A->kind] + 1 &&
             distinct(s, A->kind, A->first, A->count - 1) >= s->min_len[A->kind] &&
             model_dist(&md[ib], sample(s, A->first + A->count - 1)) <
                 model_dist(&md[i], sample(s, A->first + A->count - 1)))
        A->count--, B->first = (B->first + s->m - 1) % s->m, B->count++, moved = 1;
      while (B->count > s->min_len[B->kind] + 1 &&
             distinct(s, B->kind, B->first + 1, B->count - 1) >= s->min_len[B->kind] &&
             model_dist(&md[i], sample(s, B->first)) < model_dist(&md[ib], sample(s, B->first)))
        B->count--, B->first = (B->first + 1) % s->m, A->count++, moved = 1;
      if (moved) {
        bsfit__segment_refit(s, A, &md[i]);
        bsfit__segment_refit(s, B, &md[ib]);
      }
    }
    if (!moved) break;
  }
}

/* The cross and dot products of the ends of step k of arc p (from sample first + k to the
** next), as vectors from its centre. */
static void step_products(const seg_section *s, const bsfit_piece *p, const seg_model *md,
                          size_t k, double *cross, double *dot) {
  const double *a = sample(s, p->first + k), *b = sample(s, p->first + k + 1);
  double ax = a[0] - md->circle.c[0], ay = a[1] - md->circle.c[1];
  double bx = b[0] - md->circle.c[0], by = b[1] - md->circle.c[1];
  *cross = ax * by - ay * bx, *dot = ax * bx + ay * by;
}

/* The turn of step k round the arc's centre, in its direction, in [0, 2 pi). */
static double step_turn(const seg_section *s, const bsfit_piece *p, const seg_model *md,
                        size_t k) {
  double cross, dot, t;
  step_products(s, p, md, k, &cross, &dot);
  t = md->orient * atan2(cross, dot);
  return t < 0 ? t + 2 * PI : t;
}

/* A stand-in for step k's turn, in [0, 4), growing with it (the diamond angle: y / (x + y)
** across the first quadrant, and so on; each form free of cancellation, a few roundings
** from the exact value, as the turn is from atan2). A step along the centre's axis (cross
** +-0) takes its turn from atan2, whose signed zeros decide it, as 0 or 2 (pi). */
static double step_rank(const seg_section *s, const bsfit_piece *p, const seg_model *md,
                        size_t k) {
  double cross, dot, y, x;
  step_products(s, p, md, k, &cross, &dot);
  y = md->orient * cross, x = dot;
  if (y == 0) return step_turn(s, p, md, k) == 0 ? 0 : 2;
  if (y > 0) return x >= 0 ? y / (x + y) : 1 + -x / (-x + y);
  return x < 0 ? 2 + -y / (-x - y) : 3 + x / (x - y);
}

/* Does one arc holding every sample of a closed section go round its circle? The closing
** step (from the last sample to the first, around the centre in the samples' direction)
** must be no longer than 1.5 times the longest of the others: half a circle is an open
** arc, however exactly it is sampled. The steps are ranked by the stand-in (an atan2 per
** step was 2.5% of a 10^5-sample circle); atan2 turns only those within 1e-13 of the
** largest stand-in so far. A step left out turns less than the one holding that largest (a
** turn taken) by far more than the stand-in's and atan2's roundings, so the longest is
** atan2's, to the bit. */
static int goes_round(const seg_section *s, const bsfit_piece *p, const seg_model *md) {
  double longest = 0, top = 0;
  size_t k;
  for (k = 0; k + 1 < p->count; k++) { /* the last step, k = count - 1, closes the section */
    double r = step_rank(s, p, md, k), t;
    if (r < top * (1 - 1e-13)) continue;
    if (r > top) top = r;
    t = step_turn(s, p, md, k);
    if (t > longest) longest = t;
  }
  return p->count == 0 || step_turn(s, p, md, p->count - 1) <= 1.5 * longest;
}

/* The angle of (x, y) in (-pi, pi], as step_wrap counts it: -0 is above the axis (atan2
** would put (-1, -0) at -pi). */
static double angle_of(double x, double y) { return atan2(y < 0 ? y : fabs(y), x); }

/* How the short step from a to b (vectors from the centre, neither zero) crosses the
** negative x axis, where the angle jumps between pi and -pi: +1 going counter-clockwise from
** above it (y >= 0) to below, -1 clockwise from below to above, 0 when it does not (it
** crosses the positive axis or none). A half turn counts as counter-clockwise, as
** atan2(+0, -1) = pi has it. */
static int step_wrap(double ax, double ay, double bx, double by) {
  double cross;
  if ((ay < 0) == (by < 0)) return 0;
  cross = ax * by - ay * bx;
  if (cross > 0 || (cross == 0 && ax * bx + ay * by < 0)) return ay < 0 ? 0 : 1;
  return ay < 0 ? -1 : 0;
}

/* How far an arc's samples turn round its centre, step by step in its direction (each step
** taken the short way). Samples all on one circle but not in order along it (cos i, sin i
** for i = 1 .. 9119 winds round 1451 times) fit the circle to rounding, yet are no arc:
** their one curve would miss them by the diameter. Along a run of samples off the centre
** the steps' angles add up to the angle between its ends plus a whole turn per crossing of
** the negative x axis: two atan2 per run, not one per step (those were 1.8 ms of the 33 of
** a 10^5-sample circle). A sample at the centre has no direction: its steps do not turn. */
static double arc_turn(const seg_section *s, const bsfit_piece *p, const seg_model *md) {
  double ends = 0, px = 0, py = 0;
  long wraps = 0;
  size_t k, i = p->first % s->m;
  for (k = 0; k < p->count; k++, i = i + 1 == s->m ? 0 : i + 1) {
    double x = s->pts[2 * i] - md->circle.c[0], y = s->pts[2 * i + 1] - md->circle.c[1];
    int on = x != 0 || y != 0, prev_on = k > 0 && (px != 0 || py != 0);
    if (on && prev_on) wraps += step_wrap(px, py, x, y);
    if (on && !prev_on) ends -= angle_of(x, y); /* a run starts here */
    if (!on && prev_on) ends += angle_of(px, py); /* and ended at the previous sample */
    px = x, py = y;
  }
  if (px != 0 || py != 0) ends += angle_of(px, py);
  return md->orient * (ends + 2 * PI * (double)wraps);
}

/* Models, ends and sweeps of the np pieces of the cover (p has room for 2 np). */
static size_t finish_pieces(const seg_section *s, bsfit_piece *p, seg_model *md, size_t np) {
  size_t i;
  for (i = 0; i < np; i++) {
    md[i].kind = p[i].kind;
    if (p[i].kind != FREE) bsfit__segment_refit(s, &p[i], &md[i]);
    /* a model that cannot be fitted on its piece's samples is none (a dense cover's arc
    ** moved onto every sample of a straight side, whose circle fit then fails, came out
    ** with max = inf): an arc becomes the line of its samples, else a free run */
    if (p[i].kind == ARC && !(p[i].max < HUGE_VAL)) {
      p[i].kind = md[i].kind = LINE;
      bsfit__segment_refit(s, &p[i], &md[i]);
    }
    if (p[i].kind != FREE && !(p[i].max < HUGE_VAL)) p[i].kind = md[i].kind = FREE;
    /* an arc goes round at most once (a closed section's whole circle closes that turn) */
    if (p[i].kind == ARC && arc_turn(s, &p[i], &md[i]) > 2 * PI * (1 + 1e-9))
      p[i].kind = md[i].kind = FREE;
  }
  np = s->noisy ? absorb_strays(s, p, md, np) : absorb_free_runs(s, p, md, np);
  short_runs(s, p, md, np);
  if (s->noisy) np = arcs_take_lines(s, p, md, np);
  rebalance(s, p, md, np);
  bsfit__cover_fillets(s, p, md, np);
  np = bsfit__split_corner_arcs(s, p, md, np);
  if (np == 1 && s->closed && p[0].kind == ARC &&
      goes_round(s, &p[0], &md[0])) { /* a whole circle */
    bsfit__model_foot(&md[0], sample(s, p[0].first), p[0].start, p[0].t_start);
    memcpy(p[0].end, p[0].start, sizeof p[0].end);
    memcpy(p[0].t_end, p[0].t_start, sizeof p[0].t_end);
    p[0].join = BSFIT_JOIN_TANGENT;
    set_arc_sweep(&p[0], &md[0], 1);
    return 1;
  }
  if (np == 1 && s->closed && p[0].kind == FREE) {
    memcpy(p[0].start, sample(s, p[0].first), sizeof p[0].start);
    memcpy(p[0].end, p[0].start, sizeof p[0].end);
    p[0].join = BSFIT_JOIN_TANGENT;
    return 1;
  }
  np = place_ends(s, p, md, np);
  if (!s->closed) open_ends(s, p, md, np);
  bsfit__refit_fillets(s, p, md, np);
  rejoin_lines(s, p, md, np);
  for (i = 0; i < np; i++) {
    if (p[i].kind == LINE) set_line_ends(&p[i], &md[i]);
    if (p[i].kind == ARC) set_arc_sweep(&p[i], &md[i], 0);
  }
  for (i = 0; i < np; i++) {
    const bsfit_piece *q = &p[(i + np - 1) % np];
    if (p[i].join != BSFIT_JOIN_CORNER) continue;
    p[i].turn = atan2(fabs(q->t_end[0] * p[i].t_start[1] - q->t_end[1] * p[i].t_start[0]),
                      q->t_end[0] * p[i].t_start[0] + q->t_end[1] * p[i].t_start[1]);
    p[i].evidence = bsfit__join_evidence(s, q, &md[(i + np - 1) % np], &p[i], &md[i], s->unit);
  }
  return np;
}

/* The standard error of an arc's radius at the noise (s->unit), from its samples round its
** centre: the radius's entry of the inverse of J^T J, J's rows (u_x, u_y, 1) for the unit
** vector u from the centre to each sample (the derivatives of the distance |x - c| - r by
** the centre and the radius): what a free arc's own samples say (a fillet's is
** bsfit__fillet_radius_se, arc_radius_se). */
static double radius_se(const seg_section *s, const bsfit_piece *p) {
  double M[6] = {0, 0, 0, 0, 0, 0}; /* xx xy x1 yy y1 11 */
  double det, cof;
  size_t k;
  if (!s->noisy) return 0.0;
  for (k = 0; k < p->count; k++) {
    const double *q = sample(s, p->first + k);
    double dx = q[0] - p->centre[0], dy = q[1] - p->centre[1], d = hypot(dx, dy);
    if (!(d > 0)) continue;
    dx /= d, dy /= d;
    M[0] += dx * dx, M[1] += dx * dy, M[2] += dx, M[3] += dy * dy, M[4] += dy, M[5] += 1;
  }
  cof = M[0] * M[3] - M[1] * M[1];
  det = M[0] * (M[3] * M[5] - M[4] * M[4]) - M[1] * (M[1] * M[5] - M[4] * M[2]) +
        M[2] * (M[1] * M[4] - M[3] * M[2]);
  if (!(det > 1e-12 * M[5] * M[5] * M[5]) || !(cof > 0)) return HUGE_VAL;
  return s->unit * sqrt(cof / det);
}

/* Is arc i a fillet: between two lines, its circle tangent to both (refitted so,
** segment_fillets.c)? */
static int is_fillet(const seg_section *s, const bsfit_piece *p, const seg_model *md, size_t np,
                     size_t i) {
  size_t ia = (i + np - 1) % np, ib = (i + 1) % np;
  if (np < 3 || p[ia].kind != LINE || p[ib].kind != LINE) return 0;
  if (!s->closed && (i == 0 || i + 1 == np)) return 0;
  return fabs(bsfit__line_dist(&md[ia].line, p[i].centre) - p[i].radius) <= 1e-9 * s->size &&
         fabs(bsfit__line_dist(&md[ib].line, p[i].centre) - p[i].radius) <= 1e-9 * s->size;
}

/* the standard error of arc i's radius: a fillet's with its lines' errors, else its own
** samples' (radius_se) */
static double arc_radius_se(const seg_section *s, const bsfit_piece *p, const seg_model *md,
                            size_t np, size_t i) {
  if (s->noisy && is_fillet(s, p, md, np, i))
    return bsfit__fillet_radius_se(s, &p[(i + np - 1) % np], &md[(i + np - 1) % np], &p[i],
                                   &p[(i + 1) % np], &md[(i + 1) % np]);
  return radius_se(s, &p[i]);
}

static void count_gaps(seg_section *s) {
  size_t i;
  s->gaps[0] = 0;
  if (s->moves) s->moves[0] = 0;
  for (i = 0; i < 2 * s->m; i++) {
    const double *p = sample(s, i), *q = sample(s, i + 1);
    double d = hypot(q[0] - p[0], q[1] - p[1]);
    s->gaps[i + 1] = s->gaps[i] + (d > s->tol);
    if (s->moves) s->moves[i + 1] = s->moves[i] + (d > 0);
  }
}

bsfit_err bsfit_segment(const double *pts, size_t m, int dim, const bsfit_segment_opts *opts,
                        bsfit_piece *pieces, size_t cap, size_t *count, const bsfit_allocator *a,
                        bsfit_status *st) {
  bsfit_segment_opts o;
  seg_section s;
  size_t *len[2] = {NULL, NULL}, np, i;
  cell *prim = NULL, *fr = NULL;
  bsfit_piece *buf = NULL;
  seg_model *md = NULL;
  start_heap heaps[2];
  size_t *heap_at = NULL, *heap_below = NULL;
  double *heap_key = NULL;
  bsfit__moments mom;
  bsfit_err e;
  memset(&o, 0, sizeof o);
  if (opts) o = *opts;
  if (count) *count = 0;
  if (count == NULL || (pieces == NULL && cap > 0))
    return bsfit__fail(st, BSFIT_EINVAL, "segmentation: count (and pieces when cap > 0) required");
  e = bsfit__segment_check(pts, m, dim, &o, st);
  if (e != BSFIT_OK) return e;
  s.pts = pts;
  s.m = m;
  s.closed = o.closed != 0;
  s.a = a;
  s.mom = NULL;
  memset(&mom, 0, sizeof mom);
  s.min_len[LINE] = o.min_line ? o.min_line : 3;
  s.min_len[ARC] = o.min_arc ? o.min_arc : 4;
  s.size = bsfit__segment_size(pts, m);
  s.tol = fmax((o.tol_sigma > 0 ? o.tol_sigma : 4.0) * o.sigma,
               fmax((o.exact > 0 ? o.exact : 1e-10) * s.size, rounding_floor(pts, m)));
  s.unit = s.tol / (o.tol_sigma > 0 ? o.tol_sigma : 4.0);
  s.noisy = o.sigma > 0 && s.tol <= (o.tol_sigma > 0 ? o.tol_sigma : 4.0) * o.sigma;
  s.gaps = bsfit__alloc(a, bsfit__mulsize(2 * m + 1, sizeof(size_t)));
  s.moves = s.noisy ? bsfit__alloc(a, bsfit__mulsize(2 * m + 1, sizeof(size_t))) : NULL;
  len[0] = bsfit__alloc(a, bsfit__mulsize(m, sizeof(size_t)));
  len[1] = bsfit__alloc(a, bsfit__mulsize(m, sizeof(size_t)));
  prim = bsfit__alloc(a, bsfit__mulsize(m, sizeof(cell)));
  fr = bsfit__alloc(a, bsfit__mulsize(m, sizeof(cell)));
  buf = bsfit__alloc(a, bsfit__mulsize(2 * m + 2, sizeof(bsfit_piece)));
  md = bsfit__alloc(a, bsfit__mulsize(2 * m + 2, sizeof(seg_model)));
  heap_at = bsfit__alloc(a, bsfit__mulsize(2 * m, sizeof(size_t)));
  heap_key = bsfit__alloc(a, bsfit__mulsize(2 * m, sizeof(double)));
  heap_below = bsfit__alloc(a, bsfit__mulsize(2 * m, sizeof(size_t)));
  if (!s.gaps || (s.noisy && !s.moves) || !len[0] || !len[1] || !prim || !fr || !buf || !md ||
      !heap_at || !heap_key || !heap_below) {
    e = bsfit__fail(st, BSFIT_ENOMEM, "out of memory for the segmentation of %zu points", m);
    goto done;
  }
  count_gaps(&s);
  if (s.noisy && m > BSFIT__DENSE_MOST) {
    np = bsfit__dense_cover(&s, &o, buf, &e, st);
    if (e != BSFIT_OK) goto done;
  } else {
    /* below 1e-6 of the size the moments' rounding is no longer far below sigma^2 */
    s.penalty = o.param_cost > 0 ? o.param_cost : RSS_PENALTY;
    if (s.noisy && isfinite(s.penalty) && o.sigma >= 1e-6 * s.size) {
      if (bsfit__moments_init(&mom, pts, m, a) != BSFIT_OK) {
        e = bsfit__fail(st, BSFIT_ENOMEM, "out of memory for the segmentation of %zu points", m);
        goto done;
      }
      s.mom = &mom;
    }
    if ((e = maximal_runs(&s, LINE, len[0])) != BSFIT_OK ||
        (e = maximal_runs(&s, ARC, len[1])) != BSFIT_OK) {
      e = bsfit__fail(st, e, "segmentation interrupted");
      goto done;
    }
    heaps[0].at = heap_at, heaps[0].key = heap_key, heaps[0].below = heap_below;
    heaps[1].at = heap_at + m, heaps[1].key = heap_key + m, heaps[1].below = heap_below + m;
    np = cover(&s, len, prim, fr, heaps, buf);
  }
  np = finish_pieces(&s, buf, md, np);
  for (i = 0; i < np; i++) buf[i].radius_se = buf[i].kind == ARC ? arc_radius_se(&s, buf, md, np, i) : 0.0;
  for (i = 0; i < np && i < cap; i++) pieces[i] = buf[i];
  *count = np;
  e = bsfit__ok(st);
done:
  bsfit__moments_free(&mom, a);
  bsfit__free(a, s.gaps, s.gaps ? (2 * m + 1) * sizeof(size_t): 0);
  bsfit__free(a, s.moves, s.moves ? (2 * m + 1) * sizeof(size_t): 0);
  bsfit__free(a, len[0], len[0] ? m * sizeof(size_t): 0);
  bsfit__free(a, len[1], len[1] ? m * sizeof(size_t): 0);
  bsfit__free(a, prim, prim ? m * sizeof(cell) : 0);
  bsfit__free(a, fr, fr ? m * sizeof(cell) : 0);
  bsfit__free(a, buf, buf ? (2 * m + 2) * sizeof(bsfit_piece) : 0);
  bsfit__free(a, md, md ? (2 * m + 2) * sizeof(seg_model) : 0);
  bsfit__free(a, heap_at, heap_at ? 2 * m * sizeof(size_t) : 0);
  bsfit__free(a, heap_key, heap_key ? 2 * m * sizeof(double) : 0);
  bsfit__free(a, heap_below, heap_below ? 2 * m * sizeof(size_t) : 0);
  return e;
}
