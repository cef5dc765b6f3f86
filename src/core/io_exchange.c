/*
** io_exchange.c
** What the CAD exchange writers share (io_step.c, io_iges.c, io_iges_set.c, io_dxf.c): the
** check of a curve a format can hold, and writing the text a writer made to its file.
*/
#include "io_internal.h"

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
