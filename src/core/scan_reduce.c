/*
** scan_reduce.c
** Centre-of-mass reduction (Fonseca Jr & Carvalho): the points of each cell of a square
** grid are replaced by their mean, weighted by the cell's count (or by the sum of the
** points' weights). Cells are found by hashing their integer coordinates, so the cost
** is O(m) whatever the extent. The target mode bisects the logarithm of the cell size.
*/
#include "scan_internal.h"

#include <math.h>
#include <string.h>

typedef struct cellmap {
  int64_t *key; /* 2 per slot */
  size_t *out;  /* output index + 1 per slot, 0 = empty */
  size_t mask;
} cellmap;

static bsfit_err check_input(const double *xy, size_t m, const double *w, bsfit_status *st) {
  size_t i;
  if (xy == NULL || m == 0) return bsfit__fail(st, BSFIT_EINVAL, "no points to reduce");
  for (i = 0; i < 2 * m; i++)
    if (!isfinite(xy[i]))
      return bsfit__fail(st, BSFIT_ENONFINITE, "point %zu is not finite", i / 2 + 1);
  for (i = 0; w != NULL && i < m; i++)
    if (!(w[i] > 0) || !isfinite(w[i]))
      return bsfit__fail(st, BSFIT_EWEIGHT, "weight %zu is %g (must be positive)", i + 1, w[i]);
  return BSFIT_OK;
}

/* The reduction with a given cell (input already checked; map sized for m). */
static bsfit_err reduce(const double *xy, size_t m, const double *w, double cell, cellmap *cm,
                        double *oxy, double *ow, size_t *om, const bsfit_allocator *a,
                        bsfit_status *st) {
  size_t i, n = 0;
  memset(cm->out, 0, (cm->mask + 1) * sizeof(size_t));
  for (i = 0; i < m; i++) {
    double fx = floor(xy[2 * i] / cell), fy = floor(xy[2 * i + 1] / cell), wi = w ? w[i] : 1;
    int64_t kx, ky;
    size_t h;
    if ((i & 0xffff) == 0 && bsfit__interrupted(a))
      return bsfit__fail(st, BSFIT_EINTR, "reduction interrupted");
    if (!(fabs(fx) < 4e18 && fabs(fy) < 4e18))
      return bsfit__fail(st, BSFIT_EINVAL, "cell size %g too small for coordinates near %g", cell,
                         fabs(xy[2 * i]) > fabs(xy[2 * i + 1]) ? xy[2 * i] : xy[2 * i + 1]);
    kx = (int64_t)fx;
    ky = (int64_t)fy;
    h = (size_t)(((uint64_t)kx * 0x9E3779B97F4A7C15ull) ^ ((uint64_t)ky * 0xC2B2AE3D27D4EB4Full));
    h = (h ^ (h >> 31)) & cm->mask;
    while (cm->out[h] != 0 && (cm->key[2 * h] != kx || cm->key[2 * h + 1] != ky))
      h = (h + 1) & cm->mask;
    if (cm->out[h] == 0) {
      cm->key[2 * h] = kx;
      cm->key[2 * h + 1] = ky;
      cm->out[h] = ++n;
      oxy[2 * (n - 1)] = oxy[2 * (n - 1) + 1] = ow[n - 1] = 0;
    }
    oxy[2 * (cm->out[h] - 1)] += wi * xy[2 * i];
    oxy[2 * (cm->out[h] - 1) + 1] += wi * xy[2 * i + 1];
    ow[cm->out[h] - 1] += wi;
  }
  for (i = 0; i < n; i++) {
    oxy[2 * i] /= ow[i];
    oxy[2 * i + 1] /= ow[i];
  }
  *om = n;
  return BSFIT_OK;
}

static bsfit_err map_new(cellmap *cm, size_t m, const bsfit_allocator *a, bsfit_status *st) {
  size_t n = 64;
  while (n < 2 * m) n *= 2;
  cm->mask = n - 1;
  cm->key = bsfit__alloc(a, bsfit__mulsize(2 * n, sizeof(int64_t)));
  cm->out = bsfit__alloc(a, bsfit__mulsize(n, sizeof(size_t)));
  if (cm->key == NULL || cm->out == NULL) {
    bsfit__free(a, cm->key, 2 * n * sizeof(int64_t));
    bsfit__free(a, cm->out, n * sizeof(size_t));
    return bsfit__fail(st, BSFIT_ENOMEM, "out of memory (reduction)");
  }
  return BSFIT_OK;
}

