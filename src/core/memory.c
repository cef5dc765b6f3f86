/*
** memory.c
** Allocation through a caller-supplied allocator (lua_Alloc contract) or the C library.
*/
#include "internal.h"

#include <math.h>
#include <stdint.h>
#include <stdlib.h>

void *bsfit__realloc(const bsfit_allocator *a, void *p, size_t osize, size_t nsize) {
  if (a != NULL && a->fn != NULL) return a->fn(a->ud, p, osize, nsize);
  if (nsize == 0) {
    free(p);
    return NULL;
  }
  return realloc(p, nsize);
}

void *bsfit__alloc(const bsfit_allocator *a, size_t nsize) {
  if (nsize == 0) return NULL;
  return bsfit__realloc(a, NULL, 0, nsize);
}

void bsfit__free(const bsfit_allocator *a, void *p, size_t osize) {
  if (p != NULL) (void)bsfit__realloc(a, p, osize, 0);
}

size_t bsfit__mulsize(size_t n, size_t size) {
  if (size != 0 && n > SIZE_MAX / size) return 0;
  return n * size;
}

int bsfit__all_finite(const double *x, size_t n) {
  size_t i;
  for (i = 0; i < n; i++)
    if (!isfinite(x[i])) return 0;
  return 1;
}
