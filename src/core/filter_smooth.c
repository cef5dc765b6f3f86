/*
** filter_smooth.c
** Smoothing to a tolerance: the smoothest curve of degree q within tol of C that the
** kernel filters give. "Smoothest" is the least bending energy (the integral of
** curvature^2 ds, bsfit_curve_bending_energy). Each width tried is judged on what would
** be returned: the filtered curve (order r, half-width delta) brought to degree q by the
** L2 projection on C's break points (filter_reduce.c), and a certified upper bound of its
** distance to C, the largest |R(t) - C(t)| from the Bernstein coefficients of the
** difference on each span (filter_bound.c): O(n) per width, no closest points. For each
** order (the given one, or 1..MAX_AUTO_ORDER) the widest delta whose bound meets tol is
** searched in a few evaluations (search_order: steps scaled by the delta^2 growth of the
** shrinking, then a secant inside the bracket), the next order starting from the width of
** the same kernel variance. The order whose result has least energy wins; its distance to C
** is then measured once, as a true distance (at most the bound). When no width keeps C
** within tol, or the best result is not at least MIN_GAIN smoother than C, C is returned
** unchanged (at degree q) and the report says so.
*/
#include "filter_internal.h"

#include <float.h>
#include <math.h>
#include <string.h>

#define MAX_AUTO_ORDER 3 /* order 4 costs the most and smooths no better than 2 or 3 */
#define TARGET 0.95      /* the search aims the bound at this much of tol ... */
#define CLOSE 0.9        /* ... and stops once a feasible width's bound reaches this much */
#define DONE_RATIO 1.03  /* or once the widest feasible and narrowest infeasible are this near */
#define MAX_EVALS 8      /* widths tried per order, at most */
#define REPORT_SAMPLES 4 /* the measured distance of the result: samples per knot span */
#define ENERGY_SAMPLES 8 /* energy and turning: samples per knot span of C (>= 256) */
#define BASE_SHARE 0.25  /* of tol, for C's own reduction when its degree exceeds q */
#define FOLLOW 0.002    /* the winner's projection follows its filtered curve this closely */
#define RIPPLE 1.005    /* ... when its energy exceeds the filtered curve's by this factor */
#define MIN_GAIN 0.01   /* a result less smoother than this is not worth moving C */
#define MEASURED_BELOW 0.8 /* a winner measured below this much of tol is searched again ... */
#define MEASURED_MARGIN 0.995 /* ... by its measured distance, kept below this much of tol */

/* What the search carries. */
typedef struct smooth_ctx {
  const bsfit_curve *c;
  const bsfit_allocator *al;
  int q;
  double tol, a, b;
  size_t samples;            /* energy samples */
  double last_delta;         /* the previous order's best width (0: none yet) */
  int last_order;
  const bsfit__breaks *base; /* the target's break points in [a, b] (C's, and any knots the
                                reduction of C itself to degree q needed) */
  int evals;
  int measured; /* judge widths by the measured distance (second pass), not the bound */
} smooth_ctx;

/* One candidate: the filtered curve brought to degree q, its bound and its energy. */
typedef struct candidate {
  int order;
  double delta, bound, dist, energy, turning; /* dist: measured, or -1 when not yet */
  size_t added;                              /* knots added to follow the filtered curve */
  bsfit_curve R;
} candidate;

static void cand_init(candidate *k) {
  memset(k, 0, sizeof *k);
  bsfit_curve_init(&k->R);
}

static void cand_free(candidate *k) { bsfit_curve_free(&k->R); }

/* The break points of the target for the filtered F: the base ones (an open F is
** projected over C's domain only: its widened ends, where it turns into the constant
** extension, would make the projection ring into the interior; a closed F may start its
** period later, and the base points come round again after it). */
static bsfit_err target_breaks(const smooth_ctx *x, const bsfit_curve *F, bsfit__breaks *b) {
  const bsfit__breaks *B = x->base;
  double lo, hi, T = x->b - x->a, eps = 1e-9 * T;
  size_t i;
  int j;
  memset(b, 0, sizeof *b);
  if (bsfit__breaks_reserve(x->al, b, 2 * B->n + 4) != BSFIT_OK) return BSFIT_ENOMEM;
  if (F->periodic) bsfit_curve_domain(F, &lo, &hi);
  else lo = x->a, hi = x->b;
  b->x[0] = lo;
  b->mult[0] = 1;
  b->n = 1;
  for (j = 0; j < (F->periodic ? 2 : 1); j++)
    for (i = 0; i < B->n; i++) {
      double v = B->x[i] + (double)j * T;
      if (v > b->x[b->n - 1] + eps && v < hi - eps) {
        b->mult[b->n] = B->mult[i];
        b->x[b->n++] = v;
      }
    }
  b->mult[b->n] = 1;
  b->x[b->n++] = hi;
  return BSFIT_OK;
}

