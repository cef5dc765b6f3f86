/*
** filter_kernel.c
** Kernel filters: r passes of the box filter of half-width delta are the convolution of
** the curve (extended by its end control points) with the cardinal B-spline kernel of
** degree r - 1 and support 2 r delta (the box is the B-spline of degree 0, and convolving
** B-splines of degrees a and b gives the one of degree a + b + 1). On uniform knots with
** 2 delta = k spacing each pass is the moving average of k control points, so the r-fold
** moving average is the discrete filter whose weights are the B-spline's; on any knots
** each pass is the exact filter of filter_exact.c. The passes work on raw splines, so
** only the final result is validated and handed to a curve or surface.
*/
#include "filter_internal.h"

#include <float.h>
#include <math.h>
#include <string.h>

/* {====================================================================
** Passes on raw splines
** ===================================================================== */

typedef struct kernel_arg {
  int exact;    /* exact filter of half-width delta, else moving average of k points */
  int k;
  double delta;
  int periodic; /* expanded periodic splines (curves only) */
} kernel_arg;

static bsfit_err one_pass(const bsfit__fview *v, const kernel_arg *arg,
                          const bsfit_allocator *a, bsfit__fspline *out, bsfit_status *st) {
  if (arg->exact)
    return arg->periodic ? bsfit__filter_exact_periodic(v, arg->delta, a, out, st)
                         : bsfit__filter_exact_open(v, arg->delta, a, out, st);
  return arg->periodic ? bsfit__filter_ma_periodic(v, arg->k, a, out, st)
                       : bsfit__filter_ma_open(v, arg->k, a, out, st);
}

static bsfit__fview view_of(const bsfit__fspline *f) {
  bsfit__fview v;
  v.p = f->p;
  v.n = f->n;
  v.d = f->d;
  v.U = f->U;
  v.P = f->P;
  return v;
}

/* `order` passes of the filter on in; the intermediate splines are freed as soon as the
** next pass has read them. The first pass is checked by the caller (width, knots); later
** passes work on a spline of the same spacing (moving average) or on a wider domain. */
static bsfit_err passes(const bsfit__fview *in, int order, const kernel_arg *arg,
                        const bsfit_allocator *a, bsfit__fspline *out, bsfit_status *st) {
  bsfit__fspline cur, next;
  bsfit__fview v;
  bsfit_err e;
  int i;
  e = one_pass(in, arg, a, &cur, st);
  for (i = 1; i < order && e == BSFIT_OK; i++) {
    if (bsfit__interrupted(a)) {
      bsfit__fspline_free(a, &cur);
      return bsfit__fail(st, BSFIT_EINTR, "kernel filter interrupted after %d of %d passes", i,
                         order);
    }
    v = view_of(&cur);
    e = one_pass(&v, arg, a, &next, st);
    bsfit__fspline_free(a, &cur);
    cur = next;
  }
  if (e != BSFIT_OK) return e;
  *out = cur;
  return BSFIT_OK;
}

/* }==================================================================== */

/* {====================================================================
** Curves
** ===================================================================== */

static bsfit_err check_order(int order, int degree, const char *dir, bsfit_status *st) {
  if (order < 1)
    return bsfit__fail(st, BSFIT_EINVAL, "kernel order%s = %d must be >= 1", dir, order);
  if (order > BSFIT_MAX_DEGREE - degree)
    return bsfit__fail(st, BSFIT_EDEGREE, "kernel order%s = %d raises the degree %d above %d",
                       dir, order, degree, BSFIT_MAX_DEGREE);
  return BSFIT_OK;
}

/* {====================================================================
** Closed curves, exact filter: unwrapped once over enough periods for all r passes, the
** passes on the open curve, one period read back (the box filter's closed case, which
** unwraps again at every pass, over a fixed margin)
** ===================================================================== */

/* Knot t_j of the periodic sequence, j any integer. */
static double periodic_knot(const bsfit_curve *c, size_t N, long j) {
  size_t p = (size_t)c->degree;
  long m = j % (long)N, fl = j / (long)N;
  double T = c->knots[p + N] - c->knots[p];
  if (m < 0) {
    m += (long)N;
    fl--;
  }
  return c->knots[p + (size_t)m] + (double)fl * T;
}

