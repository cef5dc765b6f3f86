/*
** fit.c
** The fitter: settings, a workspace reused across fits, the span-by-span assembly of the
** banded normal equations N^T W N P = N^T W Q (docs/method.md §5), the open solve with exact end
** constraints, the diagnostics pass, global interpolation and the paper's wrap closing.
** The periodic solve lives in periodic.c, every LAPACK call in linalg.c.
*/
#include "fit_internal.h"

#include <math.h>
#include <string.h>

void bsfit_fit_opts_init(bsfit_fit_opts *o) {
  memset(o, 0, sizeof *o);
  o->degree = 3;
  o->rule = BSFIT_KNOTS_AVERAGING;
}

/* {======================================================================
** Configuration and workspace
** ======================================================================= */

/* Sizes of the workspace block, in doubles / ints / bytes, for a configured fitter. */
static size_t block_bytes(const bsfit_fitter *f, size_t off[13]) {
  size_t p = (size_t)f->p, n = f->nraw, N = f->count, np = f->periodic ? N - p : 0;
  size_t counts[12], i, total = 0;
  counts[0] = f->nk;                             /* U */
  counts[1] = f->periodic ? N + 1 : 0;           /* period */
  counts[2] = bsfit__fit_poly_stride(f->p) ? 0 : (n - p) * f->tri; /* inv (degrees > 3) */
  counts[3] = (p + 1) * n;                       /* band */
  counts[4] = 4 * n;                             /* rhs */
  counts[5] = 3 * n;                             /* work */
  counts[6] = (p + 1) * np;                      /* a11 */
  counts[7] = np * p;                            /* a12 */
  counts[8] = f->periodic ? np * p : 0;          /* y */
  counts[9] = f->periodic ? p * p : 0;           /* s22 */
  counts[10] = f->periodic ? 4 * N : 0;          /* r2 */
  counts[11] = (n - p) * bsfit__fit_poly_stride(f->p); /* poly */
  for (i = 0; i < 12; i++) {
    off[i] = total;
    total += counts[i] * sizeof(double);
  }
  off[12] = total; /* iwork, then occ */
  return total + n * sizeof(int) + n;
}

static void carve(bsfit_fitter *f, const size_t off[13]) {
  char *b = f->block;
  f->U = (double *)(void *)(b + off[0]);
  f->period = (double *)(void *)(b + off[1]);
  f->inv = (double *)(void *)(b + off[2]);
  f->band = (double *)(void *)(b + off[3]);
  f->rhs = (double *)(void *)(b + off[4]);
  f->work = (double *)(void *)(b + off[5]);
  f->a11 = (double *)(void *)(b + off[6]);
  f->a12 = (double *)(void *)(b + off[7]);
  f->y = (double *)(void *)(b + off[8]);
  f->s22 = (double *)(void *)(b + off[9]);
  f->r2 = (double *)(void *)(b + off[10]);
  f->poly = (double *)(void *)(b + off[11]);
  f->iwork = (int *)(void *)(b + off[12]);
  f->occ = (unsigned char *)(b + off[12] + f->nraw * sizeof(int));
}

static bsfit_err check_opts(const bsfit_fit_opts *o, bsfit_status *st) {
  size_t need, td;
  if (o == NULL) return bsfit__fail(st, BSFIT_EINVAL, "fit options are NULL");
  if (o->degree < 1 || o->degree > BSFIT_MAX_DEGREE)
    return bsfit__fail(st, BSFIT_EDEGREE, "degree %d out of range 1..%d", o->degree,
                       BSFIT_MAX_DEGREE);
  if (o->count < (size_t)o->degree + 1 || o->count < 2)
    return bsfit__fail(st, BSFIT_EDEGREE, "degree %d needs more than %zu control points",
                       o->degree, o->count);
  if (o->count > ((size_t)1 << 28))
    return bsfit__fail(st, BSFIT_EINVAL, "control point count %zu is too large", o->count);
  if (o->knots == NULL && bsfit_knots_place_count(o->rule, o->degree, o->count) == 0)
    return bsfit__fail(st, BSFIT_EINVAL, "unknown knot rule %d", (int)o->rule);
  if (o->solver != BSFIT_SOLVER_CHOLESKY && o->solver != BSFIT_SOLVER_QR &&
      o->solver != BSFIT_SOLVER_AUTO)
    return bsfit__fail(st, BSFIT_EINVAL, "unknown solver %d", (int)o->solver);
  if (o->periodic && (o->fix_ends || o->tangent_start || o->tangent_end))
    return bsfit__fail(st, BSFIT_EINVAL, "fixed ends and end tangents need an open fit");
  if ((o->tangent_start || o->tangent_end) && (o->tangent_dim < 1 || o->tangent_dim > 4))
    return bsfit__fail(st, BSFIT_EINVAL, "tangent_dim %d out of range 1..4", o->tangent_dim);
  if (o->tangent_start && !bsfit__all_finite(o->tangent_start, (size_t)o->tangent_dim))
    return bsfit__fail(st, BSFIT_ENONFINITE, "tangent_start is not finite");
  if (o->tangent_end && !bsfit__all_finite(o->tangent_end, (size_t)o->tangent_dim))
    return bsfit__fail(st, BSFIT_ENONFINITE, "tangent_end is not finite");
  td = (size_t)o->tangent_dim;
  if ((o->tangent_start && bsfit__first_out_of_range(o->tangent_start, td) < td) ||
      (o->tangent_end && bsfit__first_out_of_range(o->tangent_end, td) < td))
    return bsfit__fail(st, BSFIT_ERANGE, "an end tangent has a coordinate beyond 1e100");
  need = (size_t)(o->tangent_start ? 2 : o->fix_ends ? 1 : 0) +
         (size_t)(o->tangent_end ? 2 : o->fix_ends ? 1 : 0);
  if (need > o->count)
    return bsfit__fail(st, BSFIT_EINVAL, "the end constraints need %zu control points, count is %zu",
                       need, o->count);
  return BSFIT_OK;
}

