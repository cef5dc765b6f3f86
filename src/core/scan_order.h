/*
** scan_order.h
** What the two halves of the ordering share: the neighbour lists (scan_order.c builds
** them and runs the star test) and the graph tour (scan_order_graph.c). Private.
*/
#ifndef BSFIT_SCAN_ORDER_H
#define BSFIT_SCAN_ORDER_H

#include "scan_internal.h"

#include <math.h>

#define BSFIT__NONE ((size_t)-1)

typedef struct bsfit__ordwork {
  const double *xy;
  size_t m, k;
  size_t *nbr;     /* m*k neighbour ids, nearest first (BSFIT__NONE past the end) */
  double *nd;      /* their distances */
  double *spacing; /* m: local spacing (2nd neighbour distance, floored) */
  double gap;
  size_t min_points;
  const bsfit_allocator *a;
} bsfit__ordwork;

static inline double bsfit__dist(const double *xy, size_t i, size_t j) {
  double dx = xy[2 * i] - xy[2 * j], dy = xy[2 * i + 1] - xy[2 * j + 1];
  return sqrt(dx * dx + dy * dy);
}

/* The spacing a step from i to j is judged against: the geometric mean of the two local
** spacings, so a gradual change of density passes while a lone outlier (whose own
** spacing is the distance to the section) cannot bridge to the section. */
static inline double bsfit__pair_spacing(const bsfit__ordwork *w, size_t i, size_t j) {
  return sqrt(w->spacing[i] * w->spacing[j]);
}

/* The graph method: fills r (arrays allocated by the caller for m points). */
bsfit_err bsfit__order_graph(const bsfit__ordwork *w, bsfit_order_result *r, bsfit_status *st);

/* 2-opt over the neighbour lists on tour t[0..n-1] (closed or open); pos[t[i]] == i on
** entry and exit; comp[v] == id marks the tour's points. */
void bsfit__two_opt(const bsfit__ordwork *w, size_t *t, size_t n, int closed, size_t *pos,
                    const size_t *comp, size_t id);

#endif
