/*
** segment_fillets.c
** Fillets of a segmentation: an arc between two lines it meets tangentially is refitted
** with its circle tangent to both (one unknown, its radius), and takes the samples of the
** lines past its tangent points; under noise, the cover's misreadings of a fillet (a short
** line between two corners, an arc that misses the tangency) become that fillet first
** (docs/auto.md, step 8 "Fillets"). The fillet's geometry here (its frame, a try of it, how
** it is settled) is shared with segment_corner_fillets.c and segment_fillet_se.c.
*/
#include "segment_internal.h"

#include <math.h>
#include <stddef.h>
#include <string.h>

/* The radius of the circle tangent to two lines (its centre V + u k r) that fits F's
** samples best: Gauss-Newton on the geometric distances, from r. Its residual sum of
** squares into *rss, and the information of the radius (sum of the squared derivatives of
** the distances: its variance is sigma^2 over it) into *info; -1 when it fails. */
static double fillet_radius(const seg_section *s, const bsfit_piece *F, const double *V,
                            const double *u, double k, double r, double *rss, double *info) {
  int it;
  size_t j;
  for (it = 0; it < 20; it++) {
    double g = 0, h = 0, step;
    *rss = 0;
    for (j = 0; j < F->count; j++) {
      const double *q = sample(s, F->first + j);
      double dx = q[0] - V[0] - u[0] * k * r, dy = q[1] - V[1] - u[1] * k * r, d = hypot(dx, dy);
      double e = d - r, de = d > 0 ? -(dx * u[0] + dy * u[1]) * k / d - 1.0 : -1.0;
      g += de * e;
      h += de * de;
      *rss += e * e;
    }
    if (!(h > 0)) return -1.0;
    *info = h;
    step = -g / h;
    r += step;
    if (!(r > 0)) return -1.0;
    if (fabs(step) <= 1e-15 * r) break;
  }
  return r;
}

/* the cross product of two lines' directions: the sign of the turn from a to b */
static double turn_sign(const seg_model *a, const seg_model *b) {
  return a->line.d[0] * b->line.d[1] - a->line.d[1] * b->line.d[0];
}

/* whether a point runs from `from` to `to` forwards along direction d */
static int ahead_along(const double *from, const double *to, const double *d) {
  return (to[0] - from[0]) * d[0] + (to[1] - from[1]) * d[1] > 0;
}

/* segment_internal.h. Two fillets on a short line put their tangent points past each
** other, and the line between them ran backwards (a gear of 6 samples per side at noise
** 3e-3 read at 2.6 times its noise). */
int bsfit__line_runs_forward(const seg_section *s, const bsfit_piece *prev, const seg_model *mprev,
                             const bsfit_piece *L, const seg_model *ml, const bsfit_piece *next,
                             const seg_model *mnext) {
  double a[2], b[2], t[2];
  if (!prev || prev->kind == FREE || !bsfit__segment_meet(s, prev, mprev, L, ml, a))
    bsfit__model_foot(ml, sample(s, L->first), a, t);
  if (!next || next->kind == FREE || !bsfit__segment_meet(s, L, ml, next, mnext, b))
    bsfit__model_foot(ml, sample(s, L->first + L->count - 1), b, t);
  return ahead_along(a, b, ml->line.d);
}

/* segment_internal.h. The frame of a fillet between lines A and B: their corner V, the unit bisector u into
** the turn and k = 1 / sin(half the inner angle), so that the circle of radius r tangent
** to both is centred at V + u k r. 0 when the lines are parallel or turn back. */
int bsfit__fillet_frame(const seg_model *ma, const seg_model *mb, double *V, double *u, double *k) {
  double un, cosphi;
  if (!bsfit__meet_lines(&ma->line, &mb->line, V)) return 0;
  u[0] = mb->line.d[0] - ma->line.d[0];
  u[1] = mb->line.d[1] - ma->line.d[1];
  un = hypot(u[0], u[1]);
  cosphi = -(ma->line.d[0] * mb->line.d[0] + ma->line.d[1] * mb->line.d[1]);
  if (!(un > 1e-12) || cosphi >= 1 - 1e-12) return 0;
  u[0] /= un, u[1] /= un;
  *k = 1.0 / sin(0.5 * acos(fmax(-1.0, fmin(1.0, cosphi))));
  return 1;
}

