/*
** io_atomic.c
** Atomic file replacement: write `path.tmp.<pid>.<n>`, optionally fsync it, then
** rename(2) it over path, so a reader sees either the old file or the whole new one.
** POSIX only (open/write/fsync/getpid).
*/
#define _POSIX_C_SOURCE 200809L

#include "io_internal.h"

#include <errno.h>
#include <fcntl.h>
#include <stdio.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

/* Enough unique names to get past stale temporaries left by a crashed process. */
#define MAX_TMP_TRIES 1000

/* Creates a fresh temporary next to path. The counter lives on the stack and O_EXCL
** makes the name unique, so two threads (or two writers in one process) never share
** a temporary and no static state is needed. */
static int open_temp(const char *path, char *tmp, size_t cap) {
  long pid = (long)getpid();
  int n;
  for (n = 0; n < MAX_TMP_TRIES; n++) {
    int fd;
    if ((size_t)snprintf(tmp, cap, "%s.tmp.%ld.%d", path, pid, n) >= cap) {
      errno = ENAMETOOLONG;
      return -1;
    }
    fd = open(tmp, O_WRONLY | O_CREAT | O_EXCL, 0666);
    if (fd >= 0 || errno != EEXIST) return fd;
  }
  return -1;
}

static int write_all(int fd, const char *data, size_t len) {
  while (len > 0) {
    ssize_t w = write(fd, data, len);
    if (w < 0) {
      if (errno == EINTR) continue;
      return -1;
    }
    data += w;
    len -= (size_t)w;
  }
  return 0;
}

bsfit_err bsfit__write_atomic(const char *path, const char *data, size_t len, int durable,
                              bsfit_status *st) {
  char tmp[4096];
  int fd, err;
  if (path == NULL || path[0] == '\0')
    return bsfit__fail(st, BSFIT_EINVAL, "no file name to write to");
  if (data == NULL && len > 0) return bsfit__fail(st, BSFIT_EINVAL, "no data to write");
  fd = open_temp(path, tmp, sizeof tmp);
  if (fd < 0)
    return bsfit__fail(st, BSFIT_EIO, "cannot create a temporary file for %s: %s", path,
                       strerror(errno));
  if (write_all(fd, data, len) != 0 || (durable && fsync(fd) != 0)) {
    err = errno;
    close(fd);
    remove(tmp);
    return bsfit__fail(st, BSFIT_EIO, "cannot write %s: %s", tmp, strerror(err));
  }
  if (close(fd) != 0) {
    err = errno;
    remove(tmp);
    return bsfit__fail(st, BSFIT_EIO, "cannot close %s: %s", tmp, strerror(err));
  }
  if (rename(tmp, path) != 0) {
    err = errno;
    remove(tmp);
    return bsfit__fail(st, BSFIT_EIO, "cannot replace %s: %s", path, strerror(err));
  }
  return bsfit__ok(st);
}

bsfit_err bsfit_write_file_atomic(const char *path, const char *data, size_t len,
                                  bsfit_status *st) {
  return bsfit__write_atomic(path, data, len, 1, st);
}
