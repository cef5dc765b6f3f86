/*
** bsfit_io.h
** Files (docs/formats.md): point files (CSV / whitespace text), curve and surface JSON,
** SVG pictures, IGES 5.3 export (entities 126 and 128), and atomic file writing.
** Included by bsfit.h; include bsfit.h rather than this file.
**
** Every writer here replaces its target atomically (bsfit_write_file_atomic): on any
** error the previous file is left untouched and no temporary remains.
** Numbers are written with "%.17g" so that they read back bit for bit; the library
** never calls setlocale, and a host that sets LC_NUMERIC to a locale with a decimal
** comma must restore "C" around these calls.
*/
#ifndef BSFIT_IO_H
#define BSFIT_IO_H

#include "bsfit.h"

/* {====================================================================
** Atomic writing
** ===================================================================== */

/** Writes len bytes of data to path atomically: the bytes go to a new temporary
** `path.tmp.<pid>.<n>` in the same directory, which is fsync'ed and then renamed over
** path. On any error the temporary is removed and path is untouched.
** @return BSFIT_OK, BSFIT_EINVAL (path NULL or empty, data NULL with len > 0) or
**         BSFIT_EIO (message names the file and the system's reason). */
BSFIT_API bsfit_err bsfit_write_file_atomic(const char *path, const char *data, size_t len,
                                            bsfit_status *st);

/* }==================================================================== */

/* {====================================================================
** Point files
** Text, one point a line: fields separated by ';' (if the line has one), else by ','
** (if it has one), else by blanks. '#' starts a comment; blank lines are ignored.
** An optional header line names the columns, any order, case-insensitive, from
** x, y, z, w (x and y required). Without a header: 2 columns are x,y; 3 are x,y,z;
** 4 are x,y,z,w. w is the per-point weight.
** ===================================================================== */

/** Parses point text.
** @param[in]  text  len bytes (need not be NUL-terminated).
** @param[out] xy    *m * *dim doubles, row-major [x0,y0,(z0,)x1,...]; allocated with a,
**                   to be released by bsfit_points_free (or with a, size m*dim*8).
** @param[out] m     number of points (>= 1).
** @param[out] dim   2, or 3 when there is a z column.
** @param[out] w     when not NULL: *w receives m weights (allocated with a, size m*8),
**                   or NULL when the text has no w column. When w itself is NULL the
**                   weights are checked and dropped.
** On error the outputs are set to NULL / 0 and nothing is left allocated.
** @return BSFIT_OK; BSFIT_EFORMAT (line N: unknown or repeated column name, missing
**         x or y, a field that is not a number, a row with the wrong number of
**         columns, 1 or more than 4 columns); BSFIT_ENONFINITE (line N: NaN or Inf);
**         BSFIT_EWEIGHT (line N: zero or negative weight); BSFIT_ETOOFEW (no data);
**         BSFIT_EINVAL (text NULL with len > 0, or xy/m/dim NULL); BSFIT_ENOMEM. */
BSFIT_API bsfit_err bsfit_points_parse(const char *text, size_t len, double **xy, size_t *m,
                                       int *dim, double **w, const bsfit_allocator *a,
                                       bsfit_status *st);

/** Reads a point file; as bsfit_points_parse, messages prefixed with "path:line:".
** The file is read line by line (streaming): memory grows with the points kept, not
** with the file, and reading stops at the first bad line. A UTF-8 byte order mark
** before the first line is skipped.
** @return the codes of bsfit_points_parse, BSFIT_EFORMAT also for a line longer than
**         64 KiB or holding a NUL byte (binary data: the rest is not read), and
**         BSFIT_EIO (the file cannot be read, e.g. a directory: the message gives the
**         path and the system's reason). */
BSFIT_API bsfit_err bsfit_points_read(const char *path, double **xy, size_t *m, int *dim,
                                      double **w, const bsfit_allocator *a, bsfit_status *st);

