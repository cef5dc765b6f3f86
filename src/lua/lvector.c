/*
** lvector.c
** bsfit.Vector: n doubles in one block (per-point weights, parameters, residuals),
** passed to the kernels without going through Lua tables.
*/
#include "laux.h"

#include <math.h>
#include <stdint.h>
#include <string.h>

/* {====================================================================
** 1. Type name and checker
** ===================================================================== */

static bsfit_vector_ud *checkvector(lua_State *L, int i) {
  return (bsfit_vector_ud *)luaL_checkudata(L, i, BSFIT_VECTOR_T);
}

bsfit_vector_ud *bsfit__lua_checkvector(lua_State *L, int arg) { return checkvector(L, arg); }

/* }==================================================================== */

/* {====================================================================
** 2. Constructors
** ===================================================================== */

bsfit_vector_ud *bsfit__lua_allocvector(lua_State *L, size_t n) {
  bsfit_vector_ud *v;
  if (n > (SIZE_MAX - sizeof *v) / sizeof(double)) luaL_error(L, "vector too large");
  v = (bsfit_vector_ud *)lua_newuserdatauv(L, sizeof *v + n * sizeof(double), 0);
  v->n = n;
  luaL_setmetatable(L, BSFIT_VECTOR_T);
  return v;
}

bsfit_vector_ud *bsfit__lua_newvector(lua_State *L, size_t n) {
  bsfit_vector_ud *v = bsfit__lua_allocvector(L, n);
  if (n) memset(v->x, 0, n * sizeof(double));
  return v;
}

static bsfit_vector_ud *fromtable(lua_State *L, int t) {
  size_t i, n = (size_t)luaL_len(L, t);
  bsfit_vector_ud *v = bsfit__lua_newvector(L, n);
  for (i = 0; i < n; i++) {
    int ok;
    lua_geti(L, t, (lua_Integer)i + 1);
    v->x[i] = lua_tonumberx(L, -1, &ok);
    if (!ok || lua_type(L, -1) != LUA_TNUMBER)
      luaL_argerror(L, t, lua_pushfstring(L, "element %d is not a number", (int)i + 1));
    lua_pop(L, 1);
  }
  return v;
}

bsfit_vector_ud *bsfit__lua_tovector(lua_State *L, int arg) {
  bsfit_vector_ud *v;
  if (lua_type(L, arg) != LUA_TTABLE) return checkvector(L, arg);
  arg = lua_absindex(L, arg);
  v = fromtable(L, arg);
  lua_replace(L, arg);
  return v;
}

/* bs.vector.new{...} | bs.vector.new(n [, fill]) */
static int vector_new(lua_State *L) {
  if (lua_type(L, 1) == LUA_TTABLE) {
    fromtable(L, 1);
  } else {
    size_t n = bsfit__lua_checkcount(L, 1, 0, LUA_MAXINTEGER), i;
    double fill = luaL_optnumber(L, 2, 0.0);
    bsfit_vector_ud *v = bsfit__lua_newvector(L, n);
    for (i = 0; fill != 0.0 && i < n; i++) v->x[i] = fill;
  }
  return 1;
}

static int vector_frombytes(lua_State *L) {
  size_t len;
  const char *s = luaL_checklstring(L, 1, &len);
  bsfit_vector_ud *v;
  luaL_argcheck(L, len % sizeof(double) == 0, 1, "length is not a multiple of 8");
  v = bsfit__lua_newvector(L, len / sizeof(double));
  if (len) memcpy(v->x, s, len);
  return 1;
}

/* }==================================================================== */

/* {====================================================================
** 3. Methods and metamethods
** ===================================================================== */

static int vector_get(lua_State *L) {
  bsfit_vector_ud *v = checkvector(L, 1);
  lua_pushnumber(L, v->x[bsfit__lua_index(L, 2, v->n)]);
  return 1;
}

static int vector_set(lua_State *L) {
  bsfit_vector_ud *v = checkvector(L, 1);
  size_t i = bsfit__lua_index(L, 2, v->n);
  v->x[i] = luaL_checknumber(L, 3);
  lua_settop(L, 1);
  return 1;
}

static int vector_totable(lua_State *L) {
  bsfit_vector_ud *v = checkvector(L, 1);
  size_t i;
  lua_createtable(L, (int)v->n, 0);
  for (i = 0; i < v->n; i++) {
    lua_pushnumber(L, v->x[i]);
    lua_rawseti(L, -2, (lua_Integer)i + 1);
  }
  return 1;
}

static int vector_bytes(lua_State *L) {
  bsfit_vector_ud *v = checkvector(L, 1);
  lua_pushlstring(L, (const char *)v->x, v->n * sizeof(double));
  return 1;
}

static int vector_sum(lua_State *L) {
  bsfit_vector_ud *v = checkvector(L, 1);
  double s = 0.0;
  size_t i;
  for (i = 0; i < v->n; i++) s += v->x[i];
  lua_pushnumber(L, s);
  return 1;
}

