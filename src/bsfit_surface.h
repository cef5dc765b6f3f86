/*
** bsfit_surface.h
** Tensor-product B-spline / NURBS / Bézier surfaces.
** Included by bsfit.h; include bsfit.h rather than this file.
*/
#ifndef BSFIT_SURFACE_H
#define BSFIT_SURFACE_H

#include "bsfit.h"

/** A tensor-product surface S(u,v) = sum_i sum_j V_ij B_i(u) B_j(v) (rational when
** `weights` is not NULL). Control net row-major over (i, j): point (i, j) starts at
** ctrl[(i * nv + j) * dim]; weights[i * nv + j]. Knots: nu+pu+1 in u, nv+pv+1 in v.
** `bezier` surfaces have nu = pu+1, nv = pv+1 and clamped [0,1] knots. */
typedef struct bsfit_surface {
  int degree_u, degree_v;
  int dim;               /**< 1..4 (3 for ordinary surfaces) */
  int bezier;
  size_t nu, nv;         /**< control points in u and v */
  double *knots_u;       /**< nu + degree_u + 1 */
  double *knots_v;       /**< nv + degree_v + 1 */
  double *ctrl;          /**< nu * nv * dim */
  double *weights;       /**< nu * nv, or NULL */
  bsfit_allocator alloc;
} bsfit_surface;

#endif /* BSFIT_SURFACE_H */
