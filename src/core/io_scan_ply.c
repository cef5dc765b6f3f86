/*
** io_scan_ply.c
** PLY reader (ascii, binary_little_endian, binary_big_endian): the vertex element's
** x, y, z (any numeric type) and the face element's vertex index list (vertex_indices
** or vertex_index), polygons split into fans of triangles. Every other element and
** property is read past. Errors name the file, the element and its 1-based index, and
** the line (ascii) or the byte offset (binary).
*/
#include "scan_internal.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define MAXPROPS 64
#define MAXELEMS 32
#define MAXPOLY 1024 /* vertices of one face: more is refused */

typedef enum ptype { P_NONE = 0, P_I8, P_U8, P_I16, P_U16, P_I32, P_U32, P_F32, P_F64 } ptype;

typedef struct pprop {
  ptype type;
  ptype count_type; /* P_NONE unless a list */
  char name[32];
} pprop;

typedef struct pelem {
  char name[32];
  size_t count;
  pprop props[MAXPROPS];
  int nprops;
} pelem;

typedef struct ply {
  const char *name;
  int format; /* 0 ascii, 1 little endian, 2 big endian */
  pelem elems[MAXELEMS];
  int nelems;
  size_t data; /* byte offset where the body starts */
  bsfit__cursor cur;
  size_t nvert; /* vertices declared */
  bsfit_status *st;
} ply;

static const struct {
  const char *name;
  ptype t;
  size_t size;
} types[] = {
    {"char", P_I8, 1},   {"int8", P_I8, 1},     {"uchar", P_U8, 1},   {"uint8", P_U8, 1},
    {"short", P_I16, 2}, {"int16", P_I16, 2},   {"ushort", P_U16, 2}, {"uint16", P_U16, 2},
    {"int", P_I32, 4},   {"int32", P_I32, 4},   {"uint", P_U32, 4},   {"uint32", P_U32, 4},
    {"float", P_F32, 4}, {"float32", P_F32, 4}, {"double", P_F64, 8}, {"float64", P_F64, 8}};

static ptype type_of(const char *s) {
  size_t i;
  for (i = 0; i < sizeof types / sizeof types[0]; i++)
    if (strcmp(s, types[i].name) == 0) return types[i].t;
  return P_NONE;
}

static size_t size_of(ptype t) {
  static const size_t sz[] = {0, 1, 1, 2, 2, 4, 4, 4, 8};
  return sz[t];
}

/* {======================================================================
** Header
** ====================================================================== */

/* Splits one header line (at most 255 bytes) into up to 6 words. */
static int header_words(ply *p, char line[256], char *w[6]) {
  int n = 0;
  char *s = line;
  size_t k = 0;
  while (p->cur.pos < p->cur.len && p->cur.s[p->cur.pos] != '\n') {
    if (k < 255) line[k++] = p->cur.s[p->cur.pos];
    p->cur.pos++;
  }
  if (p->cur.pos >= p->cur.len) return -1; /* no newline: the header is cut */
  p->cur.pos++;
  p->cur.line++;
  line[k] = '\0';
  while (*s != '\0' && n < 6) {
    while (*s == ' ' || *s == '\t' || *s == '\r') *s++ = '\0';
    if (*s == '\0') break;
    w[n++] = s;
    while (*s != '\0' && *s != ' ' && *s != '\t' && *s != '\r') s++;
  }
  return n;
}

static bsfit_err header_fail(ply *p, const char *what) {
  return bsfit__fail(p->st, BSFIT_EFORMAT, "%s:%zu: %s", p->name, p->cur.line - 1, what);
}

