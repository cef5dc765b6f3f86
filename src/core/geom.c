/*
** geom.c
** Geometry kernels on ordered point sequences for the fitting strategies
** (docs/method.md §7-10): circumradius per point and the paper's weights from it, interior
** angles, curvature inversions, turning and spacing weights, and the projection of
** a point onto a line used by the tangent correction. Every kernel is one O(m) pass
** over the points and allocates nothing.
*/
#include "internal.h"

#include <math.h>

#define RAD_TO_DEG (180.0 / 3.14159265358979323846)

/* {====================================================================
** Argument checks and small vector helpers
** ===================================================================== */

static bsfit_err check_dim(int dim, bsfit_status *st) {
  if (dim != 2 && dim != 3)
    return bsfit__fail(st, BSFIT_EDIM, "dim must be 2 or 3, got %d", dim);
  return BSFIT_OK;
}

/* The checks shared by every kernel on a sequence; `what` names the output. */
static bsfit_err check_seq(const double *pts, size_t m, int dim, const void *out,
                           const char *what, bsfit_status *st) {
  size_t i, n;
  bsfit_err e = check_dim(dim, st);
  if (e != BSFIT_OK) return e;
  if (m < 3) return bsfit__fail(st, BSFIT_ETOOFEW, "m = %zu points, at least 3 needed", m);
  if (pts == NULL) return bsfit__fail(st, BSFIT_EINVAL, "pts is NULL");
  if (out == NULL) return bsfit__fail(st, BSFIT_EINVAL, "%s is NULL", what);
  n = bsfit__mulsize(m, (size_t)dim);
  if (n == 0) return bsfit__fail(st, BSFIT_EINVAL, "m = %zu points overflow the size", m);
  i = bsfit__first_out_of_range(pts, n);
  if (i < n && !isfinite(pts[i]))
    return bsfit__fail(st, BSFIT_ENONFINITE, "point %zu has a non-finite coordinate",
                       i / (size_t)dim);
  if (i < n)
    return bsfit__fail(st, BSFIT_ERANGE, "point %zu has a coordinate %g beyond 1e100",
                       i / (size_t)dim, pts[i]);
  return BSFIT_OK;
}

/* The triple (a, b, c) as u = b - a, v = c - b, scaled by a power of two 2^-*ex (exact)
** that brings the largest difference near 1: every kernel here is a ratio or an angle,
** and unscaled, squares of differences below 1e-154 underflowed (a triangle of side
** 1e-170 had radius 0, weights 0/0) or above 1e154 overflowed. */
static void scaled_edges(const double *a, const double *b, const double *c, int dim, double u[3],
                         double v[3], int *ex) {
  double big = 0.0;
  int i;
  u[0] = u[1] = u[2] = v[0] = v[1] = v[2] = 0.0;
  for (i = 0; i < dim; i++) {
    u[i] = b[i] - a[i];
    v[i] = c[i] - b[i];
    big = fmax(big, fmax(fabs(u[i]), fabs(v[i])));
  }
  *ex = 0;
  if (big == 0.0) return;
  (void)frexp(big, ex);
  for (i = 0; i < dim; i++) {
    u[i] = ldexp(u[i], -*ex);
    v[i] = ldexp(v[i], -*ex);
  }
}

static const double *point_at(const double *pts, int dim, size_t k) {
  return pts + k * (size_t)dim;
}

static double dist2(const double *a, const double *b, int dim) {
  double s = 0.0;
  int i;
  for (i = 0; i < dim; i++) s += (b[i] - a[i]) * (b[i] - a[i]);
  return s;
}

/* x = u x v (2D: only x[2] is non-zero). With u = b - a and v = c - b its norm is twice
** the area of the triangle (a, b, c), and its direction is the turn direction at b,
** which is why the inflection count uses the same product. */
static void cross3(const double u[3], const double v[3], double x[3]) {
  x[0] = u[1] * v[2] - u[2] * v[1];
  x[1] = u[2] * v[0] - u[0] * v[2];
  x[2] = u[0] * v[1] - u[1] * v[0];
}

static double norm3(const double x[3]) { return sqrt(x[0] * x[0] + x[1] * x[1] + x[2] * x[2]); }

static double max3(double a, double b, double c) {
  double m = a > b ? a : b;
  return m > c ? m : c;
}

/* docs/method.md §7's collinearity test, given twice the area and the three squared sides.
** A zero longest side (three coincident points) gives 0 <= 0: collinear. */
static int is_collinear(double area2, double s0, double s1, double s2) {
  return area2 <= BSFIT_GEOM_COLLINEAR_EPS * max3(s0, s1, s2);
}

