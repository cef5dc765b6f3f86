/*
** filter.c
** Smoothing by box filtering (Persiano, docs/filtering.md): the paper's moving average of
** the control points for uniform curves (open with the end rule, or closed), and the
** public curve / surface entry points, which check their input and dispatch to the
** moving average or to the exact filter of filter_exact.c.
*/
#include "filter_internal.h"

#include <float.h>
#include <math.h>
#include <string.h>

/* {====================================================================
** Uniform knots
** ===================================================================== */

int bsfit__knots_equal_spans(const double *U, size_t nk) {
  size_t i;
  double h, tol;
  if (nk < 2) return 0;
  h = (U[nk - 1] - U[0]) / (double)(nk - 1);
  /* rounding of knots like i/n is a few ulps of the knot values, not of h */
  tol = 1e-8 * h + 8.0 * DBL_EPSILON * (fabs(U[0]) + fabs(U[nk - 1]));
  if (!(h > 0) || !isfinite(h)) return 0;
  for (i = 1; i < nk; i++)
    if (!(fabs((U[i] - U[i - 1]) - h) <= tol)) return 0; /* NaN spans fail too */
  return 1;
}

/* }==================================================================== */

/* {====================================================================
** Moving averages (F section 3, Corollary of Theorem 2)
** ===================================================================== */

/* The window sum is carried from one point to the next (add the entering point,
** subtract the leaving one) so the cost is O(1) per point whatever k; it is
** recomputed from scratch every REFRESH points so rounding cannot drift over a
** million points. Recomputing costs k, done every max(k, REFRESH) points. */
#define REFRESH 4096

/* Index of V^j: clamped to 0..n-1 (the end rule) or taken modulo n (closed curves). */
static size_t window_index(long j, size_t n, int cyclic) {
  if (cyclic) {
    long m = j % (long)n;
    return (size_t)(m < 0 ? m + (long)n : m);
  }
  if (j < 0) return 0;
  if ((size_t)j >= n) return n - 1;
  return (size_t)j;
}

/* Next index after i (which is window_index(j)), for window_index(j + 1), without a
** division: the window slides by one point at a time. */
static size_t next_index(size_t i, long j, size_t n, int cyclic) {
  if (cyclic) return i + 1 == n ? 0 : i + 1;
  return j + 1 <= 0 ? 0 : (i + 1 < n ? i + 1 : n - 1);
}

/* out[i*d..] = (1/k) sum_{j=s+i-k+1..s+i} V^{index(j)}, i = 0..count-1. Returns 0 when
** the host interrupted (looked at with every refresh of the sum). */
static int moving_average(const double *V, size_t n, size_t d, int k, long s, size_t count,
                          int cyclic, const bsfit_allocator *a, double *sum, double *out) {
  size_t i, c, every = (size_t)k > REFRESH ? (size_t)k : REFRESH, left = 0, iin = 0, iout = 0;
  double inv = 1.0 / (double)k;
  for (i = 0; i < count; i++) {
    long top = s + (long)i;
    if (left-- == 0) { /* a countdown, not i % every: a division per point costs */
      long j;
      if (bsfit__interrupted(a)) return 0;
      left = every - 1;
      memset(sum, 0, d * sizeof(double));
      for (j = top - k + 1; j <= top; j++) {
        const double *v = V + window_index(j, n, cyclic) * d;
        for (c = 0; c < d; c++) sum[c] += v[c];
      }
      iin = window_index(top, n, cyclic);
      iout = window_index(top - k, n, cyclic);
    } else {
      const double *vin, *vout;
      iin = next_index(iin, top - 1, n, cyclic);
      iout = next_index(iout, top - 1 - k, n, cyclic);
      vin = V + iin * d;
      vout = V + iout * d;
      for (c = 0; c < d; c++) sum[c] += vin[c] - vout[c];
    }
    for (c = 0; c < d; c++) out[i * d + c] = sum[c] * inv;
  }
  return 1;
}

