/*
** filter_reduce.c
** A curve brought to a chosen degree q: the L2 projection onto the splines of degree q on
** chosen break points,
**     min over S of  integral over [a, b] of |S(t) - C(t)|^2 dt,
** whose normal equations G x = B have the (banded) Gram matrix G_ij = int N_i N_j of the
** degree-q basis and B_i = int N_i C. Both are computed exactly by Gauss-Legendre
** quadrature on every span of the merged break points of S and C (the integrands are
** polynomials of degree 2q and q + p there); G is solved by banded Cholesky, or for
** a closed curve by the cyclic block elimination of the periodic fitter. Never dense.
** Where the result may be farther than tol from C (the certified bound of filter_bound.c
** first, O(n); where it misses tol, the distance of filter_distance.c: the cheap local
** measure, the global one to confirm) a knot is inserted in the middle of every offending
** span, and the projection repeated.
*/
#include "filter_internal.h"
#include "fit_internal.h"
#include "quadrature.h"

#include <float.h>
#include <math.h>
#include <string.h>

#define DEFAULT_DEGREE 3
#define MAX_GL 64         /* Gauss-Legendre nodes per span, at most */
#define RATIONAL_EXTRA 8  /* more nodes for rational input, whose integrand is not polynomial */
#define DEFAULT_SAMPLES 16
#define MIN_SPAN 1e-6     /* spans narrower than this much of the domain are not split */
#define STALL_ROUNDS 3    /* rounds of knots added that may leave the deviation as it was */

/* {====================================================================
** Break points with multiplicities (the target space)
** ===================================================================== */

void bsfit__breaks_free(const bsfit_allocator *a, bsfit__breaks *b) {
  bsfit__free(a, b->x, b->cap * sizeof(double));
  bsfit__free(a, b->mult, b->cap * sizeof(int));
  memset(b, 0, sizeof *b);
}

bsfit_err bsfit__breaks_reserve(const bsfit_allocator *a, bsfit__breaks *b, size_t cap) {
  double *x;
  int *m;
  if (cap <= b->cap) return BSFIT_OK;
  x = bsfit__alloc(a, cap * sizeof(double));
  m = bsfit__alloc(a, cap * sizeof(int));
  if (x == NULL || m == NULL) {
    bsfit__free(a, x, cap * sizeof(double));
    bsfit__free(a, m, cap * sizeof(int));
    return BSFIT_ENOMEM;
  }
  if (b->n > 0) {
    memcpy(x, b->x, b->n * sizeof(double));
    memcpy(m, b->mult, b->n * sizeof(int));
  }
  bsfit__free(a, b->x, b->cap * sizeof(double));
  bsfit__free(a, b->mult, b->cap * sizeof(int));
  b->x = x;
  b->mult = m;
  b->cap = cap;
  return BSFIT_OK;
}

/* The multiplicity q needs at x to be as smooth as the spline of degree p on the nk knots
** U there (at most C^{q-1}): continuity p - m at a knot of multiplicity m, C^p elsewhere. */
static int target_mult(const double *U, size_t nk, int p, int q, double x) {
  int m = bsfit_knots_multiplicity(U, nk, x);
  int k = p - m, t = k >= q ? 1 : q - k;
  return t < 1 ? 1 : (t > q ? q : t);
}

bsfit_err bsfit__knot_breaks(const double *U, size_t nk, int p, double a, double e, int q,
                             const double *xs, size_t nx, const bsfit_allocator *al,
                             bsfit__breaks *b, bsfit_status *st) {
  size_t i;
  memset(b, 0, sizeof *b);
  if (bsfit__breaks_reserve(al, b, (xs ? nx : nk) + 2) != BSFIT_OK)
    return bsfit__fail(st, BSFIT_ENOMEM, "out of memory for %zu break points", nk);
  if (xs != NULL) {
    for (i = 0; i < nx; i++) b->x[i] = xs[i];
    b->n = nx;
  } else {
    b->x[b->n++] = a;
    for (i = 0; i < nk; i++)
      if (U[i] > b->x[b->n - 1] && U[i] < e) b->x[b->n++] = U[i];
    b->x[b->n++] = e;
  }
  for (i = 0; i < b->n; i++) b->mult[i] = target_mult(U, nk, p, q, b->x[i]);
  return BSFIT_OK;
}

