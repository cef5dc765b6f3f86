/*
** surface.c
** Tensor-product B-spline, NURBS and Bézier surfaces: construction, validation,
** ownership, evaluation, partial derivatives (NURBS Book A3.6 / A4.4), normals and
** fast grid sampling.
*/
#include "internal.h"

#include <math.h>
#include <string.h>

/* {====================================================================
** Ownership
** ===================================================================== */

static size_t nknots_u(const bsfit_surface *s) { return s->nu + (size_t)s->degree_u + 1; }
static size_t nknots_v(const bsfit_surface *s) { return s->nv + (size_t)s->degree_v + 1; }
static size_t npoints(const bsfit_surface *s) { return s->nu * s->nv; }

void bsfit_surface_init(bsfit_surface *s) {
  memset(s, 0, sizeof *s);
}

void bsfit_surface_free(bsfit_surface *s) {
  if (s == NULL) return;
  bsfit__free(&s->alloc, s->knots_u, nknots_u(s) * sizeof(double));
  bsfit__free(&s->alloc, s->knots_v, nknots_v(s) * sizeof(double));
  bsfit__free(&s->alloc, s->ctrl, npoints(s) * (size_t)s->dim * sizeof(double));
  bsfit__free(&s->alloc, s->weights, npoints(s) * sizeof(double));
  bsfit_surface_init(s);
}

static bsfit_err check_shape(int pu, int pv, int dim, size_t nu, size_t nv, bsfit_status *st) {
  size_t np = bsfit__mulsize(nu, nv);
  if (dim < 1 || dim > 4) return bsfit__fail(st, BSFIT_EDIM, "dimension %d out of range 1..4", dim);
  if (pu < 0 || pu > BSFIT_MAX_DEGREE || pv < 0 || pv > BSFIT_MAX_DEGREE)
    return bsfit__fail(st, BSFIT_EDEGREE, "degrees (%d, %d) out of range 0..%d", pu, pv,
                       BSFIT_MAX_DEGREE);
  if (nu == 0 || nv == 0 || np == 0 || bsfit__mulsize(np, (size_t)dim * sizeof(double)) == 0 ||
      nu > ((size_t)-1) / 16 || nv > ((size_t)-1) / 16)
    return bsfit__fail(st, BSFIT_EINVAL, "bad control net size %zu x %zu", nu, nv);
  return BSFIT_OK;
}

bsfit_err bsfit_surface_alloc(bsfit_surface *s, int degree_u, int degree_v, int dim, size_t nu,
                              size_t nv, int rational, const bsfit_allocator *a,
                              bsfit_status *st) {
  size_t nc;
  bsfit_err e;
  bsfit_surface_free(s);
  e = check_shape(degree_u, degree_v, dim, nu, nv, st);
  if (e != BSFIT_OK) return e;
  if (a != NULL) s->alloc = *a;
  s->degree_u = degree_u;
  s->degree_v = degree_v;
  s->dim = dim;
  s->nu = nu;
  s->nv = nv;
  nc = npoints(s) * (size_t)dim * sizeof(double);
  s->knots_u = bsfit__alloc(&s->alloc, nknots_u(s) * sizeof(double));
  s->knots_v = bsfit__alloc(&s->alloc, nknots_v(s) * sizeof(double));
  s->ctrl = bsfit__alloc(&s->alloc, nc);
  s->weights = rational ? bsfit__alloc(&s->alloc, npoints(s) * sizeof(double)) : NULL;
  if (!s->knots_u || !s->knots_v || !s->ctrl || (rational && !s->weights)) {
    bsfit_surface_free(s);
    return bsfit__fail(st, BSFIT_ENOMEM, "out of memory for a %zu x %zu surface", nu, nv);
  }
  memset(s->knots_u, 0, nknots_u(s) * sizeof(double));
  memset(s->knots_v, 0, nknots_v(s) * sizeof(double));
  memset(s->ctrl, 0, nc);
  if (s->weights) memset(s->weights, 0, npoints(s) * sizeof(double));
  return bsfit__ok(st);
}

