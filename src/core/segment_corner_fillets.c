/*
** segment_corner_fillets.c
** Corners between two lines tried as the fillet tangent to both, under noise on sparse
** sections (bsfit__fillet_corners; docs/auto.md, step 8).
*/
#include "segment_internal.h"

#include <math.h>
#include <stddef.h>
#include <string.h>

/* Corners that are fillets (bsfit__fillet_corners).
**
** The cover's lines take every sample within the tolerance (4 sigma), so a fillet whose
** middle lies a few sigma off its lines' corner is held by them: its end samples go to
** the lines, the rest to neither (a corner, the lines tilted towards it). At the noise
** itself the cover then leaves a residual of 1.4 to 1.9 times the noise, and the noise
** search (segment_sigma.c) only matched at twice the noise, where the corner stood (a
** rounded rectangle with fillets of radius 1.5 and 4 samples each at noise 1e-3 of its size:
** twice the floor off). So each corner between two lines is tried as the fillet tangent to
** both, taking up to CORNER_TAKE samples of each line's end next to it, the lines refitted
** without them, and kept where it saves more than CORNER_FILLET_PRICE sigma^2. A try is
** judged as it will stand: its samples claimed and its radius refitted (settle_fillet), and
** both its lines still running forwards to their other joins (line_runs_forward): a fillet
** too wide for a short line, or two whose tangent points pass each other on one, made lines
** that ran backwards (5 of 3130 lines of the sweep). A chamfer (a short line between two
** corners) was tried as a fillet too: 2 more of 780 filleted polygons within the floor, 16
** fewer of 300 chamfered ones (real chamfers rounded), not kept. */

/* samples tried from each line's end next to a corner, and the least a fillet takes (its
** one parameter, the radius, and two degrees of freedom: two samples at true sharp
** corners of letters of 3 per side made fillets of them) */
#define CORNER_TAKE 4
#define CORNER_LEAST 3
/* What a fillet must save over the corner, in sigma^2: one parameter more, chosen among up
** to 25 ways to take the samples. Measured on the sweep, its three held-out draws (2340),
** 300 filleted and 300 chamfered polygons (test_segment_corner_fillets) and 840 smooth
** sections: 6: 257, 1542, 143, 115; 9: 255, 1536, 143, 117, and a smooth star of 120
** samples at noise 1e-3 through pieces with 2 corners; 12: 255, 1527, 139, 116; 16: 257,
** 1516, 133, 116; 20: 257, 1505, 127, 115. 16 keeps the smooth sections and the sweep;
** 12 gains 11 held-out sections for 2 of the sweep's (before the lines had to keep running
** forwards, 9 and 12 rounded sharp corners: 30 and 22 sections farther off). */
#define CORNER_FILLET_PRICE 16.0
/* Lines of at most this many samples: the fillets their lines hold are those of sparse
** sections (a fillet of many samples is an arc of the cover). On a dense section's every
** k-th sample, the lines of 20 to 70 samples along a smooth star's bends took fillets
** between them, and the star became lines and arcs with corners. */
#define CORNER_LINE_MOST 24

/* line piece q (what is left of one) refitted, and whether it is still a line */
static int still_line(const seg_section *s, bsfit_piece *q, seg_model *mq) {
  if (q->count < s->min_len[LINE] || distinct(s, LINE, q->first, q->count) < s->min_len[LINE])
    return 0;
  bsfit__segment_refit(s, q, mq);
  return q->max <= s->tol;
}

/* what is left of a line next to a corner after giving k samples to a fillet */
typedef struct line_left {
  bsfit_piece p;
  seg_model md;
  int ok;
} line_left;

/* left[k]: line L (model ml) without its k samples next to the corner (its last when
** at_end, else its first), k = 0 .. CORNER_TAKE */
static void lines_left(const seg_section *s, const bsfit_piece *L, const seg_model *ml, int at_end,
                       line_left *left) {
  size_t k;
  for (k = 0; k <= CORNER_TAKE; k++) {
    left[k].p = *L, left[k].md = *ml, left[k].ok = k < L->count;
    if (!left[k].ok || k == 0) continue;
    left[k].p.count -= k;
    if (!at_end) left[k].p.first = (L->first + k) % s->m;
    left[k].ok = still_line(s, &left[k].p, &left[k].md);
  }
}

/* the pieces before line A and after line B of a corner (NULL at an open section's ends) */
typedef struct seg_neighbours {
  const bsfit_piece *before, *after;
  const seg_model *mbefore, *mafter;
} seg_neighbours;

/* whether both lines of fillet try t still run forwards (bsfit__line_runs_forward) */
static int keeps_lines(const seg_section *s, const seg_neighbours *nb, seg_fillet_try *t) {
  return bsfit__line_runs_forward(s, nb->before, nb->mbefore, &t->a, &t->ma, &t->f, &t->mf) &&
         bsfit__line_runs_forward(s, &t->f, &t->mf, &t->b, &t->mb, nb->after, nb->mafter);
}

/* the fillet between what is left of two lines (a, b) on the ka + kb samples between them,
** settled, its lines still running forwards */
static int corner_fillet(const seg_section *s, const line_left *a, const line_left *b, size_t ka,
                         size_t kb, const seg_neighbours *nb, seg_fillet_try *t) {
  bsfit_piece f;
  seg_model mf;
  memset(&f, 0, sizeof f), memset(&mf, 0, sizeof mf);
  f.first = (a->p.first + a->p.count) % s->m;
  f.count = ka + kb;
  return bsfit__fillet_try(s, &a->p, &a->md, &f, &mf, &b->p, &b->md, 0, t) &&
         bsfit__settle_fillet(s, &t->a, &t->ma, &t->f, &t->mf, &t->b, &t->mb) &&
         keeps_lines(s, nb, t);
}

