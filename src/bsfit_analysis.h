/*
** bsfit_analysis.h
** Reading a noisy section before fitting it (issue 7): the noise level of the points,
** estimated from the data alone, and the sharp corners of the contour.
** Included by bsfit.h; include bsfit.h rather than this file.
*/
#ifndef BSFIT_ANALYSIS_H
#define BSFIT_ANALYSIS_H

#include "bsfit.h"

/** Estimates the standard deviation of the noise normal to the curve, from the
** ordered points alone.
**
** Each point's window of 2h+1 neighbours (h = 4; shifted inwards at the ends of open
** data) is expressed in a local frame (origin at the point, first axis along the chord
** of the window); the normal coordinate(s) are fitted by a cubic in the tangential
** coordinate, and the point's residual is divided by sqrt(1 - leverage), which makes it
** an unbiased sample of the noise whatever the spacing. The scale is the 40% quantile of
** the standardised residual magnitudes divided by that of the noise distribution
** (half-normal in 2D: 0.5244; chi with 2 degrees of freedom in 3D: 1.0108), so corners
** and outliers, which inflate the upper residuals, do not bias it even when a third of
** the windows hold one.
**
** @param[in]  pts    m points, dim doubles each (dim 2 or 3).
** @param[in]  closed non-zero: the windows wrap around.
** @param[out] sigma  the estimate (0 for data exactly on a smooth curve or a line).
** @return BSFIT_OK, BSFIT_EDIM, BSFIT_ETOOFEW (m < 6), BSFIT_ENONFINITE,
**         BSFIT_EDEGENERATE (no window with distinct points), BSFIT_ENOMEM. */
BSFIT_API bsfit_err bsfit_noise_sigma(const double *pts, size_t m, int dim, int closed,
                                      double *sigma, bsfit_status *st);

/** Options of bsfit_corners_detect. Zero-initialise, then set what you need. */
typedef struct bsfit_corner_opts {
  int closed;            /**< the contour is closed */
  double sigma;          /**< noise level; <= 0: estimated with bsfit_noise_sigma */
  double min_angle_deg;  /**< smallest turn that can be a corner; 0: 30 degrees */
  double scale;          /**< length of each side window; 0: automatic (see below) */
} bsfit_corner_opts;

/** A corner found by bsfit_corners_detect. */
typedef struct bsfit_corner {
  size_t index;      /**< the sample nearest to the corner */
  double angle;      /**< the turn between the two sides, degrees */
  double position;   /**< where the corner lies along the samples: a fractional index j + f
                          (f in [0, 1)) between samples j and j+1, f the share of the path
                          Q_j -> point -> Q_{j+1} before the corner point; in [0, m).
                          Only when both sides are straight to within 2 sigma (else the
                          side lines miss the true corner) and the polygon turns less than
                          90% of the corner's turn at `index`: otherwise `index` itself. */
  double point[3];   /**< the corner itself: where the side lines meet (dim coordinates) */
} bsfit_corner;

/** Finds sharp corners: points where the contour turns much more than along its sides.
**
** For each point k, the points before and after it are collected until they are `scale`
** away from Q_k (Euclidean distance, so the window does not depend on the density of
** the points nor on noise inflating the chord length); a line is fitted to each side
** (total least squares). Q_k is a corner candidate when
**   - the turn between the two side lines is at least min_angle_deg and at least six
**     times its standard error given sigma;
**   - both sides are straight: their RMS distance to their line is at most 2.5 sigma
**     plus 2% of the scale (a curve that turns steadily is not a corner);
**   - the two lines explain the window much better than a parabola in the frame of the
**     window's chord: the parabola's residual sum of squares exceeds the lines' by 25
**     sigma^2 and is at least twice theirs (a tight smooth bend follows a parabola);
**   - the turn measured with half the scale is at least 75% of it (a corner turns as
**     much at any scale, a bend in proportion to the scale);
**   - the lines of the two sides' outer halves (from scale/2 on: the tangents of a
**     rounded bend, where the whole sides would give secants) meet near the data: within
**     3 sigma + half the local spacing + 2% of the scale of Q_k (a rounded fillet's
**     tangent lines meet far from the arc).
** Of neighbouring candidates, the one nearest to where its side lines meet is kept. The automatic scale is
** max(40 sigma, 4 median spacings), capped at a tenth of the bounding-box diagonal.
**
** Limits: with noise sigma, a smooth bend whose radius of curvature is below about 20
** sigma is not told apart from a corner; pass a smaller `scale` to resolve finer detail.
** Cost: O(m * w), w the number of points within `scale` of a point.
**
** @param[out] corners the corners in increasing `index`; at most `cap` are written. A
**                     corner between two samples keeps its true place in `position` and
**                     `point`. Positions follow the order of the indices, so for closed
**                     data the first may wrap to just below m.
** @param[out] count   the number of corners found (may exceed cap: then retry larger).
** @return BSFIT_OK, or the errors of bsfit_noise_sigma. */
BSFIT_API bsfit_err bsfit_corners_detect(const double *pts, size_t m, int dim,
                                         const bsfit_corner_opts *opts, bsfit_corner *corners,
                                         size_t cap, size_t *count, bsfit_status *st);

