/*
** io_buf.c
** The growable text buffer used by the writers (JSON, CSV, SVG, IGES).
*/
#include "io_internal.h"

#include <stdarg.h>
#include <stdio.h>
#include <string.h>

void bsfit__buf_init(bsfit__buf *b, const bsfit_allocator *a) {
  memset(b, 0, sizeof *b);
  if (a != NULL) b->alloc = *a;
}

void bsfit__buf_free(bsfit__buf *b) {
  bsfit__free(&b->alloc, b->data, b->cap);
  b->data = NULL;
  b->len = b->cap = 0;
}

/* Room for n more bytes plus the terminating NUL; doubles so appends are amortised O(1). */
static int reserve(bsfit__buf *b, size_t n) {
  size_t need, cap;
  char *p;
  if (b->failed) return 0;
  need = b->len + n + 1;
  if (need < b->len) goto fail;
  if (need <= b->cap) return 1;
  cap = b->cap ? b->cap : 256;
  while (cap < need) {
    if (cap > ((size_t)-1) / 2) goto fail;
    cap *= 2;
  }
  p = bsfit__realloc(&b->alloc, b->data, b->cap, cap);
  if (p == NULL) goto fail;
  b->data = p;
  b->cap = cap;
  return 1;
fail:
  b->failed = 1;
  return 0;
}

void bsfit__buf_putn(bsfit__buf *b, const char *s, size_t n) {
  if (!reserve(b, n)) return;
  memcpy(b->data + b->len, s, n);
  b->len += n;
  b->data[b->len] = '\0';
}

void bsfit__buf_puts(bsfit__buf *b, const char *s) { bsfit__buf_putn(b, s, strlen(s)); }

void bsfit__buf_printf(bsfit__buf *b, const char *fmt, ...) {
  char small[128];
  va_list ap;
  int n;
  va_start(ap, fmt);
  n = vsnprintf(small, sizeof small, fmt, ap);
  va_end(ap);
  if (n < 0) {
    b->failed = 1;
    return;
  }
  if ((size_t)n < sizeof small) {
    bsfit__buf_putn(b, small, (size_t)n);
    return;
  }
  /* too long for the stack buffer: format straight into the reserved space */
  if (!reserve(b, (size_t)n)) return;
  va_start(ap, fmt);
  vsnprintf(b->data + b->len, (size_t)n + 1, fmt, ap);
  va_end(ap);
  b->len += (size_t)n;
}

void bsfit__buf_num(bsfit__buf *b, double x) { bsfit__buf_printf(b, "%.17g", x); }

bsfit_err bsfit__buf_take(bsfit__buf *b, char **out, size_t *len, bsfit_status *st) {
  char *p;
  if (!b->failed && b->data == NULL) bsfit__buf_putn(b, "", 0);
  if (b->failed) {
    bsfit__buf_free(b);
    return bsfit__fail(st, BSFIT_ENOMEM, "out of memory while formatting text");
  }
  /* the caller frees len+1 bytes, so the block must have exactly that size */
  p = bsfit__realloc(&b->alloc, b->data, b->cap, b->len + 1);
  if (p == NULL) {
    bsfit__buf_free(b);
    return bsfit__fail(st, BSFIT_ENOMEM, "out of memory while formatting text");
  }
  *out = p;
  if (len) *len = b->len;
  b->data = NULL;
  b->len = b->cap = 0;
  return bsfit__ok(st);
}

bsfit_err bsfit__buf_write(bsfit__buf *b, const char *path, bsfit_status *st) {
  bsfit_err e;
  if (b->failed) {
    bsfit__buf_free(b);
    return bsfit__fail(st, BSFIT_ENOMEM, "out of memory while formatting %s",
                       path ? path : "a file");
  }
  e = bsfit__write_atomic(path, b->data ? b->data : "", b->len, 1, st);
  bsfit__buf_free(b);
  return e;
}
