/*
** lfitter.c
** bsfit.Fitter: weighted least-squares fitting settings plus the core's reusable
** workspace (docs/method.md §5, §13). The workspace comes from Lua's allocator and is
** released by an idempotent __gc shared with __close; a closed fitter raises.
*/
#include "laux.h"

#include <float.h>
#include <stdio.h>
#include <string.h>

/* {====================================================================
** 1. Type name and checker
** ===================================================================== */

typedef struct fitter_ud {
  bsfit_fitter *f; /* NULL once closed (or before bsfit_fitter_new succeeded) */
  int degree;
  int periodic;
  size_t count;
} fitter_ud;

static fitter_ud *toud(lua_State *L, int i) {
  return (fitter_ud *)luaL_checkudata(L, i, BSFIT_FITTER_T);
}

static fitter_ud *checkfitter(lua_State *L, int i) {
  fitter_ud *F = toud(L, i);
  if (F->f == NULL) luaL_error(L, "attempt to use a closed fitter");
  return F;
}

/* }==================================================================== */

/* {====================================================================
** 2. Settings and constructor
** ===================================================================== */

static const char *const rule_names[] = {"averaging", "carvalho-closed", "periodic-averaging",
                                         "uniform", "periodic-uniform", NULL};
static const bsfit_knot_rule rule_values[] = {
  BSFIT_KNOTS_AVERAGING, BSFIT_KNOTS_CARVALHO_CLOSED, BSFIT_KNOTS_PERIODIC_AVERAGING,
  BSFIT_KNOTS_UNIFORM, BSFIT_KNOTS_PERIODIC_UNIFORM};

/* bsfit_solver values in order */
static const char *const solver_names[] = {"cholesky", "qr", "auto", NULL};

/* field `k` as a tangent {dx, dy[, dz]} into T (4 doubles); returns its length or 0 */
static int opt_tangent(lua_State *L, int t, const char *k, double *T) {
  int n = 0, i;
  if (bsfit__lua_field(L, t, k) != LUA_TNIL) {
    if (!lua_istable(L, -1) || (n = (int)luaL_len(L, -1)) < 1 || n > 4)
      luaL_argerror(L, t, lua_pushfstring(L, "field '%s' must be a table of 1 to 4 numbers", k));
    for (i = 0; i < n; i++) {
      int ok;
      lua_geti(L, -1, i + 1);
      T[i] = lua_tonumberx(L, -1, &ok);
      if (!ok || lua_type(L, -1) != LUA_TNUMBER)
        luaL_argerror(L, t, lua_pushfstring(L, "field '%s' must be a table of 1 to 4 numbers", k));
      lua_pop(L, 1);
    }
  }
  lua_pop(L, 1);
  return n;
}

/* The knots field: a Knots userdata is a full vector (periodic: the expanded form,
** whose period is U[p..p+N]); a table or Vector is a full open vector or one period. */
static void knots_setting(lua_State *L, int t, bsfit_fit_opts *o) {
  int ty = bsfit__lua_field(L, t, "knots");
  size_t p = (size_t)o->degree;
  if (ty == LUA_TNIL) {
    lua_pop(L, 1);
    return;
  }
  if (luaL_testudata(L, -1, BSFIT_KNOTS_T)) {
    bsfit_knots_ud *K = bsfit__lua_checkknots(L, -1);
    if (K->degree != o->degree)
      luaL_argerror(L, t, lua_pushfstring(L, "knots of degree %d for a fit of degree %d", K->degree, o->degree));
    o->knots = K->U;
    o->nknots = K->n;
    if (o->periodic) {
      if (K->n < 2 * p + 3) luaL_argerror(L, t, "periodic knots too short");
      o->knots = K->U + p;
      o->nknots = K->n - 2 * p;
    }
  } else if (ty == LUA_TTABLE || luaL_testudata(L, -1, BSFIT_VECTOR_T)) {
    bsfit_vector_ud *v = bsfit__lua_tovector(L, -1);
    bsfit__lua_checkknotvalues(L, t, v->x, v->n, o->periodic ? -1 : o->degree);
    o->knots = v->x;
    o->nknots = v->n;
  } else {
    luaL_argerror(L, t, "field 'knots' must be a bsfit.Knots, bsfit.Vector or table");
  }
  /* the value stays on the stack: it anchors the array until configuration copies it */
  if (o->count == 0 && o->nknots > 0)
    o->count = o->periodic ? o->nknots - 1 : (o->nknots > p + 1 ? o->nknots - p - 1 : 0);
}

