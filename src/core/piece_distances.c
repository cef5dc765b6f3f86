/*
** piece_distances.c
** The distances of a section's samples to the one curve assembled from its pieces
** (bsfit.strategy.sharp): the deviation report of auto's sharp path, in one call.
**
** Each sample's foot is first found by Newton from the sample's place in its own piece's
** parameter range: a search that never has to cross a corner (a search from a global
** start can stall at a C0 knot and report the distance to the corner instead). That
** distance d is certified when the foot lies on a straight span (its control points on
** one line to CERT_RTOL), d is no more than the distance to that line (plus the slack),
** and no other span comes within d of the sample (their control points' bounding boxes,
** which hold them, lie farther: a tree of boxes over the spans answers in O(log n)); the
** smaller of d and the distance to the line is then the sample's distance, within the
** slack of the true one. Every other sample (on an arc or a free run, near a corner, or
** near another part of the curve: a thin slot's far side) takes the nearer of d and the
** global search of bsfit_curve_closest_many. On a section of lines nearly every sample is
** certified: the global search, two thirds of the cost, runs only near the corners (a
** square of 10^5 exact samples: 21 -> 6 ms).
**
** Spans that lie on a circle (the rational arcs of the pieces, found by the Bernstein
** coefficients of their distance to it) certify their samples in the same way, and before
** Newton: a sample whose start is on such a span, whose foot on the circle lies on the
** span and which no other span comes near takes its distance to the circle (an exact
** circle of 10^5 samples: 459 ms with the global search, 4 ms so).
*/
#include "internal.h"

#include <math.h>
#include <stdint.h>

#define CERT_RTOL 1e-14 /* straightness and certificate slack, relative to the largest
                           control-point coordinate (about 50 units of its last place) */
#define TREE_STACK 64   /* pending nodes of a descent: one per level at most */

/* Boxes of the spans' control points, as a complete binary tree over the spans in order
** (node 1 the root, node k's children 2k and 2k + 1, leaf j at node leaves + j): spans of
** a curve in order are near each other, so a subtree's box is tight. */
typedef struct span_tree {
  size_t leaves; /* a power of two >= the number of spans */
  size_t d;
  double *box;   /* per node: d lows, then d highs; an empty node: low > high */
  unsigned char *straight; /* per span: its control points lie on a line */
  double *circle;          /* per span: centre and radius of the circle it lies on (r 0: none) */
  unsigned char *minor;    /* per span on a circle: it runs along the minor arc of its ends */
  size_t arcs;             /* how many spans do */
  double tol;              /* how near their line or circle the straight and circular spans lie */
} span_tree;

/* The box of span s's control points into b (lows, highs): the whole space when a weight
** is not positive (the convex hull no longer holds the curve). Sets *line: the control
** points lie within tol of the line through the first and the last. */
static void span_box(const bsfit_curve *c, size_t s, double tol, double *b, unsigned char *line) {
  size_t p = (size_t)c->degree, d = (size_t)c->dim, i, q;
  const double *Q0 = c->ctrl + (s - p) * d, *Q1 = c->ctrl + s * d;
  double t[4], len = 0.0;
  int pos = 1;
  for (q = 0; q < d; q++) b[q] = INFINITY, b[d + q] = -INFINITY;
  for (i = s - p; i <= s; i++) {
    pos = pos && (c->weights == NULL || c->weights[i] > 0);
    for (q = 0; q < d; q++) {
      b[q] = fmin(b[q], c->ctrl[i * d + q]);
      b[d + q] = fmax(b[d + q], c->ctrl[i * d + q]);
    }
  }
  if (!pos)
    for (q = 0; q < d; q++) b[q] = -INFINITY, b[d + q] = INFINITY;
  for (q = 0; q < d; q++) t[q] = Q1[q] - Q0[q], len += t[q] * t[q];
  len = sqrt(len);
  *line = len > 0;
  for (i = s - p + 1; *line && i < s; i++) {
    double x[4], along = 0.0, off = 0.0;
    for (q = 0; q < d; q++) x[q] = c->ctrl[i * d + q] - Q0[q], along += x[q] * t[q] / len;
    for (q = 0; q < d; q++) off += (x[q] - along * t[q] / len) * (x[q] - along * t[q] / len);
    *line = sqrt(off) <= tol;
  }
}