/* Copies the user's fixed knots into f (sizes already set) and checks them. */
static bsfit_err load_knots(bsfit_fitter *f, const bsfit_fit_opts *o, bsfit_status *st) {
  size_t p = (size_t)f->p, n = f->nraw;
  bsfit_err e;
  if (f->periodic) {
    if (o->nknots != f->count + 1)
      return bsfit__fail(st, BSFIT_ENKNOTS, "a periodic fit with %zu control points needs %zu "
                         "knots (one period), got %zu", f->count, f->count + 1, o->nknots);
    memcpy(f->period, o->knots, (f->count + 1) * sizeof(double));
    e = bsfit_knots_periodic(f->p, f->count, f->period, f->U, st);
  } else {
    if (o->nknots != f->nk)
      return bsfit__fail(st, BSFIT_ENKNOTS, "%zu control points of degree %d need %zu knots, got %zu",
                         n, f->p, f->nk, o->nknots);
    memcpy(f->U, o->knots, f->nk * sizeof(double));
    e = bsfit_knots_validate(f->U, f->nk, f->p, n, st);
  }
  if (e != BSFIT_OK) return e;
  if ((f->fix_ends || f->has_t0 || f->has_t1) && (f->U[0] != f->U[p] || f->U[n] != f->U[n + p]))
    return bsfit__fail(st, BSFIT_EINVAL, "fixed ends and end tangents need clamped knots");
  bsfit__fit_prepare_spans(f);
  return BSFIT_OK;
}

static void apply_settings(bsfit_fitter *f, const bsfit_fit_opts *o) {
  int k;
  f->p = o->degree;
  f->periodic = o->periodic != 0;
  f->count = o->count;
  f->rule = o->rule;
  if (f->periodic && !bsfit_knot_rule_closed(f->rule)) f->rule = BSFIT_KNOTS_PERIODIC_AVERAGING;
  if (!f->periodic && bsfit_knot_rule_closed(f->rule)) f->rule = BSFIT_KNOTS_AVERAGING;
  f->user_knots = o->knots != NULL;
  f->solver = o->solver;
  f->fix_ends = o->fix_ends != 0;
  f->has_t0 = o->tangent_start != NULL;
  f->has_t1 = o->tangent_end != NULL;
  f->tangent_dim = f->has_t0 || f->has_t1 ? o->tangent_dim : 0;
  for (k = 0; k < f->tangent_dim; k++) {
    f->t0[k] = f->has_t0 ? o->tangent_start[k] : 0.0;
    f->t1[k] = f->has_t1 ? o->tangent_end[k] : 0.0;
  }
  f->nraw = f->count + (f->periodic ? (size_t)f->p : 0);
  f->nk = f->nraw + (size_t)f->p + 1;
  f->tri = (size_t)f->p * (size_t)(f->p + 1) / 2;
  f->fitted = 0;
}

bsfit_err bsfit_fitter_configure(bsfit_fitter *f, const bsfit_fit_opts *o, bsfit_status *st) {
  bsfit_fitter next;
  size_t off[13];
  bsfit_err e;
  if (f == NULL) return bsfit__fail(st, BSFIT_EINVAL, "fitter is NULL");
  e = check_opts(o, st);
  if (e != BSFIT_OK) return e;
  /* build the new configuration aside, so a failure leaves f as it was */
  memset(&next, 0, sizeof next);
  next.alloc = f->alloc;
  next.order = f->order; /* the QR's index array depends on m only: kept */
  next.order_cap = f->order_cap;
  apply_settings(&next, o);
  next.block_size = block_bytes(&next, off);
  next.block = bsfit__alloc(&next.alloc, next.block_size);
  if (next.block == NULL)
    return bsfit__fail(st, BSFIT_ENOMEM, "out of memory for a fitter of %zu control points",
                       next.count);
  carve(&next, off);
  if (next.user_knots) {
    e = load_knots(&next, o, st);
    if (e != BSFIT_OK) {
      bsfit__free(&next.alloc, next.block, next.block_size);
      return e;
    }
  }
  bsfit__free(&f->alloc, f->block, f->block_size);
  *f = next;
  return bsfit__ok(st);
}

