/*
** bsfit_fit.h
** Parameters, knot placement and weighted least-squares fitting (open and periodic),
** global interpolation, and the paper's "wrap closing" of an open fit (docs/method.md §2-6, §13).
** Included by bsfit.h; include bsfit.h rather than this file.
**
** Array layouts used below:
** - points `pts`: m rows of `dim` doubles, row-major [x0,y0,(z0,)x1,y1,...], 1 <= dim <= 4;
** - parameters `u`: m doubles, one per point;
** - weights `w`: m finite doubles >= DBL_MIN (positive and not subnormal: a subnormal
**   weight keeps too few digits for the sums), one per point;
** - a "period" of knots for a closed curve with N distinct control points: N+1
**   non-decreasing values t[0] < t[N] (see bsfit_knots_periodic for the expanded form).
*/
#ifndef BSFIT_FIT_H
#define BSFIT_FIT_H

#include "bsfit.h"

/* {====================================================================
** Parameters (docs/method.md §2)
** ===================================================================== */

/** How parameter values are assigned to points. */
typedef enum bsfit_param_kind {
  BSFIT_PARAM_UNIFORM = 0,    /**< equally spaced */
  BSFIT_PARAM_CHORD = 1,      /**< chord length (P-8, P-9) */
  BSFIT_PARAM_CENTRIPETAL = 2 /**< square root of chord length */
} bsfit_param_kind;

/** Parameters ū_k for ordered points Q_0..Q_{m-1}.
**
** Open data (`closed == 0`): ū_0 = 0, ū_{m-1} = 1, ū_k = ū_{k-1} + l_k / L, where l_k is
** |Q_k - Q_{k-1}| (chord), its square root (centripetal) or 1 (uniform) and L the sum.
** Closed data (`closed != 0`): the closing chord Q_{m-1} -> Q_0 is part of L, so the
** parameters cover one period [0, 1): ū_0 = 0 and ū_{m-1} = 1 - l_close / L < 1. The last
** point must then differ from the first (do not repeat the first point at the end).
**
** Coincident consecutive points have a zero chord: they get the SAME parameter (never
** NaN). Fitters accept shared parameters; an interpolation through them is singular.
**
** @param[in]  pts    m points, row-major (see the file head).
** @param[in]  m      number of points, >= 2.
** @param[in]  dim    1..4.
** @param[in]  kind   one of bsfit_param_kind.
** @param[in]  closed 0 for open data, non-zero for a closed section.
** @param[out] u      m parameters, non-decreasing, in [0, 1] (open) or [0, 1) (closed).
**                    Untouched on error. Must not overlap pts.
** @return BSFIT_OK; BSFIT_EINVAL (NULL array, unknown kind, closed data whose last point
**         repeats the first); BSFIT_EDIM; BSFIT_ETOOFEW (m < 2); BSFIT_ENONFINITE (NaN/Inf
**         in a point, or chords overflowing); BSFIT_ERANGE (a coordinate beyond
**         BSFIT_COORD_MAX); BSFIT_EDEGENERATE (all points coincident, whatever the kind).
**         Chords are scaled like hypot, so points 1e-300 apart still get distinct
**         parameters: on success the parameters are finite and non-decreasing. */
BSFIT_API bsfit_err bsfit_params(const double *pts, size_t m, int dim, bsfit_param_kind kind,
                                 int closed, double *u, bsfit_status *st);

/* }==================================================================== */

/* {====================================================================
** Knot placement (docs/method.md §3-4)
** ===================================================================== */

/** Knot placement rules. "Open" rules give a clamped knot vector, "closed" rules one
** period of knots for a periodic curve. */
typedef enum bsfit_knot_rule {
  /** open: NURBS Book eq. 9.68-9.69 (P-10, P-11), clamped on [ū_0, ū_{m-1}] */
  BSFIT_KNOTS_AVERAGING = 0,
  /** closed: the paper's P-12/P-13 as read in docs/method.md §3-4 ("carvalho-closed"), literal:
  ** t_0 = ū_0, t_k = (1-α) ū_{i-1} + α ū_i with i = int(k d), α = k d - i, d = m/N,
  ** t_N = ū_0 + 1. Its first span is short and its last long (kept to reproduce the paper). */
  BSFIT_KNOTS_CARVALHO_CLOSED = 1,
  /** closed: the same α-interpolation applied consistently around the circle
  ** (ū_{i+m} = ū_i + 1): t_k sits at fractional index k d + c, c = 0 for odd p and d/2 for
  ** even p, so that with m == N it gives the classical periodic interpolation knots
  ** (knots at the parameters for odd p, at their midpoints for even p). The period is
  ** [t_0, t_0 + 1], t_0 = ū_0 for odd p. */
  BSFIT_KNOTS_PERIODIC_AVERAGING = 2,
  /** open: clamped, equally spaced interior knots on [ū_0, ū_{m-1}] */
  BSFIT_KNOTS_UNIFORM = 3,
  /** closed: t_k = ū_0 + k/N */
  BSFIT_KNOTS_PERIODIC_UNIFORM = 4
} bsfit_knot_rule;

