/*
** fuzz_points.c
** The point-file reader: bsfit_points_parse on the bytes, and bsfit_points_read
** (the streaming reader) on the same bytes written to a file. Contract: OK =>
** m >= 1, dim 2 or 3, every coordinate finite, every weight finite and > 0; the two
** readers agree (points, weights, or the error code), except that the file reader
** refuses lines longer than 64 KiB.
*/
#include "fuzz_util.h"

#include <unistd.h>

static char path[64];

static void write_file(const uint8_t *data, size_t size) {
  FILE *f;
  if (path[0] == '\0') snprintf(path, sizeof path, "/tmp/fuzz_points.%ld.csv", (long)getpid());
  f = fopen(path, "wb");
  if (f == NULL) abort();
  if (size > 0 && fwrite(data, 1, size, f) != size) abort();
  fclose(f);
}

static int has_long_line(const uint8_t *data, size_t size) {
  size_t i, run = 0;
  for (i = 0; i < size; i++) {
    run = data[i] == '\n' ? 0 : run + 1;
    if (run > 65536) return 1;
  }
  return 0;
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size) {
  double *xy = NULL, *w = NULL, *xy2 = NULL, *w2 = NULL;
  size_t m = 0, m2 = 0, i;
  int dim = 0, dim2 = 0;
  bsfit_status st, st2;
  bsfit_err e = bsfit_points_parse((const char *)data, size, &xy, &m, &dim, &w, NULL, &st), e2;
  if (e == BSFIT_OK) {
    if (m < 1 || (dim != 2 && dim != 3)) fz_fail("points: shape", st.msg);
    fz_check_finite(xy, m * (size_t)dim, "points: coordinates");
    for (i = 0; w && i < m; i++)
      if (!isfinite(w[i]) || !(w[i] > 0)) fz_fail("points: weights", NULL);
  } else if (xy != NULL || m != 0) {
    fz_fail("points: outputs set on error", st.msg);
  }
  write_file(data, size);
  e2 = bsfit_points_read(path, &xy2, &m2, &dim2, &w2, NULL, &st2);
  if (!has_long_line(data, size)) {
    if (e2 != e) fz_fail("points: read and parse disagree", st2.msg);
    if (e == BSFIT_OK &&
        (m2 != m || dim2 != dim || memcmp(xy, xy2, m * (size_t)dim * sizeof(double)) != 0 ||
         (w == NULL) != (w2 == NULL) || (w && memcmp(w, w2, m * sizeof(double)) != 0)))
      fz_fail("points: read and parse give different points", NULL);
  }
  bsfit_points_free(xy, m, dim, w, NULL);
  bsfit_points_free(xy2, m2, dim2, w2, NULL);
  return 0;
}
