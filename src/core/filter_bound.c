/*
** filter_bound.c
** A certified upper bound of the distance between two curves (or two surfaces) that share
** their parameter, as a smoothing and its input do: |A(t) - B(t)| bounds the distance from
** A(t) to B and from B(t) to A, so its maximum over the domain bounds the Hausdorff
** distance of the two point sets. On an interval where both are polynomials of degree at
** most m the difference is D(s) = sum_k b_k B_k^m(s) (s in [0, 1], Bernstein basis), and
** |D| <= max_k |b_k| (D(s) is a convex combination of the b_k). The b_k come from the
** values of D at m + 1 interior nodes by one fixed (m+1) x (m+1) matrix, the inverse of
** the Bernstein collocation matrix, computed once per call; the rounding of the values,
** magnified by that matrix's norm, is added to the bound. An interval whose bound exceeds
** the threshold while its values do not is halved (the Bernstein coefficients of the halves
** converge quadratically to the values), a few times at most. Surfaces: the same on each
** patch, in both directions. O(m^2) work per interval, no allocation.
*/
#include "filter_internal.h"

#include <float.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#define BOUND_DEPTH 4         /* halvings of a curve interval, at most */
#define BOUND_DEPTH_SURFACE 2 /* of a surface patch (each makes four) */

/* {====================================================================
** The Bernstein conversion
** ===================================================================== */

/* Node i of m + 1 in (0, 1): the middle of the i-th of m + 1 equal cells, so that a node
** never sits on a knot and the span found for it is the interval's own. */
static double node(int m, int i) { return ((double)i + 0.5) / ((double)m + 1.0); }

static double bernstein(int m, int k, double s) {
  double c = 1.0, v;
  int i;
  for (i = 1; i <= k; i++) c = c * (double)(m - k + i) / (double)i;
  v = c;
  for (i = 0; i < k; i++) v *= s;
  for (i = 0; i < m - k; i++) v *= 1.0 - s;
  return v;
}

bsfit_err bsfit__bern_init(int m, bsfit__bern *z) {
  double A[(BSFIT__BERN_MAX + 1) * (BSFIT__BERN_MAX + 1)];
  int n = m + 1, i, j, k;
  if (m < 0 || m > BSFIT__BERN_MAX) return BSFIT_EDEGREE;
  z->m = m;
  for (i = 0; i < n; i++)
    for (j = 0; j < n; j++) {
      A[i * n + j] = bernstein(m, j, node(m, i));
      z->inv[i * n + j] = i == j;
    }
  for (k = 0; k < n; k++) { /* Gauss-Jordan, partial pivoting: a tiny, well-posed system */
    int piv = k;
    double f;
    for (i = k + 1; i < n; i++)
      if (fabs(A[i * n + k]) > fabs(A[piv * n + k])) piv = i;
    for (j = 0; j < n; j++) {
      double t = A[k * n + j];
      A[k * n + j] = A[piv * n + j], A[piv * n + j] = t;
      t = z->inv[k * n + j];
      z->inv[k * n + j] = z->inv[piv * n + j], z->inv[piv * n + j] = t;
    }
    f = 1.0 / A[k * n + k];
    for (j = 0; j < n; j++) A[k * n + j] *= f, z->inv[k * n + j] *= f;
    for (i = 0; i < n; i++) {
      double g = A[i * n + k];
      if (i == k || g == 0.0) continue;
      for (j = 0; j < n; j++) {
        A[i * n + j] -= g * A[k * n + j];
        z->inv[i * n + j] -= g * z->inv[k * n + j];
      }
    }
  }
  z->norm = 0.0;
  for (i = 0; i < n; i++) {
    double row = 0.0;
    for (j = 0; j < n; j++) row += fabs(z->inv[i * n + j]);
    if (row > z->norm) z->norm = row;
  }
  return BSFIT_OK;
}

/* }==================================================================== */

/* {====================================================================
** Curves
** ===================================================================== */

typedef struct cbound {
  const bsfit__bern *z;
  const bsfit_curve *A, *B;
  double thr;
  int depth;
} cbound;

/* c at t inside its knot span s (polynomial c, t already in c's period). */
static void eval_in_span(const bsfit_curve *c, size_t s, double t, double *out) {
  double N[BSFIT__BERN_MAX + 1];
  size_t p = (size_t)c->degree, j, k, d = (size_t)c->dim;
  const double *P = c->ctrl + (s - p) * d;
  bsfit_basis_funs(s, t, c->degree, c->knots, N);
  for (k = 0; k < d; k++) out[k] = 0.0;
  for (j = 0; j <= p; j++)
    for (k = 0; k < d; k++) out[k] += N[j] * P[j * d + k];
}