/* v:rms([w [, clip]]): sqrt(sum w_i min(|v_i|, clip)^2 / sum w_i), w a Vector of the
** same length (nil: all 1), clip > 0 (nil: none). Winsorised, it is the search statistic
** of the auto strategy; 0 for an empty vector. */
static int vector_rms(lua_State *L) {
  bsfit_vector_ud *v = checkvector(L, 1), *w = NULL;
  double clip = luaL_optnumber(L, 3, HUGE_VAL), s = 0.0, sw = 0.0;
  size_t i;
  if (!lua_isnoneornil(L, 2)) {
    w = checkvector(L, 2);
    if (w->n != v->n)
      return luaL_argerror(L, 2, lua_pushfstring(L, "%d weights for %d values", (int)w->n, (int)v->n));
  }
  luaL_argcheck(L, clip > 0.0, 3, "clip must be positive");
  for (i = 0; i < v->n; i++) {
    double a = fabs(v->x[i]), wi = w ? w->x[i] : 1.0;
    if (a > clip) a = clip;
    s += wi * a * a;
    sw += wi;
  }
  lua_pushnumber(L, sw > 0.0 ? sqrt(s / sw) : 0.0);
  return 1;
}

/* extreme value and its 1-based index (nil for an empty vector); sign = +1 max, -1 min */
static int extreme(lua_State *L, double sign) {
  bsfit_vector_ud *v = checkvector(L, 1);
  size_t i, best = 0;
  if (v->n == 0) {
    luaL_pushfail(L);
    return 1;
  }
  for (i = 1; i < v->n; i++)
    if (sign * v->x[i] > sign * v->x[best] || isnan(v->x[best])) best = i;
  lua_pushnumber(L, v->x[best]);
  lua_pushinteger(L, (lua_Integer)best + 1);
  return 2;
}

static int vector_max(lua_State *L) { return extreme(L, 1.0); }
static int vector_min(lua_State *L) { return extreme(L, -1.0); }

/* v:distinct(): the number of runs of equal consecutive values, the number of distinct
** values when v is sorted (parameters of points that coincide are equal); 0 when empty.
** A NaN equals nothing, so each counts. */
static int vector_distinct(lua_State *L) {
  bsfit_vector_ud *v = checkvector(L, 1);
  size_t i, n = v->n > 0;
  for (i = 1; i < v->n; i++)
    if (v->x[i] != v->x[i - 1]) n++;
  lua_pushinteger(L, (lua_Integer)n);
  return 1;
}

static int vector_copy(lua_State *L) {
  bsfit_vector_ud *v = checkvector(L, 1);
  bsfit_vector_ud *w = bsfit__lua_newvector(L, v->n);
  if (v->n) memcpy(w->x, v->x, v->n * sizeof(double));
  return 1;
}

static int vector_len(lua_State *L) {
  lua_pushinteger(L, (lua_Integer)checkvector(L, 1)->n);
  return 1;
}

static int vector_tostring(lua_State *L) {
  bsfit_vector_ud *v = checkvector(L, 1);
  lua_pushfstring(L, "bsfit.Vector(n=%I): %p", (lua_Integer)v->n, (void *)v);
  return 1;
}

/* }==================================================================== */

/* {====================================================================
** 4. Registration arrays
** ===================================================================== */

static const luaL_Reg vector_meth[] = {
  {"get", vector_get}, {"set", vector_set}, {"totable", vector_totable},
  {"bytes", vector_bytes}, {"sum", vector_sum}, {"rms", vector_rms}, {"max", vector_max},
  {"min", vector_min}, {"copy", vector_copy}, {"distinct", vector_distinct}, {NULL, NULL}};

static const luaL_Reg vector_metameth[] = {
  {"__index", NULL}, {"__len", vector_len}, {"__tostring", vector_tostring}, {NULL, NULL}};

static const luaL_Reg vector_funcs[] = {
  {"new", vector_new}, {"frombytes", vector_frombytes}, {NULL, NULL}};

/* }==================================================================== */

/* {====================================================================
** 5. Open
** ===================================================================== */

void bsfit_lua_open_vector(lua_State *L) {
  luaL_newmetatable(L, BSFIT_VECTOR_T);
  luaL_setfuncs(L, vector_metameth, 0);
  luaL_newlibtable(L, vector_meth);
  luaL_setfuncs(L, vector_meth, 0);
  lua_setfield(L, -2, "__index");
  lua_pop(L, 1);
}

void bsfit__lua_lib_vector(lua_State *L) { luaL_newlib(L, vector_funcs); }

const double *bsfit_lua_checkvector(lua_State *L, int arg, size_t *n) {
  bsfit_vector_ud *v = checkvector(L, arg);
  if (n) *n = v->n;
  return v->x;
}

double *bsfit_lua_pushvector(lua_State *L, size_t n) { return bsfit__lua_newvector(L, n)->x; }

/* }==================================================================== */
