/*
** lsurface.c
** bsfit.Surface: tensor-product B-spline, NURBS and Bézier surfaces (docs/method.md §1,
** src/bsfit_surface.h). The userdata holds a bsfit_surface whose arrays come from
** Lua's allocator (STYLE R7), freed by an idempotent __gc that __close shares.
**   bs.surface.new{degree_u =, degree_v =, knots_u =, knots_v =,
**                  control_points = {{{x,y,z}, ...nv...}, ...nu...}, weights = nil}
**   bs.bezier_surface.new{control_points =, weights =}
**   bs.surface.from_json(s)
** Row i of control_points runs along v at the i-th u position: point (i, j) is
** control_points[i][j]; weights, when given, have the same nu x nv shape.
*/
#include "laux.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

/* {====================================================================
** 1. Type name and checker
** ===================================================================== */

static bsfit_surface_ud *toud(lua_State *L, int i) {
  return (bsfit_surface_ud *)luaL_checkudata(L, i, BSFIT_SURFACE_T);
}

static bsfit_surface *checksurface(lua_State *L, int i) {
  bsfit_surface_ud *ud = toud(L, i);
  if (ud->s.ctrl == NULL) luaL_error(L, "attempt to use a closed surface");
  return &ud->s;
}

bsfit_surface *bsfit__lua_checksurface(lua_State *L, int arg) { return checksurface(L, arg); }

/* }==================================================================== */

/* {====================================================================
** 2. Constructors
** ===================================================================== */

/* An empty surface first (liolib's newprefile): if anything below raises, __gc finds
** a surface that is safe to free. */
bsfit_surface_ud *bsfit__lua_newsurface(lua_State *L, bsfit_allocator *a) {
  bsfit_surface_ud *ud = (bsfit_surface_ud *)lua_newuserdatauv(L, sizeof *ud, 0);
  bsfit_surface_init(&ud->s);
  luaL_setmetatable(L, BSFIT_SURFACE_T);
  *a = bsfit__lua_allocator(L);
  return ud;
}

/* A raised error about field `k` of the constructor's table (argument t). */
static int field_error(lua_State *L, int t, const char *k, const char *fmt, int i, int j, int n) {
  char msg[128];
  snprintf(msg, sizeof msg, fmt, i, j, n);
  return luaL_argerror(L, t, lua_pushfstring(L, "field '%s': %s", k, msg));
}

/* Number of entries of row i (1-based) of the nested table on the stack top, which
** must be a non-empty table of the same length as the first row (*nv, 0 = unknown). */
static size_t row_length(lua_State *L, int t, const char *k, int i, size_t *nv) {
  size_t n;
  if (!lua_istable(L, -1)) field_error(L, t, k, "row %d is not a table", i, 0, 0);
  n = (size_t)luaL_len(L, -1);
  if (*nv == 0) *nv = n;
  if (n == 0 || n != *nv) field_error(L, t, k, "row %d has %d entries, expected %d", i, (int)n, (int)*nv);
  return n;
}

/* The coordinates of entry (i, j), the table on the stack top, into x; *dim is fixed by
** the first entry. */
static void read_point(lua_State *L, int t, int i, int j, size_t *dim, double *x) {
  size_t k, d;
  if (!lua_istable(L, -1)) field_error(L, t, "control_points", "point (%d, %d) is not a table", i, j, 0);
  d = (size_t)luaL_len(L, -1);
  if (*dim == 0) *dim = d;
  if (d != *dim || d < 1 || d > 4)
    field_error(L, t, "control_points", "point (%d, %d) has %d coordinates", i, j, (int)d);
  for (k = 0; k < d; k++) {
    int ok;
    lua_geti(L, -1, (lua_Integer)k + 1);
    x[k] = lua_tonumberx(L, -1, &ok);
    if (!ok || lua_type(L, -1) != LUA_TNUMBER)
      field_error(L, t, "control_points", "point (%d, %d) has a coordinate that is not a number", i, j, 0);
    if (!isfinite(x[k]))
      field_error(L, t, "control_points", "point (%d, %d) has a non-finite coordinate", i, j, 0);
    lua_pop(L, 1);
  }
}