/* F's circle becomes the one of radius r tangent to A and B (frame V, u, k): its model,
** centre, radius, ends on both lines, tangents there, and its residual. */
static void set_fillet(const seg_section *s, bsfit_piece *A, const seg_model *ma, bsfit_piece *F,
                       seg_model *mf, bsfit_piece *B, const seg_model *mb, const double *V,
                       const double *u, double k, double r) {
  double c[2], f[2], t[2], rms = 0;
  c[0] = V[0] + u[0] * k * r;
  c[1] = V[1] + u[1] * k * r;
  mf->circle.c[0] = c[0], mf->circle.c[1] = c[1], mf->circle.r = r;
  F->centre[0] = c[0], F->centre[1] = c[1], F->radius = r;
  bsfit__model_foot(ma, c, f, t);
  memcpy(A->end, f, sizeof f), memcpy(F->start, f, sizeof f);
  bsfit__model_foot(mb, c, f, t);
  memcpy(B->start, f, sizeof f), memcpy(F->end, f, sizeof f);
  bsfit__model_foot(mf, F->start, f, F->t_start);
  bsfit__model_foot(mf, F->end, f, F->t_end);
  F->max = bsfit__circle_max(&mf->circle, &(bsfit__run){s->pts, s->m, F->first, F->count}, &rms);
  F->rms = rms;
}

/* A fillet: an arc meeting a line tangentially at both ends. Its circle is then known
** from the two lines up to its radius (its centre on the bisector of their corner), so
** it is refitted with that one unknown: a short noisy arc alone leaves its radius
** uncertain by many percent, the lines fix all but one of its parameters. But the lines
** are extrapolated to their corner, and an error there moves the radius by 1/(k - 1)
** times as much (2.4 at a right angle): the refit is taken only when its samples do not
** tell against it, i.e. it adds at most 9 sigma^2 to their residual (the chi-square of its
** two fewer parameters at 99%). The tangent points move to the new circle. */
static void refit_fillet(const seg_section *s, bsfit_piece *A, const seg_model *ma, bsfit_piece *F,
                         seg_model *mf, bsfit_piece *B, const seg_model *mb) {
  double V[2], u[2], k, r, rss, info;
  if (!bsfit__fillet_frame(ma, mb, V, u, &k)) return;
  r = fillet_radius(s, F, V, u, k, mf->circle.r, &rss, &info);
  if (!(r > 0) || rss - F->rms * F->rms * (double)F->count > 9.0 * s->unit * s->unit) return;
  set_fillet(s, A, ma, F, mf, B, mb, V, u, k, r);
}

/* Samples of line A past its tangent point with fillet F (their feet beyond A's end along
** A), and of B before it, lie on the fillet: a line that held them (they were within its
** tolerance) bends the fillet's radius by percents. They go to F, while each line keeps
** its least number of distinct positions (a circle's samples given three times each once
** left a line of two); returns how many moved. */
static size_t claim_for_fillet(const seg_section *s, bsfit_piece *A, const seg_model *ma,
                               bsfit_piece *F, bsfit_piece *B, const seg_model *mb) {
  size_t moved = 0;
  while (A->count > s->min_len[LINE] &&
         distinct(s, LINE, A->first, A->count - 1) >= s->min_len[LINE]) {
    const double *q = sample(s, A->first + A->count - 1);
    if ((q[0] - A->end[0]) * ma->line.d[0] + (q[1] - A->end[1]) * ma->line.d[1] <= 0) break;
    A->count--, F->first = (F->first + s->m - 1) % s->m, F->count++, moved++;
  }
  while (B->count > s->min_len[LINE] &&
         distinct(s, LINE, B->first + 1, B->count - 1) >= s->min_len[LINE]) {
    const double *q = sample(s, B->first);
    if ((q[0] - B->start[0]) * mb->line.d[0] + (q[1] - B->start[1]) * mb->line.d[1] >= 0) break;
    B->first = (B->first + 1) % s->m, B->count--, F->count++, moved++;
  }
  return moved;
}

