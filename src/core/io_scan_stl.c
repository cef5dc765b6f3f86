/*
** io_scan_stl.c
** STL reader, ASCII and binary. STL stores every triangle with its own three corners;
** corners with identical coordinates (bit for bit, -0 = +0) are merged into one vertex
** through a hash table, so that neighbouring triangles share vertex ids and the slicer
** chains them by ids. Binary is recognised by its size (84 + 50 n bytes); a file that
** starts with "solid" and has another size is read as ASCII.
*/
#include "scan_internal.h"

#include <ctype.h>
#include <stdio.h>
#include <string.h>
#include <strings.h>

/* {======================================================================
** Merging identical corners
** ====================================================================== */

typedef struct vmerge {
  uint32_t *slot; /* vertex id + 1, 0 = empty */
  size_t mask;
  bsfit__scanbuild *b;
} vmerge;

static uint64_t bits_of(double x) {
  uint64_t u;
  if (x == 0) x = 0; /* -0 and +0 are one coordinate */
  memcpy(&u, &x, sizeof u);
  return u;
}

static size_t hash3(const double *v) {
  uint64_t h = bits_of(v[0]) * 0x9E3779B97F4A7C15ull;
  h ^= bits_of(v[1]) + 0x7F4A7C159E3779B9ull + (h << 6) + (h >> 2);
  h ^= bits_of(v[2]) * 0xC2B2AE3D27D4EB4Full + (h << 6) + (h >> 2);
  h ^= h >> 29;
  return (size_t)h;
}

static bsfit_err vm_init(vmerge *v, bsfit__scanbuild *b, size_t corners, bsfit_status *st) {
  size_t n = 1024, bytes;
  while (n < 2 * corners && n < ((size_t)1 << 40)) n *= 2;
  bytes = bsfit__mulsize(n, sizeof(uint32_t));
  v->b = b;
  v->mask = n - 1;
  v->slot = bytes ? (uint32_t *)bsfit__alloc(&b->a, bytes) : NULL;
  if (v->slot == NULL) return bsfit__fail(st, BSFIT_ENOMEM, "%s: out of memory", b->name);
  memset(v->slot, 0, bytes);
  return BSFIT_OK;
}

static void vm_free(vmerge *v) {
  bsfit__free(&v->b->a, v->slot, (v->mask + 1) * sizeof(uint32_t));
}

/* The id of the vertex at p, added when new; UINT32_MAX when out of room. */
static uint32_t vm_id(vmerge *v, const double *p) {
  size_t h = hash3(p) & v->mask;
  bsfit__scanbuild *b = v->b;
  while (v->slot[h] != 0) {
    const double *q = b->xyz + 3 * (size_t)(v->slot[h] - 1);
    if (bits_of(q[0]) == bits_of(p[0]) && bits_of(q[1]) == bits_of(p[1]) &&
        bits_of(q[2]) == bits_of(p[2]))
      return v->slot[h] - 1;
    h = (h + 1) & v->mask;
  }
  if (b->nv >= v->mask / 2 || b->nv >= UINT32_MAX - 1) return UINT32_MAX;
  bsfit__sb_vertex(b, p[0], p[1], p[2]);
  if (b->failed) return UINT32_MAX;
  v->slot[h] = (uint32_t)b->nv;
  return (uint32_t)(b->nv - 1);
}

/* Adds a triangle of three corners (9 doubles). */
static int vm_triangle(vmerge *v, const double *c) {
  uint32_t id[3];
  int k;
  for (k = 0; k < 3; k++) {
    id[k] = vm_id(v, c + 3 * k);
    if (id[k] == UINT32_MAX) return 0;
  }
  bsfit__sb_tri(v->b, id[0], id[1], id[2]);
  return !v->b->failed;
}

/* }====================================================================== */

/* {======================================================================
** Binary
** ====================================================================== */

static float le_float(const unsigned char *p) {
  uint32_t u = (uint32_t)p[0] | (uint32_t)p[1] << 8 | (uint32_t)p[2] << 16 | (uint32_t)p[3] << 24;
  float f;
  memcpy(&f, &u, 4);
  return f;
}

static bsfit_err read_binary(const unsigned char *d, size_t len, bsfit__scanbuild *b,
                             bsfit_status *st) {
  size_t n, i, k;
  vmerge v;
  double c[9];
  bsfit_err e;
  if (len < 84)
    return bsfit__fail(st, BSFIT_EFORMAT,
                       "%s: truncated binary STL (%zu bytes; the header alone has 84)", b->name,
                       len);
  n = (size_t)d[80] | (size_t)d[81] << 8 | (size_t)d[82] << 16 | (size_t)d[83] << 24;
  if ((len - 84) / 50 != n || (len - 84) % 50 != 0)
    return bsfit__fail(st, BSFIT_EFORMAT,
                       "%s: binary STL of %zu triangles needs %zu bytes, the file has %zu "
                       "(truncated or not an STL)",
                       b->name, n, 84 + 50 * n, len);
  if (!bsfit__sb_reserve(b, n / 2 + 3, n))
    return bsfit__fail(st, BSFIT_ENOMEM, "%s: out of memory", b->name);
  e = vm_init(&v, b, 3 * n, st);
  if (e != BSFIT_OK) return e;
  for (i = 0; i < n; i++) {
    const unsigned char *t = d + 84 + 50 * i + 12; /* skip the normal */
    if ((i & 0xffff) == 0 && bsfit__interrupted(&b->a)) {
      vm_free(&v);
      return bsfit__fail(st, BSFIT_EINTR, "%s: interrupted", b->name);
    }
    for (k = 0; k < 9; k++) c[k] = le_float(t + 4 * k);
    if (!vm_triangle(&v, c)) break;
  }
  vm_free(&v);
  if (i < n) return bsfit__fail(st, BSFIT_ENOMEM, "%s: out of memory", b->name);
  return BSFIT_OK;
}

