/*
** segment_dense.c
** The cover of a dense noisy section (bsfit__dense_cover, segment_internal.h): read off
** every k-th sample, then moved onto every sample.
**
** Why: on a dense noisy section the cover sees models only through their tolerance. A
** line of a thousand samples is cut wherever one sample lies past 4 sigma (one in 16000
** does), a long side is taken by an arc of a radius a hundred times the size whose
** sagitta is below the noise, and the residual that tells the two apart (the weighed
** cover) costs m times the run length. Every k-th sample keeps the noise of each sample
** and the spacing of a section the cover was made for. The pieces' kinds and order come
** from there, each boundary is placed among the samples around it where the two models
** explain them best, and the caller refits every model on all its samples (segment.c);
** the corners' evidence then counts every sample next to them.
*/
#include "segment_internal.h"

#include <math.h>
#include <string.h>

/* features_internal.h */
double *bsfit__spread(const double *pts, size_t m, size_t first, size_t most,
                      const bsfit_allocator *a, size_t *msub, size_t *k) {
  double *sub;
  size_t i;
  *k = (m + most - 1) / most, *msub = (m + *k - 1) / *k;
  sub = bsfit__alloc(a, bsfit__mulsize(2 * *msub, sizeof *sub));
  if (sub)
    for (i = 0; i < *msub; i++) memcpy(sub + 2 * i, pts + 2 * ((first + i * *k) % m), 2 * sizeof *sub);
  return sub;
}

static double square(double x) { return x * x; }

/* unwrapped subsample index u of a section of m samples read every k-th (msub of them)
** from sample `first` -> unwrapped index of the section */
static size_t full_index(size_t u, size_t msub, size_t m, size_t k, size_t first) {
  return u / msub * m + first + u % msub * k;
}

/* The first sample of B, A the piece before it: ea is A's last sample, sb B's first (from
** the subsample, unwrapped; ea = sb when they share it). The boundary goes where A's and B's
** models explain the samples from ea + 1 - reach to sb + reach best (between them when reach
** is 0, which keeps each piece every sample it had); with a free piece, half-way. */
static size_t boundary(const seg_section *s, const bsfit_piece *A, const bsfit_piece *B,
                       size_t ea, size_t sb, size_t reach) {
  size_t lo = ea + 1 > reach ? ea + 1 - reach : 0, hi = sb + reach, j, at = hi;
  double cost = 0, best;
  if (ea >= sb) return sb;
  if (A->kind == FREE || B->kind == FREE) return (ea + sb + 1) / 2;
  for (j = lo; j < hi; j++) cost += square(bsfit__piece_dist(A, sample(s, j)));
  best = cost;
  for (j = hi; j-- > lo;) { /* sample j moves from A to B: B starts at j */
    const double *q = sample(s, j);
    cost += square(bsfit__piece_dist(B, q)) - square(bsfit__piece_dist(A, q));
    if (cost < best) best = cost, at = j;
  }
  return at;
}

