/*
** corners.c
** Sharp corners of a noisy ordered contour: two straight sides meeting near the data
** at a turn much larger than the noise allows (see bsfit_analysis.h).
*/
#include "internal.h"

#include <math.h>
#include <string.h>

#define PI 3.14159265358979323846

/* first and second moments of a run of points, from prefix sums */
typedef struct moments {
  double n, s[3], ss[3][3];
} moments;

typedef struct side {
  double dir[3];  /* unit direction, oriented along the traversal */
  double centre[3];
  double rms;     /* RMS distance of the side's points to its line */
  double extent;  /* distance from the corner point to the far end */
  size_t count;
  double outer_dir[3], outer_centre[3]; /* line of the outer half (from scale/2 on) */
} side;

typedef struct contour {
  const double *pts;
  size_t m;
  int dim, closed;
  double *prefix; /* (m+1) * 10: n, sx, sy, sz, sxx, sxy, sxz, syy, syz, szz over [0, i) */
  double origin[3];
} contour;

static const double *point(const contour *c, size_t i) { return c->pts + (i % c->m) * (size_t)c->dim; }

static double dist(const contour *c, size_t i, size_t j) {
  const double *a = point(c, i), *b = point(c, j);
  double s = 0;
  int d;
  for (d = 0; d < c->dim; d++) s += (a[d] - b[d]) * (a[d] - b[d]);
  return sqrt(s);
}

static void build_prefix(contour *c) {
  size_t i;
  int d, e, q;
  memset(c->prefix, 0, 10 * sizeof(double));
  for (i = 0; i < c->m; i++) {
    const double *P = point(c, i);
    double x[3] = {0, 0, 0};
    double *cur = c->prefix + (i + 1) * 10, *prev = c->prefix + i * 10;
    for (d = 0; d < c->dim; d++) x[d] = P[d] - c->origin[d];
    cur[0] = prev[0] + 1;
    for (d = 0; d < 3; d++) cur[1 + d] = prev[1 + d] + x[d];
    for (d = 0, q = 4; d < 3; d++)
      for (e = d; e < 3; e++, q++) cur[q] = prev[q] + x[d] * x[e];
  }
}

/* moments of the points first..last inclusive, walking forward (modulo m if closed) */
static moments run_moments(const contour *c, size_t first, size_t last) {
  moments mo;
  double acc[10];
  int q, d, e;
  if (first <= last) {
    for (q = 0; q < 10; q++) acc[q] = c->prefix[(last + 1) * 10 + q] - c->prefix[first * 10 + q];
  } else { /* wraps: [first, m) + [0, last] */
    for (q = 0; q < 10; q++)
      acc[q] = c->prefix[c->m * 10 + q] - c->prefix[first * 10 + q] + c->prefix[(last + 1) * 10 + q];
  }
  mo.n = acc[0];
  for (d = 0; d < 3; d++) mo.s[d] = acc[1 + d];
  for (d = 0, q = 4; d < 3; d++)
    for (e = d; e < 3; e++, q++) mo.ss[d][e] = mo.ss[e][d] = acc[q];
  return mo;
}

/* Unit principal direction of a 2 x 2 covariance [a b; b d] in closed form: of the two
** eigenvector formulas for the larger eigenvalue, the longer one (the other may vanish);
** an isotropic covariance has no principal direction, so the hint stands. */
static double principal_2d(double a, double b, double d, const double *hint, double *v) {
  double h = 0.5 * (a - d), lam = 0.5 * (a + d) + sqrt(h * h + b * b);
  double x1 = lam - d, y1 = b, x2 = b, y2 = lam - a, n1 = x1 * x1 + y1 * y1,
         n2 = x2 * x2 + y2 * y2, nrm;
  if (n2 > n1) x1 = x2, y1 = y2, n1 = n2;
  nrm = sqrt(n1);
  if (!(nrm > 1e-300)) {
    x1 = hint[0], y1 = hint[1], nrm = sqrt(x1 * x1 + y1 * y1);
    if (!(nrm > 0)) x1 = 1.0, y1 = 0.0, nrm = 1.0;
  }
  v[0] = x1 / nrm, v[1] = y1 / nrm, v[2] = 0.0;
  return lam;
}