static bsfit_err header_property(ply *p, char *w[6], int n) {
  pelem *e;
  pprop *q;
  if (p->nelems == 0) return header_fail(p, "property before any element");
  e = &p->elems[p->nelems - 1];
  if (e->nprops == MAXPROPS) return header_fail(p, "too many properties");
  q = &e->props[e->nprops];
  memset(q, 0, sizeof *q);
  if (n == 5 && strcmp(w[1], "list") == 0) {
    q->count_type = type_of(w[2]);
    q->type = type_of(w[3]);
    if (q->count_type == P_NONE || q->type == P_NONE || q->count_type >= P_F32)
      return header_fail(p, "bad list property types");
    snprintf(q->name, sizeof q->name, "%s", w[4]);
  } else if (n == 3) {
    q->type = type_of(w[1]);
    if (q->type == P_NONE) return header_fail(p, "unknown property type");
    snprintf(q->name, sizeof q->name, "%s", w[2]);
  } else {
    return header_fail(p, "malformed property line");
  }
  e->nprops++;
  return BSFIT_OK;
}

static bsfit_err header_element(ply *p, char *w[6], int n) {
  pelem *e;
  char *end;
  double c;
  if (n != 3) return header_fail(p, "malformed element line");
  if (p->nelems == MAXELEMS) return header_fail(p, "too many elements");
  c = strtod(w[2], &end);
  if (*end != '\0' || !(c >= 0) || c != floor(c) || c > 4.0e15)
    return header_fail(p, "bad element count");
  e = &p->elems[p->nelems++];
  memset(e, 0, sizeof *e);
  snprintf(e->name, sizeof e->name, "%s", w[1]);
  e->count = (size_t)c;
  return BSFIT_OK;
}

static bsfit_err header_line(ply *p, char *w[6], int n, int *done) {
  if (n == 0 || strcmp(w[0], "comment") == 0 || strcmp(w[0], "obj_info") == 0) return BSFIT_OK;
  if (strcmp(w[0], "end_header") == 0) {
    *done = 1;
    return BSFIT_OK;
  }
  if (strcmp(w[0], "format") == 0) {
    if (n != 3) return header_fail(p, "malformed format line");
    if (strcmp(w[1], "ascii") == 0)
      p->format = 0;
    else if (strcmp(w[1], "binary_little_endian") == 0)
      p->format = 1;
    else if (strcmp(w[1], "binary_big_endian") == 0)
      p->format = 2;
    else
      return header_fail(p, "unknown format");
    return BSFIT_OK;
  }
  if (strcmp(w[0], "element") == 0) return header_element(p, w, n);
  if (strcmp(w[0], "property") == 0) return header_property(p, w, n);
  return header_fail(p, "unknown header keyword");
}

static bsfit_err read_header(ply *p) {
  char line[256], *w[6];
  int n, done = 0, saw_format = 0;
  bsfit_err e;
  n = header_words(p, line, w);
  if (n != 1 || strcmp(w[0], "ply") != 0)
    return bsfit__fail(p->st, BSFIT_EFORMAT, "%s:1: not a PLY file (no 'ply' line)", p->name);
  while (!done) {
    n = header_words(p, line, w);
    if (n < 0)
      return bsfit__fail(p->st, BSFIT_EFORMAT, "%s: truncated header (no end_header)", p->name);
    if (n > 0 && strcmp(w[0], "format") == 0) saw_format = 1;
    e = header_line(p, w, n, &done);
    if (e != BSFIT_OK) return e;
  }
  if (!saw_format) return bsfit__fail(p->st, BSFIT_EFORMAT, "%s: no format line", p->name);
  p->data = p->cur.pos;
  return BSFIT_OK;
}

/* }====================================================================== */

/* {======================================================================
** Body: the roles of properties, and one value at a time
** ====================================================================== */

/* What a property is for. */
enum { R_SKIP = 0, R_X, R_Y, R_Z, R_FACE };

static int role_of(const pelem *e, const pprop *q) {
  if (strcmp(e->name, "vertex") == 0 && q->count_type == P_NONE) {
    if (strcmp(q->name, "x") == 0) return R_X;
    if (strcmp(q->name, "y") == 0) return R_Y;
    if (strcmp(q->name, "z") == 0) return R_Z;
  }
  if (strcmp(e->name, "face") == 0 && q->count_type != P_NONE &&
      (strcmp(q->name, "vertex_indices") == 0 || strcmp(q->name, "vertex_index") == 0))
    return R_FACE;
  return R_SKIP;
}

