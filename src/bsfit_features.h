/*
** bsfit_features.h
** Sharp features of a section (issue 14): its segmentation into straight lines,
** circular arcs and free-form runs meeting at corners or tangentially, and the
** assembly of one degree-3 curve (NURBS when it has arcs) from such pieces.
** Included by bsfit.h; include bsfit.h rather than this file.
*/
#ifndef BSFIT_FEATURES_H
#define BSFIT_FEATURES_H

#include "bsfit.h"

/** What a piece of a segmented section is. */
typedef enum bsfit_piece_kind {
  BSFIT_PIECE_LINE = 0, /**< a straight segment */
  BSFIT_PIECE_ARC = 1,  /**< a circular arc */
  BSFIT_PIECE_FREE = 2  /**< a free-form run (fitted by least squares by the caller) */
} bsfit_piece_kind;

/** How a piece meets the one before it. */
typedef enum bsfit_join_kind {
  BSFIT_JOIN_END = 0,     /**< first piece of an open section: no predecessor */
  BSFIT_JOIN_CORNER = 1,  /**< C0: the two pieces' directions differ */
  BSFIT_JOIN_TANGENT = 2  /**< G1: the directions agree (line into fillet, arc into arc) */
} bsfit_join_kind;

/** One piece of a segmentation (2D). */
typedef struct bsfit_piece {
  bsfit_piece_kind kind;
  bsfit_join_kind join;   /**< how it meets the previous piece (the last, for closed) */
  size_t first, count;    /**< its samples: count of them from first (0-based, modulo m for
                               closed sections); a free piece that only bridges two
                               primitives whose models do not meet has none */
  double start[2], end[2];/**< its end points: where it meets its neighbours */
  double t_start[2], t_end[2]; /**< unit tangents at its ends (along the traversal) */
  double centre[2];       /**< arcs: the centre */
  double radius;          /**< arcs: the radius (0 otherwise) */
  double sweep;           /**< arcs: the signed angle swept, radians (> 0: counter-clockwise) */
  double rms, max;        /**< distances of its samples to its model (free: 0, 0) */
  double turn;            /**< corner joins: the angle between the two directions, radians */
  double evidence;        /**< corner joins: how much worse one smooth curve (a circle, or
                               a cubic over the chord) explains both pieces' samples than
                               the two models meeting at the corner, in units of
                               (tol/tol_sigma)^2, i.e. sigma^2 on noisy data */
  double radius_se;       /**< arcs: the standard error of the radius at the noise sigma, from
                               the spread of the arc's samples round its centre (the free
                               circle's Gauss-Newton information), or for a fillet (tangent
                               to a line at both ends) from its samples and its lines'
                               errors (docs/auto.md); 0 on exact data and for other pieces;
                               HUGE_VAL when the samples cannot fix it */
} bsfit_piece;

/** Options of bsfit_segment. Zero-initialise, then set what you need. */
typedef struct bsfit_segment_opts {
  int closed;        /**< the section is closed */
  double sigma;      /**< noise level (>= 0); 0: the data is taken as exact */
  double tol_sigma;  /**< a sample fits a model within tol_sigma * sigma; 0: 4 */
  double exact;      /**< relative tolerance of exact data (of the size); 0: 1e-10 */
  size_t min_line;   /**< fewest samples of a line; 0: 3 */
  size_t min_arc;    /**< fewest samples of an arc; 0: 4 */
  double param_cost; /**< noisy data: what a parameter of a piece costs, in sigma^2 of its
                          residual; 0: 32, HUGE_VAL: parameters only (no residual) */
} bsfit_segment_opts;

