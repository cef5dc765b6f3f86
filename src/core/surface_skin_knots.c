/*
** surface_skin_knots.c
** Skinning's common knot vector (The NURBS Book 10.3 needs compatible sections): every
** section elevated to the highest degree, then refined to the union of the period knots.
** Two things make that union clean:
**   - the seam knot is whole: a periodic curve may store copies of its knot at 0 as period
**     knots equal to 1 (the period's end); counted there, the seam's multiplicity was split
**     between two values and the sections never became compatible;
**   - knots of different sections that nearly coincide are merged before refinement, so the
**     common vector holds no sliver spans (which made refinement refuse at corners): C0
**     knots (multiplicity p) are moved onto one value by reparametrising, affinely, each
**     piece between a section's C0 knots (exact: a piece between knots of multiplicity p
**     depends on its own knots only); knots of any multiplicity that are rounding apart are
**     moved onto one value (the curve moves by far less than 1e-9 of its size).
** Sections are on [0, 1) here (surface_skin.c normalises them first).
*/
#include "skin_internal.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

/* {====================================================================
** Seams
** ===================================================================== */

bsfit_err bsfit__skin_rotate(const bsfit_curve *c, double u, bsfit_curve *out,
                             const bsfit_allocator *a, bsfit_status *st) {
  size_t p = (size_t)c->degree, N, i, j, d = (size_t)c->dim;
  double *t, *P;
  bsfit_curve r;
  bsfit_err e;
  bsfit_curve_init(&r);
  e = bsfit_knots_multiplicity(c->knots, c->n + p + 1, u) == 0
          ? bsfit_curve_insert_knot(c, u, 1, &r, st)
          : bsfit_curve_copy(c, &r, a, st);
  if (e != BSFIT_OK) return e;
  N = r.n - p;
  for (j = 0; j < N && r.knots[p + j] != u; j++) continue;
  if (j == N) j = 0; /* u == 0 already, up to the period's end */
  t = bsfit__alloc(a, (N + 1) * sizeof(double));
  P = bsfit__alloc(a, N * d * sizeof(double));
  if (t == NULL || P == NULL) {
    e = bsfit__fail(st, BSFIT_ENOMEM, "out of memory for a section of %zu points", N);
  } else {
    for (i = 0; i < N; i++) {
      size_t s = (i + j) % N;
      /* knots after the period's end come back 1 later; the end is exactly 1 */
      t[i] = i + j < N ? r.knots[p + s] - u : r.knots[p + s] + (1.0 - u);
      memcpy(P + i * d, r.ctrl + s * d, d * sizeof(double));
    }
    t[0] = 0.0;
    t[N] = 1.0;
    e = bsfit_curve_new_periodic(out, c->degree, c->dim, N, t, P, NULL, a, st);
  }
  bsfit__free(a, t, (N + 1) * sizeof(double));
  bsfit__free(a, P, N * d * sizeof(double));
  bsfit_curve_free(&r);
  return e;
}

bsfit_err bsfit__skin_seam_whole(bsfit_curve *c, const bsfit_allocator *a, bsfit_status *st) {
  size_t p = (size_t)c->degree, N = c->n - p;
  bsfit_curve tmp;
  bsfit_err e;
  if (c->knots[p + N - 1] != c->knots[p + N]) return BSFIT_OK;
  bsfit_curve_init(&tmp);
  e = bsfit__skin_rotate(c, c->knots[p + N], &tmp, a, st);
  if (e == BSFIT_OK) bsfit_curve_move(&tmp, c);
  bsfit_curve_free(&tmp);
  return e;
}

/* }==================================================================== */

/* {====================================================================
** Period knots
** ===================================================================== */

static int cmp_double(const void *x, const void *y) {
  double a = *(const double *)x, b = *(const double *)y;
  return (a > b) - (a < b);
}

/* The runs of equal values of the period knots t_0..t_{N-1} of c, one at a time:
** *i is the index of the next run; returns its length (0 at the end). */
static int next_run(const bsfit_curve *c, size_t *i) {
  size_t p = (size_t)c->degree, N = c->n - p, j;
  if (*i >= N) return 0;
  for (j = *i + 1; j < N && c->knots[p + j] == c->knots[p + *i]; j++) continue;
  return (int)(j - *i);
}

/* Index of x in the sorted values v[0..D-1] (the last one <= x). */
static size_t find_value(const double *v, size_t D, double x) {
  size_t lo = 0, hi = D;
  while (hi - lo > 1) {
    size_t mid = lo + (hi - lo) / 2;
    if (v[mid] <= x) lo = mid;
    else hi = mid;
  }
  return lo;
}

