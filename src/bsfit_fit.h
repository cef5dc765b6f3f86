/*
** bsfit_fit.h
** Parameters, knot placement and weighted least-squares fitting (open and periodic).
** Included by bsfit.h; include bsfit.h rather than this file.
*/
#ifndef BSFIT_FIT_H
#define BSFIT_FIT_H

#include "bsfit.h"

#endif /* BSFIT_FIT_H */
