/*
** segment_corner_arcs.c
** Under noise, lines a sparse cover missed at a corner: an arc that meets neither way round
** a corner is tried as the two lines of that corner (bsfit__split_corner_arcs), and two
** lines that do not meet get the side between them (bsfit__split_bridges;
** segment_internal.h).
**
** The cover prices a piece at RSS_PENALTY sigma^2 per parameter (segment_cover.c), so that a
** letter's square stem end is not read as a semicircle; but the same price makes one arc
** cheaper than two lines across a short noisy corner. A serif's two sides of 4 to 6
** samples became one arc of radius 0.15 whose circle met neither neighbour: the join
** became a bridge, and the section lost its pieces. Where that happens, and only there,
** the arc's samples (and up to TAKE_BACK of each neighbour's next to it, which the arc
** may have taken from them) are tried as two lines, at Akaike's price.
**
** Likewise a short side (a serif's end, a step 8 to 30 sigma deep): its samples lie within
** the tolerance of the long sides' lines next to it, each of which takes a few, and the
** two lines meet nowhere between them. Their end samples are tried as the side's line.
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

/* a line of n >= min_len samples from first, within the tolerance and of `positions`
** distinct positions (a run's line: min_len) */
static int line_of(const seg_section *s, size_t first, size_t n, size_t positions, bsfit_piece *l,
                   seg_model *ml) {
  memset(l, 0, sizeof *l);
  l->kind = LINE;
  l->first = first % s->m;
  l->count = n;
  if (n < s->min_len[LINE] || distinct(s, LINE, first, n) < positions) return 0;
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
    if (!line_of(s, first, k, s->min_len[LINE], &t.l1, &t.m1) ||
        !line_of(s, first + k, n - k, s->min_len[LINE], &t.l2, &t.m2))
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

/* ---- a side between two pieces that do not meet ---- */

/* samples tried from each line's end for the side between them (12 instead: the same on
** the sweep and three other draws of it, within 2 sections) */
#define SIDE_TAKE 4

/* a side found between A and B: what it leaves of them and itself */
typedef struct side_split {
  bsfit_piece a, c, b;
  seg_model ma, mc, mb;
  double rss;
} side_split;

/* Does point x lie ahead of point o along the samples of piece q, from its first to its last? */
static int ahead(const seg_section *s, const bsfit_piece *q, const double *o, const double *x) {
  const double *f = sample(s, q->first), *l = sample(s, q->first + q->count - 1);
  return (x[0] - o[0]) * (l[0] - f[0]) + (x[1] - o[1]) * (l[1] - f[1]) > 0;
}

/* the pieces around a side's two: the one before A and the one after B (NULL when free or
** none) */
typedef struct side_around {
  const bsfit_piece *before, *after;
  const seg_model *mbefore, *mafter;
} side_around;

/* Does the side meet both pieces at corners, the three joins in the order of the samples
** (A's join with the piece before it, then A's with the side, the side's with B, B's with
** the piece after it, each on the way along the line between them)? */
static int side_meets(const seg_section *s, const side_split *t, const side_around *r) {
  double x1[2], x2[2], y[2];
  if (bsfit__segment_meet(s, &t->a, &t->ma, &t->c, &t->mc, x1) != BSFIT_JOIN_CORNER ||
      bsfit__segment_meet(s, &t->c, &t->mc, &t->b, &t->mb, x2) != BSFIT_JOIN_CORNER ||
      !ahead(s, &t->c, x1, x2))
    return 0;
  if (!(r->before && bsfit__segment_meet(s, r->before, r->mbefore, &t->a, &t->ma, y)))
    memcpy(y, sample(s, t->a.first), sizeof y);
  if (!ahead(s, &t->a, y, x1)) return 0;
  if (!(r->after && bsfit__segment_meet(s, &t->b, &t->mb, r->after, r->mafter, y)))
    memcpy(y, sample(s, t->b.first + t->b.count - 1), sizeof y);
  return ahead(s, &t->b, x2, y);
}

/* what a line keeps once a side takes k of its samples at its end (`at_end`) or start */
typedef struct kept {
  bsfit_piece p;
  seg_model md;
  int ok; /* still a piece of its kind, within the tolerance */
} kept;

static void keep(const seg_section *s, const bsfit_piece *q, const seg_model *mq, size_t k,
                 int at_end, kept *out) {
  out->p = *q, out->md = *mq;
  out->p.count -= k;
  if (!at_end) out->p.first = (q->first + k) % s->m;
  out->ok = out->p.count > 0 && still_piece(s, &out->p, &out->md);
}

/* The side of A's last ka and B's first kb samples (what they keep: a, b), when better than
** *best */
static void side_of(const seg_section *s, const bsfit_piece *A, const kept *a, const kept *b,
                    size_t ka, size_t kb, const side_around *r, side_split *best) {
  side_split t;
  if (!a->ok || !b->ok) return;
  memset(&t, 0, sizeof t);
  t.a = a->p, t.ma = a->md, t.b = b->p, t.mb = b->md;
  /* the side's line needs only 2 distinct positions, not a run's 3: a side 16 sigma long
  ** holds 4 samples within 2.5 tolerances, and its corners with the lines either side fix
  ** it. Asking 3, of test_segment_sides' 400 notched polygons at their true noise 194 were
  ** read as their own lines (252 now), 184 kept a bridge (112); through auto 118 of 300
  ** were within the floor (149) */
  if (!line_of(s, A->first + A->count - ka, ka + kb, 2, &t.c, &t.mc)) return;
  t.rss = fitted_rss(&t.a) + fitted_rss(&t.c) + fitted_rss(&t.b);
  if (t.rss < best->rss && side_meets(s, &t, r)) *best = t;
}

/* the piece before piece i (k < 0) or after it (k > 0), its index into *at, when it is a
** primitive and neither of the side's two (np >= 3), else NULL */
static const bsfit_piece *around(const seg_section *s, const bsfit_piece *p, size_t np, size_t i,
                                 int k, size_t *at) {
  size_t j = k < 0 ? (i + np - 1) % np : (i + 1) % np;
  if (!s->closed && ((k < 0 && i == 0) || (k > 0 && i + 1 == np))) return NULL;
  *at = j;
  return p[j].kind == FREE || np < 3 ? NULL : &p[j];
}

/* segment_internal.h */
size_t bsfit__split_bridges(const seg_section *s, bsfit_piece *p, seg_model *md, size_t np) {
  size_t i;
  if (!s->noisy || s->m > BSFIT__DENSE_MOST || np < 2) return np;
  for (i = 0; i < np; i++) {
    size_t ib = (i + 1) % np, ka, kb;
    bsfit_piece *A = &p[i], *B = &p[ib];
    side_split best;
    side_around r;
    kept a[SIDE_TAKE + 1], b[SIDE_TAKE + 1];
    double x[2];
    if ((!s->closed && ib == 0) || A->kind != LINE || B->kind != LINE ||
        B->first != (A->first + A->count) % s->m || bsfit__segment_meet(s, A, &md[i], B, &md[ib], x))
      continue;
    {
      size_t ja = 0, jb = 0;
      r.before = around(s, p, np, i, -1, &ja), r.after = around(s, p, np, ib, 1, &jb);
      r.mbefore = &md[ja], r.mafter = &md[jb];
    }
    for (ka = 0; ka <= SIDE_TAKE; ka++) { /* each line's part left, refitted once */
      keep(s, A, &md[i], ka < A->count ? ka : A->count, 1, &a[ka]);
      keep(s, B, &md[ib], ka < B->count ? ka : B->count, 0, &b[ka]);
    }
    best.rss = HUGE_VAL;
    for (ka = 0; ka <= SIDE_TAKE; ka++)
      for (kb = 0; kb <= SIDE_TAKE; kb++)
        if (ka + kb >= s->min_len[LINE]) side_of(s, A, &a[ka], &b[kb], ka, kb, &r, &best);
    if (!(best.rss < fitted_rss(A) + fitted_rss(B))) continue;
    *A = best.a, md[i] = best.ma;
    *B = best.b, md[ib] = best.mb;
    memmove(&p[i + 2], &p[i + 1], (np - i - 1) * sizeof *p);
    memmove(&md[i + 2], &md[i + 1], (np - i - 1) * sizeof *md);
    p[i + 1] = best.c, md[i + 1] = best.mc;
    np++;
    i++; /* past the side */
  }
  return np;
}