/* Bound of |A - B| over [x0, x1]; *low receives the largest value seen (a lower bound of
** the maximum). Each curve is one polynomial there: its span is found once, at the
** middle (B's parameter moved into its period when B is closed: shift). */
static double interval_bound(const cbound *w, double x0, double x1, int depth, double *low) {
  double V[(BSFIT__BERN_MAX + 1) * 4], a[4], b[4], scale = 0.0, top = 0.0, val = 0.0;
  double mid = 0.5 * (x0 + x1), shift = bsfit__curve_wrap(w->B, mid) - mid;
  int m = w->z->m, n = m + 1, d = w->A->dim, i, k, c;
  size_t sa = bsfit_knots_find_span(w->A->knots, w->A->n, w->A->degree, mid);
  size_t sb = bsfit_knots_find_span(w->B->knots, w->B->n, w->B->degree, mid + shift);
  for (i = 0; i < n; i++) {
    double t = x0 + (x1 - x0) * node(m, i), s2 = 0.0;
    eval_in_span(w->A, sa, t, a);
    eval_in_span(w->B, sb, t + shift, b);
    for (c = 0; c < d; c++) {
      V[i * d + c] = a[c] - b[c];
      s2 += V[i * d + c] * V[i * d + c];
      scale = fmax(scale, fabs(a[c]) + fabs(b[c]));
    }
    val = fmax(val, sqrt(s2));
  }
  for (k = 0; k < n; k++) { /* coefficient k = sum_i inv[k][i] V_i */
    double s2 = 0.0;
    for (c = 0; c < d; c++) {
      double bk = 0.0;
      for (i = 0; i < n; i++) bk += w->z->inv[k * n + i] * V[i * d + c];
      s2 += bk * bk;
    }
    top = fmax(top, sqrt(s2));
  }
  /* values carry about (m + 2) roundings of the coordinates' size each */
  top += w->z->norm * 16.0 * (double)(m + 2) * DBL_EPSILON * scale;
  if (top > w->thr && val <= w->thr && depth < w->depth && x1 - x0 > 4.0 * DBL_EPSILON * scale) {
    double l1 = 0.0, l2 = 0.0;
    double b1 = interval_bound(w, x0, mid, depth + 1, &l1);
    double b2 = interval_bound(w, mid, x1, depth + 1, &l2);
    *low = fmax(*low, fmax(l1, l2));
    return fmax(b1, b2);
  }
  *low = fmax(*low, val);
  return top;
}

static int cmp_double(const void *x, const void *y) {
  double a = *(const double *)x, b = *(const double *)y;
  return a < b ? -1 : (a > b);
}

/* x[0..m) sorted, each value once; returns how many */
static size_t sorted_unique(double *x, size_t m) {
  size_t i, k;
  qsort(x, m, sizeof(double), cmp_double);
  for (i = k = 0; i < m; i++)
    if (k == 0 || x[i] > x[k - 1]) x[k++] = x[i];
  return k;
}

/* The distinct knots of A and of B (B's moved by whole periods when B is closed) strictly
** inside (lo, hi), sorted, into x (room for both knot vectors, three times B's). */
static size_t inner_knots(const bsfit_curve *A, const bsfit_curve *B, double lo, double hi,
                          double *x) {
  size_t na = A->n + (size_t)A->degree + 1, nb = B->n + (size_t)B->degree + 1, i, m = 0;
  double a, b;
  int j;
  for (i = 0; i < na; i++)
    if (A->knots[i] > lo && A->knots[i] < hi) x[m++] = A->knots[i];
  bsfit_curve_domain(B, &a, &b);
  for (j = B->periodic ? -1 : 0; j <= (B->periodic ? 1 : 0); j++)
    for (i = 0; i < nb; i++) {
      double v = B->knots[i] + (double)j * (b - a);
      if (v > lo && v < hi) x[m++] = v;
    }
  return sorted_unique(x, m);
}

