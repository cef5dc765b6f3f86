/*
** closest_pieces.c
** The global stage of the closest-point searches: proof that no part of the curve lies
** nearer than the foot found, or the nearer foot.
**
** The sample-and-Newton search of curve_geom.c finds a local minimum of the distance; a
** valley narrower than the samples (a thin spike's tip, a span next to a sliver) can hide
** a nearer one. Here every span is a Bezier piece (its control points by blossoming,
** homogeneous for NURBS), and the squared distance over a piece is, with H(t) = C_w(t) -
** P w(t), the ratio N(t) / W(t) of two Bernstein polynomials of degree 2p, N = |H|^2 and
** W = w^2. Three facts decide a piece without sampling it:
**   - N - t W >= 0 on the piece when all its Bernstein coefficients are (their convex
**     hull holds the graph): then no point of the piece is nearer than sqrt(t);
**   - the derivative of N / W has the sign of N'W - NW', whose Bernstein coefficients
**     change sign at least as often as it does (variation diminishing): with one change
**     from - to + the piece has a single minimum, found by Newton inside the piece; with
**     none, or from + to -, its minimum is at an end;
**   - otherwise the piece is halved (de Casteljau) and both halves decided the same way.
** Pieces are reached through a strip tree (Ballard 1981: each node a chord and a width
** that holds its pieces, the control points' hull lying within it: weights are positive),
** searched from the foot's leaf up, so a point near the curve looks at the few pieces that
** come within the distance found: O(log spans) per point. Spans of zero length are no
** piece; a sliver span is a piece like any other, tiny (Newton in it is finished a double
** at a time by curve_geom.c).
**
** The guarantee: the distance returned is at most (1 + PIECE_REL) times the true minimum
** plus PIECE_ABS times the extent of the control points (and the rounding of the
** coordinates). A foot is replaced only by one nearer by more than that, so a search that
** was right keeps its answer bit for bit.
*/
#include "curve_ops_internal.h"

#include <math.h>
#include <stdint.h>
#include <string.h>

#define PIECE_REL 1e-9        /* relative tolerance of the distance */
#define PIECE_ABS 1e-13       /* absolute tolerance, times the curve's extent */
#define PIECE_LEAF 4          /* pieces per leaf of the strip tree at most */
#define PIECE_MAX_DEPTH 40    /* halvings of a span at most */
#define PIECE_TREE_STACK 64   /* pending nodes: one per level at most */
#define PIECE_COEF (4 * BSFIT_MAX_DEGREE + 1)
#define STRIP(d) (2 * (d) + 2) /* doubles of a strip: A, B, width, 1 / |B - A|^2 (or 0) */

/* {====================================================================
** Building: the pieces, the strips, the binomials, the scratch
** ===================================================================== */

/* Room for the blocks below, doubles first: strips (nnode * (2d+1)), binomials
** ((4p+1)^2), the piece stack ((PIECE_MAX_DEPTH + 3) pieces of (p+1) hd), the spans'
** pieces and strips (ns of each), then the spans (ns). 0 on overflow. */
static size_t block_doubles(const bsfit__pieces *pc) {
  size_t p1 = (size_t)pc->p + 1, nb = 4 * (size_t)pc->p + 1, w = p1 * (size_t)pc->hd;
  size_t k = STRIP((size_t)pc->d), fixed = pc->nnode * k + nb * nb + (PIECE_MAX_DEPTH + 3) * w;
  size_t pieces = bsfit__mulsize(pc->ns, w + k);
  return pieces == 0 || pieces > SIZE_MAX / sizeof(double) - fixed ? 0 : fixed + pieces;
}