/* Reads the options table at t into o (arrays anchored on the stack); T0, T1 hold the
** tangents. Raises on misuse. */
static void read_settings(lua_State *L, int t, bsfit_fit_opts *o, double *T0, double *T1) {
  static const char *const opts[] = {"degree", "count", "knots", "periodic", "fix_ends", "rule",
                                     "tangent_start", "tangent_end", "solver", NULL};
  lua_Integer p, n;
  int n0, n1;
  const char *rule, *solver;
  size_t r;
  bsfit__lua_check_options(L, t, opts);
  bsfit_fit_opts_init(o);
  p = opt_integer(L, t, "degree", 3);
  if (p < 1 || p > BSFIT_MAX_DEGREE)
    luaL_argerror(L, t, lua_pushfstring(L, "field 'degree' must be in 1..%d", BSFIT_MAX_DEGREE));
  o->degree = (int)p;
  o->periodic = opt_boolean(L, t, "periodic", 0);
  o->fix_ends = opt_boolean(L, t, "fix_ends", 0);
  n = opt_integer(L, t, "count", 0);
  if (n < 0 || n > ((lua_Integer)1 << 40))
    luaL_argerror(L, t, "field 'count' out of range");
  o->count = (size_t)n;
  rule = opt_string(L, t, "rule", o->periodic ? "periodic-averaging" : "averaging");
  for (r = 0; rule_names[r] != NULL && strcmp(rule_names[r], rule) != 0; r++) continue;
  if (rule_names[r] == NULL)
    luaL_argerror(L, t, lua_pushfstring(L, "field 'rule': invalid option '%s'", rule));
  o->rule = rule_values[r];
  solver = opt_string(L, t, "solver", "cholesky");
  for (r = 0; solver_names[r] != NULL && strcmp(solver_names[r], solver) != 0; r++) continue;
  if (solver_names[r] == NULL)
    luaL_argerror(L, t, lua_pushfstring(L, "field 'solver': invalid option '%s'", solver));
  o->solver = (bsfit_solver)r;
  knots_setting(L, t, o);
  if (o->count == 0) luaL_argerror(L, t, "field 'count' (or 'knots') is required");
  n0 = opt_tangent(L, t, "tangent_start", T0);
  n1 = opt_tangent(L, t, "tangent_end", T1);
  if (n0 && n1 && n0 != n1) luaL_argerror(L, t, "tangents of different dimensions");
  o->tangent_start = n0 ? T0 : NULL;
  o->tangent_end = n1 ? T1 : NULL;
  o->tangent_dim = n0 ? n0 : n1;
}

static void remember(fitter_ud *F, const bsfit_fit_opts *o) {
  F->degree = o->degree;
  F->periodic = o->periodic;
  F->count = o->count;
}

/* bs.fitter{degree =, count =, knots =, periodic =, fix_ends =, rule =, tangent_start =,
** tangent_end =, solver =} --> Fitter */
static int fitter_new(lua_State *L) {
  bsfit_fit_opts o;
  double T0[4], T1[4];
  bsfit_allocator a;
  bsfit_status st;
  fitter_ud *F;
  bsfit_err e;
  luaL_checktype(L, 1, LUA_TTABLE);
  read_settings(L, 1, &o, T0, T1);
  F = (fitter_ud *)lua_newuserdatauv(L, sizeof *F, 0); /* closed state first */
  memset(F, 0, sizeof *F);
  luaL_setmetatable(L, BSFIT_FITTER_T);
  a = bsfit__lua_allocator(L);
  e = bsfit_fitter_new(&F->f, &o, &a, &st);
  if (e != BSFIT_OK) return bsfit__lua_raise(L, e, &st, 1);
  remember(F, &o);
  return 1;
}

/* }==================================================================== */

/* {====================================================================
** 3. Methods and metamethods
** ===================================================================== */

/* F:configure{...}: new settings (same options as bs.fitter); on error the fitter
** keeps its settings. Returns F. */
static int fitter_configure(lua_State *L) {
  fitter_ud *F = checkfitter(L, 1);
  bsfit_fit_opts o;
  double T0[4], T1[4];
  bsfit_status st;
  bsfit_err e;
  luaL_checktype(L, 2, LUA_TTABLE);
  read_settings(L, 2, &o, T0, T1);
  e = bsfit_fitter_configure(F->f, &o, &st);
  if (e != BSFIT_OK) return bsfit__lua_raise(L, e, &st, 2);
  remember(F, &o);
  lua_settop(L, 1);
  return 1;
}

