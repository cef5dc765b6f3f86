/*
** bsfit_curve_ops.h
** Curve operations: derivatives, batch evaluation, knot insertion, splitting, reversal,
** degree elevation, arc length, closest point, sampling.
** Included by bsfit.h; include bsfit.h rather than this file.
*/
#ifndef BSFIT_CURVE_OPS_H
#define BSFIT_CURVE_OPS_H

#include "bsfit.h"

#endif /* BSFIT_CURVE_OPS_H */