/* claim_for_fillet, and the lines refitted without the samples they gave; returns how many
** moved */
static size_t claim_and_refit(const seg_section *s, bsfit_piece *A, seg_model *ma, bsfit_piece *F,
                              bsfit_piece *B, seg_model *mb) {
  size_t moved = claim_for_fillet(s, A, ma, F, B, mb);
  if (moved) {
    bsfit__segment_refit(s, A, ma);
    bsfit__segment_refit(s, B, mb);
  }
  return moved;
}

/* segment_internal.h. F, made the fillet between A and B (models ma, mb), takes the samples of the lines past
** its tangent points (claim_for_fillet), the lines are refitted without them and F's
** radius again with them: the lines had held a few of the fillet's samples within their
** tolerance, and fitted with them they misplace the fillet (a filleted hexagon of 6
** samples per side at noise 1e-3, whose chord of 3 of a fillet's samples beat the fillet
** on those 3 by 3 sigma^2). Returns 0 where a piece then leaves its tolerance. */
int bsfit__settle_fillet(const seg_section *s, bsfit_piece *A, seg_model *ma, bsfit_piece *F,
                         seg_model *mf, bsfit_piece *B, seg_model *mb) {
  double V[2], u[2], k, r, rss, info;
  if (!claim_and_refit(s, A, ma, F, B, mb)) return 1;
  if (!(A->max <= s->tol) || !(B->max <= s->tol) || !bsfit__fillet_frame(ma, mb, V, u, &k) ||
      !(k - 1 > 1e-6))
    return 0;
  r = fillet_radius(s, F, V, u, k, mf->circle.r, &rss, &info);
  if (!(r > 0)) return 0;
  set_fillet(s, A, ma, F, mf, B, mb, V, u, k, r);
  return F->max <= s->tol;
}

/* segment_internal.h. The fillet tangent to lines A and B on F's samples, its radius
** fitted from r0 (from F's middle sample when r0 is 0), set on copies of the three pieces,
** not yet settled: 0 when the lines frame no fillet or a sample of F lies past the
** tolerance of it. */
int bsfit__fillet_try(const seg_section *s, const bsfit_piece *A, const seg_model *ma,
                      const bsfit_piece *F, const seg_model *mf, const bsfit_piece *B,
                      const seg_model *mb, double r0, seg_fillet_try *t) {
  double V[2], u[2], k, r, rss, info;
  if (!bsfit__fillet_frame(ma, mb, V, u, &k) || !(k - 1 > 1e-6)) return 0;
  if (!(r0 > 0)) {
    const double *q = sample(s, F->first + F->count / 2);
    r0 = hypot(q[0] - V[0], q[1] - V[1]) / (k - 1);
  }
  r = fillet_radius(s, F, V, u, k, r0, &rss, &info);
  if (!(r > 0)) return 0;
  t->a = *A, t->f = *F, t->b = *B, t->ma = *ma, t->mf = *mf, t->mb = *mb;
  t->mf.kind = t->f.kind = ARC;
  t->mf.orient = turn_sign(ma, mb) > 0 ? 1.0 : -1.0;
  set_fillet(s, &t->a, &t->ma, &t->f, &t->mf, &t->b, &t->mb, V, u, k, r);
  return t->f.max <= s->tol;
}

/* X, between lines A and B, becomes the fillet tangent to both (its radius fitted from
** r0; from X's middle sample when r0 is 0) when its samples lie within the tolerance of
** it and the three pieces' residual is at most `price` sigma^2 more than before: with the
** samples the fillet takes from the lines (settle_fillet) where that passes, else as the
** lines are. Returns whether it did. How well the samples fix the radius is not asked:
** where they barely do (a 60-degree fillet, whose centre moves along the bisector with
** its radius), they fix the curve's place all the better, and the two corners the fillet
** was kept as before (while its samples had to fix the radius to 1%) cut it by 0.4 of
** its radius, softened or not. The arc's radius_se says how far its radius is to be
** trusted. */
static int to_fillet(const seg_section *s, bsfit_piece *A, seg_model *ma, bsfit_piece *X,
                     seg_model *mx, bsfit_piece *B, seg_model *mb, double r0, double price) {
  double most = fitted_rss(A) + fitted_rss(X) + fitted_rss(B) + price * s->unit * s->unit;
  seg_fillet_try t, settled;
  if (!bsfit__fillet_try(s, A, ma, X, mx, B, mb, r0, &t)) return 0;
  settled = t;
  if (bsfit__settle_fillet(s, &settled.a, &settled.ma, &settled.f, &settled.mf, &settled.b, &settled.mb) &&
      bsfit__fillet_try_rss(&settled) <= most)
    t = settled;
  else if (!(bsfit__fillet_try_rss(&t) <= most))
    return 0;
  *A = t.a, *X = t.f, *B = t.b, *ma = t.ma, *mx = t.mf, *mb = t.mb;
  return 1;
}

