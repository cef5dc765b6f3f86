/*
** io_iges.c
** IGES 5.3 export of one curve (entity 126, rational B-spline curve) or one surface
** (entity 128, rational B-spline surface): fixed 80-column records in the Start,
** Global, Directory Entry, Parameter Data and Terminate sections.
*/
#define _POSIX_C_SOURCE 200809L

#include "io_internal.h"

#include <math.h>
#include <stdio.h>
#include <string.h>
#include <stdlib.h>

/* {====================================================================
** Records
** ===================================================================== */

/* Packs parameters into the data columns of one section, never splitting a parameter
** across records (IGES 5.3, 2.2.3). Global records use 72 columns; Parameter Data
** records use 64, then a blank and the entity's DE pointer in columns 66-72. */
typedef struct packer {
  bsfit__buf *out;
  char line[80];
  size_t used, width, seq;
  char letter;
  int de;
} packer;

static void pack_init(packer *k, bsfit__buf *out, char letter, size_t width, int de) {
  memset(k, 0, sizeof *k);
  k->out = out;
  k->letter = letter;
  k->width = width;
  k->de = de;
}

static void pack_flush(packer *k) {
  if (k->used == 0) return;
  k->seq++;
  if (k->letter == 'P')
    bsfit__buf_printf(k->out, "%-64.*s %7d%c%7zu\n", (int)k->used, k->line, k->de, k->letter,
                      k->seq);
  else
    bsfit__buf_printf(k->out, "%-72.*s%c%7zu\n", (int)k->used, k->line, k->letter, k->seq);
  k->used = 0;
}

/* One parameter followed by its delimiter (',' or ';'). */
static void pack(packer *k, const char *tok, char delim) {
  size_t n = strlen(tok);
  if (n + 1 > k->width) n = k->width - 1; /* cannot happen for the tokens written here */
  if (k->used + n + 1 > k->width) pack_flush(k);
  memcpy(k->line + k->used, tok, n);
  k->line[k->used + n] = delim;
  k->used += n + 1;
}

static void pack_int(packer *k, long v, char delim) {
  char t[32];
  snprintf(t, sizeof t, "%ld", v);
  pack(k, t, delim);
}

/* IGES reals need a decimal point: 1 -> "1.0", 1E+20 -> "1.0E+20". %.17G round-trips. */
static void pack_real(packer *k, double x, char delim) {
  char t[40], u[44], *e;
  snprintf(t, sizeof t, "%.17G", x);
  if (strchr(t, '.') == NULL) {
    e = strchr(t, 'E');
    if (e != NULL) {
      size_t head = (size_t)(e - t);
      memcpy(u, t, head);
      memcpy(u + head, ".0", 2);
      strcpy(u + head + 2, e);
    } else {
      snprintf(u, sizeof u, "%s.0", t);
    }
    pack(k, u, delim);
    return;
  }
  pack(k, t, delim);
}

static void pack_string(packer *k, const char *s, char delim) {
  char t[80];
  size_t n = strlen(s);
  if (n > 60) n = 60;
  snprintf(t, sizeof t, "%zuH%.*s", n, (int)n, s);
  pack(k, n ? t : "", delim);
}

/* }==================================================================== */

/* {====================================================================
** Sections
** ===================================================================== */

static size_t start_section(bsfit__buf *b, const char *what) {
  bsfit__buf_printf(b, "%-72.72s%c%7d\n", what, 'S', 1);
  return 1;
}

/* The file's date: SOURCE_DATE_EPOCH when set to a plain decimal count of seconds (the
** reproducible-builds convention: the same curve then gives the same bytes), else now. */
static void iges_date(char out[16]) {
  bsfit__exchange_time("%Y%m%d.%H%M%S", out, 16, "19700101.000000");
}

/* The 25 parameters of the Global section (IGES 5.3, 2.2.4.3); units millimetres. */
static size_t global_section(bsfit__buf *b, const char *file, double maxcoord) {
  packer k;
  char date[16];
  const char *base = strrchr(file, '/');
  iges_date(date);
  pack_init(&k, b, 'G', 72, 0);
  pack(&k, "1H,", ',');
  pack(&k, "1H;", ',');
  pack_string(&k, "bsfit", ',');
  pack_string(&k, base ? base + 1 : file, ',');
  pack_string(&k, "bsfit " BSFIT_VERSION, ',');
  pack_string(&k, "bsfit " BSFIT_VERSION, ',');
  pack_int(&k, 32, ',');
  pack_int(&k, 38, ',');
  pack_int(&k, 6, ',');
  pack_int(&k, 308, ',');
  pack_int(&k, 15, ',');
  pack_string(&k, "bsfit", ',');
  pack_real(&k, 1.0, ',');
  pack_int(&k, 2, ',');
  pack_string(&k, "MM", ',');
  pack_int(&k, 1, ',');
  pack_real(&k, 1.0, ',');
  pack_string(&k, date, ',');
  pack_real(&k, 1e-9, ',');
  pack_real(&k, maxcoord, ',');
  pack_string(&k, "", ',');
  pack_string(&k, "", ',');
  pack_int(&k, 11, ',');
  pack_int(&k, 0, ',');
  pack_string(&k, date, ';');
  pack_flush(&k);
  return k.seq;
}

