/*
** bsfit_scan.h
** From a scan to sections: reading triangle meshes and point clouds (PLY, STL, OBJ,
** XYZ/CSV), cutting them by parallel planes (meshes exactly, clouds by slabs), the
** centre-of-mass reduction of a section's points (Fonseca Jr & Carvalho) and the
** ordering of reduced points into loops. Included by bsfit.h; include bsfit.h.
**
** Indices in messages count from 1 (vertex 1 is the file's first vertex), byte
** offsets count from 0, lines from 1. Vertex indices stored in bsfit_scan.tri are
** 0-based (C arrays).
*/
#ifndef BSFIT_SCAN_H
#define BSFIT_SCAN_H

#include "bsfit.h"

#include <stdint.h>

/* {====================================================================
** Scans: a mesh (vertices + triangles) or a cloud (vertices only)
** ===================================================================== */

/** A scan read from a file. Faces with more than three vertices are split into fans
** of triangles; STL files have their identical vertices merged (exact coordinates), so
** triangles share vertex ids and slicing can chain them. */
typedef struct bsfit_scan {
  double *xyz;           /**< nv*3 coordinates, row-major */
  size_t nv;             /**< number of vertices */
  uint32_t *tri;         /**< nt*3 vertex ids (0-based), NULL for a cloud */
  size_t nt;             /**< number of triangles (0 for a cloud) */
  bsfit_allocator alloc; /**< what xyz and tri were allocated with */
} bsfit_scan;

/** File formats of bsfit_scan_read / bsfit_scan_parse. */
typedef enum bsfit_scan_format {
  BSFIT_SCAN_AUTO = 0, /**< from the file name's extension (read only) */
  BSFIT_SCAN_PLY,      /**< PLY: ascii, binary_little_endian, binary_big_endian */
  BSFIT_SCAN_STL,      /**< STL: ASCII or binary (told apart by size and content) */
  BSFIT_SCAN_OBJ,      /**< Wavefront OBJ: v and f lines */
  BSFIT_SCAN_XYZ       /**< point text (bsfit_points_parse) with x, y, z columns */
} bsfit_scan_format;

/** An empty scan, safe to free. */
BSFIT_API void bsfit_scan_init(bsfit_scan *s);
/** Releases a scan's arrays (NULL-safe, idempotent); s becomes empty. */
BSFIT_API void bsfit_scan_free(bsfit_scan *s);

/** Parses a scan held in memory.
** @param[in]  data  len bytes of the file.
** @param[in]  fmt   the format (not BSFIT_SCAN_AUTO).
** @param[in]  name  the file name used in messages (may be NULL: "<scan>").
** @param[out] s     filled on success (freed first); empty on error. Arrays are
**                   allocated with a and released by bsfit_scan_free.
** @return BSFIT_OK; BSFIT_EFORMAT (the message names the file and the element, line or
**         byte offset: bad header, a number that does not parse, a truncated file, a
**         face with fewer than 3 vertices, a vertex index out of range); BSFIT_ENONFINITE
**         (a vertex with a NaN or infinite coordinate, named); BSFIT_ETOOFEW (no
**         vertices); BSFIT_EINVAL (bad arguments, more than 2^32-1 vertices); BSFIT_ENOMEM. */
BSFIT_API bsfit_err bsfit_scan_parse(const char *data, size_t len, bsfit_scan_format fmt,
                                     const char *name, bsfit_scan *s, const bsfit_allocator *a,
                                     bsfit_status *st);

/** Reads a scan file. fmt BSFIT_SCAN_AUTO takes the format from the extension
** (case-insensitive): .ply, .stl, .obj, and .xyz .csv .txt .pts .asc for clouds.
** @return bsfit_scan_parse's codes; BSFIT_EIO (the file cannot be read); BSFIT_EINVAL
**         (an unknown extension). */
BSFIT_API bsfit_err bsfit_scan_read(const char *path, bsfit_scan_format fmt, bsfit_scan *s,
                                    const bsfit_allocator *a, bsfit_status *st);

/* }==================================================================== */

/* {====================================================================
** Planes and sections
** ===================================================================== */

/** A cutting plane with its frame: the points origin + x u + y v, where (u, v, normal)
** is a right-handed orthonormal frame and origin = position * normal. Loops that are
** counter-clockwise in (u, v) are counter-clockwise seen from +normal. */
typedef struct bsfit_plane {
  double position; /**< signed distance of the plane from (0,0,0) along normal */
  double origin[3], u[3], v[3], normal[3];
} bsfit_plane;

/** The frame of the plane {x : x.n = position}, n = dir normalised. For the axes the
** frame is fixed: x: (u, v) = (y, z); y: (z, x); z: (x, y). Other directions take
** u = normalise(e x n) with e the axis least aligned with n.
** @return BSFIT_OK, BSFIT_EINVAL (dir NULL or zero), BSFIT_ENONFINITE. */
BSFIT_API bsfit_err bsfit_plane_frame(const double dir[3], double position, bsfit_plane *p,
                                      bsfit_status *st);