bsfit_err bsfit__curve_diff_bound(const bsfit_curve *A, const bsfit_curve *B, double thr,
                                  const bsfit__breaks *br, double *span_max,
                                  const bsfit_allocator *al, bsfit__bound *out,
                                  bsfit_status *st) {
  size_t na = A->n + (size_t)A->degree + 1, nb = B->n + (size_t)B->degree + 1, nx, i;
  size_t bytes = bsfit__mulsize(na + 3 * nb + 2, sizeof(double));
  int m = A->degree > B->degree ? A->degree : B->degree;
  double lo, hi, *x;
  bsfit__bern z;
  cbound w;
  if (bsfit__bern_init(m, &z) != BSFIT_OK)
    return bsfit__fail(st, BSFIT_EDEGREE, "no distance bound for degree %d (at most %d)", m,
                       BSFIT__BERN_MAX);
  x = bsfit__alloc(al, bytes);
  if (x == NULL) return bsfit__fail(st, BSFIT_ENOMEM, "out of memory for a distance bound");
  bsfit_curve_domain(A, &lo, &hi);
  x[0] = lo;
  nx = 1 + inner_knots(A, B, lo, hi, x + 1);
  x[nx++] = hi;
  w.z = &z;
  w.A = A;
  w.B = B;
  w.thr = thr;
  w.depth = BOUND_DEPTH;
  out->bound = out->low = 0.0;
  if (span_max != NULL) memset(span_max, 0, (br->n - 1) * sizeof(double));
  for (i = 0; i + 1 < nx; i++) {
    double low = 0.0, bd = interval_bound(&w, x[i], x[i + 1], 0, &low);
    out->bound = fmax(out->bound, bd);
    out->low = fmax(out->low, low);
    if (span_max != NULL) {
      size_t s = bsfit__break_span(br, 0.5 * (x[i] + x[i + 1]));
      span_max[s] = fmax(span_max[s], bd);
    }
    if ((i & 1023) == 1023 && bsfit__interrupted(al)) {
      bsfit__free(al, x, bytes);
      return bsfit__fail(st, BSFIT_EINTR, "distance bound interrupted");
    }
  }
  bsfit__free(al, x, bytes);
  return BSFIT_OK;
}

/* }==================================================================== */

/* {====================================================================
** Surfaces
** ===================================================================== */

typedef struct sbound {
  const bsfit__bern *zu, *zv;
  const bsfit_surface *A, *B;
  double thr;
} sbound;

/* Bound of |A - B| over one patch (both polynomial there). */
static double patch_bound(const sbound *w, const double *u, const double *v, int depth,
                          double *low) {
  enum { N1 = BSFIT__BERN_MAX + 1 };
  double V[N1 * N1 * 4], T[N1 * N1 * 4], a[4], b[4], scale = 0.0, top = 0.0, val = 0.0;
  int mu = w->zu->m, mv = w->zv->m, nu = mu + 1, nv = mv + 1, d = w->A->dim, i, j, k, c;
  for (i = 0; i < nu; i++)
    for (j = 0; j < nv; j++) {
      double s = u[0] + (u[1] - u[0]) * node(mu, i), t = v[0] + (v[1] - v[0]) * node(mv, j);
      double s2 = 0.0, *Vij = V + (i * nv + j) * d;
      bsfit_surface_eval(w->A, s, t, a, NULL);
      bsfit_surface_eval(w->B, s, t, b, NULL);
      for (c = 0; c < d; c++) {
        Vij[c] = a[c] - b[c];
        s2 += Vij[c] * Vij[c];
        scale = fmax(scale, fabs(a[c]) + fabs(b[c]));
      }
      val = fmax(val, sqrt(s2));
    }
  for (k = 0; k < nu; k++) /* T = inv_u V, then coefficients = T inv_v^T */
    for (j = 0; j < nv; j++)
      for (c = 0; c < d; c++) {
        double s = 0.0;
        for (i = 0; i < nu; i++) s += w->zu->inv[k * nu + i] * V[(i * nv + j) * d + c];
        T[(k * nv + j) * d + c] = s;
      }
  for (k = 0; k < nu; k++)
    for (j = 0; j < nv; j++) {
      double s2 = 0.0;
      for (c = 0; c < d; c++) {
        double s = 0.0;
        for (i = 0; i < nv; i++) s += w->zv->inv[j * nv + i] * T[(k * nv + i) * d + c];
        s2 += s * s;
      }
      top = fmax(top, sqrt(s2));
    }
  top += w->zu->norm * w->zv->norm * 16.0 * (double)(mu + mv + 2) * DBL_EPSILON * scale;
  if (top > w->thr && val <= w->thr && depth < BOUND_DEPTH_SURFACE) {
    double um[2][2] = {{u[0], 0.5 * (u[0] + u[1])}, {0.5 * (u[0] + u[1]), u[1]}};
    double vm[2][2] = {{v[0], 0.5 * (v[0] + v[1])}, {0.5 * (v[0] + v[1]), v[1]}};
    double best = 0.0;
    for (i = 0; i < 2; i++)
      for (j = 0; j < 2; j++) best = fmax(best, patch_bound(w, um[i], vm[j], depth + 1, low));
    return best;
  }
  *low = fmax(*low, val);
  return top;
}