/* {====================================================================
** Spans on a circle (the arcs of the pieces: rational Bezier spans)
** ===================================================================== */

#define ARC_MAXDEG 7

static double choose(int n, int k) {
  double b = 1.0;
  int i;
  for (i = 1; i <= k; i++) b = b * (double)(n - k + i) / (double)i;
  return b;
}

/* the circle through a, b, c: 0 when they are (nearly) collinear */
static int circle_through(const double *a, const double *b, const double *c, double *circ) {
  double bx = b[0] - a[0], by = b[1] - a[1], cx = c[0] - a[0], cy = c[1] - a[1];
  double D = 2.0 * (bx * cy - by * cx), b2 = bx * bx + by * by, c2 = cx * cx + cy * cy, ux, uy;
  if (!(fabs(D) > 1e-10 * sqrt(b2 * c2))) return 0;
  ux = (cy * b2 - by * c2) / D;
  uy = (bx * c2 - cx * b2) / D;
  circ[0] = a[0] + ux, circ[1] = a[1] + uy, circ[2] = sqrt(ux * ux + uy * uy);
  return 1;
}

/* Whether x lies in the sector of the circle's centre between a and b, on the minor arc's
** side (a and b less than a half turn apart). */
static int in_sector(const double *circ, const double *a, const double *b, const double *x) {
  double ax = a[0] - circ[0], ay = a[1] - circ[1], bx = b[0] - circ[0], by = b[1] - circ[1];
  double fx = x[0] - circ[0], fy = x[1] - circ[1], ab = ax * by - ay * bx;
  double af = ax * fy - ay * fx, fb = fx * by - fy * bx;
  if (!(fabs(ab) > 1e-6 * (ax * ax + ay * ay))) return 0; /* a and b (nearly) opposite */
  return ab > 0 ? af >= 0 && fb >= 0 : af <= 0 && fb <= 0;
}

/* Whether span s, a Bezier span of a 2D curve (its ends knots of multiplicity p), lies
** within tol of a circle: the one through its ends and middle. With weights w_i > 0 and
** points P_i, F(t) = w(t)^2 (|X(t) - c|^2 - r^2) is a polynomial of degree 2p whose
** Bernstein coefficients are sums of w_i w_j ((P_i - c).(P_j - c) - r^2); |F| is at most
** their largest, and a point of the span lies |F| / (w^2 (|X - c| + r)) <= max / (w_min^2 r)
** from the circle. Sets circ (centre, radius) and returns 1 when that is within tol; sets
** *minor when its middle lies on the minor arc of its ends (a connected part of the circle
** through both ends and that point then holds that whole arc). */
static int span_circle(const bsfit_curve *c, size_t s, double tol, double *circ,
                       unsigned char *minor) {
  int p = c->degree, i, j, k;
  const double *U = c->knots, *Q = c->ctrl + (s - (size_t)p) * 2;
  const double *W = c->weights ? c->weights + (s - (size_t)p) : NULL;
  double w[ARC_MAXDEG + 1], h[3] = {0, 0, 0}, mid[2], wmin = INFINITY, big = 0.0;
  if (c->dim != 2 || p < 2 || p > ARC_MAXDEG || U[s - (size_t)p + 1] != U[s] ||
      U[s + (size_t)p] != U[s + 1])
    return 0;
  for (i = 0; i <= p; i++) {
    double b = choose(p, i);
    w[i] = W ? W[i] : 1.0;
    wmin = fmin(wmin, w[i]);
    h[0] += b * w[i] * Q[2 * i], h[1] += b * w[i] * Q[2 * i + 1], h[2] += b * w[i];
  }
  if (!(wmin > 0)) return 0;
  mid[0] = h[0] / h[2], mid[1] = h[1] / h[2];
  if (!circle_through(Q, mid, Q + 2 * p, circ)) return 0;
  *minor = (unsigned char)in_sector(circ, Q, Q + 2 * p, mid);
  for (k = 0; k <= 2 * p; k++) {
    double f = 0.0;
    for (i = k - p > 0 ? k - p : 0; i <= p && i <= k; i++) {
      j = k - i;
      f += choose(p, i) * choose(p, j) * w[i] * w[j] *
           ((Q[2 * i] - circ[0]) * (Q[2 * j] - circ[0]) +
            (Q[2 * i + 1] - circ[1]) * (Q[2 * j + 1] - circ[1]) - circ[2] * circ[2]);
    }
    big = fmax(big, fabs(f) / choose(2 * p, k));
  }
  return big / (wmin * wmin * circ[2]) <= tol;
}