/* c with period knots t (N + 1 values, t[N] = 1), the same control points: in place. */
static bsfit_err set_knots(bsfit_curve *c, const double *t, const bsfit_allocator *a,
                           bsfit_status *st) {
  bsfit_curve tmp;
  bsfit_err e;
  bsfit_curve_init(&tmp);
  e = bsfit_curve_new_periodic(&tmp, c->degree, c->dim, c->n - (size_t)c->degree, t, c->ctrl,
                               NULL, a, st);
  if (e == BSFIT_OK) bsfit_curve_move(&tmp, c);
  bsfit_curve_free(&tmp);
  return e;
}

/* }==================================================================== */

/* {====================================================================
** Merging the C0 knots (multiplicity p) of different sections
** ===================================================================== */

#define MERGE_STRETCH 1.5 /* a piece between corners keeps its length within this factor */

/* A C0 knot of one section. anchored: it may not move (the seam; the ends of a section's
** piece across the seam, whose map would move the seam; a knot next to the period's end). */
typedef struct corner {
  double x;
  int anchored;
  size_t section;
} corner;

static int cmp_corner(const void *x, const void *y) {
  return cmp_double(&((const corner *)x)->x, &((const corner *)y)->x);
}

/* The C0 knots of c (section k), in order, into out (when not NULL); returns their count.
** Corners within tol of the period's end are anchored. */
static size_t corners_of(const bsfit_curve *c, size_t k, double tol, corner *out) {
  size_t i = 0, n = 0;
  int m, p = c->degree, seam = 0;
  for (; (m = next_run(c, &i)) > 0; i += (size_t)m) {
    double x = c->knots[(size_t)p + i];
    if (m < p) continue;
    if (x == 0.0) seam = 1;
    if (out != NULL) {
      out[n].x = x;
      out[n].anchored = x == 0.0 || x > 1.0 - tol;
      out[n].section = k;
    }
    n++;
  }
  if (out != NULL && n > 0 && !seam) out[0].anchored = out[n - 1].anchored = 1;
  return n;
}

/* rep[i]: where sorted corner c[i] goes: the first anchored value of its cluster, else the
** cluster's first. A cluster holds values within tol of its first and at most one corner of
** each section (last[k]: the last cluster section k was seen in). */
static void cluster_corners(const corner *c, size_t n, double tol, double *rep, size_t *last) {
  size_t i, j, k, id = 0;
  for (i = 0; i < n; i = j, id++) {
    double r = c[i].x;
    for (j = i; j < n && c[j].x - c[i].x <= tol && last[c[j].section] != id; j++)
      last[c[j].section] = id;
    for (k = i; k < j; k++)
      if (c[k].anchored) {
        r = c[k].x;
        break;
      }
    for (k = i; k < j; k++) rep[k] = r;
  }
}

/* The period knots t (N + 1) of c after its corners X[0..m-1] go to R[0..m-1] (strictly
** increasing; with X[0] = 0 the nodes include 1 -> 1): each piece mapped affinely, the
** knots outside the first and last corner unchanged. */
static void map_pieces(const bsfit_curve *c, const double *X, const double *R, size_t m,
                       double *t) {
  size_t p = (size_t)c->degree, N = c->n - p, i, j = 0;
  for (i = 0; i < N; i++) {
    double x = c->knots[p + i];
    while (j + 1 < m && X[j + 1] <= x) j++;
    if (x < X[0] || (j + 1 == m && x > X[j])) t[i] = x;
    else if (x == X[j]) t[i] = R[j];
    else t[i] = R[j] + (x - X[j]) * ((R[j + 1] - R[j]) / (X[j + 1] - X[j]));
  }
  t[N] = 1.0;
}

/* Whether the piece from corner j to j + 1 keeps its length within a factor MERGE_STRETCH
** (the period's end after the last corner when the seam is a corner: wrap). */
static int piece_kept(const double *X, const double *R, size_t m, size_t j, int wrap) {
  double x = j + 1 < m ? X[j + 1] - X[j] : 1.0 - X[j], r = j + 1 < m ? R[j + 1] - R[j] : 1.0 - R[j];
  if (j + 1 == m && !wrap) return 1; /* past the last corner nothing is mapped */
  return r * MERGE_STRETCH >= x && r <= x * MERGE_STRETCH;
}

/* Corners whose move would stretch or squeeze a piece next to them by more than
** MERGE_STRETCH stay where they are, until every piece is kept. */
static void keep_pieces(const double *X, double *R, size_t m, int wrap) {
  size_t j, pass;
  int changed = 1;
  for (pass = 0; pass <= m && changed; pass++) {
    changed = 0;
    for (j = 0; j < m; j++)
      if (!piece_kept(X, R, m, j, wrap)) {
        size_t next = j + 1 < m ? j + 1 : 0;
        changed |= R[j] != X[j] || (wrap || j + 1 < m ? R[next] != X[next] : 0);
        R[j] = X[j];
        if (j + 1 < m) R[j + 1] = X[j + 1];
      }
  }
}