/* The same in 3D by power iteration started on the hint, stopped once the direction
** no longer moves. */
static double principal_3d(double cov[3][3], const double *hint, double *v) {
  double lam = 0;
  int d, e, it;
  for (d = 0; d < 3; d++) v[d] = hint[d];
  for (it = 0; it < 60; it++) {
    double w[3] = {0, 0, 0}, nrm = 0, moved = 0;
    for (d = 0; d < 3; d++)
      for (e = 0; e < 3; e++) w[d] += cov[d][e] * v[e];
    for (d = 0; d < 3; d++) nrm += w[d] * w[d];
    nrm = sqrt(nrm);
    if (!(nrm > 0)) break;
    for (d = 0; d < 3; d++) {
      double x = w[d] / nrm;
      moved += fabs(x - v[d]);
      v[d] = x;
    }
    lam = nrm;
    if (moved < 1e-15) break;
  }
  return lam;
}

/* principal direction of the covariance (oriented along the hint) and the variance
** left across it */
static void fit_line(const contour *c, const moments *mo, const double *hint, side *sd) {
  double cov[3][3], v[3], lam, tr = 0, dot = 0;
  int d, e;
  for (d = 0; d < 3; d++) sd->centre[d] = mo->s[d] / mo->n;
  for (d = 0; d < 3; d++)
    for (e = 0; e < 3; e++) cov[d][e] = mo->ss[d][e] / mo->n - sd->centre[d] * sd->centre[e];
  for (d = 0; d < c->dim; d++) tr += cov[d][d];
  if (c->dim == 2) lam = principal_2d(cov[0][0], cov[0][1], cov[1][1], hint, v);
  else lam = principal_3d(cov, hint, v);
  for (d = 0; d < 3; d++) dot += v[d] * hint[d];
  for (d = 0; d < 3; d++) sd->dir[d] = dot < 0 ? -v[d] : v[d];
  sd->rms = sqrt(fmax(tr - lam, 0.0));
  for (d = 0; d < 3; d++) sd->centre[d] += c->origin[d];
}

static size_t step(const contour *c, size_t i, int forward) {
  if (forward) return (i + 1) % c->m;
  return (i + c->m - 1) % c->m;
}

/* The side of point k in one direction: the points after (or before) k until one is
** `scale` away, k itself excluded (a corner between two samples would otherwise bend
** both sides). 0 when the side is too short or has fewer than 3 points. */
static int collect_side(const contour *c, size_t k, int forward, double scale, side *sd,
                        size_t *far_index) {
  size_t j = k, count = 0, limit = c->closed ? c->m / 2 : c->m, first, mid = k, nouter = 0;
  double hint[3] = {0, 0, 0};
  moments mo;
  side outer;
  int d;
  while (count < limit) {
    size_t nxt = step(c, j, forward);
    if (!c->closed && ((forward && nxt == 0) || (!forward && j == 0))) break;
    j = nxt;
    count++;
    if (mid == k && dist(c, j, k) >= 0.5 * scale) mid = j;
    if (mid != k) nouter++;
    if (dist(c, j, k) >= scale) break;
  }
  if (count < 3 || dist(c, j, k) < 0.5 * scale) return 0;
  first = step(c, k, forward);
  mo = forward ? run_moments(c, first, j) : run_moments(c, j, first);
  for (d = 0; d < c->dim; d++) hint[d] = forward ? point(c, j)[d] - point(c, k)[d] : point(c, k)[d] - point(c, j)[d];
  fit_line(c, &mo, hint, sd);
  /* The outer half stands for the tangent of a rounded bend, the whole side for a
  ** secant; secants of a fillet meet near the arc, tangents do not. */
  if (nouter >= 3) {
    mo = forward ? run_moments(c, mid, j) : run_moments(c, j, mid);
    fit_line(c, &mo, hint, &outer);
  } else {
    outer = *sd;
  }
  memcpy(sd->outer_dir, outer.dir, sizeof outer.dir);
  memcpy(sd->outer_centre, outer.centre, sizeof outer.centre);
  sd->extent = dist(c, j, k);
  sd->count = count;
  *far_index = j;
  return 1;
}

