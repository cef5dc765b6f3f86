/*
** io_dxf.c
** DXF (AutoCAD R2000, AC1015) export of curves as SPLINE entities: the HEADER, TABLES,
** BLOCKS, ENTITIES and OBJECTS sections with the handles and owners an R2000 reader
** checks (ezdxf's auditor passes the files without fixes).
** Every curve is written clamped (io_clamp.c): DXF readers differ on unclamped knot
** vectors, and knot insertion gives the same curve, with the same parametrisation.
*/
#include "io_internal.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

/* {====================================================================
** Sections
** ===================================================================== */

/* Handles: fixed ones for the tables and blocks, then one per spline from FIRST_SPLINE. */
enum {
  H_LTYPE_TABLE = 1, H_BYBLOCK, H_BYLAYER, H_CONTINUOUS, H_LAYER_TABLE, H_LAYER0,
  H_STYLE_TABLE, H_STANDARD, H_BR_TABLE, H_BR_MODEL, H_BR_PAPER, H_BLOCK_MODEL, H_ENDBLK_MODEL,
  H_BLOCK_PAPER, H_ENDBLK_PAPER, H_ROOT_DICT, H_GROUP_DICT, H_APPID_TABLE, H_APPID_ACAD,
  H_VPORT_TABLE, H_VIEW_TABLE, H_UCS_TABLE, H_DIMSTYLE_TABLE, FIRST_SPLINE
};

static void code(bsfit__buf *b, int gc, const char *value) {
  bsfit__buf_printf(b, "%3d\n%s\n", gc, value);
}

static void code_int(bsfit__buf *b, int gc, long v) { bsfit__buf_printf(b, "%3d\n%ld\n", gc, v); }

static void code_hex(bsfit__buf *b, int gc, long h) { bsfit__buf_printf(b, "%3d\n%lX\n", gc, h); }

static void code_real(bsfit__buf *b, int gc, double x) {
  bsfit__buf_printf(b, "%3d\n%.17g\n", gc, x);
}

static void header(bsfit__buf *b, long handseed) {
  code(b, 0, "SECTION");
  code(b, 2, "HEADER");
  code(b, 9, "$ACADVER");
  code(b, 1, "AC1015");
  code(b, 9, "$HANDSEED");
  code_hex(b, 5, handseed);
  code(b, 9, "$INSUNITS");
  code_int(b, 70, 4); /* millimetres, as the IGES and STEP writers say */
  code(b, 0, "ENDSEC");
}

/* The head of a symbol table and of its records. */
static void table(bsfit__buf *b, const char *name, long h, int count) {
  code(b, 0, "TABLE");
  code(b, 2, name);
  code_hex(b, 5, h);
  code_hex(b, 330, 0);
  code(b, 100, "AcDbSymbolTable");
  code_int(b, 70, count);
}

static void record(bsfit__buf *b, const char *type, long h, long owner, const char *subclass,
                   const char *name) {
  code(b, 0, type);
  code_hex(b, type[0] == 'D' ? 105 : 5, h);
  code_hex(b, 330, owner);
  code(b, 100, "AcDbSymbolTableRecord");
  code(b, 100, subclass);
  code(b, 2, name);
  code_int(b, 70, 0);
}

static void linetype(bsfit__buf *b, long h, const char *name, const char *what) {
  record(b, "LTYPE", h, H_LTYPE_TABLE, "AcDbLinetypeTableRecord", name);
  code(b, 3, what);
  code_int(b, 72, 65);
  code_int(b, 73, 0);
  code_real(b, 40, 0.0);
}

/* A table with no records (AutoCAD expects all nine tables, in this order). */
static void empty_table(bsfit__buf *b, const char *name, long h) {
  table(b, name, h, 0);
  if (strcmp(name, "DIMSTYLE") == 0) code(b, 100, "AcDbDimStyleTable");
  code(b, 0, "ENDTAB");
}

