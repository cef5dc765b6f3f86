/*
** lpoints.c
** bsfit.Points: m points of dim coordinates in one contiguous row-major block
** (STYLE R8), the type every numeric kernel takes instead of Lua tables.
*/
#include "laux.h"

#include <stdint.h>
#include <string.h>

#define MAXDIM 4

/* {====================================================================
** 1. Type name and checker
** ===================================================================== */

static bsfit_points_ud *checkpoints(lua_State *L, int i) {
  return (bsfit_points_ud *)luaL_checkudata(L, i, BSFIT_POINTS_T);
}

bsfit_points_ud *bsfit__lua_checkpoints(lua_State *L, int arg) { return checkpoints(L, arg); }

/* }==================================================================== */

/* {====================================================================
** 2. Constructor: a zeroed block of the final size, then the metatable
** ===================================================================== */

/* Points whose coordinates the caller overwrites in full (or drops on error), so the
** block is not zeroed first: that pass costs as much as a sampling kernel. */
bsfit_points_ud *bsfit__lua_allocpoints(lua_State *L, size_t n, size_t dim) {
  bsfit_points_ud *P;
  if (dim < 1 || dim > MAXDIM) luaL_error(L, "point dimension %d out of range 1..%d", (int)dim, MAXDIM);
  if (n > (SIZE_MAX - sizeof *P) / sizeof(double) / dim) luaL_error(L, "too many points");
  P = (bsfit_points_ud *)lua_newuserdatauv(L, sizeof *P + n * dim * sizeof(double), 0);
  P->n = n;
  P->dim = dim;
  luaL_setmetatable(L, BSFIT_POINTS_T);
  return P;
}

bsfit_points_ud *bsfit__lua_newpoints(lua_State *L, size_t n, size_t dim) {
  bsfit_points_ud *P;
  size_t bytes;
  if (dim < 1 || dim > MAXDIM) luaL_error(L, "point dimension %d out of range 1..%d", (int)dim, MAXDIM);
  if (n > (SIZE_MAX - sizeof *P) / sizeof(double) / dim) luaL_error(L, "too many points");
  bytes = n * dim * sizeof(double);
  P = (bsfit_points_ud *)lua_newuserdatauv(L, sizeof *P + bytes, 0);
  P->n = n;
  P->dim = dim;
  if (bytes) memset(P->xy, 0, bytes);
  luaL_setmetatable(L, BSFIT_POINTS_T);
  return P;
}

/* The single table -> C copy (LPeg's getpatt idea): {{x,y},{x,y},...}. */
static bsfit_points_ud *fromtable(lua_State *L, int t, lua_Integer dimarg) {
  size_t i, k, n = (size_t)luaL_len(L, t), dim = (size_t)dimarg;
  bsfit_points_ud *P;
  if (dim == 0 && n > 0) {
    if (lua_geti(L, t, 1) != LUA_TTABLE) luaL_argerror(L, t, "point 1 is not a table");
    dim = (size_t)luaL_len(L, -1);
    lua_pop(L, 1);
  }
  if (dim == 0) dim = 2; /* an empty set of plane points */
  if (dim > MAXDIM) luaL_argerror(L, t, lua_pushfstring(L, "points of %d coordinates (1..%d allowed)", (int)dim, MAXDIM));
  P = bsfit__lua_newpoints(L, n, dim);
  for (i = 0; i < n; i++) {
    if (lua_geti(L, t, (lua_Integer)i + 1) != LUA_TTABLE)
      luaL_argerror(L, t, lua_pushfstring(L, "point %d is not a table", (int)i + 1));
    if ((size_t)luaL_len(L, -1) != dim)
      luaL_argerror(L, t, lua_pushfstring(L, "point %d has %d coordinates, expected %d", (int)i + 1,
                                          (int)luaL_len(L, -1), (int)dim));
    for (k = 0; k < dim; k++) {
      int ok;
      lua_geti(L, -1, (lua_Integer)k + 1);
      P->xy[i * dim + k] = lua_tonumberx(L, -1, &ok);
      if (!ok || lua_type(L, -1) != LUA_TNUMBER)
        luaL_argerror(L, t, lua_pushfstring(L, "point %d coordinate %d is not a number", (int)i + 1,
                                            (int)k + 1));
      lua_pop(L, 1);
    }
    lua_pop(L, 1);
  }
  return P;
}

bsfit_points_ud *bsfit__lua_topoints(lua_State *L, int arg) {
  bsfit_points_ud *P;
  if (lua_type(L, arg) != LUA_TTABLE) return checkpoints(L, arg);
  arg = lua_absindex(L, arg);
  P = fromtable(L, arg, 0);
  lua_replace(L, arg);
  return P;
}

