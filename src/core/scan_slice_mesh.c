/*
** scan_slice_mesh.c
** Exact plane sections of a triangle mesh. Each vertex gets its signed height above
** the plane; heights within tol count as zero and zero is treated as +0 (a symbolic
** perturbation of the plane towards -normal... seen from the vertex, it is above), so
** every triangle is either uncut or cut along exactly two of its edges. A crossing point
** is named by its edge (the two vertex ids), so the segments of neighbouring triangles
** meet at the same node without comparing coordinates, and the segments chain into
** loops by walking the node graph. A vertex on the plane gives its own position (not an
** interpolation), so a vertex, an edge or a face lying on the plane yields the points of
** the plane itself; consecutive equal points are merged afterwards.
*/
#include "scan_sections.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

typedef struct slicer {
  const bsfit_scan *m;
  double *h; /* vertex heights along the normal */
  double tol;
  const bsfit_allocator *a;
  size_t cap;     /* candidate triangles the scratch below is sized for */
  uint64_t *keys; /* hash of edge keys, 4*cap rounded up to a power of 2 */
  uint32_t *slot; /* node id + 1 per hash slot */
  size_t hmask;
  double *nuv;   /* 2 per node */
  uint32_t *seg; /* 2 per segment */
  size_t *adj_start;
  uint32_t *adj, *chain;
  unsigned char *used;
  size_t nnodes, nsegs;
} slicer;

/* {======================================================================
** Scratch memory
** ====================================================================== */

static void scratch_free(slicer *S) {
  size_t c = S->cap, hs = S->hmask + 1;
  bsfit__free(S->a, S->keys, hs * sizeof(uint64_t));
  bsfit__free(S->a, S->slot, hs * sizeof(uint32_t));
  bsfit__free(S->a, S->nuv, 4 * c * sizeof(double));
  bsfit__free(S->a, S->seg, 2 * c * sizeof(uint32_t));
  bsfit__free(S->a, S->adj_start, (2 * c + 1) * sizeof(size_t));
  bsfit__free(S->a, S->adj, 2 * c * sizeof(uint32_t));
  bsfit__free(S->a, S->chain, (2 * c + 1) * sizeof(uint32_t));
  bsfit__free(S->a, S->used, c);
  S->keys = NULL;
  S->slot = NULL;
  S->nuv = NULL;
  S->seg = S->adj = S->chain = NULL;
  S->adj_start = NULL;
  S->used = NULL;
  S->cap = 0;
  S->hmask = 0;
}

/* Scratch for c candidate triangles (at most 2c nodes, c segments). */
static int scratch_alloc(slicer *S, size_t c) {
  size_t hs = 64;
  if (c < 16) c = 16;
  while (hs < 4 * c) hs *= 2;
  S->cap = c;
  S->hmask = hs - 1;
  S->keys = bsfit__alloc(S->a, hs * sizeof(uint64_t));
  S->slot = bsfit__alloc(S->a, hs * sizeof(uint32_t));
  S->nuv = bsfit__alloc(S->a, 4 * c * sizeof(double));
  S->seg = bsfit__alloc(S->a, 2 * c * sizeof(uint32_t));
  S->adj_start = bsfit__alloc(S->a, (2 * c + 1) * sizeof(size_t));
  S->adj = bsfit__alloc(S->a, 2 * c * sizeof(uint32_t));
  S->chain = bsfit__alloc(S->a, (2 * c + 1) * sizeof(uint32_t));
  S->used = bsfit__alloc(S->a, c);
  return S->keys && S->slot && S->nuv && S->seg && S->adj_start && S->adj && S->chain && S->used;
}

/* }====================================================================== */

/* {======================================================================
** Segments of one plane
** ====================================================================== */