/* The Bezier control points of span s (homogeneous: (w x, w) when rational) into B, each
** the blossom of the span at (a^(p-i), b^i) by de Boor's scheme with a new argument at
** each level. The denominators are at least the span's length: never zero. */
static void span_bezier(const bsfit__pieces *pc, size_t s, double *B) {
  const bsfit_curve *c = pc->c;
  const double *U = c->knots;
  size_t p = (size_t)pc->p, hd = (size_t)pc->hd, d = (size_t)pc->d, i, j, r, q;
  double T[(BSFIT_MAX_DEGREE + 1) * 5];
  for (i = 0; i <= p; i++) {
    for (j = 0; j <= p; j++) {
      size_t k = s - p + j;
      double w = c->weights ? c->weights[k] : 1.0;
      for (q = 0; q < d; q++) T[j * hd + q] = w * c->ctrl[k * d + q];
      if (hd > d) T[j * hd + d] = w;
    }
    for (r = 1; r <= p; r++) {
      double x = r <= p - i ? U[s] : U[s + 1];
      for (j = p; j >= r; j--) {
        double lo = U[s - p + j], al = (x - lo) / (U[s + 1 + j - r] - lo);
        for (q = 0; q < hd; q++)
          T[j * hd + q] = (1.0 - al) * T[(j - 1) * hd + q] + al * T[j * hd + q];
      }
    }
    memcpy(B + i * hd, T + p * hd, hd * sizeof(double));
  }
}

#if defined(__GNUC__)
#  define PIECE_INLINE static inline __attribute__((always_inline))
#else
#  define PIECE_INLINE static inline
#endif

/* The squared distance from x to the segment [A, B] (d coordinates; inv: 1 / |B - A|^2,
** 0 when A = B). */
PIECE_INLINE double seg_dist2(const double *x, const double *A, const double *B, double inv,
                              const size_t d) {
  double ax = 0.0, t, r = 0.0;
  size_t q;
  for (q = 0; q < d; q++) ax += (x[q] - A[q]) * (B[q] - A[q]);
  t = ax * inv;
  t = t < 0.0 ? 0.0 : (t > 1.0 ? 1.0 : t);
  for (q = 0; q < d; q++) {
    double e = x[q] - A[q] - t * (B[q] - A[q]);
    r += e * e;
  }
  return r;
}

/* 1 / |B - A|^2 of a chord, 0 when it has no length (its distances are then to A) */
static double chord_inv(const double *A, const double *B, size_t d) {
  double ab = 0.0;
  size_t q;
  for (q = 0; q < d; q++) ab += (B[q] - A[q]) * (B[q] - A[q]);
  return ab > 0.0 && isfinite(1.0 / ab) ? 1.0 / ab : 0.0;
}

/* the distance from x to strip S's chord */
static double chord_dist(const double *x, const double *S, size_t d) {
  return sqrt(seg_dist2(x, S, S + d, S[2 * d + 1], d));
}

/* The strip of piece i (its chord's ends, then its width: the farthest of its control
** points from the chord, which bounds every point of the piece, as the distance to a
** segment is convex and the piece lies in its control points' hull) into S (2d+1). */
static void span_strip(const bsfit__pieces *pc, size_t i, double *S) {
  size_t j, q, d = (size_t)pc->d, hd = (size_t)pc->hd, p = (size_t)pc->p;
  const double *B = pc->bez + i * (p + 1) * hd;
  double x[4];
  for (q = 0; q < d; q++) {
    S[q] = hd > d ? B[q] / B[d] : B[q];
    S[d + q] = hd > d ? B[p * hd + q] / B[p * hd + d] : B[p * hd + q];
  }
  S[2 * d] = 0.0;
  S[2 * d + 1] = chord_inv(S, S + d, d);
  for (j = 1; j < p; j++) {
    for (q = 0; q < d; q++) x[q] = hd > d ? B[j * hd + q] / B[j * hd + d] : B[j * hd + q];
    S[2 * d] = fmax(S[2 * d], chord_dist(x, S, d));
  }
}

/* The strip of node `node` at `level` (pieces [lo, hi)) and those below it (a strip tree,
** Ballard 1981): its chord from the first piece's start to the last one's end, its width
** the largest of its parts' widths plus their ends' distance from the chord. */
static void strip_node(bsfit__pieces *pc, size_t node, int level, size_t lo, size_t hi) {
  size_t d = (size_t)pc->d, k = STRIP(d), mid = lo + (hi - lo) / 2, c = 2 * node + 1, i, n;
  double *S = pc->strip + node * k, *part;
  if (lo >= hi) return; /* an empty node: never reached by the search */
  if (level == pc->depth) {
    for (i = lo; i < hi; i++) span_strip(pc, i, pc->sstrip + i * k);
    part = pc->sstrip + lo * k, n = hi - lo;
  } else {
    strip_node(pc, c, level + 1, lo, mid);
    strip_node(pc, c + 1, level + 1, mid, hi);
    part = pc->strip + c * k, n = mid > lo ? 2 : 1;
    if (mid == lo) part += k;
  }
  memcpy(S, part, d * sizeof(double));
  memcpy(S + d, part + (n - 1) * k + d, d * sizeof(double));
  S[2 * d] = 0.0;
  S[2 * d + 1] = chord_inv(S, S + d, d);
  for (i = 0; i < n; i++) {
    const double *Q = part + i * k;
    double w = fmax(chord_dist(Q, S, d), chord_dist(Q + d, S, d)) + Q[2 * d];
    S[2 * d] = fmax(S[2 * d], w);
  }
}

