/*
** scan_internal.h
** Helpers shared by the scan files of src/core (io_scan_*.c, scan_*.c): a builder that
** collects vertices and triangles while a reader parses, a cursor over text for the
** ASCII readers, and the k-d tree the ordering's neighbour search uses.
*/
#ifndef BSFIT_SCAN_INTERNAL_H
#define BSFIT_SCAN_INTERNAL_H

#include "internal.h"

#include <stdint.h>

/* {======================================================================
** Building a scan
** ====================================================================== */

typedef struct bsfit__scanbuild {
  const char *name; /* file name for messages */
  bsfit_allocator a;
  double *xyz;
  size_t nv, capv;
  uint32_t *tri;
  size_t nt, capt;
  int failed; /* an allocation failed: sticky, reported by finish */
} bsfit__scanbuild;

void bsfit__sb_init(bsfit__scanbuild *b, const char *name, const bsfit_allocator *a);
void bsfit__sb_free(bsfit__scanbuild *b);
/* Room for n more vertices / triangles (0 on out of memory: b->failed set). */
int bsfit__sb_reserve(bsfit__scanbuild *b, size_t nv, size_t nt);
void bsfit__sb_vertex(bsfit__scanbuild *b, double x, double y, double z);
/* Appends triangle (i, j, k) of 0-based ids the caller has checked. */
void bsfit__sb_tri(bsfit__scanbuild *b, uint32_t i, uint32_t j, uint32_t k);
/* Checks every vertex is finite and hands the arrays to s (b left empty). */
bsfit_err bsfit__sb_finish(bsfit__scanbuild *b, bsfit_scan *s, bsfit_status *st);

/* }====================================================================== */

/* {======================================================================
** A cursor over text (ASCII PLY, STL, OBJ): tokens separated by blanks, line counting
** ====================================================================== */

typedef struct bsfit__cursor {
  const char *s;
  size_t len, pos;
  size_t line; /* 1-based line of pos */
} bsfit__cursor;

/* Skips blanks (newlines too, counted); returns 0 at the end of the text. */
int bsfit__cur_skip(bsfit__cursor *c);
/* Skips blanks but not newlines; returns the next byte or -1 (end) / '\n'. */
int bsfit__cur_skip_inline(bsfit__cursor *c);
/* The next token (after blanks and newlines) copied into buf (NUL-terminated); returns
** its length, 0 at the end, or (size_t)-1 when it is longer than cap-1 bytes. */
size_t bsfit__cur_token(bsfit__cursor *c, char *buf, size_t cap);
/* The next token as a number; returns 0 when there is none or it does not parse. */
int bsfit__cur_number(bsfit__cursor *c, double *x);
/* Moves past the end of the current line. */
void bsfit__cur_next_line(bsfit__cursor *c);

/* }====================================================================== */

/* {======================================================================
** Format readers (io_scan_*.c), called by bsfit_scan_parse with a fresh builder
** ====================================================================== */

bsfit_err bsfit__scan_ply(const char *data, size_t len, bsfit__scanbuild *b, bsfit_status *st);
bsfit_err bsfit__scan_stl(const char *data, size_t len, bsfit__scanbuild *b, bsfit_status *st);
bsfit_err bsfit__scan_obj(const char *data, size_t len, bsfit__scanbuild *b, bsfit_status *st);

/* }====================================================================== */

/* {======================================================================
** A 2D k-d tree for neighbour queries (scan_kdtree.c)
** ====================================================================== */

typedef struct bsfit__kdtree {
  const double *xy;
  size_t m;
  size_t *perm;       /* point indices, arranged as the implicit tree */
  double *split;      /* split value of the node whose mid is the index */
  unsigned char *dim; /* its split axis */
  const bsfit_allocator *a;
} bsfit__kdtree;

bsfit_err bsfit__kdtree_build(bsfit__kdtree *t, const double *xy, size_t m,
                              const bsfit_allocator *a, bsfit_status *st);
void bsfit__kdtree_free(bsfit__kdtree *t);
/* The k nearest other points of point i: idx[0..k-1] (nearest first) and their distances
** d[0..k-1]; returns how many were found (< k only when m-1 < k). */
size_t bsfit__kdtree_knn(const bsfit__kdtree *t, size_t i, size_t k, size_t *idx, double *d);

/* }====================================================================== */

#endif
