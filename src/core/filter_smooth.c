/*
** filter_smooth.c
** Smoothing to a tolerance: the smoothest curve of degree q within tol of C that the
** kernel filters give. "Smoothest" is the least bending energy (the integral of
** curvature^2 ds, bsfit_curve_bending_energy). For each kernel order r (the given one, or
** 1..MAX_AUTO_ORDER) the widest half-width delta is searched whose filtered curve stays
** within SEARCH_MARGIN tol of C, by the local distance of filter_distance.c (an upper
** bound of the true one): the distance of a noisy curve's filter does not grow
** monotonically with delta, so the search steps delta up geometrically until the distance
** is well beyond tol, then bisects next to the widest feasible width (search_order).
** Wider windows give less energy; the order whose filtered curve has least energy wins.
** The winner is brought to degree q by the L2 projection on C's own break points
** (filter_reduce.c), knots added where its true distance to C (global closest points,
** refined maxima) exceeds tol; if that does not converge the width shrinks and the
** projection is tried again. When no width keeps C within tol, or the best result is not
** smoother than C, C is returned unchanged (at degree q) and the report says so.
*/
#include "filter_internal.h"

#include <float.h>
#include <math.h>
#include <string.h>

#define MAX_AUTO_ORDER 4
#define SEARCH_STEP 1.4   /* the widths tried grow by this factor ... */
#define SEARCH_BEYOND 1.5 /* ... until the distance is this many times tol */
#define SEARCH_DOWN 16    /* steps down from the first guess, at most */
#define SEARCH_BISECT 3   /* bisections after the steps (the last bracket: 1.4^(1/8)) */
#define SEARCH_SAMPLES 2  /* local distance: samples per knot span */
#define FINAL_SAMPLES 16  /* true distance of the result: samples per knot span */
#define ENERGY_SAMPLES 8  /* energy and turning: samples per knot span of C (>= 256) */
/* the filter keeps this much of tol; the rest goes to the degree reduction */
#define SEARCH_MARGIN 0.995
#define FINAL_TRIES 8     /* the winner's width shrinks at most this often ... */
#define FINAL_SHRINK 0.7  /* ... by this factor at least, when the true distance exceeds tol */

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

/* One candidate: the filtered curve F, its distance to C and its energy. */
typedef struct candidate {
  int order;
  double delta, dev, energy;
  bsfit_curve F;
} candidate;

static void cand_init(candidate *k) {
  memset(k, 0, sizeof *k);
  bsfit_curve_init(&k->F);
}

static void cand_free(candidate *k) { bsfit_curve_free(&k->F); }