/* The node of edge (i, j) crossing the plane, created with its point when new. */
static uint32_t edge_node(slicer *S, const bsfit_plane *pl, uint32_t i, uint32_t j) {
  uint32_t lo = i < j ? i : j, hi = i < j ? j : i;
  uint64_t key = (uint64_t)lo << 32 | hi;
  size_t s = (size_t)((key * 0x9E3779B97F4A7C15ull) >> 20) & S->hmask;
  const double *xi, *xj;
  double si, sj, p[3], t, *uv;
  int k;
  while (S->slot[s] != 0) {
    if (S->keys[s] == key) return S->slot[s] - 1;
    s = (s + 1) & S->hmask;
  }
  S->keys[s] = key;
  S->slot[s] = (uint32_t)(++S->nnodes);
  xi = S->m->xyz + 3 * (size_t)lo;
  xj = S->m->xyz + 3 * (size_t)hi;
  si = S->h[lo] - pl->position;
  sj = S->h[hi] - pl->position;
  /* a vertex on the plane gives itself: points on the plane stay exactly on it */
  t = fabs(si) <= S->tol ? 0 : fabs(sj) <= S->tol ? 1 : si / (si - sj);
  for (k = 0; k < 3; k++) p[k] = xi[k] + t * (xj[k] - xi[k]) - pl->origin[k];
  uv = S->nuv + 2 * (S->nnodes - 1);
  uv[0] = p[0] * pl->u[0] + p[1] * pl->u[1] + p[2] * pl->u[2];
  uv[1] = p[0] * pl->v[0] + p[1] * pl->v[1] + p[2] * pl->v[2];
  return (uint32_t)(S->nnodes - 1);
}

/* Cuts the candidate triangles; on-plane vertices count as side `on` (+1 or -1).
** *touch is set when some vertex lies on the plane. */
static void cut(slicer *S, const bsfit_plane *pl, const size_t *cand, size_t n, int on,
                int *touch) {
  size_t c, hs = S->hmask + 1;
  memset(S->slot, 0, hs * sizeof(uint32_t));
  S->nnodes = S->nsegs = 0;
  *touch = 0;
  for (c = 0; c < n; c++) {
    const uint32_t *t = S->m->tri + 3 * cand[c];
    int sg[3], k, lone;
    uint32_t a, b;
    for (k = 0; k < 3; k++) {
      double s = S->h[t[k]] - pl->position;
      if (fabs(s) <= S->tol) {
        sg[k] = on;
        *touch = 1;
      } else {
        sg[k] = s > 0 ? 1 : -1;
      }
    }
    if (sg[0] == sg[1] && sg[1] == sg[2]) continue;
    lone = sg[0] == sg[1] ? 2 : sg[0] == sg[2] ? 1 : 0;
    a = edge_node(S, pl, t[lone], t[(lone + 1) % 3]);
    b = edge_node(S, pl, t[lone], t[(lone + 2) % 3]);
    if (a == b) continue; /* a degenerate triangle (repeated vertex) */
    S->seg[2 * S->nsegs] = a;
    S->seg[2 * S->nsegs + 1] = b;
    S->nsegs++;
  }
}

/* Node -> segments lists (CSR). */
static void adjacency(slicer *S) {
  size_t i, *st = S->adj_start;
  memset(st, 0, (S->nnodes + 1) * sizeof(size_t));
  for (i = 0; i < 2 * S->nsegs; i++) st[S->seg[i] + 1]++;
  for (i = 0; i < S->nnodes; i++) st[i + 1] += st[i];
  for (i = 0; i < S->nsegs; i++) {
    S->adj[st[S->seg[2 * i]]++] = (uint32_t)i;
    S->adj[st[S->seg[2 * i + 1]]++] = (uint32_t)i;
  }
  for (i = S->nnodes; i > 0; i--) st[i] = st[i - 1];
  st[0] = 0;
  memset(S->used, 0, S->nsegs);
}

/* }====================================================================== */

/* {======================================================================
** Chaining and emitting
** ====================================================================== */

/* Walks from node `start` along unused segments; fills S->chain, returns its length. */
static size_t walk(slicer *S, uint32_t start) {
  size_t n = 0, k;
  uint32_t cur = start;
  S->chain[n++] = cur;
  for (;;) {
    uint32_t next_seg = UINT32_MAX;
    for (k = S->adj_start[cur]; k < S->adj_start[cur + 1]; k++)
      if (!S->used[S->adj[k]]) {
        next_seg = S->adj[k];
        break;
      }
    if (next_seg == UINT32_MAX) break;
    S->used[next_seg] = 1;
    cur = S->seg[2 * next_seg] == cur ? S->seg[2 * next_seg + 1] : S->seg[2 * next_seg];
    S->chain[n++] = cur;
    if (cur == start) break;
  }
  return n;
}