bsfit_err bsfit_fitter_new(bsfit_fitter **f, const bsfit_fit_opts *o, const bsfit_allocator *a,
                           bsfit_status *st) {
  bsfit_fitter *g;
  bsfit_allocator al = {NULL, NULL, NULL};
  bsfit_err e;
  if (f == NULL) return bsfit__fail(st, BSFIT_EINVAL, "fitter output is NULL");
  *f = NULL;
  if (a != NULL) al = *a;
  e = check_opts(o, st);
  if (e != BSFIT_OK) return e;
  g = bsfit__alloc(&al, sizeof *g);
  if (g == NULL) return bsfit__fail(st, BSFIT_ENOMEM, "out of memory for a fitter");
  memset(g, 0, sizeof *g);
  g->alloc = al;
  e = bsfit_fitter_configure(g, o, st);
  if (e != BSFIT_OK) {
    bsfit__free(&al, g, sizeof *g);
    return e;
  }
  *f = g;
  return BSFIT_OK;
}

void bsfit_fitter_free(bsfit_fitter *f) {
  bsfit_allocator al;
  if (f == NULL) return;
  al = f->alloc;
  bsfit__free(&al, f->order, f->order_cap * sizeof(size_t));
  bsfit__free(&al, f->block, f->block_size);
  bsfit__free(&al, f, sizeof *f);
}

const double *bsfit_fitter_knots(const bsfit_fitter *f, size_t *nknots) {
  if (f == NULL || !(f->fitted || f->user_knots)) return NULL;
  if (nknots) *nknots = f->nk;
  return f->U;
}

/* }====================================================================== */

/* {======================================================================
** The open solve, with end constraints by elimination
** ======================================================================= */

double bsfit__band_norm1(const double *ab, size_t ldab, int kd, size_t lo, size_t hi,
                         double *colsum) {
  size_t c, r;
  double mx = 0.0;
  for (c = lo; c <= hi; c++) colsum[c - lo] = 0.0;
  for (c = lo; c <= hi; c++) { /* column c below the diagonal is row c right of it */
    const double *col = ab + c * ldab;
    size_t rmax = hi - c < (size_t)kd ? hi - c : (size_t)kd;
    double s = fabs(col[0]);
    for (r = 1; r <= rmax; r++) {
      double v = fabs(col[r]);
      s += v;
      colsum[c + r - lo] += v;
    }
    colsum[c - lo] += s;
    if (colsum[c - lo] > mx) mx = colsum[c - lo]; /* complete: nothing left to add to it */
  }
  return mx;
}

void bsfit__fit_fixed(const bsfit_fitter *f, const double *pts, size_t m, int dim,
                      bsfit__fixed_set *fx) {
  size_t n = f->nraw, p = (size_t)f->p, c;
  const double *U = f->U, *Q0 = pts, *Q1 = pts + (m - 1) * (size_t)dim;
  fx->count = 0;
  fx->lo = 0;
  fx->hi = n; /* one past */
  if (f->fix_ends || f->has_t0) {
    fx->idx[fx->count] = 0;
    for (c = 0; c < (size_t)dim; c++) fx->val[fx->count][c] = Q0[c];
    fx->count++;
    fx->lo = 1;
  }
  if (f->has_t0) { /* C'(a) = p / (U[p+1] - U[1]) (P_1 - P_0) */
    double h = (U[p + 1] - U[1]) / (double)p;
    fx->idx[fx->count] = 1;
    for (c = 0; c < (size_t)dim; c++) fx->val[fx->count][c] = Q0[c] + h * f->t0[c];
    fx->count++;
    fx->lo = 2;
  }
  if (f->fix_ends || f->has_t1) {
    fx->idx[fx->count] = n - 1;
    for (c = 0; c < (size_t)dim; c++) fx->val[fx->count][c] = Q1[c];
    fx->count++;
    fx->hi = n - 1;
  }
  if (f->has_t1) { /* C'(b) = p / (U[n+p] - U[n-1]) (P_{n-1} - P_{n-2}) */
    double h = (U[n + p] - U[n - 1]) / (double)p;
    fx->idx[fx->count] = n - 2;
    for (c = 0; c < (size_t)dim; c++) fx->val[fx->count][c] = Q1[c] - h * f->t1[c];
    fx->count++;
    fx->hi = n - 2;
  }
}