/* Prefixes the knot validator's message with the direction, which it cannot know. */
static bsfit_err name_direction(bsfit_status *st, bsfit_err e, char dir) {
  char msg[BSFIT_STATUS_MSG_SIZE];
  if (st == NULL) return e;
  memcpy(msg, st->msg, sizeof msg);
  msg[sizeof msg - 1] = '\0';
  return bsfit__fail(st, e, "%c knots: %s", dir, msg);
}

/* The expanded periodic form in u (as curve.c's validate_periodic): the last pu rows
** repeat the first pu exactly, and the knot spans repeat with the period. */
static bsfit_err validate_periodic_u(const bsfit_surface *s, bsfit_status *st) {
  size_t i, p = (size_t)s->degree_u, N, row = s->nv * (size_t)s->dim;
  const double *U = s->knots_u;
  double tol;
  if (s->degree_u < 1 || s->bezier || s->nu < 2 * p + 1 || s->nu < p + 2)
    return bsfit__fail(st, BSFIT_ENOTPERIODIC,
                       "surface periodic in u with degree %d needs more than %zu rows", s->degree_u,
                       s->nu);
  N = s->nu - p;
  tol = bsfit__periodic_span_tol(U[p], U[N + p]);
  for (i = 0; i < p * row; i++)
    if (s->ctrl[i] != s->ctrl[N * row + i])
      return bsfit__fail(st, BSFIT_ENOTPERIODIC, "wrapped row %zu differs from row %zu",
                         N + i / row, i / row);
  for (i = 0; s->weights && i < p * s->nv; i++)
    if (s->weights[i] != s->weights[N * s->nv + i])
      return bsfit__fail(st, BSFIT_ENOTPERIODIC, "wrapped weights of row %zu differ from row %zu",
                         N + i / s->nv, i / s->nv);
  for (i = 1; i < nknots_u(s) - N; i++)
    if (fabs((U[i + N] - U[i + N - 1]) - (U[i] - U[i - 1])) > tol)
      return bsfit__fail(st, BSFIT_ENOTPERIODIC, "u knot spans %zu and %zu differ", i - 1,
                         i + N - 1);
  return BSFIT_OK;
}

/* u wrapped into the period [a, b) of a surface periodic in u (others unchanged). */
static double wrap_u(const bsfit_surface *s, double u) {
  double a, b, T;
  if (!s->periodic_u) return u;
  bsfit_knots_domain(s->knots_u, s->nu, s->degree_u, &a, &b);
  T = b - a;
  if (u < a || u >= b) {
    u = a + fmod(u - a, T);
    if (u < a) u += T;
    if (u >= b) u = a; /* fmod rounding */
  }
  return u;
}

bsfit_err bsfit_surface_validate(const bsfit_surface *s, bsfit_status *st) {
  size_t i, np;
  bsfit_err e;
  if (s == NULL || s->ctrl == NULL || s->knots_u == NULL || s->knots_v == NULL)
    return bsfit__fail(st, BSFIT_EINVAL, "empty surface");
  if (s->dim < 1 || s->dim > 4)
    return bsfit__fail(st, BSFIT_EDIM, "dimension %d out of range 1..4", s->dim);
  e = bsfit_knots_validate(s->knots_u, nknots_u(s), s->degree_u, s->nu, st);
  if (e != BSFIT_OK) return name_direction(st, e, 'u');
  e = bsfit_knots_validate(s->knots_v, nknots_v(s), s->degree_v, s->nv, st);
  if (e != BSFIT_OK) return name_direction(st, e, 'v');
  np = npoints(s);
  i = bsfit__first_out_of_range(s->ctrl, np * (size_t)s->dim);
  if (i < np * (size_t)s->dim && !isfinite(s->ctrl[i]))
    return bsfit__fail(st, BSFIT_ENONFINITE, "control points contain NaN or Inf");
  if (i < np * (size_t)s->dim)
    return bsfit__fail(st, BSFIT_ERANGE, "a control point has a coordinate %g beyond 1e100",
                       s->ctrl[i]);
  for (i = 0; s->weights && i < np; i++)
    if (!(s->weights[i] >= BSFIT_WEIGHT_MIN && s->weights[i] <= BSFIT_WEIGHT_MAX))
      return bsfit__fail(st, BSFIT_EWEIGHT, "weight (%zu, %zu) is %g (must be in [1e-100, 1e100])",
                         i / s->nv, i % s->nv, s->weights[i]);
  if (s->periodic_u && (e = validate_periodic_u(s, st)) != BSFIT_OK) return e;
  if (s->bezier && (s->nu != (size_t)s->degree_u + 1 || s->nv != (size_t)s->degree_v + 1))
    return bsfit__fail(st, BSFIT_EINVAL,
                       "a Bezier surface of degrees (%d, %d) needs %d x %d control points",
                       s->degree_u, s->degree_v, s->degree_u + 1, s->degree_v + 1);
  return bsfit__ok(st);
}