/** Releases arrays returned by bsfit_points_parse / bsfit_points_read. NULL-safe. */
BSFIT_API void bsfit_points_free(double *xy, size_t m, int dim, double *w,
                                 const bsfit_allocator *a);

/** Formats points as CSV with a header line ("x,y", "x,y,z", "x,y,w" or "x,y,z,w"),
** one point a line, numbers with %.17g.
** @param[in]  xy   m*dim doubles, dim 2 or 3.   @param[in] w  m weights or NULL.
** @param[out] out  *len+1 bytes, NUL-terminated, allocated with a; the caller frees
**                  them with the same allocator.
** @return BSFIT_OK, BSFIT_EDIM, BSFIT_EINVAL (NULL arrays, m == 0), BSFIT_ENONFINITE,
**         BSFIT_EWEIGHT (a weight <= 0) or BSFIT_ENOMEM. */
BSFIT_API bsfit_err bsfit_points_format(const double *xy, size_t m, int dim, const double *w,
                                        char **out, size_t *len, const bsfit_allocator *a,
                                        bsfit_status *st);

/** Writes bsfit_points_format's text to path atomically.
** @return the codes of bsfit_points_format and bsfit_write_file_atomic. */
BSFIT_API bsfit_err bsfit_points_write(const char *path, const double *xy, size_t m, int dim,
                                       const double *w, bsfit_status *st);

/* }==================================================================== */

/* {====================================================================
** JSON (docs/formats.md)
** Curve: {"type":"bspline"|"nurbs"|"bezier","degree":p,"dim":d,"periodic":false,
**   "knots":[...n+p+1...],"control_points":[[x,y],...n...],"weights":[...n...]
**   (rational only),"domain":[a,b]}; periodic curves in expanded form (wrapped points
**   included). A rational Bézier curve is "bezier" with "weights".
** Surface: {"type":"bspline_surface"|"nurbs_surface"|"bezier_surface","degree_u":pu,
**   "degree_v":pv,"dim":d,"knots_u":[...],"knots_v":[...],"control_points":
**   [[[x,y,z],...nv...],...nu...],"weights":[[...nv...],...nu...] (rational only),
**   "domain_u":[a,b],"domain_v":[c,d]}; a surface closed around u (bsfit_surface_skin)
**   adds "periodic_u":true and is in the expanded periodic form in u.
** The reader is strict JSON (RFC 8259): objects, arrays, numbers, strings, true,
** false, null; keys it does not know are skipped; nesting deeper than 64 is refused.
** "dim", "periodic" and the domains may be left out; when present they must agree.
** ===================================================================== */

/** Formats a valid curve as JSON.
** @param[out] out *len+1 bytes, NUL-terminated, allocated with a (NULL = realloc);
**                 the caller frees them with the same allocator.
** @return BSFIT_OK, a code of bsfit_curve_validate, or BSFIT_ENOMEM. */
BSFIT_API bsfit_err bsfit_curve_to_json(const bsfit_curve *c, char **out, size_t *len,
                                        const bsfit_allocator *a, bsfit_status *st);

/** Reads a curve from JSON text into c (previous content freed; arrays allocated with a).
** On error c is left empty.
** @return BSFIT_OK; BSFIT_EFORMAT (malformed JSON, a missing or mistyped key, an unknown
**         type, a non-integer degree, ragged control points, weights that do not match
**         the type or count, a disagreeing dim/domain; the message gives the byte
**         offset); BSFIT_ENONFINITE (a number out of double range); BSFIT_EINVAL (s NULL);
**         any code of bsfit_curve_new (e.g. BSFIT_EDEGREE, BSFIT_ENKNOTS, BSFIT_EWEIGHT);
**         BSFIT_ENOMEM. */
BSFIT_API bsfit_err bsfit_curve_from_json(const char *s, size_t len, bsfit_curve *c,
                                          const bsfit_allocator *a, bsfit_status *st);

/** Writes bsfit_curve_to_json's text to path atomically.
** @return the codes of bsfit_curve_to_json and bsfit_write_file_atomic. */
BSFIT_API bsfit_err bsfit_curve_write_json(const bsfit_curve *c, const char *path,
                                           bsfit_status *st);