/** Parameters that down-weighted points cannot distort.
**
** A point is trusted when its weight is at least `trust` times the median weight (so at
** least half the points always are: the median resists a few huge weights). The
** parameters (kind as in bsfit_params) are computed over the trusted points only, so an
** outlier does not stretch the chords of its neighbours; an untrusted point gets the
** parameter interpolated linearly, by index, between its trusted neighbours. With w
** NULL (or every point trusted) the result equals bsfit_params. Closed data: the
** result is shifted so that ū_0 = 0 and it stays non-decreasing in [0, 1).
**
** @param[in]  w      m positive weights, or NULL.
** @param[in]  trust  fraction of the median weight, in [0, 1) (0: every point trusted).
** @param[out] u      m parameters.
** @return BSFIT_OK, the codes of bsfit_params, BSFIT_EWEIGHT (a weight <= 0 or not
**         finite), BSFIT_EINVAL (trust out of range), BSFIT_EDEGENERATE (fewer than
**         two trusted points), BSFIT_ENOMEM. */
BSFIT_API bsfit_err bsfit_params_trusted(const double *pts, size_t m, int dim,
                                         bsfit_param_kind kind, int closed, const double *w,
                                         double trust, double *u, bsfit_status *st);

/** Makes parameters agree with corners that lie between samples.
**
** Chord-like parameters measure the chord Q_j Q_{j+1} across a corner, which cuts it:
** the two straight sides then disagree on the corner's parameter by the cut. For each
** corner with a fractional position j + f (f > 0), the parameter step from j to j+1 is
** stretched to the path through the corner point (|Q_j X| + |X Q_{j+1}| for chord
** parameters, the sum of square roots for centripetal; uniform parameters are left
** alone), the later parameters move up, and all are rescaled to [0, 1] (open) or
** [0, 1) with u[0] = 0 (closed). The corner's parameter is then the interpolation at
** its position (as bsfit_knots_place_breaks does). The corners must be in increasing
** position; m, dim and closed as for bsfit_params.
** @return BSFIT_OK, BSFIT_EINVAL (position out of range or decreasing, kind unknown). */
BSFIT_API bsfit_err bsfit_params_through_corners(const double *pts, size_t m, int dim,
                                                 bsfit_param_kind kind, int closed,
                                                 const bsfit_corner *corners, size_t nc,
                                                 double *u, bsfit_status *st);

/** One period of knots for a closed fit with C0 breaks (corners).
**
** The parameters u (closed, non-decreasing in [0, 1), as from bsfit_params) are cut at
** the corners `breaks`: increasing fractional point indices in [0, m) (an integer is a
** point; k + f lies between points k and k+1, its parameter interpolated, as
** bsfit_corners_detect's positions). The period starts at the first corner's parameter; each corner becomes a knot of multiplicity p (the curve may turn
** sharply there), and the remaining knots are spread over the pieces between corners in
** proportion to their number of points, by the averaging rule within each piece. A
** guard then merges knots until every non-empty span holds at least two parameters
** (taken modulo the period), so no span is ever empty. With no breaks this is periodic
** averaging with the same guard.
**
** @param[in]  n_target wanted number of distinct control points N (>= p+1).
** @param[out] period   up to n_target+1 knots t_0 <= ... <= t_N = t_0 + 1.
** @param[out] n_out    the N actually placed (<= n_target; fewer when the guard merged).
** @return BSFIT_OK, BSFIT_EDEGREE (p out of 1..BSFIT_MAX_DEGREE), BSFIT_EINVAL (breaks
**         not increasing or out of range, u not in [0,1) non-decreasing, n_target too
**         small for the breaks: N >= nb*p + 1 and N >= p+1), BSFIT_ETOOFEW (too few
**         points for even the smallest knot vector), BSFIT_ENOMEM. */
BSFIT_API bsfit_err bsfit_knots_place_breaks(const double *u, size_t m, int p, size_t n_target,
                                             const double *breaks, size_t nb, double *period,
                                             size_t *n_out, bsfit_status *st);

#endif /* BSFIT_ANALYSIS_H */