/** Non-zero when `rule` is a closed rule (writes one period of N+1 knots). */
BSFIT_API int bsfit_knot_rule_closed(bsfit_knot_rule rule);

/** Number of knots bsfit_knots_place writes: n+p+1 for open rules, n+1 (one period) for
** closed rules; 0 for an unknown rule. */
BSFIT_API size_t bsfit_knots_place_count(bsfit_knot_rule rule, int p, size_t n);

/** Places knots for a fit of degree p with n control points (closed rules: n distinct
** control points N) to the parameters u.
**
** Open parameters are those of bsfit_params(closed = 0); closed parameters those of
** bsfit_params(closed != 0): non-decreasing with ū_{m-1} < ū_0 + 1 (period 1).
**
** After placing, every knot span of positive length is checked to hold at least one
** parameter (Schoenberg-Whitney; closed rules: parameters taken modulo the period). If
** one does not, U is still filled in full and BSFIT_EEMPTYSPAN is returned, the message
** naming the first empty span: for open rules its knot-vector index s (span
** [U[s], U[s+1])), for closed rules its index k in the period (span [t_k, t_{k+1})). Use
** bsfit_knots_empty_spans for the whole list.
**
** @param[in]  rule  one of bsfit_knot_rule.
** @param[in]  u     m parameters, non-decreasing, finite.
** @param[in]  m     number of parameters, >= n.
** @param[in]  p     degree, 1..BSFIT_MAX_DEGREE.
** @param[in]  n     control points (open) or distinct control points N (closed), >= p+1
**                   (closed: also >= 2).
** @param[out] U     bsfit_knots_place_count(rule, p, n) knots.
** @return BSFIT_OK; BSFIT_EINVAL (NULL array, unknown rule, parameters decreasing, closed
**         parameters spanning a period or more); BSFIT_EDEGREE; BSFIT_ETOOFEW (m < n);
**         BSFIT_ENONFINITE; BSFIT_EDEGENERATE (open: ū_0 == ū_{m-1}); BSFIT_EEMPTYSPAN. */
BSFIT_API bsfit_err bsfit_knots_place(bsfit_knot_rule rule, const double *u, size_t m, int p,
                                      size_t n, double *U, bsfit_status *st);

/** Lists the knot spans of positive length that hold no parameter.
**
** @param[in]  U        a valid knot vector of nknots = n+p+1 knots (open, or the expanded
**                      periodic form of docs/method.md §1). Only spans inside the domain
**                      [U[p], U[n]] are considered; span s is [U[s], U[s+1]), the last
**                      one closed on the right for open vectors.
** @param[in]  periodic non-zero: parameters are taken modulo the period U[n] - U[p].
**                      zero: parameters outside the domain count in no span.
** @param[in]  u        m parameters, non-decreasing (open), or non-decreasing within one
**                      period (periodic).
** @param[out] spans    up to `cap` knot-vector indices s of empty spans, increasing
**                      (may be NULL when cap == 0).
** @param[out] count    total number of empty spans (may exceed cap).
** @return BSFIT_OK; BSFIT_EINVAL (NULL array, parameters decreasing); any code of
**         bsfit_knots_validate. */
BSFIT_API bsfit_err bsfit_knots_empty_spans(const double *U, size_t nknots, int p, int periodic,
                                            const double *u, size_t m, size_t *spans,
                                            size_t cap, size_t *count, bsfit_status *st);

/* }==================================================================== */

/* {====================================================================
** The fitter: weighted least squares, open or periodic (docs/method.md §5, §13)
** ===================================================================== */