/* angle between the two sides of k at the given scale, or -1 if a side is too short */
static double turn_at_scale(const contour *c, size_t k, double scale, side *left, side *right,
                            size_t *from, size_t *to) {
  double cosang = 0;
  int d;
  if (!collect_side(c, k, 0, scale, left, from) || !collect_side(c, k, 1, scale, right, to))
    return -1.0;
  for (d = 0; d < 3; d++) cosang += left->dir[d] * right->dir[d];
  return acos(fmax(-1.0, fmin(1.0, cosang)));
}

/* intersection (2D) or midpoint of closest approach (3D) of the outer side lines */
static int meet(const side *a, const side *b, int dim, double *x) {
  double w[3], aa = 0, ab = 0, bb = 0, aw = 0, bw = 0, den, s, t;
  const double *ad = a->outer_dir, *bd = b->outer_dir, *ac = a->outer_centre, *bc = b->outer_centre;
  int d;
  for (d = 0; d < 3; d++) {
    w[d] = ac[d] - bc[d];
    aa += ad[d] * ad[d];
    ab += ad[d] * bd[d];
    bb += bd[d] * bd[d];
    aw += ad[d] * w[d];
    bw += bd[d] * w[d];
  }
  den = aa * bb - ab * ab;
  if (!(den > 1e-12)) return 0;
  s = (ab * bw - bb * aw) / den;
  t = (aa * bw - ab * aw) / den;
  for (d = 0; d < dim; d++) x[d] = 0.5 * ((ac[d] + s * ad[d]) + (bc[d] + t * bd[d]));
  return 1;
}

typedef struct candidate {
  size_t k, from, to; /* the corner and its window (inclusive, along the traversal) */
  double angle, gap; /* the turn, and the distance from the side lines' meeting point */
  double position;    /* fractional index of the corner along the samples */
  double point[3];    /* where the side lines meet */
} candidate;

static double median_spacing(const contour *c, double *scratch) {
  size_t i, n = c->closed ? c->m : c->m - 1;
  for (i = 0; i < n; i++) scratch[i] = dist(c, i, i + 1);
  return bsfit__select(scratch, n, n / 2);
}

static double bbox_diagonal(const contour *c) {
  double lo[3] = {0, 0, 0}, hi[3] = {0, 0, 0}, s = 0;
  size_t i;
  int d;
  for (d = 0; d < c->dim; d++) lo[d] = hi[d] = c->pts[d];
  for (i = 0; i < c->m; i++)
    for (d = 0; d < c->dim; d++) {
      double v = point(c, i)[d];
      if (v < lo[d]) lo[d] = v;
      if (v > hi[d]) hi[d] = v;
    }
  for (d = 0; d < c->dim; d++) s += (hi[d] - lo[d]) * (hi[d] - lo[d]);
  return sqrt(s);
}