/* control_points = {{P_11, ..., P_1nv}, ...}: pushes Points of nu*nv (row-major over
** (i, j), the core's layout) and sets *nu, *nv. Two passes: shape, then values. */
static bsfit_points_ud *net_points(lua_State *L, int t, size_t *nu, size_t *nv) {
  size_t i, j, dim = 0;
  double x[4];
  bsfit_points_ud *P;
  int ty = bsfit__lua_field(L, t, "control_points");
  if (ty == LUA_TNIL) luaL_argerror(L, t, "field 'control_points' is required");
  if (ty != LUA_TTABLE) luaL_argerror(L, t, "field 'control_points' must be a table of rows of points");
  *nu = (size_t)luaL_len(L, -1);
  *nv = 0;
  if (*nu == 0) luaL_argerror(L, t, "field 'control_points' is empty");
  for (i = 0; i < *nu; i++) { /* shape and dimension */
    lua_geti(L, -1, (lua_Integer)i + 1);
    row_length(L, t, "control_points", (int)i + 1, nv);
    lua_geti(L, -1, 1);
    read_point(L, t, (int)i + 1, 1, &dim, x);
    lua_pop(L, 2);
  }
  P = bsfit__lua_allocpoints(L, *nu * *nv, dim);
  for (i = 0; i < *nu; i++) {
    lua_geti(L, -2, (lua_Integer)i + 1);
    for (j = 0; j < *nv; j++) {
      lua_geti(L, -1, (lua_Integer)j + 1);
      read_point(L, t, (int)i + 1, (int)j + 1, &dim, P->xy + (i * *nv + j) * dim);
      lua_pop(L, 1);
    }
    lua_pop(L, 1);
  }
  lua_remove(L, -2); /* the table; the Points stay on the stack */
  return P;
}

/* weights = {{w_11, ...}, ...} of the net's shape: pushes a Vector (or nil) */
static bsfit_vector_ud *net_weights(lua_State *L, int t, size_t nu, size_t nv) {
  size_t i, j, rows, n = nv;
  bsfit_vector_ud *w;
  int ty = bsfit__lua_field(L, t, "weights");
  if (ty == LUA_TNIL) return NULL;
  if (ty != LUA_TTABLE) luaL_argerror(L, t, "field 'weights' must be a table of rows of numbers");
  rows = (size_t)luaL_len(L, -1);
  if (rows != nu) field_error(L, t, "weights", "%d rows for %d rows of control points", (int)rows, (int)nu, 0);
  w = bsfit__lua_newvector(L, nu * nv);
  for (i = 0; i < nu; i++) {
    lua_geti(L, -2, (lua_Integer)i + 1);
    row_length(L, t, "weights", (int)i + 1, &n);
    for (j = 0; j < nv; j++) {
      int ok;
      double x;
      lua_geti(L, -1, (lua_Integer)j + 1);
      x = lua_tonumberx(L, -1, &ok);
      if (!ok || lua_type(L, -1) != LUA_TNUMBER)
        field_error(L, t, "weights", "weight (%d, %d) is not a number", (int)i + 1, (int)j + 1, 0);
      if (!(x > 0.0 && isfinite(x))) {
        char msg[128];
        snprintf(msg, sizeof msg, "field 'weights': weight (%d, %d) is %g (must be positive and finite)",
                 (int)i + 1, (int)j + 1, x);
        luaL_argerror(L, t, lua_pushstring(L, msg));
      }
      w->x[i * nv + j] = x;
      lua_pop(L, 1);
    }
    lua_pop(L, 1);
  }
  lua_remove(L, -2);
  return w;
}

