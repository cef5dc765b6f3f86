/*
** bsfit_geom.h
** Geometry kernels on point sequences used by the fitting strategies (SPEC 2.5-2.7):
** circumradius weights, turning angles, curvature inversions, local spacing.
** Included by bsfit.h; include bsfit.h rather than this file.
*/
#ifndef BSFIT_GEOM_H
#define BSFIT_GEOM_H

#include "bsfit.h"

#endif /* BSFIT_GEOM_H */
