/*
** curve_geom.c
** Geometry on a curve: arc length (Gauss-Legendre per span, subdivided until two
** estimates agree), closest point (coarse sampling, then a Newton descent on
** f(u) = C'(u).(C(u) - P) that never lets the distance grow), projection of many points
** from given starting parameters, and uniform sampling.
*/
#include "curve_ops_internal.h"
#include "quadrature.h"

#include <float.h>
#include <math.h>
#include <string.h>

#define GL_ORDER 16         /* Gauss-Legendre points per interval */
#define LEN_RTOL 1e-12      /* relative agreement of two length estimates */
#define LEN_MAX_DEPTH 12    /* at most 2^12 sub-intervals per span */
#define CLOSEST_SAMPLES 8   /* coarse samples per span */
#define NEWTON_MAX_ITERS 60 /* closest point: Newton steps */
#define HALVINGS 30         /* step halvings before a Newton step is given up */

/* {====================================================================
** Arc length
** ===================================================================== */

typedef struct len_ctx {
  const bsfit_curve *c;
  size_t s; /* the span being integrated */
  double x[GL_ORDER], w[GL_ORDER];
} len_ctx;

/* |C'(u)|, scaled like hypot: squares of a curve 1e-200 across underflowed to a length 0 */
static double speed(const len_ctx *L, double u) {
  double D[2 * 4], v = 0.0, big = 0.0;
  size_t q, d = (size_t)L->c->dim;
  bsfit__curve_derivs_span(L->c, L->s, u, 1, D);
  for (q = 0; q < d; q++) big = fmax(big, fabs(D[d + q]));
  if (big == 0.0) return 0.0;
  for (q = 0; q < d; q++) v += (D[d + q] / big) * (D[d + q] / big);
  return big * sqrt(v);
}

static double gl_integral(const len_ctx *L, double lo, double hi) {
  double h = 0.5 * (hi - lo), mid = 0.5 * (hi + lo), sum = 0.0;
  int i;
  for (i = 0; i < GL_ORDER; i++) sum += L->w[i] * speed(L, mid + h * L->x[i]);
  return h * sum;
}

/* The length over [lo, hi] to within tol (absolute: the span's share of LEN_RTOL of its
** length, but no less than the rounding of the curve's coordinates, halved with each
** split). A tolerance relative to each piece alone made a curve 3e-11 long at
** coordinates near 3.5 (its speed all rounding noise) split every span to the last
** level, 2^12 pieces: 33 ms a call, 7.7 s to join the 762 pieces of one mesh loop. */
static double adaptive_length(const len_ctx *L, double lo, double hi, double whole, double tol,
                              int depth) {
  double mid = 0.5 * (lo + hi), left = gl_integral(L, lo, mid), right = gl_integral(L, mid, hi);
  double both = left + right;
  if (depth >= LEN_MAX_DEPTH || fabs(both - whole) <= tol) return both;
  return adaptive_length(L, lo, mid, left, 0.5 * tol, depth + 1) +
         adaptive_length(L, mid, hi, right, 0.5 * tol, depth + 1);
}

bsfit_err bsfit_curve_length(const bsfit_curve *c, double a, double b, double *len,
                             bsfit_status *st) {
  len_ctx L;
  double da, db, total = 0.0, noise = 0.0;
  size_t s;
  bsfit_err e = bsfit_curve_validate(c, st);
  if (e != BSFIT_OK) return e;
  if (len == NULL) return bsfit__fail(st, BSFIT_EINVAL, "no output for the length");
  if (!isfinite(a) || !isfinite(b))
    return bsfit__fail(st, BSFIT_ENONFINITE, "length interval [%g, %g] is not finite", a, b);
  bsfit_curve_domain(c, &da, &db);
  if (a > b || a < da || b > db)
    return bsfit__fail(st, BSFIT_EDOMAIN, "length interval [%g, %g] not an interval of [%g, %g]",
                       a, b, da, db);
  L.c = c;
  bsfit__gauss_legendre(GL_ORDER, L.x, L.w);
  for (s = 0; s < c->n * (size_t)c->dim; s++) noise = fmax(noise, fabs(c->ctrl[s]));
  noise *= 64.0 * DBL_EPSILON;
  for (s = (size_t)c->degree; s < c->n; s++) {
    double lo = fmax(a, c->knots[s]), hi = fmin(b, c->knots[s + 1]), whole;
    if (!(lo < hi)) continue;
    L.s = s;
    whole = gl_integral(&L, lo, hi);
    total += adaptive_length(&L, lo, hi, whole, fmax(LEN_RTOL * fabs(whole), noise), 0);
  }
  *len = total;
  return bsfit__ok(st);
}