/* Decodes a binary value of type t at b (endianness per p->format). */
static double decode(const ply *p, const unsigned char *b, ptype t) {
  unsigned char v[8];
  size_t k, n = size_of(t);
  int8_t i8;
  int16_t i16;
  uint16_t u16;
  int32_t i32;
  uint32_t u32;
  float f;
  double d;
  int swap = (p->format == 2) != (*(const unsigned char *)&(const uint16_t){1} == 0);
  for (k = 0; k < n; k++) v[k] = swap ? b[n - 1 - k] : b[k];
  switch (t) {
    case P_I8:
      memcpy(&i8, v, 1);
      return i8;
    case P_U8:
      return v[0];
    case P_I16:
      memcpy(&i16, v, 2);
      return i16;
    case P_U16:
      memcpy(&u16, v, 2);
      return u16;
    case P_I32:
      memcpy(&i32, v, 4);
      return i32;
    case P_U32:
      memcpy(&u32, v, 4);
      return u32;
    case P_F32:
      memcpy(&f, v, 4);
      return f;
    default:
      memcpy(&d, v, 8);
      return d;
  }
}

/* Where a value is, for messages. */
static void where(const ply *p, const pelem *e, size_t i, char *buf, size_t cap) {
  if (p->format == 0)
    snprintf(buf, cap, "%s:%zu: %s %zu", p->name, p->cur.line, e->name, i + 1);
  else
    snprintf(buf, cap, "%s: %s %zu (byte %zu)", p->name, e->name, i + 1, p->cur.pos);
}

/* The next value of type t; 0 with the error set when missing or malformed. */
static int next_value(ply *p, const pelem *e, size_t i, ptype t, double *x, bsfit_err *err) {
  char loc[200];
  if (p->format == 0) {
    if (bsfit__cur_number(&p->cur, x)) return 1;
    where(p, e, i, loc, sizeof loc);
    *err = bsfit__fail(p->st, BSFIT_EFORMAT, "%s: %s", loc,
                       p->cur.pos >= p->cur.len ? "truncated (the file ends)" : "not a number");
    return 0;
  }
  if (p->cur.len - p->cur.pos < size_of(t)) {
    where(p, e, i, loc, sizeof loc);
    *err = bsfit__fail(p->st, BSFIT_EFORMAT, "%s: truncated (the file ends)", loc);
    return 0;
  }
  *x = decode(p, (const unsigned char *)p->cur.s + p->cur.pos, t);
  p->cur.pos += size_of(t);
  return 1;
}

/* }====================================================================== */

/* {======================================================================
** Body: elements
** ====================================================================== */

static bsfit_err bad_count(ply *p, const pelem *e, size_t i, const char *what) {
  char loc[200];
  where(p, e, i, loc, sizeof loc);
  return bsfit__fail(p->st, BSFIT_EFORMAT, "%s: %s", loc, what);
}

/* A face's index list: checked, then split into a fan of triangles. */
static bsfit_err read_face(ply *p, const pelem *e, size_t i, const pprop *q, int keep,
                           bsfit__scanbuild *b) {
  double c, x;
  uint32_t idx[MAXPOLY];
  size_t k, n;
  bsfit_err err = BSFIT_OK;
  if (!next_value(p, e, i, q->count_type, &c, &err)) return err;
  if (!(c >= 0) || c != floor(c) || c > MAXPOLY) return bad_count(p, e, i, "bad list length");
  n = (size_t)c;
  if (keep && n < 3) return bad_count(p, e, i, "a face needs at least 3 vertices");
  for (k = 0; k < n; k++) {
    if (!next_value(p, e, i, q->type, &x, &err)) return err;
    if (!keep) continue;
    if (!(x >= 0 && x < (double)p->nvert) || x != floor(x)) {
      char loc[200];
      where(p, e, i, loc, sizeof loc);
      return bsfit__fail(
          p->st, BSFIT_EFORMAT,
          "%s: vertex index %.17g out of range (0 to %zu, the file has %zu vertices)", loc, x,
          p->nvert - 1, p->nvert);
    }
    idx[k] = (uint32_t)x;
  }
  if (keep) {
    for (k = 1; k + 1 < n; k++) bsfit__sb_tri(b, idx[0], idx[k], idx[k + 1]);
  }
  return BSFIT_OK;
}

