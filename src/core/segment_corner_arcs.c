/*
** segment_corner_arcs.c
** Under noise, an arc of a sparse cover that meets neither way round a corner is tried as
** the two lines of that corner (bsfit__split_corner_arcs, segment_internal.h).
**
** The cover prices a piece at RSS_PENALTY sigma^2 per parameter (segment_cover.c), so that a
** letter's square stem end is not read as a semicircle; but the same price makes one arc
** cheaper than two lines across a short noisy corner. A serif's two sides of 4 to 6
** samples became one arc of radius 0.15 whose circle met neither neighbour: the join
** became a bridge, and the section lost its pieces. Where that happens, and only there,
** the arc's samples (and up to TAKE_BACK of each neighbour's next to it, which the arc
** may have taken from them) are tried as two lines, at Akaike's price.
*/
#include <math.h>
#include <string.h>

#include "segment_internal.h"

/* samples tried back from each neighbour */
#define TAKE_BACK 2
/* the split's price over the arc, in sigma^2: Akaike's 2 for the one parameter more of two
** lines (without a price, a gear's true arcs were split into chords) */
#define SPLIT_PRICE 2.0

/* the neighbours of piece i, or NULL where an open section has none or it is free */
static bsfit_piece *neighbour(const seg_section *s, bsfit_piece *p, size_t np, size_t i,
                              int after) {
  size_t j;
  if (!s->closed && (after ? i + 1 == np : i == 0)) return NULL;
  j = after ? (i + 1) % np : (i + np - 1) % np;
  return p[j].kind == FREE ? NULL : &p[j];
}

/* a split of the arc's run and what it leaves of its neighbours */
typedef struct corner_split {
  bsfit_piece a, l1, l2, b; /* a, b: the neighbours as they are left (count 0: none) */
  seg_model ma, m1, m2, mb;
  double rss;
} corner_split;

/* refits q (a neighbour, count left) and whether it is still a piece of its kind */
static int still_piece(const seg_section *s, bsfit_piece *q, seg_model *mq) {
  if (q->count == 0) return 1;
  if (q->count < s->min_len[q->kind] ||
      distinct(s, q->kind, q->first, q->count) < s->min_len[q->kind])
    return 0;
  mq->kind = q->kind;
  bsfit__segment_refit(s, q, mq);
  return q->max <= s->tol;
}

/* a line of n samples from first, within the tolerance and of 3 distinct positions */
static int line_of(const seg_section *s, size_t first, size_t n, bsfit_piece *l, seg_model *ml) {
  memset(l, 0, sizeof *l);
  l->kind = LINE;
  l->first = first % s->m;
  l->count = n;
  if (n < s->min_len[LINE] || distinct(s, LINE, first, n) < s->min_len[LINE]) return 0;
  ml->kind = LINE;
  bsfit__segment_refit(s, l, ml);
  return l->max <= s->tol;
}

/* Does the split make four pieces that meet? */
static int split_meets(const seg_section *s, const corner_split *t) {
  double x[2];
  if (t->a.count > 0 && !bsfit__segment_meet(s, &t->a, &t->ma, &t->l1, &t->m1, x)) return 0;
  if (bsfit__segment_meet(s, &t->l1, &t->m1, &t->l2, &t->m2, x) != BSFIT_JOIN_CORNER) return 0;
  return t->b.count == 0 || bsfit__segment_meet(s, &t->l2, &t->m2, &t->b, &t->mb, x);
}

/* The best split of X's samples and ka, kb of its neighbours' (A, B may be NULL) into two
** lines that meet each other and the neighbours; its residual is HUGE_VAL when none does. */
static void best_split(const seg_section *s, const bsfit_piece *A, const seg_model *ma,
                       const bsfit_piece *X, const bsfit_piece *B, const seg_model *mb,
                       size_t ka, size_t kb, corner_split *best) {
  size_t n = X->count + ka + kb, first = (X->first + s->m - ka) % s->m, k;
  corner_split t;
  memset(&t, 0, sizeof t);
  if (A) t.a = *A, t.ma = *ma, t.a.count -= ka;
  if (B) t.b = *B, t.mb = *mb, t.b.first = (B->first + kb) % s->m, t.b.count -= kb;
  if ((ka && !still_piece(s, &t.a, &t.ma)) || (kb && !still_piece(s, &t.b, &t.mb))) return;
  for (k = s->min_len[LINE]; k + s->min_len[LINE] <= n; k++) {
    if (!line_of(s, first, k, &t.l1, &t.m1) || !line_of(s, first + k, n - k, &t.l2, &t.m2))
      continue;
    t.rss = fitted_rss(&t.l1) + fitted_rss(&t.l2) + fitted_rss(&t.a) + fitted_rss(&t.b);
    if (t.rss < best->rss && split_meets(s, &t)) *best = t;
  }
}

/* Does arc i meet both its primitive neighbours? */
static int arc_meets(const seg_section *s, const bsfit_piece *p, const seg_model *md, size_t np,
                     size_t i, const bsfit_piece *A, const bsfit_piece *B) {
  double x[2];
  size_t ia = (i + np - 1) % np, ib = (i + 1) % np;
  return (!A || bsfit__segment_meet(s, A, &md[ia], &p[i], &md[i], x)) &&
         (!B || bsfit__segment_meet(s, &p[i], &md[i], B, &md[ib], x));
}

/* arc i replaced by the split's two lines (p, md have room for one more); returns np + 1 */
static size_t apply_split(bsfit_piece *p, seg_model *md, size_t np, size_t i,
                          const corner_split *t, bsfit_piece *A, bsfit_piece *B) {
  size_t ia = (i + np - 1) % np, ib = (i + 1) % np;
  if (A) *A = t->a, md[ia] = t->ma;
  if (B) *B = t->b, md[ib] = t->mb;
  memmove(&p[i + 2], &p[i + 1], (np - i - 1) * sizeof *p);
  memmove(&md[i + 2], &md[i + 1], (np - i - 1) * sizeof *md);
  p[i] = t->l1, md[i] = t->m1;
  p[i + 1] = t->l2, md[i + 1] = t->m2;
  return np + 1;
}

/* segment_internal.h */
size_t bsfit__split_corner_arcs(const seg_section *s, bsfit_piece *p, seg_model *md, size_t np) {
  size_t i;
  if (!s->noisy || s->m > BSFIT__DENSE_MOST || np < 2) return np;
  for (i = 0; i < np; i++) {
    bsfit_piece *A = neighbour(s, p, np, i, 0), *B = neighbour(s, p, np, i, 1);
    size_t ia = (i + np - 1) % np, ib = (i + 1) % np, ka, kb;
    corner_split best;
    double arc_rss;
    if (p[i].kind != ARC || (!A && !B) || A == B || arc_meets(s, p, md, np, i, A, B)) continue;
    arc_rss = fitted_rss(&p[i]) + (A ? fitted_rss(A) : 0) + (B ? fitted_rss(B) : 0);
    best.rss = HUGE_VAL;
    for (ka = 0; ka <= (A ? TAKE_BACK : 0); ka++)
      for (kb = 0; kb <= (B ? TAKE_BACK : 0); kb++)
        if ((!A || ka < A->count) && (!B || kb < B->count))
          best_split(s, A, &md[ia], &p[i], B, &md[ib], ka, kb, &best);
    if (!(best.rss + SPLIT_PRICE * s->unit * s->unit < arc_rss)) continue;
    np = apply_split(p, md, np, i, &best, A, B);
    i++; /* past the second line */
  }
  return np;
}
