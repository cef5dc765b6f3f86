/*
** io_scan_obj.c
** Wavefront OBJ reader: `v x y z [w]` vertices and `f` faces whose corners are
** `i`, `i/t`, `i//n` or `i/t/n` (1-based; negative counts back from the last vertex
** read), polygons split into fans. Other statements (vt, vn, g, o, s, usemtl, l, ...)
** are ignored. Errors name the file and the line.
*/
#include "scan_internal.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#define MAXPOLY 1024

static bsfit_err obj_fail(const bsfit__cursor *c, const bsfit__scanbuild *b, const char *what,
                          bsfit_status *st) {
  return bsfit__fail(st, BSFIT_EFORMAT, "%s:%zu: %s", b->name, c->line, what);
}

static bsfit_err obj_vertex(bsfit__cursor *c, bsfit__scanbuild *b, bsfit_status *st) {
  double x, y, z;
  if (!bsfit__cur_number(c, &x) || !bsfit__cur_number(c, &y) || !bsfit__cur_number(c, &z))
    return obj_fail(c, b, "a vertex needs 3 numbers", st);
  bsfit__sb_vertex(b, x, y, z);
  return BSFIT_OK;
}

/* One corner "i[/t[/n]]": its 0-based vertex id. */
static bsfit_err obj_corner(const char *tok, const bsfit__cursor *c, bsfit__scanbuild *b,
                            uint32_t *id, bsfit_status *st) {
  char *end;
  long long i = strtoll(tok, &end, 10);
  long long n = (long long)b->nv;
  if (end == tok || (*end != '\0' && *end != '/'))
    return obj_fail(c, b, "a face corner is not a vertex index", st);
  if (i < 0) i += n + 1; /* -1 is the last vertex read */
  if (i < 1 || i > n) {
    return bsfit__fail(st, BSFIT_EFORMAT,
                       "%s:%zu: vertex index %s out of range (%lld vertices read)", b->name,
                       c->line, tok, n);
  }
  *id = (uint32_t)(i - 1);
  return BSFIT_OK;
}

static bsfit_err obj_face(bsfit__cursor *c, bsfit__scanbuild *b, bsfit_status *st) {
  uint32_t id[MAXPOLY];
  size_t n = 0, k, len;
  char tok[96];
  bsfit_err e;
  while (bsfit__cur_skip_inline(c) > 0 && c->s[c->pos] != '\n' && c->s[c->pos] != '#') {
    len = bsfit__cur_token(c, tok, sizeof tok);
    if (len == (size_t)-1) return obj_fail(c, b, "face corner too long", st);
    if (n == MAXPOLY) return obj_fail(c, b, "a face with more than 1024 corners", st);
    e = obj_corner(tok, c, b, &id[n++], st);
    if (e != BSFIT_OK) return e;
  }
  if (n < 3) return obj_fail(c, b, "a face needs at least 3 vertices", st);
  for (k = 1; k + 1 < n; k++) bsfit__sb_tri(b, id[0], id[k], id[k + 1]);
  return BSFIT_OK;
}

bsfit_err bsfit__scan_obj(const char *data, size_t len, bsfit__scanbuild *b, bsfit_status *st) {
  bsfit__cursor c = {data, len, 0, 1};
  bsfit_err e = BSFIT_OK;
  size_t lines = 0;
  while (e == BSFIT_OK && bsfit__cur_skip(&c)) {
    const char *s = c.s + c.pos;
    if (b->failed) return bsfit__fail(st, BSFIT_ENOMEM, "%s: out of memory", b->name);
    size_t left = c.len - c.pos;
    if ((++lines & 0xffff) == 0 && bsfit__interrupted(&b->a))
      return bsfit__fail(st, BSFIT_EINTR, "%s: interrupted", b->name);
    if (left >= 2 && s[0] == 'v' && (s[1] == ' ' || s[1] == '\t')) {
      c.pos += 2;
      e = obj_vertex(&c, b, st);
    } else if (left >= 2 && s[0] == 'f' && (s[1] == ' ' || s[1] == '\t')) {
      c.pos += 2;
      e = obj_face(&c, b, st);
      continue; /* obj_face stopped at the end of its line */
    }
    if (e == BSFIT_OK) bsfit__cur_next_line(&c);
  }
  if (e == BSFIT_OK && b->failed)
    return bsfit__fail(st, BSFIT_ENOMEM, "%s: out of memory", b->name);
  return e;
}
