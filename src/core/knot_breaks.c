/*
** knot_breaks.c
** One period of knots for a closed fit whose curve may turn sharply at given corner
** points (knots of multiplicity p there), with a guard that never leaves a knot span
** without data.
*/
#include "internal.h"

#include <math.h>
#include <string.h>

/* a knot of the period being built: its value and whether it is a corner (p copies) */
typedef struct knot {
  double t;
  int corner;
} knot;

/* Parameter of point q, for q in [s0, s0 + m]: the points are walked once around the
** period from point s0, so indices past the end continue in the next period. */
static double val(const double *u, size_t m, size_t q) {
  return q < m ? u[q] : u[q - m] + 1.0;
}

static bsfit_err check_inputs(const double *u, size_t m, int p, const size_t *breaks, size_t nb,
                              bsfit_status *st) {
  size_t i;
  if (p < 1 || p > BSFIT_MAX_DEGREE)
    return bsfit__fail(st, BSFIT_EDEGREE, "degree %d out of range 1..%d", p, BSFIT_MAX_DEGREE);
  if (u == NULL || m < 2) return bsfit__fail(st, BSFIT_ETOOFEW, "need at least 2 parameters, got %zu", m);
  for (i = 0; i < m; i++)
    if (!(u[i] >= 0 && u[i] < 1) || (i > 0 && u[i] < u[i - 1]))
      return bsfit__fail(st, BSFIT_EINVAL, "parameter %zu (%g) is not in [0, 1) non-decreasing", i, u[i]);
  for (i = 0; i < nb; i++)
    if (breaks[i] >= m || (i > 0 && breaks[i] <= breaks[i - 1]))
      return bsfit__fail(st, BSFIT_EINVAL, "break %zu (point %zu) is out of range or not increasing", i,
                         breaks[i]);
  return BSFIT_OK;
}

/* corners kept: each piece between consecutive corners needs 3 points or more */
static size_t keep_breaks(const size_t *breaks, size_t nb, size_t m, size_t *kept) {
  size_t i, nk = 0;
  for (i = 0; i < nb; i++) {
    if (nk > 0 && breaks[i] - kept[nk - 1] < 3) continue;
    kept[nk++] = breaks[i];
  }
  while (nk > 1 && kept[0] + m - kept[nk - 1] < 3) nk--; /* the piece across the end */
  return nk;
}

/* K interior knots of the piece of `len` spans of points from point a (a + len is the
** next corner), at equal point counts (averaging in index space) */
static size_t place_piece(const double *u, size_t m, size_t a, size_t len, size_t K, knot *out) {
  size_t k;
  for (k = 1; k <= K; k++) {
    double x = (double)k * (double)len / (double)(K + 1);
    size_t i = (size_t)x;
    double alpha = x - (double)i;
    double v1 = i + 1 <= len ? val(u, m, a + i + 1) : val(u, m, a + len);
    out[k - 1].t = (1.0 - alpha) * val(u, m, a + i) + alpha * v1;
    out[k - 1].corner = 0;
  }
  return K;
}

/* largest-remainder share of K knots among the pieces, len[j] points each (m in all) */
static void share_knots(const size_t *len, size_t np, size_t m, size_t K, size_t *share) {
  size_t j, given = 0;
  for (j = 0; j < np; j++) {
    share[j] = (size_t)floor((double)K * (double)len[j] / (double)m);
    given += share[j];
  }
  while (given < K) {
    size_t best = 0;
    double best_r = -1;
    for (j = 0; j < np; j++) {
      double r = (double)K * (double)len[j] / (double)m - (double)share[j];
      if (r > best_r) {
        best_r = r;
        best = j;
      }
    }
    share[best]++;
    given++;
  }
}