/* c as an open spline over 2M + 1 periods (the middle one c's domain). */
static bsfit_err unwrap(const bsfit_curve *c, size_t M, const bsfit_allocator *a,
                        bsfit__fspline *o, bsfit_status *st) {
  size_t p = (size_t)c->degree, N = c->n - p, d = (size_t)c->dim, n = N + p + 2 * M * N, i;
  long i0 = -(long)(M * N);
  bsfit_err e = bsfit__fspline_alloc(a, o, c->degree, n, d, st);
  if (e != BSFIT_OK) return e;
  for (i = 0; i < n + p + 1; i++) o->U[i] = periodic_knot(c, N, i0 - (long)p + (long)i);
  for (i = 0; i < n; i++) {
    long j = (i0 + (long)i) % (long)N;
    memcpy(o->P + i * d, c->ctrl + (size_t)(j < 0 ? j + (long)N : j) * d, d * sizeof(double));
  }
  return BSFIT_OK;
}

/* One period [t0, t0 + T] of the open result f, t0 its first knot at or after lo, as a
** periodic curve (expanded form). */
static bsfit_err read_period(bsfit__fspline *f, double lo, double T, int dim,
                             const bsfit_allocator *a, bsfit_curve *out, bsfit_status *st) {
  size_t q = (size_t)f->p, d = f->d, nk = f->n + q + 1, j0 = 0, jE, N2;
  double tol = 64.0 * DBL_EPSILON * (fabs(lo) + fabs(f->U[nk - 1]) + fabs(f->U[0]));
  bsfit_curve res;
  bsfit_err e;
  while (j0 < nk && f->U[j0] < lo - tol) j0++;
  for (jE = j0; jE < nk && f->U[jE] < f->U[j0] + T - tol; jE++) continue;
  N2 = jE - j0;
  if (j0 < q || jE + q >= nk || N2 < q + 1)
    return bsfit__fail(st, BSFIT_ENOTPERIODIC,
                       "the filtered closed curve has %zu knot spans per period, fewer than "
                       "degree + 1 = %zu", N2, q + 1);
  bsfit_curve_init(&res);
  /* the period's knots t_0..t_N2 sit in f->U[j0..]; t_N2 is t_0 + T exactly */
  {
    double save = f->U[jE];
    f->U[jE] = f->U[j0] + T;
    e = bsfit_curve_new_periodic(&res, (int)q, dim, N2, f->U + j0, f->P + (j0 - q) * d, NULL,
                                 a, st);
    f->U[jE] = save;
  }
  if (e != BSFIT_OK) return e;
  bsfit_curve_move(&res, out);
  return BSFIT_OK;
}

static bsfit_err kernel_closed_exact(const bsfit_curve *c, int order, double delta,
                                     bsfit_curve *out, bsfit_status *st) {
  bsfit_allocator a = c->alloc;
  double lo, hi, T;
  size_t N = bsfit_curve_distinct(c), M;
  bsfit__fspline u, f;
  bsfit__fview v;
  kernel_arg arg = {1, 0, 0.0, 0};
  bsfit_err e;
  bsfit_curve_domain(c, &lo, &hi);
  T = hi - lo;
  /* room for the kernel's support r delta and the q + 1 knots read around the period */
  M = 1 + (size_t)floor(order * delta / T) + ((size_t)(c->degree + order) + 1) / N;
  arg.delta = delta;
  e = unwrap(c, M, &a, &u, st);
  if (e != BSFIT_OK) return e;
  v = view_of(&u);
  e = passes(&v, order, &arg, &a, &f, st);
  bsfit__fspline_free(&a, &u);
  if (e != BSFIT_OK) return e;
  e = read_period(&f, lo, T, c->dim, &a, out, st);
  bsfit__fspline_free(&a, &f);
  return e == BSFIT_OK ? bsfit__ok(st) : e;
}

/* }==================================================================== */

/* What bsfit_filter_box_curve_delta checks of a closed curve. */
static bsfit_err check_closed(const bsfit_curve *c, double delta, bsfit_status *st) {
  double lo, hi;
  bsfit_err e = bsfit_curve_validate(c, st);
  if (e != BSFIT_OK) return e;
  if (c->weights != NULL)
    return bsfit__fail(st, BSFIT_EINVAL, "rational curves cannot be filtered");
  bsfit_curve_domain(c, &lo, &hi);
  if (!isfinite(delta)) return bsfit__fail(st, BSFIT_ENONFINITE, "delta is not finite");
  if (!(delta > 0) || 2.0 * delta > hi - lo)
    return bsfit__fail(st, BSFIT_EINVAL, "delta = %g must be > 0 and at most half the period %g",
                       delta, hi - lo);
  return BSFIT_OK;
}