/* The degree of one direction: field `deg`, or the degree of a Knots in field `kn`. */
static int degree_field(lua_State *L, int t, const char *deg, const char *kn) {
  lua_Integer p;
  bsfit_knots_ud *K;
  bsfit__lua_field(L, t, kn);
  K = (bsfit_knots_ud *)luaL_testudata(L, -1, BSFIT_KNOTS_T);
  lua_pop(L, 1);
  p = K ? opt_integer(L, t, deg, K->degree) : req_integer(L, t, deg);
  if (p < 0 || p > BSFIT_MAX_DEGREE)
    luaL_argerror(L, t, lua_pushfstring(L, "field '%s' must be in 0..%d", deg, BSFIT_MAX_DEGREE));
  if (K && K->degree != p)
    luaL_argerror(L, t, lua_pushfstring(L, "field '%s': knots of degree %d for degree %d", kn, K->degree, (int)p));
  return (int)p;
}

/* The knots of one direction (Knots, Vector or table; NULL when absent, pushed or nil),
** checked against the degree and the number of control points in that direction. */
static const double *knots_field(lua_State *L, int t, const char *kn, int p, size_t n, char dir) {
  bsfit_vector_ud *v;
  size_t nk;
  const double *U;
  int ty = bsfit__lua_field(L, t, kn);
  if (ty == LUA_TNIL) return NULL;
  if (luaL_testudata(L, -1, BSFIT_KNOTS_T)) {
    bsfit_knots_ud *K = bsfit__lua_checkknots(L, -1);
    nk = K->n;
    U = K->U;
  } else {
    if (ty != LUA_TTABLE && !luaL_testudata(L, -1, BSFIT_VECTOR_T))
      luaL_argerror(L, t, lua_pushfstring(L, "field '%s' must be a table, bsfit.Vector or bsfit.Knots", kn));
    v = bsfit__lua_tovector(L, -1);
    nk = v->n;
    U = v->x;
    bsfit__lua_checkknotvalues(L, t, U, nk, p); /* 1-based messages before the core's */
  }
  if (n < (size_t)p + 1)
    luaL_argerror(L, t, lua_pushfstring(L, "degree %d in %c needs at least %d control points, got %d", p, dir,
                                        p + 1, (int)n));
  if (nk != n + (size_t)p + 1)
    luaL_argerror(L, t, lua_pushfstring(L, "degree %d with %d control points in %c needs %d knots, got %d", p,
                                        (int)n, dir, (int)n + p + 1, (int)nk));
  return U;
}

/* bs.surface.new{...} --> Surface */
static int surface_new(lua_State *L) {
  static const char *const opts[] = {"degree_u", "degree_v", "knots_u", "knots_v",
                                     "control_points", "weights", NULL};
  bsfit_status st;
  bsfit_points_ud *P;
  bsfit_vector_ud *w;
  const double *Uu, *Uv;
  bsfit_surface_ud *ud;
  bsfit_allocator a;
  size_t nu, nv;
  int pu, pv;
  bsfit_err e;
  luaL_checktype(L, 1, LUA_TTABLE);
  bsfit__lua_check_options(L, 1, opts);
  pu = degree_field(L, 1, "degree_u", "knots_u");
  pv = degree_field(L, 1, "degree_v", "knots_v");
  P = net_points(L, 1, &nu, &nv);
  w = net_weights(L, 1, nu, nv);
  if (nu < (size_t)pu + 1 || nv < (size_t)pv + 1)
    return luaL_argerror(L, 1, lua_pushfstring(L, "degrees (%d, %d) need at least %d x %d control points, got %d x %d",
                                                pu, pv, pu + 1, pv + 1, (int)nu, (int)nv));
  Uu = knots_field(L, 1, "knots_u", pu, nu, 'u');
  Uv = knots_field(L, 1, "knots_v", pv, nv, 'v');
  ud = bsfit__lua_newsurface(L, &a);
  e = bsfit_surface_new(&ud->s, pu, pv, (int)P->dim, nu, nv, Uu, Uv, P->xy, w ? w->x : NULL, &a, &st);
  if (e != BSFIT_OK) return bsfit__lua_raise(L, e, &st, 1);
  return 1;
}

