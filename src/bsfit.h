/*
** bsfit.h
** The public C API of libbsfit: B-spline / NURBS / Bézier curves and surfaces,
** weighted least-squares fitting and filtering. No Lua here (see bsfit_lua.h and
** bsfit_engine.h for the scripting layers).
**
** Conventions, valid for every function of the library:
** - A fallible function returns a bsfit_err and takes a `bsfit_status *st` as its
**   LAST argument. `st` may be NULL; when it is not, it receives the code and a
**   human-readable message. There is no global error state: the library is
**   thread-safe as long as two threads do not share one object.
** - The library never prints, exits or aborts.
** - Points and control points are stored row-major: [x0,y0,(z0,)x1,y1,...].
** - Knot vectors are plain `double` arrays; a curve of degree p with n control
**   points has n+p+1 knots and its domain is [U[p], U[n]].
** - Objects that own memory take a `const bsfit_allocator *` (NULL = realloc/free).
**
** The API is split over a few headers, one concept each, all included here:
**   bsfit_surface.h  tensor-product surfaces
**   bsfit_fit.h      parameters, knot placement, weighted least squares
**   bsfit_filter.h   smoothing by box filtering (Persiano)
**   bsfit_io.h       files: points, curve/surface JSON, SVG, IGES, atomic writing
**   bsfit_geom.h     geometry kernels on point sequences (weights, angles)
**   bsfit_analysis.h noise level and corners of a section
*/
#ifndef BSFIT_H
#define BSFIT_H

#include <stddef.h>

