/*
** io_read.c
** Reading files: whole into a text buffer (the JSON reader: curve files are small),
** or line by line through a fixed window (point files: memory proportional to the
** points kept, not to the file, and a bad line fails before the rest is read).
*/
#include "io_internal.h"

#include <errno.h>
#include <stdio.h>
#include <string.h>

bsfit_err bsfit__read_file(const char *path, bsfit__buf *b, bsfit_status *st) {
  char chunk[8192];
  FILE *f;
  size_t got;
  int err;
  if (path == NULL) return bsfit__fail(st, BSFIT_EINVAL, "no file name to read");
  f = fopen(path, "rb");
  if (f == NULL) return bsfit__fail(st, BSFIT_EIO, "cannot open %s: %s", path, strerror(errno));
  /* read by chunks rather than by ftell, so pipes and /dev/stdin work too */
  while ((got = fread(chunk, 1, sizeof chunk, f)) > 0) {
    bsfit__buf_putn(b, chunk, got);
    if (b->failed) {
      fclose(f);
      return bsfit__fail(st, BSFIT_ENOMEM, "out of memory reading %s", path);
    }
  }
  err = ferror(f) ? errno : 0;
  fclose(f);
  if (err != 0 || b->failed)
    return bsfit__fail(st, BSFIT_EIO, "cannot read %s: %s", path,
                       err ? strerror(err) : "read error");
  return bsfit__ok(st);
}

/* {====================================================================
** Line by line
** ===================================================================== */

typedef struct window {
  char *p;
  size_t len, cap; /* bytes held (the unfinished line first), size of p */
} window;

static bsfit_err too_long(const char *path, size_t line, size_t maxline, bsfit_status *st) {
  return bsfit__fail(st, BSFIT_EFORMAT, "%s:%zu: line longer than %zu bytes (not a point file?)",
                     path, line, maxline);
}

/* Hands every complete line of w to fn and keeps the unfinished tail at the front. */
static bsfit_err emit_lines(window *w, const char *path, size_t maxline, size_t *line,
                            bsfit__line_fn fn, void *ud, bsfit_status *st) {
  size_t i = 0;
  for (;;) {
    const char *nl = memchr(w->p + i, '\n', w->len - i);
    bsfit_err e;
    if (nl == NULL) break;
    ++*line;
    if ((size_t)(nl - (w->p + i)) > maxline) return too_long(path, *line, maxline, st);
    e = fn(ud, *line, w->p + i, (size_t)(nl - (w->p + i)), st);
    if (e != BSFIT_OK) return e;
    i = (size_t)(nl - w->p) + 1;
  }
  memmove(w->p, w->p + i, w->len - i);
  w->len -= i;
  return BSFIT_OK;
}

static bsfit_err read_lines_from(FILE *f, const char *path, window *w, size_t maxline,
                                 bsfit__line_fn fn, void *ud, bsfit_status *st) {
  size_t line = 0, got;
  bsfit_err e;
  while ((got = fread(w->p + w->len, 1, w->cap - w->len, f)) > 0) {
    w->len += got;
    e = emit_lines(w, path, maxline, &line, fn, ud, st);
    if (e != BSFIT_OK) return e;
    if (w->len > maxline) return too_long(path, line + 1, maxline, st); /* no newline in sight */
  }
  if (ferror(f))
    return bsfit__fail(st, BSFIT_EIO, "cannot read %s: %s", path,
                       errno ? strerror(errno) : "read error");
  if (w->len > 0) return fn(ud, line + 1, w->p, w->len, st); /* no final newline */
  return BSFIT_OK;
}

bsfit_err bsfit__read_lines(const char *path, size_t maxline, const bsfit_allocator *a,
                            bsfit__line_fn fn, void *ud, bsfit_status *st) {
  window w;
  FILE *f;
  bsfit_err e;
  if (path == NULL) return bsfit__fail(st, BSFIT_EINVAL, "no file name to read");
  w.len = 0;
  w.cap = 2 * maxline; /* a longest line plus as much again read ahead */
  w.p = bsfit__alloc(a, w.cap);
  if (w.p == NULL) return bsfit__fail(st, BSFIT_ENOMEM, "out of memory reading %s", path);
  f = fopen(path, "rb");
  if (f == NULL) {
    e = bsfit__fail(st, BSFIT_EIO, "cannot open %s: %s", path, strerror(errno));
  } else {
    errno = 0;
    e = read_lines_from(f, path, &w, maxline, fn, ud, st);
    fclose(f);
  }
  bsfit__free(a, w.p, w.cap);
  return e;
}

/* }==================================================================== */
