/*
** io_iges_set.c
** One IGES file holding several curves (the sections of a scan): each curve is
** formatted alone by bsfit_curve_to_iges, then the files are merged: the Start and
** Global sections of the curve with the largest coordinates (the Global section states
** the largest coordinate), the Directory Entry and Parameter Data records of every
** curve renumbered in turn, and a Terminate record with the new counts.
*/
#include "io_internal.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

#define REC 81 /* 80 columns and a newline */

/* Overwrites columns [c0, c0+w) (0-based) of a record with a right-aligned number. */
static void put_num(char *rec, size_t c0, int w, size_t v) {
  char f[32];
  snprintf(f, sizeof f, "%*zu", w, v % 10000000u); /* 7 digits: the IGES field width */
  memcpy(rec + c0, f, (size_t)w);
}

/* Appends the records of section `letter` of text t (renumbered by the caller). */
static size_t count_section(const char *t, size_t len, char letter) {
  size_t i, n = 0;
  for (i = 0; i + REC <= len; i += REC)
    if (t[i + 72] == letter) n++;
  return n;
}

static double curve_size(const bsfit_curve *c) {
  double m = 0;
  size_t i;
  for (i = 0; i < c->n * (size_t)c->dim; i++) m = fmax(m, fabs(c->ctrl[i]));
  return m;
}

/* The D and P records of curve j (text t) appended to d and p. */
static void entity_records(const char *t, size_t len, size_t j, size_t *pline, bsfit__buf *d,
                           bsfit__buf *p) {
  char rec[REC];
  size_t i, dl = 0, first = *pline + 1;
  for (i = 0; i + REC <= len; i += REC) {
    memcpy(rec, t + i, REC);
    if (rec[72] == 'D') {
      if (dl == 0) put_num(rec, 8, 8, first); /* field 2: the first P record */
      put_num(rec, 73, 7, 2 * j + 1 + dl++);
      bsfit__buf_putn(d, rec, REC);
    } else if (rec[72] == 'P') {
      put_num(rec, 65, 7, 2 * j + 1); /* the entity's DE pointer */
      put_num(rec, 73, 7, ++*pline);
      bsfit__buf_putn(p, rec, REC);
    }
  }
}

static bsfit_err merge(char **texts, size_t *lens, size_t n, size_t head, char **out, size_t *len,
                       const bsfit_allocator *a, bsfit_status *st) {
  bsfit__buf b, d, p;
  size_t i, j, pline = 0, ns, ng;
  char t[80];
  bsfit__buf_init(&b, a);
  bsfit__buf_init(&d, a);
  bsfit__buf_init(&p, a);
  for (i = 0; i + REC <= lens[head]; i += REC)
    if (texts[head][i + 72] == 'S' || texts[head][i + 72] == 'G')
      bsfit__buf_putn(&b, texts[head] + i, REC);
  ns = count_section(texts[head], lens[head], 'S');
  ng = count_section(texts[head], lens[head], 'G');
  for (j = 0; j < n; j++) entity_records(texts[j], lens[j], j, &pline, &d, &p);
  if (d.failed || p.failed)
    b.failed = 1;
  else {
    bsfit__buf_putn(&b, d.data, d.len);
    bsfit__buf_putn(&b, p.data, p.len);
  }
  snprintf(t, sizeof t, "S%7zuG%7zuD%7zuP%7zu", ns, ng, 2 * n, pline);
  bsfit__buf_printf(&b, "%-72s%c%7d\n", t, 'T', 1);
  bsfit__buf_free(&d);
  bsfit__buf_free(&p);
  return bsfit__buf_take(&b, out, len, st);
}

bsfit_err bsfit_curves_to_iges(const bsfit_curve *const *c, size_t n, char **out, size_t *len,
                               const bsfit_allocator *a, bsfit_status *st) {
  char **texts;
  size_t *lens, j, head = 0;
  bsfit_err e = BSFIT_OK;
  if (c == NULL || n == 0 || out == NULL || len == NULL)
    return bsfit__fail(st, BSFIT_EINVAL, "no curves to write");
  texts = bsfit__alloc(a, bsfit__mulsize(n, sizeof(char *)));
  lens = bsfit__alloc(a, bsfit__mulsize(n, sizeof(size_t)));
  if (texts == NULL || lens == NULL) {
    bsfit__free(a, texts, n * sizeof(char *));
    bsfit__free(a, lens, n * sizeof(size_t));
    return bsfit__fail(st, BSFIT_ENOMEM, "out of memory (IGES)");
  }
  memset(texts, 0, n * sizeof(char *));
  memset(lens, 0, n * sizeof(size_t));
  for (j = 0; j < n && e == BSFIT_OK; j++) {
    if (c[j] == NULL)
      e = bsfit__fail(st, BSFIT_EINVAL, "curve %zu is missing", j + 1);
    else
      e = bsfit_curve_to_iges(c[j], &texts[j], &lens[j], a, st);
    if (e == BSFIT_OK && curve_size(c[j]) > curve_size(c[head])) head = j;
  }
  if (e == BSFIT_OK) e = merge(texts, lens, n, head, out, len, a, st);
  for (j = 0; j < n; j++) bsfit__free(a, texts[j], lens[j] + 1);
  bsfit__free(a, texts, n * sizeof(char *));
  bsfit__free(a, lens, n * sizeof(size_t));
  return e;
}

bsfit_err bsfit_curves_write_iges(const bsfit_curve *const *c, size_t n, const char *path,
                                  bsfit_status *st) {
  char *text = NULL;
  size_t len = 0;
  bsfit_err e = bsfit_curves_to_iges(c, n, &text, &len, NULL, st);
  return bsfit__exchange_write(e, text, len, path, st);
}
