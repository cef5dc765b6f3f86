/*
** corners_internal.h
** What the corner detector's files share (bsfit_corners_detect, bsfit_analysis.h): the
** contour and its prefix sums, a side's line, a side's parabola, and the functions each
** file lends the others. corners_sides.c: the straight side models and where they meet;
** corners_curved.c: curved sides (parabolas); corners_slope.c: is a turn a slope jump;
** corners.c: the candidates and the detection.
*/
#ifndef BSFIT_CORNERS_INTERNAL_H
#define BSFIT_CORNERS_INTERNAL_H

#include "internal.h"

#include <math.h>

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
typedef struct parabola {
  double origin[3], axis[3], normal[2][3]; /* the side's frame */
  int nn;                                  /* normal directions: dim - 1 */
  double len;                              /* coordinate along the axis is s = a / len */
  double coef[2][3];                       /* b_j(s) = c0 + c1 s + c2 s^2 */
  double rms;                              /* RMS residual across the side */
  double rss_cubic;                        /* residual sum of squares of a cubic instead */
} parabola;

static inline const double *point(const contour *c, size_t i) {
  return c->pts + (i % c->m) * (size_t)c->dim;
}

static inline double dist(const contour *c, size_t i, size_t j) {
  const double *a = point(c, i), *b = point(c, j);
  double s = 0;
  int d;
  for (d = 0; d < c->dim; d++) s += (a[d] - b[d]) * (a[d] - b[d]);
  return sqrt(s);
}
static inline size_t at(const contour *c, size_t k, long off) {
  long m = (long)c->m;
  return (size_t)((((long)k + off) % m + m) % m);
}

static inline size_t step(const contour *c, size_t i, int forward) {
  if (forward) return (i + 1) % c->m;
  return (i + c->m - 1) % c->m;
}

/* corners_sides.c */
void bsfit__corner_build_prefix(contour *c);
moments bsfit__corner_run_moments(const contour *c, size_t first, size_t last);
void bsfit__corner_fit_line(const contour *c, const moments *mo, const double *hint, side *sd);
int bsfit__corner_collect_side(const contour *c, size_t k, int forward, double scale, side *sd,
                               size_t *far_index);
double bsfit__corner_turn_at_scale(const contour *c, size_t k, double scale, side *left,
                                   side *right, size_t *from, size_t *to);
int bsfit__corner_meet_lines(const double *ac, const double *ad, const double *bc, const double *bd,
                             int dim, double *x);
int bsfit__corner_meet(const side *a, const side *b, int dim, double *x);
double bsfit__corner_meet_variance(const side *a, const side *b, const double *x, double sigma);
double bsfit__corner_edge_distance(const contour *c, size_t k, const double *x, double turn);
int bsfit__corner_turn_concentrated(const contour *c, double position, const side *left,
                                    const side *right, double sigma);
int bsfit__corner_solve_spd(int n, double A[BSFIT__SMALL][BSFIT__SMALL], double *b);

/* corners_curved.c */
int bsfit__corner_fit_parabola(const contour *c, const side *sd, parabola *pb);
void bsfit__corner_refine_meet(const contour *c, const side *left, const side *right, double *x);
double bsfit__corner_bend_allowance(const contour *c, const side *L, const side *R, const double *x,
                                    double turn);

/* corners_slope.c */
size_t bsfit__corner_join_models(const contour *c, const side *L, const side *R, const double *x,
                                 double *rss0, double *rss1);
void bsfit__corner_grow_side(const contour *c, size_t k, int forward, double scale, double sigma,
                             double cap, side *sd);

#endif
