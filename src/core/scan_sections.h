/*
** scan_sections.h
** The builder the slicers (scan_slice_mesh.c, scan_slice_cloud.c) fill a
** bsfit_sections with (scan_plane.c). Private to src/core.
*/
#ifndef BSFIT_SCAN_SECTIONS_H
#define BSFIT_SCAN_SECTIONS_H

#include "scan_internal.h"

typedef struct bsfit__secbuild {
  const bsfit_allocator *a;
  size_t nslices;
  bsfit_plane *planes;   /* nslices, exact */
  size_t *first_part;    /* nslices + 1, exact */
  size_t *part_start;    /* cap_parts */
  unsigned char *closed; /* cap_closed */
  double *uv;            /* cap_points * 2 */
  size_t nparts, npoints, cap_parts, cap_closed, cap_points;
  int failed;
} bsfit__secbuild;

/* The unit vector along dir (EINVAL when zero, ENONFINITE). */
bsfit_err bsfit__unit(const double dir[3], double n[3], bsfit_status *st);

bsfit_err bsfit__secb_init(bsfit__secbuild *b, size_t nslices, const bsfit_allocator *a,
                           bsfit_status *st);
void bsfit__secb_free(bsfit__secbuild *b);
/* Appends a part of npoints 2D points; returns where to write them (NULL: no memory,
** b->failed set). The pointer is valid until the next append. */
double *bsfit__secb_part(bsfit__secbuild *b, size_t npoints, int closed);
/* Removes the last part / keeps only its first npoints points. */
void bsfit__secb_drop_last(bsfit__secbuild *b);
void bsfit__secb_truncate_last(bsfit__secbuild *b, size_t npoints);
/* Moves the result into out (freed first) and frees b, whatever the outcome. */
bsfit_err bsfit__secb_finish(bsfit__secbuild *b, bsfit_sections *out, bsfit_status *st);

/* Orients the closed parts p0..p1-1 (points uv, part_start, closed as in bsfit_sections):
** counter-clockwise when inside an even number of the others, clockwise otherwise. */
void bsfit__orient_loops(double *uv, const size_t *start, const unsigned char *closed, size_t p0,
                         size_t p1);

#endif