/* }==================================================================== */

/* {====================================================================
** Closest point and projection
** ===================================================================== */

/* The searches compare squared distances: a curve whose control points all lie within
** BSFIT_EXTENT_MIN of each other (but not on one point) would have them underflow to 0
** and every sample would look as close as the next. Refused rather than answered. */
#define BSFIT_EXTENT_MIN 1e-100

static bsfit_err check_extent(const bsfit_curve *c, bsfit_status *st) {
  size_t i, k, d = (size_t)c->dim;
  double ext = 0.0;
  for (i = 1; i < c->n; i++)
    for (k = 0; k < d; k++) ext = fmax(ext, fabs(c->ctrl[i * d + k] - c->ctrl[k]));
  if (ext > 0.0 && ext < BSFIT_EXTENT_MIN)
    return bsfit__fail(st, BSFIT_ERANGE,
                       "the curve is %g across, below 1e-100: its squared distances would "
                       "underflow (scale the data)",
                       ext);
  return BSFIT_OK;
}

/* Where a parameter may go: [lo, hi], clamped for open curves; periodic curves are
** evaluated at any u (wrapped) and only the final answer is wrapped. A polynomial cubic
** is evaluated span by span as a polynomial (`polys`: converted on a span's first use),
** so an evaluation is a cached span lookup and three Horner sums, not three basis
** recursions and a binary search. Other curves go through the basis derivatives. */
typedef struct span_polys {
  double *coef;         /* per span s >= 3: 4 dim coefficients (bsfit__cubic_span_poly) */
  unsigned char *ready; /* per span: converted yet */
  size_t bytes;         /* of the block holding both */
  const bsfit_allocator *a; /* what coef was allocated with */
} span_polys;

typedef struct foot_ctx {
  const bsfit_curve *c;
  const double *P;
  double lo, hi;
  span_polys *poly; /* NULL: the basis path */
  size_t s;         /* the last span used */
  double a, b;      /* the domain */
  int corners;      /* some knot has multiplicity >= degree (C0 or less) inside */
} foot_ctx;

/* whether c has a knot of multiplicity >= degree (a corner is possible there) inside its
** domain (an open curve's clamped ends are none) */
static int has_corners(const bsfit_curve *c) {
  size_t j, run = 1, nk = c->n + (size_t)c->degree + 1;
  double a, b;
  if (c->degree <= 1) return 1; /* every knot */
  bsfit_curve_domain(c, &a, &b);
  for (j = 1; j < nk; j++) {
    run = c->knots[j] == c->knots[j - 1] ? run + 1 : 1;
    if ((int)run >= c->degree && (c->periodic || (c->knots[j] > a && c->knots[j] < b)))
      return 1;
  }
  return 0;
}

static void foot_init(foot_ctx *F, const bsfit_curve *c, span_polys *poly) {
  F->c = c;
  F->P = NULL;
  F->poly = poly;
  F->s = (size_t)c->degree;
  bsfit_curve_domain(c, &F->a, &F->b);
  F->corners = has_corners(c);
}

/* Room for the span polynomials of a polynomial cubic; NULL when c is not one or out of
** memory (the basis path then serves). Free with polys_free. */
static span_polys *polys_new(const bsfit_curve *c, const bsfit_allocator *a, span_polys *sp) {
  size_t n = c->n, d = (size_t)c->dim;
  if (c->degree != 3 || c->weights != NULL || c->bezier) return NULL;
  sp->a = a;
  sp->bytes = n * 4 * d * sizeof(double) + n;
  sp->coef = bsfit__alloc(a, sp->bytes);
  if (sp->coef == NULL) return NULL;
  sp->ready = (unsigned char *)(sp->coef + n * 4 * d);
  memset(sp->ready, 0, n);
  return sp;
}

static void polys_free(span_polys *sp) {
  if (sp) bsfit__free(sp->a, sp->coef, sp->bytes);
}

