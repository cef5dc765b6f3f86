/*
** corners_sides.c
** The straight sides of a corner candidate (corners_internal.h): moments of runs from
** prefix sums, principal directions, a side's line, where two lines meet and how surely,
** and whether a turn is concentrated at the corner.
*/
#include "corners_internal.h"

#include <math.h>
#include <string.h>

void bsfit__corner_build_prefix(contour *c) {
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
moments bsfit__corner_run_moments(const contour *c, size_t first, size_t last) {
  moments mo;
  double acc[10];
  int q, d, e;
  if (first <= last) {
    for (q = 0; q < 10; q++) acc[q] = c->prefix[(last + 1) * 10 + q] - c->prefix[first * 10 + q];
  } else { /* wraps: [first, m) + [0, last] */
    for (q = 0; q < 10; q++)
      acc[q] = c->prefix[c->m * 10 + q] - c->prefix[first * 10 + q] +
               c->prefix[(last + 1) * 10 + q];
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
void bsfit__corner_fit_line(const contour *c, const moments *mo, const double *hint, side *sd) {
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
  sd->spread = lam;
  for (d = 0; d < 3; d++) sd->centre[d] += c->origin[d];
}

/* The side of point k in one direction: the points after (or before) k until one is
** `scale` away, k itself excluded (a corner between two samples would otherwise bend
** both sides). 0 when the side is too short or has fewer than 3 points. */
int bsfit__corner_collect_side(const contour *c, size_t k, int forward, double scale, side *sd,
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
  mo = forward ? bsfit__corner_run_moments(c, first, j) : bsfit__corner_run_moments(c, j, first);
  for (d = 0; d < c->dim; d++)
    hint[d] = forward ? point(c, j)[d] - point(c, k)[d] : point(c, k)[d] - point(c, j)[d];
  bsfit__corner_fit_line(c, &mo, hint, sd);
  /* The outer half stands for the tangent of a rounded bend, the whole side for a
  ** secant; secants of a fillet meet near the arc, tangents do not. */
  if (nouter >= 3) {
    mo = forward ? bsfit__corner_run_moments(c, mid, j) : bsfit__corner_run_moments(c, j, mid);
    bsfit__corner_fit_line(c, &mo, hint, &outer);
    outer.count = nouter;
  } else {
    outer = *sd;
    outer.count = count;
  }
  memcpy(sd->outer_dir, outer.dir, sizeof outer.dir);
  memcpy(sd->outer_centre, outer.centre, sizeof outer.centre);
  sd->outer_n = (double)outer.count;
  sd->outer_spread = outer.spread;
  sd->extent = dist(c, j, k);
  sd->count = count;
  sd->k = k;
  sd->forward = forward;
  *far_index = j;
  return 1;
}

/* angle between the two sides of k at the given scale, or -1 if a side is too short */
double bsfit__corner_turn_at_scale(const contour *c, size_t k, double scale, side *left,
                                   side *right, size_t *from, size_t *to) {
  double cosang = 0;
  int d;
  if (!bsfit__corner_collect_side(c, k, 0, scale, left, from) ||
      !bsfit__corner_collect_side(c, k, 1, scale, right, to))
    return -1.0;
  for (d = 0; d < 3; d++) cosang += left->dir[d] * right->dir[d];
  return acos(fmax(-1.0, fmin(1.0, cosang)));
}

/* intersection (2D) or midpoint of closest approach (3D) of the lines through ac
** along ad and through bc along bd; 0 when they are (nearly) parallel */
int bsfit__corner_meet_lines(const double *ac, const double *ad, const double *bc, const double *bd,
                             int dim, double *x) {
  double w[3], aa = 0, ab = 0, bb = 0, aw = 0, bw = 0, den, s, t;
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

/* where the outer side lines meet */
int bsfit__corner_meet(const side *a, const side *b, int dim, double *x) {
  return bsfit__corner_meet_lines(a->outer_centre, a->outer_dir, b->outer_centre, b->outer_dir, dim,
                                  x);
}

/* Variance, per coordinate direction across each line, of where the outer side lines
** meet: each line's offset at x has variance sigma^2 (1/n + d^2 / S) (d the distance
** of x from the line's centroid along it, S the sum of squares along it), and two
** lines crossing at angle theta move their meeting point by offset / sin(theta). */
double bsfit__corner_meet_variance(const side *a, const side *b, const double *x, double sigma) {
  double v = 0, sn2, dot = 0;
  const side *sd[2];
  int i, d;
  sd[0] = a;
  sd[1] = b;
  for (i = 0; i < 2; i++) {
    double along = 0, S = sd[i]->outer_n * sd[i]->outer_spread;
    for (d = 0; d < 3; d++) along += (x[d] - sd[i]->outer_centre[d]) * sd[i]->outer_dir[d];
    v += sigma * sigma * (1.0 / sd[i]->outer_n + (S > 0 ? along * along / S : 1e300));
  }
  for (d = 0; d < 3; d++) dot += a->outer_dir[d] * b->outer_dir[d];
  sn2 = fmax(1.0 - dot * dot, 1e-4);
  return v / sn2;
}

/* Distance from x to the two polygon edges at sample k (Q_{k-1} Q_k, Q_k Q_{k+1}), less
** what an edge across a corner turning by `turn` cuts off it: up to half the edge
** times tan(turn / 2), when the corner lies midway between the two samples. */
double bsfit__corner_edge_distance(const contour *c, size_t k, const double *x, double turn) {
  double best = INFINITY, cut = 0.5 * fmin(tan(0.5 * fmin(turn, 3.0)), 6.0);
  int dir, d;
  for (dir = -1; dir <= 1; dir += 2) {
    const double *a, *b;
    double ab2 = 0, t = 0, e2 = 0;
    if (!c->closed && ((dir < 0 && k == 0) || (dir > 0 && k + 1 >= c->m))) continue;
    a = point(c, dir < 0 ? (k + c->m - 1) % c->m : k);
    b = point(c, dir < 0 ? k : k + 1);
    for (d = 0; d < c->dim; d++) {
      ab2 += (b[d] - a[d]) * (b[d] - a[d]);
      t += (x[d] - a[d]) * (b[d] - a[d]);
    }
    t = ab2 > 0 ? fmin(1.0, fmax(0.0, t / ab2)) : 0.0;
    for (d = 0; d < c->dim; d++) {
      double e = a[d] + t * (b[d] - a[d]) - x[d];
      e2 += e * e;
    }
    best = fmin(best, fmax(0.0, sqrt(e2) - cut * sqrt(ab2)));
  }
  return best;
}

/* Signed turn of the polygon at sample i (radians): positive when it turns the way
** `axis` points (2D: axis[2] > 0 is counter-clockwise; 3D: the binormal of the corner),
** and its standard error for noise sigma. 0 at the ends of open data. */
static double signed_turn(const contour *c, size_t i, const double *axis, double sigma,
                          double *se) {
  const double *a, *b, *q;
  double u[3] = {0, 0, 0}, v[3] = {0, 0, 0}, cr[3], lu = 0, lv = 0, dot = 0, s, nc;
  int d;
  *se = 0;
  if (!c->closed && (i == 0 || i + 1 >= c->m)) return 0.0;
  a = point(c, (i + c->m - 1) % c->m);
  b = point(c, i);
  q = point(c, i + 1);
  for (d = 0; d < c->dim; d++) {
    u[d] = b[d] - a[d];
    v[d] = q[d] - b[d];
    lu += u[d] * u[d];
    lv += v[d] * v[d];
    dot += u[d] * v[d];
  }
  if (!(lu > 0 && lv > 0)) return 0.0;
  cr[0] = u[1] * v[2] - u[2] * v[1];
  cr[1] = u[2] * v[0] - u[0] * v[2];
  cr[2] = u[0] * v[1] - u[1] * v[0];
  nc = sqrt(cr[0] * cr[0] + cr[1] * cr[1] + cr[2] * cr[2]);
  s = cr[0] * axis[0] + cr[1] * axis[1] + cr[2] * axis[2];
  lu = sqrt(lu);
  lv = sqrt(lv);
  /* the turn moves with each of the three points across its edges */
  *se = sigma *
        sqrt(1.0 / (lu * lu) + (1.0 / lu + 1.0 / lv) * (1.0 / lu + 1.0 / lv) + 1.0 / (lv * lv));
  return (s < 0 ? -1.0 : 1.0) * atan2(nc, dot);
}

/* Is the turn at k concentrated, as a corner's is, on k and one neighbour (a corner
** between two samples splits its turn between them)? A smooth bend, however tight,
** also turns at the samples next to those, by more than the noise allows. Returns 0
** when the two samples beyond on each side turn the same way by more than three
** standard errors plus a fifth of the corner's turn (curved sides). */
int bsfit__corner_turn_concentrated(const contour *c, double position, const side *left,
                                    const side *right, double sigma) {
  double axis[3], tk, tp, tn, se, sek, sum = 0, var = 0, core;
  size_t lo, hi, i, k = (size_t)floor(position + 0.5) % c->m; /* the sample nearest the corner */
  long off;
  axis[0] = left->dir[1] * right->dir[2] - left->dir[2] * right->dir[1];
  axis[1] = left->dir[2] * right->dir[0] - left->dir[0] * right->dir[2];
  axis[2] = left->dir[0] * right->dir[1] - left->dir[1] * right->dir[0];
  if (c->dim == 2) axis[0] = axis[1] = 0, axis[2] = axis[2] < 0 ? -1.0 : 1.0;
  if (c->m < 9 || (!c->closed && (k < 4 || k + 4 >= c->m))) return 1;
  tk = signed_turn(c, k, axis, sigma, &sek);
  tp = signed_turn(c, (k + c->m - 1) % c->m, axis, sigma, &se);
  tn = signed_turn(c, (k + 1) % c->m, axis, sigma, &se);
  /* the corner's samples: k and the neighbour that turns more */
  if (tp > tn) lo = (k + c->m - 1) % c->m, hi = k;
  else lo = k, hi = (k + 1) % c->m;
  core = tk + fmax(tp, tn);
  for (off = 1; off <= 2; off++) {
    size_t before = (size_t)(((long)lo - off) % (long)c->m + (long)c->m) % c->m;
    size_t after = (hi + (size_t)off) % c->m;
    for (i = 0; i < 2; i++) {
      double t = signed_turn(c, i == 0 ? before : after, axis, sigma, &se);
      sum += t;
      var += se * se;
    }
  }
  /* turns of samples closer than the noise are noise, far from normal: no evidence */
  if (var > 4.0 * 0.25 || sek > 0.5) return 1;
  return sum <= 3.0 * sqrt(var) + 0.2 * core;
}

/* Cholesky solve of the n x n SPD system A x = b (n <= 5) in place; 0 if singular */
int bsfit__corner_solve_spd(int n, double A[BSFIT__SMALL][BSFIT__SMALL], double *b) {
  if (!bsfit__small_cholesky(n, A)) return 0;
  bsfit__small_chol_solve(n, (const double(*)[BSFIT__SMALL])A, b);
  return 1;
}
