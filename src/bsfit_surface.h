/*
** bsfit_surface.h
** Tensor-product B-spline / NURBS / Bézier surfaces.
** Included by bsfit.h; include bsfit.h rather than this file.
*/
#ifndef BSFIT_SURFACE_H
#define BSFIT_SURFACE_H

#include "bsfit.h"

/** A tensor-product surface S(u,v) = sum_i sum_j V_ij B_i(u) B_j(v) (rational when
** `weights` is not NULL). Control net row-major over (i, j): point (i, j) starts at
** ctrl[(i * nv + j) * dim]; weights[i * nv + j]. Knots: nu+pu+1 in u, nv+pv+1 in v.
** `bezier` surfaces have nu = pu+1, nv = pv+1 and clamped [0,1] knots.
** `periodic_u` surfaces are closed around u (a skinned surface, bsfit_surface_skin) and
** stored in the expanded periodic form of curves: nu = N+pu rows of control points whose
** last pu rows repeat the first pu, and knots_u whose spans repeat with the period; u is
** wrapped into the period [knots_u[pu], knots_u[nu]) by the evaluators. */
typedef struct bsfit_surface {
  int degree_u, degree_v;
  int dim;               /**< 1..4 (3 for ordinary surfaces) */
  int bezier;
  int periodic_u;         /**< expanded periodic form in u (checked by validate) */
  size_t nu, nv;         /**< control points in u and v */
  double *knots_u;       /**< nu + degree_u + 1 */
  double *knots_v;       /**< nv + degree_v + 1 */
  double *ctrl;          /**< nu * nv * dim */
  double *weights;       /**< nu * nv, or NULL */
  bsfit_allocator alloc;
} bsfit_surface;

/** Sets s to the empty surface (safe to free, to pass as an output). */
BSFIT_API void bsfit_surface_init(bsfit_surface *s);

/** Frees what s owns and re-initialises it. NULL-safe, idempotent. */
BSFIT_API void bsfit_surface_free(bsfit_surface *s);

/** Allocates s's arrays for the given shape (contents zero; weights only if rational).
** Any previous content of s is freed first. The caller fills the arrays, then should
** call bsfit_surface_validate. The arrays belong to s and are released by
** bsfit_surface_free with the allocator a (NULL = realloc/free), kept in s->alloc.
** @return BSFIT_OK, BSFIT_EDIM (dim outside 1..4), BSFIT_EDEGREE (a degree outside
**         0..BSFIT_MAX_DEGREE), BSFIT_EINVAL (nu or nv is 0, or the sizes overflow),
**         BSFIT_ENOMEM. */
BSFIT_API bsfit_err bsfit_surface_alloc(bsfit_surface *s, int degree_u, int degree_v, int dim,
                                        size_t nu, size_t nv, int rational,
                                        const bsfit_allocator *a, bsfit_status *st);

/** Builds a B-spline or NURBS surface by copying the arrays (the caller keeps theirs).
** @param[in] knots_u  nu+degree_u+1 knots, or NULL for clamped uniform knots on [0,1].
** @param[in] knots_v  nv+degree_v+1 knots, or NULL likewise.
** @param[in] ctrl     nu*nv*dim coordinates, row-major over (i, j): point (i, j)
**                     starts at ctrl[(i*nv + j)*dim] (i runs along u).
** @param[in] weights  nu*nv positive weights (weights[i*nv + j]), or NULL (polynomial).
** On error s is left empty.
** @return BSFIT_OK, BSFIT_EINVAL (ctrl NULL), any code of bsfit_surface_alloc or
**         bsfit_surface_validate. */
BSFIT_API bsfit_err bsfit_surface_new(bsfit_surface *s, int degree_u, int degree_v, int dim,
                                      size_t nu, size_t nv, const double *knots_u,
                                      const double *knots_v, const double *ctrl,
                                      const double *weights, const bsfit_allocator *a,
                                      bsfit_status *st);

/** Builds a (rational) Bézier surface of degrees (nu-1, nv-1) on [0,1]x[0,1]; the
** arrays are laid out as in bsfit_surface_new. It is evaluated with Bernstein
** polynomials (NURBS Book A1.3, no division).
** @return BSFIT_OK, BSFIT_EDEGREE (nu or nv outside 1..BSFIT_MAX_DEGREE+1), or any
**         code of bsfit_surface_new. */
BSFIT_API bsfit_err bsfit_surface_new_bezier(bsfit_surface *s, int dim, size_t nu, size_t nv,
                                             const double *ctrl, const double *weights,
                                             const bsfit_allocator *a, bsfit_status *st);