/* F projected on degree q on the target break points, into R. */
static bsfit_err project(smooth_ctx *x, const bsfit_curve *F, bsfit_curve *R, bsfit_status *st) {
  bsfit__breaks b;
  bsfit__fview v;
  bsfit__fspline f;
  bsfit_err e;
  if (target_breaks(x, F, &b) != BSFIT_OK)
    return bsfit__fail(st, BSFIT_ENOMEM, "out of memory for break points");
  v.p = F->degree;
  v.n = F->n;
  v.d = (size_t)F->dim;
  v.U = F->knots;
  v.P = F->ctrl;
  e = bsfit__project(&v, NULL, F->periodic, x->q, &b, x->al, &f, st);
  bsfit__breaks_free(x->al, &b);
  if (e != BSFIT_OK) return e;
  return bsfit__fspline_to_curve(&f, F->dim, F->periodic, x->al, R, st);
}

/* R's distance to C measured, into k->dist: a true distance, at most the bound. For a
** result the bound already certifies, the feet from the same parameter with the largest
** checked by global closest points; in the measured pass, where the distance decides,
** the global closest point of every sample. */
static bsfit_err measure(smooth_ctx *x, candidate *k, bsfit_status *st) {
  if (k->dist >= 0.0) return BSFIT_OK;
  return bsfit__curve_distance(&k->R, x->c, REPORT_SAMPLES,
                               x->measured ? BSFIT__DIST_VERIFIED : BSFIT__DIST_FEET, NULL, NULL,
                               x->al, &k->dist, st);
}

/* The value a width is judged by: the bound, or in the measured pass the distance. */
static double judged(const smooth_ctx *x, const candidate *k) {
  return x->measured ? k->dist / MEASURED_MARGIN : k->bound;
}

/* Filters C (order r, half-width delta), brings it to degree q and bounds its distance
** to C (certified); in the measured pass, measures it too. */
static bsfit_err evaluate(smooth_ctx *x, int r, double delta, candidate *k, bsfit_status *st) {
  bsfit__bound bd;
  bsfit_curve F;
  bsfit_err e;
  if (bsfit__interrupted(x->al)) return bsfit__fail(st, BSFIT_EINTR, "smoothing interrupted");
  x->evals++;
  k->order = r;
  k->delta = delta;
  bsfit_curve_init(&F);
  e = bsfit_filter_kernel_curve_delta(x->c, r, delta, &F, st);
  if (e == BSFIT_OK) e = project(x, &F, &k->R, st);
  bsfit_curve_free(&F);
  if (e == BSFIT_OK) e = bsfit__curve_diff_bound(&k->R, x->c, x->tol, NULL, NULL, x->al, &bd, st);
  k->bound = e == BSFIT_OK ? bd.bound : INFINITY;
  k->dist = -1.0;
  return e == BSFIT_OK && x->measured ? measure(x, k, st) : e;
}

/* {====================================================================
** The search over delta for one order
** ===================================================================== */

static double clampd(double v, double lo, double hi) { return v < lo ? lo : (v > hi ? hi : v); }

/* Errors that only say this delta is not usable (a window too wide for the curve). */
static int fatal(bsfit_err e) { return e == BSFIT_ENOMEM || e == BSFIT_EINTR; }

/* Evaluates order r at d; keeps the candidate in best when it is feasible and wider than
** best. *bound receives what it is judged by (4 tol when d is not usable). */
static bsfit_err try_delta(smooth_ctx *x, int r, double d, candidate *best, double *bound,
                           bsfit_status *st) {
  candidate k;
  bsfit_err e;
  cand_init(&k);
  e = evaluate(x, r, d, &k, st);
  if (e != BSFIT_OK && fatal(e)) {
    cand_free(&k);
    return e;
  }
  *bound = e == BSFIT_OK ? judged(x, &k) : 4.0 * x->tol;
  if (e == BSFIT_OK && *bound <= x->tol && (best->order != r || d > best->delta)) {
    cand_free(best);
    *best = k; /* best owns k's curve now */
    return BSFIT_OK;
  }
  cand_free(&k);
  return BSFIT_OK;
}

/* The bracket of one order's search: the widest feasible width lo (bound blo <= tol), the
** feasible width before it (prev, bound bprev: the growth rate between them), and the
** narrowest infeasible one above lo, hi (bound bhi); 0 when not found yet. */
typedef struct bracket {
  double prev, bprev, lo, blo, hi, bhi;
} bracket;

