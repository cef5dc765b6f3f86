/*
** io_scan.c
** Reading scans: the bsfit_scan object, the builder the format readers fill, the text
** cursor of the ASCII readers, and the dispatch by format (the XYZ/CSV cloud reader is
** the point-file parser of io_points.c).
*/
#include "io_internal.h"
#include "scan_internal.h"

#include <ctype.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

/* {======================================================================
** The scan object and its builder
** ====================================================================== */

void bsfit_scan_init(bsfit_scan *s) {
  if (s != NULL) memset(s, 0, sizeof *s);
}

void bsfit_scan_free(bsfit_scan *s) {
  if (s == NULL) return;
  bsfit__free(&s->alloc, s->xyz, s->nv * 3 * sizeof(double));
  bsfit__free(&s->alloc, s->tri, s->nt * 3 * sizeof(uint32_t));
  s->xyz = NULL;
  s->tri = NULL;
  s->nv = s->nt = 0;
}

void bsfit__sb_init(bsfit__scanbuild *b, const char *name, const bsfit_allocator *a) {
  memset(b, 0, sizeof *b);
  b->name = name ? name : "<scan>";
  if (a != NULL) b->a = *a;
}

void bsfit__sb_free(bsfit__scanbuild *b) {
  bsfit__free(&b->a, b->xyz, b->capv * 3 * sizeof(double));
  bsfit__free(&b->a, b->tri, b->capt * 3 * sizeof(uint32_t));
  b->xyz = NULL;
  b->tri = NULL;
  b->nv = b->nt = b->capv = b->capt = 0;
}

/* Grows an array of cap*unit bytes to hold need*unit (doubling); 0 on failure. */
static int grow(bsfit__scanbuild *b, void **p, size_t *cap, size_t need, size_t unit) {
  size_t nc = *cap ? *cap : 1024;
  void *q;
  if (need <= *cap) return 1;
  while (nc < need) {
    if (nc > ((size_t)-1) / 2 / unit) return 0;
    nc *= 2;
  }
  q = bsfit__realloc(&b->a, *p, *cap * unit, nc * unit);
  if (q == NULL) return 0;
  *p = q;
  *cap = nc;
  return 1;
}

int bsfit__sb_reserve(bsfit__scanbuild *b, size_t nv, size_t nt) {
  if (b->failed) return 0;
  if (nv > ((size_t)-1) / 2 - b->nv || nt > ((size_t)-1) / 2 - b->nt ||
      !grow(b, (void **)&b->xyz, &b->capv, b->nv + nv, 3 * sizeof(double)) ||
      !grow(b, (void **)&b->tri, &b->capt, b->nt + nt, 3 * sizeof(uint32_t)))
    b->failed = 1;
  return !b->failed;
}

void bsfit__sb_vertex(bsfit__scanbuild *b, double x, double y, double z) {
  double *p;
  if (b->nv == b->capv && !bsfit__sb_reserve(b, 1, 0)) return;
  p = b->xyz + 3 * b->nv++;
  p[0] = x;
  p[1] = y;
  p[2] = z;
}

void bsfit__sb_tri(bsfit__scanbuild *b, uint32_t i, uint32_t j, uint32_t k) {
  uint32_t *t;
  if (b->nt == b->capt && !bsfit__sb_reserve(b, 0, 1)) return;
  t = b->tri + 3 * b->nt++;
  t[0] = i;
  t[1] = j;
  t[2] = k;
}

/* Shrinks an array from cap to n units (keeps it when shrinking fails). */
static void *shrink(bsfit__scanbuild *b, void *p, size_t cap, size_t n, size_t unit) {
  void *q;
  if (p == NULL || n == cap) return p;
  if (n == 0) {
    bsfit__free(&b->a, p, cap * unit);
    return NULL;
  }
  q = bsfit__realloc(&b->a, p, cap * unit, n * unit);
  return q ? q : NULL;
}