/* Index of the middle point of the triple whose value point k receives.
** Centred: k itself; the paper's (Q_k, Q_{k+1}, Q_{k+2}): k+1. Open data clamp the
** triple inside 0..m-1, which gives the ends their nearest full triple. */
static size_t triple_middle(size_t k, size_t m, int closed, int centered) {
  if (closed) return centered ? k : (k + 1) % m;
  if (!centered) k = (k + 1 < m - 2) ? k + 1 : m - 2;
  if (k < 1) return 1;
  return k > m - 2 ? m - 2 : k;
}

/* The neighbours of middle point b (cyclic; b is 1..m-2 for open data). */
static void neighbours(size_t b, size_t m, size_t *a, size_t *c) {
  *a = (b == 0) ? m - 1 : b - 1;
  *c = (b + 1 == m) ? 0 : b + 1;
}

/* }==================================================================== */

/* {====================================================================
** Circumradius and the paper's weights
** ===================================================================== */

/* Radius of the circle through a, b, c: R = |ab| |bc| |ca| / (4 area);
** +INFINITY when the triple is collinear. */
static double circumradius3(const double *a, const double *b, const double *c, int dim) {
  double u[3], v[3], w[3], x[3], area2, sab, sbc, sca;
  int ex, i;
  scaled_edges(a, b, c, dim, u, v, &ex);
  for (i = 0; i < 3; i++) w[i] = u[i] + v[i]; /* c - a, scaled */
  sab = u[0] * u[0] + u[1] * u[1] + u[2] * u[2];
  sbc = v[0] * v[0] + v[1] * v[1] + v[2] * v[2];
  sca = w[0] * w[0] + w[1] * w[1] + w[2] * w[2];
  cross3(u, v, x);
  area2 = norm3(x);
  if (is_collinear(area2, sab, sbc, sca)) return INFINITY;
  /* three roots rather than one of the product; back to the data's scale at the end */
  return ldexp(sqrt(sab) * sqrt(sbc) * sqrt(sca) / (2.0 * area2), ex);
}

bsfit_err bsfit_geom_circumradius(const double *pts, size_t m, int dim, int closed,
                                  int centered, double *r, bsfit_status *st) {
  size_t k;
  bsfit_err e = check_seq(pts, m, dim, r, "r", st);
  if (e != BSFIT_OK) return e;
  for (k = 0; k < m; k++) {
    size_t a, b = triple_middle(k, m, closed, centered), c;
    neighbours(b, m, &a, &c);
    r[k] = circumradius3(point_at(pts, dim, a), point_at(pts, dim, b), point_at(pts, dim, c),
                         dim);
  }
  return bsfit__ok(st);
}

/* Mean + population standard deviation and minimum of the finite values of r
** (two passes, so equal radii give a standard deviation of exactly 0). Returns the
** number of finite values. */
static size_t finite_stats(const double *r, size_t m, double *rmax, double *rmin) {
  size_t k, n = 0;
  double sum = 0.0, var = 0.0, mean;
  *rmin = INFINITY;
  for (k = 0; k < m; k++)
    if (isfinite(r[k])) {
      sum += r[k];
      n++;
      if (r[k] < *rmin) *rmin = r[k];
    }
  if (n == 0) return 0;
  mean = sum / (double)n;
  /* deviations relative to the mean: squares of radii below 1e-154 would underflow */
  for (k = 0; k < m && mean > 0; k++)
    if (isfinite(r[k])) var += ((r[k] - mean) / mean) * ((r[k] - mean) / mean);
  *rmax = mean + mean * sqrt(var / (double)n);
  return n;
}

bsfit_err bsfit_weights_circumradius(const double *pts, size_t m, int dim, int closed,
                                     int centered, double *w, bsfit_status *st) {
  size_t k;
  double rmax = 0.0, rmin, wmax;
  bsfit_err e = bsfit_geom_circumradius(pts, m, dim, closed, centered, w, st);
  if (e != BSFIT_OK) return e;
  if (finite_stats(w, m, &rmax, &rmin) == 0) {
    for (k = 0; k < m; k++) w[k] = 1.0; /* all straight: nothing to prefer */
    return bsfit__ok(st);
  }
  /* min r <= mean <= r_max, so the smallest radius always gives the largest weight:
  ** computing w_max from it avoids depending on which points pass r_k <= r_max
  ** after rounding (with equal radii, rounding may put all of them above). */
  wmax = rmax / rmin;
  for (k = 0; k < m; k++) w[k] = (w[k] <= rmax) ? rmax / w[k] : wmax;
  return bsfit__ok(st);
}

