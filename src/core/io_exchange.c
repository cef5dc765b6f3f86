/*
** io_exchange.c
** What the CAD exchange writers share (io_step.c, io_iges.c, io_iges_set.c, io_dxf.c): the
** check of a curve a format can hold, the file's time stamp, and writing the text a writer
** made to its file.
*/
#define _POSIX_C_SOURCE 200809L /* gmtime_r */

#include "io_internal.h"

#include <stdlib.h>
#include <string.h>
#include <time.h>

bsfit_err bsfit__exchange_check_curve(const bsfit_curve *c, size_t k, const char *format,
                                      const char *kind, bsfit_status *st) {
  bsfit_err e;
  if (c == NULL) return bsfit__fail(st, BSFIT_EINVAL, "curve %zu is NULL", k);
  e = bsfit_curve_validate(c, st);
  if (e != BSFIT_OK) return e;
  if (c->dim < 2 || c->dim > 3)
    return bsfit__fail(st, BSFIT_EDIM, "%s holds 2D and 3D curves, curve %zu has dim %d", format,
                       k, c->dim);
  if (c->degree < 1)
    return bsfit__fail(st, BSFIT_EDEGREE, "%s have degree >= 1, curve %zu has degree 0", kind, k);
  return BSFIT_OK;
}

bsfit_err bsfit__exchange_write(bsfit_err made, char *text, size_t len, const char *path,
                                bsfit_status *st) {
  bsfit_err e;
  if (made != BSFIT_OK) return made;
  e = bsfit__write_atomic(path, text != NULL ? text : "", len, 1, st);
  bsfit__free(NULL, text, len + 1);
  return e;
}

void bsfit__exchange_time(const char *fmt, char *out, size_t size, const char *fallback) {
  const char *epoch = getenv("SOURCE_DATE_EPOCH");
  time_t now = time(NULL);
  struct tm tmv;
  if (epoch != NULL && *epoch >= '0' && *epoch <= '9') {
    char *end;
    unsigned long long v = strtoull(epoch, &end, 10);
    if (*end == '\0' && v <= 253402300799ULL) now = (time_t)v; /* up to 9999-12-31 */
  }
  if (now == (time_t)-1 || gmtime_r(&now, &tmv) == NULL ||
      strftime(out, size, fmt, &tmv) != strlen(fallback))
    strcpy(out, fallback);
}
