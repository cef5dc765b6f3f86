/*
** bsfit_curve_ops.h
** Curve operations: derivatives, batch evaluation, knot insertion, splitting, reversal,
** degree elevation, arc length, closest point, sampling.
** Included by bsfit.h; include bsfit.h rather than this file.
**
** Common rules of this header:
** - `c` must be a valid curve (built by the bsfit_curve_new* functions, or checked with
**   bsfit_curve_validate). A NULL or empty curve gives BSFIT_EINVAL.
** - Operations that build a curve write it into `out`, which must be initialised
**   (bsfit_curve_init) or hold a curve; its previous content is freed on success and
**   left untouched on error. `out` may be the same object as `c`. The result uses c's
**   allocator and belongs to the caller (release it with bsfit_curve_free).
** - Rational curves (weights != NULL) are processed in homogeneous coordinates
**   (w x, w y, ..., w), so every operation is exact for NURBS as well.
** - Bézier curves are clamped single-span B-splines for these operations; a result that
**   is still one span (reversal, elevation, splitting) keeps the `bezier` flag, one with
**   more spans (knot insertion) is an ordinary B-spline.
*/
#ifndef BSFIT_CURVE_OPS_H
#define BSFIT_CURVE_OPS_H

#include "bsfit.h"

/* {====================================================================
** Evaluation
** ===================================================================== */

/** Derivatives of orders 0..k at u (NURBS Book A3.2; rational curves by A4.2 on the
** homogeneous derivatives). Orders above the degree are 0 for polynomial curves; a
** rational curve's are computed exactly from the lower ones. u outside the domain:
** extrapolated by the end polynomials (open curves) or wrapped (periodic curves); at an
** interior knot the derivatives are those of the span on the right (at b: the left).
** @param[in]  k    highest order, >= 0 (any value: no internal limit).
** @param[out] out  (k+1)*dim doubles: C(u), C'(u), ..., C^(k)(u), each dim coordinates.
** @return BSFIT_OK, BSFIT_EINVAL (empty curve, k < 0, out NULL), BSFIT_EDIM,
**         BSFIT_EDEGREE, BSFIT_ENONFINITE (u NaN or infinite), BSFIT_ERANGE (a derivative
**         overflows: high orders over tiny knot spans, or u extrapolated far out). */
BSFIT_API bsfit_err bsfit_curve_derivs(const bsfit_curve *c, double u, int k, double *out,
                                       bsfit_status *st);

/** C(u[i]) for i = 0..m-1, the same values as bsfit_curve_eval (up to rounding).
** Sorted parameters are fastest (the span is found by stepping from the previous one);
** any order works (binary search otherwise). Periodic curves wrap u into the period.
** @param[in]  u    m parameters.
** @param[out] out  m*dim doubles, row-major. On BSFIT_ENONFINITE the points before the
**                  bad parameter are written, the others are unspecified.
** @return BSFIT_OK, BSFIT_EINVAL (empty curve, u or out NULL with m > 0), BSFIT_EDIM,
**         BSFIT_EDEGREE, BSFIT_ENONFINITE (a parameter is NaN or infinite), BSFIT_EDOMAIN
**         (as bsfit_curve_eval, checked before any point is written), BSFIT_ERANGE (an
**         extrapolated point overflows). */
BSFIT_API bsfit_err bsfit_curve_eval_many(const bsfit_curve *c, const double *u, size_t m,
                                          double *out, bsfit_status *st);

/* }==================================================================== */

/* {====================================================================
** Knot insertion and refinement
** ===================================================================== */

/** Inserts the knot u `times` times (Boehm's algorithm, done as a refinement by
** NURBS Book A5.4). The curve is unchanged as a point set and parametrisation.
**
** Multiplicity after insertion may not exceed p, or p+1 at the domain ends a, b of an
** open curve. Periodic curves stay periodic: u is wrapped into the period [a, b) and the
** knot is inserted at every periodic image, so the result has N+times distinct control
** points and keeps the expanded form of docs/method.md §1.
**
** @param[in]  c      the curve.
** @param[in]  u      the knot; open curves need a <= u <= b.
** @param[in]  times  how many copies to insert, >= 0 (0 copies c).
** @param[out] out    the refined curve (may be c).
** @return BSFIT_OK, BSFIT_EINVAL (empty curve, times < 0), BSFIT_ENONFINITE (u NaN or
**         infinite), BSFIT_EDOMAIN (u outside [a, b] of an open curve), BSFIT_EMULT
**         (multiplicity would exceed the limit), BSFIT_ENOMEM. */
BSFIT_API bsfit_err bsfit_curve_insert_knot(const bsfit_curve *c, double u, int times,
                                            bsfit_curve *out, bsfit_status *st);

