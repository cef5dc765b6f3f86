/*
** status.c
** Status codes, their messages and names, and the version of the library.
*/
#include "internal.h"

#include <stdarg.h>
#include <stdio.h>

int bsfit_version_number(void) { return BSFIT_VERSION_NUMBER; }

const char *bsfit_version(void) { return BSFIT_VERSION; }

typedef struct err_info {
  bsfit_err code;
  const char *name;
  const char *text;
} err_info;

static const err_info err_table[] = {
  {BSFIT_OK, "OK", "no error"},
  {BSFIT_ENOMEM, "ENOMEM", "not enough memory"},
  {BSFIT_EDIM, "EDIM", "bad or mismatched dimension"},
  {BSFIT_EDEGREE, "EDEGREE", "bad degree for the number of control points"},
  {BSFIT_EDOMAIN, "EDOMAIN", "parameter outside the domain, or empty domain"},
  {BSFIT_EMULT, "EMULT", "knot multiplicity too high"},
  {BSFIT_EKNOTS_DECR, "EKNOTS_DECR", "knots are decreasing"},
  {BSFIT_ENKNOTS, "ENKNOTS", "wrong number of knots"},
  {BSFIT_EINVAL, "EINVAL", "invalid argument"},
  {BSFIT_ENONFINITE, "ENONFINITE", "NaN or infinite value in the input"},
  {BSFIT_EWEIGHT, "EWEIGHT", "weight is zero, negative or not finite"},
  {BSFIT_ETOOFEW, "ETOOFEW", "too few points"},
  {BSFIT_EDEGENERATE, "EDEGENERATE", "degenerate geometry"},
  {BSFIT_ENOTPERIODIC, "ENOTPERIODIC", "curve is not in periodic form"},
  {BSFIT_ERANGE, "ERANGE", "value beyond the supported range"},
  {BSFIT_ESINGULAR, "ESINGULAR", "singular system"},
  {BSFIT_ENOTSPD, "ENOTSPD", "matrix not positive definite"},
  {BSFIT_ENOCONV, "ENOCONV", "iteration did not converge"},
  {BSFIT_ELAPACK, "ELAPACK", "LAPACK rejected an argument"},
  {BSFIT_EEMPTYSPAN, "EEMPTYSPAN", "a knot span holds no data"},
  {BSFIT_EIO, "EIO", "input/output error"},
  {BSFIT_EFORMAT, "EFORMAT", "malformed input"},
  {BSFIT_EINTR, "EINTR", "interrupted"},
};

static const err_info *find_err(bsfit_err code) {
  size_t i;
  for (i = 0; i < sizeof err_table / sizeof err_table[0]; i++)
    if (err_table[i].code == code) return &err_table[i];
  return NULL;
}

const char *bsfit_strerror(bsfit_err code) {
  const err_info *e = find_err(code);
  return e ? e->text : "unknown error";
}

const char *bsfit_errname(bsfit_err code) {
  const err_info *e = find_err(code);
  return e ? e->name : "EUNKNOWN";
}

bsfit_err bsfit__fail(bsfit_status *st, bsfit_err code, const char *fmt, ...) {
  if (st != NULL) {
    va_list ap;
    st->code = code;
    va_start(ap, fmt);
    vsnprintf(st->msg, sizeof st->msg, fmt, ap);
    va_end(ap);
  }
  return code;
}

bsfit_err bsfit__ok(bsfit_status *st) {
  if (st != NULL) {
    st->code = BSFIT_OK;
    st->msg[0] = '\0';
  }
  return BSFIT_OK;
}
