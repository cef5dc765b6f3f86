/*
** filter_smooth.c
** Smoothing to a tolerance: the smoothest curve of degree q within tol of C that the
** kernel filters give. "Smoothest" is the least bending energy (the integral of
** curvature^2 ds, bsfit_curve_bending_energy). For each kernel order r (the given one,
** or 1..MAX_AUTO_ORDER) the half-width delta is searched: the filter of order r and
** half-width delta, projected on degree q (filter_reduce.c, on C's own break points),
** must stay within tol of C, measured by the local distance of filter_distance.c (an
** upper bound of the true one). The deviation grows like delta^2 for small delta, so
** the search steps by sqrt(tol / deviation) until it brackets the largest feasible
** delta, then narrows the bracket (secant in that model, or bisection in log delta) to
** 8%. Wider windows give less energy, so the largest feasible delta of each order is
** its best; the order whose result has least energy wins. The winner is projected
** again with knots added until its true distance (global closest points, dense
** samples) is within tol. When no width keeps C within tol, or the best result is not
** smoother than C, C is returned unchanged (at degree q) and the report says so.
*/
#include "filter_internal.h"

#include <float.h>
#include <math.h>
#include <string.h>
#include <stdio.h>
#include <stdlib.h>

#define MAX_AUTO_ORDER 4
#define SEARCH_EVALS 12   /* evaluations per order, at most */
#define SEARCH_RATIO 1.08 /* stop when the bracket [lo, hi] has hi <= lo * SEARCH_RATIO */
#define SEARCH_SAMPLES 3  /* local distance: samples per knot span */
#define FINAL_SAMPLES 8   /* true distance of the result: samples per knot span */
#define ENERGY_SAMPLES 8  /* energy and turning: samples per knot span of C (>= 256) */
#define SEARCH_MARGIN 0.95 /* the search keeps the sampled distance under this much of tol */
#define FINAL_TRIES 6     /* the winner's width shrinks at most this often ... */
#define FINAL_SHRINK 0.85 /* ... by this factor, when the true distance exceeds tol */

/* What the search carries. */
typedef struct smooth_ctx {
  const bsfit_curve *c;
  const bsfit_allocator *al;
  int q;
  double tol, a, b;
  size_t samples;         /* energy samples */
  double last_delta;      /* the previous order's best width (0: none yet) */
  int last_order;
  const bsfit__breaks *base; /* C's break points in [a, b] */
  int evals;
} smooth_ctx;

/* One candidate: the filter F and its projection S. */
typedef struct candidate {
  int order;
  double delta, dev, energy;
  bsfit_curve F, S;
} candidate;

static void cand_init(candidate *k) {
  memset(k, 0, sizeof *k);
  bsfit_curve_init(&k->F);
  bsfit_curve_init(&k->S);
}

static void cand_free(candidate *k) {
  bsfit_curve_free(&k->F);
  bsfit_curve_free(&k->S);
}

/* The break points of the target for the filtered F: C's, and F's domain ends (an open
** F reaches r delta beyond C's domain; a closed one may start its period later). */
static bsfit_err target_breaks(const smooth_ctx *x, const bsfit_curve *F, bsfit__breaks *b) {
  const bsfit__breaks *B = x->base;
  double lo, hi, T = x->b - x->a, eps = 1e-9 * T;
  size_t i;
  int j;
  memset(b, 0, sizeof *b);
  if (bsfit__breaks_reserve(x->al, b, 2 * B->n + 4) != BSFIT_OK) return BSFIT_ENOMEM;
  bsfit_curve_domain(F, &lo, &hi);
  b->x[b->n++] = lo;
  for (j = 0; j < (F->periodic ? 2 : 1); j++)
    for (i = 0; i < B->n; i++) {
      double v = B->x[i] + (double)j * T;
      if (v > b->x[b->n - 1] + eps && v < hi - eps) b->x[b->n++] = v;
    }
  b->x[b->n++] = hi;
  for (i = 0; i < b->n; i++) b->mult[i] = 1;
  return BSFIT_OK;
}