/* The fitter's weights, with 1-based messages: positive and finite (as every weight), and
** not subnormal (bsfit_fitter_fit refuses those: the sums would keep too few digits). */
static void check_fit_weights(lua_State *L, const bsfit_vector_ud *w) {
  size_t i;
  bsfit__lua_checkweights(L, 4, w->x, w->n);
  for (i = 0; i < w->n; i++)
    if (w->x[i] < DBL_MIN) {
      char num[32];
      snprintf(num, sizeof num, "%g", w->x[i]);
      luaL_argerror(L, 4, lua_pushfstring(L, "weight %I is %s (must be at least DBL_MIN = "
                                          "2.2e-308)", (lua_Integer)i + 1, num));
    }
}

/* The argument a misuse status of a fit blames: the weights for a bad weight, the
** points otherwise (the core's message says which value). */
static int fit_arg(bsfit_err e) { return e == BSFIT_EWEIGHT ? 4 : 2; }

static void push_report(lua_State *L, const bsfit_fit_report *rep, int resid) {
  lua_createtable(L, 0, 9);
  lua_pushnumber(L, rep->rms);
  lua_setfield(L, -2, "rms");
  lua_pushnumber(L, rep->max);
  lua_setfield(L, -2, "max");
  lua_pushinteger(L, (lua_Integer)rep->max_index + 1);
  lua_setfield(L, -2, "max_index");
  lua_pushnumber(L, rep->rcond);
  lua_setfield(L, -2, "rcond");
  lua_pushinteger(L, (lua_Integer)rep->n_empty_spans);
  lua_setfield(L, -2, "empty_spans");
  lua_pushinteger(L, (lua_Integer)rep->m);
  lua_setfield(L, -2, "m");
  lua_pushstring(L, solver_names[rep->solver]);
  lua_setfield(L, -2, "solver");
  lua_pushvalue(L, resid);
  lua_setfield(L, -2, "residuals");
}

/* F:fit(P [, u [, w [, r]]]) --> Curve, report | nil, message, code.
** P: Points or table; u: parameters (Vector or table; default chord-length, closed
** for a periodic fitter); w: per-point weights (Vector or table, default 1); r: a
** Vector of #P that receives the residuals (report.residuals is then r), so a loop of
** big fits reuses its memory instead of a fresh Vector per call. */
static int fitter_fit(lua_State *L) {
  fitter_ud *F = checkfitter(L, 1);
  bsfit_points_ud *P = bsfit__lua_topoints(L, 2);
  bsfit_vector_ud *u = NULL, *w = NULL, *res = NULL;
  bsfit_fit_report rep;
  bsfit_allocator a;
  bsfit_curve_ud *C;
  bsfit_status st;
  bsfit_err e;
  lua_settop(L, 5);
  if (!lua_isnil(L, 3)) u = bsfit__lua_tovector(L, 3);
  if (!lua_isnil(L, 4)) w = bsfit__lua_tovector(L, 4);
  if (!lua_isnil(L, 5)) {
    res = bsfit__lua_checkvector(L, 5);
    if (res->n != P->n)
      return luaL_argerror(L, 5, lua_pushfstring(L, "%d residual slots for %d points", (int)res->n, (int)P->n));
    if (res == u || res == w)
      return luaL_argerror(L, 5, "the residuals Vector must not be the parameters or the weights");
  }
  if (u && u->n != P->n)
    return luaL_argerror(L, 3, lua_pushfstring(L, "%d parameters for %d points", (int)u->n, (int)P->n));
  if (w && w->n != P->n)
    return luaL_argerror(L, 4, lua_pushfstring(L, "%d weights for %d points", (int)w->n, (int)P->n));
  if (u == NULL) { /* chord-length parameters, written into a Vector in slot 3 */
    u = bsfit__lua_allocvector(L, P->n);
    lua_replace(L, 3);
    e = bsfit_params(P->xy, P->n, (int)P->dim, BSFIT_PARAM_CHORD, F->periodic, u->x, &st);
    if (e != BSFIT_OK) {
      bsfit__lua_checkfinite(L, 2, P); /* raises with a 1-based message if that is why */
      return bsfit__lua_result(L, e, &st, 0, 2);
    }
  }
  if (lua_isnil(L, 5)) {
    res = bsfit__lua_allocvector(L, P->n); /* every value is written by the fit */
    lua_replace(L, 5);
  }
  C = bsfit__lua_newcurve(L, &a); /* slot 6 */
  e = bsfit_fitter_fit(F->f, P->xy, P->n, (int)P->dim, u->x, w ? w->x : NULL, &C->c, &rep,
                       res->x, &st);
  if (e != BSFIT_OK) {
    /* the core checks the data in its assembly loop; on NaN or a bad weight, find the
    ** culprit again to say it with 1-based indices (no extra pass when all is well) */
    if (e == BSFIT_ENONFINITE || e == BSFIT_EWEIGHT) {
      bsfit__lua_checkfinite(L, 2, P);
      if (w) check_fit_weights(L, w);
    }
    return bsfit__lua_result(L, e, &st, 0, fit_arg(e));
  }
  push_report(L, &rep, 5);
  return 2;
}