bsfit_err bsfit__filter_ma_open(const bsfit__fview *in, int k, const bsfit_allocator *a,
                                bsfit__fspline *out, bsfit_status *st) {
  /* Output point i is V_F^{i+s}: s = -p (degree 0: -1) so that the domain
  ** [w_{p+1}, w_M] of the degree p+1 result is [U_1 - delta, U_{n+p-1} + delta]. */
  size_t p = (size_t)in->p, l = p > 0 ? 1 : 0, M = in->n + 2 * p + (size_t)k + 1 - 2 * l, j;
  long s = (long)l - (long)p - 1;
  double h = (in->U[in->n + p] - in->U[0]) / (double)(in->n + p), *sum;
  bsfit_err e = bsfit__fspline_alloc(a, out, in->p + 1, M, in->d, st);
  if (e != BSFIT_OK) return e;
  sum = bsfit__alloc(a, in->d * sizeof(double));
  if (sum == NULL) {
    bsfit__fspline_free(a, out);
    return bsfit__fail(st, BSFIT_ENOMEM, "out of memory for a window sum of %zu", in->d);
  }
  for (j = 0; j < M + p + 2; j++)
    out->U[j] = in->U[0] + ((double)((long)j + s) - 0.5 * k) * h;
  if (!moving_average(in->P, in->n, in->d, k, s, M, 0, a, sum, out->P)) {
    bsfit__free(a, sum, in->d * sizeof(double));
    bsfit__fspline_free(a, out);
    return bsfit__fail(st, BSFIT_EINTR, "filter interrupted");
  }
  bsfit__free(a, sum, in->d * sizeof(double));
  return bsfit__ok(st);
}

bsfit_err bsfit__filter_ma_periodic(const bsfit__fview *in, int k, const bsfit_allocator *a,
                                    bsfit__fspline *out, bsfit_status *st) {
  /* Stored point i is V_F^{i+s}, s = (k-1)/2, so the period starts at the original
  ** one (k even) or half a span after it (k odd), on a knot of the result. */
  size_t p = (size_t)in->p, N = in->n - p, q = p + 1, d = in->d, j;
  long s = (long)(k - 1) / 2;
  double h = (in->U[in->n + p] - in->U[0]) / (double)(in->n + p), *sum;
  bsfit_err e = bsfit__fspline_alloc(a, out, (int)q, N + q, d, st);
  if (e != BSFIT_OK) return e;
  sum = bsfit__alloc(a, d * sizeof(double));
  if (sum == NULL) {
    bsfit__fspline_free(a, out);
    return bsfit__fail(st, BSFIT_ENOMEM, "out of memory for a window sum of %zu", d);
  }
  for (j = 0; j < N + 2 * q + 1; j++)
    out->U[j] = in->U[0] + ((double)((long)j + s) - 0.5 * k) * h;
  if (!moving_average(in->P, N, d, k, s, N, 1, a, sum, out->P)) {
    bsfit__free(a, sum, d * sizeof(double));
    bsfit__fspline_free(a, out);
    return bsfit__fail(st, BSFIT_EINTR, "filter interrupted");
  }
  /* the wrapped points must repeat the first ones bit for bit (docs/method.md §1) */
  memcpy(out->P + N * d, out->P, q * d * sizeof(double));
  bsfit__free(a, sum, d * sizeof(double));
  return bsfit__ok(st);
}

/* }==================================================================== */

/* {====================================================================
** Curves
** ===================================================================== */

int bsfit_curve_is_uniform(const bsfit_curve *c) {
  if (c == NULL || c->knots == NULL || c->n == 0) return 0;
  return bsfit__knots_equal_spans(c->knots, c->n + (size_t)c->degree + 1);
}

static bsfit_err check_curve(const bsfit_curve *c, bsfit_status *st) {
  bsfit_err e;
  if (c == NULL) return bsfit__fail(st, BSFIT_EINVAL, "curve is NULL");
  e = bsfit_curve_validate(c, st);
  if (e != BSFIT_OK) return e;
  if (c->weights != NULL)
    return bsfit__fail(st, BSFIT_EINVAL,
                       "rational curves cannot be box-filtered (their average is not a "
                       "rational spline of the same kind)");
  if (c->degree + 1 > BSFIT_MAX_DEGREE)
    return bsfit__fail(st, BSFIT_EDEGREE, "filtering raises the degree %d above %d", c->degree,
                       BSFIT_MAX_DEGREE);
  return BSFIT_OK;
}


