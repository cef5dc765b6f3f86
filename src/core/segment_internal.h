/*
** segment_internal.h
** What the segmentation's files share (segment.c: the pieces and bsfit_segment;
** segment_runs.c: the maximal runs each model explains; segment_cover.c: the cover of
** least cost; segment_joins.c: where pieces meet; segment_evidence.c: the evidence of
** corners; segment_fillets.c: fillets between lines, segment_corner_fillets.c: corners
** that are fillets, segment_fillet_se.c: a fillet radius's error; segment_corner_arcs.c:
** arcs across corners, sides between lines that meet nowhere): the section worked on, a side model
** of either kind, the cover's cells and heaps, and their small accessors. Not part of the
** public API.
*/
#ifndef BSFIT_SEGMENT_INTERNAL_H
#define BSFIT_SEGMENT_INTERNAL_H

#include "features_internal.h"

#define PI 3.14159265358979323846

#define LINE BSFIT_PIECE_LINE
#define ARC BSFIT_PIECE_ARC
#define FREE BSFIT_PIECE_FREE

/* what the segmentation works on */
typedef struct seg_section {
  const double *pts;
  size_t m;
  int closed;
  size_t start; /* where its reading begins: bsfit__closed_start when closed, else 0 */
  double tol;  /* a sample fits a model within tol */
  double size; /* the diagonal of the samples' bounding box */
  double unit; /* sigma: tol / tol_sigma (evidence is counted in unit^2) */
  int noisy;   /* tol is set by sigma, not by the exact floor */
  size_t min_len[2];
  size_t *gaps; /* gaps[i]: how many of the steps j -> j+1, j < i (unwrapped, i <= 2m),
                   are longer than tol: a model needs that many distinct samples */
  size_t *moves; /* noisy sections: moves[i], how many of them are not zero (repeated
                    samples are one); NULL on exact ones, whose lines count steps only */
  const bsfit__moments *mom; /* noisy sections: pieces cost their residual too (NULL: not) */
  size_t longest[2];         /* the longest run of each kind */
  double penalty;            /* sigma^2 per parameter, with mom */
  const bsfit_allocator *a;
} seg_section;

/* distinct samples among n from first for a model of `kind`: steps longer than tol, plus
** one; for a line on a noisy section, where most steps are shorter than tol (a run sampled
** more densely than the noise), how many tol it spans end to end, plus one, but no more
** than its samples that are not repeats (a side of 0.3 in 37 samples at a tolerance of
** 0.026 has no step longer than it, yet spans 11 of it; a cluster of samples spans none;
** two points given three times each are two). An arc's chord says nothing of how much of
** a circle it holds. */
static inline size_t distinct(const seg_section *s, int kind, size_t first, size_t n) {
  size_t steps = s->gaps[first + n - 1] - s->gaps[first] + 1, moved;
  const double *a, *b;
  double span;
  if (kind != LINE || !s->moves || 2 * steps >= n) return steps;
  a = s->pts + 2 * (first % s->m), b = s->pts + 2 * ((first + n - 1) % s->m);
  span = hypot(b[0] - a[0], b[1] - a[1]) / s->tol;
  if (!(span >= (double)steps)) return steps;
  moved = s->moves[first + n - 1] - s->moves[first] + 1;
  return span + 1 < (double)moved ? (size_t)span + 1 : moved;
}

/* a model of either kind */
typedef struct seg_model {
  int kind;
  bsfit__line line;
  bsfit__circle circle;
  double orient; /* arcs: +1 counter-clockwise along the samples, -1 clockwise */
} seg_model;

static inline const double *sample(const seg_section *s, size_t i) {
  return s->pts + 2 * (i % s->m);
}

static inline bsfit__run run_of(const seg_section *s, size_t first, size_t n) {
  bsfit__run r;
  r.pts = s->pts;
  r.m = s->m;
  r.first = first % s->m;
  r.n = n;
  return r;
}

static inline double model_dist(const seg_model *md, const double *x) {
  return md->kind == LINE ? bsfit__line_dist(&md->line, x) : bsfit__circle_dist(&md->circle, x);
}

/* segment_runs.c: fits a model of `kind` to n samples from `first` (warm-started from
** warm's circle when it is an arc); its largest distance (HUGE_VAL when it cannot be
** fitted), its rms into *rms when not NULL */
double bsfit__fit_model_from(const seg_section *s, int kind, size_t first, size_t n,
                             const seg_model *warm, seg_model *md, double *rms);