static void tables(bsfit__buf *b) {
  code(b, 0, "SECTION");
  code(b, 2, "TABLES");
  empty_table(b, "VPORT", H_VPORT_TABLE);
  table(b, "LTYPE", H_LTYPE_TABLE, 3);
  linetype(b, H_BYBLOCK, "ByBlock", "");
  linetype(b, H_BYLAYER, "ByLayer", "");
  linetype(b, H_CONTINUOUS, "Continuous", "Solid line");
  code(b, 0, "ENDTAB");
  table(b, "LAYER", H_LAYER_TABLE, 1);
  record(b, "LAYER", H_LAYER0, H_LAYER_TABLE, "AcDbLayerTableRecord", "0");
  code_int(b, 62, 7);
  code(b, 6, "Continuous");
  code(b, 0, "ENDTAB");
  table(b, "STYLE", H_STYLE_TABLE, 1);
  record(b, "STYLE", H_STANDARD, H_STYLE_TABLE, "AcDbTextStyleTableRecord", "Standard");
  code_real(b, 40, 0.0);
  code_real(b, 41, 1.0);
  code_real(b, 50, 0.0);
  code_int(b, 71, 0);
  code_real(b, 42, 2.5);
  code(b, 3, "txt");
  code(b, 4, "");
  code(b, 0, "ENDTAB");
  empty_table(b, "VIEW", H_VIEW_TABLE);
  empty_table(b, "UCS", H_UCS_TABLE);
  table(b, "APPID", H_APPID_TABLE, 1);
  record(b, "APPID", H_APPID_ACAD, H_APPID_TABLE, "AcDbRegAppTableRecord", "ACAD");
  code(b, 0, "ENDTAB");
  empty_table(b, "DIMSTYLE", H_DIMSTYLE_TABLE);
  table(b, "BLOCK_RECORD", H_BR_TABLE, 2);
  record(b, "BLOCK_RECORD", H_BR_MODEL, H_BR_TABLE, "AcDbBlockTableRecord", "*Model_Space");
  record(b, "BLOCK_RECORD", H_BR_PAPER, H_BR_TABLE, "AcDbBlockTableRecord", "*Paper_Space");
  code(b, 0, "ENDTAB");
  code(b, 0, "ENDSEC");
}

static void block(bsfit__buf *b, const char *name, long h, long hend, long owner) {
  code(b, 0, "BLOCK");
  code_hex(b, 5, h);
  code_hex(b, 330, owner);
  code(b, 100, "AcDbEntity");
  code(b, 8, "0");
  code(b, 100, "AcDbBlockBegin");
  code(b, 2, name);
  code_int(b, 70, 0);
  code_real(b, 10, 0.0);
  code_real(b, 20, 0.0);
  code_real(b, 30, 0.0);
  code(b, 3, name);
  code(b, 1, "");
  code(b, 0, "ENDBLK");
  code_hex(b, 5, hend);
  code_hex(b, 330, owner);
  code(b, 100, "AcDbEntity");
  code(b, 8, "0");
  code(b, 100, "AcDbBlockEnd");
}

static void blocks(bsfit__buf *b) {
  code(b, 0, "SECTION");
  code(b, 2, "BLOCKS");
  block(b, "*Model_Space", H_BLOCK_MODEL, H_ENDBLK_MODEL, H_BR_MODEL);
  block(b, "*Paper_Space", H_BLOCK_PAPER, H_ENDBLK_PAPER, H_BR_PAPER);
  code(b, 0, "ENDSEC");
}

static void objects(bsfit__buf *b) {
  code(b, 0, "SECTION");
  code(b, 2, "OBJECTS");
  code(b, 0, "DICTIONARY");
  code_hex(b, 5, H_ROOT_DICT);
  code_hex(b, 330, 0);
  code(b, 100, "AcDbDictionary");
  code_int(b, 281, 1);
  code(b, 3, "ACAD_GROUP");
  code_hex(b, 350, H_GROUP_DICT);
  code(b, 0, "DICTIONARY");
  code_hex(b, 5, H_GROUP_DICT);
  code_hex(b, 330, H_ROOT_DICT);
  code(b, 100, "AcDbDictionary");
  code_int(b, 281, 1);
  code(b, 0, "ENDSEC");
}

/* }==================================================================== */

/* {====================================================================
** SPLINE
** ===================================================================== */