static void fill_binomials(bsfit__pieces *pc) {
  size_t n, k, nb = 4 * (size_t)pc->p + 1;
  double *C = pc->binom;
  for (n = 0; n < nb; n++)
    for (k = 0; k < nb; k++)
      C[n * nb + k] = k == 0 || k == n ? 1.0
                      : k > n          ? 0.0
                                       : C[(n - 1) * nb + k - 1] + C[(n - 1) * nb + k];
}

static double extent(const bsfit_curve *c) {
  size_t i, q, d = (size_t)c->dim;
  double ext = 0.0;
  for (q = 0; q < d; q++) {
    double lo = INFINITY, hi = -INFINITY;
    for (i = 0; i < c->n; i++) lo = fmin(lo, c->ctrl[i * d + q]), hi = fmax(hi, c->ctrl[i * d + q]);
    ext = fmax(ext, hi - lo);
  }
  return ext;
}

bsfit_err bsfit__pieces_init(bsfit__pieces *pc, const bsfit_curve *c, const bsfit_allocator *a,
                             bsfit_status *st) {
  size_t s, ns = 0, nd, bytes;
  size_t w = ((size_t)c->degree + 1) * ((size_t)c->dim + (c->weights != NULL));
  memset(pc, 0, sizeof *pc);
  pc->c = c;
  pc->p = c->degree;
  pc->d = c->dim;
  pc->hd = c->dim + (c->weights != NULL);
  if (a != NULL) pc->alloc = *a;
  for (s = (size_t)c->degree; s < c->n; s++) ns += c->knots[s + 1] > c->knots[s];
  pc->ns = ns;
  while (ns > 0 && ((ns - 1) >> pc->depth) + 1 > PIECE_LEAF) pc->depth++;
  pc->nnode = ((size_t)2 << pc->depth) - 1;
  nd = block_doubles(pc);
  bytes = bsfit__mulsize(nd, sizeof(double));
  if (nd == 0 || bytes == 0 || bytes > SIZE_MAX - ns * sizeof(size_t))
    return bsfit__fail(st, BSFIT_ENOMEM, "search tree of %zu spans too large", ns);
  pc->bytes = bytes + ns * sizeof(size_t);
  pc->block = bsfit__alloc(&pc->alloc, pc->bytes);
  if (pc->block == NULL)
    return bsfit__fail(st, BSFIT_ENOMEM, "out of memory for the search tree of %zu spans", ns);
  pc->strip = pc->block;
  pc->binom = pc->strip + pc->nnode * STRIP((size_t)pc->d);
  pc->stack = pc->binom + (4 * (size_t)pc->p + 1) * (4 * (size_t)pc->p + 1);
  pc->bez = pc->stack + (PIECE_MAX_DEPTH + 3) * w;
  pc->sstrip = pc->bez + ns * w;
  pc->span = (size_t *)(void *)((double *)pc->block + nd);
  for (s = (size_t)c->degree, ns = 0; s < c->n; s++)
    if (c->knots[s + 1] > c->knots[s]) {
      span_bezier(pc, s, pc->bez + ns * w);
      pc->span[ns++] = s;
    }
  strip_node(pc, 0, 0, 0, pc->ns);
  fill_binomials(pc);
  pc->abs_tol = PIECE_ABS * extent(c);
  return bsfit__ok(st);
}

void bsfit__pieces_free(bsfit__pieces *pc) {
  if (pc == NULL) return;
  bsfit__free(&pc->alloc, pc->block, pc->bytes);
  pc->block = NULL;
  pc->bytes = 0;
}

/* }==================================================================== */

/* {====================================================================
** One piece: Bernstein coefficients and the decision
** ===================================================================== */