/* Residual sum of squares of the best smooth model of the window from..to (inclusive):
** a parabola t = c0 + c1 s + c2 s^2 in the frame of the window's chord. A sharp corner
** cannot be followed by it; a tight smooth bend can. */
static double parabola_rss(const contour *c, size_t from, size_t to) {
  const double *a = point(c, from), *b = point(c, to);
  double ax[3] = {0, 0, 0}, len = 0, A[3][3] = {{0}}, rhs[3] = {0}, sum_tt = 0, coef[3];
  size_t i, n = (to + c->m - from) % c->m + 1;
  int d, p, q;
  for (d = 0; d < c->dim; d++) {
    ax[d] = b[d] - a[d];
    len += ax[d] * ax[d];
  }
  len = sqrt(len);
  if (!(len > 0)) return INFINITY; /* the window folds back onto itself */
  for (d = 0; d < c->dim; d++) ax[d] /= len;
  for (i = 0; i < n; i++) {
    const double *P = point(c, from + i);
    double s = 0, t2 = 0, x[3];
    for (d = 0; d < c->dim; d++) s += (P[d] - a[d]) * ax[d];
    for (d = 0; d < c->dim; d++) {
      double r = P[d] - a[d] - s * ax[d];
      t2 += r * r;
    }
    /* signed normal coordinate in 2D; in 3D the distance to the chord stands in */
    if (c->dim == 2) t2 = (P[1] - a[1]) * ax[0] - (P[0] - a[0]) * ax[1];
    else t2 = sqrt(t2);
    s /= len;
    x[0] = 1.0;
    x[1] = s;
    x[2] = s * s;
    for (p = 0; p < 3; p++) {
      for (q = 0; q < 3; q++) A[p][q] += x[p] * x[q];
      rhs[p] += x[p] * t2;
    }
    sum_tt += t2 * t2;
  }
  /* solve the 3x3 normal equations (Cramer is enough at this size) */
  {
    double det = A[0][0] * (A[1][1] * A[2][2] - A[1][2] * A[2][1]) -
                 A[0][1] * (A[1][0] * A[2][2] - A[1][2] * A[2][0]) +
                 A[0][2] * (A[1][0] * A[2][1] - A[1][1] * A[2][0]);
    double rss;
    if (!(fabs(det) > 1e-14)) return INFINITY;
    for (p = 0; p < 3; p++) {
      double M[3][3];
      memcpy(M, A, sizeof M);
      for (q = 0; q < 3; q++) M[q][p] = rhs[q];
      coef[p] = (M[0][0] * (M[1][1] * M[2][2] - M[1][2] * M[2][1]) -
                 M[0][1] * (M[1][0] * M[2][2] - M[1][2] * M[2][0]) +
                 M[0][2] * (M[1][0] * M[2][1] - M[1][1] * M[2][0])) / det;
    }
    rss = sum_tt - (coef[0] * rhs[0] + coef[1] * rhs[1] + coef[2] * rhs[2]);
    return fmax(rss, 0.0);
  }
}

/* The turn at k if it is a corner candidate, else a negative value. */
/* The turn of the polygon at sample k (angle between its two edges), radians. */
static double polygon_turn(const contour *c, size_t k) {
  const double *a, *b = point(c, k), *q;
  double ab = 0, bq = 0, dot = 0;
  int d;
  if (!c->closed && (k == 0 || k + 1 >= c->m)) return 0.0;
  a = point(c, (k + c->m - 1) % c->m);
  q = point(c, k + 1);
  for (d = 0; d < c->dim; d++) {
    ab += (b[d] - a[d]) * (b[d] - a[d]);
    bq += (q[d] - b[d]) * (q[d] - b[d]);
    dot += (b[d] - a[d]) * (q[d] - b[d]);
  }
  if (!(ab > 0 && bq > 0)) return 0.0;
  return acos(fmax(-1.0, fmin(1.0, dot / sqrt(ab * bq))));
}

/* Where the corner point x lies along the samples: on the edge at k (before or
** after it) nearest to x, as j + |Q_j x| / (|Q_j x| + |x Q_{j+1}|), wrapped into [0, m). */
static double corner_position(const contour *c, size_t k, const double *x) {
  double best_d = INFINITY, best = (double)k;
  int dir, d;
  for (dir = -1; dir <= 1; dir += 2) {
    size_t j;
    const double *a, *b;
    double ab2 = 0, t = 0, dist2 = 0, da = 0, db = 0;
    if (!c->closed && ((dir < 0 && k == 0) || (dir > 0 && k + 1 >= c->m))) continue;
    j = dir < 0 ? (k + c->m - 1) % c->m : k;
    a = point(c, j);
    b = point(c, j + 1);
    for (d = 0; d < c->dim; d++) {
      ab2 += (b[d] - a[d]) * (b[d] - a[d]);
      t += (x[d] - a[d]) * (b[d] - a[d]);
      da += (x[d] - a[d]) * (x[d] - a[d]);
      db += (x[d] - b[d]) * (x[d] - b[d]);
    }
    t = ab2 > 0 ? fmin(1.0, fmax(0.0, t / ab2)) : 0.0;
    for (d = 0; d < c->dim; d++) {
      double e = a[d] + t * (b[d] - a[d]) - x[d];
      dist2 += e * e;
    }
    if (dist2 < best_d) {
      double f = (sqrt(da) + sqrt(db)) > 0 ? sqrt(da) / (sqrt(da) + sqrt(db)) : 0.0;
      best_d = dist2;
      /* a corner at (or within rounding of) a sample is that sample */
      best = f > 1.0 - 1e-9 ? (double)(j + 1) : (double)j + (f < 1e-9 ? 0.0 : f);
    }
  }
  if (best >= (double)c->m) best -= (double)c->m;
  return best;
}