/* Appends the chain as a part, merging consecutive points closer than tol. */
static void emit(slicer *S, bsfit__secbuild *b, size_t n, int closed) {
  double *out, tol2 = S->tol * S->tol;
  size_t i, k = 0;
  if (closed) n--; /* the walk came back to its first node */
  out = bsfit__secb_part(b, n, closed);
  if (out == NULL) return;
  for (i = 0; i < n; i++) {
    const double *p = S->nuv + 2 * S->chain[i];
    if (k > 0) {
      double dx = p[0] - out[2 * k - 2], dy = p[1] - out[2 * k - 1];
      if (dx * dx + dy * dy <= tol2) continue;
    }
    out[2 * k] = p[0];
    out[2 * k + 1] = p[1];
    k++;
  }
  while (closed && k > 1) {
    double dx = out[0] - out[2 * k - 2], dy = out[1] - out[2 * k - 1];
    if (dx * dx + dy * dy > tol2) break;
    k--;
  }
  if (k < (closed ? 3u : 2u))
    bsfit__secb_drop_last(b);
  else
    bsfit__secb_truncate_last(b, k);
}

/* Chains the segments into parts: open chains from their ends first, then loops. */
static void chain_all(slicer *S, bsfit__secbuild *b) {
  size_t i, n;
  adjacency(S);
  for (i = 0; i < S->nnodes; i++) {
    if ((S->adj_start[i + 1] - S->adj_start[i]) % 2 == 0) continue;
    while ((n = walk(S, (uint32_t)i)) > 1) emit(S, b, n, 0);
  }
  for (i = 0; i < S->nsegs; i++) {
    if (S->used[i]) continue;
    n = walk(S, S->seg[2 * i]);
    emit(S, b, n, n > 2 && S->chain[n - 1] == S->chain[0]);
  }
}

/* }====================================================================== */

/* {======================================================================
** Orientation: counter-clockwise outside, clockwise inside an odd number of loops
** ====================================================================== */

static double signed_area(const double *p, size_t n) {
  double a = 0;
  size_t i;
  for (i = 0; i < n; i++) {
    const double *q = p + 2 * ((i + 1) % n);
    a += p[2 * i] * q[1] - q[0] * p[2 * i + 1];
  }
  return a / 2;
}

static int inside(const double *pt, const double *p, size_t n) {
  size_t i, j;
  int in = 0;
  for (i = 0, j = n - 1; i < n; j = i++) {
    const double *a = p + 2 * i, *b = p + 2 * j;
    if ((a[1] > pt[1]) != (b[1] > pt[1]) &&
        pt[0] < (b[0] - a[0]) * (pt[1] - a[1]) / (b[1] - a[1]) + a[0])
      in = !in;
  }
  return in;
}

static void reverse(double *p, size_t n) {
  size_t i;
  for (i = 0; i < n / 2; i++) {
    double x = p[2 * i], y = p[2 * i + 1];
    p[2 * i] = p[2 * (n - 1 - i)];
    p[2 * i + 1] = p[2 * (n - 1 - i) + 1];
    p[2 * (n - 1 - i)] = x;
    p[2 * (n - 1 - i) + 1] = y;
  }
}

void bsfit__orient_loops(double *uv, const size_t *start, const unsigned char *closed, size_t p0,
                         size_t p1) {
  size_t i, j;
  for (i = p0; i < p1; i++) {
    double *p = uv + 2 * start[i];
    size_t n = start[i + 1] - start[i];
    int depth = 0;
    if (!closed[i]) continue;
    for (j = p0; j < p1; j++)
      if (j != i && closed[j] && inside(p, uv + 2 * start[j], start[j + 1] - start[j])) depth++;
    if ((signed_area(p, n) > 0) != (depth % 2 == 0)) reverse(p, n);
  }
}

/* }====================================================================== */

/* {======================================================================
** All the planes
** ====================================================================== */

typedef struct posidx {
  double pos;
  size_t idx;
} posidx;

static int cmp_pos(const void *a, const void *b) {
  const posidx *x = a, *y = b;
  return x->pos < y->pos ? -1 : x->pos > y->pos ? 1 : (x->idx > y->idx) - (x->idx < y->idx);
}

typedef struct bucketing {
  posidx *order;  /* slices sorted by position */
  double *sorted; /* their positions */
  size_t *cstart; /* npos + 1: candidates of sorted slice r are cand[cstart[r] .. cstart[r+1]-1] */
  size_t *cand;   /* triangle ids grouped by slice */
  size_t ncand;
} bucketing;

