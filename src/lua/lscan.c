/*
** lscan.c
** bs.scan: from a scan file to ordered sections.
**
**   local scan = bs.scan.read(path [, format])
**     --> {points = Points(n x 3), triangles = Triangles or nil, kind = "mesh" | "cloud"}
**   local T = bs.scan.triangles{{1, 2, 3}, ...}  -- 1-based vertex ids; #T, T:get(i) --> a, b, c
**   local lo, hi = bs.scan.extent(P, "z" | {x, y, z})
**   local pos = bs.scan.positions(lo, hi, {slices = N | spacing = D | at = {...}})
**   local slices = bs.scan.slice(scan, {axis = "z" | direction = {x, y, z},
**                                       slices = N | spacing = D | at = {...},
**                                       thickness = T, tol = e})
**   (bs.scan.reduce, bs.scan.order and bs.scan.write_iges: lscan_section.c)
**
** A file that cannot be read or parsed returns nil, message, code (as bs.points.read);
** misuse raises.
*/
#include "lscan.h"

#include <math.h>
#include <stdint.h>
#include <string.h>

#define BSFIT_TRIANGLES_T "bsfit.Triangles"

/* n triangles of 0-based vertex ids: one block */
typedef struct tri_ud {
  size_t n;
  uint32_t t[];
} tri_ud;

static int tmp_gc(lua_State *L) {
  tmp_ud *t = (tmp_ud *)luaL_checkudata(L, 1, BSFIT_SCANTMP_T);
  bsfit_sections_free(&t->sec);
  bsfit_order_result_free(&t->ord);
  bsfit_scan_free(&t->scan);
  return 0;
}

tmp_ud *bsfit__lua_scan_tmp(lua_State *L) {
  tmp_ud *t = (tmp_ud *)lua_newuserdatauv(L, sizeof *t, 0);
  bsfit_sections_init(&t->sec);
  bsfit_order_result_init(&t->ord);
  bsfit_scan_init(&t->scan);
  luaL_setmetatable(L, BSFIT_SCANTMP_T);
  return t;
}

/* {====================================================================
** Triangles
** ===================================================================== */

static tri_ud *newtri(lua_State *L, size_t n) {
  tri_ud *T;
  luaL_argcheck(L, n <= (SIZE_MAX - sizeof(tri_ud)) / (3 * sizeof(uint32_t)), 1,
                "too many triangles");
  T = (tri_ud *)lua_newuserdatauv(L, sizeof(tri_ud) + 3 * n * sizeof(uint32_t), 0);
  T->n = n;
  luaL_setmetatable(L, BSFIT_TRIANGLES_T);
  return T;
}

static tri_ud *checktri(lua_State *L, int arg) {
  return (tri_ud *)luaL_checkudata(L, arg, BSFIT_TRIANGLES_T);
}

/* bs.scan.triangles{{a, b, c}, ...}: 1-based vertex ids */
static int scan_triangles(lua_State *L) {
  size_t n, i;
  int k;
  tri_ud *T;
  luaL_checktype(L, 1, LUA_TTABLE);
  n = (size_t)luaL_len(L, 1);
  T = newtri(L, n);
  for (i = 0; i < n; i++) {
    luaL_argcheck(L, lua_geti(L, 1, (lua_Integer)i + 1) == LUA_TTABLE, 1,
                  lua_pushfstring(L, "triangle %d is not a table", (int)i + 1));
    for (k = 0; k < 3; k++) {
      lua_Integer v;
      int isnum;
      lua_geti(L, -1, k + 1);
      v = lua_tointegerx(L, -1, &isnum);
      if (!isnum || v < 1 || v > (lua_Integer)UINT32_MAX)
        luaL_argerror(
            L, 1,
            lua_pushfstring(L, "triangle %d: vertex %d is not an id >= 1", (int)i + 1, k + 1));
      T->t[3 * i + (size_t)k] = (uint32_t)(v - 1);
      lua_pop(L, 1);
    }
    lua_pop(L, 1);
  }
  return 1;
}

static int tri_len(lua_State *L) {
  lua_pushinteger(L, (lua_Integer)checktri(L, 1)->n);
  return 1;
}

/* T:get(i) --> a, b, c (1-based vertex ids) */
static int tri_get(lua_State *L) {
  tri_ud *T = checktri(L, 1);
  size_t i = bsfit__lua_index(L, 2, T->n);
  int k;
  for (k = 0; k < 3; k++) lua_pushinteger(L, (lua_Integer)T->t[3 * i + (size_t)k] + 1);
  return 3;
}