/* The distance from P to span s's circle. */
static double circle_dist(const double *circ, const double *P) {
  double dx = P[0] - circ[0], dy = P[1] - circ[1];
  return fabs(sqrt(dx * dx + dy * dy) - circ[2]);
}

/* }==================================================================== */

static void box_union(double *to, const double *a, const double *b, size_t d) {
  size_t q;
  for (q = 0; q < d; q++) to[q] = fmin(a[q], b[q]), to[d + q] = fmax(a[d + q], b[d + q]);
}

/* the squared distance from P to box b (0 inside) */
static double box_dist2(const double *b, const double *P, size_t d) {
  double g2 = 0.0;
  size_t q;
  for (q = 0; q < d; q++) {
    double g = P[q] < b[q] ? b[q] - P[q] : (P[q] > b[d + q] ? P[q] - b[d + q] : 0.0);
    g2 += g * g;
  }
  return g2;
}

static bsfit_err tree_build(span_tree *T, const bsfit_curve *c, double tol,
                            const bsfit_allocator *a) {
  size_t p = (size_t)c->degree, ns = c->n - p, d = (size_t)c->dim, k, q;
  T->d = d;
  for (T->leaves = 1; T->leaves < ns; T->leaves *= 2) {}
  T->box = bsfit__alloc(a, bsfit__mulsize(2 * T->leaves, (2 * d + 3) * sizeof(double) + 2));
  if (T->box == NULL) return BSFIT_ENOMEM;
  T->circle = T->box + 2 * T->leaves * 2 * d;
  T->straight = (unsigned char *)(T->circle + 2 * T->leaves * 3);
  T->minor = T->straight + 2 * T->leaves;
  T->arcs = 0;
  T->tol = tol;
  for (k = 0; k < T->leaves; k++) {
    double *b = T->box + (T->leaves + k) * 2 * d;
    T->straight[k] = T->minor[k] = 0;
    T->circle[3 * k + 2] = 0.0;
    if (k < ns && c->knots[p + k + 1] > c->knots[p + k]) {
      span_box(c, p + k, tol, b, &T->straight[k]);
      if (!T->straight[k] && !span_circle(c, p + k, tol, T->circle + 3 * k, &T->minor[k]))
        T->circle[3 * k + 2] = 0.0, T->minor[k] = 0;
      T->arcs += T->minor[k];
    } else
      for (q = 0; q < d; q++) b[q] = INFINITY, b[d + q] = -INFINITY; /* empty */
  }
  for (k = T->leaves - 1; k >= 1; k--)
    box_union(T->box + k * 2 * d, T->box + 2 * k * 2 * d, T->box + (2 * k + 1) * 2 * d, d);
  return BSFIT_OK;
}

static void tree_free(span_tree *T, const bsfit_allocator *a) {
  bsfit__free(a, T->box, 2 * T->leaves * ((2 * T->d + 3) * sizeof(double) + 2));
}

