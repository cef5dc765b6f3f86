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
** Each point is predicted from its neighbours (leave-one-out) by a polynomial in the
** normal coordinate(s) of a local frame (origin at the point, first axis along the
** chord of the window), and its prediction error is divided by sqrt(1 + variance
** factor of the prediction), which makes it an unbiased sample of the noise whatever
** the spacing. The window is the first, in this order, whose fit of the other samples
** is as good as the noise allows (its residual per degree of freedom at most about the
** 95% point of chi^2, against a pilot scale from the centred windows): a cubic on 9
** samples centred on the point, a quartic on 7, a parabola on 5 (a sparse contour that
** bends fast, which the longer ones cannot follow), a cubic on the 8 samples before
** or after the point (a point next to a corner); failing all, the best fitting one.
** The point itself takes no part in the choice, so the choice does not favour small
** errors. The scale is the 40% quantile of the errors' magnitudes divided by that of
** the noise distribution (half-normal in 2D: 0.5244; chi with 2 degrees of freedom in
** 3D: 1.0108), refined by the mean square of the errors below 2.5 (3D: 3) times it,
** corrected for the cut: corners and outliers, which inflate the upper errors, do not
** bias it, and it is about as precise as a plain RMS.
**
** Limits: on a contour sampled so sparsely that a bend of radius R holds fewer than
** about 3 samples (e.g. 5-lobed stars with 100-150 samples), the fits cannot follow
** the bends and the estimate is high by 10-30% at noise 1e-4 of the size (less at
** larger noise).
**
** @param[in]  pts    m points, dim doubles each (dim 2 or 3).
** @param[in]  closed non-zero: the windows wrap around.
** @param[out] sigma  the estimate (0 for data exactly on a smooth curve or a line).
** @param[in]  a      allocator of the scratch (2m doubles) and the interrupt flag,
**                    looked at every 4096 points; NULL = realloc, never interrupted.
** @return BSFIT_OK, BSFIT_EDIM, BSFIT_ETOOFEW (m < 6), BSFIT_ENONFINITE,
**         BSFIT_EDEGENERATE (no window with distinct points), BSFIT_ENOMEM, BSFIT_EINTR. */
BSFIT_API bsfit_err bsfit_noise_sigma(const double *pts, size_t m, int dim, int closed,
                                      double *sigma, const bsfit_allocator *a,
                                      bsfit_status *st);

/** Options of bsfit_corners_detect. Zero-initialise, then set what you need. */
typedef struct bsfit_corner_opts {
  int closed;            /**< the contour is closed */
  double sigma;          /**< noise level; <= 0: estimated with bsfit_noise_sigma */
  double min_angle_deg;  /**< smallest turn that can be a corner; 0: 30 degrees */
  double scale;          /**< length of each side window; 0: automatic (see below) */
} bsfit_corner_opts;

/** A corner found by bsfit_corners_detect. */
typedef struct bsfit_corner {
  size_t index;      /**< the sample nearest to the corner (position rounded) */
  double angle;      /**< the turn between the two sides, degrees */
  double position;   /**< where the corner lies along the samples: a fractional index j + f
                          (f in [0, 1)) between samples j and j+1, f the share of the path
                          Q_j -> point -> Q_{j+1} before the corner point; in [0, m) */
  double point[3];   /**< the corner itself: where the sides meet (dim coordinates) */
} bsfit_corner;