static int tri_tostring(lua_State *L) {
  tri_ud *T = checktri(L, 1);
  lua_pushfstring(L, "bsfit.Triangles(n=%d): %p", (int)T->n, (void *)T);
  return 1;
}

/* }==================================================================== */

/* {====================================================================
** Reading
** ===================================================================== */

static const char *const format_names[] = {"auto", "ply", "stl", "obj", "xyz", NULL};

/* bs.scan.read(path [, format]) --> {points, triangles, kind} or nil, msg, code */
static int scan_read(lua_State *L) {
  const char *path = luaL_checkstring(L, 1);
  int fmt = luaL_checkoption(L, 2, "auto", format_names);
  tmp_ud *t = bsfit__lua_scan_tmp(L);
  bsfit_allocator a = bsfit__lua_allocator(L);
  bsfit_points_ud *P;
  bsfit_status st;
  bsfit_err e = bsfit_scan_read(path, (bsfit_scan_format)fmt, &t->scan, &a, &st);
  if (e == BSFIT_ENOMEM) return bsfit__lua_raise(L, e, &st, 0);
  if (e != BSFIT_OK) { /* a file that cannot be used is an outcome, not misuse */
    luaL_pushfail(L);
    lua_pushstring(L, st.msg);
    lua_pushstring(L, bsfit_errname(e));
    return 3;
  }
  lua_createtable(L, 0, 3);
  P = bsfit__lua_allocpoints(L, t->scan.nv, 3);
  memcpy(P->xy, t->scan.xyz, t->scan.nv * 3 * sizeof(double));
  lua_setfield(L, -2, "points");
  if (t->scan.tri != NULL) {
    tri_ud *T = newtri(L, t->scan.nt);
    memcpy(T->t, t->scan.tri, t->scan.nt * 3 * sizeof(uint32_t));
    lua_setfield(L, -2, "triangles");
  }
  lua_pushstring(L, t->scan.tri != NULL ? "mesh" : "cloud");
  lua_setfield(L, -2, "kind");
  bsfit_scan_free(&t->scan);
  return 1;
}

/* }==================================================================== */

/* {====================================================================
** Directions and positions
** ===================================================================== */

/* A direction at stack index i: "x" | "y" | "z" or {x, y, z}. */
static void todir(lua_State *L, int i, int arg, const char *what, double d[3]) {
  int k;
  d[0] = d[1] = d[2] = 0;
  if (lua_type(L, i) == LUA_TSTRING) {
    static const char *const axes[] = {"x", "y", "z", NULL};
    const char *s = lua_tostring(L, i);
    for (k = 0; axes[k] != NULL; k++)
      if (strcmp(s, axes[k]) == 0) {
        d[k] = 1;
        return;
      }
    luaL_argerror(L, arg,
                  lua_pushfstring(L, "%s must be \"x\", \"y\" or \"z\", got '%s'", what, s));
  }
  if (lua_type(L, i) != LUA_TTABLE)
    luaL_argerror(L, arg, lua_pushfstring(L, "%s must be an axis name or {x, y, z}", what));
  for (k = 0; k < 3; k++) {
    int isnum;
    lua_geti(L, i, k + 1);
    d[k] = lua_tonumberx(L, -1, &isnum);
    if (!isnum) luaL_argerror(L, arg, lua_pushfstring(L, "%s must hold 3 numbers", what));
    lua_pop(L, 1);
  }
  if (!(d[0] * d[0] + d[1] * d[1] + d[2] * d[2] > 0) || !isfinite(d[0] + d[1] + d[2]))
    luaL_argerror(L, arg, lua_pushfstring(L, "%s must be a finite non-zero vector", what));
}

/* The slicing direction of options table t: axis or direction (default z). */
static void opts_dir(lua_State *L, int t, double d[3]) {
  int ta = bsfit__lua_field(L, t, "axis"), td;
  lua_pop(L, 1);
  td = bsfit__lua_field(L, t, "direction");
  if (ta != LUA_TNIL && td != LUA_TNIL) luaL_argerror(L, t, "give axis or direction, not both");
  if (td != LUA_TNIL) {
    todir(L, lua_gettop(L), t, "field 'direction'", d);
  } else {
    lua_pop(L, 1);
    if (ta == LUA_TNIL)
      lua_pushliteral(L, "z");
    else
      bsfit__lua_field(L, t, "axis");
    if (lua_type(L, -1) != LUA_TSTRING)
      luaL_argerror(L, t, "field 'axis' must be \"x\", \"y\" or \"z\"");
    todir(L, lua_gettop(L), t, "field 'axis'", d);
  }
  lua_pop(L, 1);
}