/* Filters C (order r, half-width delta), projects the result on degree q (no knots
** added) and measures it: k receives F, S and the local deviation. */
static bsfit_err evaluate(smooth_ctx *x, int r, double delta, candidate *k, bsfit_status *st) {
  bsfit__fview v;
  bsfit__fspline f;
  bsfit__breaks b;
  bsfit_err e;
  x->evals++;
  k->order = r;
  k->delta = delta;
  e = bsfit_filter_kernel_curve_delta(x->c, r, delta, &k->F, st);
  if (e != BSFIT_OK) return e;
  if (target_breaks(x, &k->F, &b) != BSFIT_OK)
    return bsfit__fail(st, BSFIT_ENOMEM, "out of memory for break points");
  v.p = k->F.degree;
  v.n = k->F.n;
  v.d = (size_t)k->F.dim;
  v.U = k->F.knots;
  v.P = k->F.ctrl;
  e = bsfit__project_coarse(&v, k->F.periodic, x->q, &b, x->al, &f, st);
  if (e == BSFIT_OK) e = bsfit__fspline_to_curve(&f, x->c->dim, x->c->periodic, x->al, &k->S, st);
  if (e == BSFIT_OK)
    e = bsfit__curve_distance(&k->S, x->c, SEARCH_SAMPLES, BSFIT__DIST_LOCAL, &b, NULL, x->al,
                              &k->dev, st);
  bsfit__breaks_free(x->al, &b);
  return e;
}

/* {====================================================================
** The search over delta for one order
** ===================================================================== */

static double clampd(double v, double lo, double hi) { return v < lo ? lo : (v > hi ? hi : v); }

/* Errors that only say this delta is not usable (a window too wide for the curve). */
static int fatal(bsfit_err e) { return e == BSFIT_ENOMEM || e == BSFIT_EINTR; }


/* The search's state: the bracket [lo, hi] of the largest delta whose deviation is
** within the target (hi < 0: no infeasible delta yet), with the deviations there, and
** the last two evaluations (for the local growth rate). */
typedef struct bracket {
  double target, lo, dlo, hi, dhi, prev, dprev, cur, dcur;
} bracket;

/* The growth exponent alpha of dev ~ delta^alpha between two evaluations (2 when they
** cannot tell: the smooth-curve rate), kept in [0.5, 4]. */
static double growth(double d0, double v0, double d1, double v1) {
  double a;
  if (!(d0 > 0 && d1 > 0 && v0 > 0 && v1 > 0) || d0 == d1) return 2.0;
  a = log(v1 / v0) / log(d1 / d0);
  return !(a == a) ? 2.0 : clampd(a, 0.5, 4.0);
}

/* The next delta: in the model dev ~ delta^alpha, where the deviation meets the target
** (a hair under), kept inside the bracket, or stepping out of it towards the target. */
static double next_delta(const bracket *B, double dmax) {
  double a, g, want = 0.995 * B->target;
  if (B->hi > 0 && B->lo > 0) {
    a = growth(B->lo, B->dlo, B->hi, B->dhi);
    g = B->lo * pow(want / B->dlo, 1.0 / a);
    return clampd(g, B->lo + 0.1 * (B->hi - B->lo), B->hi - 0.1 * (B->hi - B->lo));
  }
  a = growth(B->prev, B->dprev, B->cur, B->dcur);
  g = B->dcur > 0 ? B->cur * pow(want / B->dcur, 1.0 / a) : 4.0 * B->cur;
  if (B->hi < 0) return fmin(dmax, clampd(g, 1.1 * B->cur, 4.0 * B->cur));
  return clampd(g, B->cur / 16, 0.9 * B->cur);
}