/** Splits an ordered 2D section into lines, arcs and free-form runs.
**
** Each sample belongs to one piece (or, at a corner or tangent point that was sampled,
** to the two pieces meeting there). A run of samples is a line (an arc) when every one
** of them lies within tol = max(tol_sigma * sigma, exact * size) of its total
** least-squares line (geometric circle fit), size the bounding-box diagonal; tol is at
** least 16 DBL_EPSILON times the largest coordinate (the rounding of exact samples far
** from the origin, 10^4 times their size and more). The cover
** of the section is the one of least cost by dynamic programming: 2 per line (its
** parameters), 3 per arc, 1 per free sample plus 1 per free run, so a line beats an arc
** and both beat free samples. On noisy data (sigma > 0) a piece also
** costs its residual sum of squares in sigma^2, and each parameter param_cost sigma^2: a
** line that holds the first samples of the fillet after it within tol explains them worse
** than the fillet does, and gives them up. A noisy section of more than 500 samples is
** covered on every k-th sample (k = ceil(m / 500)), each boundary then placed among the
** samples around it where the two models explain them best, and every model refitted on
** all its samples. Consecutive primitives meet where their models meet:
** tangentially (G1) when their directions there differ by less than the noise allows,
** else at a corner; when the models do not meet between the two pieces' last and first
** samples, a free run bridges them. A free run meets a primitive at that primitive's
** extreme sample, projected on its model, with its tangent (G1). A line of 2 samples
** between two lines whose corners it confirms is kept as a line.
**
** On noisy data a caller keeps a corner only when its `evidence` is large (the smooth
** alternative misses by many sigma^2): two arcs of an ellipse meet at a small angle
** that a cubic explains as well.
**
** Cost: O(m r), r the longest run (the weighed cover of noisy data tries every start of
** every run: O(m r) pieces, each O(1) from prefix sums of moments). Limits: 2D only; free-form runs are not split at
** corners of their own.
** @param[out] pieces at most cap pieces, in section order (for closed sections the
**                    first starts where a primitive starts, when there is one).
** @param[out] count  the number of pieces (may exceed cap: retry larger; m is enough).
** @return BSFIT_OK, BSFIT_EDIM (dim != 2), BSFIT_ETOOFEW (m < 3), BSFIT_ENONFINITE,
**         BSFIT_EINVAL (options), BSFIT_EDEGENERATE (all points coincide),
**         BSFIT_ENOMEM, BSFIT_EINTR. */
BSFIT_API bsfit_err bsfit_segment(const double *pts, size_t m, int dim,
                                  const bsfit_segment_opts *opts, bsfit_piece *pieces,
                                  size_t cap, size_t *count, const bsfit_allocator *a,
                                  bsfit_status *st);

/* The step between the levels of bsfit_segment_sigma's search: 10^(1/4). A caller that
** tries the levels after the one it matched (the auto strategy's noisy pieces do) steps by
** it too (bs.geom.SEGMENT_SIGMA_STEP). */
#define BSFIT_SEGMENT_SIGMA_STEP 1.7782794100389228

/** Estimates the noise of a section of lines and arcs from the models themselves.
** Segmented at a level below its noise, a section's runs stop short, and the pooled
** residual of its lines and arcs (sum of squares over degrees of freedom) exceeds the
** level; at the noise the models are right and the two match. The levels tried rise by
** 10^(1/4) (10^(1/12) where the next could match; the last at max_sigma) from a
** sixteenth of a first guess (how far samples lie off their neighbours' chord: the lower
** quartile, over its value for pure noise, 0.3186 sigma); the first whose pooled residual
** is at most 1.2 times the level gives the estimate. When none does and some level's
** models left a robust residual below the start (the first guess was above the noise),
** the levels below the start, down to a sixteenth of it: the first that matches; those
** levels are tried first, too, when a level above matched at more than 20 times the least
** robust residual of the levels before it (kept when none below matches). Sparse samples of a contour that bends between them make window-based
** estimates (bsfit_noise_sigma) many times too large; this one is not, where lines and
** arcs hold the samples. A section of more than 500 samples is read on every k-th sample
** (k = ceil(m / 500)): each keeps its noise, and the search costs the same from 500
** samples up (it took 0.9 s on every one of 40000). Cost: up to ~35 segmentations
** (typically 10-20).
** @param[in]  max_sigma the highest level tried (<= 0: 5% of the size): a caller that
**                   will not believe a larger one saves the costly high levels, where
**                   runs grow long.
** @param[out] sigma the estimate; 0 when every line and arc is exact to 1e-10 of the
**                   size, or when no level up to max_sigma explains the section (then
**                   lines and arcs do not hold it).
** @return BSFIT_OK or the codes of bsfit_segment. */
BSFIT_API bsfit_err bsfit_segment_sigma(const double *pts, size_t m, int dim, int closed,
                                        double max_sigma, double *sigma,
                                        const bsfit_allocator *a, bsfit_status *st);

/** Where the segmentation reads a closed 2D section from, whichever sample its data start
** at: the sample after its longest step (the closing one included), ties broken by the
** lowest x, then y. bsfit_segment, bsfit_segment_sigma and their every-k-th subsamples of
** large sections begin there; a caller that reads a closed section through a subsample of
** its own begins there too, and reads the same from any start. O(m).
** @param[out] first its 0-based index
** @return BSFIT_OK, BSFIT_EDIM (dim != 2), BSFIT_ETOOFEW (m == 0), BSFIT_ENONFINITE. */
BSFIT_API bsfit_err bsfit_segment_start(const double *pts, size_t m, int dim, size_t *first,
                                        bsfit_status *st);

/** A straight segment from a to b as a degree-3 curve on [0, 1] with four collinear,
** evenly spaced control points (its speed is constant). dim 1..4. */
BSFIT_API bsfit_err bsfit_curve_line(const double *a, const double *b, int dim, bsfit_curve *c,
                                     const bsfit_allocator *al, bsfit_status *st);