/* Distinct knots of one direction of both surfaces in [lo, hi] (ends included), sorted. */
static size_t merged(const double *U1, size_t n1, const double *U2, size_t n2, double lo,
                     double hi, double *x) {
  size_t i, m = 0;
  x[m++] = lo;
  x[m++] = hi;
  for (i = 0; i < n1; i++)
    if (U1[i] > lo && U1[i] < hi) x[m++] = U1[i];
  for (i = 0; i < n2; i++)
    if (U2[i] > lo && U2[i] < hi) x[m++] = U2[i];
  return sorted_unique(x, m);
}

bsfit_err bsfit__surface_diff_bound(const bsfit_surface *A, const bsfit_surface *B, double thr,
                                    const bsfit__breaks *bu, double *max_u,
                                    const bsfit__breaks *bv, double *max_v,
                                    const bsfit_allocator *al, bsfit__bound *out,
                                    bsfit_status *st) {
  size_t ku = A->nu + B->nu + (size_t)(A->degree_u + B->degree_u) + 4;
  size_t kv = A->nv + B->nv + (size_t)(A->degree_v + B->degree_v) + 4, nxu, nxv, i, j;
  size_t bytes = bsfit__mulsize(ku + kv, sizeof(double));
  int mu = A->degree_u > B->degree_u ? A->degree_u : B->degree_u;
  int mv = A->degree_v > B->degree_v ? A->degree_v : B->degree_v;
  double ua, ub, va, vb, *xu, *xv;
  bsfit__bern zu, zv;
  sbound w;
  if (bsfit__bern_init(mu, &zu) != BSFIT_OK || bsfit__bern_init(mv, &zv) != BSFIT_OK)
    return bsfit__fail(st, BSFIT_EDEGREE, "no distance bound for degrees %d x %d (at most %d)",
                       mu, mv, BSFIT__BERN_MAX);
  if (A->periodic_u != B->periodic_u)
    return bsfit__fail(st, BSFIT_EINVAL, "one surface is closed around u, the other not");
  xu = bsfit__alloc(al, bytes);
  if (xu == NULL) return bsfit__fail(st, BSFIT_ENOMEM, "out of memory for a distance bound");
  xv = xu + ku;
  bsfit_surface_domain(A, &ua, &ub, &va, &vb);
  nxu = merged(A->knots_u, A->nu + (size_t)A->degree_u + 1, B->knots_u,
               B->nu + (size_t)B->degree_u + 1, ua, ub, xu);
  nxv = merged(A->knots_v, A->nv + (size_t)A->degree_v + 1, B->knots_v,
               B->nv + (size_t)B->degree_v + 1, va, vb, xv);
  w.zu = &zu;
  w.zv = &zv;
  w.A = A;
  w.B = B;
  w.thr = thr;
  out->bound = out->low = 0.0;
  if (max_u != NULL) memset(max_u, 0, (bu->n - 1) * sizeof(double));
  if (max_v != NULL) memset(max_v, 0, (bv->n - 1) * sizeof(double));
  for (i = 0; i + 1 < nxu; i++) {
    size_t su = max_u != NULL ? bsfit__break_span(bu, 0.5 * (xu[i] + xu[i + 1])) : 0;
    if (bsfit__interrupted(al)) {
      bsfit__free(al, xu, bytes);
      return bsfit__fail(st, BSFIT_EINTR, "distance bound interrupted");
    }
    for (j = 0; j + 1 < nxv; j++) {
      double bd = patch_bound(&w, xu + i, xv + j, 0, &out->low);
      out->bound = fmax(out->bound, bd);
      if (max_u != NULL) max_u[su] = fmax(max_u[su], bd);
      if (max_v != NULL) {
        size_t sv = bsfit__break_span(bv, 0.5 * (xv[j] + xv[j + 1]));
        max_v[sv] = fmax(max_v[sv], bd);
      }
    }
  }
  bsfit__free(al, xu, bytes);
  return BSFIT_OK;
}

/* }==================================================================== */