/** How a fitter solves its least-squares problem. */
typedef enum bsfit_solver {
  /** the banded normal equations N^T W N P = N^T W Q by banded Cholesky (dpbtrf): the
  ** fastest, and accurate while the normal matrix is well conditioned; its condition
  ** number is the square of the weighted collocation matrix's, so rep.rcond near 1e-16
  ** means digits are lost (or BSFIT_ENOTSPD). The default. */
  BSFIT_SOLVER_CHOLESKY = 0,
  /** QR of the weighted collocation rows sqrt(w_k) N(u_k) (Householder reflections, the
  ** rows of a span at a time) into a banded upper triangle (periodic fits: bordered by p
  ** dense columns), then banded back substitution (dtbtrs): O(m p (p + p_border + dim)), no
  ** normal matrix, so the accuracy follows the condition number of the collocation matrix
  ** itself. About 3-5x the Cholesky time for open fits, 8x for periodic ones (bench_fit).
  ** Parameters out of order (after wrapping, for periodic fits) are sorted by span first,
  ** with an m-entry index array the fitter keeps for later fits. */
  BSFIT_SOLVER_QR = 1,
  /** Cholesky, and QR again when the normal matrix is not positive definite in floating
  ** point or its rcond is below BSFIT_SOLVER_AUTO_RCOND. The rcond is then always computed. */
  BSFIT_SOLVER_AUTO = 2
} bsfit_solver;

/** BSFIT_SOLVER_AUTO refits by QR below this reciprocal condition number of the normal
** matrix: Cholesky's relative error grows like eps / rcond, QR's like eps / sqrt(rcond). */
#define BSFIT_SOLVER_AUTO_RCOND 1e-10

/** Settings of a fitter. Initialise with bsfit_fit_opts_init, then change fields. */
typedef struct bsfit_fit_opts {
  int degree;            /**< p, 1..BSFIT_MAX_DEGREE (default 3) */
  size_t count;          /**< control points n (open) or distinct control points N (periodic) */
  int periodic;          /**< non-zero: closed curve, N distinct control points, C^{p-1} seam */
  bsfit_knot_rule rule;  /**< knot rule used at each fit when `knots` is NULL (default:
                              AVERAGING; for periodic fits PERIODIC_AVERAGING when an open
                              rule is given). Its knots depend on the fit's parameters. */
  const double *knots;   /**< fixed knots, copied at configuration: open n+p+1 knots,
                              periodic one period of N+1 knots; NULL = use `rule` */
  size_t nknots;         /**< length of `knots` */
  int fix_ends;          /**< open only: P_0 = Q_0 and P_{n-1} = Q_{m-1} exactly */
  /** open only, may be NULL: the derivative C'(a) at the start, `dim` values of the fit
  ** (at most 4, copied at configuration). Implies the start point is fixed too:
  ** P_0 = Q_0, P_1 = Q_0 + (U[p+1] - U[1]) / p * T (exact, by elimination). */
  const double *tangent_start;
  const double *tangent_end; /**< the same at the end: C'(b), fixes P_{n-1} and P_{n-2} */
  int tangent_dim;       /**< number of values in the tangents (1..4); fits of another
                              dimension are rejected with BSFIT_EDIM */
  bsfit_solver solver;   /**< default BSFIT_SOLVER_CHOLESKY */
} bsfit_fit_opts;

/** Default settings: cubic, open, count 0 (must be set), averaging knots, no constraints,
** Cholesky solver. */
BSFIT_API void bsfit_fit_opts_init(bsfit_fit_opts *o);

/** Diagnostics of one fit. */
typedef struct bsfit_fit_report {
  double rms;              /**< weighted RMS: sqrt(sum w_k r_k^2 / sum w_k) */
  double max;              /**< max_k r_k, r_k = |Q_k - C(ū_k)| */
  size_t max_index;        /**< k of the max deviation (first one on ties) */
  double rcond;            /**< reciprocal 1-norm condition number 1 / (|A|_1 |A^-1|_1) of
                                the normal matrix A of the free unknowns. Open fits: exact,
                                in one extra banded solve: A is totally nonnegative (a sum of
                                w_k N(u_k) N(u_k)^T, B-spline collocation is), so A^-1 has the
                                checkerboard sign pattern and |A^-1|_1 = |A^-1 s|_inf with
                                s = (1, -1, 1, ...). Periodic fits (A is not totally
                                nonnegative): |A^-1|_1 replaced by max(|A11^-1|_1, |S^-1|_1),
                                A11 the banded leading block (totally nonnegative: exact, as
                                above) and S the p x p Schur complement of the block
                                elimination (LAPACK dpocon's estimate): both are principal
                                parts of A^-1 in the 2-norm sense, so this is an upper bound
                                of the true value within the estimator's usual factor.
                                QR solver: the same A, as R^T R: open fits exact as above (two
                                triangular solves, exact while the parameters lie in the domain),
                                periodic fits Hager's 1-norm estimate of
                                |A^-1|_1 (LAPACK dlacon's algorithm; a lower bound, so rcond
                                from above). 1 for a fit with no free unknowns. */
  size_t n_empty_spans;    /**< spans of positive length holding no parameter */
  size_t first_empty_span; /**< knot-vector index of the first one (valid when n_empty_spans) */
  size_t m;                /**< number of points fitted */
  bsfit_solver solver;     /**< the solver that gave the result (CHOLESKY or QR) */
} bsfit_fit_report;