static double corner_turn(const contour *c, size_t k, double scale, double sigma,
                          double spacing, double min_angle, size_t *from, size_t *to,
                          double *gap_out, double *position, double *meet_point) {
  side left, right, half_left, half_right;
  double angle, half, se, x[3] = {0, 0, 0}, gap = 0, rss_lines, rss_smooth;
  size_t half_from, half_to;
  int d;
  angle = turn_at_scale(c, k, scale, &left, &right, from, to);
  if (angle < 0) return -1.0;
  /* standard error of a line direction fitted to n points spread over `extent` */
  se = sigma * sqrt(12.0 / (double)left.count) / left.extent +
       sigma * sqrt(12.0 / (double)right.count) / right.extent;
  if (angle < min_angle || angle < 6.0 * se) return -1.0;
  if (left.rms > 2.5 * sigma + 0.02 * scale || right.rms > 2.5 * sigma + 0.02 * scale) return -1.0;
  if (!meet(&left, &right, c->dim, x)) return -1.0;
  for (d = 0; d < c->dim; d++) gap += (x[d] - point(c, k)[d]) * (x[d] - point(c, k)[d]);
  *gap_out = sqrt(gap);
  /* The meeting point stands for a corner between two samples only when both sides
  ** are straight to the noise level (a curved side bends its line away from the true
  ** corner) and the polygon does not already turn (almost) all the way at Q_k itself
  ** (then the corner is that sample). */
  if (left.rms <= 2.0 * sigma + 1e-6 * scale && right.rms <= 2.0 * sigma + 1e-6 * scale &&
      polygon_turn(c, k) < 0.9 * angle)
    *position = corner_position(c, k, x);
  else
    *position = (double)k;
  memcpy(meet_point, x, sizeof x);
  if (*gap_out > 3.0 * sigma + 0.5 * spacing + 0.02 * scale) return -1.0;
  /* two lines must explain the window far better than a smooth bend does */
  rss_lines = (double)left.count * left.rms * left.rms + (double)right.count * right.rms * right.rms;
  rss_smooth = parabola_rss(c, *from, *to);
  if (rss_smooth - rss_lines < 25.0 * sigma * sigma ||
      rss_smooth < 2.0 * rss_lines)
    return -1.0;
  /* a corner turns as much at half the scale; a bend turns less, in proportion */
  half = turn_at_scale(c, k, 0.5 * scale, &half_left, &half_right, &half_from, &half_to);
  if (half >= 0 && half < 0.75 * angle) return -1.0;
  return angle;
}

/* Is k strictly inside w's window (from, to), walking forward, possibly across the
** end? The far ends are excluded: a corner may stand at the end of its neighbour's
** side (a notch as deep as the scale), since both sides passed the straightness test. */
static int in_window(const candidate *w, size_t k, size_t m) {
  size_t len = (w->to + m - w->from) % m, off = (k + m - w->from) % m;
  return off > 0 && off < len;
}

