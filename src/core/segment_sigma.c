/*
** segment_sigma.c
** The noise of a section of lines and arcs, read off the models' own residuals
** (bsfit_segment_sigma, bsfit_features.h): the first segmentation level whose pooled
** residual matches the level.
*/
#include "features_internal.h"

#include <math.h>
#include <string.h>

/* the first guess of bsfit_segment_sigma: how far samples lie off their neighbours'
** chord, normalised by the spread that noise alone gives it; its lower quartile over
** that of |N(0, 1)| (0.3186): corners and arcs only add to it, and it must not start
** high (a high start lets one model take everything) */
static double chord_sigma(const double *pts, size_t m, int closed, double *d) {
  size_t i, n = 0;
  for (i = closed ? 0 : 1; i < (closed ? m : m - 1); i++) {
    const double *a = pts + 2 * ((i + m - 1) % m), *q = pts + 2 * i, *b = pts + 2 * ((i + 1) % m);
    double dx = b[0] - a[0], dy = b[1] - a[1], l2 = dx * dx + dy * dy, t;
    if (!(l2 > 0)) continue;
    t = ((q[0] - a[0]) * dx + (q[1] - a[1]) * dy) / l2;
    d[n++] = fabs((q[0] - a[0]) * dy - (q[1] - a[1]) * dx) / sqrt(l2) /
             sqrt(1 + t * t + (1 - t) * (1 - t));
  }
  return n ? bsfit__select(d, n, n / 4) / 0.3186 : 0.0;
}

/* pooled residual of the lines and arcs: sum of squares over degrees of freedom */
static double pooled_sigma(const bsfit_piece *p, size_t np) {
  double rss = 0, dof = 0;
  size_t i;
  for (i = 0; i < np; i++) {
    double k = p[i].kind == BSFIT_PIECE_LINE ? 2 : 3;
    if (p[i].kind == BSFIT_PIECE_FREE || (double)p[i].count <= k) continue;
    rss += p[i].rms * p[i].rms * (double)p[i].count;
    dof += (double)p[i].count - k;
  }
  return dof > 0 ? sqrt(rss / dof) : -1.0;
}

bsfit_err bsfit_segment_sigma(const double *pts, size_t m, int dim, int closed, double max_sigma,
                              double *sigma, const bsfit_allocator *a, bsfit_status *st) {
  bsfit_segment_opts o;
  bsfit_piece *p;
  size_t bytes, np = 0;
  double *d, s0, size;
  int round;
  bsfit_err e;
  memset(&o, 0, sizeof o);
  o.closed = closed;
  if (sigma) *sigma = 0;
  if (sigma == NULL) return bsfit__fail(st, BSFIT_EINVAL, "segmentation noise: sigma required");
  if ((e = bsfit__segment_check(pts, m, dim, &o, st)) != BSFIT_OK) return e;
  bytes = bsfit__mulsize(2 * m + 2, sizeof *p);
  p = bsfit__alloc(a, bytes);
  d = bsfit__alloc(a, m * sizeof *d);
  if (!p || !d) {
    e = bsfit__fail(st, BSFIT_ENOMEM, "out of memory for the noise of %zu points", m);
    goto done;
  }
  /* Below the noise, the runs stop short and their pooled residual exceeds the level
  ** they were cut at; at the noise, the models are right and it matches: the first level,
  ** rising by 10^(1/2) from well below the first guess, whose pooled residual is at most
  ** 1.2 times the level is the estimate. */
  size = bsfit__segment_size(pts, m);
  s0 = fmax(chord_sigma(pts, m, closed, d) / 16.0, 1e-9 * size);
  if (!(max_sigma > 0)) max_sigma = 0.05 * size;
  for (round = 0; round < 48 && s0 < 0.05 * size && s0 <= max_sigma;
       round++, s0 *= 3.1622776601683795) {
    double s1;
    o.sigma = s0;
    if ((round & 7) == 7 && bsfit__interrupted(a)) {
      e = bsfit__fail(st, BSFIT_EINTR, "segmentation noise interrupted");
      goto done;
    }
    if ((e = bsfit_segment(pts, m, 2, &o, p, 2 * m + 2, &np, a, st)) != BSFIT_OK) goto done;
    s1 = pooled_sigma(p, np);
    if (s1 >= 0 && s1 <= 1.2 * s0) {
      *sigma = s1 <= 1e-10 * size ? 0.0 : s1;
      break;
    }
  }
  e = bsfit__ok(st);
done:
  bsfit__free(a, p, p ? bytes : 0);
  bsfit__free(a, d, d ? m * sizeof *d : 0);
  return e;
}
