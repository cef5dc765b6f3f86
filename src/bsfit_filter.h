/*
** bsfit_filter.h
** Smoothing by box filtering of splines (Persiano, docs/filtering.md), and the shape
** measures that show what a smoothing did (total turning, bending energy, deviation).
** Included by bsfit.h; include bsfit.h rather than this file.
**
** The box filter of width 2*delta maps a curve C to
**     C_F(t) = 1/(2 delta) * integral of C_ext(u) du over [t - delta, t + delta],
** a spline of one degree more. The parameter t is the original curve's parameter: no
** reparametrisation happens.
**
** Ends of open curves (decision). C_ext is C "extended by its end control points",
** the paper's end rule V^i = V^0 before the first control point and V^i = V^{n-1} after
** the last one. For any knot vector this extension is
**     C_ext(u) = V^0 + sum_{i=1..n-1} (V^i - V^{i-1}) H_i(u),
** where H_i rises from 0 to 1 over [U_i, U_{i+p}]: it equals C on the domain [U_p, U_n],
** it is the constant V^0 for u <= U_1 and V^{n-1} for u >= U_{n+p-1}, and it does not
** depend on the knots U_0 and U_{n+p}. For a clamped curve (U_1 = ... = U_p) it is
** exactly "C extended as a constant beyond its ends"; for a uniform unclamped curve
** it is what the paper's moving average filters.
** The filtered open curve is returned over the whole interval where it is not
** constant, [L - delta, R + delta], with L = U_1 and R = U_{n+p-1} (degree 0:
** L = U_0, R = U_n). It starts at V^0 and ends at V^{n-1}; for a clamped curve the
** domain is [a - delta, b + delta] and the ends are C(a) and C(b).
**
** Closed (periodic) curves need no end rule: the filtered curve is periodic with the
** same period; its period starts at the first knot of the filtered knot vector at or
** after the original domain's start a (so at a, or a + spacing/2 for odd k).
**
** "Uniform" (the moving-average functions) means every knot span is equal, with a
** relative tolerance of 1e-8: an unclamped uniform knot vector, or the expanded knots
** of a closed curve with equal spans. A clamped curve is not uniform in this sense
** (its end spans are empty): filter it with the _delta functions, which are exact for
** any knot vector and any delta > 0.
**
** Rational curves and surfaces are rejected (the average of a rational curve is not a
** rational spline of the same kind). Output objects use the input's allocator; the
** output may be the input object itself (it is replaced only on success).
*/
#ifndef BSFIT_FILTER_H
#define BSFIT_FILTER_H

#include "bsfit.h"

/* {====================================================================
** Curves
** ===================================================================== */

/** Non-zero when every knot span of c is equal (relative tolerance 1e-8), the
** condition of bsfit_filter_box_curve. NULL or empty curves give 0. */
BSFIT_API int bsfit_curve_is_uniform(const bsfit_curve *c);

/** Box filter of width k knot spans (2 delta = k * spacing) of a uniform curve, by the
** paper's moving average: V_F^i = (1/k) sum_{j=i-k+1..i} V^j, with the end rule for
** open curves and cyclically for closed ones; O(n + k) whatever k.
** Open result: degree p+1, n + 2p + k - 1 control points (degree 0: n + k + 1), the
** original uniform knots shifted by -delta, domain [U_1 - delta, U_{n+p-1} + delta]
** (see the file comment). Closed result: degree p+1, N distinct control points,
** periodic (docs/method.md §1 expanded form).
** @param[in]  c    a valid polynomial curve whose knot spans are all equal.
** @param[in]  k    window width in knot spans, 1 <= k <= number of domain spans
**                  (n - p for an open curve, N for a closed one).
** @param[out] out  receives the filtered curve (freed first; may be c itself). The
**                  caller releases it with bsfit_curve_free.
** @return BSFIT_OK; BSFIT_EINVAL (c NULL or empty, rational, k < 1, k wider than the
**         curve, or knots not uniform: the message points to
**         bsfit_filter_box_curve_delta); BSFIT_EDEGREE (p + 1 > BSFIT_MAX_DEGREE);
**         any code of bsfit_curve_validate; BSFIT_ENOMEM. On error out is unchanged. */
BSFIT_API bsfit_err bsfit_filter_box_curve(const bsfit_curve *c, int k, bsfit_curve *out,
                                           bsfit_status *st);

