/*
** side_models.c
** The models a run of samples is compared with (features_internal.h): the total
** least-squares line, the geometric least-squares circle, their distances and where
** two of them meet. Coordinates are taken relative to the run's first sample, so that
** runs far from the origin lose no digits.
*/
#include "features_internal.h"

#include <math.h>

int bsfit__fit_line(const bsfit__run *r, bsfit__line *L) {
  const double *o = bsfit__run_at(r, 0), *z = bsfit__run_at(r, r->n - 1);
  double mx = 0, my = 0, sxx = 0, sxy = 0, syy = 0, ang, dx, dy;
  size_t k;
  for (k = 0; k < r->n; k++) {
    const double *p = bsfit__run_at(r, k);
    mx += p[0] - o[0];
    my += p[1] - o[1];
  }
  mx /= (double)r->n;
  my /= (double)r->n;
  for (k = 0; k < r->n; k++) {
    const double *p = bsfit__run_at(r, k);
    double x = p[0] - o[0] - mx, y = p[1] - o[1] - my;
    sxx += x * x;
    sxy += x * y;
    syy += y * y;
  }
  if (sxx + syy <= 0) return 0;
  /* the principal axis of the scatter: angle of its largest eigenvector */
  ang = 0.5 * atan2(2.0 * sxy, sxx - syy);
  L->d[0] = cos(ang);
  L->d[1] = sin(ang);
  dx = z[0] - o[0];
  dy = z[1] - o[1];
  if (L->d[0] * dx + L->d[1] * dy < 0) L->d[0] = -L->d[0], L->d[1] = -L->d[1];
  L->p[0] = o[0] + mx;
  L->p[1] = o[1] + my;
  return 1;
}

double bsfit__line_dist(const bsfit__line *L, const double *x) {
  return fabs((x[0] - L->p[0]) * L->d[1] - (x[1] - L->p[1]) * L->d[0]);
}

/* sqrt(x^2 + y^2), not hypot, in the hot loops: hypot guards against overflow that
** coordinates relative to a run's first sample never come near, at several times the cost */
double bsfit__circle_dist(const bsfit__circle *C, const double *x) {
  double dx = x[0] - C->c[0], dy = x[1] - C->c[1];
  return fabs(sqrt(dx * dx + dy * dy) - C->r);
}

double bsfit__line_max(const bsfit__line *L, const bsfit__run *r, double *rms) {
  double mx = 0, s = 0;
  size_t k;
  for (k = 0; k < r->n; k++) {
    double d = bsfit__line_dist(L, bsfit__run_at(r, k));
    s += d * d;
    if (d > mx) mx = d;
  }
  if (rms) *rms = sqrt(s / (double)r->n);
  return mx;
}

double bsfit__circle_max(const bsfit__circle *C, const bsfit__run *r, double *rms) {
  double mx = 0, s = 0;
  size_t k;
  for (k = 0; k < r->n; k++) {
    double d = bsfit__circle_dist(C, bsfit__run_at(r, k));
    s += d * d;
    if (d > mx) mx = d;
  }
  if (rms) *rms = sqrt(s / (double)r->n);
  return mx;
}

/* the circle through a, b, c (relative to a); 0 when they are (nearly) collinear */
static int circle3(const double *a, const double *b, const double *c, bsfit__circle *C) {
  double bx = b[0] - a[0], by = b[1] - a[1], cx = c[0] - a[0], cy = c[1] - a[1];
  double D = 2.0 * (bx * cy - by * cx), b2 = bx * bx + by * by, c2 = cx * cx + cy * cy;
  double ux, uy;
  if (!(fabs(D) > 1e-13 * sqrt(b2 * c2))) return 0;
  ux = (cy * b2 - by * c2) / D;
  uy = (bx * c2 - cx * b2) / D;
  C->c[0] = a[0] + ux;
  C->c[1] = a[1] + uy;
  C->r = hypot(ux, uy);
  return 1;
}