/** The range [*lo, *hi] of x.n over n points (dir normalised). @return BSFIT_OK,
** BSFIT_EINVAL (no points, dir zero), BSFIT_ENONFINITE (a coordinate, named 1-based). */
BSFIT_API bsfit_err bsfit_scan_extent(const double *xyz, size_t n, const double dir[3], double *lo,
                                      double *hi, bsfit_status *st);

/** The sections of a slicing: for slice i (planes[i]), parts first_part[i] ..
** first_part[i+1]-1; part j holds the 2D points uv[2*part_start[j]] ..
** uv[2*part_start[j+1]-1] in its plane's (u, v) frame. A mesh's parts are its loops
** (closed[j] = 1) and open chains (closed[j] = 0, where the mesh has a hole); a
** cloud's slice has exactly one part, the slab's points (closed[j] = 0). */
typedef struct bsfit_sections {
  size_t nslices, nparts, npoints;
  bsfit_plane *planes;   /**< nslices */
  size_t *first_part;    /**< nslices + 1 */
  size_t *part_start;    /**< nparts + 1 */
  unsigned char *closed; /**< nparts */
  double *uv;            /**< npoints * 2 */
  bsfit_allocator alloc;
} bsfit_sections;

/** An empty set of sections, safe to free. */
BSFIT_API void bsfit_sections_init(bsfit_sections *s);
/** Releases the arrays (NULL-safe, idempotent). */
BSFIT_API void bsfit_sections_free(bsfit_sections *s);

/** Cuts a mesh by the planes x.n = pos[i] (n = dir normalised) exactly. Vertices within
** tol of a plane count as on it (tol <= 0: 1e-9 of the bounding box diagonal) and are
** treated as lying on its +normal side (a symbolic perturbation), so a vertex, an edge or
** a whole face on the plane gives one clean loop: the plane through a face that bounds
** the solid from below is retried with the perturbation towards -normal. Crossing points
** are identified by their edge's vertex ids, never by coordinates, so loops chain
** exactly; consecutive points closer than tol are merged; loops of fewer than 3
** distinct points are dropped. Loops are counter-clockwise seen from +normal when not
** inside another loop of the slice, clockwise when inside an odd number of them.
** Cost: O(nt log npos + crossings).
** @param[out] out  freed first; filled on success (arrays allocated with a).
** @return BSFIT_OK; BSFIT_EINVAL (no triangles, npos 0, dir zero, a triangle naming a
**         vertex that does not exist); BSFIT_ENONFINITE (a vertex or position);
**         BSFIT_ENOMEM; BSFIT_EINTR. */
BSFIT_API bsfit_err bsfit_mesh_slice(const bsfit_scan *m, const double dir[3], const double *pos,
                                     size_t npos, double tol, bsfit_sections *out,
                                     const bsfit_allocator *a, bsfit_status *st);

/** Cuts a cloud into slabs |x.n - pos[i]| <= thickness/2 and projects each slab's points
** onto its plane (one part per slice, points in file order). Slabs may overlap.
** Cost: O(n log npos + output).
** @return BSFIT_OK; BSFIT_EINVAL (n or npos 0, thickness not > 0, dir zero);
**         BSFIT_ENONFINITE; BSFIT_ENOMEM; BSFIT_EINTR. */
BSFIT_API bsfit_err bsfit_cloud_slice(const double *xyz, size_t n, const double dir[3],
                                      const double *pos, size_t npos, double thickness,
                                      bsfit_sections *out, const bsfit_allocator *a,
                                      bsfit_status *st);

/* }==================================================================== */

/* {====================================================================
** Centre-of-mass reduction (Fonseca Jr & Carvalho)
** ===================================================================== */

/** Replaces the points of each cell of a square grid of side `cell` (cells [i c, (i+1) c)
** x [j c, (j+1) c)) by their (weighted) mean; the point's weight is the sum of the
** weights of the cell's points (their count when w is NULL). Output points come in the
** order of each cell's first point. O(m) (hashing).
** @param[in]  xy     m 2D points.   @param[in] w  m positive weights or NULL.
** @param[out] out_xy room for m*2 doubles.   @param[out] out_w  room for m doubles.
** @param[out] out_m  number of reduced points.
** @return BSFIT_OK; BSFIT_EINVAL (m 0, NULL arrays, cell not > 0 or so small that a cell
**         index overflows); BSFIT_ENONFINITE; BSFIT_EWEIGHT; BSFIT_ENOMEM; BSFIT_EINTR. */
BSFIT_API bsfit_err bsfit_reduce_grid(const double *xy, size_t m, const double *w, double cell,
                                      double *out_xy, double *out_w, size_t *out_m,
                                      const bsfit_allocator *a, bsfit_status *st);