/* bs.scan.extent(P, dir) --> lo, hi of x.n over the points (n = dir normalised) */
static int scan_extent(lua_State *L) {
  bsfit_points_ud *P = bsfit__lua_checkpoints(L, 1);
  double d[3], lo, hi;
  bsfit_status st;
  bsfit_err e;
  luaL_argcheck(L, P->dim == 3, 1, "3D points expected");
  todir(L, 2, 2, "direction", d);
  e = bsfit_scan_extent(P->xy, P->n, d, &lo, &hi, &st);
  if (e != BSFIT_OK) return bsfit__lua_raise(L, e, &st, 1);
  lua_pushnumber(L, lo);
  lua_pushnumber(L, hi);
  return 2;
}

/* Pushes the positions of field 'at' of options table t, checked (see push_positions). */
static size_t push_at(lua_State *L, int t, double *gap) {
  size_t n, i;
  bsfit__lua_field(L, t, "at");
  luaL_argcheck(L, lua_type(L, -1) == LUA_TTABLE, t, "field 'at' must be a table of numbers");
  n = (size_t)luaL_len(L, -1);
  luaL_argcheck(L, n >= 1 && n <= 10000000, t, "field 'at' must hold 1 to 10^7 positions");
  lua_createtable(L, (int)n, 0);
  for (i = 1; i <= n; i++) {
    int isnum;
    double x;
    lua_geti(L, -2, (lua_Integer)i);
    x = lua_tonumberx(L, -1, &isnum);
    if (!isnum || !isfinite(x))
      luaL_argerror(L, t,
                    lua_pushfstring(L, "field 'at': position %d is not a finite number", (int)i));
    lua_seti(L, -2, (lua_Integer)i);
  }
  lua_remove(L, -2);
  for (i = 1; i < n; i++) {
    double a, b;
    lua_geti(L, -1, (lua_Integer)i);
    lua_geti(L, -2, (lua_Integer)i + 1);
    a = lua_tonumber(L, -2);
    b = lua_tonumber(L, -1);
    lua_pop(L, 2);
    if (fabs(b - a) > 0 && (*gap == 0 || fabs(b - a) < *gap)) *gap = fabs(b - a);
  }
  return n;
}

/* Pushes the positions the options at t ask for, as a table; *gap receives the smallest
** distance between neighbouring positions (0 for one position). */
static size_t push_positions(lua_State *L, int t, double lo, double hi, double *gap) {
  int has_n = bsfit__lua_field(L, t, "slices") != LUA_TNIL;
  int has_d = bsfit__lua_field(L, t, "spacing") != LUA_TNIL;
  int has_at = bsfit__lua_field(L, t, "at") != LUA_TNIL;
  size_t n, i;
  lua_pop(L, 3);
  luaL_argcheck(L, has_n + has_d + has_at == 1, t, "give exactly one of slices, spacing, at");
  *gap = 0;
  if (has_at) return push_at(L, t, gap);
  if (has_n) {
    lua_Integer k = opt_integer(L, t, "slices", 1);
    luaL_argcheck(L, k >= 1 && k <= 10000000, t, "field 'slices' must be in 1..10^7");
    n = (size_t)k;
    *gap = (hi - lo) / (double)(n + 1);
    lua_createtable(L, (int)n, 0);
    for (i = 1; i <= n; i++) {
      lua_pushnumber(L, lo + (hi - lo) * (double)i / (double)(n + 1));
      lua_seti(L, -2, (lua_Integer)i);
    }
    return n;
  } else {
    double d = opt_number(L, t, "spacing", 1), off;
    luaL_argcheck(L, d > 0 && isfinite(d), t, "field 'spacing' must be > 0");
    luaL_argcheck(L, (hi - lo) / d < 1e7, t, "field 'spacing' gives more than 10^7 slices");
    n = (size_t)floor((hi - lo) / d);
    if (n == 0) n = 1;
    off = (hi - lo - (double)(n - 1) * d) / 2; /* centred: the slabs of thickness d tile */
    *gap = d;
    lua_createtable(L, (int)n, 0);
    for (i = 0; i < n; i++) {
      lua_pushnumber(L, lo + off + d * (double)i);
      lua_seti(L, -2, (lua_Integer)i + 1);
    }
    return n;
  }
}

static const char *const positions_opts[] = {"slices", "spacing", "at", NULL};

