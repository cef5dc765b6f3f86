/*
** nearest_sample.c
** The nearest of K sample points (dimension 1..4) to a query point, exactly as a linear
** scan finds it: the smallest squared distance sum_q (x_q - P_q)^2, summed in order of q
** from 0.0, the first (smallest) sample index among equals. bsfit_curve_closest_many
** brackets each point by its nearest coarse sample of the curve; a scan costs O(K) per
** point, this index O(log K) for points near the curve.
**
** Large sample sets get a static k-d tree: median splits on the widest coordinate, a tight
** bounding box per node, leaves of at most NEAREST_LEAF samples, all in one allocation.
** Because the splits halve the counts, every leaf lies at the same depth and the tree is
** implicit (node i has children 2i+1, 2i+2; a node's range is recomputed on the way down),
** so the block holds only the samples in tree order, their indices and the boxes.
**
** The medians are the build's cost (at 10^6 points a periodic fit's curve has 4.5 * 10^6
** samples): they are found on compact float keys, with a pivot of about the right rank
** from a sample of the keys and a branch-free partition; at 4.5 * 10^6 samples these took
** the build from 0.80 s to 0.45 s.
*/
#include "curve_ops_internal.h"

#include <math.h>
#include <stdint.h>
#include <string.h>

/* Measured with bsfit_curve_closest_many on closed cubics of 4 to 2000 spans: leaves of 16
** samples beat leaves of 4 and 8 and equal 32. The whole call takes as long with a tree as
** with scans at 36 samples and a third less at 72; and at 16 points the build costs what
** the descents save, at 32 points the tree is ahead for every K measured. On the curves
** of bench_scale's sections (22 to 5 * 10^5 spans) leaves of 32 are within 5% of the
** best of 16 and 64 everywhere (16: 8% slower at 10^6 points; 64: 10% slower at 22 spans). */
#define NEAREST_LEAF 32        /* samples per leaf at most */
#define NEAREST_MIN_K 48       /* fewer samples: scan */
#define NEAREST_MIN_QUERIES 32 /* fewer points: scan */
#define PIVOT_SAMPLES 31       /* keys a large range's pivot is chosen among */
#define PART_BLOCK 64          /* keys per block of block_partition */
#define SELECT_ROUNDS 64       /* partition rounds per median at most (see select_mid) */
#define NEAREST_STACK 64       /* pending nodes: one per level at most, and depth < 64 */

/* {====================================================================
** Distances
** ===================================================================== */

/* |x - P|^2 with the arithmetic of the scan that defines the answer (and of the curve's
** own sample loop): one product per coordinate, summed in order from 0.0. */
static inline double dist2(const double *x, const double *P, size_t d) {
  double dd = 0.0;
  size_t q;
  for (q = 0; q < d; q++) dd += (x[q] - P[q]) * (x[q] - P[q]);
  return dd;
}

/* A lower bound of dist2(x, P) for every x in the box [lo, hi], valid in floating point,
** not only in exact arithmetic: per coordinate the gap g is one rounded subtraction of a
** box face, so |fl(x_q - P_q)| >= g (rounding is monotone and symmetric), hence
** fl(g*g) <= fl((x_q - P_q)^2), and a sum of smaller terms in the same order is not
** larger. A node is skipped only when this bound exceeds the best distance, so no sample
** that could equal or beat it is ever skipped: the result is the scan's, bit for bit. */
static inline double box_bound(const double *lo, const double *hi, const double *P, size_t d) {
  double lb = 0.0;
  size_t q;
  for (q = 0; q < d; q++) {
    double g = P[q] < lo[q] ? lo[q] - P[q] : (P[q] > hi[q] ? P[q] - hi[q] : 0.0);
    lb += g * g;
  }
  return lb;
}

static size_t scan(const double *smp, size_t K, size_t d, const double *P) {
  double best = INFINITY;
  size_t k, kb = 0;
  for (k = 0; k < K; k++) {
    double dd = dist2(smp + k * d, P, d);
    if (dd < best) {
      best = dd;
      kb = k;
    }
  }
  return kb;
}

