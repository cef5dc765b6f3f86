/*
** bsfit_io.h
** Point files (CSV / whitespace text, SPEC section 4).
** Included by bsfit.h; include bsfit.h rather than this file.
*/
#ifndef BSFIT_IO_H
#define BSFIT_IO_H

#include "bsfit.h"

#endif /* BSFIT_IO_H */
