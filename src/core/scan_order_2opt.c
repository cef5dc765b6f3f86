/*
** scan_order_2opt.c
** 2-opt improvement of a tour restricted to neighbour lists: for each tour edge (a, b)
** and each neighbour c of a, replacing (a, b) and (c, d) by (a, c) and (b, d) when that
** is shorter removes a crossing. Reversals walk the shorter side of a closed tour, and
** the total reversal work is capped at a multiple of n, so the cost stays O(n k) per pass.
*/
#include "scan_order.h"

#include <math.h>

/* Reverses t over the circular index range [s, s+len) (mod n), keeping pos in step. */
static void reverse(size_t *t, size_t n, size_t s, size_t len, size_t *pos) {
  size_t i, j, q;
  for (q = 0; q < len / 2; q++) {
    size_t x;
    i = (s + q) % n;
    j = (s + len - 1 - q) % n;
    x = t[i];
    t[i] = t[j];
    t[j] = x;
    pos[t[i]] = i;
    pos[t[j]] = j;
  }
}

/* Tries the moves of tour edge i; returns the reversal work done (0: no move). */
static size_t try_edge(const bsfit__ordwork *w, size_t *t, size_t n, int closed, size_t *pos,
                       const size_t *comp, size_t id, size_t i) {
  size_t a = t[i], b = t[(i + 1) % n], q;
  double dab = bsfit__dist(w->xy, a, b);
  for (q = 0; q < w->k; q++) {
    size_t c = w->nbr[a * w->k + q], j, d, lo, hi, inner;
    double gain;
    if (c == BSFIT__NONE) break;
    if (w->nd[a * w->k + q] >= dab) break; /* (a, c) must be shorter than (a, b) */
    if (comp[c] != id) continue;
    j = pos[c];
    if (j == i || j == (i + 1) % n || (!closed && j == n - 1)) continue;
    d = t[(j + 1) % n];
    if (d == a) continue;
    gain = dab + bsfit__dist(w->xy, c, d) - w->nd[a * w->k + q] - bsfit__dist(w->xy, b, d);
    if (!(gain > 1e-12 * dab)) continue;
    lo = i < j ? i : j;
    hi = i < j ? j : i;
    inner = hi - lo; /* t[lo+1 .. hi] */
    if (closed && n - inner < inner)
      reverse(t, n, hi + 1, n - inner, pos);
    else
      reverse(t, n, lo + 1, inner, pos);
    return inner + 1;
  }
  return 0;
}

void bsfit__two_opt(const bsfit__ordwork *w, size_t *t, size_t n, int closed, size_t *pos,
                    const size_t *comp, size_t id) {
  size_t pass, i, work = 0, budget = 64 * n + 1024, done;
  if (n < 4) return;
  for (pass = 0; pass < 16; pass++) {
    int improved = 0;
    for (i = 0; i + (closed ? 0 : 1) < n; i++) {
      done = try_edge(w, t, n, closed, pos, comp, id, i);
      if (done) {
        improved = 1;
        work += done;
        if (work > budget) return;
      }
    }
    if (!improved) return;
  }
}