/* Records the evaluation at d (dev, or not usable) in B; returns non-zero when the
** search is done: the deviation at lo is within 3% of the target, the bracket within
** SEARCH_RATIO, or the widest window allowed is feasible. */
static int record(bracket *B, double d, double dev, int ok, double dmax) {
  B->prev = B->cur;
  B->dprev = B->dcur;
  B->cur = d;
  B->dcur = ok ? dev : 4.0 * B->target; /* unusable: step back as from a far miss */
  if (ok && dev <= B->target) {
    B->lo = d;
    B->dlo = dev;
  } else {
    B->hi = d;
    B->dhi = B->dcur;
  }
  return (B->lo > 0 && B->dlo >= 0.97 * B->target) || B->lo >= dmax ||
         (B->hi > 0 && B->lo > 0 && B->hi <= B->lo * SEARCH_RATIO);
}

/* The largest feasible delta of order r, into best (left alone when none is found). */
static bsfit_err search_order(smooth_ctx *x, int r, candidate *best, bsfit_status *st) {
  size_t spans = x->base->n - 1;
  double h = (x->b - x->a) / (double)spans, dmax = (x->b - x->a) / (2.0 * r);
  /* same kernel variance r delta^2 / 3, same deviation to first order: the previous
  ** order's answer scaled is a close first guess */
  double d0 = x->last_order ? x->last_delta * sqrt((double)x->last_order / r) : 0.5 * h;
  double d = fmin(d0, dmax);
  bracket B;
  int i, done = 0;
  memset(&B, 0, sizeof B);
  B.target = SEARCH_MARGIN * x->tol;
  B.hi = -1;
  for (i = 0; i < SEARCH_EVALS && !done; i++) {
    candidate k;
    bsfit_err e;
    cand_init(&k);
    e = evaluate(x, r, d, &k, st);
    if (e != BSFIT_OK && fatal(e)) {
      cand_free(&k);
      return e;
    }
    done = record(&B, d, k.dev, e == BSFIT_OK, dmax);
    if (B.lo == d) {
      cand_free(best);
      *best = k; /* best owns k's curves now */
    } else {
      cand_free(&k);
    }
    d = next_delta(&B, dmax);
    if (B.lo == 0 && d < 1e-6 * h) break;
  }
  if (best->order != r) return BSFIT_OK;
  x->last_order = r;
  x->last_delta = best->delta;
  return bsfit_curve_bending_energy(&best->S, x->samples, &best->energy, st);
}

/* }==================================================================== */

/* {====================================================================
** Public entry
** ===================================================================== */

static bsfit_err check_smooth(const bsfit_curve *c, const bsfit_smooth_opts *o, int q,
                              bsfit_status *st) {
  bsfit_err e;
  if (c == NULL || o == NULL) return bsfit__fail(st, BSFIT_EINVAL, "curve or options is NULL");
  e = bsfit_curve_validate(c, st);
  if (e != BSFIT_OK) return e;
  if (c->weights != NULL)
    return bsfit__fail(st, BSFIT_EINVAL, "rational curves cannot be filtered");
  if (c->dim < 2)
    return bsfit__fail(st, BSFIT_EDIM, "smoothing needs a curve of dimension 2..4, got %d",
                       c->dim);
  if (q < 1 || q > BSFIT_MAX_DEGREE)
    return bsfit__fail(st, BSFIT_EDEGREE, "degree = %d must be in 1..%d", q, BSFIT_MAX_DEGREE);
  if (!isfinite(o->tol)) return bsfit__fail(st, BSFIT_ENONFINITE, "tol = %g is not finite", o->tol);
  if (!(o->tol > 0)) return bsfit__fail(st, BSFIT_EINVAL, "tol = %g must be > 0", o->tol);
  if (o->order < 0 || o->order > BSFIT_MAX_DEGREE - c->degree)
    return bsfit__fail(st, BSFIT_EINVAL, "order = %d must be in 1..%d (or 0: searched)", o->order,
                       BSFIT_MAX_DEGREE - c->degree);
  return BSFIT_OK;
}