/** As bsfit_reduce_grid with the cell size chosen by bisection (on its logarithm) so that
** about `target` points remain (within 5%, or the closest count found in 60 steps).
** @param[out] cell_used the cell size chosen.
** @return bsfit_reduce_grid's codes; BSFIT_EINVAL (target 0); BSFIT_EDEGENERATE (all the
**         points coincide). A target >= m returns the points unchanged (weights 1 or w). */
BSFIT_API bsfit_err bsfit_reduce_target(const double *xy, size_t m, const double *w, size_t target,
                                        double *cell_used, double *out_xy, double *out_w,
                                        size_t *out_m, const bsfit_allocator *a, bsfit_status *st);

/* }==================================================================== */

/* {====================================================================
** Ordering points into loops
** ===================================================================== */

/** How bsfit_order orders. */
typedef enum bsfit_order_method {
  /** angle when the points pass the star test and the graph tour is not shorter, else graph */
  BSFIT_ORDER_AUTO = 0,
  /** angle about the centroid (one closed loop; refused when not star-shaped) */
  BSFIT_ORDER_ANGLE,
  /** k-nearest-neighbour graph, minimum spanning forest, 2-opt */
  BSFIT_ORDER_GRAPH
} bsfit_order_method;

/** Settings of bsfit_order (bsfit_order_opts_init gives the defaults). */
typedef struct bsfit_order_opts {
  bsfit_order_method method;
  int k;             /**< neighbours per point in the graph (default 8, 2..32) */
  double gap;        /**< a step longer than gap times the local spacing splits or opens a
                       loop (default 4) */
  size_t min_points; /**< parts with fewer points are dropped as outliers (default 3) */
} bsfit_order_opts;

/** The loops found: loop j is the points index[start[j]] .. index[start[j+1]-1] (0-based
** indices into the input), closed[j] says whether it closes. Dropped points appear in no
** loop. */
typedef struct bsfit_order_result {
  size_t *index;         /**< m entries (the first start[nloops] used) */
  size_t *start;         /**< nloops + 1 */
  unsigned char *closed; /**< nloops */
  size_t nloops;
  size_t dropped;            /**< points in parts smaller than min_points */
  bsfit_order_method method; /**< ANGLE or GRAPH: what was used */
  int star;                  /**< whether the points passed the star-shape test */
  size_t capacity;           /**< m, the size the arrays were allocated for */
  bsfit_allocator alloc;
} bsfit_order_result;

BSFIT_API void bsfit_order_opts_init(bsfit_order_opts *o);
BSFIT_API void bsfit_order_result_init(bsfit_order_result *r);
BSFIT_API void bsfit_order_result_free(bsfit_order_result *r);

/** Orders m 2D points into loops. The local spacing of a point is its distance to its 2nd
** nearest neighbour (floored at a quarter of the median); a step from a to b is judged
** against gap * sqrt(spacing(a) spacing(b)), so a lone outlier cannot bridge to the section.
** Star test: every step of the order by angle about the centroid is short. Graph: the
** minimum spanning forest of the k-nearest-neighbour graph without its long edges (each tree
** is one part); each tree's longest path is the backbone, closed when its ends are near; the
** other points are inserted next to their tree neighbour where that lengthens the tour least;
** 2-opt moves over the neighbour lists then remove crossings. AUTO keeps the angular order
** only when the graph tour is not shorter. Loops are counter-clockwise unless inside another
** loop (then clockwise). O(m k log m). r must have been initialised (bsfit_order_result_init).
** @return BSFIT_OK; BSFIT_EINVAL (m 0, bad options, ANGLE asked for points that are not
**         star-shaped); BSFIT_ENONFINITE; BSFIT_ETOOFEW (no part of min_points points);
**         BSFIT_ENOMEM; BSFIT_EINTR. */
BSFIT_API bsfit_err bsfit_order(const double *xy, size_t m, const bsfit_order_opts *o,
                                bsfit_order_result *r, const bsfit_allocator *a, bsfit_status *st);

/* }==================================================================== */

/* {====================================================================
** Writing the sections' curves
** ===================================================================== */

/** Formats n valid curves (dim 1..3) as one IGES 5.3 file with one entity 126 per curve,
** in order (DE 1, 3, 5, ...), each as bsfit_curve_to_iges writes it alone.
** @param[out] out *len+1 bytes allocated with a (the caller frees them with it).
** @return BSFIT_OK, BSFIT_EINVAL (no curves, a NULL curve), bsfit_curve_to_iges's codes. */
BSFIT_API bsfit_err bsfit_curves_to_iges(const bsfit_curve *const *c, size_t n, char **out,
                                         size_t *len, const bsfit_allocator *a, bsfit_status *st);

/** Writes bsfit_curves_to_iges's text to path atomically. */
BSFIT_API bsfit_err bsfit_curves_write_iges(const bsfit_curve *const *c, size_t n, const char *path,
                                            bsfit_status *st);

/* }==================================================================== */

#endif
