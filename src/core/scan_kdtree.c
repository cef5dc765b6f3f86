/*
** scan_kdtree.c
** A 2D k-d tree over points for k-nearest-neighbour queries (the ordering's graph). The
** tree is implicit: the node of the index range [lo, hi) splits at mid = (lo + hi) / 2
** along the wider side of the range's bounding box, its children are [lo, mid) and
** [mid, hi), and its split is stored at index mid (every internal node has its own mid).
** Building is O(m log m) (a selection per level), a query O(log m + k) on any
** distribution: points on a curve, clusters and far outliers alike.
*/
#include "scan_internal.h"

#include <math.h>
#include <string.h>

#define LEAF 8

static double coord(const bsfit__kdtree *t, size_t q, int d) {
  return t->xy[2 * t->perm[q] + (size_t)d];
}

static void swap(size_t *p, size_t a, size_t b) {
  size_t x = p[a];
  p[a] = p[b];
  p[b] = x;
}

/* Reorders perm[lo..hi) so that position k holds the element of rank k along d (Hoare's
** selection with the middle element as pivot; O(n) expected on scan data). */
static void select_k(bsfit__kdtree *t, size_t lo, size_t hi, size_t k, int d) {
  while (hi - lo > 1) {
    double pivot = coord(t, lo + (hi - lo) / 2, d);
    size_t i = lo, j = hi - 1;
    while (i <= j) {
      while (coord(t, i, d) < pivot) i++;
      while (coord(t, j, d) > pivot) j--;
      if (i <= j) {
        swap(t->perm, i, j);
        i++;
        if (j == 0) break;
        j--;
      }
    }
    if (k <= j)
      hi = j + 1;
    else if (k >= i)
      lo = i;
    else
      return;
  }
}

static void build(bsfit__kdtree *t, size_t lo, size_t hi) {
  double x0 = HUGE_VAL, x1 = -HUGE_VAL, y0 = HUGE_VAL, y1 = -HUGE_VAL;
  size_t q, mid;
  int d;
  if (hi - lo <= LEAF) return;
  for (q = lo; q < hi; q++) {
    double x = coord(t, q, 0), y = coord(t, q, 1);
    x0 = x < x0 ? x : x0, x1 = x > x1 ? x : x1;
    y0 = y < y0 ? y : y0, y1 = y > y1 ? y : y1;
  }
  d = (x1 - x0) >= (y1 - y0) ? 0 : 1;
  mid = lo + (hi - lo) / 2;
  select_k(t, lo, hi, mid, d);
  t->dim[mid] = (unsigned char)d;
  t->split[mid] = coord(t, mid, d);
  build(t, lo, mid);
  build(t, mid, hi);
}

bsfit_err bsfit__kdtree_build(bsfit__kdtree *t, const double *xy, size_t m,
                              const bsfit_allocator *a, bsfit_status *st) {
  size_t i;
  memset(t, 0, sizeof *t);
  t->xy = xy;
  t->m = m;
  t->a = a;
  t->perm = bsfit__alloc(a, m * sizeof(size_t));
  t->split = bsfit__alloc(a, m * sizeof(double));
  t->dim = bsfit__alloc(a, m);
  if (t->perm == NULL || t->split == NULL || t->dim == NULL) {
    bsfit__kdtree_free(t);
    return bsfit__fail(st, BSFIT_ENOMEM, "out of memory (neighbour tree)");
  }
  for (i = 0; i < m; i++) t->perm[i] = i;
  build(t, 0, m);
  return BSFIT_OK;
}

void bsfit__kdtree_free(bsfit__kdtree *t) {
  bsfit__free(t->a, t->perm, t->m * sizeof(size_t));
  bsfit__free(t->a, t->split, t->m * sizeof(double));
  bsfit__free(t->a, t->dim, t->m);
  t->perm = NULL;
  t->split = NULL;
  t->dim = NULL;
}

/* {======================================================================
** Queries
** ====================================================================== */

typedef struct query {
  const bsfit__kdtree *t;
  size_t self, k, n;
  double x, y;
  size_t *idx;
  double *d2; /* squared distances, sorted */
} query;

static void offer(query *Q, size_t j, double d2) {
  size_t p;
  if (Q->n == Q->k && d2 >= Q->d2[Q->n - 1]) return;
  p = Q->n < Q->k ? Q->n++ : Q->n - 1;
  while (p > 0 && Q->d2[p - 1] > d2) {
    Q->d2[p] = Q->d2[p - 1];
    Q->idx[p] = Q->idx[p - 1];
    p--;
  }
  Q->d2[p] = d2;
  Q->idx[p] = j;
}

static void search(query *Q, size_t lo, size_t hi) {
  const bsfit__kdtree *t = Q->t;
  size_t mid, q;
  double diff;
  if (hi - lo <= LEAF) {
    for (q = lo; q < hi; q++) {
      size_t j = t->perm[q];
      double dx, dy;
      if (j == Q->self) continue;
      dx = t->xy[2 * j] - Q->x;
      dy = t->xy[2 * j + 1] - Q->y;
      offer(Q, j, dx * dx + dy * dy);
    }
    return;
  }
  mid = lo + (hi - lo) / 2;
  diff = (t->dim[mid] ? Q->y : Q->x) - t->split[mid];
  if (diff < 0) {
    search(Q, lo, mid);
    if (Q->n < Q->k || diff * diff < Q->d2[Q->n - 1]) search(Q, mid, hi);
  } else {
    search(Q, mid, hi);
    if (Q->n < Q->k || diff * diff < Q->d2[Q->n - 1]) search(Q, lo, mid);
  }
}

size_t bsfit__kdtree_knn(const bsfit__kdtree *t, size_t i, size_t k, size_t *idx, double *d) {
  query Q;
  size_t q;
  Q.t = t;
  Q.self = i;
  Q.k = k;
  Q.n = 0;
  Q.x = t->xy[2 * i];
  Q.y = t->xy[2 * i + 1];
  Q.idx = idx;
  Q.d2 = d;
  search(&Q, 0, t->m);
  for (q = 0; q < Q.n; q++) d[q] = sqrt(d[q]);
  return Q.n;
}

/* }====================================================================== */