/* Solves the 3 x 3 SPD system A x = g (A's lower triangle) in place of g, by LDL^T: each
** pivot measured against its own diagonal entry, which is what scaling A to a unit
** diagonal would do, without the square roots (the fit's steps are over few samples, where
** they were a third of the cost). 0 when a pivot is below 1e-13 of it. */
static int solve3(const double A[3][3], double *g) {
  double d0 = A[0][0], l10, l20, d1, l21, d2;
  if (!(d0 > 0)) return 0;
  l10 = A[1][0] / d0, l20 = A[2][0] / d0;
  d1 = A[1][1] - l10 * A[1][0];
  if (!(d1 > 1e-13 * A[1][1])) return 0;
  l21 = (A[2][1] - l20 * A[1][0]) / d1;
  d2 = A[2][2] - l20 * A[2][0] - l21 * l21 * d1;
  if (!(d2 > 1e-13 * A[2][2])) return 0;
  g[1] -= l10 * g[0];
  g[2] -= l20 * g[0] + l21 * g[1];
  g[0] /= d0, g[1] /= d1, g[2] /= d2;
  g[1] -= l21 * g[2];
  g[0] -= l10 * g[1] + l20 * g[2];
  return 1;
}

/* One Gauss-Newton step on sum (|p - c| - r)^2, in coordinates relative to o. The
** residual's gradient is (-u, -1), u the unit vector from the centre to a sample; on a
** short arc every u is nearly the same, so that the columns (u, 1) are nearly dependent
** and the normal matrix's condition is about 1/theta^4 for an arc of theta radians (4
** samples of a circle of 10^4 spanned 2e-3 rad: 1e11, and its Cholesky refused them). So
** the step is taken in a frame of the arc: t and n across and along the centre's
** direction to the middle sample, the centre moved by a t + b n and the radius by s - b,
** whose columns are (-u.t, 1 - u.n, -1) ~ (-phi, phi^2 / 2, -1): scaled to a unit
** diagonal (solve3) they are well conditioned at any theta. Returns a bound on how much
** the step moves any sample's residual, |a| max |u.t| + |b| max (1 - u.n) + |s| (on a
** short arc the centre and radius drift together by far more than any distance changes),
** and its length in *len; -1 when the normal matrix is singular. */
static double gauss_newton_step(const bsfit__run *r, const double *o, double *c, double *rad,
                                double *len) {
  double A[3][3] = {{0}}, g[3] = {0, 0, 0}, t[2], nn[2];
  const double *mid = bsfit__run_at(r, r->n / 2);
  double mx = mid[0] - o[0] - c[0], my = mid[1] - o[1] - c[1], dm = sqrt(mx * mx + my * my);
  double most[2] = {0, 0};
  size_t k;
  if (!(dm > 0)) return -1.0;
  nn[0] = mx / dm, nn[1] = my / dm, t[0] = -nn[1], t[1] = nn[0];
  for (k = 0; k < r->n; k++) {
    const double *p = bsfit__run_at(r, k);
    double x = p[0] - o[0] - c[0], y = p[1] - o[1] - c[1], d = sqrt(x * x + y * y), e;
    double ut, v, inv;
    if (d <= 0) continue;
    inv = 1.0 / d;
    ut = (x * t[0] + y * t[1]) * inv;
    /* 1 - u.n, to about DBL_EPSILON / v of itself: that only slows the steps (the circle
    ** that zeroes the residuals zeroes the gradient whatever J is) */
    v = (d - (x * nn[0] + y * nn[1])) * inv;
    if (fabs(ut) > most[0]) most[0] = fabs(ut);
    if (v > most[1]) most[1] = v;
    e = d - *rad;
    /* J = (-ut, v, -1) */
    g[0] += ut * e, g[1] -= v * e, g[2] += e;
    A[0][0] += ut * ut, A[1][0] -= v * ut, A[1][1] += v * v;
    A[2][0] += ut, A[2][1] -= v, A[2][2] += 1.0;
  }
  if (!solve3(A, g)) return -1.0;
  c[0] += g[0] * t[0] + g[1] * nn[0];
  c[1] += g[0] * t[1] + g[1] * nn[1];
  *rad += g[2] - g[1];
  *len = sqrt(g[0] * g[0] + g[1] * g[1] + (g[2] - g[1]) * (g[2] - g[1]));
  return fabs(g[0]) * most[0] + fabs(g[1]) * most[1] + fabs(g[2]);
}

/* The largest radius a run's circle may have: 1e6 times the run's extent. Its distances are
** computed to about DBL_EPSILON r, its bow over the run is about extent^2 / (8 r): beyond
** that radius the samples are collinear to rounding, and the fit drifts towards a line
** (a noisy corner's samples fitted a circle of 1e17 whose distances all came out 0). */
static double largest_radius(const bsfit__run *r) {
  const double *o = bsfit__run_at(r, 0), *b = bsfit__run_at(r, r->n / 2);
  const double *z = bsfit__run_at(r, r->n - 1);
  double bx = b[0] - o[0], by = b[1] - o[1], zx = z[0] - o[0], zy = z[1] - o[1];
  return 1e6 * sqrt(fmax(bx * bx + by * by, zx * zx + zy * zy));
}