/* Moves the fixed unknowns' columns to the right-hand side: R_i -= A_ij P_j. */
static void eliminate_fixed(bsfit_fitter *f, int dim, const bsfit__fixed_set *fx) {
  size_t t, i, n = f->nraw, p = (size_t)f->p, ldab = p + 1, c;
  for (t = 0; t < fx->count; t++) {
    size_t j = fx->idx[t];
    for (i = fx->lo; i < fx->hi; i++) {
      size_t hi = i > j ? i : j, lo = i > j ? j : i;
      double a;
      if (hi - lo > p) continue;
      a = f->band[(hi - lo) + lo * ldab];
      for (c = 0; c < (size_t)dim; c++) f->rhs[c * n + i] -= a * fx->val[t][c];
    }
  }
}

static bsfit_err empty_span_error(const bsfit_fitter *f, bsfit_err e, bsfit_status *st,
                                  size_t *count, size_t *first) {
  size_t s, p = (size_t)f->p, found = 0, first_s = 0;
  for (s = p; s < f->nraw; s++)
    if (f->U[s + 1] > f->U[s] && !f->occ[s - p] && found++ == 0) first_s = s;
  if (count) *count = found;
  if (first) *first = first_s;
  if (e != BSFIT_OK && found > 0)
    return bsfit__fail(st, BSFIT_EEMPTYSPAN,
                       "knot span %zu [%g, %g) holds no data (%zu empty): normal matrix singular",
                       first_s, f->U[first_s], f->U[first_s + 1], found);
  return e;
}

static bsfit_err open_solve(bsfit_fitter *f, const double *pts, size_t m, int dim,
                            double *ctrl, double *rcond, bsfit_status *st) {
  size_t p = (size_t)f->p, n = f->nraw, ldab = p + 1, t, i, c, nf;
  bsfit__fixed_set fx;
  bsfit_err e = BSFIT_OK;
  int kd;
  bsfit__fit_fixed(f, pts, m, dim, &fx);
  nf = fx.hi > fx.lo ? fx.hi - fx.lo : 0;
  if (rcond) *rcond = 1.0;
  if (nf > 0) {
    double *ab = f->band + fx.lo * ldab, anorm = 0.0;
    kd = (int)(nf - 1 < p ? nf - 1 : p);
    eliminate_fixed(f, dim, &fx);
    if (rcond) anorm = bsfit__band_norm1(f->band, ldab, kd, fx.lo, fx.hi - 1, f->work);
    e = bsfit__pb_factor(nf, kd, ab, ldab, st);
    if (e == BSFIT_OK) e = bsfit__pb_solve(nf, kd, ab, ldab, (size_t)dim, f->rhs + fx.lo, n, st);
    if (e != BSFIT_OK) return empty_span_error(f, e, st, NULL, NULL);
    if (rcond) *rcond = bsfit__pb_rcond_tn(nf, kd, ab, ldab, anorm, f->work);
  }
  for (i = fx.lo; i < fx.hi; i++)
    for (c = 0; c < (size_t)dim; c++) ctrl[i * (size_t)dim + c] = f->rhs[c * n + i];
  for (t = 0; t < fx.count; t++)
    for (c = 0; c < (size_t)dim; c++) ctrl[fx.idx[t] * (size_t)dim + c] = fx.val[t][c];
  return BSFIT_OK;
}

/* }====================================================================== */

/* {======================================================================
** The fit
** ======================================================================= */

/* The first point with a coordinate beyond BSFIT_COORD_MAX, named; BSFIT_OK if none.
** Only called once a fit has shown the sign of one (the scan costs a pass over the data,
** a quarter of a Cholesky fit's time). */
static bsfit_err range_error(const double *pts, size_t m, int dim, bsfit_status *st) {
  size_t d = (size_t)dim, k = bsfit__first_out_of_range(pts, m * d);
  if (k == m * d) return BSFIT_OK;
  return bsfit__fail(st, BSFIT_ERANGE, "point %zu has a coordinate %g beyond 1e100", k / d,
                     pts[k]);
}

static bsfit_err check_fit_args(const bsfit_fitter *f, const double *pts, size_t m, int dim,
                                const double *u, const bsfit_curve *out, bsfit_status *st) {
  if (f == NULL || pts == NULL || u == NULL || out == NULL)
    return bsfit__fail(st, BSFIT_EINVAL, "fitter, points, parameters or output curve is NULL");
  if (dim < 1 || dim > 4) return bsfit__fail(st, BSFIT_EDIM, "dimension %d out of range 1..4", dim);
  if (f->tangent_dim && dim != f->tangent_dim)
    return bsfit__fail(st, BSFIT_EDIM, "points have dimension %d, the end tangents %d", dim,
                       f->tangent_dim);
  if (m < f->count)
    return bsfit__fail(st, BSFIT_ETOOFEW, "%zu points are fewer than %zu control points", m,
                       f->count);
  return BSFIT_OK;
}

