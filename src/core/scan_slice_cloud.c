/*
** scan_slice_cloud.c
** Slabs of a point cloud: the points within thickness/2 of each plane, projected onto
** it. Each point finds its slabs by binary search in the sorted positions, so the cost
** is O(n log npos) plus the output, whatever the number of planes.
*/
#include "scan_sections.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

typedef struct posidx {
  double pos;
  size_t idx;
} posidx;

static int cmp_pos(const void *a, const void *b) {
  const posidx *x = a, *y = b;
  return x->pos < y->pos ? -1 : x->pos > y->pos ? 1 : (x->idx > y->idx) - (x->idx < y->idx);
}

/* First k with v[k].pos >= x. */
static size_t first_at_least(const posidx *v, size_t n, double x) {
  size_t lo = 0, hi = n;
  while (lo < hi) {
    size_t mid = lo + (hi - lo) / 2;
    if (v[mid].pos < x)
      lo = mid + 1;
    else
      hi = mid;
  }
  return lo;
}

/* Visits the slabs of every point: count (fill == NULL) or write the projections. */
static bsfit_err pass(const double *xyz, size_t n, const double nrm[3], const posidx *ord,
                      size_t npos, double half, size_t *cursor, bsfit__secbuild *b,
                      const bsfit_allocator *a, bsfit_status *st) {
  size_t i, r;
  for (i = 0; i < n; i++) {
    const double *x = xyz + 3 * i;
    double h = nrm[0] * x[0] + nrm[1] * x[1] + nrm[2] * x[2];
    if ((i & 0xffff) == 0 && bsfit__interrupted(a))
      return bsfit__fail(st, BSFIT_EINTR, "slicing interrupted");
    if (!isfinite(h)) return bsfit__fail(st, BSFIT_ENONFINITE, "point %zu is not finite", i + 1);
    for (r = first_at_least(ord, npos, h - half); r < npos && ord[r].pos <= h + half; r++) {
      size_t s = ord[r].idx;
      if (b == NULL) {
        cursor[s + 1]++;
      } else {
        const bsfit_plane *pl = &b->planes[s];
        double d[3], *uv = b->uv + 2 * cursor[s]++;
        d[0] = x[0] - pl->origin[0];
        d[1] = x[1] - pl->origin[1];
        d[2] = x[2] - pl->origin[2];
        uv[0] = d[0] * pl->u[0] + d[1] * pl->u[1] + d[2] * pl->u[2];
        uv[1] = d[0] * pl->v[0] + d[1] * pl->v[1] + d[2] * pl->v[2];
      }
    }
  }
  return BSFIT_OK;
}

/* One part per slice, sized from the counts, then the filling pass. */
static bsfit_err fill(const double *xyz, size_t n, const double nrm[3], const posidx *ord,
                      size_t npos, double half, size_t *cur, bsfit__secbuild *b,
                      const bsfit_allocator *a, bsfit_status *st) {
  size_t s;
  bsfit_err e = pass(xyz, n, nrm, ord, npos, half, cur, NULL, a, st);
  if (e != BSFIT_OK) return e;
  for (s = 0; s < npos; s++) {
    b->first_part[s] = s;
    if (bsfit__secb_part(b, cur[s + 1], 0) == NULL && b->failed)
      return bsfit__fail(st, BSFIT_ENOMEM, "out of memory slicing");
    cur[s] = b->part_start[s];
  }
  b->first_part[npos] = npos;
  return pass(xyz, n, nrm, ord, npos, half, cur, b, a, st);
}

bsfit_err bsfit_cloud_slice(const double *xyz, size_t n, const double dir[3], const double *pos,
                            size_t npos, double thickness, bsfit_sections *out,
                            const bsfit_allocator *a, bsfit_status *st) {
  double nrm[3];
  posidx *ord;
  size_t *cur, s;
  bsfit__secbuild b;
  bsfit_err e;
  if (xyz == NULL || n == 0 || out == NULL)
    return bsfit__fail(st, BSFIT_EINVAL, "no points to slice");
  if (pos == NULL || npos == 0) return bsfit__fail(st, BSFIT_EINVAL, "no planes to slice with");
  if (!(thickness > 0) || !isfinite(thickness))
    return bsfit__fail(st, BSFIT_EINVAL, "the slab thickness must be > 0, got %g", thickness);
  e = bsfit__unit(dir, nrm, st);
  if (e != BSFIT_OK) return e;
  if (!bsfit__all_finite(pos, npos))
    return bsfit__fail(st, BSFIT_ENONFINITE, "a plane position is not finite");
  ord = bsfit__alloc(a, bsfit__mulsize(npos, sizeof *ord));
  cur = bsfit__alloc(a, bsfit__mulsize(npos + 1, sizeof *cur));
  e = bsfit__secb_init(&b, npos, a, st);
  if (e == BSFIT_OK && (ord == NULL || cur == NULL)) {
    bsfit__secb_free(&b);
    e = bsfit__fail(st, BSFIT_ENOMEM, "out of memory slicing");
  }
  if (e == BSFIT_OK) {
    for (s = 0; s < npos; s++) {
      ord[s].pos = pos[s];
      ord[s].idx = s;
      bsfit_plane_frame(nrm, pos[s], &b.planes[s], NULL);
    }
    qsort(ord, npos, sizeof *ord, cmp_pos);
    memset(cur, 0, (npos + 1) * sizeof *cur);
    e = fill(xyz, n, nrm, ord, npos, thickness / 2, cur, &b, a, st);
    if (e == BSFIT_OK)
      e = bsfit__secb_finish(&b, out, st);
    else
      bsfit__secb_free(&b);
  }
  bsfit__free(a, ord, npos * sizeof *ord);
  bsfit__free(a, cur, (npos + 1) * sizeof *cur);
  return e;
}
