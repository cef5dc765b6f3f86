/*
** segment_evidence.c
** The evidence of a corner between two pieces of a segmentation (bsfit_piece.evidence):
** how much worse one smooth curve explains the samples next to it than the two models
** meeting there, in sigma^2. The smooth curves tried: a circle, a cubic over the chord, a
** regular parametric cubic, and between two arcs a bend (docs/auto.md, "Evidence of
** corners").
*/
#include "segment_internal.h"

#include <math.h>
#include <string.h>

/* the geometric circle of n samples from first: 1 and its RMS when it can be fitted */
static int fit_circle(const seg_section *s, size_t first, size_t n, double *rms) {
  bsfit__run r = run_of(s, first, n);
  bsfit__circle C;
  if (!bsfit__fit_circle(&r, NULL, 1e-3 * s->tol, &C)) return 0;
  bsfit__circle_max(&C, &r, rms);
  return 1;
}

/* residual sum of squares of a cubic y(x) over the run, in the frame of its chord (x
** along it, scaled to [-1, 1]); HUGE_VAL when it cannot be fitted */
static double cubic_rss(const seg_section *s, size_t first, size_t n) {
  const double *a = sample(s, first), *b = sample(s, first + n - 1);
  double ux = b[0] - a[0], uy = b[1] - a[1], len = hypot(ux, uy),
         A[BSFIT__SMALL][BSFIT__SMALL] = {{0}};
  double g[4] = {0, 0, 0, 0}, rss = 0;
  size_t k;
  int i, j;
  if (n < 6 || !(len > 0)) return HUGE_VAL;
  ux /= len, uy /= len;
  for (k = 0; k < n; k++) {
    const double *q = sample(s, first + k);
    double x = ((q[0] - a[0]) * ux + (q[1] - a[1]) * uy) / len * 2.0 - 1.0;
    double y = -(q[0] - a[0]) * uy + (q[1] - a[1]) * ux, pw[4] = {1, x, x * x, x * x * x};
    for (i = 0; i < 4; i++) {
      g[i] += pw[i] * y;
      for (j = 0; j < 4; j++) A[i][j] += pw[i] * pw[j];
    }
  }
  if (!bsfit__small_cholesky(4, A)) return HUGE_VAL;
  bsfit__small_chol_solve(4, A, g);
  for (k = 0; k < n; k++) {
    const double *q = sample(s, first + k);
    double x = ((q[0] - a[0]) * ux + (q[1] - a[1]) * uy) / len * 2.0 - 1.0;
    double y = -(q[0] - a[0]) * uy + (q[1] - a[1]) * ux;
    double e = y - (g[0] + x * (g[1] + x * (g[2] + x * g[3])));
    rss += e * e;
  }
  return rss;
}

/* residual sum of squares (true distances) of a parametric cubic (x(t), y(t)) over the
** run: t by chord length, one least-squares fit, each sample's foot point by Newton, a
** second fit at those feet. A smooth bend that turns too far for a cubic graph over the
** chord (the end of an ellipse, sampled sparsely) is one for it. HUGE_VAL when it cannot
** be fitted. */
#define EVIDENCE_REACH 8 /* samples on each side of a join (fewer on arcs: arc_reach) */
#define PCUBIC_MAX (2 * EVIDENCE_REACH)
static void pcubic_fit(const seg_section *s, size_t first, size_t n, const double *t, double cx[4],
                       double cy[4], int *ok) {
  double A[BSFIT__SMALL][BSFIT__SMALL] = {{0}}, L[BSFIT__SMALL][BSFIT__SMALL];
  size_t k;
  int i, j;
  for (i = 0; i < 4; i++) cx[i] = cy[i] = 0;
  for (k = 0; k < n; k++) {
    const double *q = sample(s, first + k);
    double pw[4] = {1, t[k], t[k] * t[k], t[k] * t[k] * t[k]};
    for (i = 0; i < 4; i++) {
      cx[i] += pw[i] * q[0], cy[i] += pw[i] * q[1];
      for (j = 0; j < 4; j++) A[i][j] += pw[i] * pw[j];
    }
  }
  memcpy(L, A, sizeof L);
  *ok = bsfit__small_cholesky(4, L);
  if (!*ok) return;
  bsfit__small_chol_solve(4, L, cx);
  bsfit__small_chol_solve(4, L, cy);
}

/* the foot parameter of q on the cubic from t0 (a few Newton steps), its squared distance */
static double pcubic_foot(const double cx[4], const double cy[4], const double *q, double *t0) {
  double t = *t0, ex = 0, ey = 0;
  int it;
  for (it = 0; it < 6; it++) {
    double x = cx[0] + t * (cx[1] + t * (cx[2] + t * cx[3]));
    double y = cy[0] + t * (cy[1] + t * (cy[2] + t * cy[3]));
    double dx = cx[1] + t * (2 * cx[2] + 3 * t * cx[3]), dy = cy[1] + t * (2 * cy[2] + 3 * t * cy[3]);
    double ddx = 2 * cx[2] + 6 * t * cx[3], ddy = 2 * cy[2] + 6 * t * cy[3];
    double g, h;
    ex = x - q[0], ey = y - q[1];
    g = ex * dx + ey * dy;
    h = dx * dx + dy * dy + ex * ddx + ey * ddy;
    if (!(h > 0)) break;
    t -= g / h;
  }
  {
    double x = cx[0] + t * (cx[1] + t * (cx[2] + t * cx[3]));
    double y = cy[0] + t * (cy[1] + t * (cy[2] + t * cy[3]));
    ex = x - q[0], ey = y - q[1];
  }
  *t0 = t;
  return ex * ex + ey * ey;
}

