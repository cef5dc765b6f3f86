/*
** laux.h
** Private helpers shared by the files of the Lua binding (src/lua): the userdata
** layouts, the status-to-Lua converter, option-table readers, the 1-based index
** rule and the per-type open functions called by luaopen_bsfit. Not installed.
*/
#ifndef BSFIT_LAUX_H
#define BSFIT_LAUX_H

#include "bsfit.h"
#include "bsfit_lua.h"

#include <lauxlib.h>
#include <lua.h>

/* The binding moves doubles between Lua and C without conversion. */
_Static_assert(sizeof(lua_Number) == sizeof(double), "bsfit needs lua_Number = double");

/* {====================================================================
** Metatable names and userdata layouts
** ===================================================================== */

#define BSFIT_POINTS_T "bsfit.Points"
#define BSFIT_VECTOR_T "bsfit.Vector"
#define BSFIT_KNOTS_T "bsfit.Knots"
#define BSFIT_CURVE_T "bsfit.Curve"
#define BSFIT_SURFACE_T "bsfit.Surface"
#define BSFIT_FITTER_T "bsfit.Fitter"

/* m points of dim coordinates, row-major [x0,y0,(z0,)x1,...]: one GC-counted block */
typedef struct bsfit_points_ud {
  size_t n, dim;
  double xy[];
} bsfit_points_ud;

/* n doubles (weights, parameters, residuals): one block */
typedef struct bsfit_vector_ud {
  size_t n;
  double x[];
} bsfit_vector_ud;

/* a knot vector of n knots for a given degree: one block */
typedef struct bsfit_knots_ud {
  int degree;
  size_t n;
  double U[];
} bsfit_knots_ud;

/* a curve whose arrays come from Lua's allocator; freed by __gc/__close */
typedef struct bsfit_curve_ud {
  bsfit_curve c;
} bsfit_curve_ud;

/* }==================================================================== */

/* {====================================================================
** Status conversion (STYLE R3)
** ===================================================================== */

/* Converts a core status. e == BSFIT_OK: returns nret (the results already pushed).
** A numerical outcome (singular, not SPD, no convergence, empty span, degenerate
** data, I/O or format): pushes nil, message, code name and returns 3. Anything else
** is misuse and raises: with luaL_argerror naming argument `arg` when arg > 0, with
** luaL_error otherwise. Call it only when nothing outside Lua's control is held. */
int bsfit__lua_result(lua_State *L, bsfit_err e, const bsfit_status *st, int nret, int arg);

/* Raises like bsfit__lua_result, whatever the code (for misuse-only call sites). */
int bsfit__lua_raise(lua_State *L, bsfit_err e, const bsfit_status *st, int arg);

/* The allocator the core must use for memory that userdata own; it carries the
** host's interrupt flag (registry field BSFIT_LUA_INTERRUPT, NULL when absent). */
bsfit_allocator bsfit__lua_allocator(lua_State *L);

/* Scratch box (STYLE R4): a userdata that owns up to two core-allocated blocks until
** the binding has copied them into proper userdata, so that a raise in between (out
** of memory) cannot leak them. Its __gc frees what it still holds. */
typedef struct bsfit_scratch_ud {
  bsfit_allocator a;
  void *p[2];
  size_t size[2];
} bsfit_scratch_ud;

/* Pushes an empty scratch box whose allocator is Lua's. */
bsfit_scratch_ud *bsfit__lua_newscratch(lua_State *L);
/* Frees what the box holds now (it stays a valid, empty box). */
void bsfit__lua_scratch_free(bsfit_scratch_ud *s);

/* Raises "<what>: file access is not allowed in the sandbox" when L is sandboxed
** (bsfit_lua_sandboxed). Every binding function that opens a file calls it first. */
void bsfit__lua_check_files(lua_State *L, const char *what);

/* Gives the metatable at index mt a __metatable field (a table holding only its
** __name), so scripts can read the type name but not change the metatable. */
void bsfit__lua_protect_metatable(lua_State *L, int mt);
/* Protects every "bsfit.*" metatable of the registry that is not yet protected. */
void bsfit__lua_protect_metatables(lua_State *L);

/* }==================================================================== */