/* Reads (or reads past) every instance of one element. */
static bsfit_err read_element(ply *p, const pelem *e, bsfit__scanbuild *b,
                              const bsfit_allocator *a) {
  int roles[MAXPROPS], j, is_vertex = strcmp(e->name, "vertex") == 0, face = -1;
  size_t i;
  double x, xyz[3] = {0, 0, 0};
  bsfit_err err = BSFIT_OK;
  for (j = 0; j < e->nprops; j++) {
    roles[j] = role_of(e, &e->props[j]);
    if (roles[j] == R_FACE && face < 0) face = j; /* only the first index list counts */
  }
  if (is_vertex && !bsfit__sb_reserve(b, e->count, 0))
    return bsfit__fail(p->st, BSFIT_ENOMEM, "%s: out of memory (%zu vertices)", p->name, e->count);
  for (i = 0; i < e->count; i++) {
    if ((i & 0xffff) == 0 && bsfit__interrupted(a))
      return bsfit__fail(p->st, BSFIT_EINTR, "%s: interrupted", p->name);
    for (j = 0; j < e->nprops; j++) {
      const pprop *q = &e->props[j];
      if (q->count_type != P_NONE) {
        err = read_face(p, e, i, q, j == face, b);
        if (err != BSFIT_OK) return err;
        continue;
      }
      if (!next_value(p, e, i, q->type, &x, &err)) return err;
      if (roles[j] >= R_X && roles[j] <= R_Z) xyz[roles[j] - R_X] = x;
    }
    if (is_vertex) bsfit__sb_vertex(b, xyz[0], xyz[1], xyz[2]);
  }
  return BSFIT_OK;
}

/* The vertex element must have x, y and z. */
static bsfit_err check_vertex(ply *p) {
  int k, j, found[3] = {0, 0, 0};
  for (k = 0; k < p->nelems; k++) {
    pelem *e = &p->elems[k];
    if (strcmp(e->name, "vertex") != 0) continue;
    for (j = 0; j < e->nprops; j++) {
      int r = role_of(e, &e->props[j]);
      if (r >= R_X && r <= R_Z) found[r - R_X] = 1;
    }
    p->nvert = e->count;
    if (!found[0] || !found[1] || !found[2])
      return bsfit__fail(p->st, BSFIT_EFORMAT, "%s: the vertex element lacks x, y or z", p->name);
    return BSFIT_OK;
  }
  return bsfit__fail(p->st, BSFIT_EFORMAT, "%s: no vertex element", p->name);
}

bsfit_err bsfit__scan_ply(const char *data, size_t len, bsfit__scanbuild *b, bsfit_status *st) {
  static ply zero;
  ply *p;
  bsfit_err e;
  int k;
  /* the header tables are large: keep them off the stack */
  p = (ply *)bsfit__alloc(&b->a, sizeof *p);
  if (p == NULL) return bsfit__fail(st, BSFIT_ENOMEM, "%s: out of memory", b->name);
  *p = zero;
  p->name = b->name;
  p->st = st;
  p->cur.s = data;
  p->cur.len = len;
  p->cur.line = 1;
  e = read_header(p);
  if (e == BSFIT_OK) e = check_vertex(p);
  for (k = 0; e == BSFIT_OK && k < p->nelems; k++) e = read_element(p, &p->elems[k], b, &b->a);
  if (e == BSFIT_OK && p->format == 0 && bsfit__cur_skip(&p->cur))
    e = bsfit__fail(st, BSFIT_EFORMAT, "%s:%zu: data after the last element", p->name, p->cur.line);
  bsfit__free(&b->a, p, sizeof *p);
  return e;
}

/* }====================================================================== */