/* bs.bezier_surface.new{control_points =, weights =} --> Surface of degrees (nu-1, nv-1) */
static int bezier_surface_new(lua_State *L) {
  static const char *const opts[] = {"control_points", "weights", NULL};
  bsfit_status st;
  bsfit_points_ud *P;
  bsfit_vector_ud *w;
  bsfit_surface_ud *ud;
  bsfit_allocator a;
  size_t nu, nv;
  bsfit_err e;
  luaL_checktype(L, 1, LUA_TTABLE);
  bsfit__lua_check_options(L, 1, opts);
  P = net_points(L, 1, &nu, &nv);
  w = net_weights(L, 1, nu, nv);
  ud = bsfit__lua_newsurface(L, &a);
  e = bsfit_surface_new_bezier(&ud->s, (int)P->dim, nu, nv, P->xy, w ? w->x : NULL, &a, &st);
  if (e != BSFIT_OK) return bsfit__lua_raise(L, e, &st, 1);
  return 1;
}

/* bs.surface.from_json(s) --> Surface, or nil, message, code for malformed text */
static int surface_from_json(lua_State *L) {
  size_t len;
  const char *s = luaL_checklstring(L, 1, &len);
  bsfit_allocator a;
  bsfit_surface_ud *ud = bsfit__lua_newsurface(L, &a);
  bsfit_status st;
  bsfit_err e = bsfit_surface_from_json(s, len, &ud->s, &a, &st);
  if (e == BSFIT_ENOMEM) return bsfit__lua_raise(L, e, &st, 1);
  if (e != BSFIT_OK) e = st.code = BSFIT_EFORMAT; /* the text is at fault, whatever the check */
  return bsfit__lua_result(L, e, &st, 1, 1);
}

/* }==================================================================== */

/* {====================================================================
** 3. Methods and metamethods
** ===================================================================== */

static int push_coords(lua_State *L, const double *x, int dim) {
  int k;
  luaL_checkstack(L, dim, "too many coordinates");
  for (k = 0; k < dim; k++) lua_pushnumber(L, x[k]);
  return dim;
}

/* S:eval(u, v) --> x, y, z */
static int surface_eval(lua_State *L) {
  bsfit_surface *s = checksurface(L, 1);
  double u = luaL_checknumber(L, 2), v = luaL_checknumber(L, 3), x[4];
  bsfit_status st;
  bsfit_err e = bsfit_surface_eval(s, u, v, x, &st);
  if (e != BSFIT_OK) return bsfit__lua_raise(L, e, &st, isfinite(u) ? 3 : 2);
  return push_coords(L, x, s->dim);
}

/* S:deriv(u, v, ku, kv) --> d^(ku+kv) S / du^ku dv^kv, dim numbers */
static int surface_deriv(lua_State *L) {
  bsfit_surface *s = checksurface(L, 1);
  double u = luaL_checknumber(L, 2), v = luaL_checknumber(L, 3), *out;
  lua_Integer ku = luaL_checkinteger(L, 4), kv = luaL_checkinteger(L, 5), k;
  size_t d = (size_t)s->dim;
  bsfit_status st;
  bsfit_err e;
  luaL_argcheck(L, ku >= 0 && ku <= BSFIT_MAX_DEGREE, 4, "derivative order out of range 0..30");
  luaL_argcheck(L, kv >= 0 && kv <= BSFIT_MAX_DEGREE, 5, "derivative order out of range 0..30");
  k = ku > kv ? ku : kv;
  out = (double *)lua_newuserdatauv(L, (size_t)((k + 1) * (k + 1)) * d * sizeof(double), 0);
  e = bsfit_surface_derivs(s, u, v, (int)k, out, &st);
  if (e != BSFIT_OK) return bsfit__lua_raise(L, e, &st, isfinite(u) ? 3 : 2);
  return push_coords(L, out + (size_t)(ku * (k + 1) + kv) * d, s->dim);
}