/* A parametric cubic can stop and turn (a cusp): a corner in disguise. It stands for a
** smooth curve only when its speed over [-1, 1] stays within a factor PCUBIC_SPEED (the
** samples, by chord length, move at an even pace along a smooth bend). */
#define PCUBIC_SPEED 3.0
static int pcubic_regular(const double cx[4], const double cy[4]) {
  double lo = HUGE_VAL, hi = 0;
  int k;
  for (k = 0; k <= 16; k++) {
    double t = -1 + k / 8.0, dx = cx[1] + t * (2 * cx[2] + 3 * t * cx[3]);
    double dy = cy[1] + t * (2 * cy[2] + 3 * t * cy[3]), v = hypot(dx, dy);
    lo = fmin(lo, v), hi = fmax(hi, v);
  }
  return hi > 0 && hi <= PCUBIC_SPEED * lo;
}

static double pcubic_rss(const seg_section *s, size_t first, size_t n) {
  double t[PCUBIC_MAX], cx[4], cy[4], len = 0, rss = 0;
  size_t k;
  int ok, round;
  if (n < 10 || n > PCUBIC_MAX) return HUGE_VAL;
  t[0] = 0;
  for (k = 1; k < n; k++) {
    const double *a = sample(s, first + k - 1), *b = sample(s, first + k);
    len += hypot(b[0] - a[0], b[1] - a[1]);
    t[k] = len;
  }
  if (!(len > 0)) return HUGE_VAL;
  for (k = 0; k < n; k++) t[k] = 2 * t[k] / len - 1;
  for (round = 0; round < 2; round++) {
    pcubic_fit(s, first, n, t, cx, cy, &ok);
    if (!ok) return HUGE_VAL;
    rss = 0;
    for (k = 0; k < n; k++) rss += pcubic_foot(cx, cy, sample(s, first + k), &t[k]);
  }
  return pcubic_regular(cx, cy) ? rss : HUGE_VAL;
}

/* How much worse one smooth curve explains the samples of A and B next to their corner
** (up to EVIDENCE_REACH on each side: a smooth contour is smooth locally, while two
** long pieces of it together may turn too far for one cubic) than their two models, in
** units of sigma^2 = (tol / tol_sigma)^2. */
#define EVIDENCE_TURN (PI / 4)

/* On a dense section 8 samples span less than the noise, and one cubic follows a corner
** within it: the window then reaches REACH_SIGMA sigma from the join along each piece
** (the least-squares cubic over a right angle of sides L misses it by L/20 RMS, L/7.5 at
** worst: 1.6 and 4 sigma here, 2.6 sigma^2 of evidence per sample), up to REACH_MAX
** samples. Where the join's own samples lie apart (a stretch of the outline not
** sampled), the window reaches twice that gap: two runs shorter than the gap between
** them are each a position and a direction to one cubic, which then bends through the
** gap as it likes (a T of 300 uneven noisy samples per side, 5% of each side bare at its
** ends: evidence 2 to 9 at right angles, softened into bulging bends). A corner is
** local: the window reaches at most a tenth of the section's size (at noise 1e-2 of the
** size 32 sigma spans a third of it, and the tip of an ellipse that a line cut off read
** as a corner against one cubic over half the ellipse). */
#define REACH_SIGMA 32.0
#define REACH_GAP 2.0
#define REACH_SIZE 0.1
#define REACH_MAX 512

/* how many samples of p, from its last (end) or first, the window takes: EVIDENCE_REACH,
** or on a dense section as many as lie within `reach` of that sample */
static size_t dense_reach(const seg_section *s, const bsfit_piece *p, int end, double reach) {
  const double *q0 = sample(s, end ? p->first + p->count - 1 : p->first);
  size_t n = p->count < REACH_MAX ? p->count : REACH_MAX, k;
  if (n <= EVIDENCE_REACH) return n;
  for (k = EVIDENCE_REACH; k < n; k++) {
    const double *q = sample(s, end ? p->first + p->count - 1 - k : p->first + k);
    if (!(hypot(q[0] - q0[0], q[1] - q0[1]) < reach)) break;
  }
  return k;
}