/* Whether no span other than `own` (a leaf number) has its box within r of P. */
static int alone_within(const span_tree *T, size_t own, const double *P, double r) {
  size_t stack[TREE_STACK], top = 0, d = T->d;
  double r2 = r * r;
  stack[top++] = 1;
  while (top > 0) {
    size_t k = stack[--top];
    const double *b = T->box + k * 2 * d;
    if (b[0] > b[d] || box_dist2(b, P, d) > r2) continue; /* empty, or too far */
    if (k >= T->leaves) {
      /* a span on a circle lies within tol of it: no nearer to P than its circle, less tol
      ** (a D's line lies in the box of its arc's quarters, not near their circle) */
      const double *circ = T->circle + 3 * (k - T->leaves);
      if (k - T->leaves != own && !(circ[2] > 0 && circle_dist(circ, P) - T->tol > r)) return 0;
      continue;
    }
    stack[top++] = 2 * k;
    stack[top++] = 2 * k + 1;
  }
  return 1;
}

/* The distance from P to the line through span s's first and last control points. */
static double line_dist(const bsfit_curve *c, size_t s, const double *P) {
  size_t p = (size_t)c->degree, d = (size_t)c->dim, q;
  const double *Q0 = c->ctrl + (s - p) * d, *Q1 = c->ctrl + s * d;
  double t2 = 0.0, along = 0.0, off = 0.0;
  for (q = 0; q < d; q++) t2 += (Q1[q] - Q0[q]) * (Q1[q] - Q0[q]);
  for (q = 0; q < d; q++) along += (P[q] - Q0[q]) * (Q1[q] - Q0[q]) / t2;
  for (q = 0; q < d; q++) {
    double e = P[q] - Q0[q] - along * (Q1[q] - Q0[q]);
    off += e * e;
  }
  return sqrt(off);
}

/* The starts: sample k of piece j (of count n, covering the fraction [r0, r1] of the
** domain [a, b]) at a + (b - a) (r0 + (k + 1/2) / n (r1 - r0)); a sample in no piece at
** a; a sample equal to the one before it where that one starts (the same distance, to
** the last digit). */
static void piece_starts(const bsfit_curve *c, const double *pts, size_t m, const size_t *first,
                         const size_t *count, const double *range, size_t np, double *u) {
  double a, b;
  size_t i, j, k, d = (size_t)c->dim;
  bsfit_curve_domain(c, &a, &b);
  for (i = 0; i < m; i++) u[i] = a;
  for (j = 0; j < np; j++)
    for (k = 0; k < count[j]; k++) {
      double f = ((double)k + 0.5) / (double)count[j];
      u[(first[j] + k) % m] = a + (b - a) * (range[2 * j] + f * (range[2 * j + 1] - range[2 * j]));
    }
  for (i = 1; i < m; i++) {
    const double *p = pts + (i - 1) * d, *q = pts + i * d;
    size_t q0;
    int same = 1;
    for (q0 = 0; q0 < d; q0++) same = same && p[q0] == q[q0];
    if (same) u[i] = u[i - 1];
  }
}

/* the largest absolute control-point coordinate: the curve's scale */
static double curve_scale(const bsfit_curve *c) {
  size_t i;
  double s = 0.0;
  for (i = 0; i < c->n * (size_t)c->dim; i++) s = fmax(s, fabs(c->ctrl[i]));
  return s;
}

