/*
** io_points.c
** Point files (docs/formats.md): CSV / semicolon / whitespace text with '#' comments
** and an optional header naming the columns x, y, z, w; and the CSV writer.
*/
#include "io_internal.h"

#include <ctype.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

enum { COL_X, COL_Y, COL_Z, COL_W, NCOLS };
#define MAX_FIELDS 8 /* more than 4 is already an error; keep counting a little for the message */

typedef struct field {
  const char *p;
  size_t n;
} field;

typedef struct reader {
  const char *name; /* file name for messages, or NULL */
  size_t line;
  int ncol;         /* fields per row; 0 until the header or the first row fixes it */
  int col[NCOLS];   /* field index of x, y, z, w, or -1 */
  int dim;
  double *xy, *w;
  size_t m, cap_xy, cap_w; /* rows held and rows allocated */
  const bsfit_allocator *a;
} reader;

/* {====================================================================
** Messages and storage
** ===================================================================== */

static bsfit_err fail_at(reader *r, bsfit_status *st, bsfit_err code, const char *what,
                         const field *f) {
  char q[48]; /* the field quoted, at most 40 bytes, non-ASCII and control bytes as '?' */
  size_t i, n = f ? (f->n > 40 ? 40 : f->n) : 0;
  q[0] = '\0';
  if (f) {
    q[0] = ' ';
    q[1] = '\'';
    for (i = 0; i < n; i++) {
      unsigned char c = (unsigned char)f->p[i];
      q[2 + i] = (c < 0x20 || c >= 0x7f) ? '?' : (char)c;
    }
    q[2 + n] = '\'';
    q[3 + n] = '\0';
  }
  if (r->name) return bsfit__fail(st, code, "%s:%zu: %s%s", r->name, r->line, what, q);
  return bsfit__fail(st, code, "line %zu: %s%s", r->line, what, q);
}

static void release(reader *r) {
  bsfit__free(r->a, r->xy, r->cap_xy * (size_t)r->dim * sizeof(double));
  bsfit__free(r->a, r->w, r->cap_w * sizeof(double));
  r->xy = r->w = NULL;
  r->cap_xy = r->cap_w = r->m = 0;
}

/* Resizes one array from *cap to ncap rows of `row` doubles; 1 on success. */
static int resize(const bsfit_allocator *a, double **p, size_t *cap, size_t ncap, size_t row) {
  double *q;
  if (bsfit__mulsize(ncap, row * sizeof(double)) == 0 && ncap != 0) return 0;
  q = bsfit__realloc(a, *p, *cap * row * sizeof(double), ncap * row * sizeof(double));
  if (q == NULL && ncap != 0) return 0;
  *p = q;
  *cap = ncap;
  return 1;
}

/* Room for one more row (amortised doubling). */
static int grow(reader *r) {
  size_t ncap = r->cap_xy ? 2 * r->cap_xy : 64;
  if (r->m < r->cap_xy) return 1;
  if (!resize(r->a, &r->xy, &r->cap_xy, ncap, (size_t)r->dim)) return 0;
  return r->col[COL_W] < 0 || resize(r->a, &r->w, &r->cap_w, ncap, 1);
}

/* Shrinks the arrays to exactly m rows: the caller frees them by that size. */
static int shrink(reader *r) {
  return resize(r->a, &r->xy, &r->cap_xy, r->m, (size_t)r->dim) &&
         (r->w == NULL || resize(r->a, &r->w, &r->cap_w, r->m, 1));
}

/* }==================================================================== */

/* {====================================================================
** Lines and fields
** ===================================================================== */

