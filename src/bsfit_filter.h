/*
** bsfit_filter.h
** Smoothing by box filtering of splines (Persiano).
** Included by bsfit.h; include bsfit.h rather than this file.
*/
#ifndef BSFIT_FILTER_H
#define BSFIT_FILTER_H

#include "bsfit.h"

#endif /* BSFIT_FILTER_H */