/* The samples whose distance dist[i] (at parameter u[i]) is not certified, gathered into
** pts2 (their indices into idx); returns their number, SIZE_MAX when interrupted. */
static size_t uncertified(const bsfit_curve *c, const span_tree *T, const double *pts, size_t m,
                          const double *u, double *dist, double tol, double *pts2,
                          size_t *idx, const bsfit_allocator *a) {
  size_t i, q, n2 = 0, d = (size_t)c->dim, p = (size_t)c->degree, s = p;
  const double *U = c->knots;
  for (i = 0; i < m; i++) {
    const double *P = pts + i * d;
    if (!(u[i] >= U[s] && u[i] < U[s + 1])) /* samples in order: mostly the last span */
      s = bsfit_knots_find_span(U, c->n, c->degree, u[i]);
    if ((i & 4095) == 4095 && bsfit__interrupted(a)) return SIZE_MAX;
    if (T->straight[s - p] || T->circle[3 * (s - p) + 2] > 0) {
      double dl = T->straight[s - p] ? line_dist(c, s, P) : circle_dist(T->circle + 3 * (s - p), P);
      if (dist[i] <= dl + tol && alone_within(T, s - p, P, dist[i] + tol)) {
        dist[i] = fmin(dist[i], dl);
        continue;
      }
    }
    for (q = 0; q < d; q++) pts2[n2 * d + q] = P[q];
    idx[n2++] = i;
  }
  return n2;
}

/* The samples certified without Newton, on the span of their start where that runs along
** the minor arc of a circle: the foot of the sample on the circle lies on that arc (in the
** sector of its ends), and no other span comes within its distance to the circle (plus the
** slack). The rest are gathered, in order, into pts2, u2 (their starts) and idx; returns
** their number, SIZE_MAX when interrupted. */
static size_t on_arcs(const bsfit_curve *c, const span_tree *T, const double *pts, size_t m,
                      const double *u, double *dist, double tol, double *pts2, double *u2,
                      size_t *idx, const bsfit_allocator *a) {
  size_t i, q, n2 = 0, d = (size_t)c->dim, p = (size_t)c->degree, s = p;
  const double *U = c->knots;
  for (i = 0; i < m; i++) {
    const double *P = pts + i * d;
    if (!(u[i] >= U[s] && u[i] < U[s + 1]))
      s = bsfit_knots_find_span(U, c->n, c->degree, u[i]);
    if ((i & 4095) == 4095 && bsfit__interrupted(a)) return SIZE_MAX;
    if (T->minor[s - p]) {
      const double *circ = T->circle + 3 * (s - p);
      double dc = circle_dist(circ, P);
      if (in_sector(circ, c->ctrl + (s - p) * 2, c->ctrl + s * 2, P) &&
          alone_within(T, s - p, P, dc + tol)) {
        dist[i] = dc;
        continue;
      }
    }
    for (q = 0; q < d; q++) pts2[n2 * d + q] = P[q];
    u2[n2] = u[i];
    idx[n2++] = i;
  }
  return n2;
}

/* The global search for the n2 samples not certified: the nearer answer wins. */
static bsfit_err search_rest(const bsfit_curve *c, const double *pts2, const size_t *idx,
                             size_t n2, double *dist, double *u, double *g,
                             const bsfit_allocator *a, bsfit_status *st) {
  size_t i;
  bsfit_err e = bsfit_curve_closest_many(c, pts2, n2, u, g, a, st);
  if (e != BSFIT_OK) return e;
  for (i = 0; i < n2; i++) dist[idx[i]] = fmin(dist[idx[i]], g[i]);
  return BSFIT_OK;
}

static bsfit_err check_pieces(size_t m, const size_t *first, const size_t *count,
                              const double *range, size_t np, bsfit_status *st) {
  size_t j;
  if (np > 0 && (first == NULL || count == NULL || range == NULL))
    return bsfit__fail(st, BSFIT_EINVAL, "no pieces");
  for (j = 0; j < np; j++) {
    if (first[j] >= m || count[j] > m)
      return bsfit__fail(st, BSFIT_EINVAL, "piece %zu: samples %zu + %zu outside the %zu points",
                         j + 1, first[j] + 1, count[j], m);
    if (!(isfinite(range[2 * j]) && isfinite(range[2 * j + 1])))
      return bsfit__fail(st, BSFIT_ENONFINITE, "piece %zu: its parameter range is not finite",
                         j + 1);
  }
  return BSFIT_OK;
}

