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
** an unbiased sample of the noise whatever the spacing. The scale is the median of the
** standardised residual magnitudes divided by the median of the noise-free distribution
** (half-normal in 2D: 0.6745; Rayleigh-like chi with 2 degrees of freedom in 3D: 1.1774),
** so corners and outliers do not bias it.
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
** @param[out] idx    indices of the corners, increasing; at most `cap` are written.
** @param[out] angles the turn (degrees) at each corner, or NULL.
** @param[out] count  the number of corners found (may exceed cap: then retry larger).
** @return BSFIT_OK, or the errors of bsfit_noise_sigma. */
BSFIT_API bsfit_err bsfit_corners_detect(const double *pts, size_t m, int dim,
                                         const bsfit_corner_opts *opts, size_t *idx,
                                         double *angles, size_t cap, size_t *count,
                                         bsfit_status *st);

#endif /* BSFIT_ANALYSIS_H */