/* }==================================================================== */

/* {====================================================================
** Building the tree
** ===================================================================== */

/* The order is decided on compact copies: each coordinate scaled into [0, 1] across the
** samples' box and rounded to a float, with a 32-bit sample number, 12 bytes a 2D sample
** where the doubles and a size_t take 24: half the memory the swaps move. Rounding only
** decides where ties fall: the boxes are measured on the doubles afterwards. */
typedef struct build_ctx {
  float *key;   /* K*d scaled coordinates, reordered with id */
  uint32_t *id; /* the sample number of each position */
  size_t d;
  int depth;
} build_ctx;

#define KEY(B, i, q) ((B)->key[(i) * (B)->d + (q)])

/* The keys are moved with their numbers, not through them: the partitions then read
** memory in order. */
static void swap_keys(const build_ctx *B, size_t i, size_t j) {
  uint32_t t = B->id[i];
  size_t q;
  B->id[i] = B->id[j];
  B->id[j] = t;
  for (q = 0; q < B->d; q++) {
    float x = KEY(B, i, q);
    KEY(B, i, q) = KEY(B, j, q);
    KEY(B, j, q) = x;
  }
}

/* The bulk of a Hoare partition around piv by blocks (BlockQuicksort, Edelkamp and Weiss
** 2016): the keys of a block from each end are compared without branches, noting the
** positions on the wrong side, and those are swapped in pairs. On return positions before
** *pi hold keys <= piv and positions after *pj keys >= piv; the plain scans finish. */
static void block_partition(const build_ctx *B, size_t q, float piv, size_t *pi, size_t *pj) {
  unsigned char offl[PART_BLOCK], offr[PART_BLOCK];
  size_t l = *pi, r = *pj, nl = 0, nr = 0, sl = 0, sr = 0, t, n;
  while (r - l + 1 >= 2 * PART_BLOCK) {
    if (nl == 0) { /* keys that belong right (>= piv) in [l, l + PART_BLOCK) */
      sl = 0;
      for (t = 0; t < PART_BLOCK; t++) {
        offl[nl] = (unsigned char)t;
        nl += !(KEY(B, l + t, q) < piv);
      }
    }
    if (nr == 0) { /* keys that belong left (<= piv) in (r - PART_BLOCK, r] */
      sr = 0;
      for (t = 0; t < PART_BLOCK; t++) {
        offr[nr] = (unsigned char)t;
        nr += !(KEY(B, r - t, q) > piv);
      }
    }
    n = nl < nr ? nl : nr;
    for (t = 0; t < n; t++) swap_keys(B, l + offl[sl + t], r - offr[sr + t]);
    nl -= n;
    nr -= n;
    sl += n;
    sr += n;
    if (nl == 0) l += PART_BLOCK;
    if (nr == 0) r -= PART_BLOCK;
  }
  *pi = l;
  *pj = r;
}

/* The key of rank about k among PIVOT_SAMPLES keys spread evenly over positions [lo, hi):
** the first partition then lands near k, and the next ones, on the short side left, too.
** A key of the range, so each scan of the partition finds one to stop at. */
static float sampled_pivot(const build_ctx *B, size_t lo, size_t hi, size_t k, size_t q) {
  float v[PIVOT_SAMPLES];
  size_t i, j, step = (hi - lo) / PIVOT_SAMPLES, r = (k - lo) * PIVOT_SAMPLES / (hi - lo);
  for (i = 0; i < PIVOT_SAMPLES; i++) { /* insertion sort as they are read */
    float x = KEY(B, lo + i * step, q);
    for (j = i; j > 0 && v[j - 1] > x; j--) v[j] = v[j - 1];
    v[j] = x;
  }
  return v[r < PIVOT_SAMPLES ? r : PIVOT_SAMPLES - 1];
}