/* C, C', C'' at u in span s from the span's polynomial (d: the dimension). */
#if defined(__GNUC__)
__attribute__((always_inline))
#endif
static inline void poly_derivs_d(foot_ctx *F, size_t s, double u, double *D, const size_t d) {
  const double *U = F->c->knots, *cf = F->poly->coef + s * 4 * d;
  double hinv = 1.0 / (U[s + 1] - U[s]), t = (u - U[s]) * hinv;
  size_t q;
  if (!F->poly->ready[s]) {
    bsfit__cubic_span_poly(F->c, s, F->poly->coef + s * 4 * d);
    F->poly->ready[s] = 1;
  }
  for (q = 0; q < d; q++) {
    double c0 = cf[q], c1 = cf[d + q], c2 = cf[2 * d + q], c3 = cf[3 * d + q];
    D[q] = ((c3 * t + c2) * t + c1) * t + c0;
    D[d + q] = ((3.0 * c3 * t + 2.0 * c2) * t + c1) * hinv;
    D[2 * d + q] = (6.0 * c3 * t + 2.0 * c2) * hinv * hinv;
  }
}

static void poly_derivs(foot_ctx *F, size_t s, double u, double *D) {
  if (F->c->dim == 2) poly_derivs_d(F, s, u, D, 2); /* sections: unrolled */
  else poly_derivs_d(F, s, u, D, (size_t)F->c->dim);
}

#if defined(__GNUC__)
#  define GEOM_INLINE static inline __attribute__((always_inline))
#else
#  define GEOM_INLINE static inline
#endif

/* Where u is evaluated: *w, u wrapped into the period (periodic), in span F->s, set
** here: the same span as the last evaluation, or a neighbour (samples in order, Newton's
** steps), before a search over all the knots. */
GEOM_INLINE size_t foot_span(foot_ctx *F, double u, double *w) {
  const bsfit_curve *c = F->c;
  const double *U = c->knots;
  size_t s = F->s;
  *w = (u >= F->a && u < F->b) ? u : bsfit__curve_wrap(c, u);
  if (!(*w >= U[s] && *w < U[s + 1])) {
    if (s + 1 < c->n && *w >= U[s + 1] && *w < U[s + 2]) s++;
    else if (s > (size_t)c->degree && *w >= U[s - 1] && *w < U[s]) s--;
    else s = bsfit_knots_find_span(U, c->n, c->degree, *w);
  }
  F->s = s;
  return s;
}

/* C, C', C'' at u (D: 3*dim) and |C(u) - P|^2. `poly2`: the curve is 2D and F->poly is
** set, a constant in the instances below, so the hot case compiles to straight code. */
GEOM_INLINE double foot_eval(foot_ctx *F, double u, double *D, const int poly2) {
  const bsfit_curve *c = F->c;
  size_t q, d = poly2 ? 2 : (size_t)c->dim;
  double w, d2 = 0.0;
  size_t s = foot_span(F, u, &w);
  if (poly2) poly_derivs_d(F, s, w, D, 2);
  else if (F->poly) poly_derivs(F, s, w, D);
  else bsfit__curve_derivs_span(c, s, w, 2, D);
  for (q = 0; q < d; q++) d2 += (D[q] - F->P[q]) * (D[q] - F->P[q]);
  return d2;
}

static double clampd(double u, double lo, double hi) { return u < lo ? lo : (u > hi ? hi : u); }

/* g(u) = C'.(C - P) from D = (C, C', C'') */
GEOM_INLINE double slope(const foot_ctx *F, const double *D, const int poly2) {
  size_t q, d = poly2 ? 2 : (size_t)F->c->dim;
  double g = 0.0;
  for (q = 0; q < d; q++) g += D[d + q] * (D[q] - F->P[q]);
  return g;
}