#ifdef __cplusplus
extern "C" {
#endif

/* {====================================================================
** Versions and visibility
** ===================================================================== */

#define BSFIT_VERSION_MAJOR 0
#define BSFIT_VERSION_MINOR 1
#define BSFIT_VERSION_PATCH 0
#define BSFIT_VERSION "0.1.0"
#define BSFIT_VERSION_NUMBER \
  (BSFIT_VERSION_MAJOR * 10000 + BSFIT_VERSION_MINOR * 100 + BSFIT_VERSION_PATCH)

#if defined(_WIN32)
#  if defined(BSFIT_BUILDING)
#    define BSFIT_API __declspec(dllexport)
#  else
#    define BSFIT_API __declspec(dllimport)
#  endif
#else
#  define BSFIT_API __attribute__((visibility("default")))
#endif

/** Largest |coordinate| of a point, control point or tangent the library accepts: squares,
** sums of squares and products with weights then stay far from overflow (1e200 << DBL_MAX),
** so every operation that returns OK returns finite numbers (docs/robustness-core.md). */
#define BSFIT_COORD_MAX 1e100
/** Range of the weights of a rational curve: normal numbers whose products with any
** coordinate stay finite. */
#define BSFIT_WEIGHT_MIN 1e-100
#define BSFIT_WEIGHT_MAX 1e100

/** Highest degree supported (basis work arrays live on the stack). */
#define BSFIT_MAX_DEGREE 30

/** Version of the library actually linked (compare with BSFIT_VERSION_NUMBER). */
BSFIT_API int bsfit_version_number(void);
BSFIT_API const char *bsfit_version(void);

/* }==================================================================== */

/* {====================================================================
** Errors
** ===================================================================== */

/** Status codes. Append-only: values never change meaning. */
typedef enum bsfit_err {
  BSFIT_OK = 0,
  BSFIT_ENOMEM = -1,        /**< an allocation failed */
  BSFIT_EDIM = -2,          /**< dimension out of range or mismatched */
  BSFIT_EDEGREE = -3,       /**< degree < 0 (or < 1 where needed), > BSFIT_MAX_DEGREE, or >= control points */
  BSFIT_EDOMAIN = -4,       /**< parameter outside the curve's domain, or empty domain */
  BSFIT_EMULT = -5,         /**< knot multiplicity too high */
  BSFIT_EKNOTS_DECR = -6,   /**< knots are decreasing somewhere */
  BSFIT_ENKNOTS = -7,       /**< wrong number of knots for degree and control points */
  BSFIT_EINVAL = -8,        /**< an argument is invalid (message says which) */
  BSFIT_ENONFINITE = -9,    /**< NaN or Inf in the input */
  BSFIT_EWEIGHT = -10,      /**< a weight is zero, negative or not finite */
  BSFIT_ETOOFEW = -11,      /**< too few points (e.g. fewer points than control points) */
  BSFIT_EDEGENERATE = -12,  /**< degenerate geometry (all points coincident, zero length...) */
  BSFIT_ENOTPERIODIC = -13, /**< a periodic curve's wrapped control points or knot spans do not repeat */
  BSFIT_ERANGE = -14,       /**< a finite value beyond the documented range (BSFIT_COORD_MAX,
                                 BSFIT_WEIGHT_MIN/MAX), or a result that would overflow */
  BSFIT_ESINGULAR = -20,    /**< singular system */
  BSFIT_ENOTSPD = -21,      /**< normal matrix not positive definite */
  BSFIT_ENOCONV = -22,      /**< an iteration did not converge */
  BSFIT_ELAPACK = -23,      /**< LAPACK rejected an argument (a bug: please report) */
  BSFIT_EEMPTYSPAN = -24,   /**< a knot span holds no data (Schoenberg-Whitney fails) */
  BSFIT_EIO = -30,          /**< a file could not be read or written */
  BSFIT_EFORMAT = -31,      /**< a file or string is malformed */
  BSFIT_EINTR = -40         /**< interrupted by the host */
} bsfit_err;

#define BSFIT_STATUS_MSG_SIZE 160

/** Where a fallible call reports what went wrong. Fill-in only, no allocation. */
typedef struct bsfit_status {
  bsfit_err code;
  char msg[BSFIT_STATUS_MSG_SIZE];
} bsfit_status;

/** A static string naming a code's meaning, e.g. "knots are decreasing". Never NULL. */
BSFIT_API const char *bsfit_strerror(bsfit_err code);
/** A stable short name for a code, e.g. "ESINGULAR" (used by the Lua fail triple). */
BSFIT_API const char *bsfit_errname(bsfit_err code);

/* }==================================================================== */

/* {====================================================================
** Memory
** ===================================================================== */

/** An allocator with lua_Alloc's contract: nsize == 0 frees and returns NULL;
** otherwise returns a block of nsize bytes (or NULL on failure), preserving
** min(osize, nsize) bytes of ptr. osize is the exact size of ptr's block. */
typedef void *(*bsfit_alloc_fn)(void *ud, void *ptr, size_t osize, size_t nsize);

/** The context a long computation runs in: where its memory comes from (so a host's
** memory cap counts scratch memory too) and a flag the host may set, from another
** thread or a signal handler, to stop it. Loops that can run long (fits, projections,
** filters of millions of points) look at `*interrupt` every few thousand iterations
** and return BSFIT_EINTR when it is non-zero. Zero-initialise what you do not use. */
typedef struct bsfit_allocator {
  bsfit_alloc_fn fn; /**< NULL means the C library's realloc/free */
  void *ud;
  const volatile int *interrupt; /**< NULL: never interrupted */
} bsfit_allocator;

/* }==================================================================== */

/* {====================================================================
** Knot vectors
** A knot vector is `double U[nknots]`; with degree p and n control points,
** nknots = n + p + 1 and the domain is [U[p], U[n]].
** ===================================================================== */

/** Checks a knot vector for degree p and n control points: 0 <= p <= BSFIT_MAX_DEGREE,
** n >= p+1, nknots == n+p+1, all finite, non-decreasing, no knot with multiplicity
** above p+1, and a non-empty domain U[p] < U[n].
** @return BSFIT_OK, BSFIT_EDEGREE, BSFIT_ENKNOTS, BSFIT_ENONFINITE, BSFIT_EKNOTS_DECR,
**         BSFIT_EMULT or BSFIT_EDOMAIN. */
BSFIT_API bsfit_err bsfit_knots_validate(const double *U, size_t nknots, int p, size_t n,
                                         bsfit_status *st);

/** Index s of the knot span holding u, p <= s <= n-1, with U[s] <= u < U[s+1]
** (binary search); u at or beyond the domain's end gives the last non-empty span,
** u before the domain gives the first (the curve is extrapolated by its end
** polynomials). U must be valid (bsfit_knots_validate). */
BSFIT_API size_t bsfit_knots_find_span(const double *U, size_t n, int p, double u);

/** Number of knots exactly equal to u. U must be non-decreasing (as every valid knot vector
** is): the run of equal knots is found by bisection, O(log nknots + multiplicity). */
BSFIT_API int bsfit_knots_multiplicity(const double *U, size_t nknots, double u);

/** Domain [U[p], U[n]] of a knot vector. */
BSFIT_API void bsfit_knots_domain(const double *U, size_t n, int p, double *a, double *b);

/** Uniform (unclamped) knots for degree p and n control points, with domain [a, b]:
** U[i] = a + (i-p) h, h = (b-a)/(n-p). @param[out] U  n+p+1 knots.
** @return BSFIT_OK, BSFIT_EDEGREE (n < p+1 or p out of range) or BSFIT_EDOMAIN (a >= b, non-finite). */
BSFIT_API bsfit_err bsfit_knots_uniform(int p, size_t n, double a, double b, double *U,
                                        bsfit_status *st);

/** Open-uniform (clamped) knots: p+1 copies of a, n-p-1 equally spaced interior
** knots, p+1 copies of b. Same as seed 001's order-d formula scaled to [a,b].
** @param[out] U n+p+1 knots. @return as bsfit_knots_uniform. */
BSFIT_API bsfit_err bsfit_knots_clamped(int p, size_t n, double a, double b, double *U,
                                        bsfit_status *st);

/** Expanded periodic knot vector (docs/method.md §1) for N distinct control points.
** @param[in]  period  N+1 non-decreasing knots t[0] < ... < t[N] of one period
**                     (strictly increasing ends: t[0] < t[N]).
** @param[out] U       N+2p+1 knots: U[p+i] = t[i] for i = 0..N, the spans before and
**                     after repeating the period's spans, so the domain is [t[0], t[N]].
** @return BSFIT_OK, BSFIT_EDEGREE (p < 1 or N < p+1... see below), BSFIT_EKNOTS_DECR,
**         BSFIT_ENONFINITE or BSFIT_EDOMAIN. N must be >= p+1 and >= 2. */
BSFIT_API bsfit_err bsfit_knots_periodic(int p, size_t N, const double *period, double *U,
                                         bsfit_status *st);

/* }==================================================================== */

/* {====================================================================
** Basis functions
** ===================================================================== */

/** The p+1 non-zero B-spline basis functions at u in span s (NURBS Book A2.2):
** N[j] = N_{s-p+j,p}(u), j = 0..p. 0/0 is taken as 0. No allocation. */
BSFIT_API void bsfit_basis_funs(size_t s, double u, int p, const double *U, double *N);

/** Basis functions and their derivatives up to order nd (NURBS Book A2.3):
** ders[k*(p+1)+j] = d^k/du^k N_{s-p+j,p}(u), k = 0..nd. Orders above p are 0.
** @param[out] ders (nd+1)*(p+1) doubles. nd must be <= BSFIT_MAX_DEGREE. */
BSFIT_API void bsfit_basis_ders(size_t s, double u, int p, int nd, const double *U,
                                double *ders);

/** All n+1 Bernstein polynomials B_{k,n}(u), k = 0..n (triangular scheme, no division). */
BSFIT_API void bsfit_bernstein(int n, double u, double *B);

/* }==================================================================== */

/* {====================================================================
** Curves: B-spline, NURBS, Bézier (polynomial or rational), open or periodic
** ===================================================================== */

/** A curve. The fields are public for reading; modify them only through the API.
**
** - Control points are Cartesian (row-major, `dim` doubles each); when `weights`
**   is not NULL the curve is rational (NURBS / rational Bézier) with one positive
**   weight per control point.
** - `bezier` curves have n = degree+1 control points and knots [0]*(p+1), [1]*(p+1)
**   (or another [a,b]); they are evaluated by de Casteljau.
** - `periodic` curves are stored expanded (docs/method.md §1): n = N+p control points whose
**   last p repeat the first p, and n+p+1 knots whose spans repeat with the period.
**   bsfit_curve_distinct(c) == N. Operations keep that form.
*/
typedef struct bsfit_curve {
  int degree;         /**< p >= 0 (>= 1 for periodic) */
  int dim;            /**< 1..4 */
  int periodic;       /**< expanded periodic form */
  int bezier;         /**< single-span Bézier */
  size_t n;           /**< number of stored control points */
  double *knots;      /**< n + degree + 1 knots */
  double *ctrl;       /**< n * dim coordinates */
  double *weights;    /**< n weights, or NULL for a polynomial curve */
  bsfit_allocator alloc; /**< what knots/ctrl/weights were allocated with */
} bsfit_curve;

/** Sets c to the empty curve (safe to free, to pass as an output). */
BSFIT_API void bsfit_curve_init(bsfit_curve *c);

/** Frees what c owns and re-initialises it. NULL-safe, idempotent. */
BSFIT_API void bsfit_curve_free(bsfit_curve *c);

/** Allocates c's arrays for the given shape (contents zero; knots unset, weights
** only if rational). Any previous content of c is freed first, so c MUST be
** initialised (bsfit_curve_init) or hold a curve: an uninitialised struct crashes. The caller fills the
** arrays, then should call bsfit_curve_validate.
** @return BSFIT_OK, BSFIT_EDIM, BSFIT_EDEGREE, BSFIT_EINVAL (n == 0 or overflow), BSFIT_ENOMEM. */
BSFIT_API bsfit_err bsfit_curve_alloc(bsfit_curve *c, int degree, int dim, size_t n,
                                      int rational, const bsfit_allocator *a, bsfit_status *st);

/** Builds a B-spline or NURBS curve by copying the arrays (the caller keeps theirs).
** @param[in] knots    n+degree+1 knots, or NULL for clamped uniform knots on [0,1].
** @param[in] ctrl     n*dim coordinates.
** @param[in] weights  n positive weights, or NULL (polynomial).
** @param[in] periodic 0, or 1 if the arrays are already in expanded periodic form
**                     (checked: the last p points repeat the first p, spans repeat).
** c must be initialised (bsfit_curve_init) or hold a curve, which is freed first.
** On error c is left empty.
** @return BSFIT_OK or any code of bsfit_curve_validate, BSFIT_ENOMEM. */
BSFIT_API bsfit_err bsfit_curve_new(bsfit_curve *c, int degree, int dim, size_t n,
                                    const double *knots, const double *ctrl,
                                    const double *weights, int periodic,
                                    const bsfit_allocator *a, bsfit_status *st);

/** Builds a closed (periodic) curve from N distinct control points and one period of
** knots (N+1 values, see bsfit_knots_periodic; NULL = uniform on [0,1]).
** @param[in] weights N positive weights or NULL. */
BSFIT_API bsfit_err bsfit_curve_new_periodic(bsfit_curve *c, int degree, int dim, size_t N,
                                             const double *period, const double *ctrl,
                                             const double *weights,
                                             const bsfit_allocator *a, bsfit_status *st);

/** Builds a (rational) Bézier curve of degree n-1 on [0,1] from n control points. */
BSFIT_API bsfit_err bsfit_curve_new_bezier(bsfit_curve *c, int dim, size_t n,
                                           const double *ctrl, const double *weights,
                                           const bsfit_allocator *a, bsfit_status *st);

/** Checks every invariant of c (knots, finite coordinates, positive finite weights,
** Bézier shape, periodic repetition).
** @return BSFIT_OK; a code of bsfit_knots_validate; BSFIT_ENONFINITE; BSFIT_ERANGE (a
**         coordinate beyond BSFIT_COORD_MAX in magnitude); BSFIT_EWEIGHT (a weight not in
**         [BSFIT_WEIGHT_MIN, BSFIT_WEIGHT_MAX]); BSFIT_EINVAL (Bézier shape);
**         BSFIT_ENOTPERIODIC; BSFIT_EMULT (a closed curve with a knot of multiplicity
**         above its degree, the seam included). */
BSFIT_API bsfit_err bsfit_curve_validate(const bsfit_curve *c, bsfit_status *st);

/** Deep copy src into dst (dst's previous content is freed; allocator a, or src's if NULL).
** src and dst must differ. */
BSFIT_API bsfit_err bsfit_curve_copy(const bsfit_curve *src, bsfit_curve *dst,
                                     const bsfit_allocator *a, bsfit_status *st);

/** Moves src's arrays into dst (dst freed first), leaving src empty. */
BSFIT_API void bsfit_curve_move(bsfit_curve *src, bsfit_curve *dst);

/** Domain [a, b] of the curve (for periodic curves: one period). */
BSFIT_API void bsfit_curve_domain(const bsfit_curve *c, double *a, double *b);

/** Number of distinct control points (n - p for periodic curves, n otherwise). */
BSFIT_API size_t bsfit_curve_distinct(const bsfit_curve *c);

/** Point C(u). u outside the domain: extrapolated for open curves, up to one domain
** length beyond either end (farther out the end polynomials lose their digits), wrapped
** into the period for periodic ones. @param[out] out dim doubles.
** @return BSFIT_OK, BSFIT_ENONFINITE (u not finite), BSFIT_EDOMAIN (an open curve's u more
**         than one domain length outside the domain), BSFIT_ERANGE (the extrapolated
**         point overflows). */
BSFIT_API bsfit_err bsfit_curve_eval(const bsfit_curve *c, double u, double *out,
                                     bsfit_status *st);

/* }==================================================================== */

#include "bsfit_curve_ops.h"
#include "bsfit_surface.h"
#include "bsfit_fit.h"
#include "bsfit_filter.h"
#include "bsfit_io.h"
#include "bsfit_geom.h"
#include "bsfit_analysis.h"
#include "bsfit_scan.h"
#include "bsfit_features.h"

#ifdef __cplusplus
}
#endif

#endif /* BSFIT_H */