/* Keeps the candidates nearest to where their side lines meet (the neighbours of a
** corner pass the tests too, with a larger gap); a kept corner suppresses the
** candidates in its window. */
static size_t thin_candidates(candidate *cand, size_t nc, size_t m) {
  size_t i, j, kept = 0;
  /* insertion sort by increasing gap: the candidates are few */
  for (i = 1; i < nc; i++) {
    candidate t = cand[i];
    for (j = i; j > 0 && cand[j - 1].gap > t.gap; j--) cand[j] = cand[j - 1];
    cand[j] = t;
  }
  for (i = 0; i < nc; i++) {
    int free_ = 1;
    for (j = 0; j < kept && free_; j++)
      if (in_window(&cand[j], cand[i].k, m) || in_window(&cand[i], cand[j].k, m)) free_ = 0;
    if (free_) cand[kept++] = cand[i];
  }
  /* back to contour order */
  for (i = 1; i < kept; i++) {
    candidate t = cand[i];
    for (j = i; j > 0 && cand[j - 1].k > t.k; j--) cand[j] = cand[j - 1];
    cand[j] = t;
  }
  return kept;
}

/* How far the sides of the current point reach, in index steps back and forth; moved
** along with the point (two pointers), so the scan is O(m) whatever the window. */
typedef struct window {
  size_t back, fwd;
} window;

static size_t at(const contour *c, size_t k, long off) {
  long m = (long)c->m;
  return (size_t)((((long)k + off) % m + m) % m);
}

/* Moves the window to point k: each side ends at the first point (going outwards) that
** is `scale` away, found from the previous ends. 0 when a side is cut by an open end. */
static int move_window(const contour *c, size_t k, double scale, window *w) {
  size_t limit = c->closed ? c->m / 2 : c->m;
  if (w->fwd == 0) w->fwd = w->back = 1; /* first point */
  else { w->back++; if (w->fwd > 1) w->fwd--; }
  while (w->fwd > 1 && dist(c, k, at(c, k, (long)w->fwd - 1)) >= scale) w->fwd--;
  while (w->fwd < limit && dist(c, k, at(c, k, (long)w->fwd)) < scale) w->fwd++;
  if (w->back > limit) w->back = limit;
  while (w->back > 1 && dist(c, k, at(c, k, -((long)w->back - 1))) >= scale) w->back--;
  while (w->back < limit && dist(c, k, at(c, k, -(long)w->back)) < scale) w->back++;
  if (!c->closed && (k < w->back || k + w->fwd >= c->m)) return 0;
  return 1;
}

/* A cheap first test from the two-pointer window and prefix sums, O(1) per point:
** both sides long enough, turning enough and straight enough. The exact test
** (corner_turn) runs only where this passes. */
static int quick_candidate(const contour *c, size_t k, double scale, double sigma,
                           double min_angle, window *w) {
  moments ml, mr;
  side left, right;
  double hint_l[3] = {0, 0, 0}, hint_r[3] = {0, 0, 0}, cosang = 0, angle;
  size_t first_l, first_r;
  int d;
  if (!move_window(c, k, scale, w) || w->back < 3 || w->fwd < 3) return 0;
  first_l = at(c, k, -(long)w->back);
  first_r = at(c, k, 1);
  ml = run_moments(c, first_l, at(c, k, -1));
  mr = run_moments(c, first_r, at(c, k, (long)w->fwd));
  for (d = 0; d < c->dim; d++) {
    hint_l[d] = point(c, k)[d] - point(c, first_l)[d];
    hint_r[d] = point(c, at(c, k, (long)w->fwd))[d] - point(c, k)[d];
  }
  fit_line(c, &ml, hint_l, &left);
  fit_line(c, &mr, hint_r, &right);
  for (d = 0; d < 3; d++) cosang += left.dir[d] * right.dir[d];
  angle = acos(fmax(-1.0, fmin(1.0, cosang)));
  /* generous: the exact test decides; this only skips the plainly smooth points */
  if (angle < 0.8 * min_angle) return 0;
  if (left.rms > 4.0 * sigma + 0.04 * scale || right.rms > 4.0 * sigma + 0.04 * scale) return 0;
  return 1;
}