/* {====================================================================
** Option tables (STYLE R6): fields are read with these, never luaL_check*(L, -1)
** ===================================================================== */

/* Raises `bad argument #t to 'f' (unknown option 'k')` for any key of table t not in
** the NULL-terminated list `names` (and for non-string keys). */
void bsfit__lua_check_options(lua_State *L, int t, const char *const names[]);

/* Field k of table t (t may be 0: no table, every field absent). Absent or nil gives
** def; a value of the wrong type raises `field 'k' must be a number` (etc.) as an
** argument error of argument t. */
lua_Number bsfit__lua_opt_number(lua_State *L, int t, const char *k, lua_Number def);
lua_Integer bsfit__lua_opt_integer(lua_State *L, int t, const char *k, lua_Integer def);
int bsfit__lua_opt_boolean(lua_State *L, int t, const char *k, int def);
const char *bsfit__lua_opt_string(lua_State *L, int t, const char *k, const char *def);
/* Like opt_integer, but an absent field raises `field 'k' is required`. */
lua_Integer bsfit__lua_req_integer(lua_State *L, int t, const char *k);
/* Pushes field k of table t (nil when t == 0) and returns its type. */
int bsfit__lua_field(lua_State *L, int t, const char *k);
/* The optional options table at `arg`: absent or nil gives 0 (every field at its
** default, for the readers above); anything else must be a table whose keys are all
** in `names` (bsfit__lua_check_options). Returns arg or 0. */
int bsfit__lua_opttable(lua_State *L, int arg, const char *const names[]);

#define opt_number bsfit__lua_opt_number
#define opt_integer bsfit__lua_opt_integer
#define opt_boolean bsfit__lua_opt_boolean
#define opt_string bsfit__lua_opt_string
#define req_integer bsfit__lua_req_integer

/* }==================================================================== */

/* {====================================================================
** Indices and sizes
** ===================================================================== */

/* The one 1-based <-> 0-based rule: integer argument `arg` names an element of a
** sequence of n; i in 1..n is element i, i in -n..-1 counts from the end (-1 is the
** last). Anything else raises `index out of range`. Returns the 0-based index. */
size_t bsfit__lua_index(lua_State *L, int arg, size_t n);

/* Integer argument `arg` checked to lie in [lo, hi]; raises naming `arg`. */
size_t bsfit__lua_checkcount(lua_State *L, int arg, lua_Integer lo, lua_Integer hi);

/* Input checks done by the binding before the core sees the data, so that the
** messages count points and weights from 1 as Lua users do (core messages count
** from 0). Both raise an argument error naming `arg`:
**   `point 3 has a non-finite coordinate`, `point 3 has a coordinate 1e+200 beyond 1e100`
**   `weight 2 is -1 (must be positive and finite)` */
void bsfit__lua_checkfinite(lua_State *L, int arg, const bsfit_points_ud *P);
void bsfit__lua_checkweights(lua_State *L, int arg, const double *w, size_t n);
/* The same test for weights that are data, not misuse: pushes the message of the first
** bad weight and returns 1, or returns 0 (nothing pushed) when all are good. */
int bsfit__lua_pushbadweight(lua_State *L, const double *w, size_t n);
/* n knot values: finite, non-decreasing and, when p >= 0, no value more than p + 1
** times (`knot 3 is not finite`, `knots decrease at knot 5 (0.5 < 1)`,
** `knots 1..3 equal 0: multiplicity above degree+1 = 2`). */
void bsfit__lua_checkknotvalues(lua_State *L, int arg, const double *U, size_t n, int p);
/* n parameters: finite and non-decreasing (`parameter 2 is not finite`). */
void bsfit__lua_checkparams(lua_State *L, int arg, const double *u, size_t n);

/* }==================================================================== */

/* {====================================================================
** Cross-type helpers (the host versions are in bsfit_lua.h)
** ===================================================================== */

bsfit_points_ud *bsfit__lua_newpoints(lua_State *L, size_t n, size_t dim);
/* As newpoints, not zeroed: only for a kernel that writes every coordinate. */
bsfit_points_ud *bsfit__lua_allocpoints(lua_State *L, size_t n, size_t dim);
bsfit_points_ud *bsfit__lua_checkpoints(lua_State *L, int arg);
/* Points userdata or table of points at `arg`; a table is converted and the new
** userdata replaces it in slot `arg` (so it stays anchored). */
bsfit_points_ud *bsfit__lua_topoints(lua_State *L, int arg);