/* Does line md touch circle C (its centre r from it, within twice the tolerance, as the
** joins tell a tangent join)? */
static int touches(const seg_section *s, const seg_model *md, const bsfit__circle *C) {
  return fabs(bsfit__line_dist(&md->line, C->c) - C->r) <= 2 * s->tol;
}

/* The cover's two misreadings of a noisy fillet between lines A and B, each made the
** fillet tangent to both (to_fillet):
**   - a short line X between two corners: two chords follow a 60-degree fillet of 5
**     samples within the noise, and the cover, which prices an arc at 3 parameters, finds
**     them cheaper. The fillet has one parameter (its radius) against X's two: its price
**     is 2 sigma^2 (Akaike's, for the parameter it saves). Both corners must turn the way
**     A turns into B. (The cover's own price, 32 sigma^2, took the square ends of letters'
**     stems for semicircles: 4 samples across a stem 50 sigma wide fit one within 20.)
**   - an arc X whose free circle misses the tangency to A or B (a deep fillet of 4 to 6
**     samples, its radius right to a percent, met A at a corner of a few degrees): 9 sigma^2,
**     the chi-square of its two fewer parameters at 99% (as refit_fillet). */
void bsfit__cover_fillets(const seg_section *s, bsfit_piece *p, seg_model *md, size_t np) {
  size_t i;
  if (!s->noisy || np < 3) return;
  for (i = 0; i < np; i++) {
    size_t ia = (i + np - 1) % np, ib = (i + 1) % np;
    seg_model *ma = &md[ia], *mb = &md[ib];
    const seg_model *mx = &md[i];
    double turn = turn_sign(ma, mb);
    if (!s->closed && (i == 0 || i + 1 == np)) continue;
    if (p[ia].kind != LINE || p[ib].kind != LINE) continue;
    if (p[i].kind == LINE && turn_sign(ma, mx) * turn > 0 && turn_sign(mx, mb) * turn > 0)
      to_fillet(s, &p[ia], ma, &p[i], &md[i], &p[ib], mb, 0, 2.0);
    else if (p[i].kind == ARC && mx->orient * turn > 0 &&
        !(touches(s, ma, &mx->circle) && touches(s, mb, &mx->circle)))
      to_fillet(s, &p[ia], ma, &p[i], &md[i], &p[ib], mb, mx->circle.r, 9.0);
  }
}

/* Does piece j still meet the piece after it, k, with the join k has? A free piece, or an
** open section's last, meets anything. */
static int meets_as_joined(const seg_section *s, const bsfit_piece *p, const seg_model *md,
                           size_t np, size_t j) {
  size_t k = (j + 1) % np;
  double x[2];
  if ((!s->closed && j + 1 == np) || p[j].kind == FREE || p[k].kind == FREE) return 1;
  return bsfit__segment_meet(s, &p[j], &md[j], &p[k], &md[k], x) == (int)p[k].join;
}

/* fillet i of the list p and its two lines, as they are; and put back */
static seg_fillet_try fillet_of(const bsfit_piece *p, const seg_model *md, size_t np, size_t i) {
  seg_fillet_try t;
  size_t ia = (i + np - 1) % np, ib = (i + 1) % np;
  t.a = p[ia], t.f = p[i], t.b = p[ib], t.ma = md[ia], t.mf = md[i], t.mb = md[ib];
  return t;
}