/* bsfit__fit_model_from with no warm start */
static inline double fit_model(const seg_section *s, int kind, size_t first, size_t n,
                               seg_model *md, double *rms) {
  return bsfit__fit_model_from(s, kind, first, n, NULL, md, rms);
}

/* A model explains its samples when every one lies within tol. (A chi-square test on
** their residual was tried as well: it turned fillets into corners; docs/auto.md.) This
** is what makes runs nest: a model that explains a run explains every part of it. */
static inline int fit_explains(const seg_section *s, int kind, size_t first, size_t n,
                               const seg_model *warm, seg_model *md) {
  return bsfit__fit_model_from(s, kind, first, n, warm, md, NULL) <= s->tol;
}

/* The turn from a to b round an arc's centre, in its direction, in [0, 2 pi). */
static inline double turn_between(const seg_model *md, const double *a, const double *b) {
  double ax = a[0] - md->circle.c[0], ay = a[1] - md->circle.c[1];
  double bx = b[0] - md->circle.c[0], by = b[1] - md->circle.c[1];
  double t = md->orient * atan2(ax * by - ay * bx, ax * bx + ay * by);
  return t < 0 ? t + 2 * PI : t;
}

/* the residual sum of squares of a piece's fitted model (set by bsfit__segment_refit;
** segment_cover.c's piece_rss is the cover's, from moments) */
static inline double fitted_rss(const bsfit_piece *p) { return p->rms * p->rms * (double)p->count; }

/* segment_runs.c: len[i] = the most samples from i that one model of `kind` explains (0
** when fewer than its minimum); BSFIT_EINTR when interrupted */
bsfit_err bsfit__maximal_runs(const seg_section *s, int kind, size_t *len);

/* segment_cover.c: the weighed cover's price of one more parameter, in sigma^2 (the default
** of param_cost; why, above piece_rss) */
#define RSS_PENALTY 32.0

/* DP state: the cheapest cover of offsets [0, j] whose last piece ends at j */
typedef struct cell {
  double cost;
  size_t start; /* offset of the last piece's first sample */
  int kind;
  int shared;    /* the piece before ends at `start` too (a sampled corner) */
  int prev_free; /* the piece before is free */
} cell;

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
  size_t *below; /* per start: the next older start of its group (none: (size_t)-1) */
  size_t n, next;
  size_t last, last_pos; /* the start pushed last, and where it went */
} start_heap;

/* segment_cover.c: the cheapest cover of the maximal runs len (pieces in order into p, from
** p[m + 1] as scratch; a closed section cut where its longest runs start); sets s->longest
** and returns the number of pieces */
size_t bsfit__segment_cover(seg_section *s, size_t *const len[2], cell *prim, cell *fr,
                            start_heap heaps[2], bsfit_piece *p);

/* segment_evidence.c: how much worse one smooth curve explains the samples of A and B
** next to their corner than their two models, in units of sigma^2 */
double bsfit__join_evidence(const seg_section *s, const bsfit_piece *A, const seg_model *ma,
                            const bsfit_piece *B, const seg_model *mb, double sigma);

/* segment_dense.c: the cover of a dense noisy section (more than BSFIT__DENSE_MOST samples),
** found on every k-th sample and moved onto all (kind, first, count of each piece into p,
** room for 2 m + 2); returns their number, or 0 with *e set */
size_t bsfit__dense_cover(const seg_section *s, const bsfit_segment_opts *o, bsfit_piece *p,
                          bsfit_err *e, bsfit_status *st);

/* segment_joins.c: refits p's model md to its samples, and sets p's max, rms (and centre,
** radius for arcs) */
void bsfit__segment_refit(const seg_section *s, bsfit_piece *p, seg_model *md);

/* segment_joins.c: the model's foot point f of x and its unit tangent t there (along the
** traversal) */
void bsfit__model_foot(const seg_model *md, const double *x, double *f, double *t);

/* segment_fillets.c: each arc between two lines it meets tangentially is refitted with its
** circle tangent to both; under noise it first takes their samples past its tangent points */
void bsfit__refit_fillets(const seg_section *s, bsfit_piece *p, seg_model *md, size_t np);

