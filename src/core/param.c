/*
** param.c
** Parameter values for ordered points: uniform, chord length (P-8, P-9) and centripetal,
** for open data and for closed sections (closing chord counted, docs/method.md §2).
*/
#include "internal.h"

#include <math.h>

/* |a - b| scaled by its largest component (hypot's way): squares of differences below
** 1e-154 underflow to 0 and a chord of 1e-300 would vanish, making a zero total and 0/0
** parameters; scaled, every positive difference gives a positive chord */
static double chord(const double *a, const double *b, int dim) {
  double s = 0.0, big = 0.0;
  int k;
  for (k = 0; k < dim; k++) big = fmax(big, fabs(a[k] - b[k]));
  if (big == 0.0) return 0.0;
  for (k = 0; k < dim; k++) s += ((a[k] - b[k]) / big) * ((a[k] - b[k]) / big);
  return big * sqrt(s);
}

/* Length of the step between two consecutive points under the chosen kind. Uniform
** steps are always 1, so coincident points keep distinct parameters under that kind;
** chord and centripetal steps are 0 for them, so they share a parameter (never 0/0:
** the total is positive once one pair of points differs). */
static double step(const double *a, const double *b, int dim, bsfit_param_kind kind) {
  double c;
  if (kind == BSFIT_PARAM_UNIFORM) return 1.0;
  c = chord(a, b, dim);
  return kind == BSFIT_PARAM_CENTRIPETAL ? sqrt(c) : c;
}

static bsfit_err check_input(const double *pts, size_t m, int dim, bsfit_param_kind kind,
                             const double *u, bsfit_status *st) {
  size_t k, d = (size_t)dim;
  int coincident = 1;
  if (pts == NULL || u == NULL) return bsfit__fail(st, BSFIT_EINVAL, "points or parameters are NULL");
  if (dim < 1 || dim > 4) return bsfit__fail(st, BSFIT_EDIM, "dimension %d out of range 1..4", dim);
  if (kind != BSFIT_PARAM_UNIFORM && kind != BSFIT_PARAM_CHORD && kind != BSFIT_PARAM_CENTRIPETAL)
    return bsfit__fail(st, BSFIT_EINVAL, "unknown parameter kind %d", (int)kind);
  if (m < 2) return bsfit__fail(st, BSFIT_ETOOFEW, "parameters need at least 2 points, got %zu", m);
  k = bsfit__first_out_of_range(pts, m * d);
  if (k < m * d && !isfinite(pts[k]))
    return bsfit__fail(st, BSFIT_ENONFINITE, "point %zu has a NaN or Inf coordinate", k / d);
  if (k < m * d)
    return bsfit__fail(st, BSFIT_ERANGE, "point %zu has a coordinate %g beyond 1e100", k / d,
                       pts[k]);
  for (k = d; k < m * d && coincident; k++) coincident = pts[k] == pts[k % d];
  if (coincident) return bsfit__fail(st, BSFIT_EDEGENERATE, "all %zu points coincide", m);
  return BSFIT_OK;
}

bsfit_err bsfit_params(const double *pts, size_t m, int dim, bsfit_param_kind kind, int closed,
                       double *u, bsfit_status *st) {
  size_t k, d = (size_t)dim;
  double total = 0.0, acc = 0.0, last;
  bsfit_err e = check_input(pts, m, dim, kind, u, st);
  if (e != BSFIT_OK) return e;
  for (k = 1; k < m; k++) total += step(pts + (k - 1) * d, pts + k * d, dim, kind);
  last = closed ? step(pts + (m - 1) * d, pts, dim, kind) : 0.0;
  if (closed && last == 0.0)
    return bsfit__fail(st, BSFIT_EINVAL,
                       "closed data: the last point repeats the first (drop point %zu)", m - 1);
  total += last;
  if (!isfinite(total))
    return bsfit__fail(st, BSFIT_ENONFINITE, "total chord length overflows");
  u[0] = 0.0;
  for (k = 1; k < m; k++) {
    acc += step(pts + (k - 1) * d, pts + k * d, dim, kind);
    /* the running sum may round past the total: parameters stay in [0, 1] */
    u[k] = fmin(acc / total, 1.0);
  }
  /* open data ends exactly at 1 whatever the rounding of the running sum */
  if (!closed) u[m - 1] = 1.0;
  else if (u[m - 1] >= 1.0) u[m - 1] = nextafter(1.0, 0.0);
  return bsfit__ok(st);
}