/* }==================================================================== */

/* {====================================================================
** Angles, inflections, turning and spacing weights
** ===================================================================== */

/* Interior angle at b of the triangle (a, b, c), in degrees; 180 when a or c
** coincides with b. atan2 of the cross and dot products stays accurate near 0 and
** 180 degrees, where acos of the normalised dot product loses half the digits. */
static double angle_at(const double *a, const double *b, const double *c, int dim) {
  double u[3], v[3], x[3], dot = 0.0;
  int i, ex;
  scaled_edges(a, b, c, dim, u, v, &ex); /* u = b - a: turned into a - b below */
  for (i = 0; i < 3; i++) {
    u[i] = -u[i];
    dot += u[i] * v[i];
  }
  if (norm3(u) == 0.0 || norm3(v) == 0.0) return 180.0;
  cross3(u, v, x);
  return atan2(norm3(x), dot) * RAD_TO_DEG;
}

bsfit_err bsfit_geom_angles(const double *pts, size_t m, int dim, int closed, double *ang,
                            bsfit_status *st) {
  size_t k;
  bsfit_err e = check_seq(pts, m, dim, ang, "ang", st);
  if (e != BSFIT_OK) return e;
  for (k = 0; k < m; k++) {
    size_t a, b = triple_middle(k, m, closed, 1), c;
    neighbours(b, m, &a, &c);
    ang[k] = angle_at(point_at(pts, dim, a), point_at(pts, dim, b), point_at(pts, dim, c), dim);
  }
  return bsfit__ok(st);
}

static double dot3(const double x[3], const double y[3]) {
  return x[0] * y[0] + x[1] * y[1] + x[2] * y[2];
}

/* Turn vector at vertex b; returns 0 when the vertex is collinear (no turn). */
static int vertex_turn(const double *pts, size_t m, int dim, size_t b, double x[3]) {
  size_t a, c;
  const double *A, *B, *C;
  neighbours(b, m, &a, &c);
  double u[3], v[3], w[3];
  int ex, i;
  A = point_at(pts, dim, a);
  B = point_at(pts, dim, b);
  C = point_at(pts, dim, c);
  scaled_edges(A, B, C, dim, u, v, &ex); /* the direction of the turn is all we need */
  for (i = 0; i < 3; i++) w[i] = u[i] + v[i];
  cross3(u, v, x);
  return !is_collinear(norm3(x), dot3(u, u), dot3(v, v), dot3(w, w));
}

bsfit_err bsfit_geom_inflections(const double *pts, size_t m, int dim, int closed,
                                 size_t *count, bsfit_status *st) {
  size_t k, first = closed ? 0 : 1, last = closed ? m : m - 1, n = 0, changes = 0;
  double x[3], prev[3] = {0.0, 0.0, 0.0}, head[3] = {0.0, 0.0, 0.0};
  bsfit_err e = check_seq(pts, m, dim, count, "count", st);
  if (e != BSFIT_OK) return e;
  for (k = first; k < last; k++) {
    int i;
    if (!vertex_turn(pts, m, dim, k, x)) continue;
    if (n == 0)
      for (i = 0; i < 3; i++) head[i] = x[i];
    else if (dot3(prev, x) < 0.0)
      changes++;
    for (i = 0; i < 3; i++) prev[i] = x[i];
    n++;
  }
  /* a closed polygon turns from its last vertex back to its first one too */
  if (closed && n > 1 && dot3(prev, head) < 0.0) changes++;
  *count = changes;
  return bsfit__ok(st);
}

bsfit_err bsfit_weights_turning(const double *pts, size_t m, int dim, int closed, double *w,
                                bsfit_status *st) {
  size_t k;
  double sum = 0.0;
  bsfit_err e = bsfit_geom_angles(pts, m, dim, closed, w, st);
  if (e != BSFIT_OK) return e;
  for (k = 0; k < m; k++) {
    w[k] = fabs(180.0 - w[k]);
    sum += w[k];
  }
  for (k = 0; k < m; k++) w[k] = (sum > 0.0) ? 1.0 + w[k] / (sum / (double)m) : 1.0;
  return bsfit__ok(st);
}

/* |P_j - P_i|, scaled like hypot so that neither squares underflow nor overflow */
static double chord(const double *pts, int dim, size_t i, size_t j) {
  const double *a = point_at(pts, dim, i), *b = point_at(pts, dim, j);
  double big = 0.0, s = 0.0;
  int k;
  for (k = 0; k < dim; k++) big = fmax(big, fabs(b[k] - a[k]));
  if (big == 0.0) return 0.0;
  for (k = 0; k < dim; k++) s += ((b[k] - a[k]) / big) * ((b[k] - a[k]) / big);
  return big * sqrt(s);
}

