/*
** lknots.c
** bsfit.Knots: a knot vector and its degree in one block. Every constructor
** validates through the core (non-decreasing, finite, multiplicity, domain), so a
** Knots value in Lua is always usable by a curve or a fitter of its degree.
*/
#include "laux.h"

#include <math.h>
#include <stdint.h>
#include <string.h>

/* {====================================================================
** 1. Type name and checker
** ===================================================================== */

static bsfit_knots_ud *checkknots(lua_State *L, int i) {
  return (bsfit_knots_ud *)luaL_checkudata(L, i, BSFIT_KNOTS_T);
}

bsfit_knots_ud *bsfit__lua_checkknots(lua_State *L, int arg) { return checkknots(L, arg); }

/* control points implied by a knot vector: n = nknots - p - 1 */
static size_t ncontrol(const bsfit_knots_ud *K) { return K->n - (size_t)K->degree - 1; }

/* }==================================================================== */

/* {====================================================================
** 2. Constructors
** ===================================================================== */

bsfit_knots_ud *bsfit__lua_newknots(lua_State *L, size_t n, int degree) {
  bsfit_knots_ud *K;
  if (n > (SIZE_MAX - sizeof *K) / sizeof(double)) luaL_error(L, "knot vector too large");
  K = (bsfit_knots_ud *)lua_newuserdatauv(L, sizeof *K + n * sizeof(double), 0);
  K->degree = degree;
  K->n = n;
  if (n) memset(K->U, 0, n * sizeof(double));
  luaL_setmetatable(L, BSFIT_KNOTS_T);
  return K;
}

static int checkdegree(lua_State *L, int t, int minp) {
  lua_Integer p = req_integer(L, t, "degree");
  if (p < minp || p > BSFIT_MAX_DEGREE)
    luaL_argerror(L, t, lua_pushfstring(L, "field 'degree' must be in %d..%d", minp, BSFIT_MAX_DEGREE));
  return (int)p;
}

/* field k of table t as a Vector or a table of numbers: its doubles stay valid while
** the value is in the table (a converted table is anchored as t's k field's copy) */
static bsfit_vector_ud *field_vector(lua_State *L, int t, const char *k) {
  int ty = bsfit__lua_field(L, t, k);
  if (ty == LUA_TNIL) luaL_argerror(L, t, lua_pushfstring(L, "field '%s' is required", k));
  if (ty != LUA_TTABLE && !luaL_testudata(L, -1, BSFIT_VECTOR_T))
    luaL_argerror(L, t, lua_pushfstring(L, "field '%s' must be a table or bsfit.Vector", k));
  return bsfit__lua_tovector(L, -1); /* left on the stack: the caller's anchor */
}

/* bs.knots.new{degree = p, values = {...}} */
static int knots_new(lua_State *L) {
  static const char *const opts[] = {"degree", "values", NULL};
  bsfit_status st;
  bsfit_vector_ud *v;
  bsfit_knots_ud *K;
  int p;
  bsfit_err e;
  luaL_checktype(L, 1, LUA_TTABLE);
  bsfit__lua_check_options(L, 1, opts);
  p = checkdegree(L, 1, 0);
  v = field_vector(L, 1, "values");
  if (v->n < 2 * (size_t)p + 2)
    return luaL_argerror(L, 1, lua_pushfstring(L, "degree %d needs at least %d knots, got %d", p,
                                                2 * p + 2, (int)v->n));
  bsfit__lua_checkknotvalues(L, 1, v->x, v->n, p); /* 1-based messages before the core's */
  e = bsfit_knots_validate(v->x, v->n, p, v->n - (size_t)p - 1, &st);
  if (e != BSFIT_OK) return bsfit__lua_raise(L, e, &st, 1);
  K = bsfit__lua_newknots(L, v->n, p);
  memcpy(K->U, v->x, v->n * sizeof(double));
  return 1;
}

