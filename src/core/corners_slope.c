/*
** corners_slope.c
** Is a turn a slope jump? (corners_internal.h): the corner model against the smooth model
** of a join, and sides grown while they stay straight.
*/
#include "corners_internal.h"

#include <math.h>
#include <string.h>

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
/* the frame of a join: X along the sum of the side directions, Y across (towards the
** turn), Z the binormal (3D); len scales the coordinate along X; wl, wr the first weights
** of each side's residuals (the squared cosine of its slope in the frame) */
typedef struct frame {
  double X[3], Y[3], Z[3], len, wl, wr;
  int ncomp; /* residual components: 1 in 2D, 2 in 3D */
} frame;

/* 0 when the frame is undefined (sides within ~3 degrees of a full reversal) */
static int join_frame(const contour *c, const side *L, const side *R, frame *f) {
  double nx = 0, ny = 0, dl = 0, lx = 0, ly = 0, rx = 0, ry = 0;
  int d;
  memset(f, 0, sizeof *f);
  f->ncomp = c->dim == 3 ? 2 : 1;
  f->len = fmax(L->extent, R->extent);
  for (d = 0; d < 3; d++) f->X[d] = L->dir[d] + R->dir[d], nx += f->X[d] * f->X[d];
  nx = sqrt(nx);
  if (!(nx > 0.05) || !(f->len > 0)) return 0;
  for (d = 0; d < 3; d++) f->X[d] /= nx;
  for (d = 0; d < 3; d++) dl += (R->dir[d] - L->dir[d]) * f->X[d];
  for (d = 0; d < 3; d++) f->Y[d] = R->dir[d] - L->dir[d] - dl * f->X[d], ny += f->Y[d] * f->Y[d];
  ny = sqrt(ny);
  if (!(ny > 1e-9)) { /* straight on: any perpendicular */
    double *Y = f->Y, *X = f->X;
    Y[0] = -X[1], Y[1] = X[0], Y[2] = 0, ny = sqrt(Y[0] * Y[0] + Y[1] * Y[1]);
    if (!(ny > 0)) Y[0] = 0, Y[1] = -X[2], Y[2] = X[1], ny = sqrt(Y[1] * Y[1] + Y[2] * Y[2]);
  }
  for (d = 0; d < 3; d++) f->Y[d] /= ny;
  if (f->ncomp == 2) {
    f->Z[0] = f->X[1] * f->Y[2] - f->X[2] * f->Y[1];
    f->Z[1] = f->X[2] * f->Y[0] - f->X[0] * f->Y[2];
    f->Z[2] = f->X[0] * f->Y[1] - f->X[1] * f->Y[0];
  }
  for (d = 0; d < 3; d++) {
    lx += L->dir[d] * f->X[d], ly += L->dir[d] * f->Y[d];
    rx += R->dir[d] * f->X[d], ry += R->dir[d] * f->Y[d];
  }
  f->wl = lx * lx / (lx * lx + ly * ly);
  f->wr = rx * rx / (rx * rx + ry * ry);
  return 1;
}

/* the weight of a residual at u: the first pass the side's own (w0), then the model's
** slope there (coef: the previous pass), so that it measures distance */
static double slope_weight(const frame *f, double coef[2][5], double u, int it, double w0) {
  double g = 0;
  int q;
  if (it == 0) return w0;
  for (q = 0; q < f->ncomp; q++) {
    double c3 = coef[q][3] + (u > 0 ? coef[q][4] : 0.0);
    double sl = (coef[q][1] + 2.0 * coef[q][2] * u + 3.0 * c3 * u * u) / f->len;
    g += sl * sl;
  }
  return fmax(1.0 / (1.0 + g), 0.5 * fmin(f->wl, f->wr));
}