/* Break points: xs (strictly increasing, xs[0] = a, xs[nx-1] = b) or, when xs is NULL,
** the distinct knots of c in its domain [a, b]. */
static bsfit_err make_breaks(const bsfit_curve *c, int q, const double *xs, size_t nx,
                             const bsfit_allocator *al, bsfit__breaks *b, bsfit_status *st) {
  double a, e;
  bsfit_curve_domain(c, &a, &e);
  return bsfit__knot_breaks(c->knots, c->n + (size_t)c->degree + 1, c->degree, a, e, q, xs, nx,
                            al, b, st);
}

bsfit_err bsfit__curve_breaks(const bsfit_curve *c, int q, const bsfit_allocator *al,
                              bsfit__breaks *b, bsfit_status *st) {
  return make_breaks(c, q, NULL, 0, al, b, st);
}

/* Inserts x (mult 1) after index i. */
static bsfit_err breaks_insert(const bsfit_allocator *al, bsfit__breaks *b, size_t i, double x) {
  if (b->n == b->cap && bsfit__breaks_reserve(al, b, 2 * b->cap + 8) != BSFIT_OK)
    return BSFIT_ENOMEM;
  memmove(b->x + i + 2, b->x + i + 1, (b->n - i - 1) * sizeof(double));
  memmove(b->mult + i + 2, b->mult + i + 1, (b->n - i - 1) * sizeof(int));
  b->x[i + 1] = x;
  b->mult[i + 1] = 1;
  b->n++;
  return BSFIT_OK;
}

/* Knots of the target: clamped (open) or the expanded periodic form. Returns the
** number of stored control points, 0 when there are too few for degree q. */
static size_t target_knots(const bsfit__breaks *b, int q, int periodic, double *U,
                           bsfit_status *st) {
  size_t i, at = 0, N = 0;
  int j;
  if (!periodic) {
    for (j = 0; j <= q; j++) U[at++] = b->x[0];
    for (i = 1; i + 1 < b->n; i++)
      for (j = 0; j < b->mult[i]; j++) U[at++] = b->x[i];
    for (j = 0; j <= q; j++) U[at++] = b->x[b->n - 1];
    return at - (size_t)q - 1;
  }
  /* one period t[0..N] in the tail of U, expanded in place by bsfit_knots_periodic */
  for (i = 0; i + 1 < b->n; i++) N += (size_t)b->mult[i];
  if (N < (size_t)q + 1) return 0;
  {
    double *t = U + N + 2 * (size_t)q + 1; /* scratch after the expanded knots */
    for (i = 0; i + 1 < b->n; i++)
      for (j = 0; j < b->mult[i]; j++) t[at++] = b->x[i];
    t[at] = b->x[b->n - 1];
    if (bsfit_knots_periodic(q, N, t, U, st) != BSFIT_OK) return 0;
  }
  return N + (size_t)q;
}

/* Knots needed by target_knots (expanded + period scratch). */
static size_t target_knot_room(const bsfit__breaks *b, int q) {
  size_t i, s = 0;
  for (i = 0; i < b->n; i++) s += (size_t)(b->mult[i] > q + 1 ? q + 1 : b->mult[i]);
  return 2 * (s + 3 * (size_t)q + 4);
}

/* }==================================================================== */

/* {====================================================================
** The projection
** ===================================================================== */

/* Everything one assembly needs. */
typedef struct proj {
  const bsfit__fview *in;
  const bsfit_curve *rational; /* evaluate through the curve (weights) when not NULL */
  int q, ng;
  size_t nraw, nt; /* target control points (raw), target knots */
  const double *T;
  double *band, *rhs, *cv; /* (q+1) x nraw lower band, nraw x d column-major, d */
  double gx[MAX_GL], gw[MAX_GL];
} proj;

/* C(t) into P->cv (input span s). */
static void eval_input(const proj *P, size_t s, double t) {
  const bsfit__fview *in = P->in;
  double N[BSFIT_MAX_DEGREE + 1];
  size_t d = in->d, j, k, base;
  if (P->rational != NULL) {
    bsfit__curve_eval_unchecked(P->rational, t, P->cv);
    return;
  }
  bsfit_basis_funs(s, t, in->p, in->U, N);
  base = s - (size_t)in->p;
  memset(P->cv, 0, d * sizeof(double));
  for (j = 0; j <= (size_t)in->p; j++) {
    const double *row = in->P + (base + j) * d;
    for (k = 0; k < d; k++) P->cv[k] += N[j] * row[k];
  }
}

