/*
** skin_internal.h
** The parts of skinning shared by surface_skin.c (orientation, seams, interpolation
** across) and surface_skin_knots.c (seam rotation, a common knot vector).
*/
#ifndef BSFIT_SKIN_INTERNAL_H
#define BSFIT_SKIN_INTERNAL_H

#include "internal.h"

/* C0 knots closer than this (a fraction of the period [0, 1)) are one knot in the common
** vector: a seam parameter snaps onto the nearest such knot (the seam's place is free), and
** C0 knots (multiplicity p) of different sections within it are moved onto one value by an
** exact reparametrisation (so the corners of a swept profile line up across the sections). */
#define BSFIT__SKIN_MERGE 1e-3

/* A seam parameter this near another knot snaps onto it (the seam moves by this fraction
** of the period: too little to twist the surface; any more would misalign smooth ones). */
#define BSFIT__SKIN_SNAP 1e-7

/* Knots of any multiplicity closer than this are rounding apart: moved onto one value
** (the curve moves by about this fraction of its control polygon, far below 1e-9). */
#define BSFIT__SKIN_ROUND 1e-13

/* out = c (a periodic curve on [0, 1)) started at its parameter u in [0, 1]: u is made a
** knot, then the period's knots and distinct control points are rotated so that span j
** (the first at u) becomes span 0. u = 1 moves period knots equal to 1 to the front. */
bsfit_err bsfit__skin_rotate(const bsfit_curve *c, double u, bsfit_curve *out,
                             const bsfit_allocator *a, bsfit_status *st);

/* c with its seam knot whole: period knots equal to the period's end (copies of the knot
** at 0 stored before U[p]) moved to the front, so the run at 0 starts at U[p] and every
** value of the period appears once with its full multiplicity. In place. */
bsfit_err bsfit__skin_seam_whole(bsfit_curve *c, const bsfit_allocator *a, bsfit_status *st);

/* Elevates every section to the highest degree, merges knots closer than the tolerances
** above, then refines each to the union of the period knots (largest multiplicity of each
** value): one knot vector, the same curves. */
bsfit_err bsfit__skin_compatible(bsfit_curve *w, size_t K, const bsfit_allocator *a,
                                 bsfit_status *st);

/* C0 knots (multiplicity p) of different sections within tol (BSFIT__SKIN_MERGE for the
** exact surface) moved onto one value (an exact, piecewise-affine reparametrisation;
** surface_skin_knots.c). */
bsfit_err bsfit__skin_merge_corners(bsfit_curve *w, size_t K, double tol,
                                    const bsfit_allocator *a, bsfit_status *st);

/* Corners merged before the sections are replaced by cubics within a tolerance: the cubics
** are new curves anyway, so corresponding corners fitted at parameters 2% of the period
** apart (sections of a noisy cloud) are lined up too. */
#define BSFIT__SKIN_MERGE_APPROX 2e-2

/* The C0 knot values that at least half of the K sections have, sorted, into out (room for
** all the sections' knots); returns their count. */
size_t bsfit__skin_shared_corners(const bsfit_curve *w, size_t K, double *out);

/* The sections replaced by periodic cubics on one knot vector (N uniform spans, and the
** corners most sections share), each fitted at its own chord-length parameters, N the
** smallest found that keeps each within tol of its section (Hausdorff distance, both ways).
** *count: the cubics' control points, or 0 when no N up to 4 times the largest section's
** count does (the sections unchanged); *dev: the largest distance (surface_skin_approx.c). */
bsfit_err bsfit__skin_approximate(bsfit_curve *w, size_t K, double tol, size_t *count,
                                  double *dev, const bsfit_allocator *a, bsfit_status *st);

/* Pieces of c shorter than 1e-9 of the period between two C0 knots (multiplicity p)
** whose control points lie within `limit` of the piece's start dropped, the next piece
** starting there (the curve moves by at most the largest spread, into *moved, which is
** only raised). c is periodic on [0, 1), 3D, polynomial (surface_skin_slivers.c). */
bsfit_err bsfit__skin_drop_slivers(bsfit_curve *c, double limit, double *moved,
                                   const bsfit_allocator *a, bsfit_status *st);

/* The Hausdorff distance between section c and its cubic f into *dev: c's m samples pts
** (at its sorted parameters t) projected onto f from their fitting parameters s (sorted),
** f's points at s and inside its spans given their closest points on c, each way's local
** maxima refined (surface_skin_distance.c). Once a way exceeds tol the other is skipped:
** *dev > tol then bounds the distance from below only. */
bsfit_err bsfit__skin_distance(const bsfit_curve *c, const bsfit_curve *f, const double *t,
                               const double *s, const double *pts, size_t m, double tol,
                               double *dev, const bsfit_allocator *a, bsfit_status *st);

#endif