/** Finds sharp corners: points where the contour turns much more than along its sides.
**
** For each point k, the points before and after it are collected until they are `scale`
** away from Q_k (Euclidean distance, so the window does not depend on the density of
** the points nor on noise inflating the chord length); a line is fitted to each side
** (total least squares). Only the points where a quick version of the first two tests
** passes and whose turn is the largest within a quarter of their window (and their
** neighbours) are examined. Q_k is a corner when
**   - the turn between the two side lines is at least min_angle_deg and at least six
**     times its standard error given sigma;
**   - both sides are straight: their RMS distance to their line is at most 2.5 sigma
**     plus 2% of the scale (a curve that turns steadily is not a corner);
**   - the lines of the two sides' outer halves (from scale/2 on: the tangents of a
**     rounded bend, where the whole sides would give secants) meet near the data: within
**     three standard errors of their meeting point (as the lines are known from noisy
**     samples), plus how far curved sides bend away from their lines, plus 0.5% of the
**     scale, of the polygon edges at Q_k (less what an edge across a corner cuts off
**     it). A rounded fillet's tangent lines meet far from the arc;
**   - the polygon turns at the corner's samples, not at the two beyond them on each
**     side (by three standard errors plus a fifth of the turn): a tight smooth bend that
**     sparse samples show as a few large turns is not a corner;
**   - the turn is a slope jump: with each side grown (by steps, up to 4 times the
**     scale) as long as it stays straight to the noise, two parabolas meeting anywhere
**     (a corner with curved sides) explain the sides better by at least 25 sigma^2 (or
**     25 times their own misfit per point, on clean data) than one cubic whose third
**     derivative may jump at the corner, in the frame of the two side directions: the
**     curvature of that cubic can peak at the corner and fall off along both sides, as
**     the curvature of a tight smooth bend does, but its slope cannot jump;
**   - the turn measured with half the scale is at least 75% of it (a corner turns as
**     much at any scale, a bend in proportion to the scale).
** Of neighbouring candidates, the one nearest to where its sides meet is kept. The
** corner point is where the sides' parabolas meet (for a turn above 120 degrees, a
** spike, no further out along its axis than the furthest sample, unless the side lines
** put it beyond by more than three standard errors: exact sides meet at their tip). Its
** position along the samples is the split of the samples between the two side lines that
** fits them best (of the splits within 4 sigma^2 of the best, the middle one); for a spike
** held back, the mean index of the samples within 2 sigma of the furthest out along its
** axis. The
** automatic scale is max(40 sigma, 4 median spacings), capped at a tenth of the
** bounding-box diagonal.
**
** Limits: with noise sigma, a smooth bend whose radius of curvature is below about 20
** sigma is not told apart from a corner (a 5-lobed star with valleys of radius 4-14
** sigma, or an airfoil's leading edge of radius 1.6 sigma, may get corners there); a
** right-angled corner with fewer than about 10 samples on its shorter side at noise
** 1% of the size may be missed (its slope jump then explains the data by about 20
** sigma^2, as much as a smooth bend's can). Pass a smaller `scale` to resolve finer
** detail. Cost: O(m) for the quick test, O(w) per examined point, w the points within
** 4 scales of it.
**
** @param[out] corners the corners in increasing `index`; at most `cap` are written. A
**                     corner between two samples keeps its true place in `position` and
**                     `point`. Positions follow the order of the indices, so for closed
**                     data the first may wrap to just below m.
** @param[out] count   the number of corners found (may exceed cap: then retry larger).
** @param[in] a       scratch memory (O(m)) comes from it (NULL: realloc); its interrupt
**                     flag stops the scans (BSFIT_EINTR).
** @return BSFIT_OK, BSFIT_ENOMEM, BSFIT_EINTR, or the errors of bsfit_noise_sigma. */
BSFIT_API bsfit_err bsfit_corners_detect(const double *pts, size_t m, int dim,
                                         const bsfit_corner_opts *opts, bsfit_corner *corners,
                                         size_t cap, size_t *count, const bsfit_allocator *a,
                                         bsfit_status *st);

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
** @param[in]  a      allocator of the scratch (about m (dim + 3) doubles); NULL = realloc.
** @return BSFIT_OK, the codes of bsfit_params, BSFIT_EWEIGHT (a weight <= 0 or not
**         finite), BSFIT_EINVAL (trust out of range), BSFIT_EDEGENERATE (fewer than
**         two trusted points), BSFIT_ENOMEM. */
BSFIT_API bsfit_err bsfit_params_trusted(const double *pts, size_t m, int dim,
                                         bsfit_param_kind kind, int closed, const double *w,
                                         double trust, double *u, const bsfit_allocator *a,
                                         bsfit_status *st);

/** The points that are not trusted: weight below `trust` times the median weight (the
** rule of bsfit_params_trusted).
**
** @param[in]  w      m positive, finite weights.
** @param[in]  trust  fraction of the median weight, in [0, 1) (0: every point trusted).
** @param[out] out    the 0-based indices of the untrusted points, increasing (room for m).
** @param[out] n_out  how many there are (0 when every point is trusted).
** @param[in]  a      allocator of the scratch (m doubles, only when the weights differ by
**                    more than the factor trust); NULL = realloc.
** @return BSFIT_OK, BSFIT_EWEIGHT (a weight <= 0 or not finite), BSFIT_EINVAL (trust out of
**         range, NULL arguments), BSFIT_ENOMEM. O(m). */
BSFIT_API bsfit_err bsfit_untrusted(const double *w, size_t m, double trust, size_t *out,
                                    size_t *n_out, const bsfit_allocator *a, bsfit_status *st);

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
** @param[in]  a        allocator of the scratch (O(n_target + nb)); NULL = realloc.
** @return BSFIT_OK, BSFIT_EDEGREE (p out of 1..BSFIT_MAX_DEGREE), BSFIT_EINVAL (breaks
**         not increasing or out of range, u not in [0,1) non-decreasing, n_target too
**         small for the breaks: N >= nb*p + 1 and N >= p+1), BSFIT_ETOOFEW (too few
**         points for even the smallest knot vector), BSFIT_ENOMEM. */
BSFIT_API bsfit_err bsfit_knots_place_breaks(const double *u, size_t m, int p, size_t n_target,
                                             const double *breaks, size_t nb, double *period,
                                             size_t *n_out, const bsfit_allocator *a,
                                             bsfit_status *st);

#endif /* BSFIT_ANALYSIS_H */
