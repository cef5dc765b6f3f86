/*
** lsvg.c
** bsfit.Svg: an SVG picture built in layers (src/bsfit_io.h), for scripts that draw
** points, fitted curves and their control polygons together:
**   local doc = bs.svg.new(box [, {width = 800}])
**     box: {xmin, ymin, xmax, ymax}, Points (or a table of points) or a Curve (the box
**     of its control points, which hold the curve: convex hull property)
**   doc:points(P [, class [, radius]])      doc:polyline(P [, {closed =, class =}])
**   doc:curve(C [, {samples = 400, class =}]) doc:control_polygon(C [, class])
**   doc:marker(x, y [, label [, class]])
**   doc:tostring() --> the SVG text         doc:write(path) --> doc, or nil, msg, code
** Layers return doc, so calls chain. tostring and write end the document: later
** layers raise. The core document is opaque and lives in Lua's memory; __gc (also
** __close and doc:close()) frees it, idempotently. The ended text is kept as the
** userdata's user value, so tostring and write may both be called, in any order.
** The same module draws C:write("c.svg") (bsfit__lua_curve_svg).
*/
#include "laux.h"

#include <math.h>
#include <string.h>

/* {====================================================================
** 1. Type name and checker
** ===================================================================== */

#define BSFIT_SVG_T "bsfit.Svg"

typedef struct svg_ud {
  bsfit_svg *doc; /* NULL once ended (the text is then user value 1) or closed */
  int ended;
} svg_ud;

static svg_ud *toud(lua_State *L, int i) { return (svg_ud *)luaL_checkudata(L, i, BSFIT_SVG_T); }

/* a document that still takes layers */
static bsfit_svg *checkopen(lua_State *L, int i) {
  svg_ud *ud = toud(L, i);
  if (ud->ended) luaL_error(L, "attempt to draw on an ended svg document");
  if (ud->doc == NULL) luaL_error(L, "attempt to use a closed svg document");
  return ud->doc;
}

/* }==================================================================== */

/* {====================================================================
** 2. Constructor
** ===================================================================== */

/* The box argument at arg into bbox (see the file comment). */
static void checkbox(lua_State *L, int arg, double bbox[4]) {
  bsfit_svg_bbox_init(bbox);
  if (luaL_testudata(L, arg, BSFIT_CURVE_T)) {
    const bsfit_curve *c = bsfit__lua_checkcurve(L, arg);
    luaL_argcheck(L, c->dim >= 2, arg, "curve of dimension 2 or 3 expected");
    bsfit_svg_bbox_add(bbox, c->ctrl, c->n, c->dim);
  } else if (lua_type(L, arg) == LUA_TTABLE && lua_geti(L, arg, 1) == LUA_TNUMBER) {
    int k;
    lua_pop(L, 1);
    luaL_argcheck(L, luaL_len(L, arg) == 4, arg, "box {xmin, ymin, xmax, ymax} expected");
    for (k = 0; k < 4; k++) {
      int ok;
      lua_geti(L, arg, k + 1);
      bbox[k] = lua_tonumberx(L, -1, &ok);
      if (!ok || lua_type(L, -1) != LUA_TNUMBER) luaL_argerror(L, arg, "box coordinates must be numbers");
      lua_pop(L, 1);
    }
  } else {
    bsfit_points_ud *P;
    if (lua_type(L, arg) == LUA_TTABLE) lua_pop(L, 1); /* the probe of element 1 */
    P = bsfit__lua_topoints(L, arg);
    luaL_argcheck(L, P->dim >= 2, arg, "points of dimension 2 or 3 expected");
    bsfit__lua_checkfinite(L, arg, P);
    bsfit_svg_bbox_add(bbox, P->xy, P->n, (int)P->dim);
  }
}

/* bs.svg.new(box [, {width = 800}]) --> Svg */
static int svg_new(lua_State *L) {
  static const char *const opts[] = {"width", NULL};
  double bbox[4], width;
  bsfit_allocator a;
  bsfit_status st;
  svg_ud *ud;
  bsfit_err e;
  int t;
  checkbox(L, 1, bbox);
  t = bsfit__lua_opttable(L, 2, opts);
  width = opt_number(L, t, "width", 800.0);
  if (!(width > 0.0 && width <= 1e6)) return luaL_argerror(L, t, "field 'width' must be in (0, 1e6]");
  ud = (svg_ud *)lua_newuserdatauv(L, sizeof *ud, 1); /* empty first: __gc is safe */
  ud->doc = NULL;
  ud->ended = 0;
  luaL_setmetatable(L, BSFIT_SVG_T);
  a = bsfit__lua_allocator(L);
  e = bsfit_svg_begin(&ud->doc, bbox, width, &a, &st);
  if (e != BSFIT_OK) return bsfit__lua_raise(L, e, &st, 1);
  return 1;
}