/** Checks every invariant of s: both knot vectors (bsfit_knots_validate), finite
** control points, positive finite weights, Bézier shape.
** @return BSFIT_OK, BSFIT_EINVAL (empty surface, or a Bézier surface of the wrong
**         shape), BSFIT_EDIM, BSFIT_EDEGREE, BSFIT_ENKNOTS, BSFIT_EKNOTS_DECR,
**         BSFIT_EMULT, BSFIT_EDOMAIN, BSFIT_ENONFINITE or BSFIT_EWEIGHT. */
BSFIT_API bsfit_err bsfit_surface_validate(const bsfit_surface *s, bsfit_status *st);

/** Deep copy of src into dst (dst's previous content is freed; allocator a, or src's
** if a is NULL). src and dst must differ.
** @return BSFIT_OK, or a code of bsfit_surface_alloc (BSFIT_ENOMEM). */
BSFIT_API bsfit_err bsfit_surface_copy(const bsfit_surface *src, bsfit_surface *dst,
                                       const bsfit_allocator *a, bsfit_status *st);

/** Moves src's arrays into dst (dst freed first), leaving src empty. */
BSFIT_API void bsfit_surface_move(bsfit_surface *src, bsfit_surface *dst);

/** Domain [ua, ub] x [va, vb] of the surface. Any output pointer may be NULL. */
BSFIT_API void bsfit_surface_domain(const bsfit_surface *s, double *ua, double *ub, double *va,
                                    double *vb);

/** Point S(u, v) of a valid surface. (u, v) outside the domain: extrapolated by the
** end polynomials, as curves are, up to one domain length beyond either end.
** @param[out] out dim doubles.
** @return BSFIT_OK, BSFIT_ENONFINITE (u or v not finite), BSFIT_EDOMAIN (farther out than
**         one domain length), BSFIT_ERANGE (the extrapolated point overflows). */
BSFIT_API bsfit_err bsfit_surface_eval(const bsfit_surface *s, double u, double v, double *out,
                                       bsfit_status *st);

/** Partial derivatives up to order k in each direction (NURBS Book A3.6, and A4.4
** for rational surfaces, which is why orders above the degree can be non-zero).
** @param[in]  k   0 <= k <= BSFIT_MAX_DEGREE.
** @param[out] out (k+1)*(k+1)*dim doubles: d^(a+b) S / du^a dv^b starts at
**                 out[(a*(k+1) + b)*dim], for a, b = 0..k (out[0..dim-1] is S(u,v)).
** @return BSFIT_OK, BSFIT_EINVAL (k out of range), BSFIT_ENONFINITE (u, v), BSFIT_EDOMAIN
**         (as bsfit_surface_eval) or BSFIT_ERANGE (a derivative overflows: high orders
**         over tiny knot spans). */
BSFIT_API bsfit_err bsfit_surface_derivs(const bsfit_surface *s, double u, double v, int k,
                                         double *out, bsfit_status *st);

/** Unit normal (dS/du x dS/dv) / |dS/du x dS/dv| of a 3D surface.
** @param[out] out 3 doubles.
** @return BSFIT_OK, BSFIT_EDIM (dim != 3), BSFIT_ENONFINITE (u, v) or
**         BSFIT_EDEGENERATE (the partial derivatives are parallel or zero there, as at
**         the pole of a sphere patch; out is then set to zeros). */
BSFIT_API bsfit_err bsfit_surface_normal(const bsfit_surface *s, double u, double v,
                                         double *out, bsfit_status *st);

/** Samples a ku x kv grid, equally spaced over the domain, ends included:
** u_a = ua + (ub-ua) a/(ku-1), v_b likewise. The spans and the v basis are found once
** per column, and each row contracts the u basis with the control net once, so a
** point costs O(pv+1) instead of O((pu+1)(pv+1)). Scratch memory comes from s->alloc.
** @param[out] out ku*kv*dim doubles, row-major: point (a, b) starts at
**                 out[(a*kv + b)*dim].
** @return BSFIT_OK, BSFIT_EINVAL (ku or kv below 2, or overflow) or BSFIT_ENOMEM. */
BSFIT_API bsfit_err bsfit_surface_sample_grid(const bsfit_surface *s, size_t ku, size_t kv,
                                              double *out, bsfit_status *st);

