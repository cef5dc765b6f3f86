/*
** curve_ops_internal.h
** The working form shared by the curve operations (curve_ops.c, curve_elevate.c,
** curve_eval.c, curve_geom.c): a bare knot vector and control points in homogeneous
** coordinates, so that one algorithm serves polynomial and rational curves alike; and
** the nearest-sample index of the closest-point search (nearest_sample.c).
** Not part of the public API.
*/
#ifndef BSFIT_CURVE_OPS_INTERNAL_H
#define BSFIT_CURVE_OPS_INTERNAL_H

#include "internal.h"

/* A curve reduced to what the knot algorithms touch. */
typedef struct bsfit__hcurve {
  int p;                 /* degree */
  int hd;                /* doubles per control point: dim, or dim+1 when rational */
  size_t n;              /* number of control points */
  double *U;             /* n+p+1 knots */
  double *P;             /* n*hd coordinates; rational: (w x, w y, ..., w) */
  bsfit_allocator alloc; /* what U and P were allocated with */
} bsfit__hcurve;

void bsfit__hc_init(bsfit__hcurve *h);
void bsfit__hc_free(bsfit__hcurve *h);
/* Allocates h's arrays (contents unset) with allocator a (copied). */
bsfit_err bsfit__hc_alloc(bsfit__hcurve *h, int p, int hd, size_t n, const bsfit_allocator *a,
                          bsfit_status *st);
/* The stored arrays of c, as they are (periodic curves: the expanded form). */
bsfit_err bsfit__hc_from_curve(const bsfit_curve *c, bsfit__hcurve *h, bsfit_status *st);
/* A periodic curve unrolled over three periods (one before, one after the domain), as an
** open curve with domain [a - T, b + T]: the middle period's knots are c's own. */
bsfit_err bsfit__hc_unroll(const bsfit_curve *c, bsfit__hcurve *h, bsfit_status *st);
/* Knot refinement (NURBS Book A5.4) on raw arrays, for curves and for surface nets
** filtered as curves of rows: inserts the r sorted knots X (inside the domain,
** multiplicities already checked) into the degree-q spline (U, P) of n points of d
** doubles each; Ub gets n+r+q+1 knots, Q n+r points (caller-owned). Returns 0, touching
** neither Ub nor Q, when U is not sorted, X is not sorted or leaves the domain, or a
** knot would pass multiplicity q+1; else 1. */
int bsfit__refine_raw(int q, size_t n, size_t d, const double *U, const double *P,
                      const double *X, size_t r, double *Ub, double *Q);
/* Knot refinement (A5.4): X sorted, within h's domain, multiplicities already checked. */
bsfit_err bsfit__hc_refine(const bsfit__hcurve *h, const double *X, size_t nx,
                           bsfit__hcurve *out, bsfit_status *st);
/* The part of h over [lo, hi] (lo < hi within the domain) as a clamped curve. */
bsfit_err bsfit__hc_piece(const bsfit__hcurve *h, double lo, double hi, bsfit__hcurve *out,
                          bsfit_status *st);
/* Builds a curve of dimension dim (rational when h is homogeneous) from h's arrays. */
bsfit_err bsfit__hc_to_curve(const bsfit__hcurve *h, int dim, bsfit_curve *out,
                             bsfit_status *st);
/* Builds the expanded periodic curve whose period knots are t[0..N] from an unrolled
** curve h that holds it as a contiguous part (found by matching the knots). */
bsfit_err bsfit__hc_to_periodic(const bsfit__hcurve *h, int dim, const double *t, size_t N,
                                bsfit_curve *out, bsfit_status *st);

/* curve_eval.c: C and its derivatives up to order k <= BSFIT_MAX_DEGREE at u in span s of
** a valid curve (u already wrapped), no checks. out: (k+1)*dim doubles. */
void bsfit__curve_derivs_span(const bsfit_curve *c, size_t s, double u, int k, double *out);

/* curve_eval.c: span s of a polynomial cubic (no weights, not Bezier, U[s] < U[s+1]) as a
** polynomial in t = (u - U[s]) / (U[s+1] - U[s]): coef[j*dim + q], j = 0..3, the
** coefficients of t^j (from the exact derivatives at U[s]). */
void bsfit__cubic_span_poly(const bsfit_curve *c, size_t s, double *coef);