/* The piece's halves at t = 1/2 (de Casteljau): B becomes the left half, R the right. */
static void halve(const bsfit__pieces *pc, double *B, double *R) {
  size_t p = (size_t)pc->p, hd = (size_t)pc->hd, r, j, q;
  memcpy(R + p * hd, B + p * hd, hd * sizeof(double));
  for (r = 1; r <= p; r++) {
    for (j = p; j >= r; j--)
      for (q = 0; q < hd; q++) B[j * hd + q] = 0.5 * (B[(j - 1) * hd + q] + B[j * hd + q]);
    memcpy(R + (p - r) * hd, B + p * hd, hd * sizeof(double));
  }
}

/* c (degree na + nb) = a (degree na) times b (degree nb), Bernstein coefficients */
static void bern_mul(const bsfit__pieces *pc, const double *x, size_t na, const double *y,
                     size_t nb, double *z) {
  size_t i, j, w = 4 * (size_t)pc->p + 1;
  const double *C = pc->binom;
  for (i = 0; i <= na + nb; i++) z[i] = 0.0;
  for (i = 0; i <= na; i++)
    for (j = 0; j <= nb; j++) z[i + j] += C[na * w + i] * C[nb * w + j] * x[i] * y[j];
  for (i = 0; i <= na + nb; i++) z[i] /= C[(na + nb) * w + i];
}

/* N = |H|^2 and W = w^2 of piece B for point P (degree 2p each; W NULL: polynomial) */
static void distance_poly(const bsfit__pieces *pc, const double *B, const double *P, double *N,
                          double *W) {
  size_t p = (size_t)pc->p, hd = (size_t)pc->hd, d = (size_t)pc->d, i, j, q;
  size_t w = 4 * (size_t)pc->p + 1;
  double H[(BSFIT_MAX_DEGREE + 1) * 4];
  const double *C = pc->binom + p * w;
  for (i = 0; i <= p; i++) {
    double wi = hd > d ? B[i * hd + d] : 1.0;
    for (q = 0; q < d; q++) H[i * d + q] = B[i * hd + q] - wi * P[q];
  }
  for (i = 0; i <= 2 * p; i++) N[i] = 0.0;
  for (i = 0; i <= p; i++)
    for (j = i; j <= p; j++) {
      double dot = 0.0;
      for (q = 0; q < d; q++) dot += H[i * d + q] * H[j * d + q];
      N[i + j] += (i == j ? 1.0 : 2.0) * C[i] * C[j] * dot;
    }
  for (i = 0; i <= 2 * p; i++) N[i] /= pc->binom[2 * p * w + i];
  if (W != NULL) {
    double wt[BSFIT_MAX_DEGREE + 1];
    for (i = 0; i <= p; i++) wt[i] = B[i * hd + d];
    bern_mul(pc, wt, p, wt, p, W);
  }
}

/* The sign changes of the derivative of N / W (W NULL: 1) over the piece: their number
** (zeros skipped), *first the sign of the first non-zero coefficient, *at the index of the
** first change over the number of coefficients less one (where the minimum lies, about). */
static int slope_changes(const bsfit__pieces *pc, const double *N, const double *W, int *first,
                         double *at) {
  size_t p2 = 2 * (size_t)pc->p, i, n;
  double G[PIECE_COEF], dN[PIECE_COEF], dW[PIECE_COEF], T[PIECE_COEF];
  int changes = 0, sign = 0;
  *first = 0;
  *at = 0.5;
  if (p2 == 0) return 0; /* degree 0: the piece is a point */
  for (i = 0; i < p2; i++) dN[i] = N[i + 1] - N[i];
  if (W == NULL) {
    memcpy(G, dN, p2 * sizeof(double));
    n = p2;
  } else {
    for (i = 0; i < p2; i++) dW[i] = W[i + 1] - W[i];
    bern_mul(pc, dN, p2 - 1, W, p2, G);
    bern_mul(pc, N, p2, dW, p2 - 1, T);
    n = 2 * p2;
    for (i = 0; i < n; i++) G[i] -= T[i];
  }
  for (i = 0; i < n; i++) {
    int sg = G[i] > 0.0 ? 1 : (G[i] < 0.0 ? -1 : 0);
    if (sg == 0) continue;
    if (sign == 0) *first = sg;
    else if (sg != sign) {
      if (changes == 0) *at = ((double)i - 0.5) / (double)(n > 1 ? n - 1 : 1);
      changes++;
    }
    sign = sg;
  }
  return changes;
}