/* domain = {a, b}, default [0, 1] */
static void opt_domain(lua_State *L, int t, double *a, double *b) {
  int ty = bsfit__lua_field(L, t, "domain");
  *a = 0.0;
  *b = 1.0;
  if (ty == LUA_TTABLE) {
    int ok1, ok2;
    lua_geti(L, -1, 1);
    lua_geti(L, -2, 2);
    *a = lua_tonumberx(L, -2, &ok1);
    *b = lua_tonumberx(L, -1, &ok2);
    if (!ok1 || !ok2 || luaL_len(L, -3) != 2) ty = LUA_TNONE;
    lua_pop(L, 2);
  }
  if (ty != LUA_TTABLE && ty != LUA_TNIL)
    luaL_argerror(L, t, "field 'domain' must be a table {a, b}");
  lua_pop(L, 1);
}

typedef bsfit_err (*kind_fn)(int, size_t, double, double, double *, bsfit_status *);

/* bs.knots.uniform / clamped {degree = p, count = n, domain = {a, b}} */
static int knots_kind(lua_State *L, kind_fn fn) {
  static const char *const opts[] = {"degree", "count", "domain", NULL};
  bsfit_status st;
  bsfit_knots_ud *K;
  lua_Integer n;
  double a, b;
  int p;
  bsfit_err e;
  luaL_checktype(L, 1, LUA_TTABLE);
  bsfit__lua_check_options(L, 1, opts);
  p = checkdegree(L, 1, 0);
  n = req_integer(L, 1, "count");
  if (n < p + 1 || n > INT32_MAX)
    return luaL_argerror(L, 1, lua_pushfstring(L, "field 'count' must be at least degree+1 = %d", p + 1));
  opt_domain(L, 1, &a, &b);
  K = bsfit__lua_newknots(L, (size_t)n + (size_t)p + 1, p);
  e = fn(p, (size_t)n, a, b, K->U, &st);
  if (e != BSFIT_OK) return bsfit__lua_raise(L, e, &st, 1);
  return 1;
}

static int knots_uniform(lua_State *L) { return knots_kind(L, bsfit_knots_uniform); }
static int knots_clamped(lua_State *L) { return knots_kind(L, bsfit_knots_clamped); }

/* bs.knots.periodic{degree = p, period = {t0..tN}} | {degree = p, count = N, domain = {a,b}}:
** the expanded vector of docs/method.md §1 (N + 2p + 1 knots) */
static int knots_periodic(lua_State *L) {
  static const char *const opts[] = {"degree", "count", "domain", "period", NULL};
  bsfit_status st;
  bsfit_knots_ud *K;
  bsfit_vector_ud *per;
  size_t N, i;
  int p;
  bsfit_err e;
  luaL_checktype(L, 1, LUA_TTABLE);
  bsfit__lua_check_options(L, 1, opts);
  p = checkdegree(L, 1, 1);
  if (bsfit__lua_field(L, 1, "period") != LUA_TNIL) {
    lua_pop(L, 1);
    per = field_vector(L, 1, "period");
    if (per->n < 3) return luaL_argerror(L, 1, "field 'period' needs at least 3 knots");
    N = per->n - 1;
  } else {
    lua_Integer n = req_integer(L, 1, "count");
    double a, b;
    lua_pop(L, 1);
    if (n < 2 || n < p + 1 || n > INT32_MAX)
      return luaL_argerror(L, 1, lua_pushfstring(L, "field 'count' must be at least %d", p + 1 > 2 ? p + 1 : 2));
    opt_domain(L, 1, &a, &b);
    N = (size_t)n;
    per = bsfit__lua_newvector(L, N + 1);
    for (i = 0; i <= N; i++) per->x[i] = a + (b - a) * (double)i / (double)N;
    per->x[N] = b;
  }
  K = bsfit__lua_newknots(L, N + 2 * (size_t)p + 1, p);
  e = bsfit_knots_periodic(p, N, per->x, K->U, &st);
  if (e != BSFIT_OK) return bsfit__lua_raise(L, e, &st, 1);
  return 1;
}