/* nearest_sample.c: the nearest of K samples (K*d doubles, row-major, d <= 4) to a point,
** exactly the first sample of smallest sum_q (x_q - P_q)^2 (summed in order of q), found
** by a static k-d tree when K and the number of queries make one pay, else by a scan. */
typedef struct bsfit__nearest {
  const double *smp; /* the samples (borrowed: they must outlive the index) */
  size_t K, d;
  int depth;         /* of the leaves; -1: no tree, queries scan smp */
  size_t nnode;      /* 2^(depth+1) - 1 */
  double *pts;       /* K*d: the samples in tree order */
  double *box;       /* nnode boxes, 2*d doubles each: lower corner, upper corner */
  size_t *idx;       /* K: the sample index of each tree position */
  void *block;       /* pts, box and idx in one allocation of `bytes` */
  size_t bytes;
  bsfit_allocator alloc; /* what block was allocated with */
} bsfit__nearest;

/* Builds the index for about `queries` look-ups, its memory from a (NULL = realloc).
** BSFIT_ENOMEM (nn then needs no free); on success free it with bsfit__nearest_free
** (NULL-safe, idempotent). */
bsfit_err bsfit__nearest_init(bsfit__nearest *nn, const double *smp, size_t K, size_t d,
                              size_t queries, const bsfit_allocator *a, bsfit_status *st);
/* The index of the nearest sample to P (d finite doubles); K >= 1. */
size_t bsfit__nearest_find(const bsfit__nearest *nn, const double *P);
void bsfit__nearest_free(bsfit__nearest *nn);

/* closest_pieces.c: the global stage of the closest-point searches. Every span of positive
** length as a Bezier piece, reached through a tree of its control points' boxes; a search
** proves the foot found is the nearest to a tolerance (a relative 1e-9 of the distance
** plus 1e-13 of the curve's extent) or replaces it by a nearer one. */
typedef struct bsfit__pieces {
  const bsfit_curve *c;
  int p, d, hd;        /* degree, dimension, doubles per homogeneous point */
  size_t ns;           /* spans of positive length */
  int depth;           /* of the tree's leaves */
  size_t nnode;        /* 2^(depth+1) - 1 */
  double abs_tol;      /* the absolute part of the tolerance */
  double *strip;       /* nnode strips: a chord's ends and a width, 2*d+1 doubles each */
  double *binom;       /* binomial coefficients, (4p+1)^2 */
  double *stack;       /* the pieces of one span being halved */
  double *bez;         /* ns pieces of (p+1) hd doubles: each span's Bezier control points */
  double *sstrip;      /* ns strips of the pieces */
  size_t *span;        /* ns: the spans of positive length, in order */
  void *block;         /* all of the above in one allocation of `bytes` */
  size_t bytes;
  bsfit_allocator alloc;
} bsfit__pieces;

/* Newton inside [lo, hi] from u0: the foot's parameter, *d2 its squared distance. */
typedef double (*bsfit__polish_fn)(void *ctx, double lo, double hi, double u0, double *d2);

/* Builds the tree of c's spans (O(n p d)); BSFIT_ENOMEM (then no free needed). */
bsfit_err bsfit__pieces_init(bsfit__pieces *pc, const bsfit_curve *c, const bsfit_allocator *a,
                             bsfit_status *st);
/* Replaces the foot (*u, *d2) of P by a nearer one (found by `polish`) wherever a piece
** comes nearer by more than the tolerance. critical: Newton converged at *u inside its
** bracket (a piece with one minimum that holds it needs no other). */
void bsfit__pieces_search(bsfit__pieces *pc, const double *P, double *u, double *d2,
                          int critical, bsfit__polish_fn polish, void *ctx);
void bsfit__pieces_free(bsfit__pieces *pc);

/* The post-condition of every operation that builds a curve: tmp passes
** bsfit_curve_validate (finite, in range, knots sound). Else tmp is freed and the
** validation's code returned, its message prefixed by what the operation was. O(n), as
** the operations are. */
bsfit_err bsfit__curve_result(bsfit_curve *tmp, const char *op, bsfit_status *st);

/* Cheap O(1) checks of a curve handed to an operation: not NULL, arrays present,
** degree and dimension in range. The full O(n) check is bsfit_curve_validate. */
bsfit_err bsfit__curve_check(const bsfit_curve *c, bsfit_status *st);

#endif