/** Opaque fitter: settings plus a workspace sized by degree and count, reused by every
** fit (no allocation per fit once the output curve has its shape). */
typedef struct bsfit_fitter bsfit_fitter;

/** Creates a fitter.
** @param[out] f  receives the fitter (NULL on error). Free with bsfit_fitter_free.
** @param[in]  o  settings (copied, arrays included).
** @param[in]  a  allocator for the fitter and the curves it produces (NULL = realloc).
** @return BSFIT_OK or any code of bsfit_fitter_configure, BSFIT_ENOMEM. */
BSFIT_API bsfit_err bsfit_fitter_new(bsfit_fitter **f, const bsfit_fit_opts *o,
                                     const bsfit_allocator *a, bsfit_status *st);

/** Changes the settings (e.g. another count or knot vector), resizing the workspace.
** On error the fitter keeps its previous settings and stays usable.
** @return BSFIT_OK; BSFIT_EINVAL (NULL, unknown rule, constraints on a periodic fit,
**         constraints needing more control points than count, tangent_dim out of 1..4);
**         BSFIT_ENONFINITE / BSFIT_ERANGE (a tangent NaN/Inf or beyond BSFIT_COORD_MAX);
**         BSFIT_EDEGREE (degree out of range or >= count); any code of
**         bsfit_knots_validate / bsfit_knots_periodic for fixed knots (open fixed ends or
**         tangents also need clamped knots: BSFIT_EINVAL); BSFIT_ENOMEM. */
BSFIT_API bsfit_err bsfit_fitter_configure(bsfit_fitter *f, const bsfit_fit_opts *o,
                                           bsfit_status *st);

/** Frees the fitter. NULL-safe. */
BSFIT_API void bsfit_fitter_free(bsfit_fitter *f);

/** Asks a multi-threaded BLAS (OpenBLAS) to run on one thread. bsfit's banded systems
** (bandwidth p) are far too small to gain from BLAS threads, while OpenBLAS's idle workers
** spin on the other cores (sched_yield loops) and take them from everything else. The
** setting is
** process-wide, so the library never makes it on its own: the `bsfit` program and the
** benchmarks call this at start; an application with BLAS work of its own decides.
** @return 1 when a BLAS thread setting was found and set, 0 otherwise (nothing to do). */
BSFIT_API int bsfit_blas_single_thread(void);

