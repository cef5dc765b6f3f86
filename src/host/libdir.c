/*
** libdir.c
** The path of the shared object holding the engine (dladdr, a GNU/BSD extension):
** an installed libbsfit_engine finds the Lua modules installed beside it whatever
** prefix `cmake --install --prefix P` chose after the build was configured.
*/
#define _GNU_SOURCE

#include "libdir.h"

#include <dlfcn.h>
#include <stdlib.h>
#include <string.h>

char *bsfit__code_path(void) {
  Dl_info info;
  char *out;
  size_t n;
  /* ISO C has no function-to-object pointer conversion; POSIX guarantees it. */
  if (dladdr((void *)(size_t)&bsfit__code_path, &info) == 0 || info.dli_fname == NULL)
    return NULL;
  n = strlen(info.dli_fname) + 1;
  out = (char *)malloc(n);
  if (out != NULL) memcpy(out, info.dli_fname, n);
  return out;
}
