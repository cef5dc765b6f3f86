/*
** scan_order_graph.c
** Ordering points that are not star-shaped: a curve reconstruction by spanning tree.
** The minimum spanning forest of the k-nearest-neighbour graph, with edges longer than
** gap times the local spacing left out, splits the section into parts (two legs, an
** outlier cluster). Points sampled along a curve make a tree that is nearly a path:
** its longest path is the backbone, and the few side branches (points beside the
** curve, the thickness of a slab) are inserted next to their tree neighbour where they
** lengthen the tour least, so the tour never zigzags across the section. 2-opt moves
** over the neighbour lists remove the crossings left. A part closes when the ends of
** its tour are within gap times the local spacing. Cost O(m k log(m k)).
*/
#include "scan_order.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

typedef struct edge {
  double len;
  size_t i, j;
} edge;

static int cmp_edge(const void *a, const void *b) {
  const edge *x = a, *y = b;
  if (x->len != y->len) return x->len < y->len ? -1 : 1;
  if (x->i != y->i) return x->i < y->i ? -1 : 1;
  return (x->j > y->j) - (x->j < y->j);
}

typedef struct forest {
  size_t *parent;    /* union-find */
  size_t *tstart;    /* m + 1: tree neighbours of v are tadj[tstart[v] .. tstart[v+1]-1] */
  size_t *tadj;      /* 2 (m-1) */
  size_t *comp;      /* m: component id (its root) */
  size_t *nxt, *prv; /* the tour being built, as a linked list */
  size_t *queue, *pos;
  double *dist;
} forest;

static size_t find(size_t *p, size_t x) {
  while (p[x] != x) {
    p[x] = p[p[x]];
    x = p[x];
  }
  return x;
}

/* {======================================================================
** The spanning forest
** ====================================================================== */

static bsfit_err spanning_forest(const bsfit__ordwork *w, forest *f, bsfit_status *st) {
  size_t i, q, ne = 0, nt = 0, m = w->m;
  edge *E = bsfit__alloc(w->a, bsfit__mulsize(m * w->k, sizeof(edge)));
  size_t *ti = bsfit__alloc(w->a, 2 * m * sizeof(size_t));
  if (E == NULL || ti == NULL) {
    bsfit__free(w->a, E, m * w->k * sizeof(edge));
    bsfit__free(w->a, ti, 2 * m * sizeof(size_t));
    return bsfit__fail(st, BSFIT_ENOMEM, "out of memory (ordering)");
  }
  for (i = 0; i < m; i++)
    for (q = 0; q < w->k; q++) {
      size_t j = w->nbr[i * w->k + q];
      if (j == BSFIT__NONE) break;
      if (w->nd[i * w->k + q] > w->gap * bsfit__pair_spacing(w, i, j)) continue; /* a gap */
      E[ne].len = w->nd[i * w->k + q];
      E[ne].i = i < j ? i : j;
      E[ne].j = i < j ? j : i;
      ne++;
    }
  qsort(E, ne, sizeof *E, cmp_edge);
  for (i = 0; i < m; i++) f->parent[i] = i;
  for (q = 0; q < ne && nt + 1 < m; q++) {
    size_t a = find(f->parent, E[q].i), b = find(f->parent, E[q].j);
    if (a == b) continue;
    f->parent[a] = b;
    ti[2 * nt] = E[q].i;
    ti[2 * nt + 1] = E[q].j;
    nt++;
  }
  memset(f->tstart, 0, (m + 1) * sizeof(size_t));
  for (q = 0; q < 2 * nt; q++) f->tstart[ti[q] + 1]++;
  for (i = 0; i < m; i++) f->tstart[i + 1] += f->tstart[i];
  for (q = 0; q < nt; q++) {
    f->tadj[f->tstart[ti[2 * q]]++] = ti[2 * q + 1];
    f->tadj[f->tstart[ti[2 * q + 1]]++] = ti[2 * q];
  }
  for (i = m; i > 0; i--) f->tstart[i] = f->tstart[i - 1];
  f->tstart[0] = 0;
  for (i = 0; i < m; i++) f->comp[i] = find(f->parent, i);
  bsfit__free(w->a, E, m * w->k * sizeof(edge));
  bsfit__free(w->a, ti, 2 * m * sizeof(size_t));
  return BSFIT_OK;
}