/* bs.knots.averaging{params = u, count = n, degree = 3, closed = false, rule = ...}:
** knots placed on the parameters (docs/method.md §3-4). Open rules give a clamped vector; closed
** rules ("carvalho-closed", "periodic-averaging", "periodic-uniform") the expanded
** periodic vector. A span without parameters gives nil, message, "EEMPTYSPAN". */
static int knots_averaging(lua_State *L) {
  static const char *const opts[] = {"params", "count", "degree", "closed", "rule", NULL};
  static const char *const names[] = {"averaging", "carvalho-closed", "periodic-averaging",
                                      "uniform", "periodic-uniform", NULL};
  static const bsfit_knot_rule rules[] = {
    BSFIT_KNOTS_AVERAGING, BSFIT_KNOTS_CARVALHO_CLOSED, BSFIT_KNOTS_PERIODIC_AVERAGING,
    BSFIT_KNOTS_UNIFORM, BSFIT_KNOTS_PERIODIC_UNIFORM};
  bsfit_status st;
  bsfit_vector_ud *u, *period;
  bsfit_knots_ud *K;
  bsfit_knot_rule rule;
  lua_Integer n, pp;
  const char *rname;
  size_t r, nk;
  int p, closed;
  bsfit_err e;
  luaL_checktype(L, 1, LUA_TTABLE);
  bsfit__lua_check_options(L, 1, opts);
  pp = opt_integer(L, 1, "degree", 3);
  if (pp < 1 || pp > BSFIT_MAX_DEGREE)
    return luaL_argerror(L, 1, lua_pushfstring(L, "field 'degree' must be in 1..%d", BSFIT_MAX_DEGREE));
  p = (int)pp;
  closed = opt_boolean(L, 1, "closed", 0);
  n = req_integer(L, 1, "count");
  if (n < p + 1 || n < 2 || n > INT32_MAX)
    return luaL_argerror(L, 1, lua_pushfstring(L, "field 'count' must be at least %d", p + 1));
  rname = opt_string(L, 1, "rule", closed ? "carvalho-closed" : "averaging");
  for (r = 0; names[r] != NULL && strcmp(names[r], rname) != 0; r++) continue;
  if (names[r] == NULL)
    return luaL_argerror(L, 1, lua_pushfstring(L, "field 'rule': invalid option '%s'", rname));
  rule = rules[r];
  if (bsfit_knot_rule_closed(rule) != closed)
    return luaL_argerror(L, 1, lua_pushfstring(L, "rule '%s' is for %s curves", rname,
                                                closed ? "open" : "closed"));
  u = field_vector(L, 1, "params");
  bsfit__lua_checkparams(L, 1, u->x, u->n);
  nk = bsfit_knots_place_count(rule, p, (size_t)n);
  period = bsfit__lua_newvector(L, nk); /* open rules: the whole vector */
  e = bsfit_knots_place(rule, u->x, u->n, p, (size_t)n, period->x, &st);
  if (e != BSFIT_OK) return bsfit__lua_result(L, e, &st, 0, 1);
  if (!closed) {
    K = bsfit__lua_newknots(L, nk, p);
    memcpy(K->U, period->x, nk * sizeof(double));
    return 1;
  }
  K = bsfit__lua_newknots(L, (size_t)n + 2 * (size_t)p + 1, p);
  e = bsfit_knots_periodic(p, (size_t)n, period->x, K->U, &st);
  return bsfit__lua_result(L, e, &st, 1, 1);
}

/* }==================================================================== */

/* {====================================================================
** 3. Methods and metamethods
** ===================================================================== */

static int knots_values(lua_State *L) {
  bsfit_knots_ud *K = checkknots(L, 1);
  size_t i;
  lua_createtable(L, (int)K->n, 0);
  for (i = 0; i < K->n; i++) {
    lua_pushnumber(L, K->U[i]);
    lua_rawseti(L, -2, (lua_Integer)i + 1);
  }
  return 1;
}