/* The next width. Below the bracket the bound grows like delta^alpha: alpha about 1 where
** the filter removes noise, 2 where its shrinking of the shape dominates (the kernel's
** variance is r delta^2 / 3); alpha is measured between the last two feasible widths
** (1 at first), and the step aims at the target. Inside a bracket, the secant of log bound
** against log delta, kept off its ends. */
static double next_width(const bracket *k, double target, double dmax) {
  double alpha = 1.0;
  if (k->lo == 0.0) return k->hi * clampd(target / k->bhi, 0.1, 0.7);
  if (k->hi == 0.0) {
    if (k->prev > 0.0 && k->blo > k->bprev)
      alpha = clampd(log(k->blo / k->bprev) / log(k->lo / k->prev), 0.5, 2.5);
    return fmin(dmax, k->lo * clampd(pow(target / k->blo, 1.0 / alpha), 1.2, 6.0));
  }
  if (k->bhi > k->blo) {
    double l0 = log(k->lo), l1 = log(k->hi);
    double f = (log(target) - log(k->blo)) / (log(k->bhi) - log(k->blo));
    return exp(l0 + (l1 - l0) * clampd(f, 0.15, 0.85));
  }
  return sqrt(k->lo * k->hi);
}

/* The widest feasible delta of order r, into best (left alone when none is found), in a
** few evaluations (next_width). The bound is not monotone in delta near the noise floor (it
** follows the noise the filter removes, up and down): the search keeps the widest feasible
** width it saw and narrows the bracket above it. */
static bsfit_err search_order(smooth_ctx *x, int r, candidate *best, bsfit_status *st) {
  size_t spans = x->base->n - 1;
  double h = (x->b - x->a) / (double)spans, dmax = (x->b - x->a) / (2.0 * r);
  /* same kernel variance r delta^2 / 3, about the same bound: the previous order's answer
  ** scaled is a close first guess */
  double d = fmin(x->last_order ? x->last_delta * sqrt((double)x->last_order / r) : h, dmax);
  bracket k = {0.0, 0.0, 0.0, 0.0, 0.0, 0.0};
  bsfit_err e;
  int i;
  if (best->order == r && best->dist >= 0.0) { /* the measured pass goes on from there */
    k.lo = best->delta;
    k.blo = judged(x, best);
    d = next_width(&k, TARGET * x->tol, dmax);
  }
  for (i = 0; i < MAX_EVALS; i++) {
    double bd;
    if ((e = try_delta(x, r, d, best, &bd, st)) != BSFIT_OK) return e;
    if (bd <= x->tol && d > k.lo) k.prev = k.lo, k.bprev = k.blo, k.lo = d, k.blo = bd;
    else if (bd > x->tol && d > k.lo && (k.hi == 0.0 || d < k.hi)) k.hi = d, k.bhi = bd;
    if (k.lo > 0 && (k.blo >= CLOSE * x->tol || k.lo >= dmax)) break;
    if (k.lo > 0 && k.hi > 0 && k.hi < DONE_RATIO * k.lo) break;
    d = next_width(&k, TARGET * x->tol, dmax);
  }
  if (best->order != r) return BSFIT_OK;
  x->last_order = r;
  x->last_delta = best->delta;
  bsfit__curve_shape(&best->R, x->samples, &best->turning, &best->energy);
  return BSFIT_OK;
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

/* The target's break points: C's knots, with the multiplicities degree q needs to
** reproduce C there; when C's degree exceeds q, those of C's own reduction to degree q
** within BASE_SHARE tol (knots added where it needs them, counted in knots_added). */
static bsfit_err base_breaks(smooth_ctx *x, bsfit__breaks *b, bsfit_smooth_report *rep,
                             bsfit_status *st) {
  bsfit__reduce_arg r;
  bsfit_reduce_report rr;
  bsfit_curve res;
  bsfit_err e = bsfit__curve_breaks(x->c, x->q, x->al, b, st);
  if (e != BSFIT_OK || x->c->degree <= x->q) return e;
  memset(&r, 0, sizeof r);
  r.degree = x->q;
  r.tol = BASE_SHARE * x->tol;
  r.per_span = REPORT_SAMPLES;
  r.max_added = 10 * b->n + 100;
  bsfit_curve_init(&res);
  e = bsfit__reduce_loop(x->c, &r, b, x->al, &res, &rr, st);
  bsfit_curve_free(&res);
  rep->knots_added = rr.knots_added;
  if (e != BSFIT_OK) bsfit__breaks_free(x->al, b);
  return e;
}

/* Nothing smoother within tol: C itself at degree q (elevated, or reduced within tol). */
static bsfit_err unchanged(smooth_ctx *x, bsfit_curve *res, bsfit_smooth_report *rep,
                           bsfit_status *st) {
  const bsfit_curve *c = x->c;
  bsfit_reduce_opts o;
  bsfit_reduce_report rr;
  bsfit_err e;
  rep->changed = 0;
  rep->order = 0;
  rep->delta = 0.0;
  rep->max_deviation = rep->bound = 0.0;
  rep->knots_added = 0;
  if (c->degree == x->q) return bsfit_curve_copy(c, res, x->al, st);
  if (c->degree < x->q) return bsfit_curve_elevate(c, x->q - c->degree, res, st);
  memset(&o, 0, sizeof o);
  o.degree = x->q;
  o.tol = x->tol;
  e = bsfit_filter_reduce_curve(c, &o, res, &rr, st);
  rep->max_deviation = rr.max_deviation;
  rep->bound = rr.bound;
  rep->knots_added = rr.knots_added;
  return e;
}

/* The winner's filtered curve followed more closely: its projection with knots added
** where it strays from the filtered curve by more than FOLLOW tol (the L2 projection on
** C's break points alone ripples where the filter rounded a corner over a few spans, and
** the ripples cost energy). Kept when still within tol of C (bound, or measured in the
** measured pass) and smoother. Failing to follow leaves the winner as it was. */
static bsfit_err follow(smooth_ctx *x, candidate *k, bsfit_status *st) {
  bsfit__reduce_arg ra;
  bsfit_reduce_report rr;
  bsfit__breaks b;
  candidate f;
  bsfit_curve F;
  bsfit_err e;
  cand_init(&f);
  bsfit_curve_init(&F);
  memset(&ra, 0, sizeof ra);
  ra.degree = x->q;
  ra.tol = FOLLOW * x->tol;
  ra.per_span = REPORT_SAMPLES;
  ra.max_added = x->base->n / 4 + 8;
  ra.bound_only = 1;
  e = bsfit_filter_kernel_curve_delta(x->c, k->order, k->delta, &F, st);
  if (e == BSFIT_OK) {
    double eF;
    bsfit__curve_shape(&F, x->samples, NULL, &eF);
    if (!(k->energy > RIPPLE * eF)) { /* the projection did not ripple: nothing to follow */
      bsfit_curve_free(&F);
      return BSFIT_OK;
    }
  }
  if (e == BSFIT_OK && target_breaks(x, &F, &b) != BSFIT_OK)
    e = bsfit__fail(st, BSFIT_ENOMEM, "out of memory for break points");
  else if (e == BSFIT_OK) {
    e = bsfit__reduce_loop(&F, &ra, &b, x->al, &f.R, &rr, st);
    bsfit__breaks_free(x->al, &b);
  }
  bsfit_curve_free(&F);
  if (e == BSFIT_OK && rr.knots_added > 0) {
    bsfit__bound bd;
    f.order = k->order;
    f.delta = k->delta;
    f.dist = -1.0;
    f.added = rr.knots_added;
    e = bsfit__curve_diff_bound(&f.R, x->c, x->tol, NULL, NULL, x->al, &bd, st);
    f.bound = e == BSFIT_OK ? bd.bound : INFINITY;
    if (e == BSFIT_OK && (f.bound <= x->tol || x->measured)) e = measure(x, &f, st);
    if (e == BSFIT_OK && judged(x, &f) <= x->tol) {
      bsfit__curve_shape(&f.R, x->samples, &f.turning, &f.energy);
      if (f.energy < k->energy) {
        cand_free(k);
        *k = f;
        return BSFIT_OK;
      }
    }
  }
  cand_free(&f);
  return fatal(e) ? e : BSFIT_OK;
}

/* The winner, within tol by its certified bound or its measured distance, into res. */
static bsfit_err finish(smooth_ctx *x, candidate *k, bsfit_curve *res, bsfit_smooth_report *rep,
                        bsfit_status *st) {
  bsfit_err e = follow(x, k, st);
  if (e == BSFIT_OK) e = measure(x, k, st);
  if (e != BSFIT_OK) return e;
  rep->max_deviation = k->dist;
  rep->changed = 1;
  rep->knots_added += k->added;
  rep->order = k->order;
  rep->delta = k->delta;
  rep->bound = k->bound;
  rep->turning_after = k->turning;
  rep->energy_after = k->energy;
  bsfit_curve_move(&k->R, res);
  return BSFIT_OK;
}

/* Each order's widest width (search_order); the least energy is kept in best, which may
** already hold a candidate. */
static bsfit_err over_orders(smooth_ctx *x, int r0, int r1, candidate *best, bsfit_status *st) {
  bsfit_err e = BSFIT_OK;
  int r;
  x->last_order = 0;
  for (r = r0; r <= r1 && e == BSFIT_OK; r++) {
    candidate cur;
    cand_init(&cur);
    if (best->order == r) { /* the measured pass goes on from the bound pass's width */
      cur = *best;
      cand_init(best);
    }
    e = search_order(x, r, &cur, st);
    if (e == BSFIT_OK && cur.order == r && (best->order == 0 || cur.energy < best->energy)) {
      cand_free(best);
      *best = cur;
    } else {
      cand_free(&cur);
    }
  }
  return e;
}

/* The best candidate over the orders to try, into best (order 0 when none is feasible). */
static bsfit_err search(smooth_ctx *x, int order, candidate *best, bsfit_status *st) {
  int r0 = order ? order : 1, r1 = order ? order : MAX_AUTO_ORDER;
  bsfit_err e;
  if (r1 > BSFIT_MAX_DEGREE - x->c->degree) r1 = BSFIT_MAX_DEGREE - x->c->degree;
  e = over_orders(x, r0, r1, best, st);
  if (e == BSFIT_OK && best->order != 0) e = measure(x, best, st);
  /* the bound counts motion along the curve too (tangential, at open ends, at corners):
  ** where it is far above the distance, the orders are searched again by the measured
  ** distance, each from its width of the first pass */
  if (e == BSFIT_OK && (best->order == 0 || best->dist < MEASURED_BELOW * x->tol)) {
    x->measured = 1;
    e = over_orders(x, r0, r1, best, st);
  }
  return e;
}

/* The search and its outcome into res, with the shape measures before and after. */
static bsfit_err run(smooth_ctx *x, int order, bsfit_curve *res, bsfit_smooth_report *rep,
                     bsfit_status *st) {
  candidate best;
  size_t added = rep->knots_added;
  bsfit_err e;
  cand_init(&best);
  bsfit__curve_shape(x->c, x->samples, &rep->turning_before, &rep->energy_before);
  e = search(x, order, &best, st);
  if (e == BSFIT_OK) {
    if (best.order != 0 && best.energy < (1.0 - MIN_GAIN) * rep->energy_before) {
      rep->knots_added = added;
      e = finish(x, &best, res, rep, st);
    } else {
      e = unchanged(x, res, rep, st);
      if (e == BSFIT_OK)
        bsfit__curve_shape(res, x->samples, &rep->turning_after, &rep->energy_after);
    }
  }
  cand_free(&best);
  return e;
}

bsfit_err bsfit_filter_smooth_curve(const bsfit_curve *c, const bsfit_smooth_opts *o,
                                    bsfit_curve *out, bsfit_smooth_report *rep,
                                    bsfit_status *st) {
  int q = o != NULL && o->degree != 0 ? o->degree : 3;
  bsfit_smooth_report tmp;
  bsfit_allocator al;
  bsfit__breaks base;
  smooth_ctx x;
  bsfit_curve res;
  bsfit_err e = check_smooth(c, o, q, st);
  if (e != BSFIT_OK) return e;
  if (out == NULL) return bsfit__fail(st, BSFIT_EINVAL, "output curve is NULL");
  if (rep == NULL) rep = &tmp;
  memset(rep, 0, sizeof *rep);
  al = c->alloc;
  memset(&x, 0, sizeof x);
  x.c = c;
  x.al = &al;
  x.q = q;
  x.tol = o->tol;
  bsfit_curve_domain(c, &x.a, &x.b);
  bsfit_curve_init(&res);
  e = base_breaks(&x, &base, rep, st);
  if (e == BSFIT_ENOCONV) e = unchanged(&x, &res, rep, st); /* C itself cannot be reduced */
  else if (e == BSFIT_OK) {
    x.base = &base;
    x.samples = ENERGY_SAMPLES * (base.n - 1) < 256 ? 256 : ENERGY_SAMPLES * (base.n - 1);
    e = run(&x, o->order, &res, rep, st);
    bsfit__breaks_free(&al, &base);
  }
  rep->evaluations = x.evals;
  if (e == BSFIT_OK) bsfit_curve_move(&res, out);
  bsfit_curve_free(&res);
  return e == BSFIT_OK ? bsfit__ok(st) : e;
}

/* }==================================================================== */
