/*
** filter_reduce_surface.c
** A tensor-product surface brought to degrees (qu, qv): the L2 projection over its domain
** onto the splines of those degrees on break points chosen per direction. The Gram matrix
** of a tensor basis over a rectangle is the Kronecker product of the two directions' Gram
** matrices, so the 2-D projection is the curve projection of filter_reduce.c along u
** (whole rows of the net as points; periodic when the surface is closed around u) followed
** by the one along v on the result's columns: two banded solves, never a dense system.
** The distance to the input is bounded, certified, by the Bernstein coefficients of the
** difference on each patch (filter_bound.c); while the bound exceeds tol, a knot goes in the
** middle of every u span and every v span that holds a patch beyond tol, and the projection
** is repeated.
*/
#include "filter_internal.h"

#include <math.h>
#include <string.h>

#define DEFAULT_DEGREE 3
#define STALL_ROUNDS 3 /* rounds of knots added that may leave the bound as it was */

/* {====================================================================
** The tensor projection
** ===================================================================== */

/* What the projection along v needs (bsfit__vop). */
typedef struct vproj {
  int q;
  const bsfit__breaks *b;
} vproj;

static bsfit_err project_along_v(const bsfit__fview *v, const void *arg, const bsfit_allocator *a,
                                 bsfit__fspline *out, bsfit_status *st) {
  const vproj *w = arg;
  return bsfit__project(v, NULL, 0, w->q, w->b, a, out, st);
}

bsfit_err bsfit__project_surface(const bsfit_surface *F, int qu, int qv, const bsfit__breaks *bu,
                                 const bsfit__breaks *bv, int periodic_u,
                                 const bsfit_allocator *al, bsfit_surface *out,
                                 bsfit_status *st) {
  bsfit__fview v = bsfit__surface_view_u(F);
  bsfit__fspline fu;
  vproj w;
  bsfit_err e = bsfit__project(&v, NULL, periodic_u, qu, bu, al, &fu, st);
  if (e != BSFIT_OK) return e;
  w.q = qv;
  w.b = bv;
  e = bsfit__surface_along_v(F, &fu, project_along_v, &w, periodic_u, al, out, st);
  bsfit__fspline_free(al, &fu);
  return e;
}

/* }==================================================================== */

/* {====================================================================
** Knots added until the bound meets tol
** ===================================================================== */

typedef struct rloop {
  const bsfit_surface *s;
  int qu, qv;
  double tol;
  size_t max_added;
  bsfit__breaks bu, bv;
  double *mu, *mv; /* the bound per break span of bu and bv */
  size_t cu, cv;   /* their capacities */
} rloop;

/* Room for the span bounds of the current break points. */
static bsfit_err span_room(rloop *r, const bsfit_allocator *al) {
  if (r->cu < r->bu.n) {
    bsfit__free(al, r->mu, r->cu * sizeof(double));
    r->cu = r->bu.cap;
    r->mu = bsfit__alloc(al, r->cu * sizeof(double));
  }
  if (r->cv < r->bv.n) {
    bsfit__free(al, r->mv, r->cv * sizeof(double));
    r->cv = r->bv.cap;
    r->mv = bsfit__alloc(al, r->cv * sizeof(double));
  }
  return r->mu == NULL || r->mv == NULL ? BSFIT_ENOMEM : BSFIT_OK;
}

/* One projection and its bound. */
static bsfit_err round_once(rloop *r, const bsfit_allocator *al, bsfit_surface *res,
                            bsfit__bound *bd, bsfit_status *st) {
  bsfit_err e = bsfit__project_surface(r->s, r->qu, r->qv, &r->bu, &r->bv, r->s->periodic_u, al,
                                       res, st);
  if (e == BSFIT_OK && span_room(r, al) != BSFIT_OK)
    e = bsfit__fail(st, BSFIT_ENOMEM, "out of memory for span bounds");
  if (e == BSFIT_OK)
    e = bsfit__surface_diff_bound(res, r->s, r->tol, &r->bu, r->mu, &r->bv, r->mv, al, bd, st);
  return e;
}