static size_t clampz(size_t v, size_t lo, size_t hi) { return v < lo ? lo : (v > hi ? hi : v); }

/* Adds the quadrature of [x0, x1] to band and rhs: inside the target's span st and the
** input's span sc (the knot indices the merge in assemble has reached, clamped as
** bsfit_knots_find_span would). */
static void add_span(proj *P, double x0, double x1, size_t st, size_t sc) {
  size_t q = (size_t)P->q, d = P->in->d, i, j, k, g, base;
  double mid = 0.5 * (x0 + x1), half = 0.5 * (x1 - x0), Nt[BSFIT_MAX_DEGREE + 1];
  st = clampz(st, q, P->nraw - 1);
  sc = clampz(sc, (size_t)P->in->p, P->in->n - 1);
  base = st - q;
  for (g = 0; g < (size_t)P->ng; g++) {
    double t = mid + half * P->gx[g], w = half * P->gw[g];
    bsfit_basis_funs(st, t, P->q, P->T, Nt);
    eval_input(P, sc, t);
    for (j = 0; j <= q; j++) {
      double wj = w * Nt[j];
      double *col = P->band + (base + j) * (q + 1);
      for (i = j; i <= q; i++) col[i - j] += wj * Nt[i];
      for (k = 0; k < d; k++) P->rhs[k * P->nraw + base + j] += wj * P->cv[k];
    }
  }
}

/* Quadrature over every span of the merged break points of target and input in [a, b]. */
static bsfit_err assemble(proj *P, double a, double b, const bsfit_allocator *al,
                          bsfit_status *st) {
  const double *U = P->in->U, *T = P->T;
  size_t nu = P->in->n + (size_t)P->in->p + 1, i = 0, j = 0, spans = 0;
  double x = a;
  while (x < b) {
    double next = b;
    while (i < nu && U[i] <= x) i++;
    while (j < P->nt && T[j] <= x) j++;
    if (i < nu && U[i] < next) next = U[i];
    if (j < P->nt && T[j] < next) next = T[j];
    add_span(P, x, next, j > 0 ? j - 1 : 0, i > 0 ? i - 1 : 0);
    x = next;
    if ((++spans & 4095) == 0 && bsfit__interrupted(al))
      return bsfit__fail(st, BSFIT_EINTR, "degree reduction interrupted");
  }
  return BSFIT_OK;
}

/* Closed curves: the expanded system folded onto the N distinct unknowns and solved by
** the periodic fitter's cyclic block elimination (periodic.c), through a fitter that
** holds only the arrays that solver reads. */
static bsfit_err solve_periodic(proj *P, const bsfit_allocator *al, double *ctrl,
                                bsfit_status *st) {
  size_t q = (size_t)P->q, nraw = P->nraw, N = nraw - q, n1 = N - q, d = P->in->d;
  /* r2 holds N points of d values, work q of them (d is a whole row of a surface's net) */
  size_t sizes[6] = {(q + 1) * n1, n1 * q, n1 * q, q * q, N * d, 3 * nraw + q * d};
  size_t total = 0, i;
  bsfit_fitter f;
  double *blk;
  bsfit_err e;
  for (i = 0; i < 6; i++) total += sizes[i];
  blk = bsfit__alloc(al, total * sizeof(double));
  if (blk == NULL) return bsfit__fail(st, BSFIT_ENOMEM, "out of memory for a cyclic system");
  memset(&f, 0, sizeof f);
  f.p = (int)q;
  f.periodic = 1;
  f.count = N;
  f.nraw = nraw;
  f.band = P->band;
  f.rhs = P->rhs;
  f.a11 = blk;
  f.a12 = f.a11 + sizes[0];
  f.y = f.a12 + sizes[1];
  f.s22 = f.y + sizes[2];
  f.r2 = f.s22 + sizes[3];
  f.work = f.r2 + sizes[4];
  e = bsfit__periodic_solve(&f, (int)P->in->d, ctrl, NULL, st);
  bsfit__free(al, blk, total * sizeof(double));
  if (e != BSFIT_OK) return e;
  for (i = 0; i < q; i++) memcpy(ctrl + (N + i) * P->in->d, ctrl + i * P->in->d,
                                 P->in->d * sizeof(double));
  return BSFIT_OK;
}

