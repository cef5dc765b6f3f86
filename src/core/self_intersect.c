/*
** self_intersect.c
** Does a 2D curve cross itself? (bsfit_features.h) Its polyline of k samples is tested
** edge against edge, only for the pairs whose ranges along a sweep axis overlap: the edges
** sorted by their first end along it, each compared with the following ones until their
** first end passes its last. The axis is at 1 radian to x, not x itself: the edges of a
** side parallel to the sweep's normal all overlap each other, and made objects have
** their sides along x and y (a T of 40 samples took 0.46 ms, its 2000 samples' vertical
** edges compared pairwise). The edges come in runs along the axis, which sort_by_left
** merges. Besides the k even samples, the curve is sampled ever closer to each of its
** corners (knots of multiplicity >= degree), where a loop can be far shorter than the
** even step (corner_params).
*/
#include "internal.h"

#include <float.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#define SWEEP_COS 0.54030230586813977 /* cos(1), sin(1): the sweep axis */
#define SWEEP_SIN 0.84147098480789651

typedef struct edge {
  double x0, x1; /* range along the sweep axis */
  size_t i;      /* from sample i to i+1 */
} edge;

/* Reverses E[a..b). */
static void reverse_edges(edge *E, size_t a, size_t b) {
  while (b > a + 1) {
    edge t = E[a];
    E[a++] = E[--b], E[b] = t;
  }
}

/* Merges the sorted runs E[a..m) and E[m..b) through T (stable: ties keep E's order). */
static void merge_runs(edge *E, edge *T, size_t a, size_t m, size_t b) {
  size_t i = a, j = m, o = a;
  while (i < m && j < b) T[o++] = E[j].x0 < E[i].x0 ? E[j++] : E[i++];
  while (i < m) T[o++] = E[i++];
  while (j < b) T[o++] = E[j++];
  memcpy(E + a, T + a, (b - a) * sizeof *E);
}

/* Sorts the edges by their first end, stably, in O(ne log r) for r monotone runs: along a
** stretch of the curve that runs one way along the sweep axis the first ends already come
** in order (or in reverse), so a section has as many runs as turns of the axis (a T's 2000
** edges took 15% of its 40-point run in qsort). starts: room for ne + 1 run starts. */
static void sort_by_left(edge *E, edge *T, size_t *starts, size_t ne) {
  size_t a = 0, r = 0, width, k;
  while (a < ne) { /* the runs: non-decreasing, or strictly decreasing (then reversed) */
    size_t b = a + 1;
    if (b < ne && E[b].x0 < E[a].x0) {
      while (b < ne && E[b].x0 < E[b - 1].x0) b++;
      reverse_edges(E, a, b);
    } else
      while (b < ne && E[b].x0 >= E[b - 1].x0) b++;
    starts[r++] = a;
    a = b;
  }
  starts[r] = ne;
  for (width = 1; width < r; width *= 2) /* merge neighbouring runs, bottom up */
    for (k = 0; k + width < r; k += 2 * width) {
      size_t hi = k + 2 * width < r ? k + 2 * width : r;
      merge_runs(E, T, starts[k], starts[k + width], starts[hi]);
    }
}

static double cross3(const double *o, const double *a, const double *b) {
  return (a[0] - o[0]) * (b[1] - o[1]) - (a[1] - o[1]) * (b[0] - o[0]);
}

/* the side of line ab that c is on: 1 left, 0 right, a point on the line counted left
** (a symbolic perturbation: a chain that crosses another exactly at one of its samples
** has one of its two edges there cross, not none) */
static int left_of(const double *a, const double *b, const double *c) {
  return cross3(a, b, c) >= 0;
}

/* do segments ab and cd cross (both ends of each on either side of the other)? */
static int crosses(const double *a, const double *b, const double *c, const double *d) {
  return left_of(a, b, c) != left_of(a, b, d) && left_of(c, d, a) != left_of(c, d, b);
}