/* Two DE records for the only entity, whose parameters take plines P records. */
static size_t directory_section(bsfit__buf *b, int type, size_t plines) {
  bsfit__buf_printf(b, "%8d%8d%8d%8d%8d%8d%8d%8d%8s%c%7d\n", type, 1, 0, 0, 0, 0, 0, 0,
                    "00000000", 'D', 1);
  bsfit__buf_printf(b, "%8d%8d%8d%8zu%8d%8s%8s%8s%8d%c%7d\n", type, 0, 0, plines, 0, "", "", "",
                    0, 'D', 2);
  return 2;
}

static void terminate_section(bsfit__buf *b, size_t ns, size_t ng, size_t nd, size_t np) {
  char t[80];
  snprintf(t, sizeof t, "S%7zuG%7zuD%7zuP%7zu", ns, ng, nd, np);
  bsfit__buf_printf(b, "%-72s%c%7d\n", t, 'T', 1);
}

/* Assembles the file around the Parameter Data records already in pd. */
static bsfit_err assemble(const char *file, double maxcoord, int type, bsfit__buf *pd,
                          size_t plines, char **out, size_t *len, const bsfit_allocator *a,
                          bsfit_status *st) {
  bsfit__buf b;
  size_t ns, ng, nd;
  bsfit__buf_init(&b, a);
  ns = start_section(&b, type == 126 ? "bsfit: rational B-spline curve (IGES entity 126)"
                                     : "bsfit: rational B-spline surface (IGES entity 128)");
  ng = global_section(&b, file, maxcoord);
  nd = directory_section(&b, type, plines);
  if (pd->failed) b.failed = 1;
  else bsfit__buf_putn(&b, pd->data, pd->len);
  terminate_section(&b, ns, ng, nd, plines);
  bsfit__buf_free(pd);
  return bsfit__buf_take(&b, out, len, st);
}

static double max_abs(const double *x, size_t n) {
  double m = 0.0;
  size_t i;
  for (i = 0; i < n; i++) m = fmax(m, fabs(x[i]));
  return m;
}

/* Cartesian (x, y, z) of a point of dim 1..3 (missing coordinates are 0). */
static void pack_xyz(packer *k, const double *P, int dim) {
  int t;
  for (t = 0; t < 3; t++) pack_real(k, t < dim ? P[t] : 0.0, ',');
}

/* }==================================================================== */

/* {====================================================================
** Entity 126: curve
** ===================================================================== */

static int curve_closed(const bsfit_curve *c) {
  double a, b, A[4], B[4], scale;
  int t;
  if (c->periodic) return 1;
  bsfit_curve_domain(c, &a, &b);
  bsfit__curve_eval_unchecked(c, a, A);
  bsfit__curve_eval_unchecked(c, b, B);
  scale = 1.0 + max_abs(c->ctrl, c->n * (size_t)c->dim);
  for (t = 0; t < c->dim; t++)
    if (fabs(A[t] - B[t]) > 1e-12 * scale) return 0;
  return 1;
}

static bsfit_err curve_iges(const bsfit_curve *c, const char *file, char **out, size_t *len,
                            const bsfit_allocator *a, bsfit_status *st) {
  bsfit__buf pd;
  packer k;
  size_t i, n;
  double u0, u1;
  bsfit_err e = bsfit_curve_validate(c, st);
  if (e != BSFIT_OK) return e;
  if (c->dim > 3) return bsfit__fail(st, BSFIT_EDIM, "IGES holds 1D..3D curves, got dim %d", c->dim);
  if (out == NULL) return bsfit__fail(st, BSFIT_EINVAL, "no output for the IGES text");
  n = c->n;
  bsfit__buf_init(&pd, a);
  pack_init(&k, &pd, 'P', 64, 1);
  pack_int(&k, 126, ',');
  pack_int(&k, (long)n - 1, ',');
  pack_int(&k, c->degree, ',');
  pack_int(&k, c->dim <= 2, ',');          /* PROP1 planar */
  pack_int(&k, curve_closed(c), ',');      /* PROP2 closed */
  pack_int(&k, c->weights == NULL, ',');   /* PROP3 polynomial */
  pack_int(&k, c->periodic != 0, ',');     /* PROP4 periodic */
  for (i = 0; i < n + (size_t)c->degree + 1; i++) pack_real(&k, c->knots[i], ',');
  for (i = 0; i < n; i++) pack_real(&k, c->weights ? c->weights[i] : 1.0, ',');
  for (i = 0; i < n; i++) pack_xyz(&k, c->ctrl + i * (size_t)c->dim, c->dim);
  bsfit_curve_domain(c, &u0, &u1);
  pack_real(&k, u0, ',');
  pack_real(&k, u1, ',');
  pack_real(&k, 0.0, ',');                 /* unit normal of the plane z = 0 */
  pack_real(&k, 0.0, ',');
  pack_real(&k, c->dim <= 2 ? 1.0 : 0.0, ';');
  pack_flush(&k);
  return assemble(file, max_abs(c->ctrl, n * (size_t)c->dim), 126, &pd, k.seq, out, len, a, st);
}

