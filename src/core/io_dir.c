/*
** io_dir.c
** Directories without a shell: the sorted entry names of a directory (any bytes a
** file name may hold, newlines included), what kind of thing a path names, and
** making a directory with its parents (mkdir -p).
*/
#define _POSIX_C_SOURCE 200809L

#include "io_internal.h"

#include <dirent.h>
#include <errno.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/types.h>

/* {====================================================================
** Listing
** ===================================================================== */

typedef struct names {
  char **v;
  size_t n, cap;
  const bsfit_allocator *a;
} names;

static void names_free(names *s) {
  size_t i;
  for (i = 0; i < s->n; i++) bsfit__free(s->a, s->v[i], strlen(s->v[i]) + 1);
  bsfit__free(s->a, s->v, s->cap * sizeof(char *));
  s->v = NULL;
  s->n = s->cap = 0;
}

/* Appends a copy of name; 1 on success. */
static int names_add(names *s, const char *name) {
  size_t len = strlen(name) + 1;
  char *copy;
  if (s->n == s->cap) {
    size_t ncap = s->cap ? 2 * s->cap : 16;
    char **v;
    if (bsfit__mulsize(ncap, sizeof(char *)) == 0) return 0;
    v = bsfit__realloc(s->a, s->v, s->cap * sizeof(char *), ncap * sizeof(char *));
    if (v == NULL) return 0;
    s->v = v;
    s->cap = ncap;
  }
  copy = bsfit__alloc(s->a, len);
  if (copy == NULL) return 0;
  memcpy(copy, name, len);
  s->v[s->n++] = copy;
  return 1;
}

static int by_bytes(const void *x, const void *y) {
  return strcmp(*(char *const *)x, *(char *const *)y);
}

bsfit_err bsfit_dir_list(const char *path, char ***out, size_t *n, const bsfit_allocator *a,
                         bsfit_status *st) {
  names s;
  DIR *d;
  struct dirent *e;
  int err;
  if (out == NULL || n == NULL) return bsfit__fail(st, BSFIT_EINVAL, "no output for the names");
  *out = NULL;
  *n = 0;
  if (path == NULL || path[0] == '\0') return bsfit__fail(st, BSFIT_EINVAL, "no directory name");
  d = opendir(path);
  if (d == NULL) return bsfit__fail(st, BSFIT_EIO, "cannot list %s: %s", path, strerror(errno));
  memset(&s, 0, sizeof s);
  s.a = a;
  for (;;) {
    errno = 0;
    e = readdir(d);
    if (e == NULL) break;
    if (strcmp(e->d_name, ".") == 0 || strcmp(e->d_name, "..") == 0) continue;
    if (!names_add(&s, e->d_name)) {
      closedir(d);
      names_free(&s);
      return bsfit__fail(st, BSFIT_ENOMEM, "out of memory listing %s", path);
    }
  }
  err = errno;
  closedir(d);
  if (err != 0) {
    names_free(&s);
    return bsfit__fail(st, BSFIT_EIO, "cannot list %s: %s", path, strerror(err));
  }
  if (s.n > 1) qsort(s.v, s.n, sizeof(char *), by_bytes);
  *out = s.v;
  *n = s.n;
  /* the caller frees n pointers of an array of cap: shrink so that n is the size */
  if (s.cap > s.n) {
    char **v = bsfit__realloc(a, s.v, s.cap * sizeof(char *), s.n * sizeof(char *));
    if (v != NULL || s.n == 0) *out = v;
  }
  return bsfit__ok(st);
}

void bsfit_dir_free(char **names_, size_t n, const bsfit_allocator *a) {
  size_t i;
  if (names_ == NULL) return;
  for (i = 0; i < n; i++) bsfit__free(a, names_[i], strlen(names_[i]) + 1);
  bsfit__free(a, names_, n * sizeof(char *));
}

/* }==================================================================== */

/* {====================================================================
** Kinds and making
** ===================================================================== */

int bsfit_path_kind(const char *path) {
  struct stat sb;
  if (path == NULL || path[0] == '\0' || stat(path, &sb) != 0) return BSFIT_PATH_NONE;
  if (S_ISDIR(sb.st_mode)) return BSFIT_PATH_DIR;
  if (S_ISREG(sb.st_mode)) return BSFIT_PATH_FILE;
  return BSFIT_PATH_OTHER;
}

/* mkdir of one level; an existing directory is success. */
static bsfit_err make_one(const char *path, const char *whole, bsfit_status *st) {
  if (mkdir(path, 0777) == 0) return BSFIT_OK;
  if (errno == EEXIST && bsfit_path_kind(path) == BSFIT_PATH_DIR) return BSFIT_OK;
  if (errno == EEXIST)
    return bsfit__fail(st, BSFIT_EIO, "%s is not a directory (making %s)", path, whole);
  return bsfit__fail(st, BSFIT_EIO, "cannot create directory %s: %s", whole, strerror(errno));
}

bsfit_err bsfit_dir_make(const char *path, const bsfit_allocator *a, bsfit_status *st) {
  size_t len, i;
  char *p;
  bsfit_err e = BSFIT_OK;
  if (path == NULL || path[0] == '\0') return bsfit__fail(st, BSFIT_EINVAL, "no directory name");
  if (bsfit_path_kind(path) == BSFIT_PATH_DIR) return bsfit__ok(st);
  len = strlen(path);
  p = bsfit__alloc(a, len + 1);
  if (p == NULL) return bsfit__fail(st, BSFIT_ENOMEM, "out of memory");
  memcpy(p, path, len + 1);
  for (i = 1; i <= len && e == BSFIT_OK; i++) { /* each prefix ending before a '/' */
    if (i < len && p[i] != '/') continue;
    if (p[i - 1] == '/') continue; /* "a//b", trailing '/' */
    p[i] = '\0';
    e = make_one(p, path, st);
    if (i < len) p[i] = '/';
  }
  bsfit__free(a, p, len + 1);
  return e == BSFIT_OK ? bsfit__ok(st) : e;
}

/* }==================================================================== */