/* The boundaries of the n sub-pieces with samples (idx: their places in q) on the section,
** into bound (unwrapped; bound[n] closes). A closed section's indices are unwrapped from
** one turn on, so that the boundary before the first piece, found in the turn before, is
** not below 0. Returns 0 when a piece keeps fewer samples than its kind needs, or fewer
** distinct ones (segment_internal.h: distinct; the cover's own rule for a run). */
static int place_boundaries(const seg_section *s, const bsfit_piece *q, const size_t *idx,
                            size_t n, size_t msub, size_t k, size_t first, size_t reach,
                            size_t *bound) {
  size_t i, turn = s->closed ? msub : 0, origin = q[idx[0]].first;
#define FIRST(i) (turn + origin + (q[idx[i]].first + msub - origin) % msub)
#define LAST(i) (FIRST(i) + q[idx[i]].count - 1)
  for (i = 1; i < n; i++)
    bound[i] = boundary(s, &q[idx[i - 1]], &q[idx[i]], full_index(LAST(i - 1), msub, s->m, k, first),
                        full_index(FIRST(i), msub, s->m, k, first), reach);
  if (!s->closed)
    bound[0] = 0, bound[n] = s->m;
  else if (n == 1)
    bound[0] = full_index(FIRST(0), msub, s->m, k, first), bound[1] = bound[0] + s->m;
  else /* the closing boundary: the last piece in the turn before the first */
    bound[0] = boundary(s, &q[idx[n - 1]], &q[idx[0]], full_index(LAST(n - 1) - msub, msub, s->m, k, first),
                        full_index(FIRST(0), msub, s->m, k, first), reach),
    bound[n] = bound[0] + s->m;
#undef FIRST
#undef LAST
  for (i = 0; i < n; i++) {
    int kind = q[idx[i]].kind;
    if (bound[i + 1] < bound[i] + (kind == FREE ? 1 : s->min_len[kind])) return 0;
    /* (after the count: distinct reads the samples of a piece of one at least) */
    if (kind != FREE &&
        distinct(s, kind, bound[i] % s->m, bound[i + 1] - bound[i]) < s->min_len[kind])
      return 0;
  }
  return 1;
}

/* The sub-pieces q (np of them; bridges of no samples left out: the refitted models decide
** where they meet) moved onto the section's samples, into p; idx, bound: room for np + 1.
** Each boundary is looked for within k samples of its place in the subsample (the cover of
** every k-th sample may put it a sample off); where that leaves a piece too few samples,
** every boundary is kept between its two pieces' subsample samples. Returns their number. */
static size_t move_pieces(const seg_section *s, const bsfit_piece *q, size_t np, size_t msub,
                          size_t k, size_t first, size_t *idx, size_t *bound, bsfit_piece *p) {
  size_t i, n = 0;
  for (i = 0; i < np; i++)
    if (q[i].count > 0) idx[n++] = i;
  if (n == 0) return 0;
  if (!place_boundaries(s, q, idx, n, msub, k, first, k, bound))
    place_boundaries(s, q, idx, n, msub, k, first, 0, bound);
  for (i = 0; i < n; i++) {
    memset(&p[i], 0, sizeof p[i]);
    p[i].kind = q[idx[i]].kind;
    p[i].first = bound[i] % s->m;
    p[i].count = bound[i + 1] - bound[i];
  }
  return n;
}

/* segment_internal.h */
size_t bsfit__dense_cover(const seg_section *s, const bsfit_segment_opts *o, bsfit_piece *p,
                          bsfit_err *e, bsfit_status *st) {
  size_t k, msub = 0, np = 0, pbytes = 0, bbytes = 0;
  size_t first = s->start;
  double *sub = bsfit__spread(s->pts, s->m, first, BSFIT__DENSE_MOST, s->a, &msub, &k);
  bsfit_piece *q = NULL;
  size_t *bound = NULL; /* and the pieces' places in q, after it */
  pbytes = bsfit__mulsize(2 * msub + 2, sizeof *q), bbytes = bsfit__mulsize(4 * msub + 6, sizeof *bound);
  q = bsfit__alloc(s->a, pbytes);
  bound = bsfit__alloc(s->a, bbytes);
  if (!sub || !q || !bound) {
    *e = bsfit__fail(st, BSFIT_ENOMEM, "out of memory for the segmentation of %zu points", s->m);
    goto done;
  }
  *e = bsfit_segment(sub, msub, 2, o, q, 2 * msub + 2, &np, s->a, st);
  if (*e == BSFIT_OK && (np = move_pieces(s, q, np, msub, k, first, bound + 2 * msub + 3, bound, p)) == 0)
    *e = bsfit__fail(st, BSFIT_EDEGENERATE, "segmentation: no piece on every %zu-th of %zu points", k, s->m);
done:
  bsfit__free(s->a, sub, sub ? 2 * msub * sizeof *sub : 0);
  bsfit__free(s->a, q, q ? pbytes : 0);
  bsfit__free(s->a, bound, bound ? bbytes : 0);
  return *e == BSFIT_OK ? np : 0;
}