/** Reads a JSON curve file. @return BSFIT_EIO or the codes of bsfit_curve_from_json. */
BSFIT_API bsfit_err bsfit_curve_read_json(const char *path, bsfit_curve *c,
                                          const bsfit_allocator *a, bsfit_status *st);

/** As bsfit_curve_to_json, for a surface. */
BSFIT_API bsfit_err bsfit_surface_to_json(const bsfit_surface *s, char **out, size_t *len,
                                          const bsfit_allocator *a, bsfit_status *st);

/** As bsfit_curve_from_json, for a surface (codes of bsfit_surface_new). */
BSFIT_API bsfit_err bsfit_surface_from_json(const char *text, size_t len, bsfit_surface *s,
                                            const bsfit_allocator *a, bsfit_status *st);

/** Writes bsfit_surface_to_json's text to path atomically. */
BSFIT_API bsfit_err bsfit_surface_write_json(const bsfit_surface *s, const char *path,
                                             bsfit_status *st);

/* }==================================================================== */

/* {====================================================================
** SVG pictures (2D: the x and y of 3D data)
** A document is built in layers, in drawing order: begin, then any number of points,
** polyline, curve, control polygon and marker calls, then end or write, then free.
** Data coordinates map to pixels with the y axis pointing up; the viewBox is the data
** bounding box plus a 5% margin. Default styles exist for the classes "points",
** "curve", "control" (dashed) and "marker"; any other class name made of letters,
** digits, '-' and '_' may be used and styled by the reader. A document with 3D layers
** says so in a note ("3D data drawn as its x-y projection"); the section pictures of
** bsfit reconstruct draw 3D sections in their best-fit plane instead (docs/pictures.md).
** ===================================================================== */

/** An SVG document under construction (opaque). */
typedef struct bsfit_svg bsfit_svg;

/** Sets bbox = {xmin, ymin, xmax, ymax} to the empty box. */
BSFIT_API void bsfit_svg_bbox_init(double bbox[4]);

/** Grows bbox to hold m points (x, y of each; dim >= 2 doubles a point). Non-finite
** coordinates are skipped. */
BSFIT_API void bsfit_svg_bbox_add(double bbox[4], const double *xy, size_t m, int dim);

/** Starts a document.
** @param[out] out    the new document, to release with bsfit_svg_free.
** @param[in]  bbox   {xmin, ymin, xmax, ymax} of the data; a box of zero width or
**                    height is widened to a unit box around its centre.
** @param[in]  width  picture width in pixels (> 0); the height follows the aspect ratio.
** @param[in]  a      allocator for the document (NULL = realloc).
** @return BSFIT_OK, BSFIT_EINVAL (out NULL, width <= 0, empty bbox),
**         BSFIT_ENONFINITE (bbox) or BSFIT_ENOMEM. */
BSFIT_API bsfit_err bsfit_svg_begin(bsfit_svg **out, const double bbox[4], double width,
                                    const bsfit_allocator *a, bsfit_status *st);

/** Adds a layer of m small circles (radius in pixels) at the points xy (dim doubles each,
** dim >= 2; x and y used). css_class NULL means "points".
** @return BSFIT_OK, BSFIT_EDIM, BSFIT_EINVAL (NULL, ended document, bad class name),
**         BSFIT_ENONFINITE or BSFIT_ENOMEM. */
BSFIT_API bsfit_err bsfit_svg_points(bsfit_svg *s, const double *xy, size_t m, int dim,
                                     double radius, const char *css_class, bsfit_status *st);

/** Adds a polyline through m points (closed: a polygon). css_class NULL means "curve".
** @return as bsfit_svg_points. */
BSFIT_API bsfit_err bsfit_svg_polyline(bsfit_svg *s, const double *xy, size_t m, int dim,
                                       int closed, const char *css_class, bsfit_status *st);