/* Knots of this fit from the rule (fixed knots were loaded at configuration). */
/* Knots of this fit from the rule (fixed knots were loaded at configuration). The
** per-span data is recomputed only when the knots moved: refits on the same parameters
** (reweighting, several data sets) skip it. */
static bsfit_err place_fit_knots(bsfit_fitter *f, const double *u, size_t m, bsfit_status *st) {
  bsfit_err e;
  double *dst = f->periodic ? f->period : f->U;
  size_t nplaced = f->periodic ? f->count + 1 : f->nk;
  if (f->user_knots) return BSFIT_OK;
  if (f->fitted) memcpy(f->work, dst, nplaced * sizeof(double)); /* work holds >= nk */
  e = bsfit__knots_place_rule(f->rule, u, m, f->p, f->count, dst, st);
  if (e != BSFIT_OK) {
    f->fitted = 0;
    return e;
  }
  if (f->fitted && memcmp(f->work, dst, nplaced * sizeof(double)) == 0) return BSFIT_OK;
  if (f->periodic) {
    e = bsfit_knots_periodic(f->p, f->count, f->period, f->U, st);
    if (e != BSFIT_OK) {
      f->fitted = 0;
      return e;
    }
  }
  bsfit__fit_prepare_spans(f);
  f->fitted = 1;
  return BSFIT_OK;
}

/* The first bad input, found by a precise scan once the assembly sums flagged one. */
static bsfit_err input_error(const double *pts, size_t m, int dim, const double *u,
                             const double *w, bsfit_status *st) {
  size_t k, c;
  for (k = 0; k < m; k++) {
    for (c = 0; c < (size_t)dim; c++)
      if (!isfinite(pts[k * (size_t)dim + c]))
        return bsfit__fail(st, BSFIT_ENONFINITE, "point %zu has a NaN or Inf coordinate", k);
    if (!isfinite(u[k]))
      return bsfit__fail(st, BSFIT_ENONFINITE, "parameter %zu is not finite", k);
    /* subnormal weights (below DBL_MIN) are refused too: the sums would keep only a few
    ** of their digits, and the fit would come back wrong without a word */
    if (w && !(isfinite(w[k]) && w[k] >= DBL_MIN))
      return bsfit__fail(st, BSFIT_EWEIGHT, "weight %zu is %g (must be finite and at least "
                         "DBL_MIN = 2.2e-308)", k, w[k]);
  }
  return bsfit__fail(st, BSFIT_ENONFINITE, "the normal equations overflow");
}

static bsfit_err prepare_out(const bsfit_fitter *f, int dim, bsfit_curve *out, bsfit_status *st) {
  if (out->ctrl && out->knots && !out->weights && !out->bezier && out->n == f->nraw &&
      out->degree == f->p && out->dim == dim && out->alloc.fn == f->alloc.fn &&
      out->alloc.ud == f->alloc.ud)
    return BSFIT_OK; /* same shape: reuse the arrays, no allocation */
  return bsfit_curve_alloc(out, f->p, dim, f->nraw, 0, &f->alloc, st);
}

/* Do all points coincide? Scans only until the first point differing from Q_0. */
static int all_coincide(const double *pts, size_t m, int dim) {
  size_t k, c, d = (size_t)dim;
  for (k = 1; k < m; k++)
    for (c = 0; c < d; c++)
      if (pts[k * d + c] != pts[c]) return 0;
  return 1;
}

/* Assembly and its checks: the sums are finite iff every input was (NaN and Inf
** propagate into them), so one O(n) scan replaces a per-point test. */
static bsfit_err assemble_checked(bsfit_fitter *f, const double *pts, size_t m, int dim,
                                  const double *u, const double *w, bsfit_status *st) {
  int badw = bsfit__fit_assemble(f, pts, m, dim, u, w);
  if (badw < 0) return bsfit__fail(st, BSFIT_EINTR, "fit of %zu points interrupted", m);
  if (badw || !bsfit__all_finite(f->band, (size_t)(f->p + 1) * f->nraw) ||
      !bsfit__all_finite(f->rhs, (size_t)dim * f->nraw))
    return input_error(pts, m, dim, u, w, st);
  if (all_coincide(pts, m, dim))
    return bsfit__fail(st, BSFIT_EDEGENERATE, "all %zu points coincide", m);
  return BSFIT_OK;
}

