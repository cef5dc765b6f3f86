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

size_t bsfit__first_out_of_range(const double *x, size_t n) {
  size_t i;
  for (i = 0; i < n; i++)
    if (!(fabs(x[i]) <= BSFIT_COORD_MAX)) return i;
  return n;
}

/* x * 0 is +-0 for a finite x and NaN for Inf or NaN, and a NaN survives the sums: no
** branch per element, and four running sums keep the adds independent. */
int bsfit__all_finite(const double *x, size_t n) {
  double s0 = 0.0, s1 = 0.0, s2 = 0.0, s3 = 0.0;
  size_t i;
  for (i = 0; i + 4 <= n; i += 4) {
    s0 += x[i] * 0.0;
    s1 += x[i + 1] * 0.0;
    s2 += x[i + 2] * 0.0;
    s3 += x[i + 3] * 0.0;
  }
  for (; i < n; i++) s0 += x[i] * 0.0;
  return (s0 + s1) + (s2 + s3) == 0.0;
}
