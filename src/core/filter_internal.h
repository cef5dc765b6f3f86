/*
** filter_internal.h
** What filter.c and filter_exact.c share: splines as raw arrays of any dimension (a
** surface is filtered as a curve whose "points" are whole rows of its control net),
** and the one-dimensional filters on them. Not part of the public API.
*/
#ifndef BSFIT_FILTER_INTERNAL_H
#define BSFIT_FILTER_INTERNAL_H

#include "internal.h"

#include <limits.h>

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
/* Borrowed views of a curve's, a raw spline's, and a surface's rows along u (each row of
** the net one "point" of nv*dim values). */
bsfit__fview bsfit__curve_view(const bsfit_curve *c);
bsfit__fview bsfit__fspline_view(const bsfit__fspline *f);
bsfit__fview bsfit__surface_view_u(const bsfit_surface *s);
/* dst[(j*rows + i)*dim + c] = src[(i*cols + j)*dim + c]: a net's rows become its columns. */
void bsfit__transpose_net(const double *src, size_t rows, size_t cols, size_t dim, double *dst);

/* A one-dimensional operation on a raw spline (a filter's passes, a projection). */
typedef bsfit_err (*bsfit__vop)(const bsfit__fview *v, const void *arg, const bsfit_allocator *a,
                                bsfit__fspline *out, bsfit_status *st);

/* The highest filter order a surface closed around u can take: order r raises its degree
** in u to p + r, which needs p + r + 1 distinct rows. INT_MAX when it is open. */
static inline int bsfit__closed_order_cap(const bsfit_surface *s) {
  return s->periodic_u ? (int)(s->nu - (size_t)s->degree_u) - s->degree_u - 1 : INT_MAX;
}

/* The second half of a tensor operation: fu holds s's net done along u (rows of nv*dim
** values); op runs along v on its columns (the net transposed), and the surface of fu's u
** knots and op's v knots, closed around u when periodic_u, is validated into out
** (filter_fspline.c). */
bsfit_err bsfit__surface_along_v(const bsfit_surface *s, const bsfit__fspline *fu,
                                 bsfit__vop op, const void *arg, int periodic_u,
                                 const bsfit_allocator *a, bsfit_surface *out,
                                 bsfit_status *st);
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

/* `order` passes of the exact box filter of a periodic spline in expanded form (the
** kernel filter of that order); 0 < 2 delta <= period. */
bsfit_err bsfit__filter_exact_periodic(const bsfit__fview *in, int order, double delta,
                                       const bsfit_allocator *a, bsfit__fspline *out,
                                       bsfit_status *st);

/* One direction of a filter: `order` passes of the exact box of half-width delta, or of
** the moving average of k points. */
typedef struct bsfit__pass {
  int exact;
  int k;
  double delta;
  int order;
} bsfit__pass;

/* What bsfit_filter_box_curve_delta checks (filter.c). */
bsfit_err bsfit__check_box_curve_delta(const bsfit_curve *c, double delta, bsfit_status *st);
/* What the public box surface filters check, for the passes au, av (filter.c). */
bsfit_err bsfit__check_box_surface(const bsfit_surface *s, const bsfit__pass *au,
                                   const bsfit__pass *av, bsfit_status *st);
/* The passes au along u, then av along v, of a checked surface (filter_kernel.c). */
bsfit_err bsfit__filter_surface(const bsfit_surface *s, const bsfit__pass *au,
                                const bsfit__pass *av, bsfit_surface *out, bsfit_status *st);

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
** by a global closest point (any two curves); Newton from the same parameter with the
** largest distances refined (curves already known to lie within a certified bound of each
** other, parameter by parameter: each foot's distance is a true distance to a point of the
** other curve, so at most the bound, and at least the global one). */
enum {
  BSFIT__DIST_LOCAL = 1,
  BSFIT__DIST_CORRESPONDING = 2,
  BSFIT__DIST_VERIFIED = 3,
  BSFIT__DIST_FEET = 4
};

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
  const bsfit_curve *measure; /* the curve the deviation is measured to (NULL: the input) */
  int bound_only;             /* a bound within tol ends it, unmeasured (max_deviation: it) */
} bsfit__reduce_arg;

/* Projection of c on b, knots added in the middle of every span farther than tol from
** the measured curve, until none is. res (initialised) receives the last projection,
** also on error; b grows with the knots added. */
bsfit_err bsfit__reduce_loop(const bsfit_curve *c, const bsfit__reduce_arg *r, bsfit__breaks *b,
                             const bsfit_allocator *al, bsfit_curve *res,
                             bsfit_reduce_report *rep, bsfit_status *st);