/** Adds a polyline of `samples` (>= 2) points of the curve, equally spaced in parameter
** over its domain (a periodic curve is drawn closed). css_class NULL means "curve".
** @return as bsfit_svg_points, and the codes of bsfit_curve_validate. */
BSFIT_API bsfit_err bsfit_svg_curve(bsfit_svg *s, const bsfit_curve *c, size_t samples,
                                    const char *css_class, bsfit_status *st);

/** Adds the curve's control polygon (distinct points, closed for a periodic curve).
** css_class NULL means "control" (dashed). @return as bsfit_svg_curve. */
BSFIT_API bsfit_err bsfit_svg_control_polygon(bsfit_svg *s, const bsfit_curve *c,
                                              const char *css_class, bsfit_status *st);

/** Adds a marker: a circle at (x, y) and a text label next to it (label may be NULL;
** XML special characters are escaped). css_class NULL means "marker".
** @return as bsfit_svg_points. */
BSFIT_API bsfit_err bsfit_svg_marker(bsfit_svg *s, double x, double y, const char *label,
                                     const char *css_class, bsfit_status *st);

/** Closes the document and hands out its text: *len+1 bytes, NUL-terminated, allocated
** with the document's allocator (the caller frees them with it). No layer can be added
** afterwards; s must still be released with bsfit_svg_free.
** @return BSFIT_OK, BSFIT_EINVAL (NULL or already ended) or BSFIT_ENOMEM. */
BSFIT_API bsfit_err bsfit_svg_end(bsfit_svg *s, char **out, size_t *len, bsfit_status *st);

/** Closes the document and writes it to path atomically.
** @return the codes of bsfit_svg_end and bsfit_write_file_atomic. */
BSFIT_API bsfit_err bsfit_svg_write(bsfit_svg *s, const char *path, bsfit_status *st);

/** Releases a document. NULL-safe. */
BSFIT_API void bsfit_svg_free(bsfit_svg *s);

/* }==================================================================== */

/* {====================================================================
** IGES 5.3 export
** One fixed-format file (80-column records: Start, Global, Directory Entry,
** Parameter Data, Terminate) per entity. Units: millimetres (the coordinates are
** written as they are). The Global section's dates are the time of writing, or
** SOURCE_DATE_EPOCH (seconds since 1970, UTC) when that environment variable holds one:
** set it and the same curve gives the same bytes.
** ===================================================================== */

/** Formats a valid curve of dimension 1..3 as an IGES file holding one entity 126
** (rational B-spline curve). Polynomial curves get weights 1 and PROP3 = 1; periodic
** curves are written in their expanded form with the parameter range set to one
** period and PROP4 = 1; 2D curves are planar (PROP1 = 1, normal (0,0,1)).
** @param[out] out *len+1 bytes allocated with a (the caller frees them with it).
** @return BSFIT_OK, BSFIT_EDIM (dim 4), a code of bsfit_curve_validate, BSFIT_ENOMEM. */
BSFIT_API bsfit_err bsfit_curve_to_iges(const bsfit_curve *c, char **out, size_t *len,
                                        const bsfit_allocator *a, bsfit_status *st);

/** Writes bsfit_curve_to_iges's text to path atomically (the file name goes in the
** Global section). @return those codes and bsfit_write_file_atomic's. */
BSFIT_API bsfit_err bsfit_curve_write_iges(const bsfit_curve *c, const char *path,
                                           bsfit_status *st);

/** As bsfit_curve_to_iges, for a surface: one entity 128 (rational B-spline surface). */
BSFIT_API bsfit_err bsfit_surface_to_iges(const bsfit_surface *s, char **out, size_t *len,
                                          const bsfit_allocator *a, bsfit_status *st);

/** Writes bsfit_surface_to_iges's text to path atomically. */
BSFIT_API bsfit_err bsfit_surface_write_iges(const bsfit_surface *s, const char *path,
                                             bsfit_status *st);

/* }==================================================================== */