/* {====================================================================
** Skinning: one surface through closed sections (The NURBS Book 10.3, docs/skinning.md)
** ===================================================================== */

/** Options of bsfit_surface_skin; set them with bsfit_skin_opts_init first. */
typedef struct bsfit_skin_opts {
  int degree_v; /**< degree q across the sections, 1..3 and < K; 0 = min(3, K-1) */
  int align;    /**< non-zero (default): orient the sections alike and line up their seams */
  double tol;   /**< 0 (default): through the sections exactly; > 0: through periodic cubics
                     on one uniform knot vector within tol of them (a light surface) */
} bsfit_skin_opts;

/** What skinning did, in arrays of K entries the caller provides (any may be NULL). */
typedef struct bsfit_skin_report {
  double *v_params;   /**< v of each section: S(u, v_params[k]) traces section k */
  int *reversed;      /**< 1 when section k was reversed to wind like the previous one */
  double *shifts;     /**< the parameter of section k (in its own domain) at the seam u = 0 */
  size_t bad_section; /**< set by the call: the section an error is about, or (size_t)-1 */
  size_t count;       /**< set by the call with tol: the cubics' control points N (0: none
                           within tol, so the surface passes through the sections exactly) */
  double max_deviation; /**< set by the call with tol: the largest distance from a section
                             to its cubic (parametric, so an upper bound); 0 without */
} bsfit_skin_report;

/** Sets the defaults: degree_v = 0 (min(3, K-1)), align = 1, tol = 0. */
BSFIT_API void bsfit_skin_opts_init(bsfit_skin_opts *o);

/** Skins K >= 2 closed sections into one surface, periodic in u (around the sections,
** periodic_u, domain [0, 1)) and clamped in v (across them, domain [0, 1]).
** The sections are reparametrised onto [0, 1), oriented alike and their seams lined up
** (align), elevated to the highest degree p and refined to the union of their knots
** (exact: the same curves), then each column of control points is interpolated by a
** clamped B-spline of degree q at the averaged chord-length parameters v_k. So
** S(u, v_k) is section k for every u: S(u, v_k) = C_k(shift_k + (b_k - a_k) u) for a
** section kept in its direction, C_k(shift_k - (b_k - a_k) u) for a reversed one
** (wrapped into its period [a_k, b_k)).
** The surface has as many u control points as the union of the sections' knots: sections
** fitted with the same knots give N + p, independently fitted ones up to the sum of theirs.
** With o->tol > 0 the aligned sections are first replaced by least-squares periodic cubics
** on one knot vector (uniform, plus C0 knots at the corners at least half the sections
** share), with the smallest count keeping each within tol (N + 3 columns; rep->count,
** rep->max_deviation), unless no count up to 4 times the largest section's does (then
** rep->count = 0 and the surface is the exact one).
** @param[in]  sections  K valid, periodic, polynomial, 3D curves (any degrees >= 1).
** @param[in]  o         options, or NULL for the defaults.
** @param[out] out       the surface (freed first; arrays allocated with a). Empty on error.
** @param[out] rep       optional report (see bsfit_skin_report).
** @param[in]  a         allocator for the surface and the scratch memory (NULL = realloc);
**                       its interrupt flag is looked at once per section and per column.
** @return BSFIT_OK; BSFIT_ETOOFEW (fewer than 2 sections); BSFIT_EDEGREE (degree_v out of
**         range); BSFIT_EINVAL (a NULL, open or rational section, out NULL); BSFIT_EDIM
**         (a section not 3D); BSFIT_EINVAL (tol negative or not finite); a code of
**         bsfit_curve_validate (e.g. BSFIT_ENONFINITE);
**         BSFIT_EDEGENERATE (two consecutive sections coincide, or all); BSFIT_ESINGULAR;
**         BSFIT_EINTR; BSFIT_ENOMEM. rep->bad_section names the section at fault
**         (0-based) when there is one. */
BSFIT_API bsfit_err bsfit_surface_skin(const bsfit_curve *const *sections, size_t K,
                                       const bsfit_skin_opts *o, bsfit_surface *out,
                                       bsfit_skin_report *rep, const bsfit_allocator *a,
                                       bsfit_status *st);

/* }==================================================================== */

#endif /* BSFIT_SURFACE_H */