bsfit_err bsfit_surface_new(bsfit_surface *s, int degree_u, int degree_v, int dim, size_t nu,
                            size_t nv, const double *knots_u, const double *knots_v,
                            const double *ctrl, const double *weights, const bsfit_allocator *a,
                            bsfit_status *st) {
  bsfit_err e;
  if (ctrl == NULL) {
    bsfit_surface_free(s);
    return bsfit__fail(st, BSFIT_EINVAL, "no control points");
  }
  e = bsfit_surface_alloc(s, degree_u, degree_v, dim, nu, nv, weights != NULL, a, st);
  if (e != BSFIT_OK) return e;
  if (nu < (size_t)degree_u + 1 || nv < (size_t)degree_v + 1) {
    bsfit_surface_free(s);
    return bsfit__fail(st, BSFIT_EDEGREE,
                       "degrees (%d, %d) need at least %d x %d control points, got %zu x %zu",
                       degree_u, degree_v, degree_u + 1, degree_v + 1, nu, nv);
  }
  memcpy(s->ctrl, ctrl, npoints(s) * (size_t)dim * sizeof(double));
  if (weights) memcpy(s->weights, weights, npoints(s) * sizeof(double));
  if (knots_u) memcpy(s->knots_u, knots_u, nknots_u(s) * sizeof(double));
  else (void)bsfit_knots_clamped(degree_u, nu, 0.0, 1.0, s->knots_u, NULL);
  if (knots_v) memcpy(s->knots_v, knots_v, nknots_v(s) * sizeof(double));
  else (void)bsfit_knots_clamped(degree_v, nv, 0.0, 1.0, s->knots_v, NULL);
  e = bsfit_surface_validate(s, st);
  if (e != BSFIT_OK) bsfit_surface_free(s);
  return e;
}

bsfit_err bsfit_surface_new_bezier(bsfit_surface *s, int dim, size_t nu, size_t nv,
                                   const double *ctrl, const double *weights,
                                   const bsfit_allocator *a, bsfit_status *st) {
  bsfit_err e;
  if (nu == 0 || nv == 0 || nu > BSFIT_MAX_DEGREE + 1 || nv > BSFIT_MAX_DEGREE + 1) {
    bsfit_surface_free(s);
    return bsfit__fail(st, BSFIT_EDEGREE,
                       "a Bezier surface needs 1..%d control points each way, got %zu x %zu",
                       BSFIT_MAX_DEGREE + 1, nu, nv);
  }
  e = bsfit_surface_new(s, (int)nu - 1, (int)nv - 1, dim, nu, nv, NULL, NULL, ctrl, weights, a,
                        st);
  if (e == BSFIT_OK) s->bezier = 1;
  return e;
}

bsfit_err bsfit_surface_copy(const bsfit_surface *src, bsfit_surface *dst,
                             const bsfit_allocator *a, bsfit_status *st) {
  bsfit_err e = bsfit_surface_alloc(dst, src->degree_u, src->degree_v, src->dim, src->nu,
                                    src->nv, src->weights != NULL, a ? a : &src->alloc, st);
  if (e != BSFIT_OK) return e;
  memcpy(dst->knots_u, src->knots_u, nknots_u(src) * sizeof(double));
  memcpy(dst->knots_v, src->knots_v, nknots_v(src) * sizeof(double));
  memcpy(dst->ctrl, src->ctrl, npoints(src) * (size_t)src->dim * sizeof(double));
  if (src->weights) memcpy(dst->weights, src->weights, npoints(src) * sizeof(double));
  dst->bezier = src->bezier;
  dst->periodic_u = src->periodic_u;
  return bsfit__ok(st);
}