static bsfit_err reduce_loop(rloop *r, const bsfit_allocator *al, bsfit_surface *res,
                             bsfit_reduce_report *rep, bsfit_status *st) {
  double best = INFINITY;
  size_t added = 0, nu, nv;
  int stalled = 0;
  bsfit_err e;
  for (;;) {
    bsfit__bound bd;
    if (bsfit__interrupted(al)) return bsfit__fail(st, BSFIT_EINTR, "degree reduction interrupted");
    e = round_once(r, al, res, &bd, st);
    rep->rounds++;
    if (e != BSFIT_OK) break;
    rep->bound = rep->max_deviation = bd.bound;
    if (bd.bound <= r->tol) break;
    stalled = bd.bound < 0.99 * best ? 0 : stalled + 1;
    best = fmin(best, bd.bound);
    if (added >= r->max_added || stalled >= STALL_ROUNDS) {
      e = bsfit__fail(st, BSFIT_ENOCONV,
                      "degrees %d x %d within tol = %g not reached after adding %zu knots "
                      "(bound %g)", r->qu, r->qv, r->tol, added, bd.bound);
      break;
    }
    if (bsfit__split_spans(&r->bu, r->mu, r->tol, al, &nu) != BSFIT_OK ||
        bsfit__split_spans(&r->bv, r->mv, r->tol, al, &nv) != BSFIT_OK) {
      e = bsfit__fail(st, BSFIT_ENOMEM, "out of memory adding knots");
      break;
    }
    if (nu + nv == 0) {
      e = bsfit__fail(st, BSFIT_ENOCONV, "no span to refine at bound %g", bd.bound);
      break;
    }
    added += nu + nv;
  }
  rep->knots_added = added;
  return e;
}

/* }==================================================================== */

/* {====================================================================
** Public entry
** ===================================================================== */

static bsfit_err check_reduce_surface(const bsfit_surface *s, const bsfit_reduce_surface_opts *o,
                                      int qu, int qv, bsfit_status *st) {
  bsfit_err e;
  if (s == NULL || o == NULL) return bsfit__fail(st, BSFIT_EINVAL, "surface or options is NULL");
  e = bsfit_surface_validate(s, st);
  if (e != BSFIT_OK) return e;
  if (s->weights != NULL)
    return bsfit__fail(st, BSFIT_EINVAL, "rational surfaces cannot be reduced");
  if (qu < 1 || qu > BSFIT__BERN_MAX || qv < 1 || qv > BSFIT__BERN_MAX)
    return bsfit__fail(st, BSFIT_EDEGREE, "degrees %d x %d must be in 1..%d", qu, qv,
                       BSFIT__BERN_MAX);
  if (s->degree_u > BSFIT__BERN_MAX || s->degree_v > BSFIT__BERN_MAX)
    return bsfit__fail(st, BSFIT_EDEGREE, "surface degrees %d x %d above %d: no bound",
                       s->degree_u, s->degree_v, BSFIT__BERN_MAX);
  if (isnan(o->tol)) return bsfit__fail(st, BSFIT_ENONFINITE, "tol is NaN");
  if (!(o->tol > 0)) return bsfit__fail(st, BSFIT_EINVAL, "tol = %g must be > 0", o->tol);
  return BSFIT_OK;
}

bsfit_err bsfit_filter_reduce_surface(const bsfit_surface *s, const bsfit_reduce_surface_opts *o,
                                      bsfit_surface *out, bsfit_reduce_report *rep,
                                      bsfit_status *st) {
  int qu = o != NULL && o->degree_u != 0 ? o->degree_u : DEFAULT_DEGREE;
  int qv = o != NULL && o->degree_v != 0 ? o->degree_v : DEFAULT_DEGREE;
  bsfit_reduce_report tmp;
  bsfit_allocator al;
  bsfit_surface res;
  double ua, ub, va, vb;
  rloop r;
  bsfit_err e = check_reduce_surface(s, o, qu, qv, st);
  if (e != BSFIT_OK) return e;
  if (out == NULL) return bsfit__fail(st, BSFIT_EINVAL, "output surface is NULL");
  if (rep == NULL) rep = &tmp;
  memset(rep, 0, sizeof *rep);
  memset(&r, 0, sizeof r);
  al = s->alloc;
  r.s = s;
  r.qu = qu;
  r.qv = qv;
  r.tol = o->tol;
  bsfit_surface_domain(s, &ua, &ub, &va, &vb);
  e = bsfit__knot_breaks(s->knots_u, s->nu + (size_t)s->degree_u + 1, s->degree_u, ua, ub, qu,
                         NULL, 0, &al, &r.bu, st);
  if (e == BSFIT_OK)
    e = bsfit__knot_breaks(s->knots_v, s->nv + (size_t)s->degree_v + 1, s->degree_v, va, vb, qv,
                           NULL, 0, &al, &r.bv, st);
  r.max_added = o->max_added ? o->max_added : 10 * (r.bu.n + r.bv.n) + 100;
  bsfit_surface_init(&res);
  if (e == BSFIT_OK) e = reduce_loop(&r, &al, &res, rep, st);
  bsfit__breaks_free(&al, &r.bu);
  bsfit__breaks_free(&al, &r.bv);
  bsfit__free(&al, r.mu, r.cu * sizeof(double));
  bsfit__free(&al, r.mv, r.cv * sizeof(double));
  if (e == BSFIT_OK) bsfit_surface_move(&res, out);
  bsfit_surface_free(&res);
  return e == BSFIT_OK ? bsfit__ok(st) : e;
}

/* }==================================================================== */