/* Newton on g(u) = C'.(C-P), g' = C''.(C-P) + |C'|^2, inside [lo, hi]; a step that
** would increase the distance is halved until it does not, so the result is never
** worse than the start. Returns the parameter, *d2 its squared distance. */
GEOM_INLINE double newton_body(foot_ctx *F, double u, int iters, double *d2, const int poly2) {
  double D[3 * 4], cur = foot_eval(F, u, D, poly2), scale = F->hi - F->lo;
  size_t q, d = poly2 ? 2 : (size_t)F->c->dim;
  int it, k;
  for (it = 0; it < iters; it++) {
    double g = 0.0, gp = 0.0, step, un = u, dn = cur, Dn[3 * 4];
    for (q = 0; q < d; q++) {
      double r = D[q] - F->P[q];
      g += D[d + q] * r;
      gp += D[2 * d + q] * r + D[d + q] * D[d + q];
    }
    if (g == 0.0) break;
    /* where g' <= 0 Newton points the wrong way: walk downhill instead */
    step = gp > 0.0 ? -g / gp : (g > 0.0 ? -0.05 : 0.05) * scale;
    /* converged: Newton's error is about its step, so the foot is this close to u and the
    ** distance exact to the square of it; evaluating the step would not change them */
    if (gp > 0.0 && fabs(step) <= 1e-13 * (fabs(u) + scale)) break;
    for (k = 0; k <= HALVINGS; k++, step *= 0.5) {
      un = clampd(u + step, F->lo, F->hi);
      dn = foot_eval(F, un, Dn, poly2);
      /* near the foot the distance changes below its rounding: there a step that
      ** shrinks |g| is taken as long as the distance stays level */
      if (dn <= cur || (dn <= cur * (1.0 + 1e-12) && fabs(slope(F, Dn, poly2)) < 0.5 * fabs(g)))
        break;
    }
    if (k > HALVINGS || un == u) break;
    memcpy(D, Dn, 3 * d * sizeof(double));
    cur = dn;
    if (fabs(un - u) <= 1e-15 * (fabs(u) + scale)) {
      u = un;
      break;
    }
    u = un;
  }
  *d2 = cur;
  return u;
}

static double foot_newton(foot_ctx *F, double u, int iters, double *d2) {
  if (F->poly && F->c->dim == 2) return newton_body(F, u, iters, d2, 1);
  return newton_body(F, u, iters, d2, 0);
}

/* the samples of the closest-point searches: C(u) and its derivatives into D (3*dim
** doubles); returns |C(u) - F->P|^2 */
static double sample_at(foot_ctx *F, double u, double *D) { return foot_eval(F, u, D, 0); }

/* C(u) alone into x (dim doubles), as sample_at computes it: a polynomial cubic's span by
** the same Horner sum (its derivatives, which sampling does not need, are two thirds of
** the work), any other curve through sample_at. */
static void sample_point(foot_ctx *F, double u, double *x) {
  double D[3 * 4], w;
  size_t q, d = (size_t)F->c->dim, s;
  if (F->poly == NULL) {
    (void)sample_at(F, u, D);
    memcpy(x, D, d * sizeof(double));
    return;
  }
  s = foot_span(F, u, &w);
  {
    const double *U = F->c->knots, *cf = F->poly->coef + s * 4 * d;
    double hinv = 1.0 / (U[s + 1] - U[s]), t = (w - U[s]) * hinv;
    if (!F->poly->ready[s]) {
      bsfit__cubic_span_poly(F->c, s, F->poly->coef + s * 4 * d);
      F->poly->ready[s] = 1;
    }
    for (q = 0; q < d; q++)
      x[q] = ((cf[3 * d + q] * t + cf[2 * d + q]) * t + cf[d + q]) * t + cf[q];
  }
}

/* Newton from the best sample v (step h apart from its neighbours). At a knot where the
** curve may turn (multiplicity >= degree: C0 or less) the derivative seen from one side
** cannot lead to a foot on the other: there the descent also starts half a sample step
** to either side, and the nearest of the three feet wins. */
static double closest_from_start(foot_ctx *F, double v, double h, int maybe_knot, double *d2) {
  const bsfit_curve *c = F->c;
  double u = foot_newton(F, v, NEWTON_MAX_ITERS, d2);
  int side;
  if (!maybe_knot ||
      bsfit_knots_multiplicity(c->knots, c->n + (size_t)c->degree + 1, v) < c->degree)
    return u;
  for (side = -1; side <= 1; side += 2) {
    double e2, w = v + 0.5 * h * side, x;
    if (w < F->lo || w > F->hi) continue;
    x = foot_newton(F, w, NEWTON_MAX_ITERS, &e2);
    if (e2 < *d2) *d2 = e2, u = x;
  }
  return u;
}