bsfit_err bsfit_weights_spacing(const double *pts, size_t m, int dim, int closed, double *w,
                                bsfit_status *st) {
  size_t k;
  double sum = 0.0, prev, mean;
  bsfit_err e = check_seq(pts, m, dim, w, "w", st);
  if (e != BSFIT_OK) return e;
  /* an open end has only one chord, which stands for the missing one too */
  prev = closed ? chord(pts, dim, m - 1, 0) : chord(pts, dim, 0, 1);
  for (k = 0; k < m; k++) {
    double next = (k + 1 < m) ? chord(pts, dim, k, k + 1) : (closed ? chord(pts, dim, k, 0) : prev);
    w[k] = 0.5 * (prev + next);
    sum += w[k];
    prev = next;
  }
  mean = sum / (double)m;
  for (k = 0; k < m; k++) {
    double v = (mean > 0.0) ? w[k] / mean : 1.0;
    w[k] = v > BSFIT_GEOM_SPACING_FLOOR ? v : BSFIT_GEOM_SPACING_FLOOR;
  }
  return bsfit__ok(st);
}

/* bsfit_geom.h. Squared steps, one root: the coordinates are within 1e100 (check_seq), so
** their squares are far from overflow. */
bsfit_err bsfit_geom_longest_step(const double *pts, size_t m, int dim, int closed, double *h,
                                  bsfit_status *st) {
  size_t k;
  double most = 0.0;
  bsfit_err e = check_seq(pts, m, dim, h, "h", st);
  if (e != BSFIT_OK) return e;
  for (k = closed ? 0 : 1; k < m; k++) {
    const double *a = point_at(pts, dim, k == 0 ? m - 1 : k - 1), *b = point_at(pts, dim, k);
    double s = 0.0;
    int d;
    for (d = 0; d < dim; d++) s += (b[d] - a[d]) * (b[d] - a[d]);
    if (s > most) most = s;
  }
  *h = sqrt(most);
  return bsfit__ok(st);
}

/* }==================================================================== */

/* {====================================================================
** Lines: projection and distance (tangent correction, start-point search)
** ===================================================================== */

/* Foot of the perpendicular from P to the line origin + t dir, into foot. */
static bsfit_err line_foot(const double *P, const double *origin, const double *dir, int dim,
                           const double *out, double foot[3], bsfit_status *st) {
  double dd = 0.0, pd = 0.0, t;
  int i;
  bsfit_err e = check_dim(dim, st);
  if (e != BSFIT_OK) return e;
  if (P == NULL || origin == NULL || dir == NULL || out == NULL)
    return bsfit__fail(st, BSFIT_EINVAL, "%s is NULL",
                       P == NULL ? "P" : origin == NULL ? "origin" : dir == NULL ? "dir" : "out");
  if (!bsfit__all_finite(P, (size_t)dim) || !bsfit__all_finite(origin, (size_t)dim) ||
      !bsfit__all_finite(dir, (size_t)dim))
    return bsfit__fail(st, BSFIT_ENONFINITE, "P, origin or dir has a non-finite coordinate");
  for (i = 0; i < dim; i++) {
    dd += dir[i] * dir[i];
    pd += (P[i] - origin[i]) * dir[i];
  }
  if (!(dd > 0.0) || !isfinite(dd))
    return bsfit__fail(st, BSFIT_EDEGENERATE, "dir is zero (or overflows): no line");
  t = pd / dd;
  for (i = 0; i < dim; i++) foot[i] = origin[i] + t * dir[i];
  return BSFIT_OK;
}

bsfit_err bsfit_geom_tangent_project(const double *P, const double *origin, const double *dir,
                                     int dim, double *out, bsfit_status *st) {
  double foot[3];
  int i;
  bsfit_err e = line_foot(P, origin, dir, dim, out, foot, st);
  if (e != BSFIT_OK) return e;
  for (i = 0; i < dim; i++) out[i] = foot[i]; /* written last: out may alias an input */
  return bsfit__ok(st);
}

bsfit_err bsfit_geom_line_distance(const double *P, const double *origin, const double *dir,
                                   int dim, double *d, bsfit_status *st) {
  double foot[3];
  bsfit_err e = line_foot(P, origin, dir, dim, d, foot, st);
  if (e != BSFIT_OK) return e;
  *d = sqrt(dist2(P, foot, dim));
  return bsfit__ok(st);
}

/* }==================================================================== */