/* Reorders positions lo..hi-1 so that position k holds the median by coordinate q,
** smaller keys before it and larger after (quickselect, median-of-three pivot, Hoare
** partition, which splits runs of equal keys evenly: every knot's sample appears twice).
** The split only decides speed, never the answer (the boxes are measured afterwards), so
** a pathological input stops after SELECT_ROUNDS partitions instead of going quadratic. */
static void select_mid(const build_ctx *B, size_t lo, size_t hi, size_t k, size_t q) {
  int round;
  for (round = 0; round < SELECT_ROUNDS && hi - lo > 2; round++) {
    size_t i = lo, j = hi - 1, mid = lo + (hi - lo) / 2;
    float a = KEY(B, lo, q), b = KEY(B, mid, q), c = KEY(B, hi - 1, q), piv;
    piv = a < b ? (b < c ? b : (a < c ? c : a)) : (a < c ? a : (b < c ? c : b));
    if (hi - lo >= 8 * PIVOT_SAMPLES) piv = sampled_pivot(B, lo, hi, k, q);
    /* with at least three keys and a median-of-three pivot, both sides get at least one
    ** element: at least two of the three are <= piv and two >= piv */
    block_partition(B, q, piv, &i, &j);
    for (;;) {
      while (KEY(B, i, q) < piv) i++;
      while (KEY(B, j, q) > piv) j--;
      if (i >= j) break;
      swap_keys(B, i, j);
      i++;
      j--;
    }
    /* now positions lo..j hold keys <= piv, j+1..hi-1 keys >= piv */
    if (k <= j) hi = j + 1;
    else lo = j + 1;
  }
  if (hi - lo == 2 && KEY(B, lo, q) > KEY(B, lo + 1, q)) swap_keys(B, lo, lo + 1);
}

/* Node `node` at `level` holds positions [lo, hi) inside `cell` (lower corner, upper
** corner, in key space; its parent's cell cut at the parent's median): split across the
** cell's widest side. The cell is as good a guide to the widest side as the node's own
** box, which would cost a pass over its keys per level. */
static void order_node(const build_ctx *B, int level, size_t lo, size_t hi, float *cell) {
  float wide = -1.0f, cut, keep;
  size_t q, d = B->d, axis = 0, mid = lo + (hi - lo) / 2;
  if (level == B->depth) return;
  for (q = 0; q < d; q++)
    if (cell[d + q] - cell[q] > wide) {
      wide = cell[d + q] - cell[q];
      axis = q;
    }
  if (hi - lo > 1) select_mid(B, lo, hi, mid, axis);
  cut = mid < hi ? KEY(B, mid, axis) : cell[d + axis];
  keep = cell[d + axis];
  cell[d + axis] = cut;
  order_node(B, level + 1, lo, mid, cell);
  cell[d + axis] = keep;
  keep = cell[axis];
  cell[axis] = cut;
  order_node(B, level + 1, mid, hi, cell);
  cell[axis] = keep;
}

/* The tight box of positions [lo, hi) of the ordered samples into box (lower corner,
** upper corner). Empty: every bound is +inf. */
static void measure(const bsfit__nearest *nn, size_t lo, size_t hi, double *box) {
  size_t i, q, d = nn->d;
  for (q = 0; q < d; q++) {
    double blo = INFINITY, bhi = -INFINITY;
    for (i = lo; i < hi; i++) {
      double x = nn->pts[i * d + q];
      blo = x < blo ? x : blo;
      bhi = x > bhi ? x : bhi;
    }
    box[q] = blo;
    box[d + q] = bhi;
  }
}

/* The boxes of node `node` at `level` (positions [lo, hi)) and below: a leaf's measured,
** an inner node's the union of its halves'. */
static void box_node(const bsfit__nearest *nn, size_t node, int level, size_t lo, size_t hi) {
  size_t q, d = nn->d, mid = lo + (hi - lo) / 2, c = 2 * node + 1;
  double *box = nn->box + node * 2 * d, *b1 = nn->box + c * 2 * d, *b2 = b1 + 2 * d;
  if (level == nn->depth) {
    measure(nn, lo, hi, box);
    return;
  }
  box_node(nn, c, level + 1, lo, mid);
  box_node(nn, c + 1, level + 1, mid, hi);
  for (q = 0; q < d; q++) {
    box[q] = b1[q] < b2[q] ? b1[q] : b2[q];
    box[d + q] = b1[d + q] > b2[d + q] ? b1[d + q] : b2[d + q];
  }
}