/* F:knots() --> Knots of the last fit (open n+p+1, periodic expanded), or nil */
static int fitter_knots(lua_State *L) {
  fitter_ud *F = checkfitter(L, 1);
  size_t n = 0;
  const double *U = bsfit_fitter_knots(F->f, &n);
  bsfit_knots_ud *K;
  if (U == NULL) {
    luaL_pushfail(L);
    return 1;
  }
  K = bsfit__lua_newknots(L, n, F->degree);
  memcpy(K->U, U, n * sizeof(double));
  return 1;
}

static int fitter_degree(lua_State *L) {
  lua_pushinteger(L, checkfitter(L, 1)->degree);
  return 1;
}

static int fitter_count(lua_State *L) {
  lua_pushinteger(L, (lua_Integer)checkfitter(L, 1)->count);
  return 1;
}

static int fitter_is_periodic(lua_State *L) {
  lua_pushboolean(L, checkfitter(L, 1)->periodic);
  return 1;
}

static int fitter_is_closed(lua_State *L) {
  lua_pushboolean(L, toud(L, 1)->f == NULL);
  return 1;
}

/* __gc and __close: frees the workspace once; later calls are no-ops */
static int fitter_gc(lua_State *L) {
  fitter_ud *F = toud(L, 1);
  bsfit_fitter_free(F->f);
  F->f = NULL;
  return 0;
}

static int fitter_tostring(lua_State *L) {
  fitter_ud *F = toud(L, 1);
  if (F->f == NULL) lua_pushliteral(L, "bsfit.Fitter (closed)");
  else
    lua_pushfstring(L, "bsfit.Fitter(deg=%d, n=%I%s): %p", F->degree, (lua_Integer)F->count,
                    F->periodic ? ", periodic" : "", (void *)F);
  return 1;
}

/* }==================================================================== */

/* {====================================================================
** 4. Registration arrays
** ===================================================================== */

static const luaL_Reg fitter_meth[] = {
  {"fit", fitter_fit}, {"configure", fitter_configure}, {"knots", fitter_knots},
  {"degree", fitter_degree}, {"count", fitter_count}, {"is_periodic", fitter_is_periodic},
  {"is_closed", fitter_is_closed}, {"close", fitter_gc}, {NULL, NULL}};

static const luaL_Reg fitter_metameth[] = {
  {"__index", NULL}, {"__gc", fitter_gc}, {"__close", fitter_gc},
  {"__tostring", fitter_tostring}, {NULL, NULL}};

/* }==================================================================== */

/* {====================================================================
** 5. Open
** ===================================================================== */

void bsfit_lua_open_fitter(lua_State *L) {
  luaL_newmetatable(L, BSFIT_FITTER_T);
  luaL_setfuncs(L, fitter_metameth, 0);
  luaL_newlibtable(L, fitter_meth);
  luaL_setfuncs(L, fitter_meth, 0);
  lua_setfield(L, -2, "__index");
  lua_pop(L, 1);
}

/* sets bs.fitter (the constructor) in the module table on the stack top */
void bsfit__lua_lib_fitter(lua_State *L) {
  lua_pushcfunction(L, fitter_new);
  lua_setfield(L, -2, "fitter");
}

/* }==================================================================== */