/* The knots of c where it may turn (multiplicity >= degree: C0 or less) inside [lo, hi],
** at most `max` of them, into cut (distinct values, increasing); returns their number. */
static size_t corner_knots(const bsfit_curve *c, double lo, double hi, double *cut, size_t max) {
  const double *U = c->knots;
  size_t nk = c->n + (size_t)c->degree + 1, j = 0, k = 0, hi_j = nk;
  while (hi_j - j > 1) { /* the first knot >= lo, by bisection */
    size_t mid = j + (hi_j - j) / 2;
    if (U[mid - 1] < lo) j = mid;
    else hi_j = mid;
  }
  if (j < nk && U[j] < lo) j++;
  while (j < nk && U[j] <= hi && k < max) {
    size_t r = j;
    while (r < nk && U[r] == U[j]) r++;
    if ((int)(r - j) >= c->degree) cut[k++] = U[j];
    j = r;
  }
  return k;
}

#define CORNER_CUTS 8 /* corners in one bracket looked at, at most */

/* A sample at a knot brackets its search by its own span's step; the span on the knot's
** other side may be far longer (a corner between a short span and a long one), its foot
** beyond that step. [*lo, *hi] is widened to a sample step of the span on either side. */
static void widen_at_knot(const foot_ctx *F, double v, double *lo, double *hi) {
  const bsfit_curve *c = F->c;
  const double *U = c->knots;
  size_t p = (size_t)c->degree, s = bsfit_knots_find_span(U, c->n, c->degree, v), j = s;
  if (v != U[s] && v != U[s + 1]) return;
  *hi = fmax(*hi, v + (U[s + 1] - U[s]) / CLOSEST_SAMPLES);
  while (j > 0 && U[j - 1] == U[s]) j--;
  if (j > 0 && j > p - 1) *lo = fmin(*lo, v - (U[s] - U[j - 1]) / CLOSEST_SAMPLES);
  if (!c->periodic) {
    *lo = fmax(*lo, F->a);
    *hi = fmin(*hi, F->b);
  }
}

/* Newton from the nearest sample v (step h apart from its neighbours) inside the bracket
** [F->lo, F->hi]. Newton sees the derivative on one side of a corner only, and a step that
** lands across it with a smaller distance carries the descent to the wrong side: near a
** corner of a curve (auto's C0 knots) the foot came back up to 10 times too far. So when
** the bracket holds a corner, the descent also runs in each piece between corners, kept
** inside it, from its ends and its middle; the nearest foot of all wins, never
** worse than the unrestricted descent, which still runs first (bit for bit the answer on
** curves without corners, whose brackets hold none). */
static double closest_from(foot_ctx *F, double v, double h, int maybe_knot, double *d2) {
  double cut[CORNER_CUTS + 2], lo = F->lo, hi = F->hi, u;
  size_t nc, i;
  u = closest_from_start(F, v, h, maybe_knot, d2);
  if (!F->corners) return u;
  widen_at_knot(F, v, &lo, &hi);
  nc = corner_knots(F->c, lo, hi, cut + 1, CORNER_CUTS);
  if (nc == 0) return u;
  cut[0] = lo;
  cut[nc + 1] = hi;
  for (i = 0; i <= nc; i++) {
    double a = cut[i], b = cut[i + 1], e2, x;
    int k;
    if (!(b > a)) continue;
    F->lo = a;
    F->hi = b;
    /* from both ends and the middle (a piece may hold a second basin); at a knot the
    ** curve is evaluated in the span after it, so the piece that ends there starts just
    ** before it, where the derivative is its own */
    for (k = 0; k < 3; k++) {
      x = foot_newton(F, k == 0 ? a : (k == 1 ? 0.5 * (a + b) : b - 1e-9 * (b - a)),
                      NEWTON_MAX_ITERS, &e2);
      if (e2 < *d2) *d2 = e2, u = x;
    }
  }
  F->lo = lo;
  F->hi = hi;
  return u;
}

/* A sliver piece (between knots 1e-13 apart, as auto leaves at corners) spans a few
** thousand doubles, and Newton's test of convergence, relative to |u|, stops anywhere in
** it: there the descent goes on a double at a time, in strides that double while the
** distance falls (a piece that polish is called on has one minimum, or is tiny). */
static double ulp_descent(foot_ctx *F, double u, double *d2) {
  double D[3 * 4];
  int dir, k;
  for (dir = -1; dir <= 1; dir += 2) {
    double one = fabs(nextafter(u, dir < 0 ? -INFINITY : INFINITY) - u), step = one;
    for (k = 0; k < 256; k++) {
      double x = clampd(u + (double)dir * step, F->lo, F->hi), e2;
      if (x == u) break;
      e2 = sample_at(F, x, D);
      if (e2 < *d2) {
        u = x, *d2 = e2, step *= 2.0;
      } else if (step > one) {
        step = one;
      } else {
        break;
      }
    }
  }
  return u;
}