/* }==================================================================== */

/* {====================================================================
** 3. Layers
** ===================================================================== */

/* The core's verdict on a layer: BSFIT_EINVAL can only be the class name (the document
** was checked open, the arrays exist), anything else is about the data at `arg`. */
static int layer_result(lua_State *L, bsfit_err e, const bsfit_status *st, int arg, int classarg) {
  if (e != BSFIT_OK) return bsfit__lua_raise(L, e, st, e == BSFIT_EINVAL ? classarg : arg);
  lua_settop(L, 1);
  return 1;
}

/* doc:points(P [, class [, radius]]) */
static int svg_points(lua_State *L) {
  bsfit_svg *doc = checkopen(L, 1);
  bsfit_points_ud *P = bsfit__lua_topoints(L, 2);
  const char *cls = luaL_optstring(L, 3, NULL);
  double radius = luaL_optnumber(L, 4, 2.0);
  bsfit_status st;
  luaL_argcheck(L, radius > 0.0 && isfinite(radius), 4, "radius must be positive");
  bsfit__lua_checkfinite(L, 2, P);
  return layer_result(L, bsfit_svg_points(doc, P->xy, P->n, (int)P->dim, radius, cls, &st), &st, 2, 3);
}

/* doc:polyline(P [, {closed = false, class = "curve"}]) */
static int svg_polyline(lua_State *L) {
  static const char *const opts[] = {"closed", "class", NULL};
  bsfit_svg *doc = checkopen(L, 1);
  bsfit_points_ud *P = bsfit__lua_topoints(L, 2);
  int t = bsfit__lua_opttable(L, 3, opts);
  int closed = opt_boolean(L, t, "closed", 0);
  const char *cls = opt_string(L, t, "class", NULL);
  bsfit_status st;
  bsfit__lua_checkfinite(L, 2, P);
  return layer_result(L, bsfit_svg_polyline(doc, P->xy, P->n, (int)P->dim, closed, cls, &st), &st, 2,
                      t ? t : 3);
}

/* doc:curve(C [, {samples = 400, class = "curve"}]) */
static int svg_curve(lua_State *L) {
  static const char *const opts[] = {"samples", "class", NULL};
  bsfit_svg *doc = checkopen(L, 1);
  const bsfit_curve *c = bsfit__lua_checkcurve(L, 2);
  int t = bsfit__lua_opttable(L, 3, opts);
  lua_Integer samples = opt_integer(L, t, "samples", 400);
  const char *cls = opt_string(L, t, "class", NULL);
  bsfit_status st;
  if (samples < 2 || samples > 100000000) return luaL_argerror(L, t, "field 'samples' must be in 2..1e8");
  luaL_argcheck(L, c->dim >= 2, 2, "curve of dimension 2 or 3 expected");
  return layer_result(L, bsfit_svg_curve(doc, c, (size_t)samples, cls, &st), &st, 2, t ? t : 3);
}

/* doc:control_polygon(C [, class = "control"]) */
static int svg_control_polygon(lua_State *L) {
  bsfit_svg *doc = checkopen(L, 1);
  const bsfit_curve *c = bsfit__lua_checkcurve(L, 2);
  const char *cls = luaL_optstring(L, 3, NULL);
  bsfit_status st;
  luaL_argcheck(L, c->dim >= 2, 2, "curve of dimension 2 or 3 expected");
  return layer_result(L, bsfit_svg_control_polygon(doc, c, cls, &st), &st, 2, 3);
}

/* doc:marker(x, y [, label [, class = "marker"]]) */
static int svg_marker(lua_State *L) {
  bsfit_svg *doc = checkopen(L, 1);
  double x = luaL_checknumber(L, 2), y = luaL_checknumber(L, 3);
  const char *label = luaL_optstring(L, 4, NULL);
  const char *cls = luaL_optstring(L, 5, NULL);
  bsfit_status st;
  luaL_argcheck(L, isfinite(x), 2, "coordinate is not finite");
  luaL_argcheck(L, isfinite(y), 3, "coordinate is not finite");
  return layer_result(L, bsfit_svg_marker(doc, x, y, label, cls, &st), &st, 2, 5);
}

/* }==================================================================== */

/* {====================================================================
** 4. Ending, writing, metamethods
** ===================================================================== */