/** A circular arc (2D) as an exact degree-3 rational curve on [0, 1]: the sweep is cut
** into equal parts of at most 90 degrees, each the rational quadratic arc (end weights
** 1, middle weight cos of half its angle) raised to degree 3; the parts meet at knots
** of multiplicity 3, all weights positive.
** @param[in] centre, radius (> 0), start angle a0 (radians), signed sweep (|sweep| in
**            (0, 2 pi]). */
BSFIT_API bsfit_err bsfit_curve_arc(const double *centre, double radius, double a0,
                                    double sweep, bsfit_curve *c, const bsfit_allocator *al,
                                    bsfit_status *st);

/** Joins open curves end to end into one degree-3 curve (C0 knots of multiplicity 3 at
** the joins): part i takes the parameter range [s_i, s_{i+1}] of [0, 1] in proportion
** to lengths[i] (> 0). The parts must be open, clamped, of degree <= 3 (lower degrees are
** raised), of one dimension, each one's start within 1e-9 of the size of the previous
** one's end (the start is then made equal to it). The result is rational when any part
** is, polynomial otherwise; a part's end weights must then be 1 (or it is polynomial).
** @return BSFIT_OK, BSFIT_EINVAL (no parts, a part periodic, not clamped, ends apart,
**         a length <= 0, end weights not 1), BSFIT_EDIM, BSFIT_EDEGREE, BSFIT_ENOMEM. */
BSFIT_API bsfit_err bsfit_curve_join(const bsfit_curve *const *parts, size_t n,
                                     const double *lengths, bsfit_curve *out,
                                     const bsfit_allocator *al, bsfit_status *st);

/** Whether the closed or open polyline of samples of a 2D curve crosses itself, by a
** sweep over its edges sorted along an axis (O(k log k) plus the pairs whose ranges
** overlap). The samples: k even in the parameter, and 24 on either side of every corner
** (a knot of multiplicity >= the degree), at 2^-1 .. 2^-24 of the span beside it, where a
** loop can be far shorter than the even step. Edges that share a sample do not count.
** @param[out] crossings number of crossing edge pairs found (capped at 1000).
** @param[out] where     when not NULL and crossings > 0: a parameter of the curve at
**                       the first crossing found.
** @return BSFIT_OK, BSFIT_EDIM, BSFIT_EINVAL (k < 3), BSFIT_ENOMEM, BSFIT_EINTR. */
BSFIT_API bsfit_err bsfit_curve_self_intersections(const bsfit_curve *c, size_t k,
                                                   size_t *crossings, double *where,
                                                   const bsfit_allocator *al,
                                                   bsfit_status *st);

/** The distances of m points to a curve assembled from pieces of them (auto's sharp path):
** piece j holds the points first[j] .. first[j] + count[j] - 1 (0-based, modulo m) and
** covers the fraction [range[2j], range[2j+1]] of c's domain. Each point's foot is found
** by `iters` Newton steps (bsfit_curve_project_many) from its place in its piece's range
** (sample k of n at the fraction (k + 1/2) / n of it; a point equal to the one before it
** from that one's place; a point in no piece from the domain's start), and, unless that
** foot is certified (on a straight span, no farther than the span's line, no other span's
** control points within that distance: then the smaller of the two distances), by the
** global search of bsfit_curve_closest_many: the nearer is its distance. Newton from
** inside its own piece never has to cross a corner, where a global start can stall. A
** point whose start lies on a span of a circle (a rational arc, checked by the Bernstein
** coefficients of its distance to the circle), whose foot on the circle lies on that span
** and which no other span comes near, takes its distance to the circle without Newton. A
** certified distance is within 1e-14 of the largest control-point coordinate of the
** true one.
** @param[out] dist m distances.
** Cost: iters evaluations and O(log spans) per point (none for those certified on arcs),
** plus bsfit_curve_closest_many for the points not certified; scratch (2 dim + 7) m
** doubles and the spans' boxes through a.
** @return BSFIT_OK, the codes of bsfit_curve_closest_many and bsfit_curve_project_many,
**         BSFIT_EINVAL (NULL arrays, a piece's samples outside the m points, iters < 0),
**         BSFIT_ENONFINITE (a range, a point), BSFIT_ENOMEM. */
BSFIT_API bsfit_err bsfit_curve_piece_distances(const bsfit_curve *c, const double *pts, size_t m,
                                                const size_t *first, const size_t *count,
                                                const double *range, size_t np, int iters,
                                                double *dist, const bsfit_allocator *a,
                                                bsfit_status *st);

#endif /* BSFIT_FEATURES_H */