/* The global stage's Newton: inside [lo, hi] only, from u0. The curve at hi is evaluated
** in the span after it, whose derivative at a corner leads elsewhere (a descent that
** reached it stopped there, beside the piece's own minimum): the piece ends one double
** before hi, and the next piece, which starts at hi, holds that point. */
static double polish(void *ctx, double lo, double hi, double u0, double *d2) {
  foot_ctx *F = ctx;
  double slo = F->lo, shi = F->hi, u;
  F->lo = lo;
  F->hi = hi > lo ? nextafter(hi, lo) : hi;
  u = foot_newton(F, clampd(u0, F->lo, F->hi), NEWTON_MAX_ITERS, d2);
  if (hi - lo <= 1e-6 * (fabs(lo) + fabs(hi))) u = ulp_descent(F, u, d2);
  F->lo = slo;
  F->hi = shi;
  return u;
}

/* The foot of F->P from the nearest sample v (step h), then proved the nearest or
** replaced by the global stage (closest_pieces.c). */
static double closest_global(foot_ctx *F, bsfit__pieces *pc, double v, double h,
                             int maybe_knot, double *d2) {
  double u = closest_from(F, v, h, maybe_knot, d2);
  bsfit__pieces_search(pc, F->P, &u, d2, u > F->lo && u < F->hi, polish, F);
  return u;
}

bsfit_err bsfit_curve_closest(const bsfit_curve *c, const double *P, double *u, double *dist,
                              const bsfit_allocator *al, bsfit_status *st) {
  foot_ctx F;
  span_polys sp;
  bsfit__pieces pc;
  double a, b, D[3 * 4], best = INFINITY, ubest = 0.0, hbest = 0.0, d2;
  size_t s, i, p;
  bsfit_err e = bsfit_curve_validate(c, st);
  if (e == BSFIT_OK) e = check_extent(c, st);
  if (e != BSFIT_OK) return e;
  if (P == NULL || u == NULL) return bsfit__fail(st, BSFIT_EINVAL, "no point or no output");
  if (!bsfit__all_finite(P, (size_t)c->dim))
    return bsfit__fail(st, BSFIT_ENONFINITE, "point P is not finite");
  bsfit_curve_domain(c, &a, &b);
  p = (size_t)c->degree;
  e = bsfit__pieces_init(&pc, c, al, st);
  if (e != BSFIT_OK) return e;
  foot_init(&F, c, polys_new(c, al, &sp));
  F.P = P;
  F.lo = a;
  F.hi = b;
  /* coarse samples, then a bracket of one sample step either side of the best */
  for (s = p; s < c->n; s++) {
    double h = (c->knots[s + 1] - c->knots[s]) / CLOSEST_SAMPLES;
    for (i = 0; h > 0 && i <= CLOSEST_SAMPLES; i++) {
      double v = c->knots[s] + h * (double)i, dv = sample_at(&F, v, D);
      if (dv < best || hbest == 0.0) { /* the first sample stands even if every distance
                                        ** overflows, as in bsfit_curve_closest_many */
        best = dv;
        ubest = v;
        hbest = h;
        F.lo = v - h;
        F.hi = v + h;
      }
    }
  }
  if (!c->periodic) {
    F.lo = fmax(F.lo, a);
    F.hi = fmin(F.hi, b);
  }
  ubest = closest_global(&F, &pc, ubest, hbest, 1, &d2);
  *u = bsfit__curve_wrap(c, ubest);
  if (dist) *dist = sqrt(d2);
  polys_free(F.poly);
  bsfit__pieces_free(&pc);
  return bsfit__ok(st);
}