/* Newton from the starts u of the m samples pts, then the certificate of each foot, then
** the global search for the rest; dist out. scratch: m (dim + 2) doubles. */
static bsfit_err newton_rest(const bsfit_curve *c, const span_tree *T, const double *pts,
                             size_t m, double *u, double *dist, int iters, double tol,
                             double *scratch, const bsfit_allocator *a, bsfit_status *st) {
  size_t n2, *idx;
  double *pts2 = scratch + m;
  bsfit_err e = bsfit_curve_project_many(c, pts, m, u, dist, iters, a, st);
  if (e != BSFIT_OK) return e;
  idx = (size_t *)(void *)(pts2 + m * (size_t)c->dim);
  n2 = uncertified(c, T, pts, m, u, dist, tol, pts2, idx, a);
  if (n2 == SIZE_MAX) return bsfit__fail(st, BSFIT_EINTR, "distances interrupted");
  /* u is free again */
  return n2 > 0 ? search_rest(c, pts2, idx, n2, dist, u, scratch, a, st) : BSFIT_OK;
}

bsfit_err bsfit_curve_piece_distances(const bsfit_curve *c, const double *pts, size_t m,
                                      const size_t *first, const size_t *count,
                                      const double *range, size_t np, int iters, double *dist,
                                      const bsfit_allocator *a, bsfit_status *st) {
  size_t d, bytes, n1, *idx1, i;
  double *u, *rest, *pts1, *u1, *dist1, tol;
  span_tree T;
  bsfit_err e = bsfit_curve_validate(c, st);
  if (e != BSFIT_OK) return e;
  if (m > 0 && (pts == NULL || dist == NULL))
    return bsfit__fail(st, BSFIT_EINVAL, "no points or no output");
  if ((e = check_pieces(m, first, count, range, np, st)) != BSFIT_OK) return e;
  if (iters < 0) return bsfit__fail(st, BSFIT_EINVAL, "iterations = %d is negative", iters);
  d = (size_t)c->dim;
  for (i = 0; i < m; i++) /* here, since samples certified on arcs skip Newton's checks */
    if (!bsfit__all_finite(pts + i * d, d))
      return bsfit__fail(st, BSFIT_ENONFINITE, "point %zu is not finite", i + 1);
  if (m == 0) return bsfit__ok(st);
  /* u; the scratch of newton_rest (g, then the uncertified samples' coordinates and
  ** indices); the samples not certified on arcs (coordinates, starts, distances, indices) */
  bytes = bsfit__mulsize(m, (2 * d + 7) * sizeof(double));
  u = bytes ? bsfit__alloc(a, bytes) : NULL;
  if (u == NULL) return bsfit__fail(st, BSFIT_ENOMEM, "out of memory for %zu distances", m);
  rest = u + m;
  pts1 = rest + (d + 2) * m;
  u1 = pts1 + d * m, dist1 = u1 + m;
  idx1 = (size_t *)(void *)(dist1 + m);
  piece_starts(c, pts, m, first, count, range, np, u);
  tol = CERT_RTOL * curve_scale(c);
  if (tree_build(&T, c, tol, a) != BSFIT_OK) {
    bsfit__free(a, u, bytes);
    return bsfit__fail(st, BSFIT_ENOMEM, "out of memory for the boxes of %zu spans", c->n);
  }
  if (T.arcs == 0) /* no arc: every sample takes Newton */
    e = newton_rest(c, &T, pts, m, u, dist, iters, tol, rest, a, st);
  else if ((n1 = on_arcs(c, &T, pts, m, u, dist, tol, pts1, u1, idx1, a)) == SIZE_MAX)
    e = bsfit__fail(st, BSFIT_EINTR, "distances interrupted");
  else if (n1 > 0 && (e = newton_rest(c, &T, pts1, n1, u1, dist1, iters, tol, rest, a, st)) ==
                         BSFIT_OK)
    for (i = 0; i < n1; i++) dist[idx1[i]] = dist1[i];
  tree_free(&T, a);
  bsfit__free(a, u, bytes);
  return e == BSFIT_OK ? bsfit__ok(st) : e;
}
