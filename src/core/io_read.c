/*
** io_read.c
** Reading a whole file into a text buffer (for the point and JSON readers).
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