/* bs.scan.positions(lo, hi, opts) --> {positions} */
static int scan_positions(lua_State *L) {
  double lo = luaL_checknumber(L, 1), hi = luaL_checknumber(L, 2), gap;
  int t;
  luaL_argcheck(L, isfinite(lo) && isfinite(hi) && lo <= hi, 2, "need finite lo <= hi");
  t = bsfit__lua_opttable(L, 3, positions_opts);
  luaL_argcheck(L, t != 0, 3, "options table expected");
  push_positions(L, t, lo, hi, &gap);
  return 1;
}

/* }==================================================================== */

/* {====================================================================
** Slicing
** ===================================================================== */

static void push_vec3(lua_State *L, const double *x, const char *name) {
  int k;
  lua_createtable(L, 3, 0);
  for (k = 0; k < 3; k++) {
    lua_pushnumber(L, x[k]);
    lua_seti(L, -2, k + 1);
  }
  lua_setfield(L, -2, name);
}

/* Points userdata holding part j of the sections. */
static void push_part(lua_State *L, const bsfit_sections *s, size_t j) {
  size_t n = s->part_start[j + 1] - s->part_start[j];
  bsfit_points_ud *P = bsfit__lua_allocpoints(L, n, 2);
  memcpy(P->xy, s->uv + 2 * s->part_start[j], n * 2 * sizeof(double));
}

/* The list of slice tables. */
static void push_slices(lua_State *L, const bsfit_sections *s, int mesh, double thickness) {
  size_t i, j;
  lua_createtable(L, (int)s->nslices, 0);
  for (i = 0; i < s->nslices; i++) {
    const bsfit_plane *p = &s->planes[i];
    lua_createtable(L, 0, 9);
    lua_pushinteger(L, (lua_Integer)i + 1);
    lua_setfield(L, -2, "index");
    lua_pushnumber(L, p->position);
    lua_setfield(L, -2, "position");
    push_vec3(L, p->origin, "origin");
    push_vec3(L, p->u, "u");
    push_vec3(L, p->v, "v");
    push_vec3(L, p->normal, "normal");
    if (mesh) {
      size_t n = s->first_part[i + 1] - s->first_part[i];
      lua_createtable(L, (int)n, 0); /* loops */
      lua_createtable(L, (int)n, 0); /* closed */
      for (j = s->first_part[i]; j < s->first_part[i + 1]; j++) {
        push_part(L, s, j);
        lua_seti(L, -3, (lua_Integer)(j - s->first_part[i] + 1));
        lua_pushboolean(L, s->closed[j]);
        lua_seti(L, -2, (lua_Integer)(j - s->first_part[i] + 1));
      }
      lua_setfield(L, -3, "closed");
      lua_setfield(L, -2, "loops");
    } else {
      push_part(L, s, s->first_part[i]);
      lua_setfield(L, -2, "points");
      lua_pushnumber(L, thickness);
      lua_setfield(L, -2, "thickness");
    }
    lua_seti(L, -2, (lua_Integer)i + 1);
  }
}

/* The scan at arg 1: a scan table {points, triangles} or a Points userdata (a cloud).
** Fills s with pointers into the userdata (no copy). */
static void toscan(lua_State *L, bsfit_scan *s) {
  bsfit_points_ud *P;
  bsfit_scan_init(s);
  if (lua_type(L, 1) == LUA_TTABLE) {
    lua_getfield(L, 1, "points");
    P = (bsfit_points_ud *)luaL_testudata(L, -1, BSFIT_POINTS_T);
    if (P == NULL) luaL_argerror(L, 1, "field 'points' must be Points");
    lua_pop(L, 1); /* the table keeps it alive */
    if (lua_getfield(L, 1, "triangles") != LUA_TNIL) {
      tri_ud *T = (tri_ud *)luaL_testudata(L, -1, BSFIT_TRIANGLES_T);
      if (T == NULL) luaL_argerror(L, 1, "field 'triangles' must be Triangles (bs.scan.triangles)");
      s->tri = T->t;
      s->nt = T->n;
    }
    lua_pop(L, 1);
  } else {
    P = bsfit__lua_checkpoints(L, 1);
  }
  luaL_argcheck(L, P->dim == 3, 1, "3D points expected");
  luaL_argcheck(L, P->n >= 1, 1, "no points");
  s->xyz = P->xy;
  s->nv = P->n;
}

static const char *const slice_opts[] = {"axis", "direction", "slices", "spacing",
                                         "at",   "thickness", "tol",    NULL};