void bsfit_surface_move(bsfit_surface *src, bsfit_surface *dst) {
  if (src == dst) return;
  bsfit_surface_free(dst);
  *dst = *src;
  bsfit_surface_init(src);
}

void bsfit_surface_domain(const bsfit_surface *s, double *ua, double *ub, double *va,
                          double *vb) {
  bsfit_knots_domain(s->knots_u, s->nu, s->degree_u, ua, ub);
  bsfit_knots_domain(s->knots_v, s->nv, s->degree_v, va, vb);
}

/* }==================================================================== */

/* {====================================================================
** Evaluation
** ===================================================================== */

/* Homogeneous control point (i, j): w*P and w (w = 1 when polynomial). */
static void load_hpoint(const bsfit_surface *s, size_t i, size_t j, double *h) {
  size_t k, d = (size_t)s->dim, idx = i * s->nv + j;
  double w = s->weights ? s->weights[idx] : 1.0;
  for (k = 0; k < d; k++) h[k] = w * s->ctrl[idx * d + k];
  h[d] = w;
}

/* sum_r sum_c Nu[r] Nv[c] Pw(i0+r, j0+c) into h (dim+1 doubles), then projected. */
static void contract(const bsfit_surface *s, size_t i0, size_t j0, const double *Nu,
                     const double *Nv, double *out) {
  double h[5] = {0, 0, 0, 0, 0}, q[5];
  size_t r, c, k, d = (size_t)s->dim;
  for (r = 0; r <= (size_t)s->degree_u; r++) {
    double row[5] = {0, 0, 0, 0, 0};
    for (c = 0; c <= (size_t)s->degree_v; c++) {
      load_hpoint(s, i0 + r, j0 + c, q);
      for (k = 0; k <= d; k++) row[k] += Nv[c] * q[k];
    }
    for (k = 0; k <= d; k++) h[k] += Nu[r] * row[k];
  }
  for (k = 0; k < d; k++) out[k] = h[k] / h[d];
}

/* Bézier surfaces use the Bernstein basis of the normalised parameters, a separate path
** from the knot-based one so each can check the other. */
static void eval_bezier(const bsfit_surface *s, double u, double v, double *out) {
  double Bu[BSFIT_MAX_DEGREE + 1], Bv[BSFIT_MAX_DEGREE + 1], ua, ub, va, vb;
  bsfit_surface_domain(s, &ua, &ub, &va, &vb);
  bsfit_bernstein(s->degree_u, (u - ua) / (ub - ua), Bu);
  bsfit_bernstein(s->degree_v, (v - va) / (vb - va), Bv);
  contract(s, 0, 0, Bu, Bv, out);
}

/* (u, v) finite and within one domain length of the domain in each direction: farther
** out the end polynomials' extrapolation loses its digits (as for curves) */
static bsfit_err check_uv(const bsfit_surface *s, double u, double v, bsfit_status *st) {
  double ua, ub, va, vb;
  if (!isfinite(u) || !isfinite(v))
    return bsfit__fail(st, BSFIT_ENONFINITE, "parameter (%g, %g) is not finite", u, v);
  bsfit_surface_domain(s, &ua, &ub, &va, &vb);
  if (!(u >= ua - (ub - ua) && u <= ub + (ub - ua) && v >= va - (vb - va) && v <= vb + (vb - va)))
    return bsfit__fail(st, BSFIT_EDOMAIN,
                       "parameter (%g, %g) is more than one domain length outside the domain", u,
                       v);
  return BSFIT_OK;
}