/* First k with v[k] > x (strict) or >= x, in the sorted array v[0..n-1]. */
static size_t bound(const double *v, size_t n, double x, int strict) {
  size_t lo = 0, hi = n;
  while (lo < hi) {
    size_t mid = lo + (hi - lo) / 2;
    if (v[mid] < x || (strict && v[mid] == x))
      lo = mid + 1;
    else
      hi = mid;
  }
  return lo;
}

/* The sorted slices [r0, r1) whose plane comes within tol of triangle t. */
static void tri_range(const slicer *S, const bucketing *B, size_t npos, size_t t, size_t *r0,
                      size_t *r1) {
  const uint32_t *v = S->m->tri + 3 * t;
  double a = S->h[v[0]], b = a, x;
  int k;
  for (k = 1; k < 3; k++) {
    x = S->h[v[k]];
    if (x < a) a = x;
    if (x > b) b = x;
  }
  *r0 = bound(B->sorted, npos, a - S->tol, 0);
  *r1 = bound(B->sorted, npos, b + S->tol, 1);
}

/* Distributes the triangles to the slices they may cross (counting pass, then filling). */
static bsfit_err bucket(slicer *S, bucketing *B, const double *pos, size_t npos, bsfit_status *st) {
  size_t i, t, r0, r1, r;
  for (i = 0; i < npos; i++) {
    B->order[i].pos = pos[i];
    B->order[i].idx = i;
  }
  qsort(B->order, npos, sizeof *B->order, cmp_pos);
  for (i = 0; i < npos; i++) B->sorted[i] = B->order[i].pos;
  memset(B->cstart, 0, (npos + 1) * sizeof(size_t));
  for (t = 0; t < S->m->nt; t++) {
    tri_range(S, B, npos, t, &r0, &r1);
    for (r = r0; r < r1; r++) B->cstart[r + 1]++;
  }
  for (i = 0; i < npos; i++) B->cstart[i + 1] += B->cstart[i];
  B->ncand = B->cstart[npos];
  B->cand = bsfit__alloc(S->a, bsfit__mulsize(B->ncand ? B->ncand : 1, sizeof(size_t)));
  if (B->cand == NULL) return bsfit__fail(st, BSFIT_ENOMEM, "out of memory slicing");
  for (t = 0; t < S->m->nt; t++) {
    if ((t & 0xffff) == 0 && bsfit__interrupted(S->a))
      return bsfit__fail(st, BSFIT_EINTR, "slicing interrupted");
    tri_range(S, B, npos, t, &r0, &r1);
    for (r = r0; r < r1; r++) B->cand[B->cstart[r]++] = t;
  }
  for (i = npos; i > 0; i--) B->cstart[i] = B->cstart[i - 1];
  B->cstart[0] = 0;
  return BSFIT_OK;
}

/* The vertex heights, the default tolerance, and checks of the mesh. */
static bsfit_err heights(slicer *S, const double n[3], double *tol, bsfit_status *st) {
  const bsfit_scan *m = S->m;
  double lo[3] = {HUGE_VAL, HUGE_VAL, HUGE_VAL}, hi[3] = {-HUGE_VAL, -HUGE_VAL, -HUGE_VAL};
  double *h = S->h, d2 = 0;
  size_t i;
  int k;
  for (i = 0; i < m->nv; i++) {
    const double *x = m->xyz + 3 * i;
    if (!isfinite(x[0]) || !isfinite(x[1]) || !isfinite(x[2]))
      return bsfit__fail(st, BSFIT_ENONFINITE, "vertex %zu is not finite", i + 1);
    for (k = 0; k < 3; k++) {
      if (x[k] < lo[k]) lo[k] = x[k];
      if (x[k] > hi[k]) hi[k] = x[k];
    }
    h[i] = n[0] * x[0] + n[1] * x[1] + n[2] * x[2];
  }
  for (i = 0; i < 3 * m->nt; i++)
    if (m->tri[i] >= m->nv)
      return bsfit__fail(st, BSFIT_EINVAL, "triangle %zu names vertex %lu of %zu", i / 3 + 1,
                         (unsigned long)m->tri[i] + 1, m->nv);
  for (k = 0; k < 3; k++) d2 += (hi[k] - lo[k]) * (hi[k] - lo[k]);
  if (!(*tol > 0)) *tol = 1e-9 * sqrt(d2);
  if (!(*tol > 0)) *tol = 1e-300;
  return BSFIT_OK;
}

