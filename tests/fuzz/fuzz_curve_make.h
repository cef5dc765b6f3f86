/*
** fuzz_curve_make.h
** A curve from the fuzzer's bytes, for the curve and filter targets: degree 0..7,
** dimension 1..4, 1..24 control points, open (clamped or not), periodic or Bézier,
** polynomial or rational; knots from non-negative steps (zero steps make repeated
** knots). Returns the code of the constructor; c holds the curve on BSFIT_OK.
*/
#ifndef BSFIT_FUZZ_CURVE_MAKE_H
#define BSFIT_FUZZ_CURVE_MAKE_H

#include "fuzz_util.h"

#define FZ_MAXN 24

static inline bsfit_err fz_make_curve(fuzz_in *in, bsfit_curve *c, bsfit_status *st) {
  double knots[FZ_MAXN + 16], ctrl[FZ_MAXN * 4], w[FZ_MAXN];
  int kind = fz_byte(in) % 4, p = fz_byte(in) % 8, dim = 1 + fz_byte(in) % 4;
  int rational = fz_byte(in) % 3 == 0, clamped = fz_byte(in) % 2;
  size_t n = (size_t)(1 + fz_byte(in) % FZ_MAXN), i, nk;
  double x = fz_double(in);
  if (kind == 1 && n < 2) n = 2;
  nk = kind == 1 ? n + 1 : n + (size_t)p + 1;
  for (i = 0; i < nk; i++) { /* steps: mostly positive, sometimes zero, rarely anything */
    uint8_t s = fz_byte(in);
    if (i > 0) x += s < 40 ? 0.0 : s < 250 ? (double)s / 64.0 : fabs(fz_double(in));
    if (s == 255) x = fz_double(in);
    knots[i] = x;
    if (kind == 0 && clamped && i > 0 && (i <= (size_t)p || i >= n)) knots[i] = knots[i - 1];
  }
  for (i = 0; i < n * (size_t)dim; i++) ctrl[i] = fz_double(in);
  for (i = 0; i < n; i++)
    w[i] = fz_byte(in) < 250 ? 0.25 + (double)fz_byte(in) / 32.0 : fz_double(in);
  switch (kind) {
    case 1:
      return bsfit_curve_new_periodic(c, p, dim, n, knots, ctrl, rational ? w : NULL, NULL, st);
    case 2:
      return bsfit_curve_new_bezier(c, dim, n, ctrl, rational ? w : NULL, NULL, st);
    default:
      return bsfit_curve_new(c, p, dim, n, knots, ctrl, rational ? w : NULL, 0, NULL, st);
  }
}

/* A parameter: inside the domain [a, b] mostly, anywhere sometimes. */
static inline double fz_param(fuzz_in *in, const bsfit_curve *c) {
  double a, b;
  uint8_t k = fz_byte(in);
  bsfit_knots_domain(c->knots, c->n, c->degree, &a, &b);
  if (k < 200) return a + (b - a) * (double)fz_byte(in) / 255.0;
  if (k < 230) return k % 2 ? a : b;
  {
    return fz_double(in);
  }
}

#endif
