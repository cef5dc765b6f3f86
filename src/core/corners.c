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
  double spread;  /* variance of the points along the line */
  double extent;  /* distance from the corner point to the far end */
  size_t count;
  size_t k;       /* the corner sample the side belongs to */
  int forward;    /* the side follows k (1) or precedes it (0) */
  double outer_dir[3], outer_centre[3]; /* line of the outer half (from scale/2 on) */
  double outer_n, outer_spread;         /* its number of points and spread */
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
  sd->spread = lam;
  for (d = 0; d < 3; d++) sd->centre[d] += c->origin[d];
}

static size_t at(const contour *c, size_t k, long off) {
  long m = (long)c->m;
  return (size_t)((((long)k + off) % m + m) % m);
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
static double turn_at_scale(const contour *c, size_t k, double scale, side *left, side *right,
                            size_t *from, size_t *to) {
  double cosang = 0;
  int d;
  if (!collect_side(c, k, 0, scale, left, from) || !collect_side(c, k, 1, scale, right, to))
    return -1.0;
  for (d = 0; d < 3; d++) cosang += left->dir[d] * right->dir[d];
  return acos(fmax(-1.0, fmin(1.0, cosang)));
}

/* intersection (2D) or midpoint of closest approach (3D) of the lines through ac
** along ad and through bc along bd; 0 when they are (nearly) parallel */
static int meet_lines(const double *ac, const double *ad, const double *bc, const double *bd,
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
static int meet(const side *a, const side *b, int dim, double *x) {
  return meet_lines(a->outer_centre, a->outer_dir, b->outer_centre, b->outer_dir, dim, x);
}

/* Variance, per coordinate direction across each line, of where the outer side lines
** meet: each line's offset at x has variance sigma^2 (1/n + d^2 / S) (d the distance
** of x from the line's centroid along it, S the sum of squares along it), and two
** lines crossing at angle theta move their meeting point by offset / sin(theta). */
static double meet_variance(const side *a, const side *b, const double *x, double sigma) {
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
static double edge_distance(const contour *c, size_t k, const double *x, double turn) {
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
  *se = sigma * sqrt(1.0 / (lu * lu) + (1.0 / lu + 1.0 / lv) * (1.0 / lu + 1.0 / lv) + 1.0 / (lv * lv));
  return (s < 0 ? -1.0 : 1.0) * atan2(nc, dot);
}

/* Is the turn at k concentrated, as a corner's is, on k and one neighbour (a corner
** between two samples splits its turn between them)? A smooth bend, however tight,
** also turns at the samples next to those, by more than the noise allows. Returns 0
** when the two samples beyond on each side turn the same way by more than three
** standard errors plus a fifth of the corner's turn (curved sides). */
static int turn_concentrated(const contour *c, double position, const side *left,
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
static int solve_spd(int n, double A[BSFIT__SMALL][BSFIT__SMALL], double *b) {
  if (!bsfit__small_cholesky(n, A)) return 0;
  bsfit__small_chol_solve(n, (const double(*)[BSFIT__SMALL])A, b);
  return 1;
}

/* {======================================================================
** Curved sides: a parabola across each side's line (in the line's frame), so that
** where two curved sides meet is not where their secants do (a half disc's corner
** would move out along its diameter), and so that a side's curvature can be allowed
** for when its line is extrapolated.
** ======================================================================= */

typedef struct parabola {
  double origin[3], axis[3], normal[2][3]; /* the side's frame */
  int nn;                                  /* normal directions: dim - 1 */
  double len;                              /* coordinate along the axis is s = a / len */
  double coef[2][3];                       /* b_j(s) = c0 + c1 s + c2 s^2 */
  double rms;                              /* RMS residual across the side */
  double rss_cubic;                        /* residual sum of squares of a cubic instead */
} parabola;

/* Cholesky of a 3x3 SPD matrix in place (lower); 0 if not numerically SPD */
static int cholesky3(double A[3][3]) {
  int i, j, k;
  double tr = A[0][0] + A[1][1] + A[2][2];
  for (j = 0; j < 3; j++) {
    double dd = A[j][j];
    for (k = 0; k < j; k++) dd -= A[j][k] * A[j][k];
    if (!(dd > 1e-12 * tr)) return 0;
    A[j][j] = sqrt(dd);
    for (i = j + 1; i < 3; i++) {
      double s = A[i][j];
      for (k = 0; k < j; k++) s -= A[i][k] * A[j][k];
      A[i][j] = s / A[j][j];
    }
  }
  return 1;
}

static void chol_solve3(double L[3][3], double *b) {
  int i, k;
  for (i = 0; i < 3; i++) {
    for (k = 0; k < i; k++) b[i] -= L[i][k] * b[k];
    b[i] /= L[i][i];
  }
  for (i = 2; i >= 0; i--) {
    for (k = i + 1; k < 3; k++) b[i] -= L[k][i] * b[k];
    b[i] /= L[i][i];
  }
}

/* Fits the parabola of side sd (its count points, k excluded); 0 when it cannot. */
static int fit_parabola(const contour *c, const side *sd, parabola *pb) {
  double A[3][3] = {{0}}, rhs[2][3] = {{0}}, sbb[2] = {0, 0}, A4[5][5] = {{0}}, rhs4[2][5] = {{0}};
  size_t i, j = sd->k;
  int d, p, q, e;
  if (sd->count < 4 || !(sd->extent > 0)) return 0;
  memset(pb, 0, sizeof *pb);
  memcpy(pb->origin, sd->centre, sizeof pb->origin);
  memcpy(pb->axis, sd->dir, sizeof pb->axis);
  pb->len = sd->extent;
  pb->nn = c->dim - 1;
  if (c->dim == 2) {
    pb->normal[0][0] = -sd->dir[1];
    pb->normal[0][1] = sd->dir[0];
  } else { /* n1 = axis x (the coordinate axis least along it), n2 = axis x n1 */
    double ex[3] = {0, 0, 0}, *u = pb->axis, *n1 = pb->normal[0], *n2 = pb->normal[1], nrm;
    int low = 0;
    for (d = 1; d < 3; d++)
      if (fabs(u[d]) < fabs(u[low])) low = d;
    ex[low] = 1.0;
    n1[0] = u[1] * ex[2] - u[2] * ex[1];
    n1[1] = u[2] * ex[0] - u[0] * ex[2];
    n1[2] = u[0] * ex[1] - u[1] * ex[0];
    nrm = sqrt(n1[0] * n1[0] + n1[1] * n1[1] + n1[2] * n1[2]);
    for (d = 0; d < 3; d++) n1[d] /= nrm;
    n2[0] = u[1] * n1[2] - u[2] * n1[1];
    n2[1] = u[2] * n1[0] - u[0] * n1[2];
    n2[2] = u[0] * n1[1] - u[1] * n1[0];
  }
  for (i = 0; i < sd->count; i++) {
    const double *P;
    double a = 0, x[4];
    j = step(c, j, sd->forward);
    P = point(c, j);
    for (d = 0; d < c->dim; d++) a += (P[d] - pb->origin[d]) * pb->axis[d];
    x[0] = 1.0;
    x[1] = a / pb->len;
    x[2] = x[1] * x[1];
    for (p = 0; p < 3; p++)
      for (q = 0; q <= p; q++) A[p][q] += x[p] * x[q];
    x[3] = x[2] * x[1];
    for (p = 0; p < 4; p++)
      for (q = 0; q < 4; q++) A4[p][q] += x[p] * x[q];
    for (e = 0; e < pb->nn; e++) {
      double b = 0;
      for (d = 0; d < c->dim; d++) b += (P[d] - pb->origin[d]) * pb->normal[e][d];
      for (p = 0; p < 3; p++) rhs[e][p] += x[p] * b;
      for (p = 0; p < 4; p++) rhs4[e][p] += x[p] * b;
      sbb[e] += b * b;
    }
  }
  for (p = 0; p < 3; p++)
    for (q = p + 1; q < 3; q++) A[p][q] = A[q][p];
  if (!cholesky3(A)) return 0;
  {
    double rss = 0;
    for (e = 0; e < pb->nn; e++) {
      double sol[3];
      memcpy(sol, rhs[e], sizeof sol);
      chol_solve3(A, sol);
      memcpy(pb->coef[e], sol, sizeof sol);
      rss += sbb[e] - (sol[0] * rhs[e][0] + sol[1] * rhs[e][1] + sol[2] * rhs[e][2]);
    }
    pb->rms = sqrt(fmax(rss, 0.0) / (double)sd->count);
    pb->rss_cubic = rss;
    if (sd->count >= 5) {
      double r3 = 0;
      for (e = 0; e < pb->nn; e++) {
        double M[5][5], sol[5];
        memcpy(M, A4, sizeof M);
        memcpy(sol, rhs4[e], sizeof sol);
        if (!solve_spd(4, M, sol)) { r3 = rss; break; }
        r3 += sbb[e] - (sol[0] * rhs4[e][0] + sol[1] * rhs4[e][1] + sol[2] * rhs4[e][2] + sol[3] * rhs4[e][3]);
      }
      pb->rss_cubic = fmax(fmin(r3, rss), 0.0);
    }
  }
  return 1;
}

/* The point and unit tangent of the parabola at the foot of x on its axis. */
static void parabola_at(const parabola *pb, const double *x, double *pt, double *tan) {
  double a = 0, s, nrm = 0;
  int d, e;
  for (d = 0; d < 3; d++) a += (x[d] - pb->origin[d]) * pb->axis[d];
  s = a / pb->len;
  for (d = 0; d < 3; d++) {
    pt[d] = pb->origin[d] + a * pb->axis[d];
    tan[d] = pb->axis[d];
  }
  for (e = 0; e < pb->nn; e++) {
    const double *cf = pb->coef[e];
    double b = cf[0] + cf[1] * s + cf[2] * s * s, db = (cf[1] + 2.0 * cf[2] * s) / pb->len;
    for (d = 0; d < 3; d++) {
      pt[d] += b * pb->normal[e][d];
      tan[d] += db * pb->normal[e][d];
    }
  }
  for (d = 0; d < 3; d++) nrm += tan[d] * tan[d];
  nrm = sqrt(nrm);
  for (d = 0; d < 3; d++) tan[d] /= nrm;
}

/* Where two curved sides meet: starting from x (the side lines' meeting point), each
** side's parabola is replaced by its tangent line at the foot of x, and x by where
** those lines meet, until it settles; a curved side's line would put the corner off
** the curve (a half disc's corner moves out along its diameter). x is left alone when
** a side cannot hold a parabola or the step runs away (further than a side). */
static void refine_meet(const contour *c, const side *left, const side *right, double *x) {
  parabola pl, pr;
  double y[3] = {0, 0, 0}, pt_l[3], pt_r[3], t_l[3], t_r[3], reach = fmax(left->extent, right->extent);
  int it, d;
  if (!fit_parabola(c, left, &pl) || !fit_parabola(c, right, &pr)) return;
  for (it = 0; it < 4; it++) {
    double step2 = 0;
    parabola_at(&pl, x, pt_l, t_l);
    parabola_at(&pr, x, pt_r, t_r);
    if (!meet_lines(pt_l, t_l, pt_r, t_r, c->dim, y)) return;
    for (d = 0; d < c->dim; d++) step2 += (y[d] - x[d]) * (y[d] - x[d]);
    if (!(step2 <= reach * reach)) return;
    memcpy(x, y, sizeof y);
    if (step2 < 1e-24 * reach * reach) break;
  }
}

/* How far curved sides move the meeting point of their outer lines: each outer line
** is a chord of its side, whose curvature (from the side's parabola) bends the side
** away from the line by kappa d^2 / 2 over the distance d from the line's centroid
** to the meeting point; the lines meeting at `turn` move it by that over sin(turn). */
static double bend_allowance(const contour *c, const side *L, const side *R, const double *x,
                             double turn) {
  const side *sd[2];
  double off = 0;
  int i, d, e;
  sd[0] = L;
  sd[1] = R;
  for (i = 0; i < 2; i++) {
    parabola pb;
    double kappa = 0, along = 0;
    if (!fit_parabola(c, sd[i], &pb)) continue;
    for (e = 0; e < pb.nn; e++) kappa += pb.coef[e][2] * pb.coef[e][2];
    kappa = 2.0 * sqrt(kappa) / (pb.len * pb.len);
    for (d = 0; d < 3; d++) along += (x[d] - sd[i]->outer_centre[d]) * sd[i]->outer_dir[d];
    off += 0.5 * kappa * along * along;
  }
  return off / fmax(sin(turn), 0.3);
}

/* }====================================================================== */

/* {======================================================================
** Is the turn a slope jump? The corner model (C0) lets each side follow its own
** parabola and meet the other anywhere. The smooth model (C2) is what a cubic spline
** does across the join: one cubic y(X) in the frame of the two side directions (X
** along their sum, Y across) whose third derivative may jump at the join, so its
** curvature can peak there and fall off along both sides, as a tight smooth bend's
** does, but its slope cannot jump. A corner is a join that the smooth model cannot
** follow: its residual sum of squares is much larger. Its residuals across each side
** are scaled by 1/sqrt(1 + slope^2), so steep sides count by distance, not by Y.
** ======================================================================= */

/* RSS of the corner model (rss0) and of the smooth model (rss1) over the points of
** both sides, joined at x; returns their number of points, 0 when a model cannot be
** fitted or the frame is undefined (sides within ~3 degrees of a full reversal). */
static size_t join_models(const contour *c, const side *L, const side *R, const double *x,
                          double *rss0, double *rss1) {
  double X[3], Y[3], Z[3] = {0, 0, 0}, nx = 0, ny = 0, len = fmax(L->extent, R->extent);
  double wl, wr;
  int d, p, q, e, ncomp = c->dim == 3 ? 2 : 1;
  const side *sd[2];
  parabola pl, pr;
  if (!fit_parabola(c, L, &pl) || !fit_parabola(c, R, &pr)) return 0;
  *rss0 = (double)L->count * pl.rms * pl.rms + (double)R->count * pr.rms * pr.rms;
  for (d = 0; d < 3; d++) {
    X[d] = L->dir[d] + R->dir[d];
    nx += X[d] * X[d];
  }
  nx = sqrt(nx);
  if (!(nx > 0.05) || !(len > 0)) return 0;
  for (d = 0; d < 3; d++) X[d] /= nx;
  {
    double dl = 0;
    for (d = 0; d < 3; d++) dl += (R->dir[d] - L->dir[d]) * X[d];
    for (d = 0; d < 3; d++) {
      Y[d] = R->dir[d] - L->dir[d] - dl * X[d];
      ny += Y[d] * Y[d];
    }
  }
  ny = sqrt(ny);
  if (!(ny > 1e-9)) { /* straight on: any perpendicular */
    Y[0] = -X[1], Y[1] = X[0], Y[2] = 0, ny = sqrt(Y[0] * Y[0] + Y[1] * Y[1]);
    if (!(ny > 0)) Y[0] = 0, Y[1] = -X[2], Y[2] = X[1], ny = sqrt(Y[1] * Y[1] + Y[2] * Y[2]);
  }
  for (d = 0; d < 3; d++) Y[d] /= ny;
  if (ncomp == 2) {
    Z[0] = X[1] * Y[2] - X[2] * Y[1];
    Z[1] = X[2] * Y[0] - X[0] * Y[2];
    Z[2] = X[0] * Y[1] - X[1] * Y[0];
  }
  {
    double lx = 0, ly = 0, rx = 0, ry = 0;
    for (d = 0; d < 3; d++) {
      lx += L->dir[d] * X[d], ly += L->dir[d] * Y[d];
      rx += R->dir[d] * X[d], ry += R->dir[d] * Y[d];
    }
    wl = lx * lx / (lx * lx + ly * ly);
    wr = rx * rx / (rx * rx + ry * ry);
  }
  sd[0] = L;
  sd[1] = R;
  /* iteratively reweighted: each residual across Y is scaled by the model's own slope
  ** at the point (starting from the side lines' slopes), so it measures distance */
  {
    double coef[2][5] = {{0}};
    int it;
    for (it = 0; it < 3; it++) {
      double A[5][5] = {{0}}, b[2][5] = {{0}}, svv = 0;
      for (e = 0; e < 2; e++) {
        size_t i, j = sd[e]->k;
        for (i = 0; i < sd[e]->count; i++) {
          const double *P;
          double u = 0, v[2] = {0, 0}, r[5], w;
          j = step(c, j, sd[e]->forward);
          P = point(c, j);
          for (d = 0; d < c->dim; d++) {
            u += (P[d] - x[d]) * X[d];
            v[0] += (P[d] - x[d]) * Y[d];
            v[1] += (P[d] - x[d]) * Z[d];
          }
          u /= len;
          r[0] = 1.0;
          r[1] = u;
          r[2] = u * u;
          r[3] = u * u * u;
          r[4] = u > 0 ? r[3] : 0.0;
          if (it == 0) {
            w = e == 0 ? wl : wr;
          } else {
            double g = 0;
            for (q = 0; q < ncomp; q++) {
              double sl = (coef[q][1] + 2.0 * coef[q][2] * u + 3.0 * (coef[q][3] + (u > 0 ? coef[q][4] : 0.0)) * u * u) / len;
              g += sl * sl;
            }
            w = fmax(1.0 / (1.0 + g), 0.5 * fmin(wl, wr));
          }
          for (p = 0; p < 5; p++)
            for (q = 0; q < 5; q++) A[p][q] += w * r[p] * r[q];
          for (q = 0; q < ncomp; q++) {
            for (p = 0; p < 5; p++) b[q][p] += w * r[p] * v[q];
            svv += w * v[q] * v[q];
          }
        }
      }
      *rss1 = svv;
      for (q = 0; q < ncomp; q++) {
        double M[5][5];
        memcpy(M, A, sizeof M);
        memcpy(coef[q], b[q], sizeof coef[q]);
        if (!solve_spd(5, M, coef[q])) return 0;
        for (p = 0; p < 5; p++) *rss1 -= coef[q][p] * b[q][p];
      }
    }
  }
  *rss1 = fmax(*rss1, 0.0);
  return L->count + R->count;
}

/* The side of k grown beyond `scale` (by steps of 25%, up to 4x and `cap`) while it
** stays straight to the noise level: the long straight sides of polygons give the
** slope-jump test its power on noisy data. */
static void grow_side(const contour *c, size_t k, int forward, double scale, double sigma,
                      double cap, side *sd) {
  double f;
  for (f = 1.25; f <= 4.0 && f * scale <= cap; f *= 1.25) {
    side big;
    size_t far;
    if (!collect_side(c, k, forward, f * scale, &big, &far)) return;
    if (big.count <= sd->count) continue;
    /* sparse sides grow to 5 points whatever their shape: the models need them */
    if (sd->count >= 5) {
      parabola pb;
      double rss_line = (double)big.count * big.rms * big.rms, slack = 1e-6 * big.extent * big.extent;
      if (big.rms > 1.3 * sigma + 0.001 * big.extent) return;
      /* straight: a cubic must not follow it much better than the line (an S bend can
      ** stay within the noise of a line on noisy data) */
      if (fit_parabola(c, &big, &pb) && rss_line - pb.rss_cubic > 9.0 * sigma * sigma + (double)big.count * slack) return;
    }
    *sd = big;
  }
}

/* }====================================================================== */

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

/* A spike's side lines cross at a shallow angle, so where they meet is poorly known
** along its axis (and curved sides push it outwards): the corner point is kept no
** further out along the axis than the furthest sample of the window. */
static void clamp_to_tip(const contour *c, size_t k, const side *left, const side *right,
                         double *x) {
  double axis[3], na = 0, top = -INFINITY;
  long off;
  int d;
  for (d = 0; d < 3; d++) {
    axis[d] = left->dir[d] - right->dir[d];
    na += axis[d] * axis[d];
  }
  na = sqrt(na);
  if (!(na > 0)) return;
  for (d = 0; d < 3; d++) axis[d] /= na;
  for (off = -(long)left->count; off <= (long)right->count; off++) {
    const double *P;
    double pr = 0;
    if (!c->closed && ((long)k + off < 0 || (long)k + off >= (long)c->m)) continue;
    P = point(c, at(c, k, off));
    for (d = 0; d < c->dim; d++) pr += (P[d] - x[d]) * axis[d];
    if (pr > top) top = pr;
  }
  if (top < 0) /* x lies beyond every sample: back along the axis to the furthest */
    for (d = 0; d < c->dim; d++) x[d] += top * axis[d];
}

/* Where along the samples the corner lies: the split of the samples around k (half of
** each side) between the two side lines that leaves the least squared distance to
** them (samples up to the split on the left line, the others on the right one), then
** the fraction of the path across the split edge before the corner point x. Robust
** where samples are closer than the noise (a thin trailing edge): the corner is not
** simply the sample nearest to x. */
static double split_position(const contour *c, size_t k, const side *left, const side *right,
                             const double *x, double sigma, double turn) {
  long lo = -(long)(left->count / 2), hi = (long)(right->count / 2), off, best_off = -1, n, first = 0, last = 0;
  double acc = 0, best = INFINITY, cost[256];
  size_t j;
  const double *a, *b;
  double da = 0, db = 0, f, pos;
  int d, s;
  if (!c->closed) {
    if ((long)k + lo < 0) lo = -(long)k;
    if ((long)k + hi + 1 >= (long)c->m) hi = (long)c->m - 2 - (long)k;
  }
  if (hi <= lo) return (double)k;
  if (-lo > 127) lo = -127;
  if (hi > 127) hi = 127;
  if (turn > 2.0 * PI / 3.0) {
    /* A spike: its tip is the sample furthest along the spike's axis. Where the samples
    ** there are closer than the noise, all those within 2 sigma of the furthest are
    ** the tip, and the corner is their mean position (the tip of a thin trailing edge
    ** cut at random would make the curve cross over). */
    double axis[3], na = 0, top = -INFINITY, sum = 0, cnt = 0, proj[256];
    for (d = 0; d < 3; d++) {
      axis[d] = left->dir[d] - right->dir[d];
      na += axis[d] * axis[d];
    }
    na = sqrt(na);
    for (off = lo; off <= hi; off++) {
      const double *P = point(c, at(c, k, off));
      double pr = 0;
      for (d = 0; d < c->dim; d++) pr += (P[d] - x[d]) * axis[d] / na;
      proj[off - lo] = pr;
      if (pr > top) top = pr;
    }
    for (off = lo; off <= hi; off++)
      if (proj[off - lo] >= top - 2.0 * sigma - 1e-12 * fabs(top)) sum += (double)off, cnt += 1.0;
    pos = (double)k + sum / cnt;
    if (pos < 0) pos += (double)c->m;
    if (pos >= (double)c->m) pos -= (double)c->m;
    if (!c->closed) pos = fmin(fmax(pos, 0.0), (double)(c->m - 1));
    return pos;
  }
  /* cost(split after sample k + off) = sum over samples up to it of dL^2 - dR^2 + const */
  for (off = lo; off <= hi; off++) {
    const double *P = point(c, at(c, k, off));
    double e2[2] = {0, 0};
    for (s = 0; s < 2; s++) {
      const side *sd = s == 0 ? left : right;
      double along = 0, n2 = 0;
      for (d = 0; d < c->dim; d++) along += (P[d] - sd->centre[d]) * sd->dir[d];
      for (d = 0; d < c->dim; d++) {
        double r = P[d] - sd->centre[d] - along * sd->dir[d];
        n2 += r * r;
      }
      e2[s] = n2;
    }
    acc += e2[0] - e2[1];
    cost[off - lo] = acc;
    if (acc < best) best = acc, best_off = off;
  }
  /* Samples nearer to the corner than the noise resolves fit either line: of the
  ** splits within 4 sigma^2 of the best, the middle one (a thin spike's samples near
  ** its tip would otherwise be cut at random, and the curve made to cross over). */
  for (n = 0, off = lo; off <= hi; off++)
    if (cost[off - lo] <= best + 4.0 * sigma * sigma) {
      if (n++ == 0) first = off;
      last = off;
    }
  if (n > 0) best_off = first + (last - first) / 2;
  j = at(c, k, best_off);
  a = point(c, j);
  b = point(c, j + 1);
  for (d = 0; d < c->dim; d++) {
    da += (x[d] - a[d]) * (x[d] - a[d]);
    db += (x[d] - b[d]) * (x[d] - b[d]);
  }
  da = sqrt(da);
  db = sqrt(db);
  f = da + db > 0 ? da / (da + db) : 0.0;
  /* a corner at (or within rounding of) a sample is that sample */
  pos = f > 1.0 - 1e-9 ? (double)j + 1.0 : (double)j + (f < 1e-9 ? 0.0 : f);
  if (pos >= (double)c->m) pos -= (double)c->m;
  return pos;
}

/* The turn at k if it is a corner, else a negative value; its window (from, to), the
** distance from Q_k to the corner (for thinning), where the corner lies along the
** samples and the corner point. The tests, cheapest first:
**   - the sides turn: by min_angle at least and by six standard errors;
**   - both sides are straight to the noise (plus 2% of the scale for clean data);
**   - the outer halves' lines meet near the data: a rounded fillet's tangents do not
**     (the allowance: three standard errors of where they meet, as the lines are known
**     from noisy samples, and how far curved sides bend away from their lines);
**   - the polygon turns at the corner's samples, not beyond them;
**   - the turn is a slope jump: with the sides grown as long as they stay straight, a
**     smooth join (join_models) explains them worse by 25 sigma^2 at least;
**   - a corner turns as much at half the scale; a bend turns less, in proportion. */
static double corner_turn(const contour *c, size_t k, double scale, double sigma,
                          double min_angle, double cap, size_t *from, size_t *to,
                          double *gap_out, double *position, double *meet_point) {
  side left, right, half_left, half_right, gl, gr;
  double angle, half, se, x[3] = {0, 0, 0}, gap = 0, lim, r0, r1;
  size_t half_from, half_to, n;
  int d;
  *position = (double)k;
  angle = turn_at_scale(c, k, scale, &left, &right, from, to);
  if (angle < 0) return -1.0;
  /* standard error of a line direction fitted to n points spread over `extent` */
  se = sigma * sqrt(12.0 / (double)left.count) / left.extent +
       sigma * sqrt(12.0 / (double)right.count) / right.extent;
  if (angle < min_angle || angle < 6.0 * se) return -1.0;
  if (left.rms > 2.5 * sigma + 0.02 * scale || right.rms > 2.5 * sigma + 0.02 * scale) return -1.0;
  if (!meet(&left, &right, c->dim, x)) return -1.0;
  /* the corner itself: where the curved sides meet (x stays where the outer lines
  ** meet, for the fillet test) */
  memcpy(meet_point, x, sizeof x);
  refine_meet(c, &left, &right, meet_point);
  if (angle > 2.0 * PI / 3.0) clamp_to_tip(c, k, &left, &right, meet_point);
  for (d = 0; d < c->dim; d++) gap += (meet_point[d] - point(c, k)[d]) * (meet_point[d] - point(c, k)[d]);
  *gap_out = sqrt(gap);
  *position = split_position(c, k, &left, &right, meet_point, sigma, angle);
  lim = 3.0 * sqrt(2.0 * sigma * sigma + meet_variance(&left, &right, x, sigma)) +
        bend_allowance(c, &left, &right, x, angle) + 0.005 * scale;
  if (edge_distance(c, k, x, angle) > lim) return -1.0;
  if (!turn_concentrated(c, *position, &left, &right, sigma)) return -1.0;
  gl = left;
  gr = right;
  grow_side(c, k, 0, scale, sigma, cap, &gl);
  grow_side(c, k, 1, scale, sigma, cap, &gr);
  n = join_models(c, &gl, &gr, meet_point, &r0, &r1);
  if (n == 0 && gl.count >= 4 && gr.count >= 4) return -1.0; /* no smooth model fits: no evidence */
  if (n > 0) {
    /* the noise, or the corner model's own misfit when larger (clean data) */
    double s2 = fmax(fmax(sigma * sigma, r0 / (double)(n > 8 ? n - 6 : 2)), 1e-6 * scale * scale);
    /* 25 sigma^2, and more over many points: the smooth model's own shortfall on a
    ** smooth bend adds up point by point (a 5-lobed star's valley of radius 12 sigma,
    ** seen through 400 points, falls short by 30 sigma^2) */
    if (r1 - r0 < (25.0 + 0.03 * (double)n) * s2) return -1.0;
  }
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
static double quick_candidate(const contour *c, size_t k, double scale, double sigma,
                              double min_angle, window *w) {
  moments ml, mr;
  side left, right;
  double hint_l[3] = {0, 0, 0}, hint_r[3] = {0, 0, 0}, cosang = 0, angle;
  size_t first_l, first_r;
  int d;
  if (!move_window(c, k, scale, w) || w->back < 3 || w->fwd < 3) return -1.0;
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
  if (angle < 0.8 * min_angle) return -1.0;
  if (left.rms > 4.0 * sigma + 0.04 * scale || right.rms > 4.0 * sigma + 0.04 * scale) return -1.0;
  return angle;
}

/* Is the quick turn at k the largest within r samples either way (ties to the first)?
** A corner's neighbours see the same corner off-centre, with a smaller turn: only the
** peak and the samples next to it are worth the exact test. */
static int turn_peak(const contour *c, const double *turn, size_t k, size_t r) {
  long off;
  for (off = -(long)r; off <= (long)r; off++) {
    size_t j;
    if (off == 0) continue;
    if (!c->closed && ((long)k + off < 0 || (long)k + off >= (long)c->m)) continue;
    j = at(c, k, off);
    if (turn[j] > turn[k] || (turn[j] == turn[k] && off < 0)) return 0;
  }
  return 1;
}

bsfit_err bsfit_corners_detect(const double *pts, size_t m, int dim,
                               const bsfit_corner_opts *opts, bsfit_corner *corners,
                               size_t cap, size_t *count, const bsfit_allocator *al,
                               bsfit_status *st) {
  contour c;
  candidate *cand;
  double sigma, scale, spacing, min_angle, reach_cap, *scratch;
  size_t k, nc = 0, nq = 0, kept, bytes_prefix, bytes_cand, *span = NULL, *queue = NULL;
  unsigned char *state = NULL;
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
    e = bsfit_noise_sigma(pts, m, dim, o.closed, &sigma, NULL, st);
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
  c.prefix = bsfit__alloc(al, bytes_prefix);
  cand = bsfit__alloc(al, bytes_cand);
  scratch = bsfit__alloc(al, m * sizeof(double));
  span = bsfit__alloc(al, m * sizeof(size_t));
  queue = bsfit__alloc(al, m * sizeof(size_t));
  state = bsfit__alloc(al, m);
  if (c.prefix == NULL || cand == NULL || scratch == NULL || span == NULL || queue == NULL ||
      state == NULL) {
    e = bsfit__fail(st, BSFIT_ENOMEM, "out of memory for corner detection of %zu points", m);
    goto done;
  }
  memset(state, 0, m);
  build_prefix(&c);
  spacing = median_spacing(&c, scratch);
  reach_cap = 0.4 * bbox_diagonal(&c);
  scale = o.scale > 0 ? o.scale : fmin(fmax(40.0 * sigma, 4.0 * spacing), 0.25 * reach_cap);
  min_angle = (o.min_angle_deg > 0 ? o.min_angle_deg : 30.0) * PI / 180.0;
  /* the quick turn of every sample (scratch: -1 where it cannot be a corner), and how
  ** far a peak of it rules: a quarter of its shorter side */
  for (k = 0; k < m; k++) {
    if ((k & 4095) == 4095 && bsfit__interrupted(al)) {
      e = bsfit__fail(st, BSFIT_EINTR, "corner detection interrupted");
      goto done;
    }
    scratch[k] = quick_candidate(&c, k, scale, sigma, min_angle, &reach);
    span[k] = reach.back < reach.fwd ? reach.back : reach.fwd;
  }
  /* The peaks and their neighbours are examined; where one finds the corner elsewhere
  ** (a peak leans towards a curved side, whose turn adds to the corner's), the samples
  ** around that place are examined too. Each sample at most once: queue holds the
  ** samples to examine, state[k] is 1 once queued as a peak's, 2 as found by another
  ** (such a sample must then find the corner at itself). */
  for (k = 0; k < m; k++) {
    long off;
    if (scratch[k] < 0 || !turn_peak(&c, scratch, k, span[k] / 4 > 1 ? span[k] / 4 : 1)) continue;
    for (off = -1; off <= 1; off++) {
      size_t j;
      if (!c.closed && ((long)k + off < 0 || (long)k + off >= (long)m)) continue;
      j = at(&c, k, off);
      if (!state[j]) state[j] = 1, queue[nq++] = j;
    }
  }
  while (nq > 0) {
    size_t from, to, kk = queue[--nq];
    double gap = 0, pos = (double)kk, x[3] = {0, 0, 0}, a, moved;
    int second = state[kk] == 2; /* queued from another's finding: must find itself */
    if ((nq & 255) == 0 && bsfit__interrupted(al)) {
      e = bsfit__fail(st, BSFIT_EINTR, "corner detection interrupted");
      goto done;
    }
    a = corner_turn(&c, kk, scale, sigma, min_angle, reach_cap, &from, &to, &gap, &pos, x);
    moved = fabs(pos - (double)kk);
    if (c.closed) moved = fmin(moved, (double)m - moved);
    if (second && moved >= 1.5) a = -1.0;
    if (moved >= 1.5 && !second) {
      long off, near = (long)floor(pos + 0.5);
      for (off = -1; off <= 1; off++) {
        size_t j;
        if (!c.closed && (near + off < 0 || near + off >= (long)m)) continue;
        j = at(&c, (size_t)(near < 0 ? 0 : near) % m, off);
        if (!state[j]) state[j] = 2, queue[nq++] = j;
      }
    }
    if (a >= 0) {
      cand[nc].k = kk;
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
    /* the sample nearest to where the corner lies */
    size_t near = (size_t)floor(cand[k].position + 0.5);
    corners[k].index = near >= m ? near - m : near;
    corners[k].angle = cand[k].angle * 180.0 / PI;
    corners[k].position = cand[k].position;
    memcpy(corners[k].point, cand[k].point, sizeof cand[k].point);
  }
  *count = kept;
  e = bsfit__ok(st);
done:
  bsfit__free(al, c.prefix, bytes_prefix);
  bsfit__free(al, cand, bytes_cand);
  bsfit__free(al, scratch, m * sizeof(double));
  bsfit__free(al, span, m * sizeof(size_t));
  bsfit__free(al, queue, m * sizeof(size_t));
  bsfit__free(al, state, m);
  return e;
}
