/*
** parallel.c
** A small worker pool for `bsfit reconstruct -j N`: N threads, each with its own
** bsfit engine (its own lua_State: engines share nothing, bsfit_engine.h), pull
** string items from a shared counter and call require(module)[fn](item). Results
** and error messages are copied out as malloc'd strings, in item order whatever
** thread computed them, so the output does not depend on N.
*/
#define _POSIX_C_SOURCE 200809L

#include "parallel.h"

#include "bsfit_engine.h"

#include <lauxlib.h>
#include <lua.h>

#include <pthread.h>
#include <stdlib.h>
#include <string.h>

/* Registry key of the worker's function (the address is the key; never written). */
static const char fn_key = 'f';

/* {====================================================================
** One worker
** ===================================================================== */

/* Protected set-up of a worker engine: package paths, then require(module)[fn]
** stored in the registry. Arguments: the job as a light userdata. */
static int worker_setup(lua_State *L) {
  const bsfit_pmap *job = (const bsfit_pmap *)lua_touserdata(L, 1);
  if (!job->sandbox && (job->path != NULL || job->cpath != NULL)) {
    lua_getglobal(L, "package");
    if (lua_istable(L, -1)) {
      if (job->path != NULL) lua_pushstring(L, job->path), lua_setfield(L, -2, "path");
      if (job->cpath != NULL) lua_pushstring(L, job->cpath), lua_setfield(L, -2, "cpath");
    }
    lua_pop(L, 1);
  }
  lua_getglobal(L, "require");
  lua_pushstring(L, job->module);
  lua_call(L, 1, 1);
  if (lua_getfield(L, -1, job->fn) != LUA_TFUNCTION)
    return luaL_error(L, "module '%s' has no function '%s'", job->module, job->fn);
  lua_rawsetp(L, LUA_REGISTRYINDEX, &fn_key);
  return 0;
}

/* Protected call of the function on one item (a light userdata): returns its
** result, which must be a string. */
static int worker_call(lua_State *L) {
  const bsfit_pmap_item *it = (const bsfit_pmap_item *)lua_touserdata(L, 1);
  lua_rawgetp(L, LUA_REGISTRYINDEX, &fn_key);
  lua_pushlstring(L, it->in, it->inlen);
  lua_call(L, 1, 1);
  if (lua_type(L, -1) != LUA_TSTRING)
    return luaL_error(L, "worker function returned %s, not a string", luaL_typename(L, -1));
  return 1;
}

/* out = a malloc'd NUL-terminated copy of s[0..len) (NULL when memory runs out). */
static void set_out(bsfit_pmap_item *it, const char *s, size_t len, int ok) {
  it->out = (char *)malloc(len + 1);
  it->ok = ok && it->out != NULL;
  it->outlen = it->out != NULL ? len : 0;
  if (it->out != NULL) {
    memcpy(it->out, s, len);
    it->out[len] = '\0';
  }
}

/* Pushes a C function and a light userdata: neither allocates, so this cannot
** raise outside a protected call. */
static int pcall_with(bsfit_engine *e, lua_CFunction f, void *p) {
  lua_State *L = bsfit_engine_lua(e);
  lua_pushcfunction(L, f);
  lua_pushlightuserdata(L, p);
  return bsfit_engine_pcall(e, 1, 1) == BSFIT_OK;
}

/* Records that item i ended, for the calling thread's done calls. */
static void ended(bsfit_pmap *job, size_t i) {
  if (job->ended == NULL) return;
  pthread_mutex_lock(&job->mu);
  job->ended[job->nended++] = i;
  pthread_cond_signal(&job->cv);
  pthread_mutex_unlock(&job->mu);
}

/* Takes items until none is left; each gets its result or its error. */
static void work(bsfit_pmap *job, bsfit_engine *e, const char *setup_error) {
  for (;;) {
    size_t i = atomic_fetch_add(&job->next, 1);
    bsfit_pmap_item *it;
    if (i >= job->n) break;
    it = &job->items[i];
    if (setup_error != NULL) {
      set_out(it, setup_error, strlen(setup_error), 0);
    } else if (pcall_with(e, worker_call, it)) {
      lua_State *L = bsfit_engine_lua(e);
      size_t len;
      const char *s = lua_tolstring(L, -1, &len);
      set_out(it, s, len, 1);
      lua_pop(L, 1);
    } else {
      const char *msg = bsfit_engine_errmsg(e);
      set_out(it, msg, strlen(msg), 0);
    }
    ended(job, i);
  }
}

