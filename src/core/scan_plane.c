/*
** scan_plane.c
** Cutting planes and their frames, the extent of a scan along a direction, and the
** bsfit_sections object the slicers fill (with the growable builder they share).
*/
#include "scan_sections.h"

#include <math.h>
#include <string.h>

bsfit_err bsfit__unit(const double dir[3], double n[3], bsfit_status *st) {
  double len;
  if (dir == NULL) return bsfit__fail(st, BSFIT_EINVAL, "no slicing direction");
  if (!bsfit__all_finite(dir, 3))
    return bsfit__fail(st, BSFIT_ENONFINITE, "the slicing direction is not finite");
  len = sqrt(dir[0] * dir[0] + dir[1] * dir[1] + dir[2] * dir[2]);
  if (!(len > 0) || !isfinite(len))
    return bsfit__fail(st, BSFIT_EINVAL, "the slicing direction is zero");
  n[0] = dir[0] / len;
  n[1] = dir[1] / len;
  n[2] = dir[2] / len;
  return BSFIT_OK;
}

static void cross(const double a[3], const double b[3], double c[3]) {
  c[0] = a[1] * b[2] - a[2] * b[1];
  c[1] = a[2] * b[0] - a[0] * b[2];
  c[2] = a[0] * b[1] - a[1] * b[0];
}

bsfit_err bsfit_plane_frame(const double dir[3], double position, bsfit_plane *p,
                            bsfit_status *st) {
  double n[3], e[3] = {0, 0, 0}, len;
  int k, axis = -1;
  bsfit_err err;
  if (p == NULL) return bsfit__fail(st, BSFIT_EINVAL, "no plane to fill");
  err = bsfit__unit(dir, n, st);
  if (err != BSFIT_OK) return err;
  if (!isfinite(position))
    return bsfit__fail(st, BSFIT_ENONFINITE, "the plane position is not finite");
  for (k = 0; k < 3; k++)
    if (n[k] == 1 || n[k] == -1) axis = k;
  memset(p, 0, sizeof *p);
  p->position = position;
  memcpy(p->normal, n, sizeof n);
  if (axis >= 0) {
    /* x: (y, z); y: (z, x); z: (x, y) -- cyclic, so u x v = +axis; flipped for -axis */
    p->u[(axis + 1) % 3] = 1;
    p->v[(axis + 2) % 3] = n[axis];
  } else {
    int least = 0;
    for (k = 1; k < 3; k++)
      if (fabs(n[k]) < fabs(n[least])) least = k;
    e[least] = 1;
    cross(e, n, p->u);
    len = sqrt(p->u[0] * p->u[0] + p->u[1] * p->u[1] + p->u[2] * p->u[2]);
    for (k = 0; k < 3; k++) p->u[k] /= len;
    cross(n, p->u, p->v);
  }
  for (k = 0; k < 3; k++) p->origin[k] = position * n[k];
  return bsfit__ok(st);
}

bsfit_err bsfit_scan_extent(const double *xyz, size_t n, const double dir[3], double *lo,
                            double *hi, bsfit_status *st) {
  double u[3], a = HUGE_VAL, b = -HUGE_VAL, h;
  size_t i;
  bsfit_err e;
  if (xyz == NULL || n == 0 || lo == NULL || hi == NULL)
    return bsfit__fail(st, BSFIT_EINVAL, "no points to measure");
  e = bsfit__unit(dir, u, st);
  if (e != BSFIT_OK) return e;
  for (i = 0; i < n; i++) {
    h = u[0] * xyz[3 * i] + u[1] * xyz[3 * i + 1] + u[2] * xyz[3 * i + 2];
    if (!isfinite(h)) return bsfit__fail(st, BSFIT_ENONFINITE, "point %zu is not finite", i + 1);
    if (h < a) a = h;
    if (h > b) b = h;
  }
  *lo = a;
  *hi = b;
  return bsfit__ok(st);
}

/* {======================================================================
** The sections object and its builder
** ====================================================================== */

void bsfit_sections_init(bsfit_sections *s) {
  if (s != NULL) memset(s, 0, sizeof *s);
}

void bsfit_sections_free(bsfit_sections *s) {
  if (s == NULL) return;
  bsfit__free(&s->alloc, s->planes, s->nslices * sizeof *s->planes);
  bsfit__free(&s->alloc, s->first_part, (s->nslices + 1) * sizeof(size_t));
  bsfit__free(&s->alloc, s->part_start, (s->nparts + 1) * sizeof(size_t));
  bsfit__free(&s->alloc, s->closed, s->nparts);
  bsfit__free(&s->alloc, s->uv, s->npoints * 2 * sizeof(double));
  memset(s, 0, sizeof *s);
}