/* bs.points.new{{x,y},...} | bs.points.new(n, dim) (zeroed) */
static int points_new(lua_State *L) {
  if (lua_type(L, 1) == LUA_TTABLE) {
    lua_Integer dim = luaL_optinteger(L, 2, 0);
    luaL_argcheck(L, dim >= 0 && dim <= MAXDIM, 2, "dimension out of range 1..4");
    fromtable(L, 1, dim);
  } else {
    size_t n = bsfit__lua_checkcount(L, 1, 0, LUA_MAXINTEGER);
    size_t dim = bsfit__lua_checkcount(L, 2, 1, MAXDIM);
    bsfit__lua_newpoints(L, n, dim);
  }
  return 1;
}

/* bs.points.frombytes(s, dim): native-endian doubles, as string.pack("d", ...) */
static int points_frombytes(lua_State *L) {
  size_t len;
  const char *s = luaL_checklstring(L, 1, &len);
  size_t dim = bsfit__lua_checkcount(L, 2, 1, MAXDIM);
  bsfit_points_ud *P;
  luaL_argcheck(L, len % (dim * sizeof(double)) == 0, 1, "length is not a multiple of dim doubles");
  P = bsfit__lua_newpoints(L, len / (dim * sizeof(double)), dim);
  if (len) memcpy(P->xy, s, len);
  return 1;
}

/* bs.points.read(path) --> Points, Vector of weights or nil. A file that cannot be
** read or parsed is an outcome, not misuse: nil, message, code (io.open's rule). */
static int points_read(lua_State *L) {
  const char *path = luaL_checkstring(L, 1);
  bsfit_scratch_ud *box;
  bsfit_points_ud *P;
  bsfit_status st;
  double *xy = NULL, *w = NULL;
  size_t m = 0;
  int dim = 0;
  bsfit_err e;
  bsfit__lua_check_files(L, "bs.points.read");
  box = bsfit__lua_newscratch(L);
  e = bsfit_points_read(path, &xy, &m, &dim, &w, &box->a, &st);
  if (e == BSFIT_ENOMEM) return bsfit__lua_raise(L, e, &st, 0);
  if (e != BSFIT_OK) {
    luaL_pushfail(L);
    lua_pushstring(L, st.msg);
    lua_pushstring(L, bsfit_errname(e));
    return 3;
  }
  box->p[0] = xy;
  box->size[0] = m * (size_t)dim * sizeof(double);
  box->p[1] = w;
  box->size[1] = w ? m * sizeof(double) : 0;
  P = bsfit__lua_newpoints(L, m, (size_t)dim);
  memcpy(P->xy, xy, box->size[0]);
  if (w) memcpy(bsfit__lua_newvector(L, m)->x, w, box->size[1]);
  else luaL_pushfail(L);
  bsfit__lua_scratch_free(box);
  return 2;
}

/* }==================================================================== */

/* {====================================================================
** 3. Methods and metamethods
** ===================================================================== */

static int points_dim(lua_State *L) {
  lua_pushinteger(L, (lua_Integer)checkpoints(L, 1)->dim);
  return 1;
}

static int points_get(lua_State *L) {
  bsfit_points_ud *P = checkpoints(L, 1);
  size_t i = bsfit__lua_index(L, 2, P->n), k;
  luaL_checkstack(L, (int)P->dim, "too many coordinates");
  for (k = 0; k < P->dim; k++) lua_pushnumber(L, P->xy[i * P->dim + k]);
  return (int)P->dim;
}

/* P:set(i, x, y[, z]): exactly dim coordinates */
static int points_set(lua_State *L) {
  bsfit_points_ud *P = checkpoints(L, 1);
  size_t i = bsfit__lua_index(L, 2, P->n), k;
  double x[MAXDIM];
  for (k = 0; k < P->dim; k++) x[k] = luaL_checknumber(L, 3 + (int)k);
  if (!lua_isnone(L, 3 + (int)P->dim))
    return luaL_argerror(L, 3 + (int)P->dim,
                         lua_pushfstring(L, "too many coordinates (points have %d)", (int)P->dim));
  memcpy(P->xy + i * P->dim, x, P->dim * sizeof(double));
  lua_settop(L, 1);
  return 1;
}

static int points_totable(lua_State *L) {
  bsfit_points_ud *P = checkpoints(L, 1);
  size_t i, k;
  lua_createtable(L, (int)P->n, 0);
  for (i = 0; i < P->n; i++) {
    lua_createtable(L, (int)P->dim, 0);
    for (k = 0; k < P->dim; k++) {
      lua_pushnumber(L, P->xy[i * P->dim + k]);
      lua_rawseti(L, -2, (lua_Integer)k + 1);
    }
    lua_rawseti(L, -2, (lua_Integer)i + 1);
  }
  return 1;
}

static int points_bytes(lua_State *L) {
  bsfit_points_ud *P = checkpoints(L, 1);
  lua_pushlstring(L, (const char *)P->xy, P->n * P->dim * sizeof(double));
  return 1;
}