/* C's distinct knots in its domain. */
static bsfit_err base_breaks(const bsfit_curve *c, const bsfit_allocator *al, bsfit__breaks *b) {
  size_t nk = c->n + (size_t)c->degree + 1, i;
  double a, e;
  bsfit_curve_domain(c, &a, &e);
  memset(b, 0, sizeof *b);
  if (bsfit__breaks_reserve(al, b, nk + 2) != BSFIT_OK) return BSFIT_ENOMEM;
  b->x[b->n++] = a;
  for (i = 0; i < nk; i++)
    if (c->knots[i] > b->x[b->n - 1] && c->knots[i] < e) b->x[b->n++] = c->knots[i];
  b->x[b->n++] = e;
  for (i = 0; i < b->n; i++) b->mult[i] = 1;
  return BSFIT_OK;
}

/* Nothing smoother within tol: C itself at degree q (elevated, or reduced within tol). */
static bsfit_err unchanged(smooth_ctx *x, bsfit_curve *res, bsfit_smooth_report *rep,
                           bsfit_status *st) {
  const bsfit_curve *c = x->c;
  bsfit_reduce_opts o;
  bsfit_reduce_report rr;
  bsfit_err e;
  rep->changed = 0;
  if (c->degree == x->q) return bsfit_curve_copy(c, res, x->al, st);
  if (c->degree < x->q) return bsfit_curve_elevate(c, x->q - c->degree, res, st);
  memset(&o, 0, sizeof o);
  o.degree = x->q;
  o.tol = x->tol;
  e = bsfit_filter_reduce_curve(c, &o, res, &rr, st);
  rep->max_deviation = rr.max_deviation;
  rep->knots_added = rr.knots_added;
  return e;
}

/* The winner projected again, knots added until its true distance to C is within tol
** (a few, as the filtered curve itself must be within tol already: ENOCONV when not). */
static bsfit_err final_reduce(smooth_ctx *x, const candidate *k, bsfit_curve *res,
                              bsfit_reduce_report *rr, bsfit_status *st) {
  bsfit__reduce_arg r;
  bsfit__breaks b;
  bsfit_err e;
  memset(&r, 0, sizeof r);
  r.degree = x->q;
  r.tol = x->tol;
  r.per_span = FINAL_SAMPLES;
  r.measure = x->c;
  r.max_added = x->base->n / 4 + 8;
  if (target_breaks(x, &k->F, &b) != BSFIT_OK)
    return bsfit__fail(st, BSFIT_ENOMEM, "out of memory for break points");
  e = bsfit__reduce_loop(&k->F, &r, &b, x->al, res, rr, st);
  bsfit__breaks_free(x->al, &b);
  return e;
}

/* An open result is given C's domain back (an affine change of parameter). */
static void restore_domain(const smooth_ctx *x, bsfit_curve *res) {
  double lo, hi, s;
  size_t i, nk = res->n + (size_t)res->degree + 1;
  if (res->periodic) return;
  bsfit_curve_domain(res, &lo, &hi);
  s = (x->b - x->a) / (hi - lo);
  for (i = 0; i < nk; i++) res->knots[i] = x->a + (res->knots[i] - lo) * s;
  for (i = 0; i <= (size_t)res->degree; i++) {
    res->knots[i] = x->a; /* exactly the clamped ends */
    res->knots[nk - 1 - i] = x->b;
  }
}

/* The winner made final; when the dense true distance shows the filter itself beyond
** tol somewhere the search's samples missed, its width shrinks and it is tried again. */
static bsfit_err finish(smooth_ctx *x, candidate *k, bsfit_curve *res,
                        bsfit_smooth_report *rep, bsfit_status *st) {
  bsfit_reduce_report rr;
  bsfit_err e = final_reduce(x, k, res, &rr, st);
  int i;
  for (i = 0; e == BSFIT_ENOCONV && i < FINAL_TRIES; i++) {
    int r = k->order;
    double d = k->delta * FINAL_SHRINK;
    cand_free(k);
    cand_init(k);
    e = evaluate(x, r, d, k, st);
    if (e == BSFIT_OK) e = final_reduce(x, k, res, &rr, st);
  }
  if (e != BSFIT_OK) return e;
  rep->changed = 1;
  rep->order = k->order;
  rep->delta = k->delta;
  rep->max_deviation = rr.max_deviation;
  rep->knots_added = rr.knots_added;
  restore_domain(x, res);
  return BSFIT_OK;
}