/* The first pass is checked by the box filter itself (bsfit_filter_box_curve*): out is
** written only by the last pass, so an error leaves it unchanged. */
static bsfit_err kernel_curve(const bsfit_curve *c, int order, const kernel_arg *arg,
                              bsfit_curve *out, bsfit_status *st) {
  bsfit_allocator a;
  bsfit__fview v;
  bsfit__fspline f;
  bsfit_curve first, res;
  bsfit_err e;
  if (c == NULL || out == NULL) return bsfit__fail(st, BSFIT_EINVAL, "curve or output is NULL");
  if (c->n > 0 && (e = check_order(order, c->degree, "", st)) != BSFIT_OK) return e;
  if (arg->exact && c->periodic && order > 1) {
    e = check_closed(c, arg->delta, st);
    return e == BSFIT_OK ? kernel_closed_exact(c, order, arg->delta, out, st) : e;
  }
  bsfit_curve_init(&first);
  e = arg->exact ? bsfit_filter_box_curve_delta(c, arg->delta, &first, st)
                 : bsfit_filter_box_curve(c, arg->k, &first, st);
  if (e != BSFIT_OK) return e;
  if (order == 1) {
    bsfit_curve_move(&first, out);
    return BSFIT_OK;
  }
  a = c->alloc;
  v.p = first.degree;
  v.n = first.n;
  v.d = (size_t)first.dim;
  v.U = first.knots;
  v.P = first.ctrl;
  e = passes(&v, order - 1, arg, &a, &f, st);
  bsfit_curve_free(&first);
  if (e != BSFIT_OK) return e;
  bsfit_curve_init(&res);
  res.degree = f.p;
  res.dim = c->dim;
  res.n = f.n;
  res.knots = f.U;
  res.ctrl = f.P;
  res.periodic = c->periodic;
  res.alloc = a;
  e = bsfit_curve_validate(&res, st);
  if (e != BSFIT_OK) {
    bsfit_curve_free(&res);
    return e;
  }
  bsfit_curve_move(&res, out);
  return bsfit__ok(st);
}

bsfit_err bsfit_filter_kernel_curve(const bsfit_curve *c, int order, int k, bsfit_curve *out,
                                    bsfit_status *st) {
  kernel_arg arg;
  arg.exact = 0;
  arg.k = k;
  arg.delta = 0.0;
  arg.periodic = c != NULL && c->periodic;
  return kernel_curve(c, order, &arg, out, st);
}

bsfit_err bsfit_filter_kernel_curve_delta(const bsfit_curve *c, int order, double delta,
                                          bsfit_curve *out, bsfit_status *st) {
  kernel_arg arg;
  arg.exact = 1;
  arg.k = 0;
  arg.delta = delta;
  arg.periodic = c != NULL && c->periodic;
  return kernel_curve(c, order, &arg, out, st);
}

/* }==================================================================== */

/* {====================================================================
** Surfaces: the u passes on the net's rows (each row one "point" of nv*dim values),
** a transposition, the v passes, and the transposition back.
** ===================================================================== */

/* dst[(j*rows + i)*dim + c] = src[(i*cols + j)*dim + c] */
static void transpose(const double *src, size_t rows, size_t cols, size_t dim, double *dst) {
  size_t i, j;
  for (i = 0; i < rows; i++)
    for (j = 0; j < cols; j++)
      memcpy(dst + (j * rows + i) * dim, src + (i * cols + j) * dim, dim * sizeof(double));
}

/* The v passes on the u-filtered spline fu, then the surface into out. */
static bsfit_err surface_v(const bsfit_surface *s, const bsfit__fspline *fu, int order_v,
                           const kernel_arg *av, const bsfit_allocator *a, bsfit_surface *out,
                           bsfit_status *st) {
  size_t dim = (size_t)s->dim, nu2 = fu->n, bytes = fu->n * fu->d * sizeof(double);
  bsfit__fview v;
  bsfit__fspline fv;
  bsfit_surface res;
  double *tr = bsfit__alloc(a, bytes);
  bsfit_err e;
  if (tr == NULL) return bsfit__fail(st, BSFIT_ENOMEM, "out of memory for a transposed net");
  transpose(fu->P, nu2, s->nv, dim, tr);
  v.p = s->degree_v;
  v.n = s->nv;
  v.d = nu2 * dim;
  v.U = s->knots_v;
  v.P = tr;
  e = passes(&v, order_v, av, a, &fv, st);
  bsfit__free(a, tr, bytes);
  if (e != BSFIT_OK) return e;
  bsfit_surface_init(&res);
  e = bsfit_surface_alloc(&res, fu->p, fv.p, s->dim, nu2, fv.n, 0, a, st);
  if (e == BSFIT_OK) {
    memcpy(res.knots_u, fu->U, (nu2 + (size_t)fu->p + 1) * sizeof(double));
    memcpy(res.knots_v, fv.U, (fv.n + (size_t)fv.p + 1) * sizeof(double));
    transpose(fv.P, fv.n, nu2, dim, res.ctrl);
    e = bsfit_surface_validate(&res, st);
  }
  bsfit__fspline_free(a, &fv);
  if (e != BSFIT_OK) {
    bsfit_surface_free(&res);
    return e;
  }
  bsfit_surface_move(&res, out);
  return bsfit__ok(st);
}

