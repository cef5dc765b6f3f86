/*
** filter_internal.h
** What filter.c and filter_exact.c share: splines as raw arrays of any dimension (a
** surface is filtered as a curve whose "points" are whole rows of its control net),
** and the one-dimensional filters on them. Not part of the public API.
*/
#ifndef BSFIT_FILTER_INTERNAL_H
#define BSFIT_FILTER_INTERNAL_H

#include "internal.h"

/* A borrowed spline: degree p, n control points of d doubles each (row-major),
** n+p+1 knots. d may exceed 4. */
typedef struct bsfit__fview {
  int p;
  size_t n, d;
  const double *U;
  const double *P;
} bsfit__fview;

/* An owned spline with the same layout; U holds exactly n+p+1 doubles and P exactly
** n*d, so both can be handed to a bsfit_curve allocated with the same allocator. */
typedef struct bsfit__fspline {
  int p;
  size_t n, d;
  double *U;
  double *P;
} bsfit__fspline;

void bsfit__fspline_free(const bsfit_allocator *a, bsfit__fspline *f);
bsfit_err bsfit__fspline_alloc(const bsfit_allocator *a, bsfit__fspline *f, int p, size_t n,
                               size_t d, bsfit_status *st);

/* Non-zero when all nk knots are equally spaced (relative tolerance 1e-8). */
int bsfit__knots_equal_spans(const double *U, size_t nk);

/* Moving average of an open uniform spline (end rule V^0 / V^{n-1}); 1 <= k. */
bsfit_err bsfit__filter_ma_open(const bsfit__fview *in, int k, const bsfit_allocator *a,
                                bsfit__fspline *out, bsfit_status *st);

/* Cyclic moving average of a periodic uniform spline in expanded form (N = in->n - p
** distinct points); 1 <= k <= N. The result is in expanded form too. */
bsfit_err bsfit__filter_ma_periodic(const bsfit__fview *in, int k, const bsfit_allocator *a,
                                    bsfit__fspline *out, bsfit_status *st);

/* Exact box filter of half-width delta > 0 of an open spline with any knots. */
bsfit_err bsfit__filter_exact_open(const bsfit__fview *in, double delta,
                                   const bsfit_allocator *a, bsfit__fspline *out,
                                   bsfit_status *st);

/* Exact box filter of a periodic spline in expanded form; 0 < 2 delta <= period. */
bsfit_err bsfit__filter_exact_periodic(const bsfit__fview *in, double delta,
                                       const bsfit_allocator *a, bsfit__fspline *out,
                                       bsfit_status *st);

/* {====================================================================
** Kernel filters, degree reduction, smoothing (filter_kernel.c, filter_reduce.c,
** filter_distance.c, filter_smooth.c)
** ===================================================================== */

/* Break points x[0] < ... < x[n-1] of a target spline and the multiplicity of each as a
** knot (the ends of an open target are clamped whatever their mult). */
typedef struct bsfit__breaks {
  double *x;
  int *mult;
  size_t n, cap;
} bsfit__breaks;

void bsfit__breaks_free(const bsfit_allocator *a, bsfit__breaks *b);
bsfit_err bsfit__breaks_reserve(const bsfit_allocator *a, bsfit__breaks *b, size_t cap);

/* L2 projection of the spline in (or of the rational curve `rational`, then in only
** gives its knots) onto degree q on the break points b: clamped, or periodic in expanded
** form. */
bsfit_err bsfit__project(const bsfit__fview *in, const bsfit_curve *rational, int periodic,
                         int q, const bsfit__breaks *b, const bsfit_allocator *al,
                         bsfit__fspline *out, bsfit_status *st);

/* f's arrays handed to a validated curve moved into out (f is emptied either way). */
bsfit_err bsfit__fspline_to_curve(bsfit__fspline *f, int dim, int periodic,
                                  const bsfit_allocator *a, bsfit_curve *out, bsfit_status *st);

/* Modes of bsfit__curve_distance: Newton from the same parameter only (an upper bound,
** for searches); the global closest point too, the largest distances refined, for
** curves that correspond parameter by parameter; the same, each refined maximum checked
** by a global closest point (any two curves). */
enum { BSFIT__DIST_LOCAL = 1, BSFIT__DIST_CORRESPONDING = 2, BSFIT__DIST_VERIFIED = 3 };

/* The distance between curves s and c (filter_distance.c): per_span samples per knot span
** of each projected onto the other, by `mode`. span_max (br->n - 1 values, or NULL)
** receives the largest distance attributed to each break span of s. */
bsfit_err bsfit__curve_distance(const bsfit_curve *s, const bsfit_curve *c, size_t per_span,
                                int mode, const bsfit__breaks *br, double *span_max,
                                const bsfit_allocator *al, double *out, bsfit_status *st);

typedef struct bsfit__reduce_arg {
  int degree;
  double tol;
  size_t per_span, max_added;
  int local;
  const bsfit_curve *measure; /* the curve the deviation is measured to (NULL: the input) */
} bsfit__reduce_arg;

/* Projection of c on b, knots added in the middle of every span farther than tol from
** the measured curve, until none is. res (initialised) receives the last projection,
** also on error; b grows with the knots added. */
bsfit_err bsfit__reduce_loop(const bsfit_curve *c, const bsfit__reduce_arg *r, bsfit__breaks *b,
                             const bsfit_allocator *al, bsfit_curve *res,
                             bsfit_reduce_report *rep, bsfit_status *st);

/* }==================================================================== */

#endif