/* bs.scan.slice(scan, opts) --> {slice, ...} */
static int scan_slice(lua_State *L) {
  bsfit_scan s;
  double d[3], lo, hi, gap, thick, tol, *pos;
  size_t n, i;
  int t, ptab;
  tmp_ud *tmp;
  bsfit_status st;
  bsfit_allocator a = bsfit__lua_allocator(L);
  bsfit_err e;
  toscan(L, &s);
  t = bsfit__lua_opttable(L, 2, slice_opts);
  luaL_argcheck(L, t != 0, 2, "options table expected");
  opts_dir(L, t, d);
  thick = opt_number(L, t, "thickness", 0);
  tol = opt_number(L, t, "tol", 0);
  luaL_argcheck(L, thick >= 0 && isfinite(thick), 2, "field 'thickness' must be > 0");
  luaL_argcheck(L, tol >= 0 && isfinite(tol), 2, "field 'tol' must be >= 0");
  /* an option the scan cannot honour is an error, never silently ignored */
  luaL_argcheck(L, s.tri == NULL || thick == 0, 2,
                "field 'thickness' applies to clouds (a mesh is cut exactly)");
  luaL_argcheck(L, s.tri != NULL || tol == 0, 2, "field 'tol' applies to meshes");
  e = bsfit_scan_extent(s.xyz, s.nv, d, &lo, &hi, &st);
  if (e != BSFIT_OK) return bsfit__lua_raise(L, e, &st, 1);
  n = push_positions(L, t, lo, hi, &gap);
  ptab = lua_gettop(L);
  pos = (double *)lua_newuserdatauv(L, n * sizeof(double), 0);
  for (i = 0; i < n; i++) {
    lua_geti(L, ptab, (lua_Integer)i + 1);
    pos[i] = lua_tonumber(L, -1);
    lua_pop(L, 1);
  }
  if (!(thick > 0)) /* a quarter of the spacing keeps slabs thin but populated */
    thick = gap > 0 ? gap / 4 : hi > lo ? (hi - lo) / 100 : 1e-9 * (fabs(lo) > 1 ? fabs(lo) : 1);
  tmp = bsfit__lua_scan_tmp(L);
  if (s.tri != NULL)
    e = bsfit_mesh_slice(&s, d, pos, n, tol, &tmp->sec, &a, &st);
  else
    e = bsfit_cloud_slice(s.xyz, s.nv, d, pos, n, thick, &tmp->sec, &a, &st);
  if (e == BSFIT_EINVAL && s.tri != NULL) return bsfit__lua_raise(L, e, &st, 1);
  if (e != BSFIT_OK) return bsfit__lua_raise(L, e, &st, 0);
  push_slices(L, &tmp->sec, s.tri != NULL, thick);
  bsfit_sections_free(&tmp->sec);
  return 1;
}

/* }==================================================================== */

/* {====================================================================
** Open
** ===================================================================== */

static const luaL_Reg tri_meth[] = {{"get", tri_get}, {NULL, NULL}};
static const luaL_Reg tri_metameth[] = {
    {"__index", NULL}, {"__len", tri_len}, {"__tostring", tri_tostring}, {NULL, NULL}};

static const luaL_Reg scan_funcs[] = {{"read", scan_read},     {"triangles", scan_triangles},
                                      {"extent", scan_extent}, {"positions", scan_positions},
                                      {"slice", scan_slice},   {NULL, NULL}};

/* Builds the metatables and sets bs.scan in the module table on the stack top. */
void bsfit__lua_lib_scan(lua_State *L) {
  luaL_newmetatable(L, BSFIT_TRIANGLES_T);
  luaL_setfuncs(L, tri_metameth, 0);
  luaL_newlibtable(L, tri_meth);
  luaL_setfuncs(L, tri_meth, 0);
  lua_setfield(L, -2, "__index");
  lua_pushliteral(L, BSFIT_TRIANGLES_T);
  lua_setfield(L, -2, "__metatable");
  lua_pop(L, 1);
  luaL_newmetatable(L, BSFIT_SCANTMP_T);
  lua_pushcfunction(L, tmp_gc);
  lua_setfield(L, -2, "__gc");
  lua_pushliteral(L, BSFIT_SCANTMP_T);
  lua_setfield(L, -2, "__metatable");
  lua_pop(L, 1);
  luaL_newlib(L, scan_funcs);
  bsfit__lua_scan_section_funcs(L); /* reduce, order, write_iges (lscan_section.c) */
  lua_setfield(L, -2, "scan");
}

/* }==================================================================== */
