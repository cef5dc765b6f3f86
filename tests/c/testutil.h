/*
** testutil.h
** Small helpers shared by the cmocka tests: a deterministic random generator,
** random knot vectors and tolerance names.
*/
#ifndef BSFIT_TESTUTIL_H
#define BSFIT_TESTUTIL_H

#include <math.h>
#include <stddef.h>
#include <stdint.h>
#include <stdlib.h>

/* tolerances, named per domain */
#define EPS_EXACT 1e-14 /* identities that hold up to rounding */
#define EPS_KNOT 1e-12  /* knot values */
#define EPS_FD 1e-6     /* finite differences (relative) */

/* How many of n random cases to run: all, or a third under the sanitizers (BSFIT_SANITIZED,
** set by CMake on the sanitizer build's tests), whose arithmetic is the normal build's and
** which run them several times slower. Floors that count cases are measured for both. */
static inline int test_thinned(void) { return getenv("BSFIT_SANITIZED") != NULL; }
static inline int test_cases(int n) { return test_thinned() ? (n + 2) / 3 : n; }

/* xorshift64*: deterministic, so a failing case can be reproduced */
typedef struct test_rng {
  uint64_t s;
} test_rng;

static inline double rng_uniform(test_rng *r) {
  r->s ^= r->s >> 12;
  r->s ^= r->s << 25;
  r->s ^= r->s >> 27;
  return (double)((r->s * 2685821657736338717ULL) >> 11) * (1.0 / 9007199254740992.0);
}

static inline double rng_range(test_rng *r, double a, double b) { return a + (b - a) * rng_uniform(r); }

/* Random non-decreasing knot vector for degree p and n control points: clamped
** ends when `clamped`, random interior knots (some repeated, multiplicity <= p). */
static inline void random_knots(test_rng *r, int p, size_t n, int clamped, double *U) {
  size_t nk = n + (size_t)p + 1, i, run = 1;
  for (i = 0; i < nk; i++) {
    double step = rng_range(r, 0.1, 1.0);
    if (i == 0) {
      U[0] = 0.0;
    } else if (clamped && (i <= (size_t)p || i > n)) {
      U[i] = U[i - 1];
    } else if (i != n && run < (size_t)p &&
               rng_uniform(r) < 0.15 && !(clamped && i == n)) {
      U[i] = U[i - 1]; /* an interior repeated knot, multiplicity <= p */
    } else {
      U[i] = U[i - 1] + step;
    }
    run = (i > 0 && U[i] == U[i - 1]) ? run + 1 : 1;
  }
}

/* Counting allocator (bsfit_allocator contract) that fails the N-th allocation
** (fail_at, 1-based; 0 = never) and tracks the live bytes, for the ENOMEM tests. */
typedef struct counting {
  long calls, fail_at;
  long long live;
} counting;

static inline void *counting_alloc(void *ud, void *p, size_t osz, size_t nsz) {
  counting *c = (counting *)ud;
  if (nsz == 0) {
    if (p) c->live -= (long long)osz;
    free(p);
    return NULL;
  }
  if (++c->calls == c->fail_at) return NULL;
  p = realloc(p, nsz);
  if (p) c->live += (long long)nsz - (long long)osz;
  return p;
}

#endif