/* One curve, many points: the same samples, bracket and Newton as bsfit_curve_closest,
** with the samples evaluated once for all the points, and each point's nearest sample
** found through a spatial index (nearest_sample.c) that picks exactly the sample the
** linear scan of bsfit_curve_closest picks, ties included. Sample k is number i = k % S
** (S = CLOSEST_SAMPLES + 1) of the (k / S)-th span of positive length, spans[k / S]: its
** parameter and step are recomputed as they were sampled, not stored (at 10^6 points the
** curve has 4.5 * 10^6 samples). */
typedef struct sample_grid {
  const bsfit_curve *c;
  const size_t *spans; /* the spans of positive length, in order */
} sample_grid;

/* the parameter of sample k and its step h (*h), as the sampling loop computed them */
static double sample_param(const sample_grid *G, size_t k, double *h) {
  const double *U = G->c->knots;
  size_t s = G->spans[k / (CLOSEST_SAMPLES + 1)];
  *h = (U[s + 1] - U[s]) / CLOSEST_SAMPLES;
  return U[s] + *h * (double)(k % (CLOSEST_SAMPLES + 1));
}

/* Newton from each point's nearest sample, looking at the interrupt flag every 4096 */
static bsfit_err closest_loop(foot_ctx *F, bsfit__pieces *pc, const bsfit__nearest *nn,
                              const sample_grid *G,
                              const double *pts, size_t m, double *u, double *dist,
                              const bsfit_allocator *al, bsfit_status *st) {
  const bsfit_curve *c = F->c;
  const double *U = c->knots;
  size_t i, d = (size_t)c->dim;
  for (i = 0; i < m; i++) {
    const double *P = pts + i * d;
    double d2, h, v;
    size_t kb = bsfit__nearest_find(nn, P), s = G->spans[kb / (CLOSEST_SAMPLES + 1)];
    if ((i & 4095) == 4095 && bsfit__interrupted(al))
      return bsfit__fail(st, BSFIT_EINTR, "closest points interrupted at point %zu", i);
    v = sample_param(G, kb, &h);
    F->P = P;
    F->lo = c->periodic ? v - h : fmax(v - h, F->a);
    F->hi = c->periodic ? v + h : fmin(v + h, F->b);
    /* only a span's ends are knots: no other knot lies inside a span */
    u[i] = bsfit__curve_wrap(c, closest_global(F, pc, v, h, v == U[s] || v == U[s + 1], &d2));
    if (dist) dist[i] = sqrt(d2);
  }
  return BSFIT_OK;
}

/* The samples of every span of positive length into smp (K*dim), the spans into spans. */
static void sample_spans(foot_ctx *F, size_t *spans, double *smp) {
  const bsfit_curve *c = F->c;
  size_t s, i, k = 0, g = 0, d = (size_t)c->dim;
  for (s = (size_t)c->degree; s < c->n; s++) {
    double h = (c->knots[s + 1] - c->knots[s]) / CLOSEST_SAMPLES;
    if (!(h > 0)) continue;
    spans[g++] = s;
    for (i = 0; i <= CLOSEST_SAMPLES; i++, k++)
      sample_point(F, c->knots[s] + h * (double)i, smp + k * d);
  }
}

bsfit_err bsfit_curve_closest_many(const bsfit_curve *c, const double *pts, size_t m, double *u,
                                   double *dist, const bsfit_allocator *al, bsfit_status *st) {
  foot_ctx F;
  double *smp;
  size_t s, K = 0, ng = 0, p, d, bytes;
  span_polys sp;
  sample_grid G;
  bsfit__nearest nn;
  bsfit__pieces pc;
  bsfit_err e = bsfit_curve_validate(c, st);
  if (e == BSFIT_OK) e = check_extent(c, st);
  if (e != BSFIT_OK) return e;
  if (m > 0 && (pts == NULL || u == NULL)) return bsfit__fail(st, BSFIT_EINVAL, "no points or no output");
  if (!bsfit__all_finite(pts, m * (size_t)c->dim))
    return bsfit__fail(st, BSFIT_ENONFINITE, "the points contain NaN or Inf");
  if (m == 0) return bsfit__ok(st); /* nothing to sample the curve for */
  p = (size_t)c->degree;
  d = (size_t)c->dim;
  for (s = p; s < c->n; s++)
    if (c->knots[s + 1] > c->knots[s]) ng++;
  K = ng * (CLOSEST_SAMPLES + 1);
  bytes = K * d * sizeof(double) + ng * sizeof(size_t);
  smp = bsfit__alloc(al, bytes);
  if (smp == NULL) return bsfit__fail(st, BSFIT_ENOMEM, "out of memory for %zu samples", K);
  G.c = c;
  G.spans = (size_t *)(void *)(smp + K * d);
  foot_init(&F, c, polys_new(c, al, &sp));
  F.P = pts; /* unused by the sampling below */
  sample_spans(&F, (size_t *)(void *)(smp + K * d), smp);
  e = bsfit__pieces_init(&pc, c, al, st);
  if (e == BSFIT_OK) {
    e = bsfit__nearest_init(&nn, smp, K, d, m, al, st);
    if (e == BSFIT_OK) e = closest_loop(&F, &pc, &nn, &G, pts, m, u, dist, al, st);
    bsfit__nearest_free(&nn);
    bsfit__pieces_free(&pc);
  }
  polys_free(F.poly);
  bsfit__free(al, smp, bytes);
  return e == BSFIT_OK ? bsfit__ok(st) : e;
}

