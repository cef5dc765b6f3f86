/*
** segment.c
** Segmentation of an ordered 2D section into straight lines, circular arcs and
** free-form runs (bsfit_features.h): the driver (bsfit_segment) and the pieces made of
** the cover (segment_cover.c) of the maximal runs each model explains (segment_runs.c),
** their models refitted and their ends placed where they meet (segment_joins.c).
*/
#include <float.h>
#include <math.h>
#include <string.h>

#include "segment_internal.h"

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

/* Is every coordinate a whole number of units 10^-k (within the rounding of its double)? */
static int on_decimal_grid(const double *pts, size_t m, double scale) {
  size_t i;
  for (i = 0; i < 2 * m; i++) {
    double v = pts[i] * scale;
    if (!(fabs(v) < 0x1p50) || fabs(v - nearbyint(v)) > 8.0 * DBL_EPSILON * fmax(fabs(v), 1.0))
      return 0;
  }
  return 1;
}

/* The floor a file's decimals set on the exact tolerance: samples written with k decimals
** (every coordinate a whole number of 10^-k, the coarsest such k) are their true positions
** rounded to half a unit of the k-th decimal, a distance of up to 0.71 of it: the unit,
** where it is at most QUANTUM_MOST of the size (a coarser grid is the data's own: integer
** samples of a polygon are exact); 0 otherwise. (Twice the unit let a line take 4 samples
** of a fillet of 10 uneven ones on a hexagon at 4 decimals: 14 units off.) A bracket of the demo
** set written with 6 decimals had its fillets of 3 samples meet its lines at corners of
** 0.07 degrees (the fillets' circles through rounded samples, of radius 3.0000093, miss
** the tangency to the lines by more than the tolerance of 1e-10 of the size). */
#define QUANTUM_MOST 1e-5
static double decimal_floor(const double *pts, size_t m, double size) {
  double scale = 1.0;
  int k;
  for (k = 0; k <= 15; k++, scale *= 10.0)
    if (on_decimal_grid(pts, m, scale)) return 1.0 / scale <= QUANTUM_MOST * size ? 1.0 / scale : 0.0;
  return 0.0;
}

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
    k = bsfit__segment_meet(s, A, ma, B, mb, x);
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
    if (!bsfit__segment_meet(s, &p[ia], &md[ia], &trial, &mt, x) ||
        !bsfit__segment_meet(s, &trial, &mt, &p[ib], &md[ib], x))
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
  size_t nl = L->count, na = A->count;
  size_t first = line_first ? L->first : A->first;
  size_t end = line_first ? (A->first + na) : (L->first + nl); /* one past, unwrapped below */
  size_t n = (end + s->m - first) % s->m;
  double rms = 0, max;
  seg_model mt;
  if (n != na + nl && n + 1 != na + nl) return 0; /* not next to each other */
  max = bsfit__fit_model_from(s, ARC, first, n, ma, &mt, &rms);
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

/* piece p (model md) becomes a free run of its samples: it fits no model, so nothing
** measures its samples (rms and max 0, as bsfit_features.h says; a line or an arc made free
** kept its residual, or infinity where its fit had failed) */
static void make_free(bsfit_piece *p, seg_model *md) {
  p->kind = md->kind = FREE;
  p->rms = p->max = 0;
}

/* A line whose joins with its neighbours pass each other holds no stretch of its own
** between them: it becomes a free run of its samples. Two large arcs tangent to a short
** line either side of it put their tangent points past each other, and the line ran
** backwards from one to the other, a cusp at both joins reported as tangent (a filleted
** polygon of 10 samples per side at noise 1e-2 of its size, segmented at the noise it
** showed; 2 of 11487 lines of 3000 random filleted polygons, test_segment_corner_fillets). */
static void free_backward_lines(const seg_section *s, bsfit_piece *p, seg_model *md, size_t np) {
  size_t i;
  if (np < 3) return;
  for (i = 0; i < np; i++)
    if (p[i].kind == LINE && !bsfit__line_runs_forward_at(s, p, md, np, i)) make_free(&p[i], &md[i]);
}