bsfit_vector_ud *bsfit__lua_newvector(lua_State *L, size_t n);
/* As newvector, not zeroed: only for a kernel that writes every value. */
bsfit_vector_ud *bsfit__lua_allocvector(lua_State *L, size_t n);
bsfit_vector_ud *bsfit__lua_checkvector(lua_State *L, int arg);
/* Vector userdata or table of numbers at `arg` (a table is replaced in its slot). */
bsfit_vector_ud *bsfit__lua_tovector(lua_State *L, int arg);

bsfit_knots_ud *bsfit__lua_newknots(lua_State *L, size_t n, int degree);
bsfit_knots_ud *bsfit__lua_checkknots(lua_State *L, int arg);

/* A new curve userdata holding an empty curve; *a receives Lua's allocator, to be
** passed (as a) to the core function that fills ud->c. */
bsfit_curve_ud *bsfit__lua_newcurve(lua_State *L, bsfit_allocator *a);
/* The curve at arg; raises "attempt to use a closed curve" after __close. */
bsfit_curve *bsfit__lua_checkcurve(lua_State *L, int arg);

/* a surface whose arrays come from Lua's allocator; freed by __gc/__close */
typedef struct bsfit_surface_ud {
  bsfit_surface s;
} bsfit_surface_ud;

/* A new surface userdata holding an empty surface (as bsfit__lua_newcurve). */
bsfit_surface_ud *bsfit__lua_newsurface(lua_State *L, bsfit_allocator *a);
/* The surface at arg; raises "attempt to use a closed surface" after __close. */
bsfit_surface *bsfit__lua_checksurface(lua_State *L, int arg);

/* Draws c (its control polygon, then `samples` points of the curve) into an SVG file
** at path (lsvg.c). Raises only on out of memory; returns the core's code. */
bsfit_err bsfit__lua_curve_svg(lua_State *L, const bsfit_curve *c, const char *path,
                               size_t samples, bsfit_status *st);

/* Per-type metatables and module sub-tables, called by luaopen_bsfit. Each open
** function builds the metatable and leaves nothing on the stack; each lib function
** pushes its sub-table of constructors. */
void bsfit_lua_open_points(lua_State *L);
void bsfit_lua_open_vector(lua_State *L);
void bsfit_lua_open_knots(lua_State *L);
void bsfit_lua_open_curve(lua_State *L);
void bsfit__lua_lib_points(lua_State *L);
void bsfit__lua_lib_vector(lua_State *L);
void bsfit__lua_lib_knots(lua_State *L);
void bsfit__lua_lib_curve(lua_State *L);
void bsfit__lua_lib_io(lua_State *L); /* lio.c: bs.io (absent when sandboxed) */
void bsfit__lua_lib_bezier(lua_State *L);
/* these set their fields (bs.params, bs.geom, ...) in the module table on the top */
void bsfit__lua_lib_geom(lua_State *L);
void bsfit__lua_lib_weights(lua_State *L);
void bsfit__lua_lib_fitter(lua_State *L);
void bsfit__lua_lib_filter(lua_State *L);
void bsfit__lua_lib_surface(lua_State *L);
void bsfit__lua_lib_svg(lua_State *L);
void bsfit__lua_lib_auto(lua_State *L); /* lauto.c (automatic strategy): after knots */
void bsfit__lua_lib_exchange(lua_State *L); /* lexchange.c: bs.io.write_step, write_dxf */
void bsfit__lua_lib_skin(lua_State *L);     /* lskin.c: bs.surface.skin, after surface */
void bsfit__lua_lib_scan(lua_State *L); /* lscan.c: bs.scan and its metatables */
void bsfit__lua_lib_features(lua_State *L); /* lfeatures.c: after geom and curve */
void bsfit_lua_open_fitter(lua_State *L);
void bsfit_lua_open_surface(lua_State *L);
void bsfit_lua_open_svg(lua_State *L);

/* }==================================================================== */

#endif