/* }====================================================================== */

/* {======================================================================
** ASCII
** ====================================================================== */

static bsfit_err ascii_fail(bsfit__cursor *c, bsfit__scanbuild *b, size_t facet, const char *what,
                            bsfit_status *st) {
  if (c->pos >= c->len)
    return bsfit__fail(st, BSFIT_EFORMAT, "%s:%zu: facet %zu: truncated (the file ends; %s)",
                       b->name, c->line, facet, what);
  return bsfit__fail(st, BSFIT_EFORMAT, "%s:%zu: facet %zu: %s", b->name, c->line, facet, what);
}

/* The next token must be word (case-insensitive). */
static int expect(bsfit__cursor *c, const char *word) {
  char buf[32];
  size_t n = bsfit__cur_token(c, buf, sizeof buf);
  return n != 0 && n != (size_t)-1 && strcasecmp(buf, word) == 0;
}

/* One facet after its "facet" word. */
static bsfit_err ascii_facet(bsfit__cursor *c, vmerge *v, size_t f, bsfit_status *st) {
  double c9[9], nrm;
  int k;
  if (!expect(c, "normal")) return ascii_fail(c, v->b, f, "expected 'normal'", st);
  for (k = 0; k < 3; k++)
    if (!bsfit__cur_number(c, &nrm)) return ascii_fail(c, v->b, f, "bad normal", st);
  if (!expect(c, "outer") || !expect(c, "loop"))
    return ascii_fail(c, v->b, f, "expected 'outer loop'", st);
  for (k = 0; k < 3; k++) {
    if (!expect(c, "vertex")) return ascii_fail(c, v->b, f, "expected 'vertex' (3 per facet)", st);
    if (!bsfit__cur_number(c, &c9[3 * k]) || !bsfit__cur_number(c, &c9[3 * k + 1]) ||
        !bsfit__cur_number(c, &c9[3 * k + 2]))
      return ascii_fail(c, v->b, f, "a vertex needs 3 numbers", st);
  }
  if (!expect(c, "endloop")) return ascii_fail(c, v->b, f, "expected 'endloop'", st);
  if (!expect(c, "endfacet")) return ascii_fail(c, v->b, f, "expected 'endfacet'", st);
  if (!vm_triangle(v, c9)) return bsfit__fail(st, BSFIT_ENOMEM, "%s: out of memory", v->b->name);
  return BSFIT_OK;
}

static bsfit_err read_ascii(const char *d, size_t len, bsfit__scanbuild *b, bsfit_status *st) {
  bsfit__cursor c = {d, len, 0, 1};
  char word[32];
  size_t f = 0, n;
  vmerge v;
  bsfit_err e;
  bsfit__cur_next_line(&c);              /* "solid name" */
  e = vm_init(&v, b, len / 40 + 16, st); /* an ASCII facet takes well over 40*3 bytes */
  if (e != BSFIT_OK) return e;
  for (;;) {
    n = bsfit__cur_token(&c, word, sizeof word);
    if (n == 0) {
      e = ascii_fail(&c, b, f + 1, "expected 'facet' or 'endsolid'", st);
      break;
    }
    if (n != (size_t)-1 && strcasecmp(word, "endsolid") == 0) break;
    if (n == (size_t)-1 || strcasecmp(word, "facet") != 0) {
      e = ascii_fail(&c, b, f + 1, "expected 'facet' or 'endsolid'", st);
      break;
    }
    e = ascii_facet(&c, &v, ++f, st);
    if (e != BSFIT_OK) break;
  }
  vm_free(&v);
  return e;
}

/* }====================================================================== */

/* ASCII when the file starts with "solid", is not exactly a binary STL's size, and its
** first bytes are text. */
static int is_ascii(const char *d, size_t len) {
  size_t i, n = len < 512 ? len : 512;
  if (len < 5 || strncasecmp(d, "solid", 5) != 0) return 0;
  if (len >= 84) {
    const unsigned char *u = (const unsigned char *)d;
    size_t t = (size_t)u[80] | (size_t)u[81] << 8 | (size_t)u[82] << 16 | (size_t)u[83] << 24;
    if ((len - 84) % 50 == 0 && (len - 84) / 50 == t) return 0;
  }
  for (i = 0; i < n; i++) {
    unsigned char ch = (unsigned char)d[i];
    if (ch < 9 || (ch > 13 && ch < 32) || ch > 126) return 0;
  }
  return 1;
}

bsfit_err bsfit__scan_stl(const char *data, size_t len, bsfit__scanbuild *b, bsfit_status *st) {
  bsfit_err e;
  if (is_ascii(data, len))
    e = read_ascii(data, len, b, st);
  else
    e = read_binary((const unsigned char *)data, len, b, st);
  if (e == BSFIT_OK && b->nt == 0)
    return bsfit__fail(st, BSFIT_ETOOFEW, "%s: no triangles", b->name);
  return e;
}
