/*
** corners_curved.c
** Curved sides of a corner candidate (corners_internal.h): a parabola across each
** side's line, where curved sides meet, and what a side's curvature moves.
*/
#include "corners_internal.h"

#include <math.h>
#include <string.h>

/* {======================================================================
** Curved sides: a parabola across each side's line (in the line's frame), so that
** where two curved sides meet is not where their secants do (a half disc's corner
** would move out along its diameter), and so that a side's curvature can be allowed
** for when its line is extrapolated.
** ======================================================================= */

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

/* The frame of a side's parabola: its line's centre and direction, and the normals
** (2D: the left normal; 3D: n1 = axis x the coordinate axis least along it, n2 = axis x n1) */
static void parabola_frame(const contour *c, const side *sd, parabola *pb) {
  int d;
  memset(pb, 0, sizeof *pb);
  memcpy(pb->origin, sd->centre, sizeof pb->origin);
  memcpy(pb->axis, sd->dir, sizeof pb->axis);
  pb->len = sd->extent;
  pb->nn = c->dim - 1;
  if (c->dim == 2) {
    pb->normal[0][0] = -sd->dir[1];
    pb->normal[0][1] = sd->dir[0];
  } else {
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
}

/* the normal equations of the side's samples, for the parabola (A, rhs) and the cubic
** (A4, rhs4) across each normal; sbb the sums of squares of the offsets */
typedef struct side_sums {
  double A[3][3], rhs[2][3], sbb[2], A4[5][5], rhs4[2][5];
} side_sums;

static void side_normal_equations(const contour *c, const side *sd, const parabola *pb,
                                  side_sums *S) {
  size_t i, j = sd->k;
  int d, p, q, e;
  memset(S, 0, sizeof *S);
  for (i = 0; i < sd->count; i++) {
    const double *P;
    double a = 0, x[4];
    j = step(c, j, sd->forward);
    P = point(c, j);
    for (d = 0; d < c->dim; d++) a += (P[d] - pb->origin[d]) * pb->axis[d];
    x[0] = 1.0, x[1] = a / pb->len, x[2] = x[1] * x[1], x[3] = x[2] * x[1];
    for (p = 0; p < 3; p++)
      for (q = 0; q <= p; q++) S->A[p][q] += x[p] * x[q];
    for (p = 0; p < 4; p++)
      for (q = 0; q < 4; q++) S->A4[p][q] += x[p] * x[q];
    for (e = 0; e < pb->nn; e++) {
      double b = 0;
      for (d = 0; d < c->dim; d++) b += (P[d] - pb->origin[d]) * pb->normal[e][d];
      for (p = 0; p < 3; p++) S->rhs[e][p] += x[p] * b;
      for (p = 0; p < 4; p++) S->rhs4[e][p] += x[p] * b;
      S->sbb[e] += b * b;
    }
  }
  for (p = 0; p < 3; p++)
    for (q = p + 1; q < 3; q++) S->A[p][q] = S->A[q][p];
}

/* the residual sum of squares of a cubic across the side instead (rss: the parabola's;
** kept when the cubic's system is singular) */
static double cubic_rss(const parabola *pb, side_sums *S, double rss) {
  double r3 = 0;
  int e;
  for (e = 0; e < pb->nn; e++) {
    double M[5][5], sol[5];
    memcpy(M, S->A4, sizeof M);
    memcpy(sol, S->rhs4[e], sizeof sol);
    if (!bsfit__corner_solve_spd(4, M, sol)) return fmax(rss, 0.0);
    r3 += S->sbb[e] - (sol[0] * S->rhs4[e][0] + sol[1] * S->rhs4[e][1] +
                       sol[2] * S->rhs4[e][2] + sol[3] * S->rhs4[e][3]);
  }
  return fmax(fmin(r3, rss), 0.0);
}

/* Fits the parabola of side sd (its count points, k excluded); 0 when it cannot. */
int bsfit__corner_fit_parabola(const contour *c, const side *sd, parabola *pb) {
  side_sums S;
  double rss = 0;
  int e;
  if (sd->count < 4 || !(sd->extent > 0)) return 0;
  parabola_frame(c, sd, pb);
  side_normal_equations(c, sd, pb, &S);
  if (!cholesky3(S.A)) return 0;
  for (e = 0; e < pb->nn; e++) {
    double sol[3];
    memcpy(sol, S.rhs[e], sizeof sol);
    chol_solve3(S.A, sol);
    memcpy(pb->coef[e], sol, sizeof sol);
    rss += S.sbb[e] - (sol[0] * S.rhs[e][0] + sol[1] * S.rhs[e][1] + sol[2] * S.rhs[e][2]);
  }
  pb->rms = sqrt(fmax(rss, 0.0) / (double)sd->count);
  pb->rss_cubic = sd->count >= 5 ? cubic_rss(pb, &S, rss) : rss;
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
void bsfit__corner_refine_meet(const contour *c, const side *left, const side *right, double *x) {
  parabola pl, pr;
  double y[3] = {0, 0, 0}, pt_l[3], pt_r[3], t_l[3], t_r[3];
  double reach = fmax(left->extent, right->extent);
  int it, d;
  if (!bsfit__corner_fit_parabola(c, left, &pl) || !bsfit__corner_fit_parabola(c, right, &pr))
    return;
  for (it = 0; it < 4; it++) {
    double step2 = 0;
    parabola_at(&pl, x, pt_l, t_l);
    parabola_at(&pr, x, pt_r, t_r);
    if (!bsfit__corner_meet_lines(pt_l, t_l, pt_r, t_r, c->dim, y)) return;
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
double bsfit__corner_bend_allowance(const contour *c, const side *L, const side *R, const double *x,
                                    double turn) {
  const side *sd[2];
  double off = 0;
  int i, d, e;
  sd[0] = L;
  sd[1] = R;
  for (i = 0; i < 2; i++) {
    parabola pb;
    double kappa = 0, along = 0;
    if (!bsfit__corner_fit_parabola(c, sd[i], &pb)) continue;
    for (e = 0; e < pb.nn; e++) kappa += pb.coef[e][2] * pb.coef[e][2];
    kappa = 2.0 * sqrt(kappa) / (pb.len * pb.len);
    for (d = 0; d < 3; d++) along += (x[d] - sd[i]->outer_centre[d]) * sd[i]->outer_dir[d];
    off += 0.5 * kappa * along * along;
  }
  return off / fmax(sin(turn), 0.3);
}

/* }====================================================================== */