/* Pushes the document's text, ending it on the first call. The core hands the text
** over in Lua's memory; a scratch box owns it until it is a Lua string (R4). */
static const char *pushtext(lua_State *L, int i, size_t *len) {
  svg_ud *ud = toud(L, i);
  if (!ud->ended) {
    bsfit_scratch_ud *box;
    bsfit_status st;
    char *text = NULL;
    bsfit_err e;
    if (ud->doc == NULL) luaL_error(L, "attempt to use a closed svg document");
    box = bsfit__lua_newscratch(L);
    e = bsfit_svg_end(ud->doc, &text, len, &st);
    if (e != BSFIT_OK) bsfit__lua_raise(L, e, &st, 0);
    box->p[0] = text;
    box->size[0] = *len + 1;
    lua_pushlstring(L, text, *len);
    bsfit__lua_scratch_free(box);
    lua_setiuservalue(L, i, 1);
    lua_pop(L, 1); /* the box */
    bsfit_svg_free(ud->doc);
    ud->doc = NULL;
    ud->ended = 1;
  }
  lua_getiuservalue(L, i, 1);
  return lua_tolstring(L, -1, len);
}

/* doc:tostring() --> the SVG text */
static int svg_tostring(lua_State *L) {
  size_t len;
  pushtext(L, 1, &len);
  return 1;
}

/* doc:write(path) --> doc, or nil, message, code when the file cannot be written */
static int svg_write(lua_State *L) {
  const char *path = luaL_checkstring(L, 2);
  size_t len;
  const char *text;
  bsfit_status st;
  bsfit_err e;
  bsfit__lua_check_files(L, "write");
  text = pushtext(L, 1, &len);
  e = bsfit_write_file_atomic(path, text, len, &st);
  lua_settop(L, 1);
  return bsfit__lua_result(L, e, &st, 1, 2);
}

/* __gc, __close and doc:close(): frees the core document; a second call is a no-op */
static int svg_gc(lua_State *L) {
  svg_ud *ud = toud(L, 1);
  bsfit_svg_free(ud->doc);
  ud->doc = NULL;
  return 0;
}

static int svg_meta_tostring(lua_State *L) {
  svg_ud *ud = toud(L, 1);
  lua_pushfstring(L, "bsfit.Svg (%s): %p", ud->ended ? "ended" : ud->doc ? "open" : "closed", (void *)ud);
  return 1;
}

static const luaL_Reg svg_meth[] = {
  {"points", svg_points}, {"polyline", svg_polyline}, {"curve", svg_curve},
  {"control_polygon", svg_control_polygon}, {"marker", svg_marker},
  {"tostring", svg_tostring}, {"write", svg_write}, {"close", svg_gc}, {NULL, NULL}};

static const luaL_Reg svg_metameth[] = {
  {"__index", NULL}, {"__gc", svg_gc}, {"__close", svg_gc}, {"__tostring", svg_meta_tostring},
  {NULL, NULL}};

static const luaL_Reg svg_funcs[] = {{"new", svg_new}, {NULL, NULL}};

/* }==================================================================== */

/* {====================================================================
** 5. Open, and the picture of one curve
** ===================================================================== */

void bsfit_lua_open_svg(lua_State *L) {
  luaL_newmetatable(L, BSFIT_SVG_T);
  luaL_setfuncs(L, svg_metameth, 0);
  luaL_newlibtable(L, svg_meth);
  luaL_setfuncs(L, svg_meth, 0);
  lua_setfield(L, -2, "__index");
  lua_pop(L, 1);
}

/* sets bs.svg in the module table on the stack top */
void bsfit__lua_lib_svg(lua_State *L) {
  luaL_newlib(L, svg_funcs);
  lua_setfield(L, -2, "svg");
}

bsfit_err bsfit__lua_curve_svg(lua_State *L, const bsfit_curve *c, const char *path,
                               size_t samples, bsfit_status *st) {
  double bbox[4];
  bsfit_allocator a = bsfit__lua_allocator(L);
  svg_ud *ud = (svg_ud *)lua_newuserdatauv(L, sizeof *ud, 1); /* owns the document */
  bsfit_err e;
  ud->doc = NULL;
  ud->ended = 0;
  luaL_setmetatable(L, BSFIT_SVG_T);
  bsfit_svg_bbox_init(bbox);
  bsfit_svg_bbox_add(bbox, c->ctrl, c->n, c->dim);
  e = bsfit_svg_begin(&ud->doc, bbox, 800.0, &a, st);
  if (e == BSFIT_OK) e = bsfit_svg_control_polygon(ud->doc, c, NULL, st);
  if (e == BSFIT_OK) e = bsfit_svg_curve(ud->doc, c, samples, NULL, st);
  if (e == BSFIT_OK) e = bsfit_svg_write(ud->doc, path, st);
  bsfit_svg_free(ud->doc);
  ud->doc = NULL;
  lua_pop(L, 1);
  return e;
}

/* }==================================================================== */