/** The exact filter's smallest half-width, relative to the length of the (unwrapped)
** domain: below it the difference of antiderivatives keeps fewer than ~9 digits. */
#define BSFIT_FILTER_MIN_DELTA (1.0 / 16777216.0)

/** Exact box filter of half-width delta of any polynomial curve (clamped, unclamped,
** non-uniform, closed), by the antiderivative spline I (degree p+1, control points
** J^i = sum_{j<i} Q^j (u_{j+p+1} - u_j)/(p+1)) and C_F(t) = (I(t+delta) - I(t-delta))/(2 delta),
** both shifted copies brought to one knot vector by knot refinement (NURBS Book A5.4).
** Result: degree p+1 on the knots {u_i +- delta} (knots closer than about 1e-14 of
** the curve's extent are merged, never two knots of one shifted copy, nor u - delta with
** u + delta). Open curves: clamped result over
** [L - delta, R + delta] (file comment). Closed curves: periodic result.
** For a uniform curve and delta = k * spacing / 2 it is the same curve (as a function
** of t) as bsfit_filter_box_curve's.
** @param[in]  c      a valid polynomial curve.
** @param[in]  delta  half-width of the window, finite, > 0, 2 delta <= the domain
**                    length (open) or the period (closed).
** @param[out] out    receives the filtered curve (freed first; may be c itself).
** @return BSFIT_OK; BSFIT_ENONFINITE (delta NaN or infinite); BSFIT_EINVAL (c NULL or
**         empty, rational, delta <= 0, window wider than the curve); BSFIT_EMULT (an
**         open curve with U_1 = ... = U_{p+1} or U_{n-1} = ... = U_{n+p-1}: its end
**         control point is not used by the curve, so the end rule would jump);
**         BSFIT_EDEGREE (p + 1 > BSFIT_MAX_DEGREE); BSFIT_ENOTPERIODIC (a closed
**         result with too few knots per period for the expanded form); BSFIT_EDOMAIN
**         (delta below BSFIT_FILTER_MIN_DELTA times the domain length, plus 2^20 ulps
**         of the knots; a closed curve is unwrapped over 2M+1 periods, M = 3 +
**         (p+1)/N, and that length counts); any code of
**         bsfit_curve_validate; BSFIT_ENOMEM. On error out is unchanged. */
BSFIT_API bsfit_err bsfit_filter_box_curve_delta(const bsfit_curve *c, double delta,
                                                 bsfit_curve *out, bsfit_status *st);

/* }==================================================================== */

/* {====================================================================
** Tensor-product surfaces (separable: one pass along u, one along v)
** ===================================================================== */

/** Box filter over a k x l window of knot spans of a surface whose u and v knot
** vectors are both uniform: V_F^{ij} = 1/(kl) sum_{r=i-k+1..i} sum_{s=j-l+1..j} V^{rs},
** with the end rule in both directions. Result: degrees (pu+1, pv+1), each direction
** shaped as an open curve's (bsfit_filter_box_curve).
** @param[in]  s     a valid polynomial surface, uniform knots in u and v.
** @param[in]  k, l  window widths in knot spans, 1 <= k <= nu - pu, 1 <= l <= nv - pv.
** @param[out] out   receives the filtered surface (freed first; may be s itself). The
**                   caller releases it with bsfit_surface_free.
** @return BSFIT_OK; BSFIT_EINVAL (s NULL or empty, rational, closed around u (periodic_u),
**         k or l out of range, knots not uniform); BSFIT_EDEGREE; any code of
**         bsfit_surface_validate; BSFIT_ENOMEM. On error out is unchanged. */
BSFIT_API bsfit_err bsfit_filter_box_surface(const bsfit_surface *s, int k, int l,
                                             bsfit_surface *out, bsfit_status *st);