/* adds one side's samples to the normal equations of the smooth model (A, b, svv) */
static void add_side(const contour *c, const side *sd, const double *x, const frame *f,
                     double coef[2][5], int it, double w0, double A[5][5], double b[2][5],
                     double *svv) {
  size_t i, j = sd->k;
  int d, p, q;
  for (i = 0; i < sd->count; i++) {
    const double *P;
    double u = 0, v[2] = {0, 0}, r[5], w;
    j = step(c, j, sd->forward);
    P = point(c, j);
    for (d = 0; d < c->dim; d++) {
      u += (P[d] - x[d]) * f->X[d];
      v[0] += (P[d] - x[d]) * f->Y[d];
      v[1] += (P[d] - x[d]) * f->Z[d];
    }
    u /= f->len;
    r[0] = 1.0, r[1] = u, r[2] = u * u, r[3] = u * u * u, r[4] = u > 0 ? r[3] : 0.0;
    w = slope_weight(f, coef, u, it, w0);
    for (p = 0; p < 5; p++)
      for (q = 0; q < 5; q++) A[p][q] += w * r[p] * r[q];
    for (q = 0; q < f->ncomp; q++) {
      for (p = 0; p < 5; p++) b[q][p] += w * r[p] * v[q];
      *svv += w * v[q] * v[q];
    }
  }
}

size_t bsfit__corner_join_models(const contour *c, const side *L, const side *R, const double *x,
                                 double *rss0, double *rss1) {
  double coef[2][5] = {{0}};
  frame f;
  parabola pl, pr;
  int it, p, q;
  if (!bsfit__corner_fit_parabola(c, L, &pl) || !bsfit__corner_fit_parabola(c, R, &pr)) return 0;
  *rss0 = (double)L->count * pl.rms * pl.rms + (double)R->count * pr.rms * pr.rms;
  if (!join_frame(c, L, R, &f)) return 0;
  /* iteratively reweighted: each residual across Y is scaled by the model's own slope
  ** at the point (starting from the side lines' slopes), so it measures distance */
  for (it = 0; it < 3; it++) {
    double A[5][5] = {{0}}, b[2][5] = {{0}}, svv = 0;
    add_side(c, L, x, &f, coef, it, f.wl, A, b, &svv);
    add_side(c, R, x, &f, coef, it, f.wr, A, b, &svv);
    *rss1 = svv;
    for (q = 0; q < f.ncomp; q++) {
      double M[5][5];
      memcpy(M, A, sizeof M);
      memcpy(coef[q], b[q], sizeof coef[q]);
      if (!bsfit__corner_solve_spd(5, M, coef[q])) return 0;
      for (p = 0; p < 5; p++) *rss1 -= coef[q][p] * b[q][p];
    }
  }
  *rss1 = fmax(*rss1, 0.0);
  return L->count + R->count;
}

/* The side of k grown beyond `scale` (by steps of 25%, up to 4x and `cap`) while it
** stays straight to the noise level: the long straight sides of polygons give the
** slope-jump test its power on noisy data. */
void bsfit__corner_grow_side(const contour *c, size_t k, int forward, double scale, double sigma,
                             double cap, side *sd) {
  double f;
  for (f = 1.25; f <= 4.0 && f * scale <= cap; f *= 1.25) {
    side big;
    size_t far;
    if (!bsfit__corner_collect_side(c, k, forward, f * scale, &big, &far)) return;
    if (big.count <= sd->count) continue;
    /* sparse sides grow to 5 points whatever their shape: the models need them */
    if (sd->count >= 5) {
      parabola pb;
      double rss_line = (double)big.count * big.rms * big.rms;
      double slack = 1e-6 * big.extent * big.extent;
      if (big.rms > 1.3 * sigma + 0.001 * big.extent) return;
      /* straight: a cubic must not follow it much better than the line (an S bend can
      ** stay within the noise of a line on noisy data) */
      if (bsfit__corner_fit_parabola(c, &big, &pb) &&
          rss_line - pb.rss_cubic > 9.0 * sigma * sigma + (double)big.count * slack)
        return;
    }
    *sd = big;
  }
}

/* }====================================================================== */
