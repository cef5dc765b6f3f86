/*
** lweights.c
** bs.weights: the per-point weighting rules of the fitting strategies (docs/method.md §7,
** src/bsfit_geom.h), each returning one weight per point as a Vector:
**   bs.weights.circumradius(P [, {closed = true, centered = true}])
**   bs.weights.turning(P [, {closed = true}])
**   bs.weights.spacing(P [, {closed = true}])
**   bs.weights.uniform(P | n)                          ones: the rule that changes nothing
**   bs.weights.untrusted(w [, trust = 0.1])            1-based indices of the weights below
**                                                      trust x median ({} when none)
** P is a bsfit.Points of dim 2 or 3 or a table of points. `closed` defaults to true:
** the points are a cross-section, whose last point joins the first. `centered` (the
** circle through Q_{k-1}, Q_k, Q_{k+1} rather than the paper's Q_k, Q_{k+1}, Q_{k+2})
** exists only for the circumradius rule. Bad input is misuse and raises; the binding
** checks the coordinates first so that the message counts points from 1.
*/
#include "laux.h"

/* {====================================================================
** Rules
** ===================================================================== */

static const char *const opts_closed[] = {"closed", NULL};
static const char *const opts_radius[] = {"closed", "centered", NULL};

typedef bsfit_err (*rule_fn)(const double *pts, size_t m, int dim, int closed, double *w,
                             bsfit_status *st);

/* f(P [, {closed}]): arguments checked, then the result Vector, then the core (R4) */
static int run_rule(lua_State *L, rule_fn fn) {
  bsfit_points_ud *P = bsfit__lua_topoints(L, 1);
  int t = bsfit__lua_opttable(L, 2, opts_closed);
  int closed = opt_boolean(L, t, "closed", 1);
  bsfit_vector_ud *w;
  bsfit_status st;
  bsfit_err e;
  bsfit__lua_checkfinite(L, 1, P);
  w = bsfit__lua_newvector(L, P->n);
  e = fn(P->xy, P->n, (int)P->dim, closed, w->x, &st);
  return bsfit__lua_result(L, e, &st, 1, 1);
}

static int weights_circumradius(lua_State *L) {
  bsfit_points_ud *P = bsfit__lua_topoints(L, 1);
  int t = bsfit__lua_opttable(L, 2, opts_radius);
  int closed = opt_boolean(L, t, "closed", 1);
  int centered = opt_boolean(L, t, "centered", 1);
  bsfit_vector_ud *w;
  bsfit_status st;
  bsfit_err e;
  bsfit__lua_checkfinite(L, 1, P);
  w = bsfit__lua_newvector(L, P->n);
  e = bsfit_weights_circumradius(P->xy, P->n, (int)P->dim, closed, centered, w->x, &st);
  return bsfit__lua_result(L, e, &st, 1, 1);
}

static int weights_turning(lua_State *L) { return run_rule(L, bsfit_weights_turning); }

static int weights_spacing(lua_State *L) { return run_rule(L, bsfit_weights_spacing); }

/* bs.weights.uniform(P | n): a strategy names "no weighting" like any other rule; a
** count serves scripts that have no points at hand */
static int weights_uniform(lua_State *L) {
  size_t n, k;
  bsfit_vector_ud *w;
  if (lua_type(L, 1) == LUA_TNUMBER) n = bsfit__lua_checkcount(L, 1, 0, LUA_MAXINTEGER);
  else n = bsfit__lua_topoints(L, 1)->n;
  w = bsfit__lua_newvector(L, n);
  for (k = 0; k < n; k++) w->x[k] = 1.0;
  return 1;
}

/* bs.weights.untrusted(w [, trust]): the points that bs.params_trusted and the automatic
** strategy leave out of their chords, noise and pieces. A bad weight is data, not misuse
** (it comes from a file): nil, "weight K is V (must be positive and finite)", "EWEIGHT". */
static int weights_untrusted(lua_State *L) {
  bsfit_vector_ud *w = bsfit__lua_tovector(L, 1);
  lua_Number trust = luaL_optnumber(L, 2, 0.1);
  bsfit_allocator a = bsfit__lua_allocator(L);
  bsfit_status st;
  size_t k, n = 0, *out;
  bsfit_err e;
  luaL_argcheck(L, trust >= 0 && trust < 1, 2, "trust must be in [0, 1)");
  if (bsfit__lua_pushbadweight(L, w->x, w->n)) {
    lua_pushnil(L);
    lua_insert(L, -2);
    lua_pushliteral(L, "EWEIGHT");
    return 3;
  }
  out = lua_newuserdatauv(L, (w->n > 0 ? w->n : 1) * sizeof(size_t), 0); /* freed by the GC */
  e = bsfit_untrusted(w->x, w->n, trust, out, &n, &a, &st);
  if (e != BSFIT_OK) return bsfit__lua_result(L, e, &st, 0, 0);
  lua_createtable(L, (int)n, 0);
  for (k = 0; k < n; k++) {
    lua_pushinteger(L, (lua_Integer)out[k] + 1);
    lua_rawseti(L, -2, (lua_Integer)k + 1);
  }
  return 1;
}

/* }==================================================================== */

/* {====================================================================
** Registration
** ===================================================================== */

static const luaL_Reg weights_funcs[] = {
  {"circumradius", weights_circumradius}, {"turning", weights_turning},
  {"spacing", weights_spacing},           {"uniform", weights_uniform},
  {"untrusted", weights_untrusted},       {NULL, NULL}};

/* sets bs.weights in the module table on the stack top */
void bsfit__lua_lib_weights(lua_State *L) {
  luaL_newlib(L, weights_funcs);
  lua_setfield(L, -2, "weights");
}

/* }==================================================================== */
