/*
** filter_testutil.h
** Helpers of the filter tests (test_filter.c, test_filter_kernel.c, test_filter_surface.c):
** the error check, curves as functions (the curve, its constant extension), the end rule
** built by definition, random control points. Include after cmocka.h and testutil.h.
*/
#ifndef BSFIT_FILTER_TESTUTIL_H
#define BSFIT_FILTER_TESTUTIL_H

#include <stdlib.h>
#include <string.h>

#include "bsfit.h"
#include "testutil.h"

/* A vector-valued function of one parameter (dim <= 4 values into out). */
typedef void (*vec_fn)(const void *ctx, double u, double *out);

static inline void expect_error(bsfit_err got, bsfit_err want, const bsfit_status *st) {
  assert_int_equal(got, want);
  assert_int_equal(st->code, want);
  assert_true(strlen(st->msg) > 0);
}

static inline void curve_fn(const void *ctx, double u, double *out) {
  bsfit_status st;
  assert_int_equal(bsfit_curve_eval((const bsfit_curve *)ctx, u, out, &st), BSFIT_OK);
}

/* C(u) clamped to the domain: the constant extension of a clamped curve */
static inline void clamped_fn(const void *ctx, double u, double *out) {
  const bsfit_curve *c = ctx;
  double a, b;
  bsfit_curve_domain(c, &a, &b);
  curve_fn(ctx, u < a ? a : (u > b ? b : u), out);
}

static inline void random_points(test_rng *r, size_t n, int dim, double *P) {
  size_t i;
  for (i = 0; i < n * (size_t)dim; i++) P[i] = rng_range(r, -1.0, 1.0);
}

/* The end rule by definition: K copies of V^0 before, K of V^{n-1} after, on knots
** extended with spacing h (any positive spacing gives the same curve). */
static inline void pad_curve(const bsfit_curve *c, size_t K, double h, bsfit_curve *out) {
  size_t p = (size_t)c->degree, n = c->n, d = (size_t)c->dim, nk = n + p + 1, i;
  double *U = malloc((nk + 2 * K) * sizeof(double)), *P = malloc((n + 2 * K) * d * sizeof(double));
  bsfit_status st;
  assert_non_null(U);
  assert_non_null(P);
  for (i = 0; i < nk + 2 * K; i++) {
    if (i < K) U[i] = c->knots[0] - (double)(K - i) * h;
    else if (i < K + nk) U[i] = c->knots[i - K];
    else U[i] = c->knots[nk - 1] + (double)(i - K - nk + 1) * h;
  }
  for (i = 0; i < n + 2 * K; i++) {
    size_t j = i < K ? 0 : (i - K >= n ? n - 1 : i - K);
    memcpy(P + i * d, c->ctrl + j * d, d * sizeof(double));
  }
  bsfit_curve_init(out);
  assert_int_equal(bsfit_curve_new(out, c->degree, c->dim, n + 2 * K, U, P, NULL, 0, NULL, &st),
                   BSFIT_OK);
  free(U);
  free(P);
}

#endif