bsfit_err bsfit_corners_detect(const double *pts, size_t m, int dim,
                               const bsfit_corner_opts *opts, bsfit_corner *corners,
                               size_t cap, size_t *count, bsfit_status *st) {
  contour c;
  candidate *cand;
  double sigma, scale, spacing, min_angle, *scratch;
  size_t k, nc = 0, kept, bytes_prefix, bytes_cand;
  window reach = {0, 0};
  bsfit_corner_opts o;
  bsfit_err e;
  memset(&o, 0, sizeof o);
  if (opts) o = *opts;
  *count = 0;
  if (o.scale < 0 || !isfinite(o.scale) || !isfinite(o.sigma) || o.min_angle_deg < 0 ||
      o.min_angle_deg >= 180 || !isfinite(o.min_angle_deg))
    return bsfit__fail(st, BSFIT_EINVAL, "corner options: scale %g, sigma %g, min_angle_deg %g out of range",
                       o.scale, o.sigma, o.min_angle_deg);
  sigma = o.sigma;
  if (sigma <= 0) {
    e = bsfit_noise_sigma(pts, m, dim, o.closed, &sigma, st);
    if (e != BSFIT_OK) return e;
  } else if (dim != 2 && dim != 3) {
    return bsfit__fail(st, BSFIT_EDIM, "corner detection needs 2D or 3D points, got dim %d", dim);
  } else if (pts == NULL || m < 6) {
    return bsfit__fail(st, BSFIT_ETOOFEW, "corner detection needs at least 6 points, got %zu", m);
  } else if (!bsfit__all_finite(pts, m * (size_t)dim)) {
    return bsfit__fail(st, BSFIT_ENONFINITE, "points contain NaN or Inf");
  }
  memset(&c, 0, sizeof c);
  c.pts = pts;
  c.m = m;
  c.dim = dim;
  c.closed = o.closed != 0;
  memcpy(c.origin, pts, (size_t)dim * sizeof(double));
  bytes_prefix = (m + 1) * 10 * sizeof(double);
  bytes_cand = m * sizeof(candidate);
  c.prefix = bsfit__alloc(NULL, bytes_prefix);
  cand = bsfit__alloc(NULL, bytes_cand);
  scratch = bsfit__alloc(NULL, m * sizeof(double));
  if (c.prefix == NULL || cand == NULL || scratch == NULL) {
    e = bsfit__fail(st, BSFIT_ENOMEM, "out of memory for corner detection of %zu points", m);
    goto done;
  }
  build_prefix(&c);
  spacing = median_spacing(&c, scratch);
  scale = o.scale > 0 ? o.scale : fmin(fmax(40.0 * sigma, 4.0 * spacing), 0.1 * bbox_diagonal(&c));
  min_angle = (o.min_angle_deg > 0 ? o.min_angle_deg : 30.0) * PI / 180.0;
  for (k = 0; k < m; k++) {
    size_t from, to;
    double gap = 0, pos = 0, x[3] = {0, 0, 0}, a;
    if (!quick_candidate(&c, k, scale, sigma, min_angle, &reach)) continue;
    a = corner_turn(&c, k, scale, sigma, spacing, min_angle, &from, &to, &gap, &pos, x);
    if (a >= 0) {
      cand[nc].k = k;
      cand[nc].from = from;
      cand[nc].to = to;
      cand[nc].angle = a;
      cand[nc].gap = gap;
      cand[nc].position = pos;
      memcpy(cand[nc].point, x, sizeof x);
      nc++;
    }
  }
  kept = thin_candidates(cand, nc, m);
  for (k = 0; k < kept && k < cap; k++) {
    corners[k].index = cand[k].k;
    corners[k].angle = cand[k].angle * 180.0 / PI;
    corners[k].position = cand[k].position;
    memcpy(corners[k].point, cand[k].point, sizeof cand[k].point);
  }
  *count = kept;
  e = bsfit__ok(st);
done:
  bsfit__free(NULL, c.prefix, bytes_prefix);
  bsfit__free(NULL, cand, bytes_cand);
  bsfit__free(NULL, scratch, m * sizeof(double));
  return e;
}