/* The control points must be finite and, so that the curve is valid, within
** BSFIT_COORD_MAX: beyond it the data were (points beyond 1e100 are named). */
static bsfit_err solution_finite(const bsfit_fitter *f, const double *pts, size_t m, int dim,
                                 const bsfit_curve *out, bsfit_status *st) {
  size_t nc = f->nraw * (size_t)dim, k = bsfit__first_out_of_range(out->ctrl, nc);
  if (k < nc && bsfit__all_finite(out->ctrl, nc)) {
    if (range_error(pts, m, dim, st) != BSFIT_OK) return BSFIT_ERANGE;
    return bsfit__fail(st, BSFIT_ERANGE, "control point %zu of the fit is %g, beyond 1e100",
                       k / (size_t)dim, out->ctrl[k]);
  }
  if (k == nc) return BSFIT_OK;
  return bsfit__fail(st, BSFIT_ESINGULAR, "the solution is not finite: the normal matrix is "
                     "numerically singular");
}

/* The periodic solvers write the N distinct control points; the expanded form repeats p. */
static void wrap_ctrl(const bsfit_fitter *f, int dim, bsfit_curve *out) {
  size_t p = (size_t)f->p, d = (size_t)dim;
  if (f->periodic) memcpy(out->ctrl + f->count * d, out->ctrl, p * d * sizeof(double));
}

/* Normal equations, banded Cholesky. */
static bsfit_err fit_cholesky(bsfit_fitter *f, const double *pts, size_t m, int dim,
                              const double *u, const double *w, bsfit_curve *out, double *rc,
                              bsfit_status *st) {
  bsfit_err e = assemble_checked(f, pts, m, dim, u, w, st);
  if (e == BSFIT_OK) e = prepare_out(f, dim, out, st);
  if (e != BSFIT_OK) return e;
  e = f->periodic ? bsfit__periodic_solve(f, dim, out->ctrl, rc, st)
                  : open_solve(f, pts, m, dim, out->ctrl, rc, st);
  if (e != BSFIT_OK) return empty_span_error(f, e, st, NULL, NULL);
  wrap_ctrl(f, dim, out);
  return solution_finite(f, pts, m, dim, out, st);
}

/* QR of the weighted rows (fit_qr.c): no normal matrix. */
static bsfit_err fit_qr(bsfit_fitter *f, const double *pts, size_t m, int dim, const double *u,
                        const double *w, bsfit_curve *out, double *rc, bsfit_status *st) {
  bsfit__fixed_set fx;
  int badw;
  bsfit_err e;
  /* every point and parameter, as the Cholesky path's sums check them: rows that reach
  ** no free unknown (fixed ends, no free control point) leave no trace in R */
  if (!bsfit__all_finite(pts, m * (size_t)dim) || !bsfit__all_finite(u, m))
    return input_error(pts, m, dim, u, w, st);
  bsfit__fit_fixed(f, pts, m, dim, &fx); /* periodic fits have no constraints: lo..hi all */
  e = bsfit__qr_factor(f, pts, m, dim, u, w, &fx, &badw, st);
  if (e != BSFIT_OK) return e;
  if (badw || !bsfit__qr_finite(f, dim)) return input_error(pts, m, dim, u, w, st);
  if (all_coincide(pts, m, dim))
    return bsfit__fail(st, BSFIT_EDEGENERATE, "all %zu points coincide", m);
  e = prepare_out(f, dim, out, st);
  if (e == BSFIT_OK) e = bsfit__qr_solve(f, dim, &fx, out->ctrl, rc, st);
  if (e != BSFIT_OK) return empty_span_error(f, e, st, NULL, NULL);
  wrap_ctrl(f, dim, out);
  return solution_finite(f, pts, m, dim, out, st);
}

/* BSFIT_SOLVER_AUTO: does the Cholesky result call for QR? */
static int needs_qr(bsfit_err e, double rcond) {
  return e == BSFIT_ENOTSPD || e == BSFIT_ESINGULAR ||
         (e == BSFIT_OK && rcond < BSFIT_SOLVER_AUTO_RCOND);
}