static void put_fillet(bsfit_piece *p, seg_model *md, size_t np, size_t i, const seg_fillet_try *t) {
  size_t ia = (i + np - 1) % np, ib = (i + 1) % np;
  p[ia] = t->a, p[i] = t->f, p[ib] = t->b, md[ia] = t->ma, md[i] = t->mf, md[ib] = t->mb;
}

/* Fillet i takes the samples of its lines past its tangent points (claim_and_refit) and is
** refitted, unless the four joins of its lines (before, with it, after) no longer hold as
** they were placed: a join that no longer holds keeps the old models' place, off the
** refitted line's direction (a slot of 5 samples per side at noise 3e-3, whose fillet
** refit was then refused: its line 0.45 degrees off its reported tangent). */
static void claim_if_joins_hold(const seg_section *s, bsfit_piece *p, seg_model *md, size_t np,
                                size_t i) {
  size_t ia = (i + np - 1) % np, ib = (i + 1) % np, iaa = (ia + np - 1) % np;
  seg_fillet_try before = fillet_of(p, md, np, i);
  if (!claim_and_refit(s, &p[ia], &md[ia], &p[i], &p[ib], &md[ib])) return;
  refit_fillet(s, &p[ia], &md[ia], &p[i], &md[i], &p[ib], &md[ib]);
  if (meets_as_joined(s, p, md, np, iaa) && meets_as_joined(s, p, md, np, ia) &&
      meets_as_joined(s, p, md, np, i) && meets_as_joined(s, p, md, np, ib))
    return;
  put_fillet(p, md, np, i, &before);
}

/* segment_internal.h. Its neighbours in the list; none before an open section's first
** piece, none after its last. */
int bsfit__line_runs_forward_at(const seg_section *s, const bsfit_piece *p, const seg_model *md,
                                size_t np, size_t i) {
  size_t ia = (i + np - 1) % np, ib = (i + 1) % np;
  int first = !s->closed && i == 0, last = !s->closed && i + 1 == np;
  return bsfit__line_runs_forward(s, first ? NULL : &p[ia], &md[ia], &p[i], &md[i],
                                  last ? NULL : &p[ib], &md[ib]);
}

/* whether the lines of fillet i still run forwards between their joins */
static int fillet_lines_forward(const seg_section *s, const bsfit_piece *p, const seg_model *md,
                                size_t np, size_t i) {
  return bsfit__line_runs_forward_at(s, p, md, np, (i + np - 1) % np) &&
         bsfit__line_runs_forward_at(s, p, md, np, (i + 1) % np);
}

/* Fillet i refitted (and on the first pass under noise, its samples claimed), undone where
** a line of it would then run backwards: its radius grown past what a short line between it
** and the next fillet holds (a gear of 6 samples per side at noise 3e-3). */
static void refit_keeping_lines(const seg_section *s, bsfit_piece *p, seg_model *md, size_t np,
                                size_t i, int pass) {
  size_t ia = (i + np - 1) % np, ib = (i + 1) % np;
  seg_fillet_try before = fillet_of(p, md, np, i);
  refit_fillet(s, &p[ia], &md[ia], &p[i], &md[i], &p[ib], &md[ib]);
  /* the second pass places every tangent point on the lines as they end up */
  if (pass == 0 && s->noisy) claim_if_joins_hold(s, p, md, np, i);
  if (!fillet_lines_forward(s, p, md, np, i)) put_fillet(p, md, np, i, &before);
}

void bsfit__refit_fillets(const seg_section *s, bsfit_piece *p, seg_model *md, size_t np) {
  size_t i;
  int pass;
  for (pass = 0; pass < 2; pass++)
    for (i = 0; i < np; i++) {
      size_t ia = (i + np - 1) % np, ib = (i + 1) % np;
      if (p[i].kind != ARC || np < 3 || p[ia].kind != LINE || p[ib].kind != LINE) continue;
      if (!s->closed && (i == 0 || i + 1 == np)) continue;
      if (p[i].join != BSFIT_JOIN_TANGENT || p[ib].join != BSFIT_JOIN_TANGENT) continue;
      refit_keeping_lines(s, p, md, np, i, pass);
    }
}