/* segment_fillets.c: under noise, a short line between two lines it meets at corners
** turning the same way, or an arc between two lines that misses the tangency to one, becomes
** the fillet tangent to both where its samples allow (before the ends are placed: the
** joins then find it tangent) */
void bsfit__cover_fillets(const seg_section *s, bsfit_piece *p, seg_model *md, size_t np);

/* segment_fillets.c: whether line L (model ml) runs forwards from where it meets the piece
** before it to where it meets the piece after it (prev, next: NULL at an open section's
** ends; where a join cannot be had, or the neighbour is free, the foot of L's own end
** sample) */
int bsfit__line_runs_forward(const seg_section *s, const bsfit_piece *prev, const seg_model *mprev,
                             const bsfit_piece *L, const seg_model *ml, const bsfit_piece *next,
                             const seg_model *mnext);
/* segment_fillets.c: the same for line i of the list p (np pieces) between its neighbours */
int bsfit__line_runs_forward_at(const seg_section *s, const bsfit_piece *p, const seg_model *md,
                                size_t np, size_t i);

/* segment_fillets.c: the frame of a fillet between lines A and B (models ma, mb): the
** lines' corner V, the unit bisector u into the turn and k = 1 / sin(half the inner angle),
** the circle of radius r tangent to both centred at V + u k r (0 when the lines are
** parallel or turn back) */
int bsfit__fillet_frame(const seg_model *ma, const seg_model *mb, double *V, double *u, double *k);

/* a fillet between two lines as it would be made: the three pieces and their models */
typedef struct seg_fillet_try {
  bsfit_piece a, f, b;
  seg_model ma, mf, mb;
} seg_fillet_try;

static inline double bsfit__fillet_try_rss(const seg_fillet_try *t) {
  return fitted_rss(&t->a) + fitted_rss(&t->f) + fitted_rss(&t->b);
}

/* segment_fillets.c: t, the fillet tangent to lines A and B on F's samples (its radius
** fitted from r0, or from F's middle sample when r0 is 0), set on copies of the three
** pieces; 0 when the lines frame none or F's samples leave its tolerance */
int bsfit__fillet_try(const seg_section *s, const bsfit_piece *A, const seg_model *ma,
                      const bsfit_piece *F, const seg_model *mf, const bsfit_piece *B,
                      const seg_model *mb, double r0, seg_fillet_try *t);

/* segment_fillets.c: F (made the fillet between A and B) takes the lines' samples past its
** tangent points, all refitted; 0 where a piece then leaves its tolerance */
int bsfit__settle_fillet(const seg_section *s, bsfit_piece *A, seg_model *ma, bsfit_piece *F,
                         seg_model *mf, bsfit_piece *B, seg_model *mb);

/* segment_corner_fillets.c: under noise, a corner between two lines whose samples next to it fit
** the fillet tangent to both better by a price becomes that fillet (p and md have room for
** np more; saving, scratch for 2 np); returns the new count */
size_t bsfit__fillet_corners(const seg_section *s, bsfit_piece *p, seg_model *md, size_t np,
                             double *saving);

/* segment_fillet_se.c: the standard error of fillet F's radius (its circle tangent to lines
** A and B, its radius fitted with them held), the lines' own errors included; HUGE_VAL
** when it cannot be had, 0 on exact data */
double bsfit__fillet_radius_se(const seg_section *s, const bsfit_piece *A, const seg_model *ma,
                               const bsfit_piece *F, const bsfit_piece *B, const seg_model *mb);

/* segment_joins.c: where A and B (B after A) meet: 0 (nowhere between them), BSFIT_JOIN_CORNER or
** BSFIT_JOIN_TANGENT, the point written to x */
int bsfit__segment_meet(const seg_section *s, const bsfit_piece *A, const seg_model *ma,
                        const bsfit_piece *B, const seg_model *mb, double *x);

/* segment_corner_arcs.c: under noise, on a sparse section, each arc that fails to meet a
** neighbour becomes the two lines of its samples (and up to two of each neighbour's) where
** they meet each other and the neighbours and explain the samples better by Akaike's price;
** p and md have room for np more; returns the new count */
size_t bsfit__split_corner_arcs(const seg_section *s, bsfit_piece *p, seg_model *md, size_t np);

/* segment_corner_arcs.c: under noise, two pieces that do not meet get the line of a side
** between them from their end samples (p, md have room for np more); returns the count */
size_t bsfit__split_bridges(const seg_section *s, bsfit_piece *p, seg_model *md, size_t np);

#endif