/** Knot refinement (NURBS Book A5.4): inserts all the knots of X at once.
** @param[in]  X   nx knots, non-decreasing, within [a, b] (periodic curves: within
**                 [a, b], wrapped into [a, b) and inserted at every periodic image; the
**                 wrapped list need not be sorted). A value may repeat.
** @param[in]  nx  number of knots (0 copies c; X may then be NULL).
** @param[out] out the refined curve (may be c), n+nx control points (periodic: N+nx
**                 distinct ones).
** @return BSFIT_OK, BSFIT_EINVAL (empty curve, X NULL with nx > 0), BSFIT_ENONFINITE,
**         BSFIT_EKNOTS_DECR (X decreases), BSFIT_EDOMAIN (a knot outside [a, b]),
**         BSFIT_EMULT (a multiplicity above p, or p+1 at the ends of an open curve),
**         BSFIT_ENOMEM. */
BSFIT_API bsfit_err bsfit_curve_refine(const bsfit_curve *c, const double *X, size_t nx,
                                       bsfit_curve *out, bsfit_status *st);

/* }==================================================================== */

/* {====================================================================
** Splitting, reversal, degree elevation
** ===================================================================== */

/** Splits an open curve at u into two clamped curves: `left` over [a, u] and `right`
** over [u, b], each with its own knots (u inserted to multiplicity p). An open curve
** with unclamped ends comes back clamped at a and b as well (same points on the domain).
** Bézier curves give two Bézier curves.
**
** A periodic curve is cut open at u (wrapped into [a, b)): `left` receives ONE open
** clamped curve over [u, u + (b - a)] that starts and ends at C(u) (its first and last
** control points are equal); `right` may be NULL and, if not, is emptied.
**
** @param[out] left, right  the pieces; either may be c itself, but not each other.
** @return BSFIT_OK, BSFIT_EINVAL (empty curve, left NULL or equal to right, right NULL
**         for an open curve), BSFIT_ENONFINITE (u), BSFIT_EDOMAIN (open curve and u not
**         strictly inside (a, b)), any code of bsfit_curve_validate, BSFIT_ENOMEM. */
BSFIT_API bsfit_err bsfit_curve_split(const bsfit_curve *c, double u, bsfit_curve *left,
                                      bsfit_curve *right, bsfit_status *st);

/** Reverses the direction: knots U'[i] = a + b - U[last-i], control points (and weights)
** in reverse order, so that out(t) = c(a + b - t) on the same domain [a, b]. Keeps the
** periodic and Bézier flags.
** @param[out] out the reversed curve (may be c).
** @return BSFIT_OK, BSFIT_EINVAL (empty curve, out NULL), any code of
**         bsfit_curve_validate, BSFIT_ENOMEM. */
BSFIT_API bsfit_err bsfit_curve_reverse(const bsfit_curve *c, bsfit_curve *out,
                                        bsfit_status *st);

/** Degree elevation by t: the same curve (points and parametrisation) of degree p+t.
** Bézier curves use the Bézier formula and stay Bézier. B-splines use NURBS Book A5.9:
** every distinct knot gains exactly t copies (the ends p+t+1), so the continuity at each
** knot is kept. An open curve with unclamped ends comes back clamped (same points on the
** domain). Periodic curves stay periodic: N distinct control points become N + t*D,
** D the number of distinct knots in one period.
** @param[in]  t    elevation, >= 0 (0 copies c), p + t <= BSFIT_MAX_DEGREE.
** @param[out] out  the elevated curve (may be c).
** @return BSFIT_OK, BSFIT_EINVAL (empty curve, out NULL, t < 0), BSFIT_EDEGREE (p + t too
**         high), BSFIT_EMULT (a B-spline with an interior knot of multiplicity > p, i.e. a
**         discontinuous curve, including any interior knot of a degree-0 spline), any code
**         of bsfit_curve_validate, BSFIT_ENOMEM. */
BSFIT_API bsfit_err bsfit_curve_elevate(const bsfit_curve *c, int t, bsfit_curve *out,
                                        bsfit_status *st);

/* }==================================================================== */

/* {====================================================================
** Geometry: arc length, closest point, sampling
** ===================================================================== */

/** Arc length of c over [a, b] (within the domain): 16-point Gauss-Legendre per knot
** span, each span halved until two estimates agree to a relative 1e-12 (at most 2^12
** pieces per span, so a cusp ends with the best estimate rather than an error).
** @param[out] len  the length (0 when a == b).
** @return BSFIT_OK, BSFIT_EINVAL (empty curve, len NULL), BSFIT_ENONFINITE (a or b),
**         BSFIT_EDOMAIN (a > b, or [a, b] not inside the domain), any code of
**         bsfit_curve_validate. */
BSFIT_API bsfit_err bsfit_curve_length(const bsfit_curve *c, double a, double b, double *len,
                                       bsfit_status *st);