/* How many samples of an arc, counted from its sample `from` (its first when step is +1,
** its last when -1), lie within EVIDENCE_TURN of that sample around its centre: an arc's
** tangent turns as it goes, and two half ellipses meet at the ends of the major axis in
** what one cubic across 8 + 8 sparse samples (two thirds of the ellipse) cannot follow. */
static size_t arc_reach(const seg_section *s, const bsfit_piece *p, const seg_model *md, size_t n,
                        int end) {
  const double *c = md->circle.c, *q0 = sample(s, end ? p->first + p->count - 1 : p->first);
  size_t k;
  if (md->kind != ARC) return n;
  for (k = 1; k < n; k++) {
    const double *q = sample(s, end ? p->first + p->count - 1 - k : p->first + k);
    double ax = q0[0] - c[0], ay = q0[1] - c[1], bx = q[0] - c[0], by = q[1] - c[1];
    if (atan2(fabs(ax * by - ay * bx), ax * bx + ay * by) > EVIDENCE_TURN) break;
  }
  return k < 3 && n >= 3 ? 3 : k;
}

/* The residual over the window [first, first + n) (na samples of A, then B's) of a bend
** instead of the corner: a circle tangent to both pieces at their meeting point V, of
** radius r (its tangent points r tan(turn/2) from V), the models beyond. The bend is the
** one smooth alternative a sparse section can tell from a corner only when it is wider
** than the spacing: r from the one two steps long (arc length 2 h) up, the best kept. A
** sparse ellipse's end (radius of curvature about a step) is such a bend; a true corner,
** its nearest samples half a step away, is far from every one. */
static double bend_rss(const seg_section *s, const bsfit_piece *A, const seg_model *ma,
                       const bsfit_piece *B, const seg_model *mb, size_t first, size_t na,
                       size_t n) {
  const double *V = A->end, *ta = A->t_end, *tb = B->t_start;
  double theta = atan2(fabs(ta[0] * tb[1] - ta[1] * tb[0]), ta[0] * tb[0] + ta[1] * tb[1]);
  double u[2] = {tb[0] - ta[0], tb[1] - ta[1]}, un = hypot(u[0], u[1]), len = 0, reach = 0;
  double r, best = HUGE_VAL;
  size_t k;
  if (!(theta > 1e-3) || !(theta < PI - 1e-3) || n < 2 || !(un > 0)) return HUGE_VAL;
  u[0] /= un, u[1] /= un;
  for (k = 0; k < n; k++) {
    const double *q = sample(s, first + k);
    if (k > 0) len += hypot(q[0] - sample(s, first + k - 1)[0], q[1] - sample(s, first + k - 1)[1]);
    reach = fmax(reach, hypot(q[0] - V[0], q[1] - V[1]));
  }
  for (r = 2 * len / (double)(n - 1) / theta; r * tan(theta / 2) <= reach; r *= 1.3) {
    double T = r * tan(theta / 2), d = r / cos(theta / 2), c[2] = {V[0] + u[0] * d, V[1] + u[1] * d};
    double rss = 0;
    for (k = 0; k < n; k++) {
      const double *q = sample(s, first + k);
      double e;
      if (k < na && (q[0] - V[0]) * ta[0] + (q[1] - V[1]) * ta[1] < -T)
        e = model_dist(ma, q);
      else if (k >= na && (q[0] - V[0]) * tb[0] + (q[1] - V[1]) * tb[1] > T)
        e = model_dist(mb, q);
      else
        e = fabs(hypot(q[0] - c[0], q[1] - c[1]) - r);
      rss += e * e;
    }
    best = fmin(best, rss);
  }
  return best;
}

double bsfit__join_evidence(const seg_section *s, const bsfit_piece *A, const seg_model *ma,
                            const bsfit_piece *B, const seg_model *mb, double sigma) {
  const double *qa = sample(s, A->first + A->count - 1), *qb = sample(s, B->first);
  double reach = fmin(fmax(REACH_SIGMA * sigma, REACH_GAP * hypot(qb[0] - qa[0], qb[1] - qa[1])),
                      REACH_SIZE * s->size);
  size_t na = arc_reach(s, A, ma, dense_reach(s, A, 1, reach), 1);
  size_t nb = arc_reach(s, B, mb, dense_reach(s, B, 0, reach), 0), k,
         first, n;
  int shared = B->first == (A->first + A->count - 1) % s->m;
  double two = 0, one, rms;
  first = A->first + A->count - na;
  for (k = 0; k < na; k++) two += pow(model_dist(ma, sample(s, first + k)), 2);
  for (k = 0; k < nb; k++) two += pow(model_dist(mb, sample(s, B->first + k)), 2);
  if (shared)
    two -= 0.5 * (pow(model_dist(ma, sample(s, B->first)), 2) +
                  pow(model_dist(mb, sample(s, B->first)), 2));
  n = na + nb - (size_t)shared;
  if (n > s->m) n = s->m;
  one = fmin(cubic_rss(s, first, n), pcubic_rss(s, first, n));
  if (ma->kind == ARC && mb->kind == ARC)
    one = fmin(one, bend_rss(s, A, ma, B, mb, first, shared ? na - 1 : na, n));
  if (fit_circle(s, first, n, &rms) && rms * rms * (double)n < one) one = rms * rms * (double)n;
  return (one - two) / (sigma * sigma);
}