/* The best fillet at the corner of lines A and B, on up to CORNER_TAKE samples of each; its
** residual, HUGE_VAL when none. */
static double best_corner_fillet(const seg_section *s, const bsfit_piece *A, const seg_model *ma,
                                 const bsfit_piece *B, const seg_model *mb,
                                 const seg_neighbours *nb, seg_fillet_try *best) {
  line_left a[CORNER_TAKE + 1], b[CORNER_TAKE + 1];
  double best_rss = HUGE_VAL;
  size_t ka, kb;
  seg_fillet_try t;
  lines_left(s, A, ma, 1, a);
  lines_left(s, B, mb, 0, b);
  for (ka = 0; ka <= CORNER_TAKE; ka++)
    for (kb = 0; kb <= CORNER_TAKE; kb++)
      if (ka + kb >= CORNER_LEAST && a[ka].ok && b[kb].ok &&
          corner_fillet(s, &a[ka], &b[kb], ka, kb, nb, &t)) {
        double rss = bsfit__fillet_try_rss(&t);
        if (rss < best_rss) *best = t, best_rss = rss;
      }
  return best_rss;
}

/* the pieces before and after lines i and j (j after i), NULL at an open section's ends */
static seg_neighbours neighbours(const seg_section *s, const bsfit_piece *p, const seg_model *md,
                                 size_t np, size_t i, size_t j) {
  seg_neighbours nb;
  size_t ia = (i + np - 1) % np, jb = (j + 1) % np;
  nb.before = (s->closed || i > 0) && ia != j ? &p[ia] : NULL, nb.mbefore = &md[ia];
  nb.after = (s->closed || j + 1 < np) && jb != i ? &p[jb] : NULL, nb.mafter = &md[jb];
  return nb;
}

/* what making corner i (between lines i and i + 1) a fillet saves, in the residual
** (-HUGE_VAL where it cannot be one) */
static double corner_saving(const seg_section *s, const bsfit_piece *p, const seg_model *md,
                            size_t np, size_t i, seg_fillet_try *t) {
  size_t ib = (i + 1) % np;
  double corner_rss, price = CORNER_FILLET_PRICE * s->unit * s->unit;
  seg_neighbours nb;
  if (!s->closed && i + 1 == np) return -HUGE_VAL;
  if (p[i].kind != LINE || p[ib].kind != LINE || ib == i) return -HUGE_VAL;
  if (p[i].count > CORNER_LINE_MOST || p[ib].count > CORNER_LINE_MOST) return -HUGE_VAL;
  corner_rss = fitted_rss(&p[i]) + fitted_rss(&p[ib]);
  /* no fillet leaves less than nothing: a corner whose lines leave at most the price
  ** cannot save it (most corners of a section at its noise level; this took the step's
  ** cost on a 40-sample T at noise 1e-4 from 0.14 to 0.04 ms, the result the same) */
  if (corner_rss <= price) return -HUGE_VAL;
  nb = neighbours(s, p, md, np, i, ib);
  return corner_rss - best_corner_fillet(s, &p[i], &md[i], &p[ib], &md[ib], &nb, t);
}

/* corner i made fillet t (p, md have room for one more); returns np + 1 */
static size_t insert_fillet(bsfit_piece *p, seg_model *md, size_t np, size_t i, const seg_fillet_try *t) {
  /* A, the fillet, B (B at 0 when A was the last piece of a closed section) */
  memmove(&p[i + 2], &p[i + 1], (np - i - 1) * sizeof *p);
  memmove(&md[i + 2], &md[i + 1], (np - i - 1) * sizeof *md);
  p[i] = t->a, md[i] = t->ma, p[i + 1] = t->f, md[i + 1] = t->mf;
  p[(i + 2) % (np + 1)] = t->b, md[(i + 2) % (np + 1)] = t->mb;
  return np + 1;
}

/* segment_internal.h. The corner that saves most goes first, then those near it are
** weighed again (they share a line with it): not in the pieces' order, which depends on
** the sample a closed section starts at. */
size_t bsfit__fillet_corners(const seg_section *s, bsfit_piece *p, seg_model *md, size_t np,
                             double *saving) {
  double price = CORNER_FILLET_PRICE * s->unit * s->unit;
  size_t i;
  seg_fillet_try t;
  if (!s->noisy || s->m > BSFIT__DENSE_MOST || np < 2) return np;
  for (i = 0; i < np; i++) saving[i] = corner_saving(s, p, md, np, i, &t);
  for (;;) {
    size_t best = np;
    int d;
    for (i = 0; i < np; i++)
      if (saving[i] > price && (best == np || saving[i] > saving[best])) best = i;
    if (best == np) return np;
    corner_saving(s, p, md, np, best, &t);
    np = insert_fillet(p, md, np, best, &t);
    memmove(&saving[best + 2], &saving[best + 1], (np - best - 2) * sizeof *saving);
    for (d = -2; d <= 3; d++) { /* best + d, round a closed section */
      ptrdiff_t j = (ptrdiff_t)best + d;
      if (!s->closed && (j < 0 || j >= (ptrdiff_t)np)) continue;
      j = (j + 3 * (ptrdiff_t)np) % (ptrdiff_t)np;
      saving[j] = corner_saving(s, p, md, np, (size_t)j, &t);
    }
  }
}
