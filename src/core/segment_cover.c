/*
** segment_cover.c
** The cover of least cost of a segmentation: the pieces (lines, arcs, free runs) that
** cover a section's samples at the least cost in parameters (and, on noisy sections, in
** residual), found by dynamic programming over the maximal runs (segment_runs.c); a
** closed section is cut where the longest runs start.
*/
#include "segment_internal.h"

#include <math.h>
#include <string.h>

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

/* features_internal.h. Squared steps: the order is the steps', and a 10^5-sample section
** asks for it at every sample (hypot there cost 3 ms). */
int bsfit__starts_before(const double *pts, size_t m, size_t i, size_t j) {
  const double *ia = pts + 2 * ((i + m - 1) % m), *ib = pts + 2 * i;
  const double *ja = pts + 2 * ((j + m - 1) % m), *jb = pts + 2 * j;
  double hi = (ib[0] - ia[0]) * (ib[0] - ia[0]) + (ib[1] - ia[1]) * (ib[1] - ia[1]);
  double hj = (jb[0] - ja[0]) * (jb[0] - ja[0]) + (jb[1] - ja[1]) * (jb[1] - ja[1]);
  if (hi != hj) return hi > hj;
  return ib[0] < jb[0] || (ib[0] == jb[0] && ib[1] < jb[1]);
}

/* bsfit_features.h */
bsfit_err bsfit_segment_start(const double *pts, size_t m, int dim, size_t *first,
                              bsfit_status *st) {
  if (first) *first = 0;
  if (first == NULL) return bsfit__fail(st, BSFIT_EINVAL, "segmentation start: first required");
  if (dim != 2) return bsfit__fail(st, BSFIT_EDIM, "segmentation start needs 2D points, got dim %d", dim);
  if (pts == NULL || m == 0) return bsfit__fail(st, BSFIT_ETOOFEW, "segmentation start needs a point");
  if (!bsfit__all_finite(pts, 2 * m)) return bsfit__fail(st, BSFIT_ENONFINITE, "points contain NaN or Inf");
  *first = bsfit__closed_start(pts, m);
  return bsfit__ok(st);
}

/* features_internal.h */
size_t bsfit__closed_start(const double *pts, size_t m) {
  size_t i, best = 0;
  for (i = 1; i < m; i++)
    if (bsfit__starts_before(pts, m, i, best)) best = i;
  return best;
}

/* The longest run of each kind: its length (rmax) and where it starts (from[kind]).
** Among runs of equal length, the one that starts first in bsfit__starts_before's order
** (after the longer step, then lowest in x, then y): the choice, and so where a closed
** section is cut, does not depend on which sample the data happened to start at (a
** filleted pentagon of 6 samples per side at noise 1e-4, its equal sides cut at the first
** of them, was 1e-4 or 1.6e-2 of its size off by the start), and a run that holds every
** sample of an open run of an outline, tried as closed, starts after its gap. */
static void longest_runs(const seg_section *s, size_t *const len[2], size_t rmax[2],
                         size_t from[2]) {
  size_t i;
  int k;
  rmax[0] = rmax[1] = from[0] = from[1] = 0;
  for (i = 0; i < s->m; i++)
    for (k = 0; k < 2; k++)
      if (len[k][i] > rmax[k] || (len[k][i] == rmax[k] && rmax[k] > 0 &&
                                   bsfit__starts_before(s->pts, s->m, i, from[k])))
        rmax[k] = len[k][i], from[k] = i;
}

/* The cheapest cover (pieces in order into p, from p[m + 1] as scratch). A closed
** section is cut where a piece starts: tried at the starts of the longest line and arc
** and at the samples after them, the cheapest kept. Returns the number of pieces. */
size_t bsfit__segment_cover(seg_section *s, size_t *const len[2], cell *prim, cell *fr,
                            start_heap heaps[2], bsfit_piece *p) {
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