/** Exact box filter over a 2 delta_u x 2 delta_v window of any polynomial surface
** (each direction as bsfit_filter_box_curve_delta on an open curve).
** @return BSFIT_OK; BSFIT_ENONFINITE; BSFIT_EINVAL (s NULL or empty, rational,
**         periodic_u, a delta <= 0 or wider than the domain); BSFIT_EMULT; BSFIT_EDEGREE;
**         any code of bsfit_surface_validate; BSFIT_ENOMEM. On error out is unchanged. */
BSFIT_API bsfit_err bsfit_filter_box_surface_delta(const bsfit_surface *s, double delta_u,
                                                   double delta_v, bsfit_surface *out,
                                                   bsfit_status *st);

/* }==================================================================== */

/* {====================================================================
** Shape measures, by sampling (no allocation)
** The curve is sampled at `samples` parameters equally spaced over its domain, ends
** included for open curves; a closed curve is sampled over one period and the
** sampled polygon is closed.
** ===================================================================== */

/** Total absolute turning: the sum of the angles between consecutive chords of the
** sampled polygon, which tends to the integral of |curvature| ds (plus the turn at
** every corner) as samples grows. A full circle gives 2 pi. Zero-length chords are
** skipped.
** @param[in]  c        a valid curve of dimension 2..4.
** @param[in]  samples  >= 3.
** @param[out] out      the turning, in radians.
** @return BSFIT_OK, BSFIT_EINVAL (c or out NULL, c empty, samples < 3), BSFIT_EDIM
**         (dimension 1), or a code of bsfit_curve_validate. */
BSFIT_API bsfit_err bsfit_curve_total_turning(const bsfit_curve *c, size_t samples,
                                              double *out, bsfit_status *st);

/** Bending energy, the integral of curvature^2 ds, from the sampled polygon: each
** interior vertex i with turning angle theta_i and half its two chords l_i contributes
** theta_i^2 / l_i (curvature theta_i / l_i over a length l_i). A circle of radius r
** gives 2 pi / r; corners make it grow without bound as samples grows.
** @return as bsfit_curve_total_turning. */
BSFIT_API bsfit_err bsfit_curve_bending_energy(const bsfit_curve *c, size_t samples,
                                               double *out, bsfit_status *st);

/** Maximum parametric deviation max_t |A(t) - B(t)| over `samples` parameters equally
** spaced over the intersection of the two domains (ends included): an upper bound of
** the distance from each sampled point of A to the curve B. For a filtered curve this
** is the displacement the smoothing caused at each parameter.
** @param[in]  samples  >= 2.
** @return BSFIT_OK, BSFIT_EINVAL (NULL or empty curve, samples < 2), BSFIT_EDIM (the
**         dimensions differ), BSFIT_EDOMAIN (the domains do not overlap), or a code
**         of bsfit_curve_validate. */
BSFIT_API bsfit_err bsfit_curve_max_deviation(const bsfit_curve *a, const bsfit_curve *b,
                                              size_t samples, double *out,
                                              bsfit_status *st);

/* }==================================================================== */

/* {====================================================================
** Kernel filters (r box passes), reduction to a chosen degree, smoothing to a
** tolerance (docs/filtering.md)
** ===================================================================== */

/** Kernel filter of order r: r passes of the box filter of half-width delta, which is
** the convolution of C_ext (the curve extended by its end control points, see the file
** comment) with the cardinal B-spline kernel of degree r - 1, support [-r delta, r delta].
** This function is the uniform-knot form: each pass is the moving average of k control
** points (2 delta = k * spacing), so the control points get the r-fold moving average,
** B-spline-weighted. Result: degree p + r; open curves over [L - r delta, R + r delta],
** closed curves periodic. Cost O(r (n + k)).
** @param[in]  c      a valid polynomial curve whose knot spans are all equal.
** @param[in]  order  r >= 1, p + r <= BSFIT_MAX_DEGREE.
** @param[in]  k      window of each pass in knot spans, as bsfit_filter_box_curve.
** @param[out] out    the filtered curve (freed first; may be c itself).
** @return BSFIT_OK; BSFIT_EINVAL (order < 1, and every error of bsfit_filter_box_curve);
**         BSFIT_EDEGREE (p + r too high); BSFIT_EINTR; BSFIT_ENOMEM. On error out is
**         unchanged. */
BSFIT_API bsfit_err bsfit_filter_kernel_curve(const bsfit_curve *c, int order, int k,
                                              bsfit_curve *out, bsfit_status *st);

