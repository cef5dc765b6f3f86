/*
** surface_skin_slivers.c
** Sliver pieces dropped from a section before it is approximated within a tolerance. `auto`
** on an exact mesh loop ends many lines at a corner through a piece 1e-12 of the period
** long and under 1e-9 long in space (two C0 knots that close: 260 of the 690 corners of a
** 1000-facet loop). Closest-point searches once bracketed by a span's own step and
** stopped at the corner next to such a piece (they are global now: closest_pieces.c).
** Those pieces carry no shape: each is removed, and the curve after it starts
** where it started, which moves the section by no more than the piece's control points
** spread (reported, and added to the distance the cubic is measured at).
** On a piece between two knots of multiplicity p the curve depends on that piece's knots
** and control points only (it is a clamped piece of its own), so the removal is local.
*/
#include "skin_internal.h"

#include <math.h>
#include <string.h>

#define SLIVER_SPAN 1e-9 /* a piece this short (fraction of the period) is a sliver */

static double dist3(const double *x, const double *y) {
  return sqrt((x[0] - y[0]) * (x[0] - y[0]) + (x[1] - y[1]) * (x[1] - y[1]) +
              (x[2] - y[2]) * (x[2] - y[2]));
}

/* The length of the run of equal period knots t[j..] (N of them); 0 at the end. */
static size_t run_length(const double *t, size_t N, size_t j) {
  size_t r = j;
  while (r < N && t[r] == t[j]) r++;
  return r - j;
}

/* Marks the slivers of c (period knots t[0..N-1], distinct control points P): drop_t[i],
** drop_P[i] set for what goes; returns how many knots go, *moved the largest spread. The
** piece from run A (at t[j], multiplicity p) to run B (multiplicity p, not past the
** period's end) runs over control points p + j - 1 .. 2p + j - 1 (mod N), C(t[j]) being
** the first: run B and the last p of those go, the piece after B then starts there. */
static size_t mark_slivers(const bsfit_curve *c, const double *t, size_t N, double limit,
                           char *drop_t, char *drop_P, double *moved) {
  size_t p = (size_t)c->degree, j = 0, gone = 0, r;
  const double *P = c->ctrl;
  while (j < N) {
    size_t ma = run_length(t, N, j), k = j + ma, mb = k < N ? run_length(t, N, k) : 0;
    double spread = 0;
    if (ma != p || mb != p || !(t[k] - t[j] < SLIVER_SPAN)) {
      j = k;
      continue;
    }
    for (r = 0; r < p; r++) {
      spread = fmax(spread, dist3(P + 3 * ((p + j + r) % N), P + 3 * ((p + j - 1) % N)));
      if (drop_P[(p + j + r) % N] || drop_P[(p + j - 1) % N]) spread = HUGE_VAL; /* wrapped */
    }
    if (spread <= limit && N - gone > 2 * p + 1) {
      for (r = 0; r < p; r++) drop_t[k + r] = 1, drop_P[(p + j + r) % N] = 1;
      gone += p;
      *moved = fmax(*moved, spread);
    }
    j = k + mb; /* run B is gone (or kept): the next pair starts after it */
  }
  return gone;
}

bsfit_err bsfit__skin_drop_slivers(bsfit_curve *c, double limit, double *moved,
                                   const bsfit_allocator *a, bsfit_status *st) {
  size_t p = (size_t)c->degree, N = c->n - p, i, n = 0, m = 0;
  size_t bytes = (4 * N + 1) * sizeof(double) + 2 * N;
  double *t = bsfit__alloc(a, bytes), *P;
  char *drop;
  bsfit_curve out;
  bsfit_err e = BSFIT_OK;
  if (t == NULL) return bsfit__fail(st, BSFIT_ENOMEM, "out of memory for %zu knots", N);
  P = t + N + 1;
  drop = (char *)(P + 3 * N);
  memset(drop, 0, 2 * N);
  if (mark_slivers(c, c->knots + p, N, limit, drop, drop + N, moved) > 0) {
    for (i = 0; i < N; i++) {
      if (!drop[i]) t[n++] = c->knots[p + i];
      if (!drop[N + i]) memcpy(P + 3 * m++, c->ctrl + 3 * i, 3 * sizeof(double));
    }
    t[n] = 1.0;
    bsfit_curve_init(&out);
    e = bsfit_curve_new_periodic(&out, c->degree, 3, n, t, P, NULL, a, st);
    if (e == BSFIT_OK) bsfit_curve_move(&out, c);
    bsfit_curve_free(&out);
  }
  bsfit__free(a, t, bytes);
  return e;
}
