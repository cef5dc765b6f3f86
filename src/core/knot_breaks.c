/*
** knot_breaks.c
** One period of knots for a closed fit whose curve may turn sharply at given corners
** (knots of multiplicity p there), with a guard that never leaves a knot span
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

/* Parameter at index q in [0, 2m]: the points are walked around the period, so
** indices past the end continue in the next period. */
static double val(const double *u, size_t m, size_t q) {
  return q < m ? u[q] : u[q - m] + 1.0;
}

/* Parameter at the fractional index x in [0, 2m): interpolated between points. */
static double interp(const double *u, size_t m, double x) {
  size_t i = (size_t)x;
  double f = x - (double)i;
  return f > 0 ? (1.0 - f) * val(u, m, i) + f * val(u, m, i + 1) : val(u, m, i);
}

static bsfit_err check_inputs(const double *u, size_t m, int p, const double *breaks, size_t nb,
                              bsfit_status *st) {
  size_t i;
  if (p < 1 || p > BSFIT_MAX_DEGREE)
    return bsfit__fail(st, BSFIT_EDEGREE, "degree %d out of range 1..%d", p, BSFIT_MAX_DEGREE);
  if (u == NULL || m < 2) return bsfit__fail(st, BSFIT_ETOOFEW, "need at least 2 parameters, got %zu", m);
  for (i = 0; i < m; i++)
    if (!(u[i] >= 0 && u[i] < 1) || (i > 0 && u[i] < u[i - 1]))
      return bsfit__fail(st, BSFIT_EINVAL, "parameter %zu (%g) is not in [0, 1) non-decreasing", i, u[i]);
  for (i = 0; i < nb; i++)
    if (!(breaks[i] >= 0 && breaks[i] < (double)m) || (i > 0 && !(breaks[i] > breaks[i - 1])))
      return bsfit__fail(st, BSFIT_EINVAL, "break %zu (at %g) is out of [0, %zu) or not increasing",
                         i, breaks[i], m);
  return BSFIT_OK;
}

/* Corners kept: each piece between consecutive corners must span 3 point gaps or
** more (its interior control points need data). */
static size_t keep_breaks(const double *breaks, size_t nb, size_t m, double *kept) {
  size_t i, nk = 0;
  for (i = 0; i < nb; i++) {
    if (nk > 0 && breaks[i] - kept[nk - 1] < 3.0) continue;
    kept[nk++] = breaks[i];
  }
  while (nk > 1 && kept[0] + (double)m - kept[nk - 1] < 3.0) nk--; /* across the end */
  return nk;
}

/* K interior knots of the piece from fractional index a to b, at equal point counts
** (averaging in index space). */
static size_t place_piece(const double *u, size_t m, double a, double b, size_t K, knot *out) {
  size_t k;
  for (k = 1; k <= K; k++) {
    out[k - 1].t = interp(u, m, a + (b - a) * (double)k / (double)(K + 1));
    out[k - 1].corner = 0;
  }
  return K;
}

/* largest-remainder share of K knots among the pieces, of lengths len[j] (total m) */
static void share_knots(const double *len, size_t np, double m, size_t K, size_t *share) {
  size_t j, given = 0;
  for (j = 0; j < np; j++) {
    share[j] = (size_t)floor((double)K * len[j] / m);
    given += share[j];
  }
  while (given < K) {
    size_t best = 0;
    double best_r = -1;
    for (j = 0; j < np; j++) {
      double r = (double)K * len[j] / m - (double)share[j];
      if (r > best_r) {
        best_r = r;
        best = j;
      }
    }
    share[best]++;
    given++;
  }
}

/* The guard: walks the spans in order and merges each span holding fewer than `need`
** parameters into its neighbour, by removing the simple knot between them (the next
** one; or, when the next is a corner or the period's end, the span's own start).
** knots[0], the period start, stays. The points are walked from index s0, whose
** parameters lie in [t0, t0 + 1). Returns the new number of knots. */
static size_t guard_spans(const double *u, size_t m, size_t s0, double t_end, knot *knots,
                          size_t nk, size_t need) {
  size_t q = s0, k, w = 1, c = 0;
  for (k = 0; k < nk; k++) {
    double hi = k + 1 < nk ? knots[k + 1].t : t_end;
    while (q < s0 + m && val(u, m, q) < hi) {
      q++;
      c++;
    }
    if (k + 1 < nk && c < need && !knots[k + 1].corner) continue; /* drop knots[k+1] */
    if (c < need && w > 1 && !knots[w - 1].corner) w--;        /* drop the span's start */
    if (k + 1 < nk) knots[w++] = knots[k + 1];
    c = 0;
  }
  return w;
}

/* Knots of the pieces between the kept corners; returns their number. */
static size_t place_with_corners(const double *u, size_t m, int p, size_t n_target,
                                 const double *kept, size_t nbk, double *len, size_t *share,
                                 knot *knots) {
  size_t j, nk = 0, K = n_target - nbk * (size_t)p;
  for (j = 0; j < nbk; j++) len[j] = (j + 1 < nbk ? kept[j + 1] : kept[0] + (double)m) - kept[j];
  share_knots(len, nbk, (double)m, K, share);
  for (j = 0; j < nbk; j++) {
    knots[nk].t = interp(u, m, kept[j]);
    knots[nk++].corner = 1;
    nk += place_piece(u, m, kept[j], kept[j] + len[j], share[j], knots + nk);
  }
  return nk;
}

