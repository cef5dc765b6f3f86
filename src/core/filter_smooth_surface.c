/*
** filter_smooth_surface.c
** Smoothing a tensor-product surface to a tolerance, the surface counterpart of
** filter_smooth.c: kernel filters of one order r in both directions, half-widths
** proportional to the mean knot spacing in each direction (delta_u = w h_u,
** delta_v = w h_v), the widest w kept within tol, brought back to degree q in both
** directions over the input's domain by the tensor L2 projection (the curve projection
** along u with whole rows of the net as points, then along v), the order with least
** thin-plate energy (the integral of |S_uu|^2 + 2 |S_uv|^2 + |S_vv|^2, sampled) relative
** to the input's kept, both measured over the interior no kernel support reaches from an
** edge (near the edges the end rule, the surface extended as constant, shapes the
** filter). The distance to the input is the certified upper bound of filter_bound.c, the
** largest |R(u,v) - S(u,v)| from the Bernstein coefficients of the difference on every
** patch: every point of either surface lies that close to the other, so it bounds the
** true distance from above. No knots are added: where the projection on the input's break
** points misses tol, the width is narrower.
*/
#include "filter_internal.h"

#include <math.h>
#include <string.h>

#define MAX_AUTO_ORDER 4
#define STEP 1.4          /* widths tried grow by this factor ... */
#define BEYOND 1.5        /* ... until the distance is this many times tol */
#define DOWN 16           /* steps down, at most */
#define BISECT 3
#define ENERGY_GRID 6     /* energy samples per knot span, each direction */
#define TRIES 8           /* the final width shrinks at most this often, by SHRINK */
#define SHRINK 0.8

typedef struct sctx {
  const bsfit_surface *s;
  const bsfit_allocator *al;
  int q;
  double tol, ua, ub, va, vb, hu, hv;
  int evals;
} sctx;

/* {====================================================================
** Measures
** ===================================================================== */

static size_t spans(const double *U, size_t n, int p) {
  size_t i, k = 0;
  for (i = (size_t)p; i < n; i++) k += U[i + 1] > U[i];
  return k;
}

/* The sampled thin-plate energy of A over the input's domain less margins mu, mv at each
** edge (A's parameter being the input's). */
static double thin_plate(const sctx *x, const bsfit_surface *A, double mu, double mv) {
  double ua = x->ua + mu, ub = x->ub - mu, va = x->va + mv, vb = x->vb - mv, D[3 * 3 * 4];
  double e = 0.0, cell;
  size_t nu = ENERGY_GRID * spans(x->s->knots_u, x->s->nu, x->s->degree_u);
  size_t nv = ENERGY_GRID * spans(x->s->knots_v, x->s->nv, x->s->degree_v), i, j;
  int k, d = A->dim;
  cell = (ub - ua) * (vb - va) / (double)(nu * nv);
  for (i = 0; i < nu; i++)
    for (j = 0; j < nv; j++) {
      double u = ua + (ub - ua) * ((double)i + 0.5) / (double)nu;
      double v = va + (vb - va) * ((double)j + 0.5) / (double)nv;
      bsfit_surface_derivs(A, u, v, 2, D, NULL);
      for (k = 0; k < d; k++) {
        /* D holds d^(a+b) S / du^a dv^b at (a * 3 + b) * d */
        double suu = D[6 * d + k], suv = D[4 * d + k], svv = D[2 * d + k];
        e += (suu * suu + 2.0 * suv * suv + svv * svv) * cell;
      }
    }
  return e;
}

/* The energies of the input and of A over the interior no kernel support (r w spans)
** reaches from an edge, where the end rule (the surface extended as constant) shapes the
** filter rather than the data; at least the middle fifth of each direction. */
static void interior_energies(const sctx *x, const bsfit_surface *A, int r, double w,
                              double *before, double *after) {
  double mu = fmin(r * w * x->hu, 0.4 * (x->ub - x->ua));
  double mv = fmin(r * w * x->hv, 0.4 * (x->vb - x->va));
  *before = thin_plate(x, x->s, mu, mv);
  *after = thin_plate(x, A, mu, mv);
}

/* }==================================================================== */

/* {====================================================================
** The tensor projection on the input's break points
** ===================================================================== */

/* The L2 projection of F, over the input's domain, on degree q in both directions on the
** input's break points (filter_reduce_surface.c). Over the input's domain only: the
** filter's widened edges, where it turns into the constant extension, would make the
** projection ring (the L2 projection is not local) into the interior. */
static bsfit_err project_surface(const sctx *x, const bsfit_surface *F, bsfit_surface *out,
                                 bsfit_status *st) {
  const bsfit_surface *s = x->s;
  bsfit__breaks bu, bv;
  bsfit_err e;
  memset(&bv, 0, sizeof bv);
  e = bsfit__knot_breaks(s->knots_u, s->nu + (size_t)s->degree_u + 1, s->degree_u, x->ua, x->ub,
                         x->q, NULL, 0, x->al, &bu, st);
  if (e == BSFIT_OK)
    e = bsfit__knot_breaks(s->knots_v, s->nv + (size_t)s->degree_v + 1, s->degree_v, x->va,
                           x->vb, x->q, NULL, 0, x->al, &bv, st);
  if (e == BSFIT_OK)
    e = bsfit__project_surface(F, x->q, x->q, &bu, &bv, s->periodic_u, x->al, out, st);
  bsfit__breaks_free(x->al, &bu);
  bsfit__breaks_free(x->al, &bv);
  return e;
}