static bsfit_err fit_body(bsfit_fitter *f, const double *pts, size_t m, int dim, const double *u,
                          const double *w, bsfit_curve *out, bsfit_fit_report *rep,
                          double *res, bsfit_status *st) {
  double rms, max, rcond = 1.0;
  double *rc = rep || f->solver == BSFIT_SOLVER_AUTO ? &rcond : NULL;
  bsfit_solver used = f->solver == BSFIT_SOLVER_QR ? BSFIT_SOLVER_QR : BSFIT_SOLVER_CHOLESKY;
  size_t imax;
  bsfit_err e = place_fit_knots(f, u, m, st);
  if (e != BSFIT_OK) return e;
  if (used == BSFIT_SOLVER_CHOLESKY) e = fit_cholesky(f, pts, m, dim, u, w, out, rc, st);
  if (f->solver == BSFIT_SOLVER_AUTO && needs_qr(e, rcond)) used = BSFIT_SOLVER_QR;
  if (used == BSFIT_SOLVER_QR) e = fit_qr(f, pts, m, dim, u, w, out, rc, st);
  if (e != BSFIT_OK) return e;
  memcpy(out->knots, f->U, f->nk * sizeof(double));
  out->periodic = f->periodic;
  /* OK means a valid curve: knots placed on clustered parameters can repeat beyond what
  ** the degree allows (a closed degree-1 fit, found by the fuzzer) */
  e = bsfit_curve_validate(out, st);
  if (e != BSFIT_OK) return e;
  if (rep) {
    rep->rcond = rcond;
    rep->solver = used;
  }
  if (rep == NULL && res == NULL) return bsfit__ok(st); /* nobody reads the residuals */
  if (bsfit__fit_residuals(f, out->ctrl, pts, m, dim, u, w, res, &rms, &max, &imax) != 0)
    return bsfit__fail(st, BSFIT_EINTR, "fit of %zu points interrupted", m);
  if (!isfinite(rms) || !isfinite(max)) { /* squares of coordinates beyond ~1e154 */
    if (range_error(pts, m, dim, st) == BSFIT_OK)
      (void)bsfit__fail(st, BSFIT_ERANGE, "the residuals overflow");
    return BSFIT_ERANGE;
  }
  if (rep) {
    rep->rms = rms;
    rep->max = max;
    rep->max_index = imax;
    rep->m = m;
    rep->first_empty_span = 0;
    (void)empty_span_error(f, BSFIT_OK, NULL, &rep->n_empty_spans, &rep->first_empty_span);
  }
  return bsfit__ok(st);
}

bsfit_err bsfit_fitter_fit(bsfit_fitter *f, const double *pts, size_t m, int dim, const double *u,
                           const double *w, bsfit_curve *out, bsfit_fit_report *rep,
                           double *residuals_out, bsfit_status *st) {
  bsfit_err e = check_fit_args(f, pts, m, dim, u, out, st);
  if (e == BSFIT_OK) e = fit_body(f, pts, m, dim, u, w, out, rep, residuals_out, st);
  if (e != BSFIT_OK && out != NULL) bsfit_curve_free(out);
  return e;
}

/* }====================================================================== */

/* {======================================================================
** Interpolation and wrap closing
** ======================================================================= */

static bsfit_err check_interp(const double *pts, size_t m, int dim, const double *u, int p,
                              int periodic, const bsfit_curve *out, bsfit_status *st) {
  size_t k;
  if (pts == NULL || u == NULL || out == NULL)
    return bsfit__fail(st, BSFIT_EINVAL, "points, parameters or output curve is NULL");
  if (dim < 1 || dim > 4) return bsfit__fail(st, BSFIT_EDIM, "dimension %d out of range 1..4", dim);
  if (p < 1 || p > BSFIT_MAX_DEGREE || m < (size_t)p + 1 || m < 2)
    return bsfit__fail(st, BSFIT_EDEGREE, "degree %d cannot interpolate %zu points", p, m);
  if (!bsfit__all_finite(pts, m * (size_t)dim) || !bsfit__all_finite(u, m))
    return bsfit__fail(st, BSFIT_ENONFINITE, "points or parameters contain NaN or Inf");
  for (k = 1; k < m; k++)
    if (!(u[k] > u[k - 1]))
      return bsfit__fail(st, BSFIT_EINVAL, "interpolation parameters must increase strictly "
                         "(index %zu)", k);
  if (periodic && !(u[m - 1] < u[0] + 1.0))
    return bsfit__fail(st, BSFIT_EINVAL, "closed parameters must lie in one period [u0, u0+1)");
  return BSFIT_OK;
}

/* NURBS Book eq. 9.8: interior knots average p consecutive parameters */
static void interp_knots(const double *u, size_t m, int p, double *U) {
  size_t j, i, P = (size_t)p;
  for (j = 0; j <= P; j++) {
    U[j] = u[0];
    U[m + j] = u[m - 1];
  }
  for (j = 1; j + P < m; j++) {
    double s = 0.0;
    for (i = j; i < j + P; i++) s += u[i];
    U[j + P] = s / (double)p;
  }
}