/** Fits the points: minimises sum_k w_k |Q_k - C(ū_k)|^2 over the control points.
**
** Cholesky solver: assembles N^T W N (banded, bandwidth p) and N^T W Q span by span from
** the p+1 non-zero basis functions of each point and solves it by banded Cholesky (all
** coordinates at once). Periodic fits fold the wrapped unknowns and solve the cyclic
** system by block elimination of the last p unknowns: O(N p^2). QR solver: see
** bsfit_solver; both solve the same problem (the same minimum).
**
** @param[in]  f         the fitter.
** @param[in]  pts       m points, row-major, dim per point.
** @param[in]  m         number of points, >= count.
** @param[in]  dim       1..4 (equal to tangent_dim when tangents are set).
** @param[in]  u         m parameters (need not be sorted, though sorted is faster; knot
**                       rules need them non-decreasing). Periodic fits take them modulo
**                       the period. Open fits with fixed knots: a parameter outside the
**                       domain [U[p], U[n]] belongs to the end span on its side and is
**                       fitted by that span's polynomial continued, as bsfit_curve_eval
**                       extrapolates (the residuals agree with it).
** @param[in]  w         m weights, or NULL for all 1.
** @param[out] out       receives the curve (open: count control points; periodic: the
**                       expanded form, bsfit_curve_distinct(out) == count). Its arrays are
**                       reused when it already has the right shape, else reallocated with
**                       the fitter's allocator. On error *out is left empty (freed).
** @param[out] rep       diagnostics, or NULL (then the rcond estimate is skipped).
** @param[out] residuals m distances |Q_k - C(ū_k)|, or NULL.
** @return BSFIT_OK; BSFIT_EINVAL (NULL arrays); BSFIT_EDIM; BSFIT_ETOOFEW (m < count);
**         BSFIT_ENONFINITE (NaN/Inf in a point or parameter: both solvers find every one,
**         even with no free unknown); BSFIT_ERANGE (data beyond BSFIT_COORD_MAX that
**         push a control point beyond it or make the squared residuals overflow; the
**         message names the first point beyond the range); BSFIT_EWEIGHT (a weight
**         zero, negative, subnormal or not finite); BSFIT_EDEGENERATE (all points coincident);
**         any code of bsfit_knots_place except BSFIT_EEMPTYSPAN (rule-based knots);
**         BSFIT_EEMPTYSPAN (the normal matrix is not positive definite and some span holds
**         no data: the message names the first); BSFIT_ENOTSPD (not positive definite
**         otherwise); BSFIT_ENOMEM. Never returns BSFIT_OK with a NaN in its outputs. */
BSFIT_API bsfit_err bsfit_fitter_fit(bsfit_fitter *f, const double *pts, size_t m, int dim,
                                     const double *u, const double *w, bsfit_curve *out,
                                     bsfit_fit_report *rep, double *residuals,
                                     bsfit_status *st);

/** The full knot vector of the last fit (open n+p+1, periodic expanded N+2p+1), borrowed
** from the fitter until the next fit or configuration; NULL before a first fit.
** @param[out] nknots its length (may be NULL). */
BSFIT_API const double *bsfit_fitter_knots(const bsfit_fitter *f, size_t *nknots);

/* }==================================================================== */

/* {====================================================================
** Interpolation and wrap closing
** ===================================================================== */

/** Global interpolation (NURBS Book A9.1): the curve of degree p through all m points at
** their parameters.
** - Open: m control points, knots by averaging (NURBS Book eq. 9.8), clamped on
**   [ū_0, ū_{m-1}]; solved by banded LU (dgbsv).
** - Periodic: m distinct control points, BSFIT_KNOTS_PERIODIC_AVERAGING knots; solved as
**   the periodic least-squares fit with as many control points as points (its minimum is
**   the interpolant, residuals zero up to rounding).
** @param[in]  u     m parameters, strictly increasing (periodic: within one period).
** @param[out] out   the curve (freed first; allocated with `a`). Left empty on error.
** @return BSFIT_OK; BSFIT_EINVAL (NULL array, parameters not strictly increasing, closed
**         parameters spanning a period or more); BSFIT_EDIM; BSFIT_EDEGREE (p < 1 or
**         m < p+1); BSFIT_ENONFINITE; BSFIT_ESINGULAR (open, numerically singular);
**         BSFIT_ENOTSPD / BSFIT_EEMPTYSPAN (periodic); BSFIT_ENOMEM. */
BSFIT_API bsfit_err bsfit_interpolate(const double *pts, size_t m, int dim, const double *u,
                                      int p, int periodic, bsfit_curve *out,
                                      const bsfit_allocator *a, bsfit_status *st);

/** The paper's wrap closing (docs/method.md §6): reads the n control points of an open fit as the
** polygon of a periodic curve of the same degree, with BSFIT_KNOTS_CARVALHO_CLOSED knots
** placed on the closed parameters u (an empty span there is not an error here).
** @param[in]  open  a polynomial (non-rational), non-periodic curve with n >= p+1 and n >= 2.
** @param[in]  u     m closed parameters (bsfit_params with closed != 0), m >= n.
** @param[out] out   the periodic curve, n distinct control points (freed first).
** @return BSFIT_OK; BSFIT_EINVAL (rational, periodic or empty input, NULL array); any
**         code of bsfit_knots_place except BSFIT_EEMPTYSPAN; BSFIT_ENOMEM. */
BSFIT_API bsfit_err bsfit_curve_wrap_closed(const bsfit_curve *open, const double *u, size_t m,
                                            bsfit_curve *out, const bsfit_allocator *a,
                                            bsfit_status *st);

/* }==================================================================== */

#endif /* BSFIT_FIT_H */