/* {====================================================================
** STEP export (ISO 10303-21, AP214 "automotive_design")
** Curves: B_SPLINE_CURVE_WITH_KNOTS (rational: the complex instance with
** RATIONAL_B_SPLINE_CURVE), all of them in one GEOMETRIC_CURVE_SET of a
** GEOMETRICALLY_BOUNDED_WIREFRAME_SHAPE_REPRESENTATION; a surface:
** B_SPLINE_SURFACE_WITH_KNOTS (or RATIONAL_B_SPLINE_SURFACE) in a GEOMETRIC_SET of a
** GEOMETRICALLY_BOUNDED_SURFACE_SHAPE_REPRESENTATION; both attached to one PRODUCT so
** CAD readers transfer them. Units: millimetres (coordinates written as they are, %.17G).
** Knots are written as distinct values and multiplicities. Periodic curves (and surfaces
** periodic in u) are written in their expanded, unclamped form with closed_curve .T.:
** the same parametrisation, domain [U[p], U[n]]. 2D curves get z = 0. FILE_NAME's time
** stamp is the time of writing, or SOURCE_DATE_EPOCH (as the IGES writer) for
** reproducible bytes. See docs/exchange.md.
** ===================================================================== */

/** Formats n valid curves (dim 2 or 3, degree >= 1) as one STEP file.
** @param[in]  c     n pointers to curves.
** @param[in]  name  the file name recorded in FILE_NAME (NULL: "bsfit.step").
** @param[out] out   *len+1 bytes allocated with a (the caller frees them with it).
** @return BSFIT_OK, BSFIT_EINVAL (c NULL, n == 0, a NULL curve, out NULL), BSFIT_EDIM
**         (dim 1 or 4), BSFIT_EDEGREE (degree 0), a code of bsfit_curve_validate,
**         BSFIT_ENOMEM. Messages count curves from 0. */
BSFIT_API bsfit_err bsfit_curves_to_step(const bsfit_curve *const *c, size_t n, const char *name,
                                         char **out, size_t *len, const bsfit_allocator *a,
                                         bsfit_status *st);

/** Writes bsfit_curves_to_step's text to path atomically.
** @return those codes and bsfit_write_file_atomic's. */
BSFIT_API bsfit_err bsfit_curves_write_step(const bsfit_curve *const *c, size_t n,
                                            const char *path, bsfit_status *st);

/** As bsfit_curves_to_step, for one surface (dim 2 or 3, degrees >= 1). */
BSFIT_API bsfit_err bsfit_surface_to_step(const bsfit_surface *s, const char *name, char **out,
                                          size_t *len, const bsfit_allocator *a,
                                          bsfit_status *st);

/** Writes bsfit_surface_to_step's text to path atomically. */
BSFIT_API bsfit_err bsfit_surface_write_step(const bsfit_surface *s, const char *path,
                                             bsfit_status *st);

/* }==================================================================== */

/* {====================================================================
** DXF export (AutoCAD R2000, AC1015)
** One SPLINE entity per curve in model space (layer "0"), with the minimal HEADER,
** TABLES, BLOCKS and OBJECTS an R2000 reader checks. Group codes: 70 flags (1 closed,
** 4 rational, 8 planar, 16 linear), 71 degree, 72/73/74 knot / control point / fit point
** counts, 40 knots, 41 weights, 10/20/30 control points (z = 0 for 2D curves). Every
** curve is written clamped, with the same parametrisation: open curves with unclamped
** ends by knot insertion, periodic ones cut open at the start of their period (closed
** flag set), since readers disagree on unclamped knots. See docs/exchange.md.
** ===================================================================== */

/** Formats n valid curves (dim 2 or 3, degree >= 1) as one DXF file.
** @param[out] out *len+1 bytes allocated with a (the caller frees them with it).
** @return BSFIT_OK, BSFIT_EINVAL (c NULL, n == 0, a NULL curve, out NULL), BSFIT_EDIM,
**         BSFIT_EDEGREE (degree 0), a code of bsfit_curve_validate, BSFIT_ENOMEM.
**         Messages count curves from 0. */
BSFIT_API bsfit_err bsfit_curves_to_dxf(const bsfit_curve *const *c, size_t n, char **out,
                                        size_t *len, const bsfit_allocator *a,
                                        bsfit_status *st);