bsfit_err bsfit_curve_to_iges(const bsfit_curve *c, char **out, size_t *len,
                              const bsfit_allocator *a, bsfit_status *st) {
  return curve_iges(c, "bsfit.igs", out, len, a, st);
}

/* }==================================================================== */

/* {====================================================================
** Entity 128: surface
** ===================================================================== */

/* Closed in u when the first and last rows of the net coincide (v likewise). */
static int net_closed(const bsfit_surface *s, int along_u) {
  size_t i, t, d = (size_t)s->dim, n = along_u ? s->nv : s->nu;
  for (i = 0; i < n; i++) {
    size_t first = along_u ? i : i * s->nv;
    size_t last = along_u ? (s->nu - 1) * s->nv + i : i * s->nv + s->nv - 1;
    for (t = 0; t < d; t++)
      if (s->ctrl[first * d + t] != s->ctrl[last * d + t]) return 0;
    if (s->weights && s->weights[first] != s->weights[last]) return 0;
  }
  return 1;
}

static bsfit_err surface_iges(const bsfit_surface *s, const char *file, char **out, size_t *len,
                              const bsfit_allocator *a, bsfit_status *st) {
  bsfit__buf pd;
  packer k;
  size_t i, j;
  double ua, ub, va, vb;
  bsfit_err e = bsfit_surface_validate(s, st);
  if (e != BSFIT_OK) return e;
  if (s->dim > 3) return bsfit__fail(st, BSFIT_EDIM, "IGES holds 1D..3D surfaces, got dim %d", s->dim);
  if (out == NULL) return bsfit__fail(st, BSFIT_EINVAL, "no output for the IGES text");
  bsfit__buf_init(&pd, a);
  pack_init(&k, &pd, 'P', 64, 1);
  pack_int(&k, 128, ',');
  pack_int(&k, (long)s->nu - 1, ',');
  pack_int(&k, (long)s->nv - 1, ',');
  pack_int(&k, s->degree_u, ',');
  pack_int(&k, s->degree_v, ',');
  pack_int(&k, net_closed(s, 1), ',');     /* PROP1 closed in u */
  pack_int(&k, net_closed(s, 0), ',');     /* PROP2 closed in v */
  pack_int(&k, s->weights == NULL, ',');   /* PROP3 polynomial */
  /* PROP4, PROP5: not periodic. A surface periodic in u (periodic_u) goes out in its
  ** expanded form as an ordinary unclamped surface: flagged closed or periodic, it is
  ** made periodic by OpenCASCADE, wrongly when a knot of multiplicity p sits at the seam
  ** (tests/sh/test_exchange.sh, skinned_corners) */
  pack_int(&k, 0, ',');
  pack_int(&k, 0, ',');
  for (i = 0; i < s->nu + (size_t)s->degree_u + 1; i++) pack_real(&k, s->knots_u[i], ',');
  for (i = 0; i < s->nv + (size_t)s->degree_v + 1; i++) pack_real(&k, s->knots_v[i], ',');
  /* IGES runs the first (u) index fastest; our net runs j (v) fastest */
  for (j = 0; j < s->nv; j++)
    for (i = 0; i < s->nu; i++) pack_real(&k, s->weights ? s->weights[i * s->nv + j] : 1.0, ',');
  for (j = 0; j < s->nv; j++)
    for (i = 0; i < s->nu; i++) pack_xyz(&k, s->ctrl + (i * s->nv + j) * (size_t)s->dim, s->dim);
  bsfit_surface_domain(s, &ua, &ub, &va, &vb);
  pack_real(&k, ua, ',');
  pack_real(&k, ub, ',');
  pack_real(&k, va, ',');
  pack_real(&k, vb, ';');
  pack_flush(&k);
  return assemble(file, max_abs(s->ctrl, s->nu * s->nv * (size_t)s->dim), 128, &pd, k.seq, out,
                  len, a, st);
}

bsfit_err bsfit_surface_to_iges(const bsfit_surface *s, char **out, size_t *len,
                                const bsfit_allocator *a, bsfit_status *st) {
  return surface_iges(s, "bsfit.igs", out, len, a, st);
}

/* }==================================================================== */

bsfit_err bsfit_curve_write_iges(const bsfit_curve *c, const char *path, bsfit_status *st) {
  char *text = NULL;
  size_t len = 0;
  bsfit_err e;
  if (path == NULL) return bsfit__fail(st, BSFIT_EINVAL, "no file name to write to");
  e = curve_iges(c, path, &text, &len, NULL, st);
  return bsfit__exchange_write(e, text, len, path, st);
}

bsfit_err bsfit_surface_write_iges(const bsfit_surface *s, const char *path, bsfit_status *st) {
  char *text = NULL;
  size_t len = 0;
  bsfit_err e;
  if (path == NULL) return bsfit__fail(st, BSFIT_EINVAL, "no file name to write to");
  e = surface_iges(s, path, &text, &len, NULL, st);
  return bsfit__exchange_write(e, text, len, path, st);
}
