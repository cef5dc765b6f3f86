/*
** segment_joins.c
** Where the pieces of a segmentation meet: each primitive's model refitted to its
** samples, and the point where two consecutive models meet between their samples (a
** tangent join where they touch, else a corner where they cross), or none.
*/
#include "segment_internal.h"

#include <math.h>
#include <string.h>

/* segment_internal.h */
void bsfit__segment_refit(const seg_section *s, bsfit_piece *p, seg_model *md) {
  double rms = 0;
  p->max = fit_model(s, p->kind, p->first, p->count, md, &rms);
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
  size_t k, n = p->count;
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
int bsfit__segment_meet(const seg_section *s, const bsfit_piece *A, const seg_model *ma,
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