/* The best candidate over the orders to try, into best (order 0 when none is feasible). */
static bsfit_err search(smooth_ctx *x, int order, candidate *best, bsfit_status *st) {
  int r, r0 = order ? order : 1, r1 = order ? order : MAX_AUTO_ORDER;
  if (r1 > BSFIT_MAX_DEGREE - x->c->degree) r1 = BSFIT_MAX_DEGREE - x->c->degree;
  for (r = r0; r <= r1; r++) {
    candidate cur;
    bsfit_err e;
    cand_init(&cur);
    e = search_order(x, r, &cur, st);
    if (e != BSFIT_OK) {
      cand_free(&cur);
      return e;
    }
    if (cur.order == r && (best->order == 0 || cur.energy < best->energy)) {
      cand_free(best);
      *best = cur;
    } else {
      cand_free(&cur);
    }
  }
  return BSFIT_OK;
}

static bsfit_err smooth_measures(smooth_ctx *x, const bsfit_curve *c, double *turn, double *en,
                                 bsfit_status *st) {
  bsfit_err e = bsfit_curve_total_turning(c, x->samples, turn, st);
  return e == BSFIT_OK ? bsfit_curve_bending_energy(c, x->samples, en, st) : e;
}

bsfit_err bsfit_filter_smooth_curve(const bsfit_curve *c, const bsfit_smooth_opts *o,
                                    bsfit_curve *out, bsfit_smooth_report *rep,
                                    bsfit_status *st) {
  int q = o != NULL && o->degree != 0 ? o->degree : 3;
  bsfit_smooth_report tmp;
  bsfit_allocator al;
  bsfit__breaks base;
  smooth_ctx x;
  candidate best;
  bsfit_curve res;
  bsfit_err e = check_smooth(c, o, q, st);
  if (e != BSFIT_OK) return e;
  if (out == NULL) return bsfit__fail(st, BSFIT_EINVAL, "output curve is NULL");
  if (rep == NULL) rep = &tmp;
  memset(rep, 0, sizeof *rep);
  al = c->alloc;
  if (base_breaks(c, &al, &base) != BSFIT_OK)
    return bsfit__fail(st, BSFIT_ENOMEM, "out of memory for break points");
  memset(&x, 0, sizeof x);
  x.c = c;
  x.al = &al;
  x.q = q;
  x.tol = o->tol;
  bsfit_curve_domain(c, &x.a, &x.b);
  x.base = &base;
  x.samples = ENERGY_SAMPLES * (base.n - 1) < 256 ? 256 : ENERGY_SAMPLES * (base.n - 1);
  cand_init(&best);
  bsfit_curve_init(&res);
  e = smooth_measures(&x, c, &rep->turning_before, &rep->energy_before, st);
  if (e == BSFIT_OK) e = search(&x, o->order, &best, st);
  if (e == BSFIT_OK) {
    if (best.order != 0 && best.energy < rep->energy_before) e = finish(&x, &best, &res, rep, st);
    else e = unchanged(&x, &res, rep, st);
  }
  if (e == BSFIT_OK) e = smooth_measures(&x, &res, &rep->turning_after, &rep->energy_after, st);
  rep->evaluations = x.evals;
  cand_free(&best);
  bsfit__breaks_free(&al, &base);
  if (e == BSFIT_OK) bsfit_curve_move(&res, out);
  bsfit_curve_free(&res);
  return e == BSFIT_OK ? bsfit__ok(st) : e;
}

/* }==================================================================== */
