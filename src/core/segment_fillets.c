/*
** segment_fillets.c
** Fillets of a segmentation: an arc between two lines it meets tangentially is refitted
** with its circle tangent to both (one unknown, its radius), and takes the samples of the
** lines past its tangent points; under noise, the cover's misreadings of a fillet (a short
** line between two corners, an arc that misses the tangency) become that fillet first
** (docs/auto.md, step 8 "Fillets").
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

/* The frame of a fillet between lines A and B: their corner V, the unit bisector u into
** the turn and k = 1 / sin(half the inner angle), so that the circle of radius r tangent
** to both is centred at V + u k r. 0 when the lines are parallel or turn back. */
static int fillet_frame(const seg_model *ma, const seg_model *mb, double *V, double *u, double *k) {
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
  if (!fillet_frame(ma, mb, V, u, &k)) return;
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

/* the cross product of two lines' directions: the sign of the turn from a to b */
static double turn_sign(const seg_model *a, const seg_model *b) {
  return a->line.d[0] * b->line.d[1] - a->line.d[1] * b->line.d[0];
}

/* F, made the fillet between A and B (models ma, mb), takes the samples of the lines past
** its tangent points (claim_for_fillet), the lines are refitted without them and F's
** radius again with them: the lines had held a few of the fillet's samples within their
** tolerance, and fitted with them they misplace the fillet (a filleted hexagon of 6
** samples per side at noise 1e-3, whose chord of 3 of a fillet's samples beat the fillet
** on those 3 by 3 sigma^2). Returns 0 where a piece then leaves its tolerance. */
static int settle_fillet(const seg_section *s, bsfit_piece *A, seg_model *ma, bsfit_piece *F,
                         seg_model *mf, bsfit_piece *B, seg_model *mb) {
  double V[2], u[2], k, r, rss, info;
  if (!claim_and_refit(s, A, ma, F, B, mb)) return 1;
  if (!(A->max <= s->tol) || !(B->max <= s->tol) || !fillet_frame(ma, mb, V, u, &k) ||
      !(k - 1 > 1e-6))
    return 0;
  r = fillet_radius(s, F, V, u, k, mf->circle.r, &rss, &info);
  if (!(r > 0)) return 0;
  set_fillet(s, A, ma, F, mf, B, mb, V, u, k, r);
  return F->max <= s->tol;
}

/* a fillet between two lines as it would be made: the three pieces and their models */
typedef struct fillet_try {
  bsfit_piece a, f, b;
  seg_model ma, mf, mb;
} fillet_try;

static double try_rss(const fillet_try *t) {
  return fitted_rss(&t->a) + fitted_rss(&t->f) + fitted_rss(&t->b);
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
  double V[2], u[2], k, r, rss, info, turn = turn_sign(ma, mb);
  double most = fitted_rss(A) + fitted_rss(X) + fitted_rss(B) + price * s->unit * s->unit;
  fillet_try t, settled;
  if (!fillet_frame(ma, mb, V, u, &k) || !(k - 1 > 1e-6)) return 0;
  if (!(r0 > 0)) {
    const double *q = sample(s, X->first + X->count / 2);
    r0 = hypot(q[0] - V[0], q[1] - V[1]) / (k - 1);
  }
  r = fillet_radius(s, X, V, u, k, r0, &rss, &info);
  if (!(r > 0)) return 0;
  t.a = *A, t.f = *X, t.b = *B, t.ma = *ma, t.mf = *mx, t.mb = *mb;
  t.mf.kind = t.f.kind = ARC;
  t.mf.orient = turn > 0 ? 1.0 : -1.0;
  set_fillet(s, &t.a, &t.ma, &t.f, &t.mf, &t.b, &t.mb, V, u, k, r);
  if (!(t.f.max <= s->tol)) return 0;
  settled = t;
  if (settle_fillet(s, &settled.a, &settled.ma, &settled.f, &settled.mf, &settled.b, &settled.mb) &&
      try_rss(&settled) <= most)
    t = settled;
  else if (!(try_rss(&t) <= most))
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

/* Fillet i takes the samples of its lines past its tangent points (claim_and_refit) and is
** refitted, unless the four joins of its lines (before, with it, after) no longer hold as
** they were placed: a join that no longer holds keeps the old models' place, off the
** refitted line's direction (a slot of 5 samples per side at noise 3e-3, whose fillet
** refit was then refused: its line 0.45 degrees off its reported tangent). */
static void claim_if_joins_hold(const seg_section *s, bsfit_piece *p, seg_model *md, size_t np,
                                size_t i) {
  size_t ia = (i + np - 1) % np, ib = (i + 1) % np, iaa = (ia + np - 1) % np;
  bsfit_piece A = p[ia], F = p[i], B = p[ib];
  seg_model ma = md[ia], mf = md[i], mb = md[ib];
  if (!claim_and_refit(s, &p[ia], &md[ia], &p[i], &p[ib], &md[ib])) return;
  refit_fillet(s, &p[ia], &md[ia], &p[i], &md[i], &p[ib], &md[ib]);
  if (meets_as_joined(s, p, md, np, iaa) && meets_as_joined(s, p, md, np, ia) &&
      meets_as_joined(s, p, md, np, i) && meets_as_joined(s, p, md, np, ib))
    return;
  p[ia] = A, p[i] = F, p[ib] = B, md[ia] = ma, md[i] = mf, md[ib] = mb;
}

/* whether the lines of fillet i still run forwards between their joins
** (bsfit__line_runs_forward) */
static int fillet_lines_forward(const seg_section *s, const bsfit_piece *p, const seg_model *md,
                                size_t np, size_t i) {
  size_t ia = (i + np - 1) % np, ib = (i + 1) % np, iaa = (ia + np - 1) % np, ibb = (ib + 1) % np;
  int open_a = !s->closed && ia == 0, open_b = !s->closed && ib + 1 == np;
  return bsfit__line_runs_forward(s, open_a ? NULL : &p[iaa], &md[iaa], &p[ia], &md[ia], &p[i], &md[i]) &&
         bsfit__line_runs_forward(s, &p[i], &md[i], &p[ib], &md[ib], open_b ? NULL : &p[ibb], &md[ibb]);
}

/* Fillet i refitted (and on the first pass under noise, its samples claimed), undone where
** a line of it would then run backwards: its radius grown past what a short line between it
** and the next fillet holds (a gear of 6 samples per side at noise 3e-3). */
static void refit_keeping_lines(const seg_section *s, bsfit_piece *p, seg_model *md, size_t np,
                                size_t i, int pass) {
  size_t ia = (i + np - 1) % np, ib = (i + 1) % np;
  bsfit_piece A = p[ia], F = p[i], B = p[ib];
  seg_model ma = md[ia], mf = md[i], mb = md[ib];
  refit_fillet(s, &p[ia], &md[ia], &p[i], &md[i], &p[ib], &md[ib]);
  /* the second pass places every tangent point on the lines as they end up */
  if (pass == 0 && s->noisy) claim_if_joins_hold(s, p, md, np, i);
  if (!fillet_lines_forward(s, p, md, np, i))
    p[ia] = A, p[i] = F, p[ib] = B, md[ia] = ma, md[i] = mf, md[ib] = mb;
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

/* The standard error of a fillet's radius (bsfit__fillet_radius_se) */

/* the frame of the fillet between lines a and b (fillet_frame); 0 when they frame none */
typedef struct fillet_frame_of {
  double V[2], u[2], k;
} fillet_frame_of;

static int frame_of(const bsfit__line *a, const bsfit__line *b, fillet_frame_of *f) {
  seg_model ma, mb;
  ma.kind = mb.kind = LINE, ma.line = *a, mb.line = *b;
  return fillet_frame(&ma, &mb, f->V, f->u, &f->k);
}

/* sample q's distance to the circle of radius r of frame f, minus r */
static double frame_residual(const fillet_frame_of *f, const double *q, double r) {
  return hypot(q[0] - f->V[0] - f->u[0] * f->k * r, q[1] - f->V[1] - f->u[1] * f->k * r) - r;
}

/* a line through its samples' centroid x turned by dphi and moved by dc along its normal:
** the perturbations whose variances are sigma^2 / S_tt and sigma^2 / n */
static bsfit__line moved_line(const bsfit__line *L, const double *x, double dphi, double dc) {
  bsfit__line M;
  double c = cos(dphi), sn = sin(dphi);
  M.d[0] = c * L->d[0] - sn * L->d[1];
  M.d[1] = sn * L->d[0] + c * L->d[1];
  M.p[0] = x[0] - M.d[1] * dc;
  M.p[1] = x[1] + M.d[0] * dc;
  return M;
}

/* the centroid x of line piece l's samples (its foot on L); returns the spread of their
** places along it, S_tt */
static double line_spread(const seg_section *s, const bsfit_piece *l, const bsfit__line *L,
                          double *x) {
  double stt = 0, tm = 0;
  size_t j;
  for (j = 0; j < l->count; j++) {
    const double *q = sample(s, l->first + j);
    tm += ((q[0] - L->p[0]) * L->d[0] + (q[1] - L->p[1]) * L->d[1]) / (double)l->count;
  }
  x[0] = L->p[0] + tm * L->d[0], x[1] = L->p[1] + tm * L->d[1];
  for (j = 0; j < l->count; j++) {
    const double *q = sample(s, l->first + j);
    double t = (q[0] - x[0]) * L->d[0] + (q[1] - x[1]) * L->d[1];
    stt += t * t;
  }
  return stt;
}

/* The four line parameters' perturbed frames (each line's direction and offset, by +h and
** -h: up[k], down[k]) and their variances over sigma^2; 0 when one frames no fillet. */
static int perturbed_frames(const seg_section *s, const bsfit_piece *A, const bsfit__line *la,
                            const bsfit_piece *B, const bsfit__line *lb, fillet_frame_of *up,
                            fillet_frame_of *down, double *h, double *var) {
  const bsfit__line *L[2] = {la, lb};
  const bsfit_piece *lp[2] = {A, B};
  int side, par;
  for (side = 0; side < 2; side++) {
    double x[2], stt = line_spread(s, lp[side], L[side], x);
    for (par = 0; par < 2; par++) {
      int k = 2 * side + par;
      bsfit__line lu, ld;
      h[k] = par == 0 ? 1e-7 : 1e-7 * s->size;
      var[k] = par == 0 ? (stt > 0 ? 1.0 / stt : HUGE_VAL) : 1.0 / (double)lp[side]->count;
      lu = moved_line(L[side], x, par == 0 ? h[k] : 0, par == 1 ? h[k] : 0);
      ld = moved_line(L[side], x, par == 0 ? -h[k] : 0, par == 1 ? -h[k] : 0);
      if (!frame_of(side ? la : &lu, side ? &lu : lb, &up[k]) ||
          !frame_of(side ? la : &ld, side ? &ld : lb, &down[k]))
        return 0;
    }
  }
  return 1;
}

/* segment_internal.h. The radius is fitted to F's samples with the lines held (r solves
** sum e_j de_j/dr = 0), and the lines are fitted to their own samples: by the delta
** method its variance is sigma^2 / I (I = sum (de_j/dr)^2, its own samples) plus, for
** each of the four line parameters theta (each line's direction and offset at its
** centroid, independent, of variances sigma^2 / S_tt and sigma^2 / n), (g / I)^2 Var(theta)
** with g = sum de_j/dtheta de_j/dr: how far an error of the lines moves the fitted radius
** (1 / (k - 1) times their offset, more at a gentle turn). Derivatives by central
** differences; no scratch memory. */
double bsfit__fillet_radius_se(const seg_section *s, const bsfit_piece *A, const seg_model *ma,
                               const bsfit_piece *F, const bsfit_piece *B, const seg_model *mb) {
  fillet_frame_of f, up[4], down[4];
  double h[4], var[4], g[4] = {0, 0, 0, 0}, I = 0, r = F->radius, hr = 1e-6 * F->radius, v;
  size_t j;
  int k;
  if (!s->noisy) return 0.0;
  if (F->count == 0 || !(r > 0) || !frame_of(&ma->line, &mb->line, &f) ||
      !perturbed_frames(s, A, &ma->line, B, &mb->line, up, down, h, var))
    return HUGE_VAL;
  for (j = 0; j < F->count; j++) {
    const double *q = sample(s, F->first + j);
    double dr = (frame_residual(&f, q, r + hr) - frame_residual(&f, q, r - hr)) / (2 * hr);
    I += dr * dr;
    for (k = 0; k < 4; k++)
      g[k] += (frame_residual(&up[k], q, r) - frame_residual(&down[k], q, r)) / (2 * h[k]) * dr;
  }
  if (!(I > 0)) return HUGE_VAL;
  v = 1.0 / I;
  for (k = 0; k < 4; k++) v += (g[k] / I) * (g[k] / I) * var[k];
  return v < HUGE_VAL ? s->unit * sqrt(v) : HUGE_VAL;
}

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
static int keeps_lines(const seg_section *s, const seg_neighbours *nb, fillet_try *t) {
  return bsfit__line_runs_forward(s, nb->before, nb->mbefore, &t->a, &t->ma, &t->f, &t->mf) &&
         bsfit__line_runs_forward(s, &t->f, &t->mf, &t->b, &t->mb, nb->after, nb->mafter);
}

/* the fillet between what is left of two lines (a, b) on the ka + kb samples between them */
static int corner_fillet(const seg_section *s, const line_left *a, const line_left *b, size_t ka,
                         size_t kb, const seg_neighbours *nb, fillet_try *t) {
  double V[2], u[2], k, r, rss, info, r0;
  const double *q;
  t->a = a->p, t->ma = a->md, t->b = b->p, t->mb = b->md;
  if (!fillet_frame(&t->ma, &t->mb, V, u, &k) || !(k - 1 > 1e-6)) return 0;
  memset(&t->f, 0, sizeof t->f);
  t->f.kind = t->mf.kind = ARC;
  t->f.first = (a->p.first + a->p.count) % s->m;
  t->f.count = ka + kb;
  t->mf.orient = turn_sign(&t->ma, &t->mb) > 0 ? 1.0 : -1.0;
  q = sample(s, t->f.first + t->f.count / 2);
  r0 = hypot(q[0] - V[0], q[1] - V[1]) / (k - 1);
  r = fillet_radius(s, &t->f, V, u, k, r0, &rss, &info);
  if (!(r > 0)) return 0;
  set_fillet(s, &t->a, &t->ma, &t->f, &t->mf, &t->b, &t->mb, V, u, k, r);
  if (!(t->f.max <= s->tol) || !settle_fillet(s, &t->a, &t->ma, &t->f, &t->mf, &t->b, &t->mb))
    return 0;
  return keeps_lines(s, nb, t);
}

/* The best fillet at the corner of lines A and B, on up to CORNER_TAKE samples of each; its
** residual, HUGE_VAL when none. */
static double best_corner_fillet(const seg_section *s, const bsfit_piece *A, const seg_model *ma,
                                 const bsfit_piece *B, const seg_model *mb,
                                 const seg_neighbours *nb, fillet_try *best) {
  line_left a[CORNER_TAKE + 1], b[CORNER_TAKE + 1];
  double best_rss = HUGE_VAL;
  size_t ka, kb;
  fillet_try t;
  lines_left(s, A, ma, 1, a);
  lines_left(s, B, mb, 0, b);
  for (ka = 0; ka <= CORNER_TAKE; ka++)
    for (kb = 0; kb <= CORNER_TAKE; kb++)
      if (ka + kb >= CORNER_LEAST && a[ka].ok && b[kb].ok &&
          corner_fillet(s, &a[ka], &b[kb], ka, kb, nb, &t) && try_rss(&t) < best_rss)
        *best = t, best_rss = try_rss(&t);
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
                            size_t np, size_t i, fillet_try *t) {
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
static size_t insert_fillet(bsfit_piece *p, seg_model *md, size_t np, size_t i, const fillet_try *t) {
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
  fillet_try t;
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
