/*
** fuzz_util.h
** What the libFuzzer targets share: a reader that turns the fuzzer's bytes into
** sizes and numbers (mostly tame values, so the fuzzer reaches deep paths, sometimes
** raw doubles: NaN, Inf, subnormals, 1e308), and the contract checks. A broken
** contract aborts, which libFuzzer reports as a crash with the input saved.
*/
#ifndef BSFIT_FUZZ_UTIL_H
#define BSFIT_FUZZ_UTIL_H

#include <math.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "bsfit.h"

typedef struct fuzz_in {
  const uint8_t *p;
  size_t n;
} fuzz_in;

static inline uint8_t fz_byte(fuzz_in *in) {
  uint8_t b;
  if (in->n == 0) return 0;
  b = *in->p++;
  in->n--;
  return b;
}

/* An integer in [lo, hi] (hi - lo < 65536). */
static inline int fz_int(fuzz_in *in, int lo, int hi) {
  unsigned v = (unsigned)fz_byte(in) | (unsigned)fz_byte(in) << 8;
  return lo + (int)(v % (unsigned)(hi - lo + 1));
}

/* A number: usually a small value with a few digits, sometimes any double. */
static inline double fz_double(fuzz_in *in) {
  uint8_t kind = fz_byte(in);
  if (kind < 200) return (double)(int16_t)(fz_byte(in) | fz_byte(in) << 8) / 64.0;
  if (kind < 240) return (double)(int8_t)fz_byte(in) * pow(10.0, (double)fz_int(in, -12, 12));
  {
    double x = 0;
    uint8_t b[8];
    int i;
    for (i = 0; i < 8; i++) b[i] = fz_byte(in);
    memcpy(&x, b, sizeof x);
    return x;
  }
}

static inline void fz_fail(const char *what, const char *detail) {
  fprintf(stderr, "CONTRACT BROKEN: %s (%s)\n", what, detail ? detail : "");
  abort();
}

/* Whether the finiteness of results is checked for this input. Inputs with numbers
** beyond 1e100 (control points, weights, knots) are run for memory errors and validity
** only: the core still accepts coordinates whose products overflow (issue 13, item 9,
** owned by the curve validation; the regression inputs are kept in regressions/). */
static int fz_strict = 1;

static inline int fz_tame(const double *x, size_t n) {
  size_t i;
  for (i = 0; i < n; i++)
    if (!(fabs(x[i]) <= 1e100) || (x[i] != 0 && fabs(x[i]) < 1e-100)) return 0;
  return 1;
}

static inline void fz_check_finite(const double *x, size_t n, const char *what) {
  size_t i;
  if (!fz_strict) return;
  for (i = 0; i < n; i++)
    if (!isfinite(x[i])) fz_fail(what, "not finite");
}

/* OK => the curve is valid and every number in it finite (finite: strict inputs). */
static inline void fz_check_curve(const bsfit_curve *c, const char *what) {
  bsfit_status st;
  if (bsfit_curve_validate(c, &st) != BSFIT_OK) fz_fail(what, st.msg);
  fz_check_finite(c->knots, c->n + (size_t)c->degree + 1, what);
  fz_check_finite(c->ctrl, c->n * (size_t)c->dim, what);
  if (c->weights) fz_check_finite(c->weights, c->n, what);
}

#endif
