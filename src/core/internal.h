/*
** internal.h
** Helpers shared by the files of src/core; not part of the public API.
*/
#ifndef BSFIT_INTERNAL_H
#define BSFIT_INTERNAL_H

#include "../bsfit.h"

#include <float.h>
#include <math.h>
#include <stddef.h>

#if defined(__GNUC__)
#  define BSFIT_PRINTF(a, b) __attribute__((format(printf, a, b)))
#else
#  define BSFIT_PRINTF(a, b)
#endif

/* Records code and a formatted message in st (when not NULL); returns code. */
bsfit_err bsfit__fail(bsfit_status *st, bsfit_err code, const char *fmt, ...) BSFIT_PRINTF(3, 4);

/* Marks st as successful; returns BSFIT_OK. */
bsfit_err bsfit__ok(bsfit_status *st);

/* Allocation through an optional allocator (NULL or NULL fn = realloc/free).
** bsfit__alloc returns NULL for nsize == 0 or on failure. */
void *bsfit__alloc(const bsfit_allocator *a, size_t nsize);
void *bsfit__realloc(const bsfit_allocator *a, void *p, size_t osize, size_t nsize);
void bsfit__free(const bsfit_allocator *a, void *p, size_t osize);

/* Non-zero when the host asked the computation running with allocator a to stop.
** Cheap: call it every few thousand iterations of a long loop, return BSFIT_EINTR. */
static inline int bsfit__interrupted(const bsfit_allocator *a) {
  return a != NULL && a->interrupt != NULL && *a->interrupt != 0;
}

/* How far two spans of a periodic knot vector with period [a, b] may differ and still
** repeat: the rounding of adding the period (a few ulps of the knots' magnitude) plus a
** relative slack of the period. Never 1e-12 of the magnitude: knots near 4e11 spaced by 3
** would then pass with spans 0.9 apart. */
static inline double bsfit__periodic_span_tol(double a, double b) {
  return 64.0 * DBL_EPSILON * (fabs(a) + fabs(b)) + 1e-12 * (b - a);
}

/* n*size without overflow; 0 on overflow (callers treat 0 as an error). */
size_t bsfit__mulsize(size_t n, size_t size);

/* Non-zero when every one of the n doubles is finite. */
int bsfit__all_finite(const double *x, size_t n);

/* Index of the first of the n doubles with |x| > BSFIT_COORD_MAX or NaN, or n if none. */
size_t bsfit__first_out_of_range(const double *x, size_t n);

/* curve.c: u wrapped into one period (periodic curves only; others unchanged) */
double bsfit__curve_wrap(const bsfit_curve *c, double u);
/* curve.c: non-zero when an open curve may be evaluated at u: within one domain length
** of the domain (extrapolation by the end polynomials loses its digits, then overflows,
** farther out: the basis divides sums like (U - u) + (u - U')); periodic curves: any
** finite u. */
int bsfit__curve_reach(const bsfit_curve *c, double u);
/* curve.c: C(u) for a valid curve and finite u, no checks */
void bsfit__curve_eval_unchecked(const bsfit_curve *c, double u, double *out);

/* noise.c: k-th smallest of x[0..n-1], reordering x (selection, O(n) expected) */
double bsfit__select(double *x, size_t n, size_t k);

/* small_spd.c: tiny dense SPD systems (n <= BSFIT__SMALL), lower Cholesky in place.
** bsfit__small_cholesky returns 0 when A is not numerically SPD (a pivot below 1e-13
** of the trace). */
#define BSFIT__SMALL 5
int bsfit__small_cholesky(int n, double A[BSFIT__SMALL][BSFIT__SMALL]);
void bsfit__small_chol_solve(int n, const double L[BSFIT__SMALL][BSFIT__SMALL], double *b);

#endif