/* The samples of nn in tree order (into nn->pts, their numbers into nn->idx), ordered on
** keys in `scratch` (K*d floats, then K uint32). */
static void order_samples(bsfit__nearest *nn, void *scratch) {
  size_t i, q, d = nn->d, K = nn->K;
  double lo[4], inv[4];
  float cell[2 * 4];
  build_ctx B;
  B.key = scratch;
  B.id = (uint32_t *)(void *)(B.key + K * d);
  B.d = d;
  B.depth = nn->depth;
  for (q = 0; q < d; q++) {
    double hi = -INFINITY;
    lo[q] = INFINITY;
    for (i = 0; i < K; i++) {
      lo[q] = fmin(lo[q], nn->smp[i * d + q]);
      hi = fmax(hi, nn->smp[i * d + q]);
    }
    inv[q] = hi > lo[q] && isfinite(1.0 / (hi - lo[q])) ? 1.0 / (hi - lo[q]) : 0.0;
    cell[q] = 0.0f;
    cell[d + q] = 1.0f;
  }
  for (i = 0; i < K; i++) {
    B.id[i] = (uint32_t)i;
    for (q = 0; q < d; q++) KEY(&B, i, q) = (float)((nn->smp[i * d + q] - lo[q]) * inv[q]);
  }
  order_node(&B, 0, 0, K, cell);
  for (i = 0; i < K; i++) {
    nn->idx[i] = B.id[i];
    memcpy(nn->pts + i * d, nn->smp + (size_t)B.id[i] * d, d * sizeof(double));
  }
}

bsfit_err bsfit__nearest_init(bsfit__nearest *nn, const double *smp, size_t K, size_t d,
                              size_t queries, const bsfit_allocator *a, bsfit_status *st) {
  size_t nnode, nb, nd, ni, ns;
  void *scratch;
  int depth = 0;
  nn->smp = smp;
  nn->K = K;
  nn->d = d;
  nn->depth = -1;
  nn->nnode = 0;
  nn->block = NULL;
  nn->bytes = 0;
  nn->alloc.fn = NULL;
  nn->alloc.ud = NULL;
  nn->alloc.interrupt = NULL;
  if (a != NULL) nn->alloc = *a;
  /* a non-finite sample (an overflowing NURBS) would poison the boxes: the scan copes;
  ** so does it past 2^32 samples, which the sample numbers of the build cannot count */
  if (K < NEAREST_MIN_K || queries < NEAREST_MIN_QUERIES || K > UINT32_MAX ||
      !bsfit__all_finite(smp, K * d))
    return bsfit__ok(st);
  /* the smallest depth whose leaves (all at that depth, ceil(K / 2^depth) samples at
  ** most) hold NEAREST_LEAF samples or fewer */
  while (((K - 1) >> depth) + 1 > NEAREST_LEAF) depth++;
  nnode = ((size_t)2 << depth) - 1;
  nd = bsfit__mulsize(K, d);
  nb = bsfit__mulsize(nnode, 2 * d);
  ni = bsfit__mulsize(K, sizeof(size_t));
  ns = bsfit__mulsize(K, d * sizeof(float) + sizeof(uint32_t));
  /* doubles first, then the indices: both parts stay aligned */
  if (nd == 0 || nb == 0 || ni == 0 || ns == 0 || nd > SIZE_MAX / sizeof(double) - nb ||
      (nd + nb) * sizeof(double) > SIZE_MAX - ni)
    return bsfit__fail(st, BSFIT_ENOMEM, "search tree of %zu samples too large", K);
  nn->bytes = (nd + nb) * sizeof(double) + ni;
  nn->block = bsfit__alloc(&nn->alloc, nn->bytes);
  scratch = nn->block != NULL ? bsfit__alloc(&nn->alloc, ns) : NULL;
  if (scratch == NULL) {
    bsfit__free(&nn->alloc, nn->block, nn->bytes);
    nn->block = NULL;
    nn->bytes = 0;
    return bsfit__fail(st, BSFIT_ENOMEM, "out of memory for the search tree of %zu samples", K);
  }
  nn->pts = nn->block;
  nn->box = nn->pts + nd;
  nn->idx = (size_t *)(void *)(nn->box + nb);
  nn->nnode = nnode;
  nn->depth = depth;
  order_samples(nn, scratch);
  bsfit__free(&nn->alloc, scratch, ns);
  box_node(nn, 0, 0, 0, K);
  return bsfit__ok(st);
}

