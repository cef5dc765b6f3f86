/*
** filter_kernel.c
** Kernel filters: r passes of the box filter of half-width delta are the convolution of
** the curve (extended by its end control points) with the cardinal B-spline kernel of
** degree r - 1 and support 2 r delta (the box is the B-spline of degree 0, and convolving
** B-splines of degrees a and b gives the one of degree a + b + 1). On uniform knots with
** 2 delta = k spacing each pass is the moving average of k control points, so the r-fold
** moving average is the discrete filter whose weights are the B-spline's; on any knots
** each pass is the exact filter of filter_exact.c (a closed curve is unwrapped once for
** all r passes there). The passes work on raw splines, so only the final result is
** validated and handed to a curve or surface. The surface passes here also serve the box
** filter of filter.c (one pass each way).
*/
#include "filter_internal.h"

#include <float.h>
#include <math.h>
#include <string.h>

/* {====================================================================
** Passes on raw splines
** ===================================================================== */

static bsfit_err one_pass(const bsfit__fview *v, const bsfit__pass *arg, int periodic,
                          const bsfit_allocator *a, bsfit__fspline *out, bsfit_status *st) {
  if (arg->exact)
    return periodic ? bsfit__filter_exact_periodic(v, 1, arg->delta, a, out, st)
                    : bsfit__filter_exact_open(v, arg->delta, a, out, st);
  return periodic ? bsfit__filter_ma_periodic(v, arg->k, a, out, st)
                  : bsfit__filter_ma_open(v, arg->k, a, out, st);
}