/** Kernel filter of order r and half-width delta (each pass as
** bsfit_filter_box_curve_delta) of any polynomial curve: open, closed, non-uniform.
** @return as bsfit_filter_kernel_curve, with the errors of bsfit_filter_box_curve_delta. */
BSFIT_API bsfit_err bsfit_filter_kernel_curve_delta(const bsfit_curve *c, int order,
                                                    double delta, bsfit_curve *out,
                                                    bsfit_status *st);

/** Kernel filters of a surface: order_u passes along u and order_v along v of the box
** filter over k (resp. l) knot spans (uniform knots in both directions). Degrees
** (pu + order_u, pv + order_v).
** @return BSFIT_OK; BSFIT_EINVAL (an order < 1, and the errors of
**         bsfit_filter_box_surface); BSFIT_EDEGREE; BSFIT_EINTR; BSFIT_ENOMEM. */
BSFIT_API bsfit_err bsfit_filter_kernel_surface(const bsfit_surface *s, int order_u,
                                                int order_v, int k, int l,
                                                bsfit_surface *out, bsfit_status *st);

/** Kernel filters of any polynomial surface, half-widths delta_u and delta_v.
** @return as bsfit_filter_kernel_surface, with the errors of
**         bsfit_filter_box_surface_delta. */
BSFIT_API bsfit_err bsfit_filter_kernel_surface_delta(const bsfit_surface *s, int order_u,
                                                      int order_v, double delta_u,
                                                      double delta_v, bsfit_surface *out,
                                                      bsfit_status *st);

/** Options of bsfit_filter_reduce_curve. Zero-initialise, then set what you need. */
typedef struct bsfit_reduce_opts {
  int degree;           /**< q >= 1; 0 means 3 */
  double tol;           /**< > 0; INFINITY: the projection on the break points, no knot added */
  const double *breaks; /**< break points of the result, strictly increasing from the curve's
                             domain start to its end; NULL: the curve's distinct knots */
  size_t nbreaks;
  size_t max_added;     /**< knots that may be added; 0: 10 per break point + 100 */
  size_t samples;       /**< deviation: samples per knot span of each curve; 0: 16 */
} bsfit_reduce_opts;

typedef struct bsfit_reduce_report {
  double max_deviation; /**< distance between result and input: samples of each projected on
                             the other (feet by Newton from the same parameter, the largest
                             refined between samples; global closest points when the bound
                             below does not already meet tol) */
  size_t knots_added;
  int rounds;           /**< projections computed */
  double bound;         /**< certified upper bound of the distance, max_t |result(t) - c(t)|
                             (Bernstein coefficients of the difference per span); INFINITY
                             when the degrees pass 12 */
} bsfit_reduce_report;