static void map_free(cellmap *cm, const bsfit_allocator *a) {
  bsfit__free(a, cm->key, 2 * (cm->mask + 1) * sizeof(int64_t));
  bsfit__free(a, cm->out, (cm->mask + 1) * sizeof(size_t));
}

bsfit_err bsfit_reduce_grid(const double *xy, size_t m, const double *w, double cell,
                            double *out_xy, double *out_w, size_t *out_m, const bsfit_allocator *a,
                            bsfit_status *st) {
  cellmap cm;
  bsfit_err e = check_input(xy, m, w, st);
  if (e != BSFIT_OK) return e;
  if (out_xy == NULL || out_w == NULL || out_m == NULL)
    return bsfit__fail(st, BSFIT_EINVAL, "no room for the reduced points");
  if (!(cell > 0) || !isfinite(cell))
    return bsfit__fail(st, BSFIT_EINVAL, "the cell size must be > 0, got %g", cell);
  e = map_new(&cm, m, a, st);
  if (e != BSFIT_OK) return e;
  e = reduce(xy, m, w, cell, &cm, out_xy, out_w, out_m, a, st);
  map_free(&cm, a);
  return e == BSFIT_OK ? bsfit__ok(st) : e;
}

/* The bisection: hi gives too few points, lo too many. */
static bsfit_err bisect(const double *xy, size_t m, const double *w, size_t target, double diag,
                        cellmap *cm, double *cell_used, double *oxy, double *ow, size_t *om,
                        const bsfit_allocator *a, bsfit_status *st) {
  double lo = diag * 1e-9, hi = diag * 2, best = hi, c;
  size_t n, best_err = (size_t)-1, it, tol = target / 20;
  bsfit_err e;
  for (it = 0; it < 60; it++) {
    c = sqrt(lo * hi);
    e = reduce(xy, m, w, c, cm, oxy, ow, &n, a, st);
    if (e != BSFIT_OK) return e;
    if ((n > target ? n - target : target - n) < best_err) {
      best_err = n > target ? n - target : target - n;
      best = c;
    }
    if (best_err <= tol) break;
    if (n > target)
      lo = c;
    else
      hi = c;
  }
  *cell_used = best;
  return reduce(xy, m, w, best, cm, oxy, ow, om, a, st);
}

bsfit_err bsfit_reduce_target(const double *xy, size_t m, const double *w, size_t target,
                              double *cell_used, double *out_xy, double *out_w, size_t *out_m,
                              const bsfit_allocator *a, bsfit_status *st) {
  cellmap cm;
  double x0 = HUGE_VAL, y0 = HUGE_VAL, x1 = -HUGE_VAL, y1 = -HUGE_VAL, diag;
  size_t i;
  bsfit_err e = check_input(xy, m, w, st);
  if (e != BSFIT_OK) return e;
  if (target == 0) return bsfit__fail(st, BSFIT_EINVAL, "the target count must be >= 1");
  if (out_xy == NULL || out_w == NULL || out_m == NULL || cell_used == NULL)
    return bsfit__fail(st, BSFIT_EINVAL, "no room for the reduced points");
  for (i = 0; i < m; i++) {
    x0 = fmin(x0, xy[2 * i]), x1 = fmax(x1, xy[2 * i]);
    y0 = fmin(y0, xy[2 * i + 1]), y1 = fmax(y1, xy[2 * i + 1]);
  }
  diag = hypot(x1 - x0, y1 - y0);
  if (!(diag > 0)) return bsfit__fail(st, BSFIT_EDEGENERATE, "all %zu points coincide", m);
  if (target >= m) {
    memcpy(out_xy, xy, 2 * m * sizeof(double));
    for (i = 0; i < m; i++) out_w[i] = w ? w[i] : 1;
    *out_m = m;
    *cell_used = 0;
    return bsfit__ok(st);
  }
  e = map_new(&cm, m, a, st);
  if (e != BSFIT_OK) return e;
  e = bisect(xy, m, w, target, diag, &cm, cell_used, out_xy, out_w, out_m, a, st);
  map_free(&cm, a);
  return e == BSFIT_OK ? bsfit__ok(st) : e;
}