/* Cuts the planes one after the other, in the caller's order. */
static bsfit_err cut_all(slicer *S, bucketing *B, const double n[3], const double *pos, size_t npos,
                         bsfit__secbuild *b, bsfit_status *st) {
  size_t r, i, *rank = B->cstart + npos + 1; /* rank[i]: sorted place of slice i */
  int touch;
  for (r = 0; r < npos; r++) rank[B->order[r].idx] = r;
  for (i = 0; i < npos; i++) {
    size_t r0 = rank[i], p0 = b->nparts;
    bsfit_plane *pl = &b->planes[i];
    const size_t *cand = B->cand + B->cstart[r0];
    size_t nc = B->cstart[r0 + 1] - B->cstart[r0];
    bsfit_plane_frame(n, pos[i], pl, NULL);
    b->first_part[i] = p0;
    if (bsfit__interrupted(S->a)) return bsfit__fail(st, BSFIT_EINTR, "slicing interrupted");
    cut(S, pl, cand, nc, 1, &touch);
    chain_all(S, b);
    if (b->nparts == p0 && touch) { /* the plane only touches: try the other side */
      cut(S, pl, cand, nc, -1, &touch);
      chain_all(S, b);
    }
    if (b->failed) return bsfit__fail(st, BSFIT_ENOMEM, "out of memory slicing");
    bsfit__orient_loops(b->uv, b->part_start, b->closed, p0, b->nparts);
  }
  b->first_part[npos] = b->nparts;
  return BSFIT_OK;
}

bsfit_err bsfit_mesh_slice(const bsfit_scan *m, const double dir[3], const double *pos, size_t npos,
                           double tol, bsfit_sections *out, const bsfit_allocator *a,
                           bsfit_status *st) {
  slicer S;
  bucketing B;
  bsfit__secbuild b;
  double n[3];
  size_t i, maxc = 0;
  bsfit_err e;
  if (m == NULL || m->tri == NULL || m->nt == 0 || out == NULL)
    return bsfit__fail(st, BSFIT_EINVAL, "no triangles to slice");
  if (pos == NULL || npos == 0) return bsfit__fail(st, BSFIT_EINVAL, "no planes to slice with");
  e = bsfit__unit(dir, n, st);
  if (e != BSFIT_OK) return e;
  if (!bsfit__all_finite(pos, npos))
    return bsfit__fail(st, BSFIT_ENONFINITE, "a plane position is not finite");
  memset(&S, 0, sizeof S);
  memset(&B, 0, sizeof B);
  S.m = m;
  S.a = a;
  S.h = bsfit__alloc(a, bsfit__mulsize(m->nv, sizeof(double)));
  B.order = bsfit__alloc(a, bsfit__mulsize(npos, sizeof(posidx)));
  B.sorted = bsfit__alloc(a, bsfit__mulsize(npos, sizeof(double)));
  B.cstart = bsfit__alloc(a, bsfit__mulsize(2 * npos + 1, sizeof(size_t)));
  e = (S.h && B.order && B.sorted && B.cstart)
          ? BSFIT_OK
          : bsfit__fail(st, BSFIT_ENOMEM, "out of memory slicing");
  if (e == BSFIT_OK) e = heights(&S, n, &tol, st);
  S.tol = tol;
  if (e == BSFIT_OK) e = bucket(&S, &B, pos, npos, st);
  for (i = 0; e == BSFIT_OK && i < npos; i++)
    if (B.cstart[i + 1] - B.cstart[i] > maxc) maxc = B.cstart[i + 1] - B.cstart[i];
  if (e == BSFIT_OK && !scratch_alloc(&S, maxc))
    e = bsfit__fail(st, BSFIT_ENOMEM, "out of memory slicing");
  if (e == BSFIT_OK) e = bsfit__secb_init(&b, npos, a, st);
  if (e == BSFIT_OK) {
    e = cut_all(&S, &B, n, pos, npos, &b, st);
    if (e == BSFIT_OK)
      e = bsfit__secb_finish(&b, out, st);
    else
      bsfit__secb_free(&b);
  }
  scratch_free(&S);
  bsfit__free(a, S.h, m->nv * sizeof(double));
  bsfit__free(a, B.order, npos * sizeof(posidx));
  bsfit__free(a, B.sorted, npos * sizeof(double));
  bsfit__free(a, B.cstart, (2 * npos + 1) * sizeof(size_t));
  bsfit__free(a, B.cand, (B.ncand ? B.ncand : 1) * sizeof(size_t));
  return e;
}

/* }====================================================================== */