/* }====================================================================== */

/* {======================================================================
** One tree: backbone, insertions
** ====================================================================== */

/* Distances along the tree from s (f->dist, parents in f->prv); returns the farthest. */
static size_t farthest(const bsfit__ordwork *w, forest *f, size_t s) {
  size_t head = 0, tail = 0, best = s, q;
  f->dist[s] = 0;
  f->prv[s] = BSFIT__NONE;
  f->queue[tail++] = s;
  while (head < tail) {
    size_t v = f->queue[head++];
    if (f->dist[v] > f->dist[best]) best = v;
    for (q = f->tstart[v]; q < f->tstart[v + 1]; q++) {
      size_t x = f->tadj[q];
      if (x == f->prv[v]) continue;
      f->prv[x] = v;
      f->dist[x] = f->dist[v] + bsfit__dist(w->xy, v, x);
      f->queue[tail++] = x;
    }
  }
  return best;
}

/* Puts x into the tour beside its tree neighbour p, on the cheaper side. */
static void insert(const bsfit__ordwork *w, forest *f, size_t p, size_t x) {
  size_t a = f->prv[p], b = f->nxt[p];
  double dpx = bsfit__dist(w->xy, p, x);
  double before =
      a == BSFIT__NONE ? dpx : bsfit__dist(w->xy, a, x) + dpx - bsfit__dist(w->xy, a, p);
  double after = b == BSFIT__NONE ? dpx : bsfit__dist(w->xy, x, b) + dpx - bsfit__dist(w->xy, p, b);
  if (before < after) {
    f->prv[x] = a;
    f->nxt[x] = p;
    if (a != BSFIT__NONE) f->nxt[a] = x;
    f->prv[p] = x;
  } else {
    f->nxt[x] = b;
    f->prv[x] = p;
    if (b != BSFIT__NONE) f->prv[b] = x;
    f->nxt[p] = x;
  }
}

/* Whether points a and b, the ends of a backbone, are near enough to close it. */
static int closes(const bsfit__ordwork *w, size_t a, size_t b, size_t n) {
  return n >= 3 && a != b && bsfit__dist(w->xy, a, b) <= w->gap * bsfit__pair_spacing(w, a, b);
}

/* The tour of the tree holding s, written to out; returns its length. Whether it closes
** is decided on the backbone's ends, before the side branches are inserted (they could
** otherwise be placed beyond an end and move it); a closed backbone is linked into a
** ring, so insertions may fall across its seam. */
static size_t tour(const bsfit__ordwork *w, forest *f, size_t s, size_t *out, int *closed) {
  size_t a = farthest(w, f, s), b = farthest(w, f, a), v, head = 0, tail = 0, n = 0, q;
  for (v = b; v != BSFIT__NONE; v = f->prv[v]) f->queue[tail++] = v; /* b .. a */
  for (q = 0; q < tail; q++) f->pos[f->queue[q]] = 1;                /* in the tour */
  for (q = 0; q < tail; q++) {
    v = f->queue[q];
    f->prv[v] = q > 0 ? f->queue[q - 1] : BSFIT__NONE;
    f->nxt[v] = q + 1 < tail ? f->queue[q + 1] : BSFIT__NONE;
  }
  *closed = closes(w, a, b, tail);
  if (*closed) {
    f->prv[b] = a;
    f->nxt[a] = b;
  }
  while (head < tail) { /* breadth first from the backbone: a point's parent is placed */
    size_t p = f->queue[head++];
    for (q = f->tstart[p]; q < f->tstart[p + 1]; q++) {
      size_t x = f->tadj[q];
      if (f->pos[x]) continue;
      f->pos[x] = 1;
      insert(w, f, p, x);
      f->queue[tail++] = x;
    }
  }
  if (*closed) {
    v = b;
    do {
      out[n++] = v;
      v = f->nxt[v];
    } while (v != b);
    return n;
  }
  for (v = b; f->prv[v] != BSFIT__NONE; v = f->prv[v]) {
  }
  for (; v != BSFIT__NONE; v = f->nxt[v]) out[n++] = v;
  return n;
}