bsfit_err bsfit__sb_finish(bsfit__scanbuild *b, bsfit_scan *s, bsfit_status *st) {
  size_t i;
  void *q;
  if (b->failed) return bsfit__fail(st, BSFIT_ENOMEM, "%s: out of memory", b->name);
  if (b->nv == 0) return bsfit__fail(st, BSFIT_ETOOFEW, "%s: no vertices", b->name);
  if (b->nv > UINT32_MAX)
    return bsfit__fail(st, BSFIT_EINVAL, "%s: more than 2^32-1 vertices", b->name);
  for (i = 0; i < b->nv; i++)
    if (!isfinite(b->xyz[3 * i]) || !isfinite(b->xyz[3 * i + 1]) || !isfinite(b->xyz[3 * i + 2]))
      return bsfit__fail(st, BSFIT_ENONFINITE, "%s: vertex %zu has a non-finite coordinate",
                         b->name, i + 1);
  bsfit_scan_free(s);
  /* a failed shrink keeps the larger block: record its true size */
  q = shrink(b, b->xyz, b->capv, b->nv, 3 * sizeof(double));
  if (q != NULL) b->xyz = q, b->capv = b->nv;
  q = shrink(b, b->tri, b->capt, b->nt, 3 * sizeof(uint32_t));
  if (q != NULL || b->nt == 0) b->tri = q, b->capt = b->nt;
  if (b->capv != b->nv || b->capt != b->nt)
    return bsfit__fail(st, BSFIT_ENOMEM, "%s: out of memory", b->name);
  s->xyz = b->xyz;
  s->nv = b->nv;
  s->tri = b->tri;
  s->nt = b->nt;
  s->alloc = b->a;
  b->xyz = NULL;
  b->tri = NULL;
  b->nv = b->nt = b->capv = b->capt = 0;
  return bsfit__ok(st);
}

/* }====================================================================== */

/* {======================================================================
** Text cursor
** ====================================================================== */

int bsfit__cur_skip(bsfit__cursor *c) {
  while (c->pos < c->len) {
    char ch = c->s[c->pos];
    if (ch == '\n')
      c->line++;
    else if (ch != ' ' && ch != '\t' && ch != '\r' && ch != '\f' && ch != '\v')
      return 1;
    c->pos++;
  }
  return 0;
}

int bsfit__cur_skip_inline(bsfit__cursor *c) {
  while (c->pos < c->len) {
    char ch = c->s[c->pos];
    if (ch != ' ' && ch != '\t' && ch != '\r' && ch != '\f' && ch != '\v') return (unsigned char)ch;
    c->pos++;
  }
  return -1;
}

size_t bsfit__cur_token(bsfit__cursor *c, char *buf, size_t cap) {
  size_t n = 0;
  if (!bsfit__cur_skip(c)) return 0;
  while (c->pos < c->len && !isspace((unsigned char)c->s[c->pos])) {
    if (n + 1 >= cap) return (size_t)-1;
    buf[n++] = c->s[c->pos++];
  }
  buf[n] = '\0';
  return n;
}

/* Clinger's fast path: a decimal of at most 15 significant digits times 10^e, |e| <= 22,
** is one exact integer times (or over) one exact power of ten, so a single rounding gives
** the correctly rounded double, as strtod would. Returns 0 when the token is not of that
** simple form (then strtod decides). */
static int fast_number(const char *s, double *x) {
  static const double p10[] = {1e0,  1e1,  1e2,  1e3,  1e4,  1e5,  1e6,  1e7,
                               1e8,  1e9,  1e10, 1e11, 1e12, 1e13, 1e14, 1e15,
                               1e16, 1e17, 1e18, 1e19, 1e20, 1e21, 1e22};
  uint64_t mant = 0;
  int neg = 0, digits = 0, any = 0, e = 0, ee = 0, eneg = 0;
  if (*s == '-' || *s == '+') neg = *s++ == '-';
  for (; *s >= '0' && *s <= '9'; s++, any = 1) {
    if (mant == 0 && *s == '0') continue; /* leading zeros are not significant */
    if (++digits > 15) return 0;
    mant = mant * 10 + (uint64_t)(*s - '0');
  }
  if (*s == '.') {
    for (s++; *s >= '0' && *s <= '9'; s++, any = 1) {
      e--;
      if (mant == 0 && *s == '0') continue;
      if (++digits > 15) return 0;
      mant = mant * 10 + (uint64_t)(*s - '0');
    }
  }
  if (!any) return 0;
  if (*s == 'e' || *s == 'E') {
    s++;
    if (*s == '-' || *s == '+') eneg = *s++ == '-';
    if (!(*s >= '0' && *s <= '9')) return 0;
    for (; *s >= '0' && *s <= '9'; s++)
      if ((ee = ee * 10 + (*s - '0')) > 400) return 0;
    e += eneg ? -ee : ee;
  }
  if (*s != '\0' || e < -22 || e > 22) return 0;
  *x = e < 0 ? (double)mant / p10[-e] : (double)mant * p10[e];
  if (neg) *x = -*x;
  return 1;
}

int bsfit__cur_number(bsfit__cursor *c, double *x) {
  char buf[80], *end;
  size_t n = bsfit__cur_token(c, buf, sizeof buf);
  if (n == 0 || n == (size_t)-1) return 0;
  if (fast_number(buf, x)) return 1;
  *x = strtod(buf, &end);
  return *end == '\0';
}

