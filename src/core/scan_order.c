/*
** scan_order.c
** Ordering a section's points into loops: the neighbour lists, the star test (angle
** about the centroid, accepted only when every step of that order is short compared to
** the local spacing), the orientation of the loops, and the public entry points. The
** graph method for sections that are not star-shaped is in scan_order_graph.c.
*/
#include "scan_order.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

void bsfit_order_opts_init(bsfit_order_opts *o) {
  if (o == NULL) return;
  o->method = BSFIT_ORDER_AUTO;
  o->k = 8;
  o->gap = 4;
  o->min_points = 3;
}

void bsfit_order_result_init(bsfit_order_result *r) {
  if (r != NULL) memset(r, 0, sizeof *r);
}

void bsfit_order_result_free(bsfit_order_result *r) {
  size_t m;
  if (r == NULL) return;
  m = r->capacity;
  bsfit__free(&r->alloc, r->index, m * sizeof(size_t));
  bsfit__free(&r->alloc, r->start, (m + 1) * sizeof(size_t));
  bsfit__free(&r->alloc, r->closed, m);
  memset(r, 0, sizeof *r);
}

/* {======================================================================
** Neighbours
** ====================================================================== */

static bsfit_err neighbours(bsfit__ordwork *w, bsfit_status *st) {
  bsfit__kdtree g;
  size_t i, q, n;
  double *tmp, med;
  bsfit_err e = bsfit__kdtree_build(&g, w->xy, w->m, w->a, st);
  if (e != BSFIT_OK) return e;
  for (i = 0; i < w->m; i++) {
    if ((i & 0xfff) == 0 && bsfit__interrupted(w->a)) {
      bsfit__kdtree_free(&g);
      return bsfit__fail(st, BSFIT_EINTR, "ordering interrupted");
    }
    n = bsfit__kdtree_knn(&g, i, w->k, w->nbr + i * w->k, w->nd + i * w->k);
    for (q = n; q < w->k; q++) {
      w->nbr[i * w->k + q] = BSFIT__NONE;
      w->nd[i * w->k + q] = HUGE_VAL;
    }
    w->spacing[i] = n >= 2 ? w->nd[i * w->k + 1] : n == 1 ? w->nd[i * w->k] : 0;
  }
  bsfit__kdtree_free(&g);
  /* repeated or clustered points would give a zero spacing: floor it at a quarter of
  ** the median, so a step is only judged against spacings the section really has */
  tmp = bsfit__alloc(w->a, w->m * sizeof(double));
  if (tmp == NULL) return bsfit__fail(st, BSFIT_ENOMEM, "out of memory (ordering)");
  memcpy(tmp, w->spacing, w->m * sizeof(double));
  med = bsfit__select(tmp, w->m, w->m / 2);
  bsfit__free(w->a, tmp, w->m * sizeof(double));
  for (i = 0; i < w->m; i++)
    if (w->spacing[i] < med / 4) w->spacing[i] = med / 4;
  return BSFIT_OK;
}

/* }====================================================================== */

/* {======================================================================
** Star test
** ====================================================================== */

typedef struct angidx {
  double ang;
  size_t i;
} angidx;

static int cmp_ang(const void *a, const void *b) {
  const angidx *x = a, *y = b;
  return x->ang < y->ang ? -1 : x->ang > y->ang ? 1 : (x->i > y->i) - (x->i < y->i);
}

/* The angular order about the centroid in r->index; returns whether every step of it is
** within gap times the local spacing. */
static int star_order(const bsfit__ordwork *w, bsfit_order_result *r, angidx *ai) {
  double cx = 0, cy = 0;
  size_t i, m = w->m;
  for (i = 0; i < m; i++) {
    cx += w->xy[2 * i];
    cy += w->xy[2 * i + 1];
  }
  cx /= (double)m;
  cy /= (double)m;
  for (i = 0; i < m; i++) {
    ai[i].ang = atan2(w->xy[2 * i + 1] - cy, w->xy[2 * i] - cx);
    ai[i].i = i;
  }
  qsort(ai, m, sizeof *ai, cmp_ang);
  for (i = 0; i < m; i++) r->index[i] = ai[i].i;
  if (m < 3) return 0;
  for (i = 0; i < m; i++) {
    size_t a = r->index[i], b = r->index[(i + 1) % m];
    double s = bsfit__pair_spacing(w, a, b);
    if (bsfit__dist(w->xy, a, b) > w->gap * s) return 0;
  }
  return 1;
}