/* }==================================================================== */

/* {====================================================================
** The search
** ===================================================================== */

typedef struct search {
  bsfit__pieces *pc;
  const double *P;
  double *u, *d2;
  double r, t; /* a foot replaces the one found when nearer than r (squared: t): a
               ** tolerance nearer; r < 0 when the foot is within the tolerance of P */
  int critical; /* the foot given is where Newton converged, inside its bracket */
  bsfit__polish_fn polish;
  void *ctx;
} search;

static void set_threshold(search *S) {
  S->r = sqrt(*S->d2) * (1.0 - PIECE_REL) - S->pc->abs_tol;
  S->t = S->r > 0.0 ? S->r * S->r : -1.0;
}

/* Newton inside [lo, hi] from u0; the foot replaces the best when it is nearer than t. */
static void try_foot(search *S, double lo, double hi, double u0) {
  double e2, x = S->polish(S->ctx, lo, hi, u0, &e2);
  if (e2 < S->t) {
    *S->u = x, *S->d2 = e2;
    set_threshold(S);
  }
}

/* Whether N - t W has a negative coefficient (the piece may come nearer than sqrt(t)). */
static int may_beat(const double *N, const double *W, size_t n, double t) {
  size_t i;
  for (i = 0; i < n; i++)
    if (N[i] - t * (W ? W[i] : 1.0) < 0.0) return 1;
  return 0;
}

/* Decides the piece B over [ua, ub] at `depth`; returns 1 when it must be halved. */
static int decide(search *S, const double *B, double ua, double ub, int depth) {
  const bsfit__pieces *pc = S->pc;
  size_t p2 = 2 * (size_t)pc->p;
  double N[PIECE_COEF], Wb[PIECE_COEF], *W = pc->hd > pc->d ? Wb : NULL, at;
  int first, v;
  if (S->t < 0.0) return 0;
  distance_poly(pc, B, S->P, N, W);
  if (!may_beat(N, W, p2 + 1, S->t)) return 0;
  /* the ends are points of the curve */
  if (N[0] < S->t * (W ? W[0] : 1.0)) try_foot(S, ua, ub, ua);
  if (S->t >= 0.0 && N[p2] < S->t * (W ? W[p2] : 1.0)) try_foot(S, ua, ub, ub);
  if (S->t < 0.0) return 0;
  v = slope_changes(pc, N, W, &first, &at);
  if (v == 0 || (v == 1 && first > 0)) return 0; /* the minimum is at an end */
  if (v == 1) {
    /* a single minimum inside: the foot given, when it lies inside the piece and Newton
    ** converged there (not in a sliver, where its test of convergence, relative to |u|,
    ** passes anywhere); else Newton from the foot (inside) or from the sign change */
    int inside = *S->u > ua && *S->u < ub;
    if (!(inside && S->critical && ub - ua > 1e-6 * (fabs(ua) + fabs(ub))))
      try_foot(S, ua, ub, inside ? *S->u : ua + at * (ub - ua));
    return 0;
  }
  if (depth < PIECE_MAX_DEPTH && ua < 0.5 * (ua + ub) && 0.5 * (ua + ub) < ub) return 1;
  try_foot(S, ua, ub, 0.5 * (ua + ub)); /* no finer halving: Newton from its middle */
  return 0;
}

/* Piece i decided, halving it as often as needed (a stack of pieces, one per level). */
static void search_span(search *S, size_t i) {
  bsfit__pieces *pc = S->pc;
  size_t w = ((size_t)pc->p + 1) * (size_t)pc->hd, top = 1;
  const double *U = pc->c->knots;
  double lo[PIECE_MAX_DEPTH + 3], hi[PIECE_MAX_DEPTH + 3];
  int dep[PIECE_MAX_DEPTH + 3];
  size_t s = pc->span[i];
  memcpy(pc->stack, pc->bez + i * w, w * sizeof(double));
  lo[0] = U[s], hi[0] = U[s + 1], dep[0] = 0;
  while (top > 0) {
    double *B = pc->stack + (top - 1) * w;
    top--;
    if (decide(S, B, lo[top], hi[top], dep[top])) {
      double m = 0.5 * (lo[top] + hi[top]);
      /* left half stays in place, the right one above it; the left is decided first */
      memcpy(B + w, B, w * sizeof(double));
      halve(pc, B + w, B);
      lo[top + 1] = lo[top], hi[top + 1] = m, dep[top + 1] = dep[top] + 1;
      lo[top] = m, dep[top] = dep[top] + 1;
      top += 2;
    }
  }
}