void bsfit__cur_next_line(bsfit__cursor *c) {
  while (c->pos < c->len && c->s[c->pos] != '\n') c->pos++;
  if (c->pos < c->len) {
    c->pos++;
    c->line++;
  }
}

/* }====================================================================== */

/* {======================================================================
** Dispatch
** ====================================================================== */

static bsfit_err parse_xyz(const char *data, size_t len, bsfit__scanbuild *b, bsfit_status *st) {
  double *xy = NULL;
  size_t m = 0;
  int dim = 0;
  bsfit_err e = bsfit_points_parse(data, len, &xy, &m, &dim, NULL, &b->a, st);
  if (e != BSFIT_OK) {
    if (st != NULL) {
      char msg[BSFIT_STATUS_MSG_SIZE];
      memcpy(msg, st->msg, sizeof msg);
      bsfit__fail(st, e, "%s: %s", b->name, msg);
    }
    return e;
  }
  if (dim != 3) {
    bsfit_points_free(xy, m, dim, NULL, &b->a);
    return bsfit__fail(st, BSFIT_EFORMAT, "%s: a cloud needs x, y and z columns", b->name);
  }
  b->xyz = xy;
  b->nv = b->capv = m;
  return BSFIT_OK;
}

bsfit_err bsfit_scan_parse(const char *data, size_t len, bsfit_scan_format fmt, const char *name,
                           bsfit_scan *s, const bsfit_allocator *a, bsfit_status *st) {
  bsfit__scanbuild b;
  bsfit_err e;
  if (s == NULL || (data == NULL && len > 0))
    return bsfit__fail(st, BSFIT_EINVAL, "bsfit_scan_parse: NULL argument");
  bsfit__sb_init(&b, name, a);
  switch (fmt) {
    case BSFIT_SCAN_PLY:
      e = bsfit__scan_ply(data, len, &b, st);
      break;
    case BSFIT_SCAN_STL:
      e = bsfit__scan_stl(data, len, &b, st);
      break;
    case BSFIT_SCAN_OBJ:
      e = bsfit__scan_obj(data, len, &b, st);
      break;
    case BSFIT_SCAN_XYZ:
      e = parse_xyz(data, len, &b, st);
      break;
    default:
      e = bsfit__fail(st, BSFIT_EINVAL, "%s: unknown scan format %d", b.name, (int)fmt);
  }
  if (e == BSFIT_OK) e = bsfit__sb_finish(&b, s, st);
  bsfit__sb_free(&b);
  return e;
}

/* The format named by a file's extension, or AUTO when it names none. */
static bsfit_scan_format format_of(const char *path) {
  static const struct {
    const char *ext;
    bsfit_scan_format f;
  } map[] = {{"ply", BSFIT_SCAN_PLY}, {"stl", BSFIT_SCAN_STL}, {"obj", BSFIT_SCAN_OBJ},
             {"xyz", BSFIT_SCAN_XYZ}, {"csv", BSFIT_SCAN_XYZ}, {"txt", BSFIT_SCAN_XYZ},
             {"pts", BSFIT_SCAN_XYZ}, {"asc", BSFIT_SCAN_XYZ}};
  const char *dot = strrchr(path, '.');
  size_t i, k;
  char ext[8];
  if (dot == NULL || strchr(dot, '/') != NULL || strlen(dot + 1) >= sizeof ext)
    return BSFIT_SCAN_AUTO;
  for (k = 0; dot[1 + k] != '\0'; k++) ext[k] = (char)tolower((unsigned char)dot[1 + k]);
  ext[k] = '\0';
  for (i = 0; i < sizeof map / sizeof map[0]; i++)
    if (strcmp(ext, map[i].ext) == 0) return map[i].f;
  return BSFIT_SCAN_AUTO;
}

bsfit_err bsfit_scan_read(const char *path, bsfit_scan_format fmt, bsfit_scan *s,
                          const bsfit_allocator *a, bsfit_status *st) {
  bsfit__buf buf;
  bsfit_err e;
  if (path == NULL || s == NULL)
    return bsfit__fail(st, BSFIT_EINVAL, "bsfit_scan_read: NULL argument");
  if (fmt == BSFIT_SCAN_AUTO) fmt = format_of(path);
  if (fmt == BSFIT_SCAN_AUTO)
    return bsfit__fail(st, BSFIT_EINVAL,
                       "%s: unknown scan format (.ply, .stl, .obj, .xyz, .csv, .txt, .pts, .asc)",
                       path);
  bsfit__buf_init(&buf, a);
  e = bsfit__read_file(path, &buf, st);
  if (e == BSFIT_OK) e = bsfit_scan_parse(buf.data, buf.len, fmt, path, s, a, st);
  bsfit__buf_free(&buf);
  return e;
}

/* }====================================================================== */
