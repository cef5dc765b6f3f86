/*
** fit_internal.h
** Private helpers shared by param.c, knot_placement.c, fit.c, fit_assembly.c, fit_qr.c,
** periodic.c and linalg.c:
** the LAPACKE wrappers (linalg.c is the only file calling LAPACKE), the fitter's layout
** and the span-by-span kernels. Not part of the public API.
*/
#ifndef BSFIT_FIT_INTERNAL_H
#define BSFIT_FIT_INTERNAL_H

#include "internal.h"

#include <float.h>
#include <math.h>

/* {====================================================================
** linalg.c: column-major LAPACK wrappers; every `info` goes through bsfit__lapack_status
** ===================================================================== */

/* Maps a LAPACK(E) info value of `routine` to a bsfit_err (the only place doing so):
** 0 -> OK; -1010/-1011 (LAPACKE work memory / transpose memory) -> ENOMEM; other < 0 ->
** ELAPACK "argument %d"; > 0 -> ENOTSPD when `spd` (Cholesky) else ESINGULAR. */
bsfit_err bsfit__lapack_status(int info, const char *routine, int spd, bsfit_status *st);

/* Symmetric positive definite band, lower storage AB[(i-j) + j*ldab], ldab >= kd+1. */
bsfit_err bsfit__pb_factor(size_t n, int kd, double *ab, size_t ldab, bsfit_status *st);
bsfit_err bsfit__pb_solve(size_t n, int kd, const double *ab, size_t ldab, size_t nrhs,
                          double *b, size_t ldb, bsfit_status *st);
/* Reciprocal 1-norm condition number of a factored totally nonnegative band, given its
** 1-norm: exact, in one solve (work: n doubles); for other matrices an upper bound
** (|A^-1|_1 from below). 0 on failure. An open fit's normal matrix
** A = sum_k w_k N(u_k) N(u_k)^T is totally nonnegative: the sum does not depend on the
** order of the points, B-spline collocation matrices at sorted parameters are totally
** nonnegative (de Boor), and so are products of such matrices (Cauchy-Binet) and their
** principal submatrices (fixed ends eliminated). Periodic normal matrices are not. */
double bsfit__pb_rcond_tn(size_t n, int kd, const double *ab, size_t ldab, double anorm,
                          double *work);
/* Triangular band solve (dtbtrs): `lower` band storage AB[(i-j) + j*ldab] of a lower
** triangle L with kd sub-diagonals, solving L x = b (trans 0) or L^T x = b (trans 1).
** A zero diagonal entry gives BSFIT_ESINGULAR. */
bsfit_err bsfit__tb_solve(size_t n, int kd, int trans, const double *ab, size_t ldab,
                          size_t nrhs, double *b, size_t ldb, bsfit_status *st);
/* Dense triangular solve (dtrtrs), upper triangle of column-major a: U x = b (trans 0) or
** U^T x = b (trans 1). A zero diagonal entry gives BSFIT_ESINGULAR. */
bsfit_err bsfit__tr_solve(size_t n, int trans, const double *a, size_t lda, size_t nrhs,
                          double *b, size_t ldb, bsfit_status *st);
/* Dense symmetric positive definite, lower, column-major. */
bsfit_err bsfit__po_factor(size_t n, double *a, size_t lda, bsfit_status *st);
bsfit_err bsfit__po_solve(size_t n, const double *a, size_t lda, size_t nrhs, double *b,
                          size_t ldb, bsfit_status *st);
double bsfit__po_rcond(size_t n, const double *a, size_t lda, double anorm, double *work,
                       int *iwork);
/* General band LU solve (dgbsv): ab has ldab >= 2kl+ku+1 rows, the matrix in rows kl..;
** ipiv: n ints. */
bsfit_err bsfit__gb_solve(size_t n, int kl, int ku, double *ab, size_t ldab, int *ipiv,
                          size_t nrhs, double *b, size_t ldb, bsfit_status *st);

/* }==================================================================== */

/* {====================================================================
** knot_placement.c
** ===================================================================== */

/* Number of spans [T[k], T[k+1]) (k = 0..K-1) of positive length holding no parameter of
** the sorted u; `periodic`: parameters taken modulo T[K]-T[0]; otherwise the last span is
** closed on the right. *first receives the first empty k (when the count is > 0). */
/* bsfit_knots_place without the empty-span count (the fitter reads occupancy off its
** assembly instead): argument checks, the rule, the knot vector's validity. */
bsfit_err bsfit__knots_place_rule(bsfit_knot_rule rule, const double *u, size_t m, int p,
                                  size_t n, double *U, bsfit_status *st);
size_t bsfit__count_empty(const double *T, size_t K, const double *u, size_t m, int periodic,
                          size_t *first);

/* }==================================================================== */

/* {====================================================================
** fit.c / fit_assembly.c / periodic.c: the fitter
** ===================================================================== */