/* S:normal(u, v) --> nx, ny, nz (unit); a degenerate point (a pole) gives the fail
** triple, a surface that is not 3D raises */
static int surface_normal(lua_State *L) {
  bsfit_surface *s = checksurface(L, 1);
  double u = luaL_checknumber(L, 2), v = luaL_checknumber(L, 3), n[3];
  bsfit_status st;
  bsfit_err e = bsfit_surface_normal(s, u, v, n, &st);
  if (e == BSFIT_EDIM) return bsfit__lua_raise(L, e, &st, 0);
  if (e != BSFIT_OK) return bsfit__lua_result(L, e, &st, 0, isfinite(u) ? 3 : 2);
  return push_coords(L, n, 3);
}

/* S:sample(ku, kv) --> Points of ku*kv, point (a, b) at index a*kv + b + 1 */
static int surface_sample(lua_State *L) {
  bsfit_surface *s = checksurface(L, 1);
  size_t ku = bsfit__lua_checkcount(L, 2, 2, LUA_MAXINTEGER);
  size_t kv = bsfit__lua_checkcount(L, 3, 2, LUA_MAXINTEGER);
  bsfit_points_ud *P;
  bsfit_status st;
  bsfit_err e;
  if (ku > ((size_t)-1) / kv) return luaL_argerror(L, 3, "grid too large");
  P = bsfit__lua_allocpoints(L, ku * kv, (size_t)s->dim);
  e = bsfit_surface_sample_grid(s, ku, kv, P->xy, &st);
  if (e != BSFIT_OK) return bsfit__lua_raise(L, e, &st, 0);
  return 1;
}

static int surface_domain(lua_State *L) {
  bsfit_surface *s = checksurface(L, 1);
  double d[4];
  int k;
  bsfit_surface_domain(s, &d[0], &d[1], &d[2], &d[3]);
  for (k = 0; k < 4; k++) lua_pushnumber(L, d[k]);
  return 4;
}

static int surface_degree(lua_State *L) {
  bsfit_surface *s = checksurface(L, 1);
  lua_pushinteger(L, s->degree_u);
  lua_pushinteger(L, s->degree_v);
  return 2;
}

static int surface_dim(lua_State *L) {
  lua_pushinteger(L, checksurface(L, 1)->dim);
  return 1;
}

/* S:count() --> nu, nv */
static int surface_count(lua_State *L) {
  bsfit_surface *s = checksurface(L, 1);
  lua_pushinteger(L, (lua_Integer)s->nu);
  lua_pushinteger(L, (lua_Integer)s->nv);
  return 2;
}

static int surface_kind(lua_State *L) {
  bsfit_surface *s = checksurface(L, 1);
  lua_pushstring(L, s->bezier ? "bezier" : s->weights ? "nurbs" : "bspline");
  return 1;
}

/* S:is_periodic() --> true when closed around u (a skinned surface: periodic_u) */
static int surface_is_periodic(lua_State *L) {
  lua_pushboolean(L, checksurface(L, 1)->periodic_u);
  return 1;
}

static int surface_is_rational(lua_State *L) {
  lua_pushboolean(L, checksurface(L, 1)->weights != NULL);
  return 1;
}

static int push_knots(lua_State *L, const double *U, size_t n, int p) {
  bsfit_knots_ud *K = bsfit__lua_newknots(L, n + (size_t)p + 1, p);
  memcpy(K->U, U, K->n * sizeof(double));
  return 1;
}

static int surface_knots_u(lua_State *L) {
  bsfit_surface *s = checksurface(L, 1);
  return push_knots(L, s->knots_u, s->nu, s->degree_u);
}

static int surface_knots_v(lua_State *L) {
  bsfit_surface *s = checksurface(L, 1);
  return push_knots(L, s->knots_v, s->nv, s->degree_v);
}