static void *worker(void *arg) {
  bsfit_pmap *job = (bsfit_pmap *)arg;
  bsfit_engine_opts o;
  bsfit_engine *e;
  memset(&o, 0, sizeof o);
  o.sandbox = job->sandbox;
  e = bsfit_engine_new(&o);
  if (e == NULL) {
    work(job, NULL, "cannot create a worker engine (out of memory)");
  } else if (!pcall_with(e, worker_setup, job)) {
    work(job, NULL, bsfit_engine_errmsg(e));
  } else {
    lua_pop(bsfit_engine_lua(e), 1);
    work(job, e, NULL);
  }
  bsfit_engine_free(e);
  return NULL;
}

/* }==================================================================== */

/* {====================================================================
** The pool
** ===================================================================== */

#define MAX_WORKERS 256

/* The calling thread's side of a job with a done callback: calls done for every item
** as it ends, until all have. */
static void report_done(bsfit_pmap *job) {
  size_t seen = 0;
  pthread_mutex_lock(&job->mu);
  while (seen < job->n) {
    size_t upto;
    while (job->nended == seen) pthread_cond_wait(&job->cv, &job->mu);
    upto = job->nended;
    pthread_mutex_unlock(&job->mu); /* done may take its time: workers go on */
    for (; seen < upto; seen++) job->done(job->done_ud, job->ended[seen]);
    pthread_mutex_lock(&job->mu);
  }
  pthread_mutex_unlock(&job->mu);
}

/* A job with a done callback: nthreads workers, the calling thread reports. When no
** thread starts (or no memory for the list), the calling thread works alone and reports
** each item as it ends. */
static int run_reporting(bsfit_pmap *job, int nthreads, pthread_t *th) {
  int started = 0, k;
  job->nended = 0;
  job->ended = (size_t *)malloc(job->n * sizeof *job->ended);
  if (job->ended != NULL && pthread_mutex_init(&job->mu, NULL) != 0) {
    free(job->ended);
    job->ended = NULL;
  }
  if (job->ended != NULL && pthread_cond_init(&job->cv, NULL) != 0) {
    pthread_mutex_destroy(&job->mu);
    free(job->ended);
    job->ended = NULL;
  }
  if (job->ended != NULL)
    for (k = 0; k < nthreads; k++)
      if (pthread_create(&th[started], NULL, worker, job) == 0) started++;
  if (started == 0) worker(job); /* alone: every item ends on this thread */
  if (job->ended != NULL) {
    report_done(job);
    for (k = 0; k < started; k++) pthread_join(th[k], NULL);
    pthread_cond_destroy(&job->cv);
    pthread_mutex_destroy(&job->mu);
    free(job->ended);
    job->ended = NULL;
  } else {
    size_t i;
    for (i = 0; i < job->n; i++) job->done(job->done_ud, i);
  }
  return started > 0 ? started : 1;
}

int bsfit__pmap_run(bsfit_pmap *job, int nthreads) {
  pthread_t th[MAX_WORKERS];
  int started = 0, k;
  if (nthreads < 1) nthreads = 1;
  if (nthreads > MAX_WORKERS) nthreads = MAX_WORKERS;
  if ((size_t)nthreads > job->n && job->n > 0) nthreads = (int)job->n;
  atomic_store(&job->next, 0);
  job->ended = NULL;
  if (job->done != NULL && job->n > 0) return run_reporting(job, nthreads, th);
  /* the calling thread is the last worker; a thread that cannot start is simply
  ** not there: the others take its items */
  for (k = 0; k < nthreads - 1; k++)
    if (pthread_create(&th[started], NULL, worker, job) == 0) started++;
  worker(job);
  for (k = 0; k < started; k++) pthread_join(th[k], NULL);
  return started + 1;
}

void bsfit__pmap_clear(bsfit_pmap *job) {
  size_t i;
  if (job->items == NULL) return;
  for (i = 0; i < job->n; i++) {
    free(job->items[i].out);
    job->items[i].out = NULL;
  }
}

/* }==================================================================== */
