/*
** fuzz_filter.c
** The box filters: the moving average (k control points, uniform curves), the exact
** filter of half-width delta (any polynomial curve), and the metrics that compare
** a curve with its filtered self. Contract: OK => a valid curve of one degree more
** with every number finite, and the metrics of it finite.
*/
#include "fuzz_curve_make.h"

static void check_filtered(const bsfit_curve *c, const bsfit_curve *f, const char *what) {
  double dev, turn;
  bsfit_status st;
  fz_check_curve(f, what);
  if (f->degree != c->degree + 1) fz_fail(what, "degree not raised by one");
  if (bsfit_curve_max_deviation(c, f, 64, &dev, &st) == BSFIT_OK && fz_strict && !isfinite(dev))
    fz_fail(what, "max_deviation not finite");
  if (bsfit_curve_total_turning(f, 64, &turn, &st) == BSFIT_OK && fz_strict && !isfinite(turn))
    fz_fail(what, "total_turning not finite");
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size) {
  fuzz_in in = {data, size};
  bsfit_curve c, f;
  bsfit_status st;
  bsfit_curve_init(&c);
  bsfit_curve_init(&f);
  if (fz_make_curve(&in, &c, &st) == BSFIT_OK) {
    double a, b, delta;
    int k = 1 + fz_byte(&in) % 8;
    fz_strict =
        fz_tame(c.ctrl, c.n * (size_t)c.dim) && fz_tame(c.knots, c.n + (size_t)c.degree + 1);
    if (bsfit_filter_box_curve(&c, k, &f, &st) == BSFIT_OK) check_filtered(&c, &f, "box k");
    bsfit_curve_free(&f);
    bsfit_knots_domain(c.knots, c.n, c.degree, &a, &b);
    delta = fz_byte(&in) < 200 ? (b - a) * (double)(1 + fz_byte(&in)) / 512.0 : fz_double(&in);
    if (bsfit_filter_box_curve_delta(&c, delta, &f, &st) == BSFIT_OK)
      check_filtered(&c, &f, "box delta");
  }
  bsfit_curve_free(&f);
  bsfit_curve_free(&c);
  return 0;
}