bsfit_err bsfit_surface_eval(const bsfit_surface *s, double u, double v, double *out,
                             bsfit_status *st) {
  double Nu[BSFIT_MAX_DEGREE + 1], Nv[BSFIT_MAX_DEGREE + 1];
  size_t su, sv;
  bsfit_err e;
  if (isfinite(u)) u = wrap_u(s, u); /* a periodic direction has no outside */
  e = check_uv(s, u, v, st);
  if (e != BSFIT_OK) return e;
  if (s->bezier) {
    eval_bezier(s, u, v, out);
  } else {
    su = bsfit_knots_find_span(s->knots_u, s->nu, s->degree_u, u);
    sv = bsfit_knots_find_span(s->knots_v, s->nv, s->degree_v, v);
    bsfit_basis_funs(su, u, s->degree_u, s->knots_u, Nu);
    bsfit_basis_funs(sv, v, s->degree_v, s->knots_v, Nv);
    contract(s, su - (size_t)s->degree_u, sv - (size_t)s->degree_v, Nu, Nv, out);
  }
  if (!bsfit__all_finite(out, (size_t)s->dim))
    return bsfit__fail(st, BSFIT_ERANGE, "S(%g, %g) overflows (extrapolated)", u, v);
  return bsfit__ok(st);
}

/* }==================================================================== */

/* {====================================================================
** Derivatives
** ===================================================================== */

#define KMAX (BSFIT_MAX_DEGREE + 1)

static double binom(int n, int r) {
  double b = 1.0;
  int i;
  for (i = 1; i <= r; i++) b = b * (double)(n - r + i) / (double)i;
  return b;
}

/* A3.6 on homogeneous points: Cartesian parts go to out, weights to W, layout
** [(a*(k+1) + b)]. The u basis derivatives are contracted one row of the net at a time. */
static void homogeneous_derivs(const bsfit_surface *s, double u, double v, int k, double *out,
                               double *W) {
  double Du[KMAX * KMAX], Dv[KMAX * KMAX], row[KMAX][5], q[5];
  size_t pu = (size_t)s->degree_u, pv = (size_t)s->degree_v, d = (size_t)s->dim;
  size_t su = bsfit_knots_find_span(s->knots_u, s->nu, s->degree_u, u);
  size_t sv = bsfit_knots_find_span(s->knots_v, s->nv, s->degree_v, v);
  size_t K = (size_t)k + 1, a, b, r, c, t;
  bsfit_basis_ders(su, u, s->degree_u, k, s->knots_u, Du);
  bsfit_basis_ders(sv, v, s->degree_v, k, s->knots_v, Dv);
  for (a = 0; a < K * K; a++) {
    W[a] = 0.0;
    for (t = 0; t < d; t++) out[a * d + t] = 0.0;
  }
  for (r = 0; r <= pu; r++) {
    /* row[b] = sum_c Nv^(b)[c] Pw(su-pu+r, sv-pv+c) */
    for (b = 0; b < K; b++)
      for (t = 0; t <= d; t++) row[b][t] = 0.0;
    for (c = 0; c <= pv; c++) {
      load_hpoint(s, su - pu + r, sv - pv + c, q);
      for (b = 0; b < K; b++)
        for (t = 0; t <= d; t++) row[b][t] += Dv[b * (pv + 1) + c] * q[t];
    }
    for (a = 0; a < K; a++) {
      double nu = Du[a * (pu + 1) + r];
      if (nu == 0.0) continue;
      for (b = 0; b < K; b++) {
        for (t = 0; t < d; t++) out[(a * K + b) * d + t] += nu * row[b][t];
        W[a * K + b] += nu * row[b][d];
      }
    }
  }
}

/* A4.4 in place: out holds A^(a,b) on entry and S^(a,b) on return. Entries are visited
** so that every S^(a-i, b-j) it needs is already converted. */
static void rational_derivs(size_t d, int k, const double *W, double *out) {
  size_t K = (size_t)k + 1;
  int a, b, i, j;
  size_t t;
  for (a = 0; a <= k; a++)
    for (b = 0; b <= k; b++) {
      double *S = out + ((size_t)a * K + (size_t)b) * d;
      for (i = 0; i <= a; i++)
        for (j = 0; j <= b; j++) {
          double f;
          const double *L;
          if (i == 0 && j == 0) continue;
          f = binom(a, i) * binom(b, j) * W[(size_t)i * K + (size_t)j];
          L = out + ((size_t)(a - i) * K + (size_t)(b - j)) * d;
          for (t = 0; t < d; t++) S[t] -= f * L[t];
        }
      for (t = 0; t < d; t++) S[t] /= W[0];
    }
}