/** The best approximation of c of degree q in least squares over the whole domain: the
** L2 projection onto the splines of degree q on the break points, as smooth at each
** break as c is there (at most C^{q-1}), clamped (open c) or periodic (closed c). Exact
** Gauss-Legendre quadrature per span, banded Cholesky (closed: the periodic fitter's
** cyclic elimination), O(n q^2). The distance to c is first bounded (certified, O(n):
** max_t |result(t) - c(t)| from the Bernstein coefficients of the difference per piece),
** measured only where the bound misses tol; while it exceeds tol, a knot is added in the
** middle of every span where it does and the projection repeated. A curve that
** already is of degree <= q on those break points is reproduced. Rational c: projected
** through more quadrature nodes than a polynomial needs (the integrand is not a
** polynomial), so the projection is approximate but the deviation reported is measured.
** @param[out] out  the result (freed first; may be c itself).
** @param[out] rep  the distance measured and the knots added, or NULL.
** @return BSFIT_OK; BSFIT_EDEGREE (q out of 1..BSFIT_MAX_DEGREE); BSFIT_ENONFINITE (tol
**         NaN); BSFIT_EINVAL (NULL argument, tol <= 0, bad break points); BSFIT_ETOOFEW
**         (too few break points for degree q); BSFIT_ENOCONV (tol not met within
**         max_added knots); BSFIT_ENOTSPD; BSFIT_EINTR; BSFIT_ENOMEM; any code of
**         bsfit_curve_validate. On error out is unchanged. */
BSFIT_API bsfit_err bsfit_filter_reduce_curve(const bsfit_curve *c, const bsfit_reduce_opts *o,
                                              bsfit_curve *out, bsfit_reduce_report *rep,
                                              bsfit_status *st);

/** Options of bsfit_filter_reduce_surface. Zero-initialise, then set what you need. */
typedef struct bsfit_reduce_surface_opts {
  int degree_u, degree_v; /**< 1..12 each; 0 means 3 */
  double tol;             /**< > 0; INFINITY: one projection on the surface's break points */
  size_t max_added;       /**< knots that may be added (both directions); 0: 10 per break point
                               + 100 */
} bsfit_reduce_surface_opts;

/** The best approximation of a polynomial surface by degrees (qu, qv) in least squares over
** its whole domain: the tensor-product L2 projection on its own break points in each
** direction, as smooth there as s is (at most C^{q-1}), clamped, or periodic in u when s is
** closed around u (periodic_u). Computed as the curve projection of
** bsfit_filter_reduce_curve along u on whole rows of the net, then along v (the tensor
** Gram matrix is the Kronecker product of the two): banded solves only. The distance to s
** is bounded (certified) by max |R(u,v) - s(u,v)| from the Bernstein coefficients of the
** difference on every patch (a bound of the true distance, not the distance itself); while
** it exceeds tol, a knot is added in the middle of every u span and every v span holding a
** patch beyond tol, and the projection repeated. A surface that already is of degrees
** <= (qu, qv) on those break points is reproduced.
** @param[out] out  the result (freed first; may be s itself).
** @param[out] rep  max_deviation and bound: the certified bound; knots_added: u and v
**                  together; rounds. Or NULL.
** @return BSFIT_OK; BSFIT_EDEGREE (a degree of the result or of s outside 1..12);
**         BSFIT_ENONFINITE (tol NaN); BSFIT_EINVAL (NULL argument, rational s, tol <= 0);
**         BSFIT_ETOOFEW; BSFIT_ENOCONV (tol not met within max_added knots); BSFIT_ENOTSPD;
**         BSFIT_EINTR; BSFIT_ENOMEM; any code of bsfit_surface_validate. On error out is
**         unchanged. */
BSFIT_API bsfit_err bsfit_filter_reduce_surface(const bsfit_surface *s,
                                                const bsfit_reduce_surface_opts *o,
                                                bsfit_surface *out, bsfit_reduce_report *rep,
                                                bsfit_status *st);

/** Distance between two curves as point sets: samples (per_span per knot span of each
** curve, ends included) projected on the other curve by bsfit_curve_closest_many, the
** largest distance either way (the Hausdorff distance, up to what lies between samples).
** @return BSFIT_OK; BSFIT_EINVAL (NULL, per_span < 1); BSFIT_EDIM; BSFIT_ENOMEM; any code
**         of bsfit_curve_validate. */
BSFIT_API bsfit_err bsfit_curve_distance(const bsfit_curve *a, const bsfit_curve *b,
                                         size_t per_span, double *out, bsfit_status *st);

/** Options of bsfit_filter_smooth_curve. Zero-initialise, then set tol. */
typedef struct bsfit_smooth_opts {
  double tol;  /**< the largest distance allowed between result and input, finite, > 0 */
  int degree;  /**< degree of the result, >= 1; 0 means 3 */
  int order;   /**< kernel order; 0: searched over 1..4 */
} bsfit_smooth_opts;