bsfit_err bsfit_curve_project_many(const bsfit_curve *c, const double *pts, size_t m, double *u,
                                   double *dist, int iters, const bsfit_allocator *al,
                                   bsfit_status *st) {
  foot_ctx F;
  double a, b, d2;
  size_t i, d;
  span_polys sp;
  bsfit_err e = bsfit__curve_check(c, st);
  if (e == BSFIT_OK) e = check_extent(c, st);
  if (e != BSFIT_OK) return e;
  if (m > 0 && (pts == NULL || u == NULL))
    return bsfit__fail(st, BSFIT_EINVAL, "no points or no parameters");
  if (iters < 0) return bsfit__fail(st, BSFIT_EINVAL, "iterations = %d is negative", iters);
  d = (size_t)c->dim;
  for (i = 0; i < m; i++) /* all checked before any is moved */
    if (!bsfit__all_finite(pts + i * d, d) || !isfinite(u[i]))
      return bsfit__fail(st, BSFIT_ENONFINITE, "point %zu or its parameter is not finite", i);
  bsfit_curve_domain(c, &a, &b);
  foot_init(&F, c, polys_new(c, al, &sp));
  for (i = 0; i < m; i++) {
    if ((i & 4095) == 4095 && bsfit__interrupted(al)) {
      polys_free(F.poly);
      return bsfit__fail(st, BSFIT_EINTR, "projection interrupted at point %zu", i);
    }
    F.P = pts + i * d;
    /* open: the domain; periodic: one period either side (wrapped at the end) */
    F.lo = c->periodic ? u[i] - (b - a) : a;
    F.hi = c->periodic ? u[i] + (b - a) : b;
    u[i] = bsfit__curve_wrap(c, foot_newton(&F, clampd(u[i], F.lo, F.hi), iters, &d2));
    if (dist) dist[i] = sqrt(d2);
  }
  polys_free(F.poly);
  return bsfit__ok(st);
}

/* }==================================================================== */

/* {====================================================================
** Sampling
** ===================================================================== */

bsfit_err bsfit_curve_sample(const bsfit_curve *c, size_t k, double *out,
                             const bsfit_allocator *al, bsfit_status *st) {
  double ub[256], a, b, steps;
  size_t i, j, d;
  bsfit_err e = bsfit__curve_check(c, st);
  if (e != BSFIT_OK) return e;
  if (k < 2) return bsfit__fail(st, BSFIT_EINVAL, "sampling needs k >= 2 points, got %zu", k);
  if (out == NULL) return bsfit__fail(st, BSFIT_EINVAL, "no output array");
  d = (size_t)c->dim;
  bsfit_curve_domain(c, &a, &b);
  steps = c->periodic ? (double)k : (double)(k - 1);
  /* in chunks through the batch evaluator: no allocation */
  for (i = 0; i < k; i += j) {
    size_t nb = k - i < 256 ? k - i : 256;
    if ((i & 4095) == 0 && i > 0 && bsfit__interrupted(al))
      return bsfit__fail(st, BSFIT_EINTR, "sampling interrupted at sample %zu", i);
    for (j = 0; j < nb; j++) {
      size_t idx = i + j;
      ub[j] = (!c->periodic && idx == k - 1) ? b : a + (b - a) * ((double)idx / steps);
    }
    e = bsfit_curve_eval_many(c, ub, nb, out + i * d, st);
    if (e != BSFIT_OK) return e;
  }
  return bsfit__ok(st);
}

/* }==================================================================== */