/* Exactly: only a sample shared to the last bit leaves the four edges there touching
** (samples an ulp apart are a generic pair of segments, and crosses decides them: 300
** figure-eights moved off the origin, their passes apart by rounding, all found). */
static int same_point(const double *a, const double *b) {
  return a[0] == b[0] && a[1] == b[1];
}

/* Is x strictly inside the turn from ray p->a counterclockwise to ray p->b? */
static int in_sector(const double *p, const double *a, const double *b, const double *x) {
  double ab = cross3(p, a, b);
  if (ab > 0) return cross3(p, a, x) > 0 && cross3(p, x, b) > 0;
  if (ab < 0) return cross3(p, b, x) < 0 || cross3(p, x, a) < 0;
  if ((a[0] - p[0]) * (b[0] - p[0]) + (a[1] - p[1]) * (b[1] - p[1]) < 0) return cross3(p, a, x) > 0;
  return 0; /* a and b on one ray: the chain turns back on itself, nothing between */
}

/* Two samples of the chain at one point, the ends of edges i and j: does the chain pass
** through itself there (the other pass's samples before and after on either side of this
** pass's turn) or only touch? At the end of an open chain there is no sample after. */
static int crosses_at_sample(const double *S, size_t i, size_t j, size_t ne, int closed) {
  size_t ni = i + 2, nj = j + 2;
  if (closed) ni %= ne, nj %= ne;
  else if (ni > ne || nj > ne) return 0; /* an end of an open chain only touches */
  return in_sector(S + 2 * (i + 1), S + 2 * i, S + 2 * ni, S + 2 * j) !=
         in_sector(S + 2 * (i + 1), S + 2 * i, S + 2 * ni, S + 2 * nj);
}

/* Edges i and j (not neighbours): do they cross? Where they share a sample, only the
** pair of edges that end there is asked, and whether the chain passes through itself
** there; elsewhere the two segments. */
static int edges_cross(const double *S, size_t i, size_t j, size_t ne, int closed) {
  const double *a = S + 2 * i, *b = a + 2, *c = S + 2 * j, *d = c + 2;
  if (same_point(b, d)) return crosses_at_sample(S, i, j, ne, closed);
  if (same_point(a, c) || same_point(a, d) || same_point(b, c)) return 0;
  return crosses(a, b, c, d);
}

/* do edges i and j share a sample (neighbours, or first and last of a closed chain)? */
static int adjacent(size_t i, size_t j, size_t ne, int closed) {
  size_t lo = i < j ? i : j, hi = i < j ? j : i;
  return hi == lo + 1 || (closed && lo == 0 && hi == ne - 1);
}

/* Halvings of a span towards a corner: a loop as short as 2^-REFINE of the span beside
** the corner (6e-8 of it) is still seen. A gear's smooth fit at noise 1e-3 of its size had
** its two sides cross 3e-4 of the period past a corner, between two of 2208 even samples. */
#define REFINE 24

/* the number of knots in the domain where the curve may turn (multiplicity >= degree, as
** bsfit_knots_multiplicity counts it; a periodic curve's end is its start); with u != NULL,
** REFINE parameters on either side of each, ever closer to it */
static size_t corner_params(const bsfit_curve *c, double a, double b, double *u) {
  size_t i = 0, nk = c->n + (size_t)c->degree + 1, found = 0;
  while (i < nk) {
    double t = c->knots[i];
    size_t j = i;
    while (j < nk && c->knots[j] == t) j++;
    if (j - i >= (size_t)c->degree && t >= a && (c->periodic ? t < b : t <= b) && i > 0 &&
        j < nk) {
      double before = t - c->knots[i - 1], after = c->knots[j] - t;
      if (u) {
        int r;
        double h = 0.5;
        for (r = 0; r < REFINE; r++, h *= 0.5) {
          u[2 * REFINE * found + 2 * r] = t - h * before;
          u[2 * REFINE * found + 2 * r + 1] = t + h * after;
        }
      }
      found++;
    }
    i = j;
  }
  return found;
}

static int by_value(const void *a, const void *b) {
  double x = *(const double *)a, y = *(const double *)b;
  return x < y ? -1 : x > y;
}