typedef struct bsfit_smooth_report {
  int changed;          /**< 0: no filter kept the curve within tol and smoother; out is c at
                             the degree asked */
  int order;            /**< kernel order chosen (0 when unchanged) */
  double delta;         /**< half-width of each pass (0 when unchanged) */
  double max_deviation; /**< true distance between result and input (bsfit_curve_distance) */
  size_t knots_added;   /**< knots the reduction added to meet tol */
  double turning_before, turning_after; /**< bsfit_curve_total_turning */
  double energy_before, energy_after;   /**< bsfit_curve_bending_energy */
  int evaluations;      /**< filters tried by the search */
  double bound;         /**< certified upper bound of the distance the result was checked
                             against (<= tol when changed): curves, max_t |result(t) - c(t)|;
                             surfaces, max |result(u,v) - s(u,v)| */
} bsfit_smooth_report;

/** The smoothest curve of degree q within tol of c that kernel filtering gives: for each
** order (given, or 1..3) the widest half-width whose filtered curve, projected on degree q
** on c's break points, has a certified distance bound (max_t |R(t) - c(t)| from the
** Bernstein coefficients of the difference per piece) within tol; the order whose result
** has the least bending energy wins, and its distance to c is measured. Where the bound
** is far above that distance (motion along the curve: open ends, corners) the orders are
** searched again by the measured distance (global closest points). A projection that
** ripples is redone with knots added (docs/filtering.md). A result less than 1% smoother
** than c is not taken. Open results keep c's domain [a, b] (the filter's widened ends are
** not projected), closed ones its period.
** @param[in]  c    a valid polynomial curve of dimension 2..4.
** @param[out] out  the result (freed first; may be c itself).
** @param[out] rep  what was done, or NULL.
** @return BSFIT_OK; BSFIT_EINVAL (NULL, rational, tol <= 0, order out of range);
**         BSFIT_ENONFINITE (tol NaN or infinite); BSFIT_EDIM; BSFIT_EDEGREE; the errors of
**         bsfit_filter_reduce_curve; BSFIT_EINTR; BSFIT_ENOMEM. On error out is unchanged. */
BSFIT_API bsfit_err bsfit_filter_smooth_curve(const bsfit_curve *c, const bsfit_smooth_opts *o,
                                              bsfit_curve *out, bsfit_smooth_report *rep,
                                              bsfit_status *st);

/** Smoothing of a surface to a tolerance (docs/filtering.md): kernel filters of one order
** in both directions (given, or 1..4), half-widths proportional to the mean knot spacing
** of each direction, the widest within tol; each result projected (L2, tensor product) on
** degree q in both directions on the surface's own break points; the order with the least
** thin-plate energy (the sampled integral of |S_uu|^2 + 2 |S_uv|^2 + |S_vv|^2 over the
** parameter domain) wins. The distance is a certified upper bound, max |R(u,v) - s(u,v)|
** from the Bernstein coefficients of the difference on every patch (every point of either
** surface lies that close to the other): not the distance itself, at least it. No knots
** are added. The result keeps the domain of s. Report: changed, order, delta (the u
** half-width; along v it is in the same proportion to the v spacing), max_deviation and
** bound (the bound), energy_before/after (thin plate), evaluations; turning is 0. When
** nothing smoother is within tol, out is a copy of s and changed is 0.
** @return BSFIT_OK; BSFIT_EINVAL (NULL, rational, closed around u, tol <= 0, order out of
**         range); BSFIT_ENONFINITE (tol); BSFIT_EDEGREE (degrees of s or q above 12);
**         BSFIT_EINTR; BSFIT_ENOMEM. */
BSFIT_API bsfit_err bsfit_filter_smooth_surface(const bsfit_surface *s,
                                                const bsfit_smooth_opts *o, bsfit_surface *out,
                                                bsfit_smooth_report *rep, bsfit_status *st);

/* }==================================================================== */

#endif /* BSFIT_FILTER_H */