/* }==================================================================== */

/* {====================================================================
** The search
** ===================================================================== */

typedef struct scand {
  int order;
  double w, dev, energy, before; /* energy: of R, before: of the input, same interior */
  bsfit_surface R; /* the projection, on the filtered domain */
} scand;

static int fatal(bsfit_err e) { return e == BSFIT_ENOMEM || e == BSFIT_EINTR; }

/* Filter of order r at width w (spans), projected; c receives R and its certified bound. */
static bsfit_err evaluate(sctx *x, int r, double w, scand *c, bsfit_status *st) {
  bsfit__bound bd;
  bsfit_surface F;
  bsfit_err e;
  x->evals++;
  c->order = r;
  c->w = w;
  bsfit_surface_init(&F);
  bsfit_surface_init(&c->R);
  if (bsfit__interrupted(x->al)) return bsfit__fail(st, BSFIT_EINTR, "smoothing interrupted");
  e = bsfit_filter_kernel_surface_delta(x->s, r, r, w * x->hu, w * x->hv, &F, st);
  if (e == BSFIT_OK) e = project_surface(x, &F, &c->R, st);
  bsfit_surface_free(&F);
  if (e == BSFIT_OK)
    e = bsfit__surface_diff_bound(&c->R, x->s, x->tol, NULL, NULL, NULL, NULL, x->al, &bd, st);
  c->dev = e == BSFIT_OK ? bd.bound : INFINITY;
  return e;
}

/* Evaluates (r, w); keeps it in best when feasible and wider. */
static bsfit_err try_w(sctx *x, int r, double w, scand *best, double *dev, bsfit_status *st) {
  scand c;
  bsfit_err e = evaluate(x, r, w, &c, st);
  if (e != BSFIT_OK && fatal(e)) {
    bsfit_surface_free(&c.R);
    return e;
  }
  *dev = e == BSFIT_OK ? c.dev : 4.0 * x->tol;
  if (e == BSFIT_OK && c.dev <= x->tol && (best->order != r || w > best->w)) {
    bsfit_surface_free(&best->R);
    *best = c;
    return BSFIT_OK;
  }
  bsfit_surface_free(&c.R);
  return BSFIT_OK;
}

/* The widest feasible width of order r (as filter_smooth.c's search_order). */
static bsfit_err search_order(sctx *x, int r, double w0, scand *best, bsfit_status *st) {
  double wmax = fmin((x->ub - x->ua) / x->hu, (x->vb - x->va) / x->hv) / (2.0 * r);
  double w = fmin(w0, wmax), dev = 0.0, hi = -1;
  bsfit_err e;
  int i;
  for (i = 0; i < DOWN && best->order != r; i++, w /= STEP)
    if ((e = try_w(x, r, w, best, &dev, st)) != BSFIT_OK) return e;
  if (best->order != r) return BSFIT_OK;
  w = best->w;
  while (dev <= BEYOND * x->tol && w < wmax) {
    w = fmin(w * STEP, wmax);
    if ((e = try_w(x, r, w, best, &dev, st)) != BSFIT_OK) return e;
    if (best->w == w) hi = -1;
    else if (hi < 0) hi = w;
  }
  for (i = 0; i < BISECT && hi > 0; i++) {
    double mid = sqrt(best->w * hi), lo = best->w;
    if ((e = try_w(x, r, mid, best, &dev, st)) != BSFIT_OK) return e;
    if (best->w == lo) hi = mid;
  }
  return BSFIT_OK;
}

/* }==================================================================== */

/* {====================================================================
** Public entry
** ===================================================================== */