/* Hands f's arrays (allocated with *a) to a curve and moves it into out. The curve is
** validated first (O(n), like the filters: OK must mean a valid curve) and out (possibly
** the input curve) survives an invalid result. */
static bsfit_err give_curve(bsfit__fspline *f, int dim, int periodic,
                            const bsfit_allocator *a, bsfit_curve *out, bsfit_status *st) {
  bsfit_err e = bsfit__fspline_to_curve(f, dim, periodic, a, out, st);
  return e != BSFIT_OK ? e : bsfit__ok(st);
}

static size_t domain_spans(const bsfit_curve *c) {
  return c->periodic ? bsfit_curve_distinct(c) : c->n - (size_t)c->degree;
}

bsfit_err bsfit_filter_box_curve(const bsfit_curve *c, int k, bsfit_curve *out,
                                 bsfit_status *st) {
  bsfit_allocator a;
  bsfit__fview v;
  bsfit__fspline f;
  bsfit_err e = check_curve(c, st);
  if (e != BSFIT_OK) return e;
  if (out == NULL) return bsfit__fail(st, BSFIT_EINVAL, "output curve is NULL");
  if (k < 1) return bsfit__fail(st, BSFIT_EINVAL, "window width k = %d must be >= 1", k);
  if ((size_t)k > domain_spans(c))
    return bsfit__fail(st, BSFIT_EINVAL,
                       "window width k = %d is wider than the curve's %zu knot spans", k,
                       domain_spans(c));
  if (c->periodic && domain_spans(c) < (size_t)c->degree + 2)
    return bsfit__fail(st, BSFIT_ENOTPERIODIC,
                       "filtering raises the degree to %d, and a closed curve of that degree "
                       "needs %d distinct control points; this one has %zu",
                       c->degree + 1, c->degree + 2, domain_spans(c));
  if (!bsfit_curve_is_uniform(c))
    return bsfit__fail(st, BSFIT_EINVAL,
                       "knot spans are not all equal (clamped or non-uniform): use "
                       "bsfit_filter_box_curve_delta");
  a = c->alloc;
  v = bsfit__curve_view(c);
  e = c->periodic ? bsfit__filter_ma_periodic(&v, k, &a, &f, st)
                  : bsfit__filter_ma_open(&v, k, &a, &f, st);
  if (e != BSFIT_OK) return e;
  /* validated (give_curve): a minimal period may not hold the curve of degree p + 1, and
  ** knots of a uniform curve far from 0 (spacing near their ulp) may coincide once shifted */
  return give_curve(&f, c->dim, c->periodic, &a, out, st);
}

static bsfit_err check_delta(double delta, double length, const char *what, bsfit_status *st) {
  if (!isfinite(delta)) return bsfit__fail(st, BSFIT_ENONFINITE, "%s is not finite", what);
  if (!(delta > 0)) return bsfit__fail(st, BSFIT_EINVAL, "%s = %g must be > 0", what, delta);
  if (2.0 * delta > length)
    return bsfit__fail(st, BSFIT_EINVAL, "window 2 %s = %g is wider than the domain (%g)", what,
                       2.0 * delta, length);
  return BSFIT_OK;
}

bsfit_err bsfit__check_box_curve_delta(const bsfit_curve *c, double delta, bsfit_status *st) {
  double lo, hi;
  bsfit_err e = check_curve(c, st);
  if (e != BSFIT_OK) return e;
  bsfit_curve_domain(c, &lo, &hi);
  return check_delta(delta, hi - lo, "delta", st);
}

bsfit_err bsfit_filter_box_curve_delta(const bsfit_curve *c, double delta, bsfit_curve *out,
                                       bsfit_status *st) {
  bsfit_allocator a;
  bsfit__fview v;
  bsfit__fspline f;
  bsfit_err e = bsfit__check_box_curve_delta(c, delta, st);
  if (e != BSFIT_OK) return e;
  if (out == NULL) return bsfit__fail(st, BSFIT_EINVAL, "output curve is NULL");
  a = c->alloc;
  v = bsfit__curve_view(c);
  e = c->periodic ? bsfit__filter_exact_periodic(&v, 1, delta, &a, &f, st)
                  : bsfit__filter_exact_open(&v, delta, &a, &f, st);
  if (e != BSFIT_OK) return e;
  return give_curve(&f, c->dim, c->periodic, &a, out, st);
}

