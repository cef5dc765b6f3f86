/*
** scan_grid.c
** A uniform grid over 2D points (about two points per cell) and k-nearest-neighbour
** queries on it: rings of cells are searched outwards until the k-th best distance is
** within the ring's reach, so a query costs O(k) on evenly spread points.
*/
#include "scan_internal.h"

#include <math.h>
#include <string.h>

/* The range [*lo, *hi] of coordinate c of the points between the 1% and 99% quantiles,
** widened by a tenth: a few far outliers must not make the cells so large that the whole
** section falls into a handful of them (each query would then scan O(m) points). */
static int robust_range(const double *xy, size_t m, int c, double *tmp, double *lo, double *hi) {
  size_t i, q = m / 100;
  double w;
  for (i = 0; i < m; i++) tmp[i] = xy[2 * i + (size_t)c];
  *lo = bsfit__select(tmp, m, q);
  *hi = bsfit__select(tmp, m, m - 1 - q);
  w = *hi - *lo;
  *lo -= w / 10;
  *hi += w / 10;
  return 1;
}

/* The cell of point p, clamped to the grid; *outside is set when p lies beyond it. */
static size_t cell_of(const bsfit__grid *g, const double *p, long *cx, long *cy, int *outside) {
  double fx = floor((p[0] - g->x0) / g->h), fy = floor((p[1] - g->y0) / g->h);
  *outside = !(fx >= 0 && fx < (double)g->nx && fy >= 0 && fy < (double)g->ny);
  *cx = fx < 0 ? 0 : fx >= (double)g->nx ? (long)g->nx - 1 : (long)fx;
  *cy = fy < 0 ? 0 : fy >= (double)g->ny ? (long)g->ny - 1 : (long)fy;
  return (size_t)*cy * g->nx + (size_t)*cx;
}

bsfit_err bsfit__grid_build(bsfit__grid *g, const double *xy, size_t m, const bsfit_allocator *a,
                            bsfit_status *st) {
  double x1, y1, w, h, *tmp;
  size_t i, c, ncell;
  long cx, cy;
  int out;
  memset(g, 0, sizeof *g);
  g->xy = xy;
  g->m = m;
  g->a = a;
  tmp = bsfit__alloc(a, m * sizeof(double));
  if (tmp == NULL) return bsfit__fail(st, BSFIT_ENOMEM, "out of memory (neighbour grid)");
  robust_range(xy, m, 0, tmp, &g->x0, &x1);
  robust_range(xy, m, 1, tmp, &g->y0, &y1);
  bsfit__free(a, tmp, m * sizeof(double));
  w = x1 - g->x0;
  h = y1 - g->y0;
  g->h = sqrt(w * h * 2 / (double)m);
  if (!(g->h > (w > h ? w : h) / (double)(2 * m + 1))) g->h = (w > h ? w : h) / (double)(2 * m + 1);
  if (!(g->h > 0) || !isfinite(g->h)) g->h = 1;
  g->nx = (size_t)(w / g->h) + 1;
  g->ny = (size_t)(h / g->h) + 1;
  ncell = g->nx * g->ny;
  g->cell_start = bsfit__alloc(a, (ncell + 1) * sizeof(size_t));
  g->items = bsfit__alloc(a, m * sizeof(size_t));
  if (g->cell_start == NULL || g->items == NULL) {
    bsfit__grid_free(g);
    return bsfit__fail(st, BSFIT_ENOMEM, "out of memory (neighbour grid)");
  }
  memset(g->cell_start, 0, (ncell + 1) * sizeof(size_t));
  for (i = 0; i < m; i++) g->cell_start[cell_of(g, xy + 2 * i, &cx, &cy, &out) + 1]++;
  for (c = 0; c < ncell; c++) g->cell_start[c + 1] += g->cell_start[c];
  for (i = 0; i < m; i++) g->items[g->cell_start[cell_of(g, xy + 2 * i, &cx, &cy, &out)]++] = i;
  for (c = ncell; c > 0; c--) g->cell_start[c] = g->cell_start[c - 1];
  g->cell_start[0] = 0;
  return BSFIT_OK;
}

void bsfit__grid_free(bsfit__grid *g) {
  bsfit__free(g->a, g->cell_start, (g->nx * g->ny + 1) * sizeof(size_t));
  bsfit__free(g->a, g->items, g->m * sizeof(size_t));
  g->cell_start = NULL;
  g->items = NULL;
}

/* Offers point j at squared distance d2 to the sorted best list of n (cap k). */
static size_t offer(size_t *idx, double *d, size_t n, size_t k, size_t j, double d2) {
  size_t p;
  if (n == k && d2 >= d[n - 1]) return n;
  p = n < k ? n++ : n - 1;
  while (p > 0 && d[p - 1] > d2) {
    d[p] = d[p - 1];
    idx[p] = idx[p - 1];
    p--;
  }
  d[p] = d2;
  idx[p] = j;
  return n;
}

/* Offers the points of cell (cx, cy). */
static size_t scan_cell(const bsfit__grid *g, long cx, long cy, size_t i, size_t k, size_t *idx,
                        double *d, size_t n) {
  size_t c, q;
  const double *p = g->xy + 2 * i;
  if (cx < 0 || cy < 0 || (size_t)cx >= g->nx || (size_t)cy >= g->ny) return n;
  c = (size_t)cy * g->nx + (size_t)cx;
  for (q = g->cell_start[c]; q < g->cell_start[c + 1]; q++) {
    size_t j = g->items[q];
    double dx, dy;
    if (j == i) continue;
    dx = g->xy[2 * j] - p[0];
    dy = g->xy[2 * j + 1] - p[1];
    n = offer(idx, d, n, k, j, dx * dx + dy * dy);
  }
  return n;
}

size_t bsfit__grid_knn(const bsfit__grid *g, size_t i, size_t k, size_t *idx, double *d) {
  long cx, cy, r, t, rmax = (long)(g->nx > g->ny ? g->nx : g->ny);
  size_t n = 0, q;
  int outside;
  cell_of(g, g->xy + 2 * i, &cx, &cy, &outside);
  for (r = 0; r <= rmax; r++) {
    if (r == 0) {
      n = scan_cell(g, cx, cy, i, k, idx, d, n);
    } else {
      for (t = -r; t <= r; t++) {
        n = scan_cell(g, cx + t, cy - r, i, k, idx, d, n);
        n = scan_cell(g, cx + t, cy + r, i, k, idx, d, n);
      }
      for (t = -r + 1; t <= r - 1; t++) {
        n = scan_cell(g, cx - r, cy + t, i, k, idx, d, n);
        n = scan_cell(g, cx + r, cy + t, i, k, idx, d, n);
      }
    }
    /* cells beyond ring r hold points at least r*h away -- from a point inside its own
    ** cell; border cells also hold the clamped outliers, farther still. A query from
    ** outside the grid (an outlier, rare) searches every ring. */
    if (!outside && n == k && d[k - 1] <= (double)r * g->h * (double)r * g->h) break;
  }
  for (q = 0; q < n; q++) d[q] = sqrt(d[q]);
  return n;
}
