/*
** io_obj.c
** A triangle mesh sampled from a surface, as Wavefront OBJ ("v x y z" and "f a b c"
** lines): a preview any mesh viewer opens. A surface periodic in u is sampled over one
** period without repeating its seam column, and the last column's triangles use the
** first column's vertices, so the mesh closes around u without a gap or a doubled seam.
*/
#include "io_internal.h"

#include <stdio.h>

/* Vertex (a, b) of the grid, 1-based as OBJ counts; a wraps when the surface is periodic. */
static size_t vertex(size_t a, size_t b, size_t ku, size_t nv) { return (a % ku) * nv + b + 1; }

bsfit_err bsfit_surface_to_obj(const bsfit_surface *s, size_t nu, size_t nv, char **out,
                               size_t *len, const bsfit_allocator *a, bsfit_status *st) {
  bsfit__buf b;
  double *grid;
  size_t ku, kg, i, j, d, nbytes, cols;
  bsfit_err e;
  if (out == NULL) return bsfit__fail(st, BSFIT_EINVAL, "no output for the OBJ text");
  if ((e = bsfit_surface_validate(s, st)) != BSFIT_OK) return e;
  if (s->dim < 2 || s->dim > 3)
    return bsfit__fail(st, BSFIT_EDIM, "an OBJ mesh needs a 2D or 3D surface, got dim %d", s->dim);
  if (nu < 2 || nv < 2 || nu > 100000 || nv > 100000)
    return bsfit__fail(st, BSFIT_EINVAL, "mesh of %zu x %zu samples: each must be in 2..100000",
                       nu, nv);
  /* periodic: nu distinct columns, the grid's last (= first) one dropped */
  ku = nu;
  kg = s->periodic_u ? nu + 1 : nu;
  d = (size_t)s->dim;
  nbytes = kg * nv * d * sizeof(double);
  grid = bsfit__alloc(a, nbytes);
  if (grid == NULL)
    return bsfit__fail(st, BSFIT_ENOMEM, "out of memory for %zu x %zu samples", nu, nv);
  e = bsfit_surface_sample_grid(s, kg, nv, grid, st);
  if (e != BSFIT_OK) {
    bsfit__free(a, grid, nbytes);
    return e;
  }
  bsfit__buf_init(&b, a);
  bsfit__buf_printf(&b, "# bsfit " BSFIT_VERSION ": %zu x %zu samples of a %s surface\n", nu, nv,
                    s->periodic_u ? "closed (periodic in u)" : "B-spline");
  for (i = 0; i < ku * nv; i++) {
    const double *P = grid + i * d;
    bsfit__buf_printf(&b, "v %.17g %.17g %.17g\n", P[0], P[1], d == 3 ? P[2] : 0.0);
  }
  bsfit__free(a, grid, nbytes);
  cols = s->periodic_u ? nu : nu - 1;
  for (i = 0; i < cols; i++)
    for (j = 0; j + 1 < nv; j++) {
      size_t p00 = vertex(i, j, ku, nv), p01 = vertex(i, j + 1, ku, nv);
      size_t p10 = vertex(i + 1, j, ku, nv), p11 = vertex(i + 1, j + 1, ku, nv);
      bsfit__buf_printf(&b, "f %zu %zu %zu\nf %zu %zu %zu\n", p00, p10, p11, p00, p11, p01);
    }
  return bsfit__buf_take(&b, out, len, st);
}

bsfit_err bsfit_surface_write_obj(const bsfit_surface *s, size_t nu, size_t nv, const char *path,
                                  bsfit_status *st) {
  bsfit__buf b;
  bsfit_err e;
  if (path == NULL) return bsfit__fail(st, BSFIT_EINVAL, "no file name to write to");
  bsfit__buf_init(&b, NULL);
  e = bsfit_surface_to_obj(s, nu, nv, &b.data, &b.len, NULL, st);
  if (e != BSFIT_OK) return e;
  b.cap = b.len + 1;
  return bsfit__buf_write(&b, path, st);
}