static int is_blank(char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\v' || c == '\f'; }

static field trim(const char *p, size_t n) {
  field f;
  while (n > 0 && is_blank(*p)) p++, n--;
  while (n > 0 && is_blank(p[n - 1])) n--;
  f.p = p;
  f.n = n;
  return f;
}

/* Splits a comment-free, trimmed, non-empty line; returns the number of fields (at
** most MAX_FIELDS are stored, the count goes on). */
static int split(const char *p, size_t n, field *f) {
  char sep = memchr(p, ';', n) ? ';' : memchr(p, ',', n) ? ',' : 0;
  int k = 0;
  size_t i = 0;
  if (sep) {
    size_t start = 0;
    for (i = 0; i <= n; i++)
      if (i == n || p[i] == sep) {
        if (k < MAX_FIELDS) f[k] = trim(p + start, i - start);
        k++;
        start = i + 1;
      }
    return k;
  }
  while (i < n) {
    size_t start;
    while (i < n && is_blank(p[i])) i++;
    if (i == n) break;
    start = i;
    while (i < n && !is_blank(p[i])) i++;
    if (k < MAX_FIELDS) f[k] = trim(p + start, i - start);
    k++;
  }
  return k;
}

/* The whole field must be a number (strtod's syntax); 1 on success. */
static int to_number(const field *f, double *x) {
  char tmp[128], *end;
  if (f->n == 0 || f->n >= sizeof tmp) return 0;
  memcpy(tmp, f->p, f->n);
  tmp[f->n] = '\0';
  *x = strtod(tmp, &end);
  return end == tmp + f->n;
}

static int column_id(const field *f) {
  static const char names[NCOLS] = {'x', 'y', 'z', 'w'};
  field g = *f;
  int i;
  if (g.n >= 2 && g.p[0] == '"' && g.p[g.n - 1] == '"') g = trim(g.p + 1, g.n - 2);
  if (g.n != 1) return -1;
  for (i = 0; i < NCOLS; i++)
    if (tolower((unsigned char)g.p[0]) == names[i]) return i;
  return -1;
}

/* }==================================================================== */

/* {====================================================================
** Header and rows
** ===================================================================== */

static bsfit_err set_layout(reader *r, int ncol, bsfit_status *st) {
  int i;
  if (ncol < 2 || ncol > 4)
    return fail_at(r, st, BSFIT_EFORMAT,
                   ncol < 2 ? "only 1 column (need 2, 3 or 4)" : "more than 4 columns", NULL);
  r->ncol = ncol;
  for (i = 0; i < NCOLS; i++) r->col[i] = i < ncol ? i : -1;
  r->dim = ncol >= 3 ? 3 : 2;
  return BSFIT_OK;
}

static bsfit_err read_header(reader *r, const field *f, int k, bsfit_status *st) {
  int i;
  if (k > 4) return fail_at(r, st, BSFIT_EFORMAT, "more than 4 columns in the header", NULL);
  for (i = 0; i < NCOLS; i++) r->col[i] = -1;
  for (i = 0; i < k; i++) {
    int id = column_id(&f[i]);
    if (id < 0)
      return fail_at(r, st, BSFIT_EFORMAT,
                     memchr(f[i].p, ',', f[i].n) ? "not a number (a decimal comma? write 1.5):"
                                                 : "unknown column name", &f[i]);
    if (r->col[id] >= 0) return fail_at(r, st, BSFIT_EFORMAT, "repeated column", &f[i]);
    r->col[id] = i;
  }
  if (r->col[COL_X] < 0 || r->col[COL_Y] < 0)
    return fail_at(r, st, BSFIT_EFORMAT, "the header must name both x and y", NULL);
  r->ncol = k;
  r->dim = r->col[COL_Z] >= 0 ? 3 : 2;
  return BSFIT_OK;
}

static bsfit_err read_row(reader *r, const field *f, int k, bsfit_status *st) {
  double v[NCOLS] = {0, 0, 0, 1};
  int i;
  if (k != r->ncol) {
    char what[64];
    snprintf(what, sizeof what, "expected %d columns, got %d", r->ncol, k);
    return fail_at(r, st, BSFIT_EFORMAT, what, NULL);
  }
  for (i = 0; i < NCOLS; i++) {
    const field *fi;
    if (r->col[i] < 0) continue;
    fi = &f[r->col[i]];
    if (!to_number(fi, &v[i]))
      return fail_at(r, st, BSFIT_EFORMAT,
                     memchr(fi->p, ',', fi->n) ? "not a number (a decimal comma? write 1.5):"
                                               : "not a number:", fi);
    if (!isfinite(v[i])) return fail_at(r, st, BSFIT_ENONFINITE, "not a finite number:", fi);
  }
  if (!(v[COL_W] > 0))
    return fail_at(r, st, BSFIT_EWEIGHT, "weight must be positive:", &f[r->col[COL_W]]);
  if (!grow(r))
    return bsfit__fail(st, BSFIT_ENOMEM, "out of memory after %zu points", r->m);
  for (i = 0; i < r->dim; i++) r->xy[r->m * (size_t)r->dim + (size_t)i] = v[i];
  if (r->w) r->w[r->m] = v[COL_W];
  r->m++;
  return BSFIT_OK;
}

static int looks_like_header(const field *f, int k) {
  int i;
  double x;
  for (i = 0; i < k && i < MAX_FIELDS; i++)
    if (to_number(&f[i], &x)) return 0;
  return 1;
}

/* A control byte other than blanks means binary data: say so rather than quote it. */
static bsfit_err check_text(reader *r, const char *p, size_t n, bsfit_status *st) {
  size_t i;
  for (i = 0; i < n; i++) {
    unsigned char c = (unsigned char)p[i];
    if ((c < 0x20 && !is_blank((char)c)) || c == 0x7f) {
      char what[80];
      snprintf(what, sizeof what, "binary data (byte 0x%02x at column %zu): not a point file",
               c, i + 1);
      return fail_at(r, st, BSFIT_EFORMAT, what, NULL);
    }
  }
  return BSFIT_OK;
}

static bsfit_err read_line(reader *r, const char *p, size_t n, bsfit_status *st) {
  field f[MAX_FIELDS];
  const char *hash;
  field t;
  int k;
  bsfit_err e;
  if (r->line == 1 && n >= 3 && memcmp(p, "\xEF\xBB\xBF", 3) == 0) p += 3, n -= 3; /* UTF-8 BOM */
  e = check_text(r, p, n, st);
  if (e != BSFIT_OK) return e;
  hash = memchr(p, '#', n);
  t = trim(p, hash ? (size_t)(hash - p) : n);
  if (t.n == 0) return BSFIT_OK;
  k = split(t.p, t.n, f);
  if (r->ncol == 0) {
    if (looks_like_header(f, k)) return read_header(r, f, k, st);
    e = set_layout(r, k, st);
    if (e != BSFIT_OK) return e;
  }
  return read_row(r, f, k, st);
}

/* The bsfit__line_fn of the file reader. */
static bsfit_err on_line(void *ud, size_t line, const char *p, size_t n, bsfit_status *st) {
  reader *r = (reader *)ud;
  r->line = line;
  return read_line(r, p, n, st);
}

/* }==================================================================== */

/* After the last line: at least one point, arrays shrunk to size. */
static bsfit_err finish(reader *r, bsfit_status *st) {
  if (r->m == 0) {
    if (r->name) return bsfit__fail(st, BSFIT_ETOOFEW, "%s: no data points", r->name);
    return bsfit__fail(st, BSFIT_ETOOFEW, "no data points");
  }
  if (!shrink(r)) return bsfit__fail(st, BSFIT_ENOMEM, "out of memory for %zu points", r->m);
  return bsfit__ok(st);
}

static bsfit_err parse_text(reader *r, const char *text, size_t len, bsfit_status *st) {
  size_t i = 0;
  while (i < len) {
    const char *nl = memchr(text + i, '\n', len - i);
    size_t n = nl ? (size_t)(nl - (text + i)) : len - i;
    bsfit_err e = on_line(r, r->line + 1, text + i, n, st);
    if (e != BSFIT_OK) return e;
    i += n + 1;
  }
  return finish(r, st);
}

/* Longest line of a point file: four numbers need < 100 bytes; comments may be long. */
#define MAX_LINE 65536

/* Reads from the file `name` when text is NULL, else parses the len bytes of text. */
static bsfit_err parse_named(const char *name, const char *text, size_t len, double **xy,
                             size_t *m, int *dim, double **w, const bsfit_allocator *a,
                             bsfit_status *st) {
  reader r;
  bsfit_err e;
  if (xy == NULL || m == NULL || dim == NULL)
    return bsfit__fail(st, BSFIT_EINVAL, "no output arrays for the points");
  *xy = NULL;
  *m = 0;
  *dim = 0;
  if (w) *w = NULL;
  if (name == NULL && text == NULL && len > 0)
    return bsfit__fail(st, BSFIT_EINVAL, "no text to parse");
  memset(&r, 0, sizeof r);
  r.name = name;
  r.a = a;
  r.dim = 2;
  if (name != NULL) {
    e = bsfit__read_lines(name, MAX_LINE, a, on_line, &r, st);
    if (e == BSFIT_OK) e = finish(&r, st);
  } else {
    e = parse_text(&r, text, len, st);
  }
  if (e != BSFIT_OK) {
    release(&r);
    return e;
  }
  if (w == NULL) {
    bsfit__free(a, r.w, r.m * sizeof(double));
    r.w = NULL;
  }
  *xy = r.xy;
  *m = r.m;
  *dim = r.dim;
  if (w) *w = r.w;
  return BSFIT_OK;
}

bsfit_err bsfit_points_parse(const char *text, size_t len, double **xy, size_t *m, int *dim,
                             double **w, const bsfit_allocator *a, bsfit_status *st) {
  return parse_named(NULL, text, len, xy, m, dim, w, a, st);
}

bsfit_err bsfit_points_read(const char *path, double **xy, size_t *m, int *dim, double **w,
                            const bsfit_allocator *a, bsfit_status *st) {
  if (xy) *xy = NULL;
  if (w) *w = NULL;
  if (path == NULL) return bsfit__fail(st, BSFIT_EINVAL, "no file name to read");
  return parse_named(path, NULL, 0, xy, m, dim, w, a, st);
}

void bsfit_points_free(double *xy, size_t m, int dim, double *w, const bsfit_allocator *a) {
  bsfit__free(a, xy, m * (size_t)dim * sizeof(double));
  bsfit__free(a, w, m * sizeof(double));
}

/* {====================================================================
** Writer
** ===================================================================== */

bsfit_err bsfit_points_format(const double *xy, size_t m, int dim, const double *w, char **out,
                              size_t *len, const bsfit_allocator *a, bsfit_status *st) {
  bsfit__buf b;
  size_t i, d = (size_t)dim;
  int k;
  if (dim != 2 && dim != 3)
    return bsfit__fail(st, BSFIT_EDIM, "points must be 2D or 3D, got dim %d", dim);
  if (xy == NULL || m == 0 || out == NULL)
    return bsfit__fail(st, BSFIT_EINVAL, "no points to write");
  if (bsfit__mulsize(m, d * sizeof(double)) == 0)
    return bsfit__fail(st, BSFIT_EINVAL, "too many points (%zu)", m);
  if (!bsfit__all_finite(xy, m * d))
    return bsfit__fail(st, BSFIT_ENONFINITE, "points contain NaN or Inf");
  for (i = 0; w && i < m; i++)
    if (!isfinite(w[i]) || !(w[i] > 0))
      return bsfit__fail(st, BSFIT_EWEIGHT, "weight %zu is %g (must be positive)", i, w[i]);
  bsfit__buf_init(&b, a);
  bsfit__buf_puts(&b, dim == 3 ? "x,y,z" : "x,y");
  bsfit__buf_puts(&b, w ? ",w\n" : "\n");
  for (i = 0; i < m; i++) {
    for (k = 0; k < dim; k++) {
      if (k) bsfit__buf_putn(&b, ",", 1);
      bsfit__buf_num(&b, xy[i * d + (size_t)k]);
    }
    if (w) {
      bsfit__buf_putn(&b, ",", 1);
      bsfit__buf_num(&b, w[i]);
    }
    bsfit__buf_putn(&b, "\n", 1);
  }
  return bsfit__buf_take(&b, out, len, st);
}

bsfit_err bsfit_points_write(const char *path, const double *xy, size_t m, int dim,
                             const double *w, bsfit_status *st) {
  bsfit__buf b;
  bsfit_err e;
  bsfit__buf_init(&b, NULL);
  e = bsfit_points_format(xy, m, dim, w, &b.data, &b.len, NULL, st);
  if (e != BSFIT_OK) return e;
  b.cap = b.len + 1;
  return bsfit__buf_write(&b, path, st);
}

/* }==================================================================== */