int bsfit__fit_circle(const bsfit__run *r, const bsfit__circle *init, double eps,
                      bsfit__circle *C) {
  const double *o = bsfit__run_at(r, 0);
  double c[2], rad, moved, len = 0, rmax;
  int it;
  if (r->n < 3) return 0;
  rmax = largest_radius(r);
  if (init != NULL && r->n > 3 && init->r <= rmax)
    *C = *init;
  else if (!circle3(o, bsfit__run_at(r, r->n / 2), bsfit__run_at(r, r->n - 1), C))
    return 0;
  if (r->n == 3) return C->r <= rmax;
  c[0] = C->c[0] - o[0];
  c[1] = C->c[1] - o[1];
  rad = C->r;
  /* until a step moves no sample's distance by more than eps (the caller's use of it:
  ** distances are compared with a tolerance), or the circle by 1e-13 of its scale (exact
  ** samples converge quadratically: the error left is the step's square). On a short arc
  ** the centre and radius drift together by far more than any distance changes. */
  for (it = 0; it < 30; it++) {
    moved = gauss_newton_step(r, o, c, &rad, &len);
    if (moved < 0 || !(rad <= rmax) || !isfinite(c[0]) || !isfinite(c[1])) return 0;
    if (len <= 1e-13 * (rad + fabs(c[0]) + fabs(c[1])) || moved <= eps) break;
  }
  if (!(rad > 0)) return 0;
  C->c[0] = o[0] + c[0];
  C->c[1] = o[1] + c[1];
  C->r = rad;
  return 1;
}

int bsfit__meet_lines(const bsfit__line *A, const bsfit__line *B, double x[2]) {
  double den = A->d[0] * B->d[1] - A->d[1] * B->d[0], t;
  if (fabs(den) < 1e-15) return 0;
  t = ((B->p[0] - A->p[0]) * B->d[1] - (B->p[1] - A->p[1]) * B->d[0]) / den;
  x[0] = A->p[0] + t * A->d[0];
  x[1] = A->p[1] + t * A->d[1];
  return 1;
}

int bsfit__meet_line_circle(const bsfit__line *L, const bsfit__circle *C, double x[2][2]) {
  /* foot of the centre on the line, then +-h along it */
  double t = (C->c[0] - L->p[0]) * L->d[0] + (C->c[1] - L->p[1]) * L->d[1];
  double f[2] = {L->p[0] + t * L->d[0], L->p[1] + t * L->d[1]};
  double e = hypot(C->c[0] - f[0], C->c[1] - f[1]), h2 = C->r * C->r - e * e, h;
  if (h2 < -1e-12 * C->r * C->r) return 0;
  h = h2 > 0 ? sqrt(h2) : 0.0;
  if (h <= 1e-12 * C->r) {
    x[0][0] = f[0], x[0][1] = f[1];
    return 1;
  }
  x[0][0] = f[0] - h * L->d[0], x[0][1] = f[1] - h * L->d[1];
  x[1][0] = f[0] + h * L->d[0], x[1][1] = f[1] + h * L->d[1];
  return 2;
}

int bsfit__meet_circles(const bsfit__circle *A, const bsfit__circle *B, double x[2][2]) {
  double dx = B->c[0] - A->c[0], dy = B->c[1] - A->c[1], d = hypot(dx, dy), a, h2, h, u[2];
  double big = A->r > B->r ? A->r : B->r;
  if (d <= 1e-14 * big) return 0;
  a = (d * d + A->r * A->r - B->r * B->r) / (2.0 * d);
  h2 = A->r * A->r - a * a;
  if (h2 < -1e-12 * big * big) return 0;
  h = h2 > 0 ? sqrt(h2) : 0.0;
  u[0] = dx / d;
  u[1] = dy / d;
  if (h <= 1e-12 * big) {
    x[0][0] = A->c[0] + a * u[0], x[0][1] = A->c[1] + a * u[1];
    return 1;
  }
  x[0][0] = A->c[0] + a * u[0] - h * u[1], x[0][1] = A->c[1] + a * u[1] + h * u[0];
  x[1][0] = A->c[0] + a * u[0] + h * u[1], x[1][1] = A->c[1] + a * u[1] - h * u[0];
  return 2;
}