/* Total turning and bending energy of a valid curve of dimension >= 2 from one sampled
** polygon (bsfit_curve_total_turning, bsfit_curve_bending_energy; samples >= 3); either
** output may be NULL. */
void bsfit__curve_shape(const bsfit_curve *c, size_t samples, double *turning, double *energy);

/* Index of the break span [x_i, x_{i+1}) holding u (clamped to the first and last). */
size_t bsfit__break_span(const bsfit__breaks *br, double u);

/* Break points xs (nx, strictly increasing from a to e) or, xs NULL, the distinct knots in
** [a, e] of the nk knots U of a spline of degree p; each with the multiplicity degree q
** needs there to be as smooth as that spline (filter_reduce.c). */
bsfit_err bsfit__knot_breaks(const double *U, size_t nk, int p, double a, double e, int q,
                             const double *xs, size_t nx, const bsfit_allocator *al,
                             bsfit__breaks *b, bsfit_status *st);

/* A break point (mult 1) in the middle of every break span whose span_max exceeds tol,
** unless narrower than 1e-6 of the whole; *count receives how many (filter_reduce.c). */
bsfit_err bsfit__split_spans(bsfit__breaks *b, const double *span_max, double tol,
                            const bsfit_allocator *al, size_t *count);

/* The distinct knots of c in its domain as break points, each with the multiplicity
** degree q needs there to be as smooth as c (filter_reduce.c). */
bsfit_err bsfit__curve_breaks(const bsfit_curve *c, int q, const bsfit_allocator *al,
                              bsfit__breaks *b, bsfit_status *st);

/* {====================================================================
** Certified distance bounds (filter_bound.c)
** ===================================================================== */

/* Highest degree the Bernstein bound handles (the conversion's norm grows ~2.7^m). */
#define BSFIT__BERN_MAX 12

/* Values at m + 1 nodes -> Bernstein coefficients of degree m. */
typedef struct bsfit__bern {
  int m;
  double norm; /* infinity norm of inv: how much it magnifies the values' rounding */
  double inv[(BSFIT__BERN_MAX + 1) * (BSFIT__BERN_MAX + 1)];
} bsfit__bern;

/* BSFIT_EDEGREE when m is out of 0..BSFIT__BERN_MAX. */
bsfit_err bsfit__bern_init(int m, bsfit__bern *z);

typedef struct bsfit__bound {
  double bound; /* certified: |A(t) - B(t)| <= bound everywhere, so the distance is too */
  double low;   /* the largest |A(t) - B(t)| seen at a node: the bound is at least this */
} bsfit__bound;

/* Bound of max_t |A(t) - B(t)| over A's domain (B closed: evaluated modulo its period;
** B open: its domain must hold A's). Intervals above thr are refined. span_max (br->n - 1
** values, or NULL) receives the bound of each break span of br. EDEGREE above
** BSFIT__BERN_MAX. */
bsfit_err bsfit__curve_diff_bound(const bsfit_curve *A, const bsfit_curve *B, double thr,
                                  const bsfit__breaks *br, double *span_max,
                                  const bsfit_allocator *al, bsfit__bound *out,
                                  bsfit_status *st);

/* The same for surfaces of one domain, max over it of |A(u,v) - B(u,v)|; max_u (bu->n - 1
** values) and max_v (bv->n - 1), when not NULL, receive the largest patch bound in each
** break span of bu and bv. */
bsfit_err bsfit__surface_diff_bound(const bsfit_surface *A, const bsfit_surface *B, double thr,
                                    const bsfit__breaks *bu, double *max_u,
                                    const bsfit__breaks *bv, double *max_v,
                                    const bsfit_allocator *al, bsfit__bound *out,
                                    bsfit_status *st);

/* The tensor L2 projection of the polynomial surface F on degrees (qu, qv) on the break
** points bu x bv (over that rectangle; periodic in u when periodic_u, F then closed
** around u with the period of bu), into out (filter_reduce_surface.c). */
bsfit_err bsfit__project_surface(const bsfit_surface *F, int qu, int qv, const bsfit__breaks *bu,
                                 const bsfit__breaks *bv, int periodic_u,
                                 const bsfit_allocator *al, bsfit_surface *out, bsfit_status *st);

/* }==================================================================== */

#endif
