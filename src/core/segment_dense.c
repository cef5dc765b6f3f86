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
** and the spacing of a section the cover was made for; the pieces' kinds and order come
** from there, each boundary is then placed among the k samples around it where the two
** neighbouring models explain them best, and the caller refits every model on all its
** samples (the corners' evidence then counts every sample next to them).
*/
#include "segment_internal.h"

#include <math.h>
#include <string.h>

/* unwrapped subsample index u of a section of m samples read every k-th (msub of them)
** -> unwrapped index of the section */
static size_t full_index(size_t u, size_t msub, size_t m, size_t k) {
  return u / msub * m + u % msub * k;
}

/* distance of sample q to the model of a piece of the subsample's segmentation */
static double piece_model_dist(const bsfit_piece *p, const double *q) {
  if (p->kind == BSFIT_PIECE_ARC)
    return fabs(hypot(q[0] - p->centre[0], q[1] - p->centre[1]) - p->radius);
  return fabs((q[0] - p->start[0]) * p->t_start[1] - (q[1] - p->start[1]) * p->t_start[0]);
}

/* The first sample of B among [lo, hi] (unwrapped; A holds the samples before it) where
** A's and B's models explain the samples of [lo - 1, hi] best: O(hi - lo). */
static size_t best_split(const seg_section *s, const bsfit_piece *A, const bsfit_piece *B,
                         size_t lo, size_t hi) {
  double cost = 0, best;
  size_t j, at = lo;
  for (j = lo; j <= hi; j++) cost += pow(piece_model_dist(B, sample(s, j)), 2);
  best = cost;
  for (j = lo; j < hi; j++) { /* sample j moves from B to A: the split goes to j + 1 */
    const double *q = sample(s, j);
    cost += pow(piece_model_dist(A, q), 2) - pow(piece_model_dist(B, q), 2);
    if (cost < best) best = cost, at = j + 1;
  }
  return at;
}

/* where piece b starts in the section (unwrapped), a the piece before it: sub-indices
** of a's first and last samples and of b's first and last are fa, la, fb, lb (unwrapped,
** increasing; la = fb when they share a sample); each keeps a sample at least */
static size_t boundary(const seg_section *s, const bsfit_piece *a, const bsfit_piece *b,
                       const size_t sub[4], size_t msub, size_t k) {
  size_t from = full_index(sub[0], msub, s->m, k), ea = full_index(sub[1], msub, s->m, k);
  size_t sb = full_index(sub[2], msub, s->m, k), to = full_index(sub[3], msub, s->m, k), lo, hi;
  if (a->kind == FREE || b->kind == FREE) return ea == sb ? sb : (ea + sb + 1) / 2;
  lo = ea + 1 > k ? ea + 1 - k : 0;
  if (lo < from + 1) lo = from + 1;
  hi = sb + k < to ? sb + k : to;
  if (lo > hi) lo = hi;
  return best_split(s, a, b, lo, hi);
}

/* The sub-pieces q (np of them, count-0 bridges left out) moved onto the section's
** samples, into p; returns their number (0: out of memory, or no piece with samples). */
static size_t move_pieces(const seg_section *s, const bsfit_piece *q, size_t np, size_t msub,
                          size_t k, bsfit_piece *p) {
  /* a closed section's indices are unwrapped from one turn on, so that the boundary
  ** before the first piece, found in the turn before, is not below 0 */
  size_t i, n = 0, origin = 0, turn = s->closed ? msub : 0, bytes = 4 * (np + 1) * sizeof(size_t);
  size_t *mem = bsfit__alloc(s->a, bytes), *bound, *fu, *lu, *idx;
  if (!mem) return 0;
  bound = mem, fu = mem + np + 1, lu = mem + 2 * (np + 1), idx = mem + 3 * (np + 1);
  for (i = 0; i < np; i++) {
    if (q[i].count == 0) continue;
    if (n == 0) origin = q[i].first;
    idx[n] = i;
    fu[n] = turn + origin + (q[i].first + msub - origin) % msub;
    lu[n] = fu[n] + q[i].count - 1;
    n++;
  }
  for (i = 1; i < n; i++) {
    size_t sub[4] = {fu[i - 1], lu[i - 1], fu[i], lu[i]};
    bound[i] = boundary(s, &q[idx[i - 1]], &q[idx[i]], sub, msub, k);
  }
  if (n > 0 && s->closed) {
    size_t sub[4] = {fu[n - 1] - msub, lu[n - 1] - msub, fu[0], lu[0]};
    bound[0] = n > 1 ? boundary(s, &q[idx[n - 1]], &q[idx[0]], sub, msub, k)
                     : full_index(fu[0], msub, s->m, k);
    bound[n] = bound[0] + s->m;
  } else if (n > 0) {
    bound[0] = 0, bound[n] = s->m;
  }
  for (i = 0; i < n; i++) {
    memset(&p[i], 0, sizeof p[i]);
    p[i].kind = q[idx[i]].kind;
    p[i].first = bound[i] % s->m;
    p[i].count = bound[i + 1] > bound[i] ? bound[i + 1] - bound[i] : 0;
  }
  bsfit__free(s->a, mem, bytes);
  return n;
}

/* segment_internal.h */
size_t bsfit__dense_cover(const seg_section *s, const bsfit_segment_opts *o, size_t most,
                          bsfit_piece *p, bsfit_err *e, bsfit_status *st) {
  size_t k = (s->m + most - 1) / most, msub = (s->m + k - 1) / k, np = 0, i;
  size_t pbytes = bsfit__mulsize(2 * msub + 2, sizeof(bsfit_piece));
  double *sub = bsfit__alloc(s->a, bsfit__mulsize(2 * msub, sizeof *sub));
  bsfit_piece *q = bsfit__alloc(s->a, pbytes);
  *e = BSFIT_OK;
  if (!sub || !q) {
    *e = bsfit__fail(st, BSFIT_ENOMEM, "out of memory for the segmentation of %zu points", s->m);
    goto done;
  }
  for (i = 0; i < msub; i++) memcpy(sub + 2 * i, s->pts + 2 * i * k, 2 * sizeof *sub);
  *e = bsfit_segment(sub, msub, 2, o, q, 2 * msub + 2, &np, s->a, st);
  if (*e != BSFIT_OK) goto done;
  np = move_pieces(s, q, np, msub, k, p);
  if (np == 0)
    *e = bsfit__fail(st, BSFIT_ENOMEM, "out of memory for the segmentation of %zu points", s->m);
done:
  bsfit__free(s->a, sub, sub ? 2 * msub * sizeof *sub : 0);
  bsfit__free(s->a, q, q ? pbytes : 0);
  return *e == BSFIT_OK ? np : 0;
}