/* Two lines that close a section by meeting at both joins meet at one point: both joins
** fall there, and each line would be drawn from that point back to itself (a T read at 5%
** of its size as two lines of 10 and 14 samples: 14 of 2507 lines of the sweep's sections
** at such levels, tests/bench/stress_segment.lua). The line of fewer samples becomes a
** free run of them, which closes the section from the other's end to its start. (Two lines
** that meet at one join or none are closed by bridges, and stay.) */
static void free_one_of_two_lines(const seg_section *s, bsfit_piece *p, seg_model *md, size_t np) {
  double x[2];
  size_t i;
  if (!s->closed || np != 2 || p[0].kind != LINE || p[1].kind != LINE) return;
  if (!bsfit__segment_meet(s, &p[0], &md[0], &p[1], &md[1], x) ||
      !bsfit__segment_meet(s, &p[1], &md[1], &p[0], &md[0], x))
    return;
  i = p[1].count < p[0].count ? 1 : 0;
  make_free(&p[i], &md[i]);
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
** so keeps its place. A line's join with a free run moves to the foot of its extreme sample
** on its new model (a line after a free bridge and before a fillet kept the foot on its old
** model: a filleted pentagon of 10 samples per side at noise 3e-3, 0.13 degrees off). */
static void rejoin_lines(const seg_section *s, bsfit_piece *p, seg_model *md, size_t np) {
  size_t i;
  for (i = np < 2 ? np : 0; i < np; i++) {
    size_t ia = (i + np - 1) % np;
    bsfit_piece A, B;
    if ((!s->closed && i == 0) || (p[ia].kind == FREE && p[i].kind == FREE)) continue;
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

/* Models, ends and sweeps of the np pieces of the cover (p has room for 2 np; scratch, for
** 2 m + 2 doubles). */
static size_t finish_pieces(const seg_section *s, bsfit_piece *p, seg_model *md, size_t np,
                            double *scratch) {
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
    if (p[i].kind != FREE && !(p[i].max < HUGE_VAL)) make_free(&p[i], &md[i]);
    /* an arc goes round at most once (a closed section's whole circle closes that turn) */
    if (p[i].kind == ARC && arc_turn(s, &p[i], &md[i]) > 2 * PI * (1 + 1e-9))
      make_free(&p[i], &md[i]);
  }
  np = s->noisy ? absorb_strays(s, p, md, np) : absorb_free_runs(s, p, md, np);
  short_runs(s, p, md, np);
  if (s->noisy) np = arcs_take_lines(s, p, md, np);
  rebalance(s, p, md, np);
  bsfit__cover_fillets(s, p, md, np);
  np = bsfit__split_corner_arcs(s, p, md, np);
  np = bsfit__split_bridges(s, p, md, np);
  np = bsfit__fillet_corners(s, p, md, np, scratch);
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
  free_one_of_two_lines(s, p, md, np);
  free_backward_lines(s, p, md, np);
  np = place_ends(s, p, md, np);
  if (!s->closed) open_ends(s, p, md, np);
  bsfit__refit_fillets(s, p, md, np);
  rejoin_lines(s, p, md, np);
  /* again on the lines as refitted: a fillet's refit moves its line's model, and an open
  ** section's first line kept its start on the old one (a part of a slot of 30 uneven
  ** samples per side at noise 3e-3: sin 7e-4 off its reported tangent) */
  if (!s->closed) open_ends(s, p, md, np);
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
  s.start = s.closed ? bsfit__closed_start(pts, m) : 0;
  s.a = a;
  s.mom = NULL;
  memset(&mom, 0, sizeof mom);
  s.min_len[LINE] = o.min_line ? o.min_line : 3;
  s.min_len[ARC] = o.min_arc ? o.min_arc : 4;
  s.size = bsfit__segment_size(pts, m);
  s.tol = fmax((o.tol_sigma > 0 ? o.tol_sigma : 4.0) * o.sigma,
               fmax((o.exact > 0 ? o.exact : 1e-10) * s.size,
                    fmax(rounding_floor(pts, m), decimal_floor(pts, m, s.size))));
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
  heap_key = bsfit__alloc(a, bsfit__mulsize(2 * m + 2, sizeof(double)));
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
    if ((e = bsfit__maximal_runs(&s, LINE, len[0])) != BSFIT_OK ||
        (e = bsfit__maximal_runs(&s, ARC, len[1])) != BSFIT_OK) {
      e = bsfit__fail(st, e, "segmentation interrupted");
      goto done;
    }
    heaps[0].at = heap_at, heaps[0].key = heap_key, heaps[0].below = heap_below;
    heaps[1].at = heap_at + m, heaps[1].key = heap_key + m, heaps[1].below = heap_below + m;
    np = bsfit__segment_cover(&s, len, prim, fr, heaps, buf);
  }
  np = finish_pieces(&s, buf, md, np, heap_key); /* the cover's heaps are done with */
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
  bsfit__free(a, heap_key, heap_key ? (2 * m + 2) * sizeof(double) : 0);
  bsfit__free(a, heap_below, heap_below ? 2 * m * sizeof(size_t) : 0);
  return e;
}