/* Non-zero when every control point has z == 0 (or the curve is 2D): a planar spline. */
static int planar(const bsfit_curve *c) {
  size_t i;
  if (c->dim == 2) return 1;
  for (i = 0; i < c->n; i++)
    if (c->ctrl[i * 3 + 2] != 0.0) return 0;
  return 1;
}

/* One SPLINE of the clamped curve k; closed says whether the original was periodic. */
static void spline(bsfit__buf *b, const bsfit_curve *k, long h, int closed) {
  size_t i, nk = k->n + (size_t)k->degree + 1, d = (size_t)k->dim;
  int flags = (closed ? 1 : 0) | (k->weights ? 4 : 0) | (planar(k) ? 8 : 0) |
              (k->degree == 1 ? 16 : 0);
  code(b, 0, "SPLINE");
  code_hex(b, 5, h);
  code_hex(b, 330, H_BR_MODEL);
  code(b, 100, "AcDbEntity");
  code(b, 8, "0");
  code(b, 100, "AcDbSpline");
  if (flags & 8) {
    code_real(b, 210, 0.0);
    code_real(b, 220, 0.0);
    code_real(b, 230, 1.0);
  }
  code_int(b, 70, flags);
  code_int(b, 71, k->degree);
  code_int(b, 72, (long)nk);
  code_int(b, 73, (long)k->n);
  code_int(b, 74, 0);
  code_real(b, 42, 1e-10);
  code_real(b, 43, 1e-10);
  for (i = 0; i < nk; i++) code_real(b, 40, k->knots[i]);
  for (i = 0; k->weights && i < k->n; i++) code_real(b, 41, k->weights[i]);
  for (i = 0; i < k->n; i++) {
    code_real(b, 10, k->ctrl[i * d]);
    code_real(b, 20, k->ctrl[i * d + 1]);
    code_real(b, 30, d == 3 ? k->ctrl[i * d + 2] : 0.0);
  }
}

static bsfit_err check_curve(const bsfit_curve *c, size_t k, bsfit_status *st) {
  return bsfit__exchange_check_curve(c, k, "DXF", "DXF splines", st);
}

bsfit_err bsfit_curves_to_dxf(const bsfit_curve *const *c, size_t n, char **out, size_t *len,
                              const bsfit_allocator *a, bsfit_status *st) {
  bsfit__buf b;
  size_t k;
  bsfit_err e;
  if (c == NULL || n == 0) return bsfit__fail(st, BSFIT_EINVAL, "no curves to write");
  if (out == NULL) return bsfit__fail(st, BSFIT_EINVAL, "no output for the DXF text");
  for (k = 0; k < n; k++)
    if ((e = check_curve(c[k], k, st)) != BSFIT_OK) return e;
  bsfit__buf_init(&b, a);
  header(&b, FIRST_SPLINE + (long)n);
  tables(&b);
  blocks(&b);
  code(&b, 0, "SECTION");
  code(&b, 2, "ENTITIES");
  for (k = 0; k < n; k++) {
    bsfit_curve cl;
    bsfit_curve_init(&cl);
    e = bsfit__curve_clamped(c[k], &cl, a, st);
    if (e != BSFIT_OK) {
      bsfit_curve_free(&cl);
      bsfit__buf_free(&b);
      return e;
    }
    spline(&b, &cl, FIRST_SPLINE + (long)k, c[k]->periodic);
    bsfit_curve_free(&cl);
  }
  code(&b, 0, "ENDSEC");
  objects(&b);
  code(&b, 0, "EOF");
  return bsfit__buf_take(&b, out, len, st);
}

bsfit_err bsfit_curves_write_dxf(const bsfit_curve *const *c, size_t n, const char *path,
                                 bsfit_status *st) {
  char *text = NULL;
  size_t len = 0;
  bsfit_err e;
  if (path == NULL) return bsfit__fail(st, BSFIT_EINVAL, "no file name to write to");
  e = bsfit_curves_to_dxf(c, n, &text, &len, NULL, st);
  return bsfit__exchange_write(e, text, len, path, st);
}

/* }==================================================================== */