/* The break points of the target for the filtered F: C's (an open F is projected over
** C's domain only: its widened ends, where it turns into the constant extension, would
** make the projection ring into the interior; a closed F may start its period later). */
static bsfit_err target_breaks(const smooth_ctx *x, const bsfit_curve *F, bsfit__breaks *b) {
  const bsfit__breaks *B = x->base;
  double lo, hi, T = x->b - x->a, eps = 1e-9 * T;
  size_t i;
  int j;
  memset(b, 0, sizeof *b);
  if (bsfit__breaks_reserve(x->al, b, 2 * B->n + 4) != BSFIT_OK) return BSFIT_ENOMEM;
  if (F->periodic) bsfit_curve_domain(F, &lo, &hi);
  else lo = x->a, hi = x->b;
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

/* Filters C (order r, half-width delta) and measures the filtered curve's distance to C
** (local mode: an upper bound). */
static bsfit_err evaluate(smooth_ctx *x, int r, double delta, candidate *k, bsfit_status *st) {
  bsfit_err e;
  if (bsfit__interrupted(x->al)) return bsfit__fail(st, BSFIT_EINTR, "smoothing interrupted");
  x->evals++;
  k->order = r;
  k->delta = delta;
  e = bsfit_filter_kernel_curve_delta(x->c, r, delta, &k->F, st);
  if (e != BSFIT_OK) return e;
  return bsfit__curve_distance(&k->F, x->c, SEARCH_SAMPLES, BSFIT__DIST_LOCAL, NULL, NULL, x->al,
                               &k->dev, st);
}

/* {====================================================================
** The search over delta for one order
** ===================================================================== */

static double clampd(double v, double lo, double hi) { return v < lo ? lo : (v > hi ? hi : v); }

/* Errors that only say this delta is not usable (a window too wide for the curve). */
static int fatal(bsfit_err e) { return e == BSFIT_ENOMEM || e == BSFIT_EINTR; }


/* Evaluates order r at d; keeps the candidate in best when it is feasible and wider than
** best. *dev receives its distance (4 tol when d is not usable). */
static bsfit_err try_delta(smooth_ctx *x, int r, double d, candidate *best, double *dev,
                           bsfit_status *st) {
  candidate k;
  bsfit_err e;
  cand_init(&k);
  e = evaluate(x, r, d, &k, st);
  if (e != BSFIT_OK && fatal(e)) {
    cand_free(&k);
    return e;
  }
  *dev = e == BSFIT_OK ? k.dev : 4.0 * x->tol;
  if (e == BSFIT_OK && k.dev <= SEARCH_MARGIN * x->tol && (best->order != r || d > best->delta)) {
    cand_free(best);
    *best = k; /* best owns k's curve now */
    return BSFIT_OK;
  }
  cand_free(&k);
  return BSFIT_OK;
}

/* The widest feasible delta of order r, into best (left alone when none is found). The
** distance does not grow monotonically with delta: below the width where the filter's
** shrinking of the shape dominates, it follows the noise it removes, up and down. So the
** search steps up by SEARCH_STEP from the first feasible width until the distance is
** clearly beyond tol (SEARCH_BEYOND times), keeps the widest feasible width seen, and
** bisects (in log delta) between it and the next width tried. */
static bsfit_err search_order(smooth_ctx *x, int r, candidate *best, bsfit_status *st) {
  size_t spans = x->base->n - 1;
  double h = (x->b - x->a) / (double)spans, dmax = (x->b - x->a) / (2.0 * r), dev = 0, hi;
  /* same kernel variance r delta^2 / 3, same deviation to first order: the previous
  ** order's answer scaled is a close first guess */
  double d = fmin(x->last_order ? x->last_delta * sqrt((double)x->last_order / r) : 0.5 * h, dmax);
  bsfit_err e;
  int i;
  for (i = 0; i < SEARCH_DOWN; i++) { /* down to a feasible width */
    if ((e = try_delta(x, r, d, best, &dev, st)) != BSFIT_OK) return e;
    if (best->order == r) break;
    d /= SEARCH_STEP;
  }
  if (best->order != r) return BSFIT_OK;
  for (hi = -1; dev <= SEARCH_BEYOND * x->tol && d < dmax;) { /* up while it may come back */
    d = fmin(d * SEARCH_STEP, dmax);
    if ((e = try_delta(x, r, d, best, &dev, st)) != BSFIT_OK) return e;
    if (best->delta == d) hi = -1;
    else if (hi < 0) hi = d;
  }
  for (i = 0; i < SEARCH_BISECT && hi > 0; i++) { /* between the widest feasible and hi */
    double mid = sqrt(best->delta * hi), lo = best->delta;
    if ((e = try_delta(x, r, mid, best, &dev, st)) != BSFIT_OK) return e;
    if (best->delta == lo) hi = mid;
  }
  x->last_order = r;
  x->last_delta = best->delta;
  return bsfit_curve_bending_energy(&best->F, x->samples, &best->energy, st);
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
  r.max_added = x->base->n / 2 + 8;
  if (target_breaks(x, &k->F, &b) != BSFIT_OK)
    return bsfit__fail(st, BSFIT_ENOMEM, "out of memory for break points");
  e = bsfit__reduce_loop(&k->F, &r, &b, x->al, res, rr, st);
  bsfit__breaks_free(x->al, &b);
  return e;
}

/* The winner made final; when the dense true distance shows the filter itself beyond
** tol somewhere the search's samples missed, its width shrinks (by the delta^2 model
** first, then geometrically: near the noise floor the distance hardly follows delta) and
** it is tried again. Returns ENOCONV when no try fits. */
static bsfit_err finish(smooth_ctx *x, candidate *k, bsfit_curve *res,
                        bsfit_smooth_report *rep, bsfit_status *st) {
  bsfit_reduce_report rr;
  bsfit_err e = final_reduce(x, k, res, &rr, st);
  int i;
  for (i = 0; e != BSFIT_OK && !fatal(e) && i < FINAL_TRIES; i++) {
    int r = k->order;
    double ratio = i < 2 && e == BSFIT_ENOCONV && rr.max_deviation > x->tol
                       ? sqrt(0.99 * x->tol / rr.max_deviation) : FINAL_SHRINK;
    double d = k->delta * clampd(ratio, FINAL_SHRINK, 0.99);
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
    e = BSFIT_ENOCONV;
    if (best.order != 0 && best.energy < rep->energy_before) e = finish(&x, &best, &res, rep, st);
    if (e != BSFIT_OK && !fatal(e)) e = unchanged(&x, &res, rep, st);
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