/* }====================================================================== */

static bsfit_err forest_alloc(const bsfit__ordwork *w, forest *f, int on) {
  size_t m = w->m;
  if (on) {
    f->parent = bsfit__alloc(w->a, m * sizeof(size_t));
    f->tstart = bsfit__alloc(w->a, (m + 1) * sizeof(size_t));
    f->tadj = bsfit__alloc(w->a, 2 * m * sizeof(size_t));
    f->comp = bsfit__alloc(w->a, m * sizeof(size_t));
    f->nxt = bsfit__alloc(w->a, m * sizeof(size_t));
    f->prv = bsfit__alloc(w->a, m * sizeof(size_t));
    f->queue = bsfit__alloc(w->a, m * sizeof(size_t));
    f->pos = bsfit__alloc(w->a, m * sizeof(size_t));
    f->dist = bsfit__alloc(w->a, m * sizeof(double));
    return f->parent && f->tstart && f->tadj && f->comp && f->nxt && f->prv && f->queue && f->pos &&
                   f->dist
               ? BSFIT_OK
               : BSFIT_ENOMEM;
  }
  bsfit__free(w->a, f->parent, m * sizeof(size_t));
  bsfit__free(w->a, f->tstart, (m + 1) * sizeof(size_t));
  bsfit__free(w->a, f->tadj, 2 * m * sizeof(size_t));
  bsfit__free(w->a, f->comp, m * sizeof(size_t));
  bsfit__free(w->a, f->nxt, m * sizeof(size_t));
  bsfit__free(w->a, f->prv, m * sizeof(size_t));
  bsfit__free(w->a, f->queue, m * sizeof(size_t));
  bsfit__free(w->a, f->pos, m * sizeof(size_t));
  bsfit__free(w->a, f->dist, m * sizeof(double));
  return BSFIT_OK;
}

/* Every part: its tour, closed or not, improved by 2-opt. */
static bsfit_err parts(const bsfit__ordwork *w, forest *f, bsfit_order_result *r,
                       bsfit_status *st) {
  size_t i, used = 0, n, q;
  memset(f->pos, 0, w->m * sizeof(size_t));
  r->nloops = 0;
  r->dropped = 0;
  r->start[0] = 0;
  for (i = 0; i < w->m; i++) {
    size_t *t = r->index + used;
    int closed;
    if (f->pos[i]) continue;
    if (bsfit__interrupted(w->a)) return bsfit__fail(st, BSFIT_EINTR, "ordering interrupted");
    n = tour(w, f, i, t, &closed);
    if (n < w->min_points) {
      r->dropped += n;
      continue;
    }
    for (q = 0; q < n; q++) f->nxt[t[q]] = q; /* the list is done with: positions for 2-opt */
    bsfit__two_opt(w, t, n, closed, f->nxt, f->comp, f->comp[i]);
    r->closed[r->nloops] = (unsigned char)closed;
    used += n;
    r->start[++r->nloops] = used;
  }
  return BSFIT_OK;
}

bsfit_err bsfit__order_graph(const bsfit__ordwork *w, bsfit_order_result *r, bsfit_status *st) {
  forest f;
  bsfit_err e;
  memset(&f, 0, sizeof f);
  if (forest_alloc(w, &f, 1) != BSFIT_OK) {
    forest_alloc(w, &f, 0);
    return bsfit__fail(st, BSFIT_ENOMEM, "out of memory (ordering)");
  }
  e = spanning_forest(w, &f, st);
  if (e == BSFIT_OK) e = parts(w, &f, r, st);
  forest_alloc(w, &f, 0);
  return e;
}