/* the number of control points of the period: corners count p */
static size_t period_count(const knot *knots, size_t nk, int p) {
  size_t i, N = 0;
  for (i = 0; i < nk; i++) N += knots[i].corner ? (size_t)p : 1;
  return N;
}

/* The knots before the guard: n_target of them, corners at the kept breaks; *t0 the period
** start, *s0 the first point at or after it. Returns their number. */
static size_t place_all(const double *u, size_t m, int p, size_t n_target, const double *kept,
                        size_t nbk, double *len, size_t *share, knot *knots, double *t0,
                        size_t *s0) {
  if (nbk == 0) { /* one piece around the whole period; u[0] itself is a simple knot */
    *t0 = u[0];
    *s0 = 0;
    knots[0].t = *t0;
    knots[0].corner = 0;
    return 1 + place_piece(u, m, 0.0, (double)m, n_target - 1, knots + 1);
  }
  *t0 = interp(u, m, kept[0]);
  *s0 = (size_t)ceil(kept[0]); /* the first point at or after the first corner */
  return place_with_corners(u, m, p, n_target, kept, nbk, len, share, knots);
}

/* The last resort of a section without corners: a knot at each of up to n_target distinct
** parameters, evenly among them by index, so that every span holds one (and its
** repeats). Returns their number (below n_target when fewer are distinct). */
static size_t place_at_params(const double *u, size_t m, size_t n_target, knot *knots) {
  size_t i, D = 0, j = 0, k = 0, N;
  for (i = 0; i < m; i++)
    if (i == 0 || u[i] > u[i - 1]) D++;
  N = n_target < D ? n_target : D;
  for (i = 0; i < m && k < N; i++) {
    if (i > 0 && !(u[i] > u[i - 1])) continue;
    if (j == k * D / N) {
      knots[k].t = u[i];
      knots[k++].corner = 0;
    }
    j++;
  }
  return k;
}

/* writes the period (corners as p copies) and its N; 0 when too few spans remain */
static size_t write_period(const knot *knots, size_t nk, int p, double t0, double *period) {
  size_t i, N = period_count(knots, nk, p);
  if (N < (size_t)p + 1 || N < 2) return 0;
  N = 0;
  for (i = 0; i < nk; i++) {
    size_t r, copies = knots[i].corner ? (size_t)p : 1;
    for (r = 0; r < copies; r++) period[N++] = knots[i].t;
  }
  period[N] = t0 + 1.0;
  return N;
}

bsfit_err bsfit_knots_place_breaks(const double *u, size_t m, int p, size_t n_target,
                                   const double *breaks, size_t nb, double *period, size_t *n_out,
                                   const bsfit_allocator *a, bsfit_status *st) {
  size_t *share = NULL, nbk, nk, s0, N;
  double *kept = NULL, *len = NULL, t0;
  knot *knots = NULL;
  bsfit_err e = check_inputs(u, m, p, breaks, nb, st);
  if (e != BSFIT_OK) return e;
  kept = bsfit__alloc(a, (nb + 1) * sizeof(double));
  len = bsfit__alloc(a, (nb + 1) * sizeof(double));
  share = bsfit__alloc(a, (nb + 1) * sizeof(size_t));
  knots = bsfit__alloc(a, (n_target + 1) * sizeof(knot));
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
  nk = place_all(u, m, p, n_target, kept, nbk, len, share, knots, &t0, &s0);
  nk = guard_spans(u, m, s0, t0 + 1.0, knots, nk, 2);
  if (period_count(knots, nk, p) < (size_t)p + 1) {
    /* few points (fewer than 2 (p + 1)): two parameters in every span leave too few
    ** spans; one in every span still fits (m >= N points interlacing the knots) */
    nk = place_all(u, m, p, n_target, kept, nbk, len, share, knots, &t0, &s0);
    nk = guard_spans(u, m, s0, t0 + 1.0, knots, nk, 1);
  }
  if (period_count(knots, nk, p) < (size_t)p + 1 && nbk == 0) {
    /* repeated points crowd the averaged knots together: a knot at distinct parameters */
    nk = place_at_params(u, m, n_target, knots);
    t0 = u[0];
    s0 = 0;
  }
  N = write_period(knots, nk, p, t0, period);
  if (N == 0) {
    e = bsfit__fail(st, BSFIT_ETOOFEW, "%zu points leave too few knot spans for degree %d", m, p);
    goto done;
  }
  *n_out = N;
  e = bsfit__ok(st);
done:
  bsfit__free(a, kept, (nb + 1) * sizeof(double));
  bsfit__free(a, len, (nb + 1) * sizeof(double));
  bsfit__free(a, share, (nb + 1) * sizeof(size_t));
  bsfit__free(a, knots, (n_target + 1) * sizeof(knot));
  return e;
}