void bsfit__nearest_free(bsfit__nearest *nn) {
  if (nn == NULL) return;
  bsfit__free(&nn->alloc, nn->block, nn->bytes);
  nn->block = NULL;
  nn->bytes = 0;
  nn->depth = -1;
}

/* }==================================================================== */

/* {====================================================================
** Queries
** ===================================================================== */

typedef struct pending {
  size_t node, lo, hi;
  double lb; /* box_bound of the node, computed when it was pushed */
} pending;

#if defined(__GNUC__)
#  define FIND_INLINE static inline __attribute__((always_inline))
#else
#  define FIND_INLINE static inline
#endif

/* Branch and bound, depth first: at each node the nearer half is followed at once and the
** other is left pending with its bound. `d` is a constant in the instances below, so the
** loops over the coordinates of a section (2D) or a space curve (3D) unroll. */
FIND_INLINE size_t find_body(const bsfit__nearest *nn, const double *P, const size_t d) {
  pending stack[NEAREST_STACK];
  double best = INFINITY;
  size_t kb = SIZE_MAX, top = 0, node = 0, lo = 0, hi = nn->K;
  for (;;) {
    size_t j;
    if (2 * node + 1 < nn->nnode) { /* inner: descend into the nearer half */
      size_t c = 2 * node + 1, mid = lo + (hi - lo) / 2;
      const double *b1 = nn->box + c * 2 * d, *b2 = b1 + 2 * d;
      double lb1 = box_bound(b1, b1 + d, P, d), lb2 = box_bound(b2, b2 + d, P, d);
      /* strict tests: a node whose bound equals the best may hold an equal sample of
      ** smaller index (every knot's sample appears twice), and that one must win */
      if (lb1 <= lb2) {
        if (lb2 <= best) stack[top++] = (pending){c + 1, mid, hi, lb2};
        if (lb1 <= best) {
          node = c, hi = mid;
          continue;
        }
      } else {
        if (lb1 <= best) stack[top++] = (pending){c, lo, mid, lb1};
        if (lb2 <= best) {
          node = c + 1, lo = mid;
          continue;
        }
      }
    } else { /* leaf */
      for (j = lo; j < hi; j++) {
        double dd = dist2(nn->pts + j * d, P, d);
        if (dd < best || (dd == best && nn->idx[j] < kb)) {
          best = dd;
          kb = nn->idx[j];
        }
      }
    }
    /* the next pending node that may still hold the answer (`best` may have shrunk
    ** since it was pushed) */
    while (top > 0 && stack[top - 1].lb > best) top--;
    if (top == 0) break;
    top--;
    node = stack[top].node, lo = stack[top].lo, hi = stack[top].hi;
  }
  /* kb is set: nothing is pruned while best is +inf, so the first leaf is scanned; and
  ** when every distance overflows, the rule above keeps the smallest index among the
  ** infinite ones, 0, which is also the scan's answer */
  return kb;
}

size_t bsfit__nearest_find(const bsfit__nearest *nn, const double *P) {
  if (nn->depth < 0) return scan(nn->smp, nn->K, nn->d, P);
  if (nn->d == 2) return find_body(nn, P, 2);
  if (nn->d == 3) return find_body(nn, P, 3);
  return find_body(nn, P, nn->d);
}

/* }==================================================================== */