/* P:slice(i [, j]): points i..j inclusive (j defaults to -1, the last), a copy */
static int points_slice(lua_State *L) {
  bsfit_points_ud *P = checkpoints(L, 1), *Q;
  size_t i = bsfit__lua_index(L, 2, P->n), j;
  if (lua_isnoneornil(L, 3)) j = P->n - 1;
  else j = bsfit__lua_index(L, 3, P->n);
  if (j < i) {
    Q = bsfit__lua_newpoints(L, 0, P->dim);
    return 1;
  }
  Q = bsfit__lua_newpoints(L, j - i + 1, P->dim);
  memcpy(Q->xy, P->xy + i * P->dim, Q->n * P->dim * sizeof(double));
  return 1;
}

/* P:rotate(k): a copy cyclically shifted so that point k comes first (the start-point
** search of docs/method.md §8 tries each candidate as Q_0). */
static int points_rotate(lua_State *L) {
  bsfit_points_ud *P = checkpoints(L, 1), *Q;
  size_t k = bsfit__lua_index(L, 2, P->n), d = P->dim;
  Q = bsfit__lua_newpoints(L, P->n, d);
  memcpy(Q->xy, P->xy + k * d, (P->n - k) * d * sizeof(double));
  memcpy(Q->xy + (P->n - k) * d, P->xy, k * d * sizeof(double));
  return 1;
}

static int points_copy(lua_State *L) {
  bsfit_points_ud *P = checkpoints(L, 1);
  bsfit_points_ud *Q = bsfit__lua_newpoints(L, P->n, P->dim);
  if (P->n) memcpy(Q->xy, P->xy, P->n * P->dim * sizeof(double));
  return 1;
}

/* P:write(path [, weights]): CSV with a header (x,y[,z][,w]), replaced atomically;
** returns P, or nil, message, code when the file cannot be written. */
static int points_write(lua_State *L) {
  bsfit_points_ud *P = checkpoints(L, 1);
  const char *path = luaL_checkstring(L, 2);
  bsfit_vector_ud *w = lua_isnoneornil(L, 3) ? NULL : bsfit__lua_tovector(L, 3);
  bsfit_status st;
  bsfit_err e;
  luaL_argcheck(L, w == NULL || w->n == P->n, 3, "one weight per point expected");
  bsfit__lua_check_files(L, "write");
  e = bsfit_points_write(path, P->xy, P->n, (int)P->dim, w ? w->x : NULL, &st);
  lua_settop(L, 1);
  if (e == BSFIT_EIO) return bsfit__lua_result(L, e, &st, 1, 0);
  if (e != BSFIT_OK) return bsfit__lua_raise(L, e, &st, e == BSFIT_EWEIGHT ? 3 : 1);
  return 1;
}

static int points_len(lua_State *L) {
  lua_pushinteger(L, (lua_Integer)checkpoints(L, 1)->n);
  return 1;
}

static int points_tostring(lua_State *L) {
  bsfit_points_ud *P = checkpoints(L, 1);
  lua_pushfstring(L, "bsfit.Points(n=%I, dim=%d): %p", (lua_Integer)P->n, (int)P->dim, (void *)P);
  return 1;
}

/* }==================================================================== */

/* {====================================================================
** 4. Registration arrays
** ===================================================================== */

static const luaL_Reg points_meth[] = {
  {"dim", points_dim},         {"get", points_get},       {"set", points_set},
  {"totable", points_totable}, {"bytes", points_bytes},   {"slice", points_slice},
  {"rotate", points_rotate},   {"copy", points_copy},     {"write", points_write},
  {NULL, NULL}};

static const luaL_Reg points_metameth[] = {
  {"__index", NULL}, {"__len", points_len}, {"__tostring", points_tostring}, {NULL, NULL}};

static const luaL_Reg points_funcs[] = {
  {"new", points_new}, {"frombytes", points_frombytes}, {"read", points_read}, {NULL, NULL}};

/* }==================================================================== */

/* {====================================================================
** 5. Open
** ===================================================================== */

void bsfit_lua_open_points(lua_State *L) {
  luaL_newmetatable(L, BSFIT_POINTS_T);
  luaL_setfuncs(L, points_metameth, 0);
  luaL_newlibtable(L, points_meth);
  luaL_setfuncs(L, points_meth, 0);
  lua_setfield(L, -2, "__index");
  lua_pop(L, 1);
}

void bsfit__lua_lib_points(lua_State *L) { luaL_newlib(L, points_funcs); }

/* }==================================================================== */

/* {====================================================================
** Host helpers (bsfit_lua.h)
** ===================================================================== */

const double *bsfit_lua_checkpoints(lua_State *L, int arg, size_t *n, size_t *dim) {
  bsfit_points_ud *P = checkpoints(L, arg);
  if (n) *n = P->n;
  if (dim) *dim = P->dim;
  return P->xy;
}

double *bsfit_lua_pushpoints(lua_State *L, size_t n, size_t dim) {
  return bsfit__lua_newpoints(L, n, dim)->xy;
}

/* }==================================================================== */