/* }====================================================================== */

/* {======================================================================
** Orientation of the loops found
** ====================================================================== */

static double loop_area(const double *xy, const size_t *idx, size_t n) {
  double a = 0;
  size_t i;
  for (i = 0; i < n; i++) {
    const double *p = xy + 2 * idx[i], *q = xy + 2 * idx[(i + 1) % n];
    a += p[0] * q[1] - q[0] * p[1];
  }
  return a / 2;
}

static int loop_contains(const double *xy, const size_t *idx, size_t n, const double *pt) {
  size_t i, j;
  int in = 0;
  for (i = 0, j = n - 1; i < n; j = i++) {
    const double *a = xy + 2 * idx[i], *b = xy + 2 * idx[j];
    if ((a[1] > pt[1]) != (b[1] > pt[1]) &&
        pt[0] < (b[0] - a[0]) * (pt[1] - a[1]) / (b[1] - a[1]) + a[0])
      in = !in;
  }
  return in;
}

static void orient(const double *xy, bsfit_order_result *r) {
  size_t l, j, q;
  for (l = 0; l < r->nloops; l++) {
    size_t *idx = r->index + r->start[l], n = r->start[l + 1] - r->start[l];
    int depth = 0;
    if (!r->closed[l] || n < 3) continue;
    for (j = 0; j < r->nloops; j++)
      if (j != l && r->closed[j] &&
          loop_contains(xy, r->index + r->start[j], r->start[j + 1] - r->start[j], xy + 2 * idx[0]))
        depth++;
    if ((loop_area(xy, idx, n) > 0) != (depth % 2 == 0))
      for (q = 0; q < n / 2; q++) {
        size_t t = idx[q];
        idx[q] = idx[n - 1 - q];
        idx[n - 1 - q] = t;
      }
  }
}

/* }====================================================================== */

static bsfit_err check(const double *xy, size_t m, const bsfit_order_opts *o, bsfit_status *st) {
  size_t i;
  if (xy == NULL || m == 0) return bsfit__fail(st, BSFIT_EINVAL, "no points to order");
  if (o->k < 2 || o->k > 32)
    return bsfit__fail(st, BSFIT_EINVAL, "k must be in 2..32, got %d", o->k);
  if (!(o->gap >= 1) || !isfinite(o->gap))
    return bsfit__fail(st, BSFIT_EINVAL, "gap must be >= 1, got %g", o->gap);
  if ((unsigned)o->method > BSFIT_ORDER_GRAPH)
    return bsfit__fail(st, BSFIT_EINVAL, "unknown method");
  for (i = 0; i < 2 * m; i++)
    if (!isfinite(xy[i]))
      return bsfit__fail(st, BSFIT_ENONFINITE, "point %zu is not finite", i / 2 + 1);
  return BSFIT_OK;
}

/* Allocates the work arrays and the result's arrays (sized for m). */
static bsfit_err alloc_all(bsfit__ordwork *w, bsfit_order_result *r, size_t m, bsfit_status *st) {
  const bsfit_allocator *a = w->a;
  w->nbr = bsfit__alloc(a, bsfit__mulsize(m * w->k, sizeof(size_t)));
  w->nd = bsfit__alloc(a, bsfit__mulsize(m * w->k, sizeof(double)));
  w->spacing = bsfit__alloc(a, m * sizeof(double));
  r->capacity = m;
  if (a != NULL) r->alloc = *a;
  r->index = bsfit__alloc(a, m * sizeof(size_t));
  r->start = bsfit__alloc(a, (m + 1) * sizeof(size_t));
  r->closed = bsfit__alloc(a, m);
  if (!w->nbr || !w->nd || !w->spacing || !r->index || !r->start || !r->closed)
    return bsfit__fail(st, BSFIT_ENOMEM, "out of memory (ordering)");
  return BSFIT_OK;
}