static int knots_vector(lua_State *L) {
  bsfit_knots_ud *K = checkknots(L, 1);
  bsfit_vector_ud *v = bsfit__lua_newvector(L, K->n);
  memcpy(v->x, K->U, K->n * sizeof(double));
  return 1;
}

static int knots_get(lua_State *L) {
  bsfit_knots_ud *K = checkknots(L, 1);
  lua_pushnumber(L, K->U[bsfit__lua_index(L, 2, K->n)]);
  return 1;
}

static int knots_degree(lua_State *L) {
  lua_pushinteger(L, checkknots(L, 1)->degree);
  return 1;
}

/* number of control points a curve on these knots has */
static int knots_count(lua_State *L) {
  lua_pushinteger(L, (lua_Integer)ncontrol(checkknots(L, 1)));
  return 1;
}

static int knots_domain(lua_State *L) {
  bsfit_knots_ud *K = checkknots(L, 1);
  double a, b;
  bsfit_knots_domain(K->U, ncontrol(K), K->degree, &a, &b);
  lua_pushnumber(L, a);
  lua_pushnumber(L, b);
  return 2;
}

/* K:span(t): the 1-based index i with K[i] <= t < K[i+1] (clamped into the domain's
** spans as bsfit_knots_find_span does) */
static int knots_span(lua_State *L) {
  bsfit_knots_ud *K = checkknots(L, 1);
  double t = luaL_checknumber(L, 2);
  luaL_argcheck(L, isfinite(t), 2, "parameter is not finite");
  lua_pushinteger(L, (lua_Integer)bsfit_knots_find_span(K->U, ncontrol(K), K->degree, t) + 1);
  return 1;
}

static int knots_multiplicity(lua_State *L) {
  bsfit_knots_ud *K = checkknots(L, 1);
  double t = luaL_checknumber(L, 2);
  lua_pushinteger(L, bsfit_knots_multiplicity(K->U, K->n, t));
  return 1;
}

static int knots_len(lua_State *L) {
  lua_pushinteger(L, (lua_Integer)checkknots(L, 1)->n);
  return 1;
}

static int knots_tostring(lua_State *L) {
  bsfit_knots_ud *K = checkknots(L, 1);
  lua_pushfstring(L, "bsfit.Knots(deg=%d, n=%I): %p", K->degree, (lua_Integer)K->n, (void *)K);
  return 1;
}

/* }==================================================================== */

/* {====================================================================
** 4. Registration arrays
** ===================================================================== */

static const luaL_Reg knots_meth[] = {
  {"values", knots_values}, {"totable", knots_values}, {"vector", knots_vector},
  {"get", knots_get}, {"degree", knots_degree}, {"count", knots_count},
  {"domain", knots_domain}, {"span", knots_span}, {"multiplicity", knots_multiplicity},
  {NULL, NULL}};

static const luaL_Reg knots_metameth[] = {
  {"__index", NULL}, {"__len", knots_len}, {"__tostring", knots_tostring}, {NULL, NULL}};

static const luaL_Reg knots_funcs[] = {
  {"new", knots_new}, {"uniform", knots_uniform}, {"clamped", knots_clamped},
  {"periodic", knots_periodic}, {"averaging", knots_averaging}, {NULL, NULL}};

/* }==================================================================== */

/* {====================================================================
** 5. Open
** ===================================================================== */

void bsfit_lua_open_knots(lua_State *L) {
  luaL_newmetatable(L, BSFIT_KNOTS_T);
  luaL_setfuncs(L, knots_metameth, 0);
  luaL_newlibtable(L, knots_meth);
  luaL_setfuncs(L, knots_meth, 0);
  lua_setfield(L, -2, "__index");
  lua_pop(L, 1);
}

void bsfit__lua_lib_knots(lua_State *L) { luaL_newlib(L, knots_funcs); }

/* }==================================================================== */