struct bsfit_fitter {
  bsfit_allocator alloc;
  /* settings */
  int p, periodic, fix_ends, has_t0, has_t1, tangent_dim, user_knots;
  bsfit_solver solver;
  bsfit_knot_rule rule;
  size_t count; /* n (open) or N (periodic) */
  double t0[4], t1[4];
  /* sizes */
  size_t nraw;  /* stored control points: n, or N + p */
  size_t nk;    /* nraw + p + 1 knots */
  size_t tri;   /* p(p+1)/2 reciprocal knot differences per span */
  int fitted;   /* knots hold the last fit's vector */
  /* workspace: one block */
  void *block;
  size_t block_size;
  double *U;      /* nk knots */
  double *period; /* N+1 (periodic) */
  double *inv;    /* (nraw - p) * tri, degrees above 3 (point-by-point basis) */
  double *poly;   /* (nraw - p) * bsfit__fit_poly_stride(p), degrees 1..3 */
  double *band;   /* (p+1) * nraw, lower band storage */
  double *rhs;    /* nraw * 4, column-major (coordinate k at rhs + k*nraw) */
  double *work;   /* 3 * nraw */
  double *a11;    /* periodic: (p+1) * (N-p) */
  double *a12;    /* periodic: (N-p) * p */
  double *y;      /* periodic: (N-p) * p, Z = L^-1 A12 of the block elimination */
  double *s22;    /* periodic: p * p */
  double *r2;     /* periodic: N * 4 folded right-hand sides */
  int *iwork;     /* nraw */
  unsigned char *occ; /* nraw spans touched by data */
  /* QR solver (fit_qr.c): the order in which points enter when their parameters are out
  ** of order, grown on demand (its own allocation: it scales with m, not with the count) */
  size_t *order;
  size_t order_cap;
  size_t qr_nb; /* band unknowns of the last QR factorisation */
  int qr_q;     /* border unknowns (periodic: p) */
};

/* The control points an open fit's constraints fix (fit.c): index -> coordinates. */
typedef struct bsfit__fixed_set {
  size_t idx[4];
  double val[4][4];
  size_t count, lo, hi; /* free unknowns lo..hi-1 (empty when count covers all) */
} bsfit__fixed_set;

void bsfit__fit_fixed(const bsfit_fitter *f, const double *pts, size_t m, int dim,
                      bsfit__fixed_set *fx);

/* fit_qr.c: QR of the weighted collocation rows (Householder, a span's rows at a time)
** into the banded upper triangle R (stored in f->band as the lower band of R^T), its border (f->a12, periodic),
** R22 (f->s22) and the rotated right-hand sides (f->rhs); marks occupied spans. Returns
** BSFIT_ENOMEM (order array) or BSFIT_OK; *badw is set when a weight is <= 0 or NaN;
** other non-finite input shows up as non-finite entries of R or the right-hand sides. */
bsfit_err bsfit__qr_factor(bsfit_fitter *f, const double *pts, size_t m, int dim,
                           const double *u, const double *w, const bsfit__fixed_set *fx,
                           int *badw, bsfit_status *st);
/* Non-zero when every entry of the last QR factorisation is finite. */
int bsfit__qr_finite(const bsfit_fitter *f, int dim);
/* Back substitution: the free unknowns into ctrl (row-major; open: rows lo..hi-1 of fx,
** periodic: the N distinct control points), *rcond when rcond != NULL. */
bsfit_err bsfit__qr_solve(bsfit_fitter *f, int dim, const bsfit__fixed_set *fx, double *ctrl,
                          double *rcond, bsfit_status *st);

/* x taken into the period [a, b) of a periodic fit (the assembly's and the QR's rule). */
static inline double bsfit__wrap_param(double x, double a, double b) {
  double T = b - a, v;
  if (x >= a && x < b) return x;
  v = a + fmod(x - a, T);
  if (v < a) v += T;
  return v >= b ? a : v;
}

/* fit_assembly.c: the passes over the points, span by span. */
/* Doubles per span in `poly` (degrees 1..3: the basis functions' power coefficients, then
** the span's centre and inverse half-length), 0 for higher degrees. */
size_t bsfit__fit_poly_stride(int p);
/* Per-span data of the current knots: `poly` (degrees 1..3) or reciprocal knot
** differences (`inv`, higher degrees). */
void bsfit__fit_prepare_spans(bsfit_fitter *f);
/* Assembly: band, rhs (raw unknowns), occupancy; returns nonzero when a weight is <= 0
** or NaN, negative when the allocator's interrupt flag stopped it (the band is then
** incomplete). Other non-finite input shows up as non-finite band or rhs entries. */
int bsfit__fit_assemble(bsfit_fitter *f, const double *pts, size_t m, int dim, const double *u,
                        const double *w);
/* Residual pass with the solved (raw) control points: distances into res (may be NULL),
** weighted RMS, maximum and its index. Returns 0, or negative when the allocator's
** interrupt flag stopped it (outputs unset). */
int bsfit__fit_residuals(const bsfit_fitter *f, const double *ctrl, const double *pts,
                         size_t m, int dim, const double *u, const double *w, double *res,
                         double *wrms, double *max, size_t *imax);
/* periodic.c: folds the raw system and solves it; writes the N distinct control points,
** row-major, into ctrl; *rcond when rcond != NULL. */
bsfit_err bsfit__periodic_solve(bsfit_fitter *f, int dim, double *ctrl, double *rcond,
                                bsfit_status *st);
/* 1-norm of the symmetric band (lower storage) restricted to rows/columns lo..hi. */
double bsfit__band_norm1(const double *ab, size_t ldab, int kd, size_t lo, size_t hi,
                         double *colsum);

/* }==================================================================== */

#endif