/* S:control_points() --> Points of nu*nv, point (i, j) at index (i-1)*nv + j */
static int surface_control_points(lua_State *L) {
  bsfit_surface *s = checksurface(L, 1);
  bsfit_points_ud *P = bsfit__lua_allocpoints(L, s->nu * s->nv, (size_t)s->dim);
  memcpy(P->xy, s->ctrl, s->nu * s->nv * (size_t)s->dim * sizeof(double));
  return 1;
}

/* S:weights() --> Vector laid out as control_points, or nil (polynomial surface) */
static int surface_weights(lua_State *L) {
  bsfit_surface *s = checksurface(L, 1);
  bsfit_vector_ud *w;
  if (s->weights == NULL) {
    luaL_pushfail(L);
    return 1;
  }
  w = bsfit__lua_newvector(L, s->nu * s->nv);
  memcpy(w->x, s->weights, w->n * sizeof(double));
  return 1;
}

static int surface_copy(lua_State *L) {
  bsfit_surface *s = checksurface(L, 1);
  bsfit_allocator a;
  bsfit_surface_ud *ud = bsfit__lua_newsurface(L, &a);
  bsfit_status st;
  bsfit_err e = bsfit_surface_copy(s, &ud->s, &a, &st);
  if (e != BSFIT_OK) return bsfit__lua_raise(L, e, &st, 0);
  return 1;
}

/* S:to_json() --> the JSON text (bsfit_io.h) */
static int surface_to_json(lua_State *L) {
  bsfit_surface *s = checksurface(L, 1);
  bsfit_scratch_ud *box = bsfit__lua_newscratch(L);
  bsfit_status st;
  char *text = NULL;
  size_t len = 0;
  bsfit_err e = bsfit_surface_to_json(s, &text, &len, &box->a, &st);
  if (e != BSFIT_OK) return bsfit__lua_raise(L, e, &st, 0);
  box->p[0] = text;
  box->size[0] = len + 1;
  lua_pushlstring(L, text, len);
  bsfit__lua_scratch_free(box);
  return 1;
}

static int ends_with(const char *s, size_t len, const char *ext) {
  size_t n = strlen(ext);
  return len > n && strcmp(s + len - n, ext) == 0;
}

/* S:write(path [, {samples_u = 100, samples_v = 100}]): ".json", ".iges", ".step" or
** ".obj" (a triangle mesh of samples_u x samples_v points) by extension, replaced
** atomically; returns S, or
** nil, message, code when the file cannot be written */
static int surface_write(lua_State *L) {
  static const char *const opts[] = {"samples_u", "samples_v", NULL};
  bsfit_surface *s = checksurface(L, 1);
  size_t len;
  const char *path = luaL_checklstring(L, 2, &len);
  int t = bsfit__lua_opttable(L, 3, opts);
  lua_Integer ku = opt_integer(L, t, "samples_u", 100), kv = opt_integer(L, t, "samples_v", 100);
  bsfit_status st;
  bsfit_err e;
  if (ku < 2 || ku > 100000) return luaL_argerror(L, t, "field 'samples_u' must be in 2..100000");
  if (kv < 2 || kv > 100000) return luaL_argerror(L, t, "field 'samples_v' must be in 2..100000");
  bsfit__lua_check_files(L, "write");
  if (ends_with(path, len, ".json")) e = bsfit_surface_write_json(s, path, &st);
  else if (ends_with(path, len, ".iges") || ends_with(path, len, ".igs"))
    e = bsfit_surface_write_iges(s, path, &st);
  else if (ends_with(path, len, ".step") || ends_with(path, len, ".stp")) {
    if (s->dim < 2 || s->dim > 3 || s->degree_u < 1 || s->degree_v < 1)
      return luaL_argerror(L, 2, "STEP holds 2D and 3D surfaces of degrees >= 1");
    e = bsfit_surface_write_step(s, path, &st);
  } else if (ends_with(path, len, ".obj")) {
    if (s->dim < 2 || s->dim > 3)
      return luaL_argerror(L, 2, "an OBJ mesh needs a 2D or 3D surface");
    e = bsfit_surface_write_obj(s, (size_t)ku, (size_t)kv, path, &st);
  } else {
    return luaL_argerror(L, 2, "file name must end in .json, .iges, .igs, .step, .stp or .obj");
  }
  lua_settop(L, 1);
  return bsfit__lua_result(L, e, &st, 1, 2);
}