/* `arg->order` passes of the filter on in; the intermediate splines are freed as soon as
** the next pass has read them. The first pass is checked by the caller (width, knots);
** later passes work on a spline of the same spacing (moving average) or on a wider domain. */
static bsfit_err passes(const bsfit__fview *in, const bsfit__pass *arg, int periodic,
                        const bsfit_allocator *a, bsfit__fspline *out, bsfit_status *st) {
  bsfit__fspline cur, next;
  bsfit__fview v;
  bsfit_err e;
  int i;
  if (arg->exact && periodic) /* unwrapped once for all the passes */
    return bsfit__filter_exact_periodic(in, arg->order, arg->delta, a, out, st);
  e = one_pass(in, arg, periodic, a, &cur, st);
  for (i = 1; i < arg->order && e == BSFIT_OK; i++) {
    if (bsfit__interrupted(a)) {
      bsfit__fspline_free(a, &cur);
      return bsfit__fail(st, BSFIT_EINTR, "kernel filter interrupted after %d of %d passes", i,
                         arg->order);
    }
    v = bsfit__fspline_view(&cur);
    e = one_pass(&v, arg, periodic, a, &next, st);
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

/* The first pass is checked by the box filter itself (bsfit_filter_box_curve*) and its
** result handed to the remaining passes; out is written only at the end, so an error
** leaves it unchanged. */
static bsfit_err kernel_curve(const bsfit_curve *c, const bsfit__pass *arg, bsfit_curve *out,
                              bsfit_status *st) {
  bsfit__pass rest = *arg;
  bsfit_allocator a;
  bsfit__fview v;
  bsfit__fspline f;
  bsfit_curve first;
  bsfit_err e;
  if (c == NULL || out == NULL) return bsfit__fail(st, BSFIT_EINVAL, "curve or output is NULL");
  if (c->n > 0 && (e = check_order(arg->order, c->degree, "", st)) != BSFIT_OK) return e;
  bsfit_curve_init(&first);
  if (arg->exact && c->periodic && arg->order > 1) {
    /* checked by a throw-away pass of the box filter (validity, width), then filtered
    ** once: the closed passes share one unwrapping */
    e = bsfit__check_box_curve_delta(c, arg->delta, st);
    if (e != BSFIT_OK) return e;
    a = c->alloc;
    v = bsfit__curve_view(c);
    e = passes(&v, arg, 1, &a, &f, st);
    return e == BSFIT_OK ? bsfit__fspline_to_curve(&f, c->dim, 1, &a, out, st) : e;
  }
  e = arg->exact ? bsfit_filter_box_curve_delta(c, arg->delta, &first, st)
                 : bsfit_filter_box_curve(c, arg->k, &first, st);
  if (e != BSFIT_OK) return e;
  if (arg->order == 1) {
    bsfit_curve_move(&first, out);
    return BSFIT_OK;
  }
  a = c->alloc;
  v = bsfit__curve_view(&first);
  rest.order = arg->order - 1;
  e = passes(&v, &rest, c->periodic, &a, &f, st);
  bsfit_curve_free(&first);
  if (e != BSFIT_OK) return e;
  e = bsfit__fspline_to_curve(&f, c->dim, c->periodic, &a, out, st);
  return e == BSFIT_OK ? bsfit__ok(st) : e;
}

bsfit_err bsfit_filter_kernel_curve(const bsfit_curve *c, int order, int k, bsfit_curve *out,
                                    bsfit_status *st) {
  bsfit__pass arg = {0, k, 0.0, order};
  return kernel_curve(c, &arg, out, st);
}

bsfit_err bsfit_filter_kernel_curve_delta(const bsfit_curve *c, int order, double delta,
                                          bsfit_curve *out, bsfit_status *st) {
  bsfit__pass arg = {1, 0, delta, order};
  return kernel_curve(c, &arg, out, st);
}

/* }==================================================================== */

/* {====================================================================
** Surfaces: the u passes on the net's rows (each row one "point" of nv*dim values),
** a transposition, the v passes, and the transposition back.
** ===================================================================== */

/* The passes along v (bsfit__vop). */
static bsfit_err passes_v(const bsfit__fview *v, const void *arg, const bsfit_allocator *a,
                          bsfit__fspline *out, bsfit_status *st) {
  return passes(v, (const bsfit__pass *)arg, 0, a, out, st);
}

bsfit_err bsfit__filter_surface(const bsfit_surface *s, const bsfit__pass *au,
                                const bsfit__pass *av, bsfit_surface *out, bsfit_status *st) {
  bsfit_allocator a = s->alloc;
  bsfit__fview v = bsfit__surface_view_u(s);
  bsfit__fspline fu;
  /* a surface closed around u: its rows are the points of one closed curve, filtered as
  ** closed curves are (unwrapped), so the result closes at the seam too */
  bsfit_err e = passes(&v, au, s->periodic_u, &a, &fu, st);
  if (e != BSFIT_OK) return e;
  e = bsfit__surface_along_v(s, &fu, passes_v, av, s->periodic_u, &a, out, st);
  bsfit__fspline_free(&a, &fu);
  return e == BSFIT_OK ? bsfit__ok(st) : e;
}

static bsfit_err kernel_surface(const bsfit_surface *s, const bsfit__pass *au,
                                const bsfit__pass *av, bsfit_surface *out, bsfit_status *st) {
  bsfit_err e;
  if (s == NULL) return bsfit__fail(st, BSFIT_EINVAL, "surface is NULL");
  e = bsfit_surface_validate(s, st);
  if (e == BSFIT_OK) e = check_order(au->order, s->degree_u, "_u", st);
  if (e == BSFIT_OK) e = check_order(av->order, s->degree_v, "_v", st);
  if (e == BSFIT_OK) e = bsfit__check_box_surface(s, au, av, st);
  if (e != BSFIT_OK) return e;
  if (out == NULL) return bsfit__fail(st, BSFIT_EINVAL, "output surface is NULL");
  return bsfit__filter_surface(s, au, av, out, st);
}

bsfit_err bsfit_filter_kernel_surface(const bsfit_surface *s, int order_u, int order_v, int k,
                                      int l, bsfit_surface *out, bsfit_status *st) {
  bsfit__pass au = {0, k, 0.0, order_u}, av = {0, l, 0.0, order_v};
  return kernel_surface(s, &au, &av, out, st);
}

bsfit_err bsfit_filter_kernel_surface_delta(const bsfit_surface *s, int order_u, int order_v,
                                            double delta_u, double delta_v, bsfit_surface *out,
                                            bsfit_status *st) {
  bsfit__pass au = {1, 0, delta_u, order_u}, av = {1, 0, delta_v, order_v};
  return kernel_surface(s, &au, &av, out, st);
}

/* }==================================================================== */
