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

bsfit_err bsfit__surface_along_v(const bsfit_surface *s, const bsfit__fspline *fu,
                                 bsfit__vop op, const void *arg, int periodic_u,
                                 const bsfit_allocator *a, bsfit_surface *out,
                                 bsfit_status *st) {
  /* Closed around u, only the distinct rows go along v and the wrapped rows are copied:
  ** a solve with many right-hand sides need not round equal columns equally (OpenBLAS's
  ** generic kernels do not), and a periodic net must repeat its rows exactly. */
  size_t dim = (size_t)s->dim, nu2 = fu->n, distinct = periodic_u ? fu->n - (size_t)fu->p : nu2;
  size_t bytes = distinct * s->nv * dim * sizeof(double), row;
  bsfit__fview v;
  bsfit__fspline fv;
  bsfit_surface res;
  double *tr = bsfit__alloc(a, bytes);
  bsfit_err e;
  if (tr == NULL) return bsfit__fail(st, BSFIT_ENOMEM, "out of memory for a transposed net");
  bsfit__transpose_net(fu->P, distinct, s->nv, dim, tr);
  v.p = s->degree_v;
  v.n = s->nv;
  v.d = distinct * dim;
  v.U = s->knots_v;
  v.P = tr;
  e = op(&v, arg, a, &fv, st);
  bsfit__free(a, tr, bytes);
  if (e != BSFIT_OK) return e;
  bsfit_surface_init(&res);
  e = bsfit_surface_alloc(&res, fu->p, fv.p, s->dim, nu2, fv.n, 0, a, st);
  if (e == BSFIT_OK) {
    res.periodic_u = periodic_u;
    memcpy(res.knots_u, fu->U, (nu2 + (size_t)fu->p + 1) * sizeof(double));
    memcpy(res.knots_v, fv.U, (fv.n + (size_t)fv.p + 1) * sizeof(double));
    bsfit__transpose_net(fv.P, fv.n, distinct, dim, res.ctrl);
    row = fv.n * dim;
    memcpy(res.ctrl + distinct * row, res.ctrl, (nu2 - distinct) * row * sizeof(double));
    e = bsfit_surface_validate(&res, st);
  }
  bsfit__fspline_free(a, &fv);
  if (e != BSFIT_OK) {
    bsfit_surface_free(&res);
    return e;
  }
  bsfit_surface_move(&res, out);
  return BSFIT_OK;
}