/* Moves c's unanchored corners to their cluster's value (xs[0..n-1] the sorted corners of
** all the sections, rep their values), except those that would distort a piece next to
** them (keep_pieces: a piece of the trailing edge of a meshed wing, 8.5e-4 of the period,
** was squeezed into 3.5e-7 by corners of other sections 1e-3 away; the surface passed
** through the section, the piece all but hidden in one u-sliver). A map that would
** collapse a piece leaves c alone. X, R, t: scratch of N + 2 values; own: of N + 1
** corners. */
static bsfit_err remap_section(bsfit_curve *c, const double *xs, const double *rep, size_t n,
                               double tol, corner *own, double *X, double *R, double *t,
                               const bsfit_allocator *a, bsfit_status *st) {
  size_t m = corners_of(c, 0, tol, own), j;
  int moved = 0;
  for (j = 0; j < m; j++) {
    X[j] = own[j].x;
    R[j] = own[j].anchored ? X[j] : rep[find_value(xs, n, X[j])];
  }
  keep_pieces(X, R, m, m > 0 && X[0] == 0.0);
  for (j = 0; j < m; j++) {
    moved |= R[j] != X[j];
    if (j > 0 && !(R[j] > R[j - 1])) return BSFIT_OK;
  }
  if (!moved) return BSFIT_OK;
  if (X[0] == 0.0) X[m] = R[m] = 1.0, m++; /* the last piece runs to the period's end */
  if (m > 1 && !(R[m - 1] > R[m - 2])) return BSFIT_OK;
  map_pieces(c, X, R, m, t);
  return set_knots(c, t, a, st);
}

bsfit_err bsfit__skin_merge_corners(bsfit_curve *w, size_t K, double tol,
                                    const bsfit_allocator *a, bsfit_status *st) {
  size_t k, n = 0, Nmax = 0, bytes;
  corner *c, *own;
  double *xs, *rep, *X;
  size_t *last;
  bsfit_err e = BSFIT_OK;
  for (k = 0; k < K; k++) {
    n += corners_of(&w[k], k, tol, NULL);
    if (w[k].n > Nmax) Nmax = w[k].n;
  }
  if (n < 2) return BSFIT_OK;
  bytes = n * (sizeof(corner) + 2 * sizeof(double)) + K * sizeof(size_t) +
          (Nmax + 2) * (sizeof(corner) + 3 * sizeof(double));
  c = bsfit__alloc(a, bytes);
  if (c == NULL) return bsfit__fail(st, BSFIT_ENOMEM, "out of memory for %zu corner knots", n);
  xs = (double *)(c + n);
  rep = xs + n;
  own = (corner *)(rep + n);
  X = (double *)(own + Nmax + 2);
  last = (size_t *)(X + 3 * (Nmax + 2));
  for (k = 0, n = 0; k < K; k++) n += corners_of(&w[k], k, tol, c + n), last[k] = (size_t)-1;
  qsort(c, n, sizeof *c, cmp_corner);
  for (k = 0; k < n; k++) xs[k] = c[k].x;
  cluster_corners(c, n, tol, rep, last);
  for (k = 0; k < K && e == BSFIT_OK; k++)
    e = remap_section(&w[k], xs, rep, n, tol, own, X, X + Nmax + 2, X + 2 * (Nmax + 2), a, st);
  bsfit__free(a, c, bytes);
  return e;
}

size_t bsfit__skin_shared_corners(const bsfit_curve *w, size_t K, double *out) {
  size_t k, i = 0, n = 0, kept = 0;
  int m;
  for (k = 0; k < K; k++) /* each section's corners once: the values, in out */
    for (i = 0; (m = next_run(&w[k], &i)) > 0; i += (size_t)m)
      if (m >= w[k].degree) out[n++] = w[k].knots[(size_t)w[k].degree + i];
  qsort(out, n, sizeof(double), cmp_double);
  for (i = 0; i < n; i = k) {
    for (k = i; k < n && out[k] == out[i]; k++) continue;
    if (2 * (k - i) >= K) out[kept++] = out[i];
  }
  return kept;
}

/* }==================================================================== */

/* {====================================================================
** The union
** ===================================================================== */

/* The period knots of every section, sorted, with equal values once: D of them in v. */
static size_t union_values(const bsfit_curve *w, size_t K, double *v) {
  size_t k, i, j = 0, D = 0;
  for (k = 0; k < K; k++)
    for (i = 0; i < w[k].n - (size_t)w[k].degree; i++) v[j++] = w[k].knots[(size_t)w[k].degree + i];
  qsort(v, j, sizeof(double), cmp_double);
  for (i = 0; i < j; i++)
    if (D == 0 || v[i] != v[D - 1]) v[D++] = v[i];
  return D;
}

