/*
** filter_fspline.c
** Raw splines of the filters (filter_internal.h): a degree, knots and control points of
** any dimension (a surface's rows along u are one "point" each), allocated with the
** caller's allocator, borrowed as views, and handed over to a validated curve.
*/
#include "filter_internal.h"

#include <string.h>

void bsfit__fspline_free(const bsfit_allocator *a, bsfit__fspline *f) {
  bsfit__free(a, f->U, (f->n + (size_t)f->p + 1) * sizeof(double));
  bsfit__free(a, f->P, f->n * f->d * sizeof(double));
  memset(f, 0, sizeof *f);
}

bsfit_err bsfit__fspline_alloc(const bsfit_allocator *a, bsfit__fspline *f, int p, size_t n,
                               size_t d, bsfit_status *st) {
  size_t np = bsfit__mulsize(n, d), bytes = bsfit__mulsize(np, sizeof(double));
  memset(f, 0, sizeof *f);
  if (bytes == 0)
    return bsfit__fail(st, BSFIT_EINVAL, "filtered spline of %zu x %zu too large", n, d);
  f->U = bsfit__alloc(a, (n + (size_t)p + 1) * sizeof(double));
  f->P = bsfit__alloc(a, bytes);
  f->p = p;
  f->n = n;
  f->d = d;
  if (f->U == NULL || f->P == NULL) {
    bsfit__fspline_free(a, f);
    return bsfit__fail(st, BSFIT_ENOMEM, "out of memory for a filtered spline of %zu points", n);
  }
  return BSFIT_OK;
}

bsfit__fview bsfit__curve_view(const bsfit_curve *c) {
  bsfit__fview v;
  v.p = c->degree;
  v.n = c->n;
  v.d = (size_t)c->dim;
  v.U = c->knots;
  v.P = c->ctrl;
  return v;
}

bsfit__fview bsfit__fspline_view(const bsfit__fspline *f) {
  bsfit__fview v;
  v.p = f->p;
  v.n = f->n;
  v.d = f->d;
  v.U = f->U;
  v.P = f->P;
  return v;
}

void bsfit__transpose_net(const double *src, size_t rows, size_t cols, size_t dim, double *dst) {
  size_t i, j;
  for (i = 0; i < rows; i++)
    for (j = 0; j < cols; j++)
      memcpy(dst + (j * rows + i) * dim, src + (i * cols + j) * dim, dim * sizeof(double));
}

bsfit__fview bsfit__surface_view_u(const bsfit_surface *s) {
  bsfit__fview v;
  v.p = s->degree_u;
  v.n = s->nu;
  v.d = bsfit__mulsize(s->nv, (size_t)s->dim);
  v.U = s->knots_u;
  v.P = s->ctrl;
  return v;
}

bsfit_err bsfit__fspline_to_curve(bsfit__fspline *f, int dim, int periodic,
                                  const bsfit_allocator *a, bsfit_curve *out, bsfit_status *st) {
  bsfit_curve res;
  bsfit_err e;
  bsfit_curve_init(&res);
  res.degree = f->p;
  res.dim = dim;
  res.n = f->n;
  res.knots = f->U;
  res.ctrl = f->P;
  res.periodic = periodic;
  res.alloc = *a;
  memset(f, 0, sizeof *f);
  e = bsfit_curve_validate(&res, st);
  if (e != BSFIT_OK) {
    bsfit_curve_free(&res);
    return e;
  }
  bsfit_curve_move(&res, out);
  return BSFIT_OK;
}