static bsfit_err solve_open(proj *P, double *ctrl, bsfit_status *st) {
  size_t n = P->nraw, d = P->in->d, i, k;
  int kd = (int)(n - 1 < (size_t)P->q ? n - 1 : (size_t)P->q);
  bsfit_err e = bsfit__pb_factor(n, kd, P->band, (size_t)P->q + 1, st);
  if (e == BSFIT_OK) e = bsfit__pb_solve(n, kd, P->band, (size_t)P->q + 1, d, P->rhs, n, st);
  if (e != BSFIT_OK) return e;
  for (i = 0; i < n; i++)
    for (k = 0; k < d; k++) ctrl[i * d + k] = P->rhs[k * n + i];
  return BSFIT_OK;
}

/* Number of Gauss-Legendre nodes exact for the integrands: N_i N_j (degree 2q) and
** N_i C (degree q + p). */
static int node_count(int q, int p, int rational) {
  int n = (q + (p > q ? p : q)) / 2 + 1 + (rational ? RATIONAL_EXTRA : 0);
  return n > MAX_GL ? MAX_GL : n;
}

bsfit_err bsfit__project(const bsfit__fview *in, const bsfit_curve *rational, int periodic,
                         int q, const bsfit__breaks *b, const bsfit_allocator *al,
                         bsfit__fspline *out, bsfit_status *st) {
  size_t room = target_knot_room(b, q), nraw, d = in->d, bb, rb;
  double *T = bsfit__alloc(al, room * sizeof(double));
  proj P;
  bsfit_err e;
  if (T == NULL) return bsfit__fail(st, BSFIT_ENOMEM, "out of memory for target knots");
  memset(&P, 0, sizeof P);
  nraw = target_knots(b, q, periodic, T, st);
  if (nraw < (size_t)q + 1 + (periodic ? (size_t)q : 0)) {
    bsfit__free(al, T, room * sizeof(double));
    return bsfit__fail(st, BSFIT_ETOOFEW, "%zu break points are too few for degree %d",
                       b->n, q);
  }
  P.in = in;
  P.rational = rational;
  P.q = q;
  P.ng = node_count(q, in->p, rational != NULL);
  P.nraw = nraw;
  P.nt = nraw + (size_t)q + 1;
  P.T = T;
  bsfit__gauss_legendre(P.ng, P.gx, P.gw);
  bb = bsfit__mulsize(nraw, (size_t)q + 1) * sizeof(double);
  rb = bsfit__mulsize(nraw, d) * sizeof(double);
  P.band = bsfit__alloc(al, bb);
  P.rhs = bsfit__alloc(al, rb);
  P.cv = bsfit__alloc(al, d * sizeof(double));
  e = bsfit__fspline_alloc(al, out, q, nraw, d, st);
  if (e == BSFIT_OK && (P.band == NULL || P.rhs == NULL || P.cv == NULL)) {
    bsfit__fspline_free(al, out);
    e = bsfit__fail(st, BSFIT_ENOMEM, "out of memory projecting on %zu control points", nraw);
  }
  if (e == BSFIT_OK) {
    memset(P.band, 0, bb);
    memset(P.rhs, 0, rb);
    memcpy(out->U, T, P.nt * sizeof(double));
    e = assemble(&P, b->x[0], b->x[b->n - 1], al, st);
    if (e == BSFIT_OK)
      e = periodic ? solve_periodic(&P, al, out->P, st) : solve_open(&P, out->P, st);
    if (e != BSFIT_OK) bsfit__fspline_free(al, out);
  }
  bsfit__free(al, P.band, bb);
  bsfit__free(al, P.rhs, rb);
  bsfit__free(al, P.cv, d * sizeof(double));
  bsfit__free(al, T, room * sizeof(double));
  return e;
}

/* }==================================================================== */

/* {====================================================================
** Knots added until the tolerance is met
** ===================================================================== */

/* One projection of c onto the break points b, into res. */
static bsfit_err project_curve(const bsfit_curve *c, int q, const bsfit__breaks *b,
                               const bsfit_allocator *al, bsfit_curve *res, bsfit_status *st) {
  bsfit__fview v;
  bsfit__fspline f;
  bsfit_err e;
  v.p = c->degree;
  v.n = c->n;
  v.d = (size_t)c->dim;
  v.U = c->knots;
  v.P = c->ctrl;
  e = bsfit__project(&v, c->weights ? c : NULL, c->periodic, q, b, al, &f, st);
  if (e != BSFIT_OK) return e;
  return bsfit__fspline_to_curve(&f, c->dim, c->periodic, al, res, st);
}