bsfit_err bsfit_surface_derivs(const bsfit_surface *s, double u, double v, int k, double *out,
                               bsfit_status *st) {
  double W[KMAX * KMAX];
  bsfit_err e;
  if (k < 0 || k > BSFIT_MAX_DEGREE)
    return bsfit__fail(st, BSFIT_EINVAL, "derivative order %d out of range 0..%d", k,
                       BSFIT_MAX_DEGREE);
  if (isfinite(u)) u = wrap_u(s, u); /* a periodic direction has no outside */
  e = check_uv(s, u, v, st);
  if (e != BSFIT_OK) return e;
  homogeneous_derivs(s, u, v, k, out, W);
  if (s->weights != NULL) {
    rational_derivs((size_t)s->dim, k, W, out);
  }
  if (!bsfit__all_finite(out, (size_t)(k + 1) * (size_t)(k + 1) * (size_t)s->dim))
    return bsfit__fail(st, BSFIT_ERANGE, "derivatives of order <= %d at (%g, %g) overflow", k, u,
                       v);
  return bsfit__ok(st);
}

bsfit_err bsfit_surface_normal(const bsfit_surface *s, double u, double v, double *out,
                               bsfit_status *st) {
  double D[4 * 3], n[3], len, scale, mu = 0.0, mv = 0.0;
  double *Su = D + 2 * 3, *Sv = D + 1 * 3; /* (1,0) and (0,1) with k = 1 */
  bsfit_err e;
  int q;
  if (s->dim != 3)
    return bsfit__fail(st, BSFIT_EDIM, "normals need a 3D surface, this one has dim %d", s->dim);
  e = bsfit_surface_derivs(s, u, v, 1, D, st);
  if (e != BSFIT_OK) return e;
  /* the direction is all we need: scaled to components <= 1, the products below can
  ** neither overflow (derivatives of 1e115 over tiny spans) nor underflow */
  for (q = 0; q < 3; q++) {
    mu = fmax(mu, fabs(Su[q]));
    mv = fmax(mv, fabs(Sv[q]));
  }
  for (q = 0; q < 3 && mu > 0 && mv > 0; q++) {
    Su[q] /= mu;
    Sv[q] /= mv;
  }
  n[0] = Su[1] * Sv[2] - Su[2] * Sv[1];
  n[1] = Su[2] * Sv[0] - Su[0] * Sv[2];
  n[2] = Su[0] * Sv[1] - Su[1] * Sv[0];
  len = sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
  scale = sqrt(Su[0] * Su[0] + Su[1] * Su[1] + Su[2] * Su[2]) *
          sqrt(Sv[0] * Sv[0] + Sv[1] * Sv[1] + Sv[2] * Sv[2]);
  /* relative test: |Su x Sv| = |Su||Sv| sin(angle) */
  if (!(len > 1e-12 * scale) || !(len > 0)) {
    out[0] = out[1] = out[2] = 0.0;
    return bsfit__fail(st, BSFIT_EDEGENERATE,
                       "degenerate normal at (%g, %g): partial derivatives parallel or zero", u, v);
  }
  out[0] = n[0] / len;
  out[1] = n[1] / len;
  out[2] = n[2] / len;
  return bsfit__ok(st);
}

/* }==================================================================== */

/* {====================================================================
** Grid sampling
** ===================================================================== */

typedef struct grid_work {
  size_t *span_v;  /* kv spans in v */
  double *basis_v; /* kv * (pv+1) basis values */
  double *row;     /* nv * (dim+1): the net contracted with one row's u basis */
  size_t kv, nrow;
} grid_work;