/** Closest point of the curve to P: the global minimum of the distance, to within 1e-9
** of it plus 1e-13 of the control points' extent. 8 samples per span and a safeguarded
** Newton descent on f(u) = C'(u).(C(u) - P) from the best, then a global stage: each span
** as a Bezier piece, ruled out by the Bernstein coefficients of its squared distance or
** searched (a strip tree over the spans: O(log n) pieces for a point near the curve).
** @param[in]  P     dim coordinates.
** @param[out] u     the foot's parameter, in [a, b] ([a, b) for periodic curves).
** @param[out] dist  |C(u) - P|, or NULL.
** @param[in]  a     allocator of the scratch (the span polynomials of a cubic, 4 dim + 1
**                   per control point; the Bezier pieces and their tree); NULL = realloc.
** @return BSFIT_OK, BSFIT_EINVAL (empty curve, P or u NULL), BSFIT_ENONFINITE (P),
**         BSFIT_ERANGE (control points all within 1e-100 of each other but not equal:
**         the squared distances would underflow), BSFIT_ENOMEM, any code of
**         bsfit_curve_validate. */
BSFIT_API bsfit_err bsfit_curve_closest(const bsfit_curve *c, const double *P, double *u,
                                        double *dist, const bsfit_allocator *a,
                                        bsfit_status *st);

/** bsfit_curve_closest for many points at once: the coarse samples (8 per knot span) are
** evaluated once, then each point is bracketed by its nearest sample, refined by Newton and
** proved by the global stage, exactly as bsfit_curve_closest does (same results).
** @param[in]  pts  m points, dim doubles each.
** @param[out] u    m parameters of the closest points.
** @param[out] dist m distances, or NULL.
** Cost: K = 8 (spans) + 1 samples, indexed once by a k-d tree (O(K log K)), then about
** O(log K) per point near the curve to find its nearest sample (a plain scan for small K
** or few points), plus Newton per point.
** @param[in]  a    allocator of the scratch (samples, search tree, span polynomials) and
**                  the interrupt flag, looked at every 4096 points; NULL = realloc.
** @return BSFIT_OK, the codes of bsfit_curve_validate, BSFIT_EINVAL (NULL arrays),
**         BSFIT_ENONFINITE (a point not finite), BSFIT_ERANGE (as bsfit_curve_closest),
**         BSFIT_ENOMEM, BSFIT_EINTR (the entries before the one interrupted are done). */
BSFIT_API bsfit_err bsfit_curve_closest_many(const bsfit_curve *c, const double *pts, size_t m,
                                             double *u, double *dist, const bsfit_allocator *a,
                                             bsfit_status *st);

/** Projects many points, each from its own starting parameter (the fitter's parameter
** correction): up to `iters` safeguarded Newton steps on f(u) = C'(u).(C(u) - P), a step
** being halved until the distance does not grow, so a foot is never farther than its
** start. Open curves clamp u to [a, b]; periodic curves search one period either side of
** the start and wrap the result into [a, b). No global search: see bsfit_curve_closest.
** @param[in]     pts   m*dim coordinates, row-major.
** @param[in,out] u     m parameters: starting values in, feet out.
** @param[out]    dist  m distances |C(u_i) - P_i|, or NULL.
** @param[in]     iters Newton steps per point, >= 0 (0: only clamp/wrap and measure).
** @param[in]     a     allocator of the scratch (span polynomials of a cubic) and the
**                      interrupt flag, looked at every 4096 points; NULL = realloc.
** @return BSFIT_OK, BSFIT_EINVAL (empty curve, pts or u NULL with m > 0, iters < 0),
**         BSFIT_EDIM, BSFIT_EDEGREE, BSFIT_ENONFINITE (a point or start; checked before
**         any is moved), BSFIT_ERANGE (as bsfit_curve_closest), BSFIT_EINTR (the entries
**         before the one interrupted are done). */
BSFIT_API bsfit_err bsfit_curve_project_many(const bsfit_curve *c, const double *pts, size_t m,
                                             double *u, double *dist, int iters,
                                             const bsfit_allocator *a, bsfit_status *st);

/** k equally spaced samples: open curves at a + (b-a) i/(k-1), i = 0..k-1 (both ends
** included); periodic curves at a + (b-a) i/k, i = 0..k-1 (the period [a, b), as C(b) =
** C(a) would repeat the first point).
** @param[out] out  k*dim doubles, row-major.
** @param[in]  a    carries the interrupt flag, looked at every 4096 samples (no
**                  allocation); NULL = never interrupted.
** @return BSFIT_OK, BSFIT_EINVAL (empty curve, k < 2, out NULL), BSFIT_EDIM,
**         BSFIT_EDEGREE, BSFIT_EINTR. */
BSFIT_API bsfit_err bsfit_curve_sample(const bsfit_curve *c, size_t k, double *out,
                                       const bsfit_allocator *a, bsfit_status *st);

/* }==================================================================== */

#endif /* BSFIT_CURVE_OPS_H */