/* Whether strip S may hold a point nearer to P than r (r >= 0): its chord is nearer
** than r plus its width. Squared: no root per node. */
PIECE_INLINE int strip_near_d(const double *S, const double *P, double r, const size_t d) {
  double g = r + S[2 * d];
  return seg_dist2(P, S, S + d, S[2 * d + 1], d) < g * g;
}

/* strip_near_d with d a constant for sections (2) and space curves (3): the loops unroll */
static int strip_near(const double *S, const double *P, double r, size_t d) {
  if (d == 2) return strip_near_d(S, P, r, 2);
  if (d == 3) return strip_near_d(S, P, r, 3);
  return strip_near_d(S, P, r, d);
}

/* The tree below node (at `level`, pieces [lo, hi)) searched depth first, in the order of
** the parameter; a foot found prunes what follows. */
static void search_tree(search *S, size_t node, size_t lo, size_t hi) {
  bsfit__pieces *pc = S->pc;
  size_t stack[PIECE_TREE_STACK][3], top = 0, d = (size_t)pc->d, k = STRIP(d);
  stack[top][0] = node, stack[top][1] = lo, stack[top][2] = hi, top++;
  while (top > 0 && S->r >= 0.0) {
    size_t i, c, mid;
    top--;
    node = stack[top][0], lo = stack[top][1], hi = stack[top][2];
    if (lo >= hi || !strip_near(pc->strip + node * k, S->P, S->r, d)) continue;
    if (2 * node + 1 >= pc->nnode) {
      for (i = lo; i < hi && S->r >= 0.0; i++)
        if (strip_near(pc->sstrip + i * k, S->P, S->r, d)) search_span(S, i);
      continue;
    }
    c = 2 * node + 1, mid = lo + (hi - lo) / 2;
    stack[top][0] = c + 1, stack[top][1] = mid, stack[top][2] = hi, top++;
    stack[top][0] = c, stack[top][1] = lo, stack[top][2] = mid, top++;
  }
}

/* The piece holding parameter u (wrapped into the domain), by bisection of the spans. */
static size_t piece_of(const bsfit__pieces *pc, double u) {
  const double *U = pc->c->knots;
  size_t lo = 0, hi = pc->ns;
  u = bsfit__curve_wrap(pc->c, u);
  while (hi - lo > 1) {
    size_t mid = lo + (hi - lo) / 2;
    if (U[pc->span[mid]] <= u) lo = mid;
    else hi = mid;
  }
  return lo;
}

void bsfit__pieces_search(bsfit__pieces *pc, const double *P, double *u, double *d2,
                          int critical, bsfit__polish_fn polish, void *ctx) {
  size_t path[PIECE_TREE_STACK][3], node = 0, lo = 0, hi = pc->ns, f;
  int level;
  search S;
  S.pc = pc, S.P = P, S.u = u, S.d2 = d2, S.polish = polish, S.ctx = ctx;
  S.critical = critical;
  set_threshold(&S);
  if (pc->ns == 0 || S.r < 0.0) return;
  /* from the leaf of the foot's piece up: each ancestor's other child in turn (the foot
  ** prunes most of them; the path itself holds the foot, no test needed) */
  f = piece_of(pc, *u);
  for (level = 0; level < pc->depth; level++) {
    size_t mid = lo + (hi - lo) / 2;
    path[level][0] = node, path[level][1] = lo, path[level][2] = hi;
    node = 2 * node + 1;
    if (f >= mid) node++, lo = mid;
    else hi = mid;
  }
  search_tree(&S, node, lo, hi);
  for (level = pc->depth - 1; level >= 0 && S.r >= 0.0; level--) {
    size_t pn = path[level][0], plo = path[level][1], phi = path[level][2];
    size_t pmid = plo + (phi - plo) / 2, c = 2 * pn + 1;
    if (node == c) search_tree(&S, c + 1, pmid, phi);
    else search_tree(&S, c, plo, pmid);
    node = pn;
  }
}

/* }==================================================================== */
