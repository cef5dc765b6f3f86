/*
** bsfit_filter.h
** Smoothing by box filtering of splines (Persiano, SPEC section 3), and the shape
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
** periodic (SPEC 1.3 expanded form).
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
**         k or l out of range, knots not uniform); BSFIT_EDEGREE; any code of bsfit_surface_validate;
**         BSFIT_ENOMEM. On error out is unchanged. */
BSFIT_API bsfit_err bsfit_filter_box_surface(const bsfit_surface *s, int k, int l,
                                             bsfit_surface *out, bsfit_status *st);

/** Exact box filter over a 2 delta_u x 2 delta_v window of any polynomial surface
** (each direction as bsfit_filter_box_curve_delta on an open curve).
** @return BSFIT_OK; BSFIT_ENONFINITE; BSFIT_EINVAL (s NULL or empty, rational,
**         periodic_u, a delta <= 0 or wider than the domain); BSFIT_EMULT; BSFIT_EDEGREE; any code of
**         bsfit_surface_validate; BSFIT_ENOMEM. On error out is unchanged. */
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

#endif /* BSFIT_FILTER_H */
