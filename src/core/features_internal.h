/*
** features_internal.h
** The side models of the feature code (side_models.c): lines and circles fitted to runs
** of an ordered 2D section, their distances and where two of them meet. Shared by
** segment.c; not part of the public API.
*/
#ifndef BSFIT_FEATURES_INTERNAL_H
#define BSFIT_FEATURES_INTERNAL_H

#include "internal.h"

/* a run of samples of a section: first and n samples on, modulo m (closed wraps) */
typedef struct bsfit__run {
  const double *pts; /* m 2D points */
  size_t m, first, n;
} bsfit__run;

/* the line through p with unit direction d, oriented along the run */
typedef struct bsfit__line {
  double p[2], d[2];
} bsfit__line;

/* the circle of centre c and radius r */
typedef struct bsfit__circle {
  double c[2], r;
} bsfit__circle;

/* sample k of the run (k < n) */
static inline const double *bsfit__run_at(const bsfit__run *r, size_t k) {
  return r->pts + 2 * ((r->first + k) % r->m);
}

/* Total least-squares line of the run (n >= 2); 0 when its points coincide. */
int bsfit__fit_line(const bsfit__run *r, bsfit__line *L);

/* Geometric least-squares circle of the run (n >= 3), by Gauss-Newton from `init` (a
** nearby run's circle: it then settles in a step or two) or, when NULL, from the circle
** through its first, middle and last samples, until a step moves no sample's distance by
** more than eps (or the circle by 1e-13 of its scale); steps in the frame of the arc, so
** that short arcs of dense samples fit to rounding. 0 when they are collinear, the radius
** would pass 1e6 times the run's extent (a line), or it does not settle. */
int bsfit__fit_circle(const bsfit__run *r, const bsfit__circle *init, double eps, bsfit__circle *C);

double bsfit__line_dist(const bsfit__line *L, const double *x);
double bsfit__circle_dist(const bsfit__circle *C, const double *x);

/* Largest distance and RMS of the run's samples to a line (circle). */
double bsfit__line_max(const bsfit__line *L, const bsfit__run *r, double *rms);
double bsfit__circle_max(const bsfit__circle *C, const bsfit__run *r, double *rms);

/* Meeting points of a line and a circle, or two circles: up to 2 written to x[2][2];
** returns their number (a tangent pair, within rounding, gives 1). */
int bsfit__meet_line_circle(const bsfit__line *L, const bsfit__circle *C, double x[2][2]);
int bsfit__meet_circles(const bsfit__circle *A, const bsfit__circle *B, double x[2][2]);
/* Meeting point of two lines; 0 when parallel. */
int bsfit__meet_lines(const bsfit__line *A, const bsfit__line *B, double x[2]);

/* A noisy section of more samples is read on every k-th sample (k = ceil(m / 500)): the
** segmentation's cover (segment_dense.c) and its noise search (segment_sigma.c) */
#define BSFIT__DENSE_MOST 500

/* segment_cover.c: whether sample i of a closed section of m comes before sample j in the
** order that picks where a closed section is read from and cut, whichever sample its data
** start at: after the longer step into it, then lower in x, then in y */
int bsfit__starts_before(const double *pts, size_t m, size_t i, size_t j);

/* segment_cover.c: the first sample of a closed section in bsfit__starts_before's order */
size_t bsfit__closed_start(const double *pts, size_t m);

/* segment_dense.c: every k-th of the m samples (k = ceil(m / most)) from sample `first`
** (round a closed section; 0 for an open one), a new array of *msub points (free it with 2
** *msub doubles), *k the stride; NULL when out of memory */
double *bsfit__spread(const double *pts, size_t m, size_t first, size_t most,
                      const bsfit_allocator *a, size_t *msub, size_t *k);

/* segment_joins.c: the distance of sample q to the model of piece p (a line through its ends, a
** circle); 0 for a free piece */
double bsfit__piece_dist(const bsfit_piece *p, const double *q);

/* segment.c: the bounding-box diagonal of m 2D points, and the argument checks of
** bsfit_segment (shared with segment_sigma.c) */
double bsfit__segment_size(const double *pts, size_t m);
bsfit_err bsfit__segment_check(const double *pts, size_t m, int dim, const bsfit_segment_opts *o,
                               bsfit_status *st);

/* segment_moments.c: prefix sums of a section's moments (over 2m samples, wrapping), about
** its centroid in units of its size, so that the residual sum of squares of the
** least-squares line (Kasa circle, geometric to first order) of any run is O(1). Runs are
** given unwrapped: first + n <= 2m. HUGE_VAL when the model cannot be fitted. */
typedef struct bsfit__moments {
  double *sum; /* (n + 1) x 9 prefix sums */
  size_t n;
  double c[2], scale;
} bsfit__moments;

bsfit_err bsfit__moments_init(bsfit__moments *mo, const double *pts, size_t m,
                              const bsfit_allocator *a);
void bsfit__moments_free(bsfit__moments *mo, const bsfit_allocator *a);
double bsfit__moments_line_rss(const bsfit__moments *mo, size_t first, size_t n);
double bsfit__moments_arc_rss(const bsfit__moments *mo, size_t first, size_t n);

#endif
