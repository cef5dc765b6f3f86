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

#endif