/* Checks the orders, then one box pass of the public surface filter checks everything
** else (rational, widths, uniform knots) on a throw-away result. */
static bsfit_err check_kernel_surface(const bsfit_surface *s, int ou, int ov,
                                      const kernel_arg *au, const kernel_arg *av,
                                      bsfit_status *st) {
  bsfit_surface probe;
  bsfit_err e;
  if (s == NULL) return bsfit__fail(st, BSFIT_EINVAL, "surface is NULL");
  e = bsfit_surface_validate(s, st);
  if (e == BSFIT_OK) e = check_order(ou, s->degree_u, "_u", st);
  if (e == BSFIT_OK) e = check_order(ov, s->degree_v, "_v", st);
  if (e != BSFIT_OK) return e;
  if (s->weights != NULL)
    return bsfit__fail(st, BSFIT_EINVAL, "rational surfaces cannot be filtered");
  if (au->exact) {
    double ua, ub, va, vb;
    bsfit_surface_domain(s, &ua, &ub, &va, &vb);
    if (!isfinite(au->delta) || !isfinite(av->delta))
      return bsfit__fail(st, BSFIT_ENONFINITE, "delta_u or delta_v is not finite");
    if (!(au->delta > 0) || !(av->delta > 0) || 2 * au->delta > ub - ua ||
        2 * av->delta > vb - va)
      return bsfit__fail(st, BSFIT_EINVAL,
                         "delta_u = %g, delta_v = %g must be > 0 and at most half the domain "
                         "(%g x %g)", au->delta, av->delta, ub - ua, vb - va);
    return BSFIT_OK;
  }
  bsfit_surface_init(&probe);
  e = bsfit_filter_box_surface(s, au->k, av->k, &probe, st);
  bsfit_surface_free(&probe);
  return e;
}

static bsfit_err kernel_surface(const bsfit_surface *s, int ou, int ov, const kernel_arg *au,
                                const kernel_arg *av, bsfit_surface *out, bsfit_status *st) {
  bsfit_allocator a;
  bsfit__fview v;
  bsfit__fspline fu;
  bsfit_err e = check_kernel_surface(s, ou, ov, au, av, st);
  if (e != BSFIT_OK) return e;
  if (out == NULL) return bsfit__fail(st, BSFIT_EINVAL, "output surface is NULL");
  a = s->alloc;
  v.p = s->degree_u;
  v.n = s->nu;
  v.d = bsfit__mulsize(s->nv, (size_t)s->dim);
  v.U = s->knots_u;
  v.P = s->ctrl;
  e = passes(&v, ou, au, &a, &fu, st);
  if (e != BSFIT_OK) return e;
  e = surface_v(s, &fu, ov, av, &a, out, st);
  bsfit__fspline_free(&a, &fu);
  return e;
}

bsfit_err bsfit_filter_kernel_surface(const bsfit_surface *s, int order_u, int order_v, int k,
                                      int l, bsfit_surface *out, bsfit_status *st) {
  kernel_arg au = {0, k, 0.0, 0}, av = {0, l, 0.0, 0};
  return kernel_surface(s, order_u, order_v, &au, &av, out, st);
}

bsfit_err bsfit_filter_kernel_surface_delta(const bsfit_surface *s, int order_u, int order_v,
                                            double delta_u, double delta_v, bsfit_surface *out,
                                            bsfit_status *st) {
  kernel_arg au = {1, 0, delta_u, 0}, av = {1, 0, delta_v, 0};
  return kernel_surface(s, order_u, order_v, &au, &av, out, st);
}

/* }==================================================================== */
