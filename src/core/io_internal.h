/*
** io_internal.h
** Helpers shared by the io_*.c files of src/core: a growable text buffer that
** allocates through a bsfit_allocator, and the atomic file writer.
*/
#ifndef BSFIT_IO_INTERNAL_H
#define BSFIT_IO_INTERNAL_H

#include "internal.h"

/* A growable NUL-terminated text buffer. Errors are sticky: after a failed append
** every later append is a no-op and `failed` stays set, so writers check once at the
** end instead of after every number. */
typedef struct bsfit__buf {
  char *data;
  size_t len, cap; /* cap = size of the block data points to */
  bsfit_allocator alloc;
  int failed;
} bsfit__buf;

void bsfit__buf_init(bsfit__buf *b, const bsfit_allocator *a);
void bsfit__buf_free(bsfit__buf *b);
void bsfit__buf_putn(bsfit__buf *b, const char *s, size_t n);
void bsfit__buf_puts(bsfit__buf *b, const char *s);
void bsfit__buf_printf(bsfit__buf *b, const char *fmt, ...) BSFIT_PRINTF(2, 3);
/* %.17g: enough digits for strtod to give back the same double */
void bsfit__buf_num(bsfit__buf *b, double x);
/* Hands the text to the caller as a block of exactly len+1 bytes (shrunk), leaving b
** empty. Returns BSFIT_ENOMEM (b freed) if an append failed. */
bsfit_err bsfit__buf_take(bsfit__buf *b, char **out, size_t *len, bsfit_status *st);

/* Writes data to path through `path.tmp.<pid>.<n>` and rename(2); with durable the
** temporary is fsync'ed first. On any error the temporary is removed and path is
** untouched. @return BSFIT_OK, BSFIT_EINVAL (path NULL or empty) or BSFIT_EIO. */
bsfit_err bsfit__write_atomic(const char *path, const char *data, size_t len, int durable,
                              bsfit_status *st);

/* The exchange writers (io_exchange.c). check_curve: c (curve k of a file) is valid, 2D or
** 3D and of degree >= 1, or an error naming the format ("STEP") and its kind of curve
** ("STEP B-spline curves"). write: the text a writer made with the default allocator (made:
** its status; nothing to write unless BSFIT_OK) written to path atomically, then freed. */
bsfit_err bsfit__exchange_check_curve(const bsfit_curve *c, size_t k, const char *format,
                                      const char *kind, bsfit_status *st);
bsfit_err bsfit__exchange_write(bsfit_err made, char *text, size_t len, const char *path,
                                bsfit_status *st);
/* The file's time stamp, UTC, by strftime's fmt into out (size bytes): SOURCE_DATE_EPOCH
** when set to a plain decimal count of seconds (the reproducible-builds convention: the same
** geometry then gives the same bytes), else now; fallback (a time of that format) when the
** time cannot be had or formatted. */
void bsfit__exchange_time(const char *fmt, char *out, size_t size, const char *fallback);

/* Writes a finished buffer atomically and frees it (whatever the outcome). */
bsfit_err bsfit__buf_write(bsfit__buf *b, const char *path, bsfit_status *st);

/* Appends the whole content of the file at path to b (b initialised by the caller,
** who frees it whatever the outcome). @return BSFIT_OK, BSFIT_EINVAL (path NULL),
** BSFIT_EIO (message: path and the system's reason) or BSFIT_ENOMEM. */
bsfit_err bsfit__read_file(const char *path, bsfit__buf *b, bsfit_status *st);

/* The clamped form of a curve / surface (io_clamp.c): the same points at the same
** parameters on the same domain, with end knots of multiplicity p+1 (a periodic curve is
** cut open where its period starts; the result is not periodic). Memory from al. */
bsfit_err bsfit__curve_clamped(const bsfit_curve *c, bsfit_curve *out, const bsfit_allocator *al,
                               bsfit_status *st);
bsfit_err bsfit__surface_clamped(const bsfit_surface *s, bsfit_surface *out,
                                 const bsfit_allocator *al, bsfit_status *st);

/* Called with each line of a file (1-based number, text without its '\n'). */
typedef bsfit_err (*bsfit__line_fn)(void *ud, size_t line, const char *p, size_t n,
                                    bsfit_status *st);

/* Reads the file at path line by line through a window of 2 * maxline bytes
** (allocated with a), calling fn on each line; stops at fn's first error. A line
** longer than maxline fails (EFORMAT, "path:N: line longer than ..."): a file with no
** line breaks is not read to its end. @return BSFIT_OK, fn's error, BSFIT_EINVAL
** (path NULL), BSFIT_EIO (the path and the system's reason), BSFIT_EFORMAT, ENOMEM. */
bsfit_err bsfit__read_lines(const char *path, size_t maxline, const bsfit_allocator *a,
                            bsfit__line_fn fn, void *ud, bsfit_status *st);

/* {======================================================================
** A strict JSON reader (io_jsonparse.c), pull style: the caller walks the document
** it expects, and every error names the byte offset. Errors are EFORMAT unless said.
** ====================================================================== */

#define BSFIT__JSON_MAXDEPTH 64

typedef struct bsfit__json {
  const char *s;
  size_t len, pos;
  int depth;
  bsfit_status *st;
} bsfit__json;

/* A rectangular nested array of numbers, flattened (last index fastest). */
typedef struct bsfit__numarr {
  double *v;
  size_t n, cap;
  size_t shape[3]; /* element count at each nesting level */
  int depth;       /* 1..3 */
  const bsfit_allocator *a;
} bsfit__numarr;

bsfit_err bsfit__json_fail(bsfit__json *j, bsfit_err code, const char *what);
/* Next non-blank byte (not consumed), or -1 at the end. */
int bsfit__json_peek(bsfit__json *j);
/* Consumes c (after blanks), or fails with "expected 'c'". */
bsfit_err bsfit__json_expect(bsfit__json *j, char c);
/* A string; its decoded bytes go to dst (cap >= 1, truncated, NUL-terminated;
** \u escapes outside ASCII become '?'). */
bsfit_err bsfit__json_string(bsfit__json *j, char *dst, size_t cap);
/* A number; ENONFINITE when it overflows a double. */
bsfit_err bsfit__json_number(bsfit__json *j, double *x);
bsfit_err bsfit__json_bool(bsfit__json *j, int *b);
/* Any value, checked and thrown away (for unknown keys). */
bsfit_err bsfit__json_skip(bsfit__json *j);
/* An array of `depth` nesting levels of numbers, rectangular. The caller sets a->depth
** and a->a, zeroes the rest, and frees with bsfit__numarr_free. */
bsfit_err bsfit__json_numarray(bsfit__json *j, bsfit__numarr *a);
void bsfit__numarr_free(bsfit__numarr *a);
/* Only blanks may follow the document. */
bsfit_err bsfit__json_end(bsfit__json *j);

/* }====================================================================== */

#endif