/* Knots rounding apart (within BSFIT__SKIN_ROUND of their cluster's first value) moved onto
** it, in every section whose multiplicities stay at most p. t: scratch of N + 1 values. */
static bsfit_err snap_rounding(bsfit_curve *w, size_t K, double *v, double *rep, double *t,
                               const bsfit_allocator *a, bsfit_status *st) {
  size_t D = union_values(w, K, v), i, k, start = 0;
  bsfit_err e = BSFIT_OK;
  for (i = 0; i < D; i++) {
    if (v[i] - v[start] > BSFIT__SKIN_ROUND) start = i;
    rep[i] = v[start];
  }
  for (k = 0; k < K && e == BSFIT_OK; k++) {
    size_t p = (size_t)w[k].degree, N = w[k].n - p, run = 1;
    int moved = 0, ok = 1;
    for (i = 0; i < N; i++) {
      t[i] = rep[find_value(v, D, w[k].knots[p + i])];
      moved |= t[i] != w[k].knots[p + i];
      run = i > 0 && t[i] == t[i - 1] ? run + 1 : 1;
      ok &= run <= p;
    }
    t[N] = 1.0;
    if (moved && ok) e = set_knots(&w[k], t, a, st);
  }
  return e;
}

/* The knots section c lacks from the union (value v[d] to multiplicity need[d]) into X;
** returns their count. Both lists are sorted, so one merge walk does it. */
static size_t missing_knots(const bsfit_curve *c, const double *v, const int *need, size_t D,
                            double *X) {
  size_t i = 0, d, nx = 0;
  int m = next_run(c, &i), p = c->degree;
  for (d = 0; d < D; d++) {
    int have = 0;
    if (m > 0 && c->knots[(size_t)p + i] == v[d]) {
      have = m;
      i += (size_t)m;
      m = next_run(c, &i);
    }
    while (have++ < need[d]) X[nx++] = v[d];
  }
  return nx;
}

/* Each section refined to the union of the period knots, each value with the largest
** multiplicity any section gives it. v, X: scratch of the total count; need: of ints. */
static bsfit_err refine_to_union(bsfit_curve *w, size_t K, double *v, double *X, int *need,
                                 const bsfit_allocator *a, bsfit_status *st) {
  size_t D = union_values(w, K, v), k, i, nx;
  int m;
  bsfit_err e = BSFIT_OK;
  for (i = 0; i < D; i++) need[i] = 0;
  for (k = 0; k < K; k++)
    for (i = 0; (m = next_run(&w[k], &i)) > 0; i += (size_t)m) {
      size_t d = find_value(v, D, w[k].knots[(size_t)w[k].degree + i]);
      if (m > need[d]) need[d] = m;
    }
  for (k = 0; k < K && e == BSFIT_OK; k++) {
    if (bsfit__interrupted(a)) e = bsfit__fail(st, BSFIT_EINTR, "skinning interrupted");
    nx = e == BSFIT_OK ? missing_knots(&w[k], v, need, D, X) : 0;
    if (nx > 0) e = bsfit_curve_refine(&w[k], X, nx, &w[k], st);
  }
  return e;
}

bsfit_err bsfit__skin_compatible(bsfit_curve *w, size_t K, const bsfit_allocator *a,
                                 bsfit_status *st) {
  size_t k, total = 0, Nmax = 0, bytes;
  int p = 0;
  double *v;
  bsfit_err e = BSFIT_OK;
  for (k = 0; k < K; k++) p = w[k].degree > p ? w[k].degree : p;
  for (k = 0; k < K && e == BSFIT_OK; k++)
    if (w[k].degree < p) {
      e = bsfit_curve_elevate(&w[k], p - w[k].degree, &w[k], st);
      if (e == BSFIT_OK) e = bsfit__skin_seam_whole(&w[k], a, st);
    }
  if (e == BSFIT_OK) e = bsfit__skin_merge_corners(w, K, BSFIT__SKIN_MERGE, a, st);
  if (e != BSFIT_OK) return e;
  for (k = 0; k < K; k++) {
    total += w[k].n - (size_t)p;
    if (w[k].n > Nmax) Nmax = w[k].n;
  }
  bytes = (2 * total + Nmax + 1) * sizeof(double) + total * sizeof(int);
  v = bsfit__alloc(a, bytes);
  if (v == NULL) return bsfit__fail(st, BSFIT_ENOMEM, "out of memory for %zu knots", total);
  e = snap_rounding(w, K, v, v + total, v + 2 * total, a, st);
  /* the union only grows by refinement, never past the total before it */
  if (e == BSFIT_OK)
    e = refine_to_union(w, K, v, v + total, (int *)(v + 2 * total + Nmax + 1), a, st);
  bsfit__free(a, v, bytes);
  return e;
}
