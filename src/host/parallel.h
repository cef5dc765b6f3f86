/*
** parallel.h
** Private to the bsfit program and module: run a Lua function over a list of
** string items on worker threads, one bsfit engine (Lua state) per worker
** (src/host/parallel.c; bound to Lua as bs.parallel.map by src/lua/lparallel.c).
*/
#ifndef BSFIT_PARALLEL_H
#define BSFIT_PARALLEL_H

#include <pthread.h>
#include <stdatomic.h>
#include <stddef.h>

/* One item: its input string (borrowed) and, after the run, its result. */
typedef struct bsfit_pmap_item {
  const char *in;
  size_t inlen;
  char *out;     /* malloc'd result (ok) or error message (!ok), NUL-terminated; NULL: out of memory */
  size_t outlen;
  int ok;
} bsfit_pmap_item;

/* A job: call require(module)[fn](item) for every item. */
typedef struct bsfit_pmap {
  const char *module, *fn;
  const char *path, *cpath; /* package.path / package.cpath for the workers, or NULL */
  int sandbox;              /* non-zero: workers are sandboxed engines (paths not copied) */
  bsfit_pmap_item *items;
  size_t n;
  atomic_size_t next;       /* the next item to take (workers pull items in turn) */
  /* Optional: called on the calling thread once per item, as items end (in the order
  ** they end), with the item's index; its out and ok are then set. With it, the calling
  ** thread reports instead of working (nthreads workers are started). */
  void (*done)(void *ud, size_t i);
  void *done_ud;
  /* private to parallel.c: the ended items, in order, for done */
  pthread_mutex_t mu;
  pthread_cond_t cv;
  size_t *ended, nended;
} bsfit_pmap;

/* Runs the job on nthreads workers (the calling thread is one of them). Every item
** ends with ok set, or with an error message in out (a worker that cannot create
** its engine fails the items it takes with that message).
** Returns the number of workers actually started (>= 1). */
int bsfit__pmap_run(bsfit_pmap *job, int nthreads);

/* Frees every item's out and sets it to NULL. Idempotent. */
void bsfit__pmap_clear(bsfit_pmap *job);

#endif
