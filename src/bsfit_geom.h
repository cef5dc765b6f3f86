/*
** bsfit_geom.h
** Geometry kernels on point sequences used by the fitting strategies (docs/method.md §7-10):
** circumradius weights, turning angles, curvature inversions, local spacing, and
** the line projection of the tangent correction.
** Included by bsfit.h; include bsfit.h rather than this file.
**
** Conventions shared by every kernel on a point sequence:
** - `pts` holds m points of `dim` coordinates (dim = 2 or 3), row-major
**   [x0,y0,(z0,)x1,y1,...], ordered along the contour. Closed sections do not
**   repeat the first point at the end.
** - `closed` != 0: the sequence is cyclic (Q_{-1} = Q_{m-1}, Q_m = Q_0).
**   closed == 0: an open polyline; a per-point quantity that needs both neighbours
**   is given at the two ends the value of the nearest full triple (documented per
**   function).
** - The output array (m values) is written only on success and must not overlap pts.
** - No kernel allocates memory: each works in O(m) time on the output array.
** - Common return codes: BSFIT_EINVAL (a NULL array), BSFIT_EDIM (dim not 2 or 3),
**   BSFIT_ETOOFEW (m < 3), BSFIT_ENONFINITE (a NaN or infinite coordinate); the
**   message names the argument or the first bad point.
** - A triple (A, B, C) is collinear when twice its area is at most 1e-12 times the
**   square of its longest side; coincident points count as collinear (docs/method.md §7).
*/
#ifndef BSFIT_GEOM_H
#define BSFIT_GEOM_H

#include "bsfit.h"

/** Relative threshold of the collinearity test (twice the area over the squared
** longest side). */
#define BSFIT_GEOM_COLLINEAR_EPS 1e-12

/** Radius of the circle through three consecutive points, per point (docs/method.md §7; the
** circle lies in the plane of the three points in 3D).
** @param[in]  pts       m points (see the conventions above).
** @param[in]  closed    non-zero for a cyclic sequence.
** @param[in]  centered  non-zero: r[k] comes from the triple (Q_{k-1}, Q_k, Q_{k+1});
**                       zero: from the paper's triple (Q_k, Q_{k+1}, Q_{k+2}).
**                       Open data: indices that would leave 0..m-1 take the nearest
**                       full triple instead (centred: r[0] = r[1], r[m-1] = r[m-2];
**                       paper's: r[m-2] = r[m-1] = the radius of (Q_{m-3}, Q_{m-2}, Q_{m-1})).
** @param[out] r         m radii; +INFINITY for a collinear triple.
** @return BSFIT_OK or a common code. */
BSFIT_API bsfit_err bsfit_geom_circumradius(const double *pts, size_t m, int dim, int closed,
                                            int centered, double *r, bsfit_status *st);

/** Per-point weights from the circumradius (docs/method.md §7, P-14, P-15): with the radii of
** bsfit_geom_circumradius, r_max = mean + population standard deviation of the finite
** radii; w_k = r_max / r_k when r_k <= r_max; points with r_k > r_max or r_k = +Inf
** (straight runs) get w_max = max of those w_k = r_max / min_k r_k. So tight corners
** and straight runs both pull the curve hardest.
** Edge cases: when no radius is finite (every triple collinear) every weight is 1;
** when all finite radii are equal (a regular polygon) every weight is 1.
** Every weight is finite and >= 1.
** @param[out] w  m weights.
** @return BSFIT_OK or a common code. */
BSFIT_API bsfit_err bsfit_weights_circumradius(const double *pts, size_t m, int dim, int closed,
                                               int centered, double *w, bsfit_status *st);

/** Interior angle at each point, in degrees (docs/method.md §8): the angle of the triangle
** (Q_k, Q_{k+1}, Q_{k+2}) at Q_{k+1}, stored as ang[k+1] (the angle belongs to the
** middle point). 180 means collinear (a straight run), small values sharp spikes.
** A point that coincides with one of its neighbours gets 180 (no direction change
** can be measured). Closed data: m angles, cyclic. Open data: the ends take the
** angle of their neighbour (ang[0] = ang[1], ang[m-1] = ang[m-2]).
** @param[out] ang  m angles in [0, 180].
** @return BSFIT_OK or a common code. */
BSFIT_API bsfit_err bsfit_geom_angles(const double *pts, size_t m, int dim, int closed,
                                      double *ang, bsfit_status *st);