/* A knot in the middle of every break span whose deviation exceeds tol (from the last
** span down, so the indices still to visit do not move), unless the span is already
** narrower than MIN_SPAN of the domain: a deviation that refining does not cure there is
** the input's own (a corner, a spike), not the projection's. Returns the number added. */
bsfit_err bsfit__split_spans(bsfit__breaks *b, const double *span_max, double tol,
                            const bsfit_allocator *al, size_t *count) {
  size_t i = b->n - 1;
  double w = MIN_SPAN * (b->x[b->n - 1] - b->x[0]);
  *count = 0;
  while (i-- > 0) {
    if (!(span_max[i] > tol) || b->x[i + 1] - b->x[i] < w) continue;
    if (breaks_insert(al, b, i, 0.5 * (b->x[i] + b->x[i + 1])) != BSFIT_OK) return BSFIT_ENOMEM;
    (*count)++;
  }
  return BSFIT_OK;
}

/* The deviation of one projection res from the measured curve m, into rep and span_max:
** the certified bound (filter_bound.c; polynomial curves) when it meets tol, measured by
** the feet from the same parameter (a true distance, within the bound); otherwise the
** sampled distance, the global closest points confirming a result the cheap local measure
** finds within tol. */
static bsfit_err deviation(const bsfit_curve *res, const bsfit_curve *m, const bsfit__reduce_arg *r,
                           const bsfit__breaks *b, double *span_max, const bsfit_allocator *al,
                           bsfit_reduce_report *rep, bsfit_status *st) {
  bsfit__bound bd;
  /* a rational difference is no polynomial: its Bernstein form would bound nothing */
  bsfit_err e = m->weights != NULL ? BSFIT_EDEGREE
                                   : bsfit__curve_diff_bound(res, m, r->tol, b, span_max, al,
                                                             &bd, st);
  if (e != BSFIT_OK && e != BSFIT_EDEGREE) return e;
  rep->bound = e == BSFIT_OK ? bd.bound : INFINITY;
  if (e == BSFIT_OK && bd.bound <= r->tol && r->bound_only) {
    rep->max_deviation = bd.bound;
    return BSFIT_OK;
  }
  if (e == BSFIT_OK && bd.bound <= r->tol)
    return bsfit__curve_distance(res, m, r->per_span, BSFIT__DIST_FEET, NULL, NULL, al,
                                 &rep->max_deviation, st);
  e = bsfit__curve_distance(res, m, r->per_span, BSFIT__DIST_LOCAL, b, span_max, al,
                            &rep->max_deviation, st);
  if (e == BSFIT_OK && rep->max_deviation <= r->tol)
    e = bsfit__curve_distance(res, m, r->per_span, BSFIT__DIST_CORRESPONDING, b, span_max, al,
                              &rep->max_deviation, st);
  return e;
}

bsfit_err bsfit__reduce_loop(const bsfit_curve *c, const bsfit__reduce_arg *r, bsfit__breaks *b,
                             const bsfit_allocator *al, bsfit_curve *res,
                             bsfit_reduce_report *rep, bsfit_status *st) {
  double *span_max = NULL;
  size_t cap = 0, added = 0, now;
  double best = INFINITY;
  int stalled = 0;
  bsfit_err e;
  rep->knots_added = 0;
  rep->rounds = 0;
  for (;;) {
    if (bsfit__interrupted(al)) return bsfit__fail(st, BSFIT_EINTR, "degree reduction interrupted");
    e = project_curve(c, r->degree, b, al, res, st);
    if (e == BSFIT_OK && cap < b->n) {
      bsfit__free(al, span_max, cap * sizeof(double));
      cap = b->cap;
      span_max = bsfit__alloc(al, cap * sizeof(double));
      if (span_max == NULL) e = bsfit__fail(st, BSFIT_ENOMEM, "out of memory for span deviations");
    }
    if (e == BSFIT_OK)
      e = deviation(res, r->measure ? r->measure : c, r, b, span_max, al, rep, st);
    rep->rounds++;
    if (e != BSFIT_OK || rep->max_deviation <= r->tol) break;
    /* knots that do not lower the deviation cannot meet tol: the input's own detail */
    stalled = rep->max_deviation < 0.99 * best ? 0 : stalled + 1;
    if (rep->max_deviation < best) best = rep->max_deviation;
    if (added >= r->max_added || stalled >= STALL_ROUNDS) {
      e = bsfit__fail(st, BSFIT_ENOCONV,
                      "degree %d within tol = %g not reached after adding %zu knots "
                      "(deviation %g)", r->degree, r->tol, added, rep->max_deviation);
      break;
    }
    e = bsfit__split_spans(b, span_max, r->tol, al, &now);
    if (e != BSFIT_OK) {
      e = bsfit__fail(st, BSFIT_ENOMEM, "out of memory adding knots");
      break;
    }
    if (now == 0) {
      e = bsfit__fail(st, BSFIT_ENOCONV, "no span to refine at deviation %g",
                      rep->max_deviation);
      break;
    }
    added += now;
  }
  bsfit__free(al, span_max, cap * sizeof(double));
  rep->knots_added = added;
  return e;
}