/* Length of the closed tour idx[0..n-1]. */
static double tour_length(const double *xy, const size_t *idx, size_t n) {
  double L = 0;
  size_t i;
  for (i = 0; i < n; i++) L += bsfit__dist(xy, idx[i], idx[(i + 1) % n]);
  return L;
}

/* The angular order as the result: one closed loop. */
static void as_angle(bsfit_order_result *r, const size_t *order, size_t m) {
  memcpy(r->index, order, m * sizeof(size_t));
  r->method = BSFIT_ORDER_ANGLE;
  r->nloops = 1;
  r->start[0] = 0;
  r->start[1] = m;
  r->closed[0] = 1;
  r->dropped = 0;
}

/* Short steps do not make a section star-shaped: points of two walls at one angle (a
** C, sampled coarsely) interleave with short steps. So the angular order is kept only
** when the graph tour is not shorter (on a star-shaped section they agree). */
static bsfit_err run(bsfit__ordwork *w, const bsfit_order_opts *o, bsfit_order_result *r,
                     bsfit_status *st) {
  angidx *ai;
  size_t *order, m = w->m;
  bsfit_err e = neighbours(w, st);
  if (e != BSFIT_OK) return e;
  ai = bsfit__alloc(w->a, m * (sizeof *ai + sizeof(size_t)));
  if (ai == NULL) return bsfit__fail(st, BSFIT_ENOMEM, "out of memory (ordering)");
  order = (size_t *)(void *)(ai + m);
  r->star = star_order(w, r, ai);
  memcpy(order, r->index, m * sizeof(size_t));
  if (o->method == BSFIT_ORDER_ANGLE && !r->star)
    e = bsfit__fail(st, BSFIT_EINVAL,
                    "the points are not star-shaped about their centroid "
                    "(an angular order would jump): use the graph method");
  else if (o->method == BSFIT_ORDER_ANGLE || (r->star && m < w->min_points))
    as_angle(r, order, m);
  else {
    e = bsfit__order_graph(w, r, st);
    if (e == BSFIT_OK && r->star && o->method == BSFIT_ORDER_AUTO &&
        !(r->nloops == 1 && r->closed[0] && r->dropped == 0 &&
          tour_length(w->xy, r->index, m) < (1 - 1e-9) * tour_length(w->xy, order, m)))
      as_angle(r, order, m);
  }
  bsfit__free(w->a, ai, m * (sizeof *ai + sizeof(size_t)));
  return e;
}

bsfit_err bsfit_order(const double *xy, size_t m, const bsfit_order_opts *o, bsfit_order_result *r,
                      const bsfit_allocator *a, bsfit_status *st) {
  bsfit_order_opts def;
  bsfit__ordwork w;
  bsfit_err e;
  if (r == NULL) return bsfit__fail(st, BSFIT_EINVAL, "no result to fill");
  if (o == NULL) {
    bsfit_order_opts_init(&def);
    o = &def;
  }
  e = check(xy, m, o, st);
  if (e != BSFIT_OK) return e;
  bsfit_order_result_free(r);
  memset(&w, 0, sizeof w);
  w.xy = xy;
  w.m = m;
  w.k = (size_t)o->k;
  w.gap = o->gap;
  w.min_points = o->min_points ? o->min_points : 1;
  w.a = a;
  e = alloc_all(&w, r, m, st);
  if (e == BSFIT_OK) e = run(&w, o, r, st);
  if (e == BSFIT_OK && r->nloops == 0)
    e = bsfit__fail(st, BSFIT_ETOOFEW, "no part of %zu or more points among %zu", w.min_points, m);
  if (e == BSFIT_OK) orient(xy, r);
  bsfit__free(a, w.nbr, m * w.k * sizeof(size_t));
  bsfit__free(a, w.nd, m * w.k * sizeof(double));
  bsfit__free(a, w.spacing, m * sizeof(double));
  if (e != BSFIT_OK) bsfit_order_result_free(r);
  return e == BSFIT_OK ? bsfit__ok(st) : e;
}