static bsfit_err check_smooth_surface(const bsfit_surface *s, const bsfit_smooth_opts *o, int q,
                                      bsfit_status *st) {
  bsfit_err e;
  int pmax;
  if (s == NULL || o == NULL) return bsfit__fail(st, BSFIT_EINVAL, "surface or options is NULL");
  e = bsfit_surface_validate(s, st);
  if (e != BSFIT_OK) return e;
  if (s->weights != NULL)
    return bsfit__fail(st, BSFIT_EINVAL, "rational surfaces cannot be filtered");
  if (q < 1 || q > BSFIT__BERN_MAX)
    return bsfit__fail(st, BSFIT_EDEGREE, "degree = %d must be in 1..%d", q, BSFIT__BERN_MAX);
  if (s->degree_u > BSFIT__BERN_MAX || s->degree_v > BSFIT__BERN_MAX)
    return bsfit__fail(st, BSFIT_EDEGREE, "surface degrees %d x %d above %d: no distance bound",
                       s->degree_u, s->degree_v, BSFIT__BERN_MAX);
  if (!isfinite(o->tol)) return bsfit__fail(st, BSFIT_ENONFINITE, "tol = %g is not finite", o->tol);
  if (!(o->tol > 0)) return bsfit__fail(st, BSFIT_EINVAL, "tol = %g must be > 0", o->tol);
  pmax = s->degree_u > s->degree_v ? s->degree_u : s->degree_v;
  if (o->order < 0 || o->order > BSFIT_MAX_DEGREE - pmax)
    return bsfit__fail(st, BSFIT_EINVAL, "order = %d must be in 1..%d (or 0: searched)", o->order,
                       BSFIT_MAX_DEGREE - pmax);
  if (o->order > bsfit__closed_order_cap(s))
    return bsfit__fail(st, BSFIT_ENOTPERIODIC,
                       "order = %d raises the degree in u to %d, and a surface closed around u "
                       "of that degree needs %d distinct rows; this one has %zu",
                       o->order, s->degree_u + o->order, s->degree_u + o->order + 1,
                       s->nu - (size_t)s->degree_u);
  return BSFIT_OK;
}

/* Each order's widest width, the least energy kept in best. Orders the closed net cannot
** take are not tried (each width of them failed, 10 evaluations an order for nothing). */
static bsfit_err search(sctx *x, int order, scand *best, bsfit_status *st) {
  int r, r0 = order ? order : 1, r1 = order ? order : MAX_AUTO_ORDER, last = 0;
  double w0 = 0.5;
  int pmax = x->s->degree_u > x->s->degree_v ? x->s->degree_u : x->s->degree_v;
  if (r1 > BSFIT_MAX_DEGREE - pmax) r1 = BSFIT_MAX_DEGREE - pmax;
  if (r1 > bsfit__closed_order_cap(x->s)) r1 = bsfit__closed_order_cap(x->s);
  for (r = r0; r <= r1; r++) {
    scand cur;
    bsfit_err e;
    memset(&cur, 0, sizeof cur);
    bsfit_surface_init(&cur.R);
    e = search_order(x, r, last ? w0 * sqrt((double)last / r) : w0, &cur, st);
    if (e == BSFIT_OK && cur.order == r) {
      last = r;
      w0 = cur.w;
      interior_energies(x, &cur.R, r, cur.w, &cur.before, &cur.energy);
    }
    if (e != BSFIT_OK || cur.order != r ||
        (best->order != 0 && cur.energy / cur.before >= best->energy / best->before)) {
      bsfit_surface_free(&cur.R);
      if (e != BSFIT_OK) return e;
      continue;
    }
    bsfit_surface_free(&best->R);
    *best = cur;
  }
  return BSFIT_OK;
}

bsfit_err bsfit_filter_smooth_surface(const bsfit_surface *s, const bsfit_smooth_opts *o,
                                      bsfit_surface *out, bsfit_smooth_report *rep,
                                      bsfit_status *st) {
  int q = o != NULL && o->degree != 0 ? o->degree : 3;
  bsfit_smooth_report tmp;
  bsfit_allocator al;
  sctx x;
  scand best;
  bsfit_err e = check_smooth_surface(s, o, q, st);
  if (e != BSFIT_OK) return e;
  if (out == NULL) return bsfit__fail(st, BSFIT_EINVAL, "output surface is NULL");
  if (rep == NULL) rep = &tmp;
  memset(rep, 0, sizeof *rep);
  memset(&x, 0, sizeof x);
  al = s->alloc;
  x.s = s;
  x.al = &al;
  x.q = q;
  x.tol = o->tol;
  bsfit_surface_domain(s, &x.ua, &x.ub, &x.va, &x.vb);
  x.hu = (x.ub - x.ua) / (double)spans(s->knots_u, s->nu, s->degree_u);
  x.hv = (x.vb - x.va) / (double)spans(s->knots_v, s->nv, s->degree_v);
  memset(&best, 0, sizeof best);
  bsfit_surface_init(&best.R);
  e = search(&x, o->order, &best, st);
  rep->evaluations = x.evals;
  if (e != BSFIT_OK) {
    bsfit_surface_free(&best.R);
    return e;
  }
  if (best.order == 0 || !(best.energy < best.before)) {
    bsfit_surface_free(&best.R);
    rep->energy_before = rep->energy_after = thin_plate(&x, s, 0.0, 0.0);
    e = bsfit_surface_copy(s, out, &al, st);
    return e == BSFIT_OK ? bsfit__ok(st) : e;
  }
  rep->changed = 1;
  rep->order = best.order;
  rep->delta = best.w * x.hu;
  rep->max_deviation = rep->bound = best.dev;
  rep->energy_before = best.before;
  rep->energy_after = best.energy;
  bsfit_surface_move(&best.R, out);
  return bsfit__ok(st);
}

/* }==================================================================== */