/** Number of curvature inversions of the polygon (docs/method.md §9-10): the sign changes of the
** turn direction along the sequence. The turn at Q_k is the cross product of the
** edges Q_k - Q_{k-1} and Q_{k+1} - Q_k: its sign in 2D; in 3D two turns have the
** same direction when their cross products have a positive dot product. Collinear
** vertices (zero turns, same test as above) are skipped. Closed data: vertices
** 0..m-1, cyclic, so the last turn is compared with the first too (in 2D the count
** is then even: a convex polygon gives 0, a star with s spikes 2s). Open data:
** vertices 1..m-2.
** @param[out] count  the number of sign changes.
** @return BSFIT_OK or a common code. */
BSFIT_API bsfit_err bsfit_geom_inflections(const double *pts, size_t m, int dim, int closed,
                                           size_t *count, bsfit_status *st);

/** Weights growing with the turning angle: with turn_k = 180 - ang_k (degrees, from
** bsfit_geom_angles, so the same end rule for open data), w_k = 1 + |turn_k| / mean|turn|.
** Straight runs get 1, sharp corners the most; the mean weight is 2. When every turn
** is zero (all collinear) every weight is 1.
** @param[out] w  m weights, each finite and >= 1.
** @return BSFIT_OK or a common code. */
BSFIT_API bsfit_err bsfit_weights_turning(const double *pts, size_t m, int dim, int closed,
                                          double *w, bsfit_status *st);

/** Weights proportional to the local spacing, so that dense clusters of points do not
** dominate the fit: s_k = (|Q_k - Q_{k-1}| + |Q_{k+1} - Q_k|) / 2, w_k = s_k / mean(s)
** (the mean weight is 1). Open data: an end has one chord, which stands for both
** (s_0 = |Q_1 - Q_0|). A point that coincides with both neighbours would get 0, which
** fitters reject, so weights are floored at 1e-3 (BSFIT_GEOM_SPACING_FLOOR). When all
** points coincide every weight is 1.
** @param[out] w  m weights, each finite and >= 1e-3.
** @return BSFIT_OK or a common code. */
BSFIT_API bsfit_err bsfit_weights_spacing(const double *pts, size_t m, int dim, int closed,
                                          double *w, bsfit_status *st);

/** Smallest weight bsfit_weights_spacing returns. */
#define BSFIT_GEOM_SPACING_FLOOR 1e-3

/** The longest step between consecutive points (for closed data the step from the last
** point back to the first too): how far the data leave a stretch unsampled.
** @param[out] h  the longest step (0 when all points coincide).
** @return BSFIT_OK or a common code. */
BSFIT_API bsfit_err bsfit_geom_longest_step(const double *pts, size_t m, int dim, int closed,
                                            double *h, bsfit_status *st);

/** Orthogonal projection of P onto the line origin + t dir (the tangent correction,
** docs/method.md §9-10: control points P_1, P_2 moved onto the tangent line through Q_0).
** @param[in]  P, origin, dir  dim doubles each; dir need not be normalised.
** @param[in]  dim             2 or 3.
** @param[out] out             dim doubles; may be the same array as P.
** @return BSFIT_OK, BSFIT_EINVAL (a NULL pointer), BSFIT_EDIM, BSFIT_ENONFINITE (an input
**         is not finite) or BSFIT_EDEGENERATE (dir is zero: no line). */
BSFIT_API bsfit_err bsfit_geom_tangent_project(const double *P, const double *origin,
                                               const double *dir, int dim, double *out,
                                               bsfit_status *st);

/** Distance of P from the line origin + t dir (docs/method.md §8: dt_1, dt_2 of the start-point
** search).
** @param[out] d  the distance, >= 0.
** @return as bsfit_geom_tangent_project. */
BSFIT_API bsfit_err bsfit_geom_line_distance(const double *P, const double *origin,
                                             const double *dir, int dim, double *d,
                                             bsfit_status *st);

#endif /* BSFIT_GEOM_H */