/* Drops from the sorted u[0..n) the parameters within a few ulps of the one kept before
** (of a periodic curve's start, at its end), and returns how many are left. Between two
** knots where the curve may turn, both series of corner_params reach the middle of the
** span, computed twice with different rounding: two samples an ulp apart leave an edge of
** no length between two edges that touch there, and the rounding of their cross products
** read as a crossing (an exact outline 392 sizes from the origin, reported crossing). */
static size_t distinct_params(double *u, size_t n, double a, double b, int periodic) {
  double tol = 8 * DBL_EPSILON * fmax(fabs(a), fmax(fabs(b), b - a));
  size_t i, kept = 0;
  for (i = 0; i < n; i++) {
    if (kept > 0 && u[i] - u[kept - 1] <= tol) continue;
    if (periodic && kept > 0 && b - u[i] <= tol) continue;
    u[kept++] = u[i];
  }
  return kept;
}

/* The sample parameters, sorted in [a, b] ([a, b) when periodic): the k even ones merged
** with those near the corners (wrapped into the period, sorted: far fewer). Returns their
** count; 0 on no memory. */
static size_t sample_params(const bsfit_curve *c, size_t k, double **out, size_t *bytes,
                            const bsfit_allocator *al) {
  double a, b, *u, *near;
  size_t i, j, n, nc, nn;
  bsfit_curve_domain(c, &a, &b);
  nc = corner_params(c, a, b, NULL);
  nn = 2 * REFINE * nc;
  n = k + nn;
  *bytes = bsfit__mulsize(n + nn + 1, sizeof *u);
  if (!(u = *out = bsfit__alloc(al, *bytes))) return 0;
  near = u + n; /* scratch after the merged list */
  corner_params(c, a, b, near);
  for (i = 0; i < nn; i++) {
    if (c->periodic) near[i] = a + fmod(fmod(near[i] - a, b - a) + (b - a), b - a);
    else near[i] = fmin(fmax(near[i], a), b);
  }
  qsort(near, nn, sizeof *near, by_value);
  for (i = k, j = nn; i > 0 || j > 0;) { /* merge from the top; the even ones made as taken */
    double even = i > 0 ? a + (b - a) * (double)(i - 1) / (double)(c->periodic ? k : k - 1) : 0;
    int take_near = j > 0 && (i == 0 || near[j - 1] > even);
    u[i + j - 1] = take_near ? near[j - 1] : even;
    if (take_near) j--;
    else i--;
  }
  return distinct_params(u, n, a, b, c->periodic);
}

/* E sorted (sort_by_left), then each edge compared with those after it that it overlaps */
static size_t sweep(const double *S, const edge *E, size_t ne, int closed, size_t *first,
                    const bsfit_allocator *al, int *stop) {
  size_t a, b, found = 0;
  for (a = 0; a < ne && found < 1000; a++) {
    if ((a & 4095) == 0 && bsfit__interrupted(al)) {
      *stop = 1;
      return found;
    }
    for (b = a + 1; b < ne && E[b].x0 <= E[a].x1; b++) {
      size_t i = E[a].i, j = E[b].i;
      if (adjacent(i, j, ne, closed)) continue;
      if (edges_cross(S, i, j, ne, closed)) {
        if (found++ == 0) *first = i < j ? i : j;
      }
    }
  }
  return found;
}

/* The rounding of the coordinates of the k samples S: two samples closer than this are
** one point. */
static double rounding_of(const double *S, size_t k) {
  double scale = 0;
  size_t i;
  for (i = 0; i < 2 * k; i++) scale = fmax(scale, fabs(S[i]));
  return 16 * DBL_EPSILON * scale;
}

static int meet(const double *a, const double *b, double tol) {
  return fabs(a[0] - b[0]) <= tol && fabs(a[1] - b[1]) <= tol;
}