static bsfit_err interp_open(const double *pts, size_t m, int dim, const double *u, int p,
                             bsfit_curve *out, const bsfit_allocator *a, bsfit_status *st) {
  size_t k, j, c, kl = 0, ku = 0, ldab, bytes, P = (size_t)p;
  double N[BSFIT_MAX_DEGREE + 1], *ab, *b;
  void *blk;
  bsfit_err e = bsfit_curve_alloc(out, p, dim, m, 0, a, st);
  if (e != BSFIT_OK) return e;
  interp_knots(u, m, p, out->knots);
  for (k = 0; k < m; k++) { /* band widths from the actual spans */
    size_t s = bsfit_knots_find_span(out->knots, m, p, u[k]);
    if (k + P > s && k + P - s > kl) kl = k + P - s;
    if (s > k && s - k > ku) ku = s - k;
  }
  ldab = 2 * kl + ku + 1;
  bytes = (ldab * m + m * (size_t)dim) * sizeof(double) + m * sizeof(int);
  blk = bsfit__alloc(a, bytes);
  if (blk == NULL) return bsfit__fail(st, BSFIT_ENOMEM, "out of memory interpolating %zu points", m);
  ab = blk;
  b = ab + ldab * m;
  memset(ab, 0, ldab * m * sizeof(double));
  for (k = 0; k < m; k++) {
    size_t s = bsfit_knots_find_span(out->knots, m, p, u[k]);
    bsfit_basis_funs(s, u[k], p, out->knots, N);
    for (j = 0; j <= P; j++) ab[kl + ku + k - (s - P + j) + (s - P + j) * ldab] = N[j];
    for (c = 0; c < (size_t)dim; c++) b[c * m + k] = pts[k * (size_t)dim + c];
  }
  e = bsfit__gb_solve(m, (int)kl, (int)ku, ab, ldab, (int *)(void *)(b + m * (size_t)dim),
                      (size_t)dim, b, m, st);
  if (e == BSFIT_OK)
    for (k = 0; k < m; k++)
      for (c = 0; c < (size_t)dim; c++) out->ctrl[k * (size_t)dim + c] = b[c * m + k];
  bsfit__free(a, blk, bytes);
  if (e == BSFIT_OK && !bsfit__all_finite(out->ctrl, m * (size_t)dim))
    e = bsfit__fail(st, BSFIT_ESINGULAR, "interpolation is numerically singular");
  return e;
}

static bsfit_err interp_periodic(const double *pts, size_t m, int dim, const double *u, int p,
                                 bsfit_curve *out, const bsfit_allocator *a, bsfit_status *st) {
  bsfit_fit_opts o;
  bsfit_fitter *f;
  bsfit_curve c;
  bsfit_err e;
  bsfit_fit_opts_init(&o);
  o.degree = p;
  o.count = m;
  o.periodic = 1;
  o.rule = BSFIT_KNOTS_PERIODIC_AVERAGING;
  e = bsfit_fitter_new(&f, &o, a, st);
  if (e != BSFIT_OK) return e;
  bsfit_curve_init(&c);
  e = bsfit_fitter_fit(f, pts, m, dim, u, NULL, &c, NULL, NULL, st);
  bsfit_fitter_free(f);
  if (e == BSFIT_OK) bsfit_curve_move(&c, out);
  return e;
}

bsfit_err bsfit_interpolate(const double *pts, size_t m, int dim, const double *u, int p,
                            int periodic, bsfit_curve *out, const bsfit_allocator *a,
                            bsfit_status *st) {
  bsfit_err e = check_interp(pts, m, dim, u, p, periodic, out, st);
  if (e != BSFIT_OK) {
    if (out) bsfit_curve_free(out);
    return e;
  }
  bsfit_curve_free(out);
  e = periodic ? interp_periodic(pts, m, dim, u, p, out, a, st)
               : interp_open(pts, m, dim, u, p, out, a, st);
  if (e != BSFIT_OK) bsfit_curve_free(out);
  else e = bsfit__ok(st);
  return e;
}

bsfit_err bsfit_curve_wrap_closed(const bsfit_curve *open, const double *u, size_t m,
                                  bsfit_curve *out, const bsfit_allocator *a, bsfit_status *st) {
  size_t N;
  double *period;
  bsfit_err e;
  if (open == NULL || out == NULL || u == NULL || open->ctrl == NULL || open->knots == NULL)
    return bsfit__fail(st, BSFIT_EINVAL, "open curve, parameters or output is NULL or empty");
  if (open->weights || open->periodic || open->bezier || open == out)
    return bsfit__fail(st, BSFIT_EINVAL, "wrap closing needs a polynomial open B-spline, "
                       "distinct from the output");
  N = open->n;
  period = bsfit__alloc(a, (N + 1) * sizeof(double));
  if (period == NULL) return bsfit__fail(st, BSFIT_ENOMEM, "out of memory for %zu knots", N + 1);
  e = bsfit_knots_place(BSFIT_KNOTS_CARVALHO_CLOSED, u, m, open->degree, N, period, st);
  if (e == BSFIT_OK || e == BSFIT_EEMPTYSPAN)
    e = bsfit_curve_new_periodic(out, open->degree, open->dim, N, period, open->ctrl, NULL, a, st);
  bsfit__free(a, period, (N + 1) * sizeof(double));
  return e;
}

/* }====================================================================== */