/** Writes bsfit_curves_to_dxf's text to path atomically.
** @return those codes and bsfit_write_file_atomic's. */
BSFIT_API bsfit_err bsfit_curves_write_dxf(const bsfit_curve *const *c, size_t n,
                                           const char *path, bsfit_status *st);

/* }==================================================================== */

/* {====================================================================
** OBJ mesh of a surface (a preview for mesh viewers)
** ===================================================================== */

/** Formats a triangle mesh sampled from a valid 2D or 3D surface as Wavefront OBJ:
** "v x y z" lines (z = 0 for 2D), then "f a b c" lines (1-based, two triangles per grid
** cell, counter-clockwise seen along dS/du x dS/dv). The grid is nu x nv samples equally
** spaced in parameter, ends included; a surface periodic in u gets nu distinct columns
** over one period and triangles from the last column back to the first (closed, no
** seam gap, no doubled vertices): nu*nv vertices and 2*nu*(nv-1) triangles, otherwise
** 2*(nu-1)*(nv-1).
** @param[out] out *len+1 bytes allocated with a (the caller frees them with it).
** @return BSFIT_OK, BSFIT_EINVAL (nu or nv outside 2..100000, out NULL), BSFIT_EDIM, a
**         code of bsfit_surface_validate, BSFIT_ENOMEM. */
BSFIT_API bsfit_err bsfit_surface_to_obj(const bsfit_surface *s, size_t nu, size_t nv, char **out,
                                         size_t *len, const bsfit_allocator *a,
                                         bsfit_status *st);

/** Writes bsfit_surface_to_obj's text to path atomically.
** @return those codes and bsfit_write_file_atomic's. */
BSFIT_API bsfit_err bsfit_surface_write_obj(const bsfit_surface *s, size_t nu, size_t nv,
                                            const char *path, bsfit_status *st);

/* }==================================================================== */

/* {====================================================================
** Directories (no shell: any byte a file name may hold, newlines included)
** ===================================================================== */

/** What bsfit_path_kind finds at a path (stat(2), links followed). */
enum { BSFIT_PATH_NONE = 0, BSFIT_PATH_FILE = 1, BSFIT_PATH_DIR = 2, BSFIT_PATH_OTHER = 3 };

/** The names in directory path ("." and ".." left out), sorted by bytes (strcmp).
** @param[out] names *n NUL-terminated strings, allocated with a; release them with
**                   bsfit_dir_free(names, n, a). NULL when the directory is empty.
** @return BSFIT_OK, BSFIT_EINVAL (path NULL or empty), BSFIT_EIO (missing, not a
**         directory or unreadable: the message gives the path and the system's
**         reason) or BSFIT_ENOMEM. */
BSFIT_API bsfit_err bsfit_dir_list(const char *path, char ***names, size_t *n,
                                   const bsfit_allocator *a, bsfit_status *st);

/** Releases what bsfit_dir_list returned. NULL-safe. */
BSFIT_API void bsfit_dir_free(char **names, size_t n, const bsfit_allocator *a);

/** BSFIT_PATH_DIR, _FILE (a regular file), _OTHER (a FIFO, a device...) or _NONE
** (nothing there, or it cannot be looked at). */
BSFIT_API int bsfit_path_kind(const char *path);

/** Makes directory path and its missing parents (mkdir -p, mode 0777 & ~umask).
** An existing directory is success.
** @return BSFIT_OK, BSFIT_EINVAL (path NULL or empty), BSFIT_EIO (a part exists and
**         is not a directory, or mkdir failed: the message names it) or BSFIT_ENOMEM. */
BSFIT_API bsfit_err bsfit_dir_make(const char *path, const bsfit_allocator *a,
                                   bsfit_status *st);

/* }==================================================================== */

#endif /* BSFIT_IO_H */