/* The guard: walks the spans in order and merges each span holding fewer than two
** parameters into its neighbour, by removing the simple knot between them (the next
** one; or, when the next is a corner or the period's end, the span's own start).
** knots[0], the period start, stays. Returns the new number of knots. */
static size_t guard_spans(const double *u, size_t m, size_t s0, knot *knots, size_t nk) {
  size_t q = s0, k, w = 1, c = 0;
  double t_end = val(u, m, s0 + m);
  for (k = 0; k < nk; k++) {
    double hi = k + 1 < nk ? knots[k + 1].t : t_end;
    while (q < s0 + m && val(u, m, q) < hi) {
      q++;
      c++;
    }
    if (k + 1 < nk && c < 2 && !knots[k + 1].corner) continue; /* drop knots[k+1] */
    if (c < 2 && w > 1 && !knots[w - 1].corner) w--;        /* drop the span's start */
    if (k + 1 < nk) knots[w++] = knots[k + 1];
    c = 0;
  }
  return w;
}

bsfit_err bsfit_knots_place_breaks(const double *u, size_t m, int p, size_t n_target,
                                   const size_t *breaks, size_t nb, double *period, size_t *n_out,
                                   bsfit_status *st) {
  size_t *kept = NULL, *len = NULL, *share = NULL, nbk, j, nk = 0, K, i, N, s0;
  knot *knots = NULL;
  double t0;
  bsfit_err e = check_inputs(u, m, p, breaks, nb, st);
  if (e != BSFIT_OK) return e;
  kept = bsfit__alloc(NULL, (nb + 1) * sizeof(size_t));
  len = bsfit__alloc(NULL, (nb + 1) * sizeof(size_t));
  share = bsfit__alloc(NULL, (nb + 1) * sizeof(size_t));
  knots = bsfit__alloc(NULL, (n_target + 1) * sizeof(knot));
  if (!kept || !len || !share || !knots) {
    e = bsfit__fail(st, BSFIT_ENOMEM, "out of memory for %zu knots", n_target);
    goto done;
  }
  nbk = keep_breaks(breaks, nb, m, kept);
  if (n_target < (size_t)p + 1 || n_target < nbk * (size_t)p + 1) {
    e = bsfit__fail(st, BSFIT_EINVAL, "%zu control points are too few for degree %d with %zu corners",
                    n_target, p, nbk);
    goto done;
  }
  s0 = nbk > 0 ? kept[0] : 0;
  t0 = u[s0];
  if (nbk == 0) {
    /* one piece around the whole period; t0 itself is a simple knot */
    knots[0].t = t0;
    knots[0].corner = 0;
    nk = 1 + place_piece(u, m, 0, m, n_target - 1, knots + 1);
  } else {
    K = n_target - nbk * (size_t)p;
    for (j = 0; j < nbk; j++) len[j] = (j + 1 < nbk ? kept[j + 1] : kept[0] + m) - kept[j];
    share_knots(len, nbk, m, K, share);
    for (j = 0; j < nbk; j++) {
      knots[nk].t = val(u, m, kept[j]);
      knots[nk++].corner = 1;
      nk += place_piece(u, m, kept[j], len[j], share[j], knots + nk);
    }
  }
  nk = guard_spans(u, m, s0, knots, nk);
  /* expand corners to p copies */
  N = 0;
  for (i = 0; i < nk; i++) N += knots[i].corner ? (size_t)p : 1;
  if (N < (size_t)p + 1 || N < 2) {
    e = bsfit__fail(st, BSFIT_ETOOFEW, "%zu points leave only %zu knot spans for degree %d", m, N, p);
    goto done;
  }
  N = 0;
  for (i = 0; i < nk; i++) {
    size_t r, copies = knots[i].corner ? (size_t)p : 1;
    for (r = 0; r < copies; r++) period[N++] = knots[i].t;
  }
  period[N] = t0 + 1.0;
  *n_out = N;
  e = bsfit__ok(st);
done:
  bsfit__free(NULL, kept, (nb + 1) * sizeof(size_t));
  bsfit__free(NULL, len, (nb + 1) * sizeof(size_t));
  bsfit__free(NULL, share, (nb + 1) * sizeof(size_t));
  bsfit__free(NULL, knots, (n_target + 1) * sizeof(knot));
  return e;
}