/* __gc and __close: free and mark closed; a second call is a no-op */
static int surface_gc(lua_State *L) {
  bsfit_surface_free(&toud(L, 1)->s);
  return 0;
}

static int surface_tostring(lua_State *L) {
  bsfit_surface_ud *ud = toud(L, 1);
  if (ud->s.ctrl == NULL) lua_pushliteral(L, "bsfit.Surface (closed)");
  else
    lua_pushfstring(L, "bsfit.Surface(deg=%dx%d, n=%Ix%I, dim=%d): %p", ud->s.degree_u, ud->s.degree_v,
                    (lua_Integer)ud->s.nu, (lua_Integer)ud->s.nv, ud->s.dim, (void *)ud);
  return 1;
}

/* }==================================================================== */

/* {====================================================================
** 4. Registration arrays
** ===================================================================== */

static const luaL_Reg surface_meth[] = {
  {"eval", surface_eval}, {"deriv", surface_deriv}, {"normal", surface_normal},
  {"sample", surface_sample}, {"domain", surface_domain}, {"degree", surface_degree},
  {"dim", surface_dim}, {"count", surface_count}, {"kind", surface_kind},
  {"is_rational", surface_is_rational}, {"is_periodic", surface_is_periodic},
  {"knots_u", surface_knots_u},
  {"knots_v", surface_knots_v}, {"control_points", surface_control_points},
  {"weights", surface_weights}, {"copy", surface_copy}, {"to_json", surface_to_json},
  {"write", surface_write}, {"close", surface_gc}, {NULL, NULL}};

static const luaL_Reg surface_metameth[] = {
  {"__index", NULL}, {"__gc", surface_gc}, {"__close", surface_gc},
  {"__tostring", surface_tostring}, {NULL, NULL}};

static const luaL_Reg surface_funcs[] = {
  {"new", surface_new}, {"from_json", surface_from_json}, {NULL, NULL}};

static const luaL_Reg bezier_surface_funcs[] = {{"new", bezier_surface_new}, {NULL, NULL}};

/* }==================================================================== */

/* {====================================================================
** 5. Open
** ===================================================================== */

void bsfit_lua_open_surface(lua_State *L) {
  luaL_newmetatable(L, BSFIT_SURFACE_T);
  luaL_setfuncs(L, surface_metameth, 0);
  luaL_newlibtable(L, surface_meth);
  luaL_setfuncs(L, surface_meth, 0);
  lua_setfield(L, -2, "__index");
  lua_pop(L, 1);
}

/* sets bs.surface and bs.bezier_surface in the module table on the stack top */
void bsfit__lua_lib_surface(lua_State *L) {
  luaL_newlib(L, surface_funcs);
  lua_setfield(L, -2, "surface");
  luaL_newlib(L, bezier_surface_funcs);
  lua_setfield(L, -2, "bezier_surface");
}

/* }==================================================================== */

/* {====================================================================
** Host helpers (bsfit_lua.h)
** ===================================================================== */

const bsfit_surface *bsfit_lua_checksurface(lua_State *L, int arg) { return checksurface(L, arg); }

void bsfit_lua_pushsurface(lua_State *L, const bsfit_surface *src) {
  bsfit_allocator a;
  bsfit_surface_ud *ud = bsfit__lua_newsurface(L, &a);
  bsfit_status st;
  bsfit_err e = bsfit_surface_copy(src, &ud->s, &a, &st);
  if (e != BSFIT_OK) bsfit__lua_raise(L, e, &st, 0);
}

/* }==================================================================== */