static void grid_free(const bsfit_surface *s, grid_work *g, size_t pv1) {
  bsfit__free(&s->alloc, g->span_v, g->kv * sizeof(size_t));
  bsfit__free(&s->alloc, g->basis_v, g->kv * pv1 * sizeof(double));
  bsfit__free(&s->alloc, g->row, g->nrow * sizeof(double));
}

static double grid_param(double a, double b, size_t i, size_t k) {
  if (i + 1 == k) return b; /* exact end despite rounding */
  return a + (b - a) * (double)i / (double)(k - 1);
}

/* Bézier surfaces evaluate their clamped single-span basis here: it is the Bernstein
** basis, and A2.2 needs no division by 1-u. */
static void grid_columns(const bsfit_surface *s, grid_work *g) {
  size_t b, pv1 = (size_t)s->degree_v + 1;
  double va, vb;
  bsfit_surface_domain(s, NULL, NULL, &va, &vb);
  for (b = 0; b < g->kv; b++) {
    double v = grid_param(va, vb, b, g->kv);
    g->span_v[b] = bsfit_knots_find_span(s->knots_v, s->nv, s->degree_v, v);
    bsfit_basis_funs(g->span_v[b], v, s->degree_v, s->knots_v, g->basis_v + b * pv1);
  }
}

static void grid_row(const bsfit_surface *s, const grid_work *g, double u, double *out) {
  double Nu[BSFIT_MAX_DEGREE + 1], q[5];
  size_t pu = (size_t)s->degree_u, pv = (size_t)s->degree_v, d = (size_t)s->dim, hd = d + 1;
  size_t su = bsfit_knots_find_span(s->knots_u, s->nu, s->degree_u, u), r, j, b, c, t;
  bsfit_basis_funs(su, u, s->degree_u, s->knots_u, Nu);
  memset(g->row, 0, s->nv * hd * sizeof(double));
  for (r = 0; r <= pu; r++)
    for (j = 0; j < s->nv; j++) {
      load_hpoint(s, su - pu + r, j, q);
      for (t = 0; t < hd; t++) g->row[j * hd + t] += Nu[r] * q[t];
    }
  for (b = 0; b < g->kv; b++) {
    const double *Nv = g->basis_v + b * (pv + 1);
    const double *R = g->row + (g->span_v[b] - pv) * hd;
    double h[5] = {0, 0, 0, 0, 0};
    for (c = 0; c <= pv; c++)
      for (t = 0; t < hd; t++) h[t] += Nv[c] * R[c * hd + t];
    for (t = 0; t < d; t++) out[b * d + t] = h[t] / h[d];
  }
}

bsfit_err bsfit_surface_sample_grid(const bsfit_surface *s, size_t ku, size_t kv, double *out,
                                    bsfit_status *st) {
  grid_work g;
  size_t a, pv1 = (size_t)s->degree_v + 1, d = (size_t)s->dim;
  double ua, ub;
  if (ku < 2 || kv < 2 || bsfit__mulsize(bsfit__mulsize(ku, kv), d * sizeof(double)) == 0 ||
      bsfit__mulsize(kv, pv1 * sizeof(double)) == 0)
    return bsfit__fail(st, BSFIT_EINVAL, "grid %zu x %zu: need at least 2 x 2 points", ku, kv);
  g.kv = kv;
  g.nrow = s->nv * (d + 1);
  g.span_v = bsfit__alloc(&s->alloc, kv * sizeof(size_t));
  g.basis_v = bsfit__alloc(&s->alloc, kv * pv1 * sizeof(double));
  g.row = bsfit__alloc(&s->alloc, g.nrow * sizeof(double));
  if (!g.span_v || !g.basis_v || !g.row) {
    grid_free(s, &g, pv1);
    return bsfit__fail(st, BSFIT_ENOMEM, "out of memory for a %zu x %zu grid", ku, kv);
  }
  grid_columns(s, &g);
  bsfit_surface_domain(s, &ua, &ub, NULL, NULL);
  for (a = 0; a < ku; a++) grid_row(s, &g, grid_param(ua, ub, a, ku), out + a * kv * d);
  grid_free(s, &g, pv1);
  return bsfit__ok(st);
}

/* }==================================================================== */