static int grow(bsfit__secbuild *b, void **p, size_t *cap, size_t need, size_t unit) {
  size_t nc = *cap ? *cap : 64;
  void *q;
  if (b->failed) return 0;
  if (need <= *cap) return 1;
  while (nc < need) {
    if (nc > ((size_t)-1) / 4 / unit) return (b->failed = 1), 0;
    nc *= 2;
  }
  q = bsfit__realloc(b->a, *p, *cap * unit, nc * unit);
  if (q == NULL) return (b->failed = 1), 0;
  *p = q;
  *cap = nc;
  return 1;
}

bsfit_err bsfit__secb_init(bsfit__secbuild *b, size_t nslices, const bsfit_allocator *a,
                           bsfit_status *st) {
  memset(b, 0, sizeof *b);
  b->a = a;
  b->nslices = nslices;
  b->planes = (bsfit_plane *)bsfit__alloc(a, bsfit__mulsize(nslices, sizeof(bsfit_plane)));
  b->first_part = (size_t *)bsfit__alloc(a, bsfit__mulsize(nslices + 1, sizeof(size_t)));
  if (b->planes == NULL || b->first_part == NULL) {
    bsfit__secb_free(b);
    return bsfit__fail(st, BSFIT_ENOMEM, "out of memory slicing");
  }
  return BSFIT_OK;
}

void bsfit__secb_free(bsfit__secbuild *b) {
  bsfit__free(b->a, b->planes, b->nslices * sizeof(bsfit_plane));
  bsfit__free(b->a, b->first_part, (b->nslices + 1) * sizeof(size_t));
  bsfit__free(b->a, b->part_start, b->cap_parts * sizeof(size_t));
  bsfit__free(b->a, b->closed, b->cap_parts);
  bsfit__free(b->a, b->uv, b->cap_points * 2 * sizeof(double));
  b->planes = NULL;
  b->first_part = b->part_start = NULL;
  b->closed = NULL;
  b->uv = NULL;
}

double *bsfit__secb_part(bsfit__secbuild *b, size_t npoints, int closed) {
  double *p;
  if (!grow(b, (void **)&b->part_start, &b->cap_parts, b->nparts + 2, sizeof(size_t))) return NULL;
  if (!grow(b, (void **)&b->closed, &b->cap_closed, b->nparts + 1, 1)) return NULL;
  if (!grow(b, (void **)&b->uv, &b->cap_points, b->npoints + npoints + 1, 2 * sizeof(double)))
    return NULL;
  b->part_start[b->nparts] = b->npoints;
  b->closed[b->nparts] = (unsigned char)(closed != 0);
  p = b->uv + 2 * b->npoints;
  b->nparts++;
  b->npoints += npoints;
  b->part_start[b->nparts] = b->npoints;
  return p;
}

void bsfit__secb_drop_last(bsfit__secbuild *b) {
  if (b->nparts == 0) return;
  b->nparts--;
  b->npoints = b->part_start[b->nparts];
}

void bsfit__secb_truncate_last(bsfit__secbuild *b, size_t npoints) {
  b->npoints = b->part_start[b->nparts - 1] + npoints;
  b->part_start[b->nparts] = b->npoints;
}

/* A copy of n bytes of p in a block of exactly n bytes (NULL for n == 0 or no memory). */
static void *exact(bsfit__secbuild *b, const void *p, size_t n) {
  void *q = bsfit__alloc(b->a, n);
  if (q != NULL)
    memcpy(q, p, n);
  else if (n > 0)
    b->failed = 1;
  return q;
}

bsfit_err bsfit__secb_finish(bsfit__secbuild *b, bsfit_sections *out, bsfit_status *st) {
  bsfit_sections s;
  size_t zero = 0;
  memset(&s, 0, sizeof s);
  if (b->a != NULL) s.alloc = *b->a;
  s.nslices = b->nslices;
  s.nparts = b->nparts;
  s.npoints = b->npoints;
  /* the blocks are handed over at their exact sizes, which bsfit_sections_free uses */
  s.part_start = exact(b, b->nparts ? b->part_start : &zero, (b->nparts + 1) * sizeof(size_t));
  s.closed = exact(b, b->closed, b->nparts);
  s.uv = exact(b, b->uv, b->npoints * 2 * sizeof(double));
  s.planes = b->planes;
  s.first_part = b->first_part;
  b->planes = NULL;
  b->first_part = NULL;
  if (b->failed) {
    bsfit_sections_free(&s);
    bsfit__secb_free(b);
    return bsfit__fail(st, BSFIT_ENOMEM, "out of memory slicing");
  }
  bsfit__secb_free(b);
  bsfit_sections_free(out);
  *out = s;
  return bsfit__ok(st);
}

/* }====================================================================== */