/* }==================================================================== */

/* {====================================================================
** Surfaces: a surface is a curve along u whose points are rows of nv*dim values;
** filter along u, transpose, filter along v, transpose back.
** ===================================================================== */

static bsfit_err check_surface(const bsfit_surface *s, bsfit_status *st) {
  bsfit_err e;
  if (s == NULL) return bsfit__fail(st, BSFIT_EINVAL, "surface is NULL");
  e = bsfit_surface_validate(s, st);
  if (e != BSFIT_OK) return e;
  if (s->weights != NULL)
    return bsfit__fail(st, BSFIT_EINVAL, "rational surfaces cannot be box-filtered");
  if (s->degree_u + 1 > BSFIT_MAX_DEGREE || s->degree_v + 1 > BSFIT_MAX_DEGREE)
    return bsfit__fail(st, BSFIT_EDEGREE, "filtering raises a degree above %d",
                       BSFIT_MAX_DEGREE);
  return BSFIT_OK;
}

bsfit_err bsfit__check_box_surface(const bsfit_surface *s, const bsfit__pass *au,
                                   const bsfit__pass *av, bsfit_status *st) {
  double ua, ub, va, vb;
  bsfit_err e = check_surface(s, st);
  size_t nper;
  if (e != BSFIT_OK) return e;
  nper = s->nu - (size_t)s->degree_u; /* closed around u: its distinct rows */
  if (au->order > bsfit__closed_order_cap(s))
    return bsfit__fail(st, BSFIT_ENOTPERIODIC,
                       "filtering raises the degree in u to %d, and a surface closed around u "
                       "of that degree needs %d distinct rows; this one has %zu",
                       s->degree_u + au->order, s->degree_u + au->order + 1, nper);
  if (au->exact) {
    bsfit_surface_domain(s, &ua, &ub, &va, &vb);
    e = check_delta(au->delta, ub - ua, "delta_u", st);
    return e == BSFIT_OK ? check_delta(av->delta, vb - va, "delta_v", st) : e;
  }
  if (au->k < 1 || (size_t)au->k > s->nu - (size_t)s->degree_u)
    return bsfit__fail(st, BSFIT_EINVAL, "window width k = %d out of range 1..%zu (spans in u)",
                       au->k, s->nu - (size_t)s->degree_u);
  if (av->k < 1 || (size_t)av->k > s->nv - (size_t)s->degree_v)
    return bsfit__fail(st, BSFIT_EINVAL, "window width l = %d out of range 1..%zu (spans in v)",
                       av->k, s->nv - (size_t)s->degree_v);
  if (!bsfit__knots_equal_spans(s->knots_u, s->nu + (size_t)s->degree_u + 1) ||
      !bsfit__knots_equal_spans(s->knots_v, s->nv + (size_t)s->degree_v + 1))
    return bsfit__fail(st, BSFIT_EINVAL,
                       "knot spans are not all equal in u and v: use "
                       "bsfit_filter_box_surface_delta");
  return BSFIT_OK;
}

/* The public surface filters: checked, then one pass each way (filter_kernel.c). */
static bsfit_err box_surface(const bsfit_surface *s, const bsfit__pass *au,
                             const bsfit__pass *av, bsfit_surface *out, bsfit_status *st) {
  bsfit_err e = bsfit__check_box_surface(s, au, av, st);
  if (e != BSFIT_OK) return e;
  if (out == NULL) return bsfit__fail(st, BSFIT_EINVAL, "output surface is NULL");
  return bsfit__filter_surface(s, au, av, out, st);
}

bsfit_err bsfit_filter_box_surface(const bsfit_surface *s, int k, int l, bsfit_surface *out,
                                   bsfit_status *st) {
  bsfit__pass au = {0, k, 0.0, 1}, av = {0, l, 0.0, 1};
  return box_surface(s, &au, &av, out, st);
}

bsfit_err bsfit_filter_box_surface_delta(const bsfit_surface *s, double delta_u, double delta_v,
                                         bsfit_surface *out, bsfit_status *st) {
  bsfit__pass au = {1, 0, delta_u, 1}, av = {1, 0, delta_v, 1};
  return box_surface(s, &au, &av, out, st);
}

/* }==================================================================== */