/* Drops each sample that meets the one kept before it (S and its parameters u), and
** returns how many are left. Where the curve stands still (a span of coincident control
** points) the edge of no length between two samples has no side: a crossing through
** that point was lost, and the edges on either side of it were read as crossing. */
static size_t drop_repeats(double *S, double *u, size_t k, double tol) {
  size_t i, kept = 1;
  for (i = 1; i < k; i++) {
    if (meet(S + 2 * (kept - 1), S + 2 * i, tol)) continue;
    S[2 * kept] = S[2 * i], S[2 * kept + 1] = S[2 * i + 1], u[kept] = u[i];
    kept++;
  }
  return kept;
}

bsfit_err bsfit_curve_self_intersections(const bsfit_curve *c, size_t k, size_t *crossings,
                                         double *where, const bsfit_allocator *al,
                                         bsfit_status *st) {
  double *S = NULL, *u = NULL;
  edge *E = NULL;
  size_t *starts = NULL;
  size_t i, ne, first = 0, bs = 0, es = 0, us = 0, ss = 0;
  int closed, stop = 0;
  double tol;
  bsfit_err e;
  if (crossings) *crossings = 0;
  if (c == NULL || crossings == NULL)
    return bsfit__fail(st, BSFIT_EINVAL, "self-intersection: no curve");
  if (c->dim != 2)
    return bsfit__fail(st, BSFIT_EDIM, "self-intersection needs a 2D curve, got dim %d", c->dim);
  if (k < 3)
    return bsfit__fail(st, BSFIT_EINVAL, "self-intersection needs at least 3 samples, got %zu", k);
  if (c->n == 0 || c->knots == NULL)
    return bsfit__fail(st, BSFIT_EINVAL, "self-intersection: empty curve");
  k = sample_params(c, k, &u, &us, al);
  if (k) {
    bs = bsfit__mulsize(k + 1, 2 * sizeof(double));
    S = bsfit__alloc(al, bs);
    es = bsfit__mulsize(k, 2 * sizeof *E); /* the edges, then the merge's scratch */
    E = bsfit__alloc(al, es);
    ss = bsfit__mulsize(k + 1, sizeof *starts);
    starts = bsfit__alloc(al, ss);
  }
  if (!u || !S || !E || !starts) {
    e = bsfit__fail(st, BSFIT_ENOMEM, "self-intersection: out of memory");
    goto done;
  }
  e = bsfit_curve_eval_many(c, u, k, S, st);
  if (e != BSFIT_OK) goto done;
  tol = rounding_of(S, k);
  k = drop_repeats(S, u, k, tol);
  /* A closed curve (periodic, or whose ends meet) is a closed polyline. A curve joined
  ** from pieces that close (its last control point its first) evaluates at its end an ulp
  ** or two from its start: taken as open, its last edge touched its first there, and the
  ** rounding of their cross products read as a crossing (test_self_intersect: 6 of 400
  ** convex outlines of lines and fillets). */
  closed = c->periodic;
  if (k > 1 && meet(S, S + 2 * (k - 1), tol)) closed = 1, k--; /* the last repeats the first */
  if (k < 3) { /* the curve stands still (or only goes and comes back): nothing to cross */
    e = bsfit__ok(st);
    goto done;
  }
  if (closed) S[2 * k] = S[0], S[2 * k + 1] = S[1];
  ne = closed ? k : k - 1;
  for (i = 0; i < ne; i++) {
    double p = SWEEP_COS * S[2 * i] + SWEEP_SIN * S[2 * i + 1];
    double q = SWEEP_COS * S[2 * i + 2] + SWEEP_SIN * S[2 * i + 3];
    E[i].x0 = fmin(p, q);
    E[i].x1 = fmax(p, q);
    E[i].i = i;
  }
  sort_by_left(E, E + k, starts, ne);
  *crossings = sweep(S, E, ne, closed, &first, al, &stop);
  if (stop) {
    e = bsfit__fail(st, BSFIT_EINTR, "self-intersection: interrupted");
    goto done;
  }
  if (where && *crossings > 0) *where = u[first];
  e = bsfit__ok(st);
done:
  bsfit__free(al, u, u ? us : 0);
  bsfit__free(al, S, S ? bs : 0);
  bsfit__free(al, E, E ? es : 0);
  bsfit__free(al, starts, starts ? ss : 0);
  return e;
}