/* }==================================================================== */

/* {====================================================================
** Public entry
** ===================================================================== */

static bsfit_err check_reduce(const bsfit_curve *c, const bsfit_reduce_opts *o, int q,
                              bsfit_status *st) {
  double a, b;
  size_t i;
  bsfit_err e;
  if (c == NULL || o == NULL) return bsfit__fail(st, BSFIT_EINVAL, "curve or options is NULL");
  e = bsfit_curve_validate(c, st);
  if (e != BSFIT_OK) return e;
  if (q < 1 || q > BSFIT_MAX_DEGREE)
    return bsfit__fail(st, BSFIT_EDEGREE, "degree = %d must be in 1..%d", q, BSFIT_MAX_DEGREE);
  if (isnan(o->tol)) return bsfit__fail(st, BSFIT_ENONFINITE, "tol is NaN");
  if (!(o->tol > 0)) return bsfit__fail(st, BSFIT_EINVAL, "tol = %g must be > 0", o->tol);
  if (o->breaks == NULL) return BSFIT_OK;
  bsfit_curve_domain(c, &a, &b);
  if (o->nbreaks < 2 || o->breaks[0] != a || o->breaks[o->nbreaks - 1] != b)
    return bsfit__fail(st, BSFIT_EINVAL,
                       "break points must run from the domain's start %g to its end %g", a, b);
  for (i = 1; i < o->nbreaks; i++)
    if (!(o->breaks[i] > o->breaks[i - 1]))
      return bsfit__fail(st, BSFIT_EINVAL, "break point %zu (%g) does not increase", i + 1,
                         o->breaks[i]);
  return BSFIT_OK;
}

bsfit_err bsfit_filter_reduce_curve(const bsfit_curve *c, const bsfit_reduce_opts *o,
                                    bsfit_curve *out, bsfit_reduce_report *rep,
                                    bsfit_status *st) {
  int q = o != NULL && o->degree != 0 ? o->degree : DEFAULT_DEGREE;
  bsfit__reduce_arg r;
  bsfit_reduce_report tmp;
  bsfit_allocator al;
  bsfit__breaks b;
  bsfit_curve res;
  bsfit_err e = check_reduce(c, o, q, st);
  if (e != BSFIT_OK) return e;
  if (out == NULL) return bsfit__fail(st, BSFIT_EINVAL, "output curve is NULL");
  al = c->alloc;
  e = make_breaks(c, q, o->breaks, o->nbreaks, &al, &b, st);
  if (e != BSFIT_OK) return e;
  memset(&r, 0, sizeof r);
  r.degree = q;
  r.tol = o->tol;
  r.per_span = o->samples ? o->samples : DEFAULT_SAMPLES;
  r.max_added = o->max_added ? o->max_added : 10 * b.n + 100;
  bsfit_curve_init(&res);
  e = bsfit__reduce_loop(c, &r, &b, &al, &res, rep ? rep : &tmp, st);
  bsfit__breaks_free(&al, &b);
  if (e == BSFIT_OK) bsfit_curve_move(&res, out);
  bsfit_curve_free(&res);
  return e == BSFIT_OK ? bsfit__ok(st) : e;
}

/* }==================================================================== */
