/*
** io_step.c
** STEP (ISO 10303-21, schema AP214 "automotive_design") export of curves and surfaces:
** B_SPLINE_CURVE_WITH_KNOTS / B_SPLINE_SURFACE_WITH_KNOTS, and for rational ones the
** complex instances with RATIONAL_B_SPLINE_CURVE / _SURFACE. The geometry sits in a
** wireframe (curves: GEOMETRIC_CURVE_SET) or surface (GEOMETRIC_SET) shape
** representation attached to one product, which is what a CAD reader (OpenCASCADE's
** STEPControl_Reader among them) looks for when it transfers a file.
*/
#define _POSIX_C_SOURCE 200809L

#include "io_internal.h"

#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* {====================================================================
** Tokens and entities
** ===================================================================== */

/* A file being written: its text and the next free entity number. */
typedef struct step {
  bsfit__buf b;
  long next;
} step;

/* Starts entity #n and returns n. */
static long entity(step *s, const char *fmt, ...) BSFIT_PRINTF(2, 3);

static long entity(step *s, const char *fmt, ...) {
  char small[512];
  va_list ap;
  long id = s->next++;
  int n;
  va_start(ap, fmt);
  n = vsnprintf(small, sizeof small, fmt, ap);
  va_end(ap);
  if (n < 0 || (size_t)n >= sizeof small) s->b.failed = 1; /* only short fixed texts come here */
  else bsfit__buf_printf(&s->b, "#%ld=%s\n", id, small);
  return id;
}

/* A STEP real needs a decimal point before the exponent: 1 -> "1.", 1E+20 -> "1.E+20".
** %.17G gives back the same double. */
static void put_real(bsfit__buf *b, double x) {
  char t[40];
  char *e;
  snprintf(t, sizeof t, "%.17G", x);
  if (strchr(t, '.') != NULL) {
    bsfit__buf_puts(b, t);
    return;
  }
  e = strchr(t, 'E');
  if (e == NULL) {
    bsfit__buf_printf(b, "%s.", t);
    return;
  }
  bsfit__buf_putn(b, t, (size_t)(e - t));
  bsfit__buf_printf(b, ".%s", e);
}

/* A CARTESIAN_POINT of a point of dim 2 or 3 (z = 0 for 2D); returns its number. */
static long point(step *s, const double *P, int dim) {
  long id = s->next++;
  int t;
  bsfit__buf_printf(&s->b, "#%ld=CARTESIAN_POINT('',(", id);
  for (t = 0; t < 3; t++) {
    if (t) bsfit__buf_puts(&s->b, ",");
    put_real(&s->b, t < dim ? P[t] : 0.0);
  }
  bsfit__buf_puts(&s->b, "));\n");
  return id;
}

/* "(#a,#b,...)" for count consecutive entity numbers from first. */
static void put_refs(bsfit__buf *b, long first, size_t count) {
  size_t i;
  bsfit__buf_puts(b, "(");
  for (i = 0; i < count; i++) bsfit__buf_printf(b, i ? ",#%ld" : "#%ld", first + (long)i);
  bsfit__buf_puts(b, ")");
}

/* "(m1,m2,...)": the multiplicities of the distinct knots of U. */
static void put_mults(bsfit__buf *b, const double *U, size_t nk) {
  size_t i, j;
  bsfit__buf_puts(b, "(");
  for (i = 0; i < nk; i = j) {
    for (j = i + 1; j < nk && U[j] == U[i]; j++) continue;
    bsfit__buf_printf(b, i ? ",%zu" : "%zu", j - i);
  }
  bsfit__buf_puts(b, ")");
}

/* "(k1,k2,...)": the distinct knots of U. */
static void put_distinct(bsfit__buf *b, const double *U, size_t nk) {
  size_t i, j;
  bsfit__buf_puts(b, "(");
  for (i = 0; i < nk; i = j) {
    for (j = i + 1; j < nk && U[j] == U[i]; j++) continue;
    if (i) bsfit__buf_puts(b, ",");
    put_real(b, U[i]);
  }
  bsfit__buf_puts(b, ")");
}

/* "(m1,...),(k1,...)": STEP's knot_multiplicities and knots. */
static void put_knots(bsfit__buf *b, const double *U, size_t nk) {
  put_mults(b, U, nk);
  bsfit__buf_puts(b, ",");
  put_distinct(b, U, nk);
}

static void put_reals(bsfit__buf *b, const double *x, size_t n, size_t stride) {
  size_t i;
  bsfit__buf_puts(b, "(");
  for (i = 0; i < n; i++) {
    if (i) bsfit__buf_puts(b, ",");
    put_real(b, x[i * stride]);
  }
  bsfit__buf_puts(b, ")");
}

/* }==================================================================== */

/* {====================================================================
** Header, context and product
** ===================================================================== */

/* The time of writing as ISO 8601, or SOURCE_DATE_EPOCH (seconds since 1970, UTC)
** when set to a plain decimal number: the same geometry then gives the same bytes. */
static void step_time(char out[32]) {
  bsfit__exchange_time("%Y-%m-%dT%H:%M:%S", out, 32, "1970-01-01T00:00:00");
}

/* Part 21 strings: a quote is doubled; bytes outside printable ASCII become '_'. */
static void put_string(bsfit__buf *b, const char *s) {
  bsfit__buf_puts(b, "'");
  for (; *s; s++) {
    unsigned char ch = (unsigned char)*s;
    if (ch == '\'') bsfit__buf_puts(b, "''");
    else if (ch == '\\') bsfit__buf_puts(b, "\\\\");
    else bsfit__buf_putn(b, ch >= 32 && ch < 127 ? s : "_", 1);
  }
  bsfit__buf_puts(b, "'");
}

static void header(step *s, const char *file, const char *what) {
  char when[32];
  const char *base = strrchr(file, '/');
  step_time(when);
  bsfit__buf_puts(&s->b, "ISO-10303-21;\nHEADER;\nFILE_DESCRIPTION((");
  put_string(&s->b, what);
  bsfit__buf_puts(&s->b, "),'2;1');\nFILE_NAME(");
  put_string(&s->b, base ? base + 1 : file);
  bsfit__buf_printf(&s->b, ",'%s',(''),(''),'bsfit " BSFIT_VERSION "','bsfit " BSFIT_VERSION
                           "','');\n", when);
  bsfit__buf_puts(&s->b, "FILE_SCHEMA(('AUTOMOTIVE_DESIGN { 1 0 10303 214 1 1 1 1 }'));\n"
                         "ENDSEC;\nDATA;\n");
}

/* Units (millimetre, radian, steradian) and the 3D geometric context; returns the
** context's number. */
static long context(step *s) {
  long mm = entity(s, "(LENGTH_UNIT()NAMED_UNIT(*)SI_UNIT(.MILLI.,.METRE.));");
  long rad = entity(s, "(NAMED_UNIT(*)PLANE_ANGLE_UNIT()SI_UNIT($,.RADIAN.));");
  long sr = entity(s, "(NAMED_UNIT(*)SI_UNIT($,.STERADIAN.)SOLID_ANGLE_UNIT());");
  long unc = entity(s, "UNCERTAINTY_MEASURE_WITH_UNIT(LENGTH_MEASURE(1.E-07),#%ld,"
                       "'distance_accuracy_value','confusion accuracy');", mm);
  return entity(s, "(GEOMETRIC_REPRESENTATION_CONTEXT(3)GLOBAL_UNCERTAINTY_ASSIGNED_CONTEXT("
                   "(#%ld))GLOBAL_UNIT_ASSIGNED_CONTEXT((#%ld,#%ld,#%ld))REPRESENTATION_CONTEXT("
                   "'',''));", unc, mm, rad, sr);
}

/* The product the representation `rep` is the shape of (AP214's minimum), then the
** end of the file. */
static void product(step *s, long rep) {
  long app = entity(s, "APPLICATION_CONTEXT('core data for automotive mechanical design "
                       "processes');");
  long pc, pdc, prod, pdf, pd, pds;
  entity(s, "APPLICATION_PROTOCOL_DEFINITION('international standard','automotive_design',"
            "2000,#%ld);", app);
  pc = entity(s, "PRODUCT_CONTEXT('',#%ld,'mechanical');", app);
  pdc = entity(s, "PRODUCT_DEFINITION_CONTEXT('part definition',#%ld,'design');", app);
  prod = entity(s, "PRODUCT('bsfit','bsfit','',(#%ld));", pc);
  entity(s, "PRODUCT_RELATED_PRODUCT_CATEGORY('part',$,(#%ld));", prod);
  pdf = entity(s, "PRODUCT_DEFINITION_FORMATION('','',#%ld);", prod);
  pd = entity(s, "PRODUCT_DEFINITION('design','',#%ld,#%ld);", pdf, pdc);
  pds = entity(s, "PRODUCT_DEFINITION_SHAPE('','',#%ld);", pd);
  entity(s, "SHAPE_DEFINITION_REPRESENTATION(#%ld,#%ld);", pds, rep);
  bsfit__buf_puts(&s->b, "ENDSEC;\nEND-ISO-10303-21;\n");
}

/* }==================================================================== */

/* {====================================================================
** Curves
** ===================================================================== */

static bsfit_err check_curve(const bsfit_curve *c, size_t k, bsfit_status *st) {
  return bsfit__exchange_check_curve(c, k, "STEP", "STEP B-spline curves", st);
}

/* One clamped curve (its points, then the curve); returns the curve's number. closed:
** the original was periodic (closed_curve .T.). */
static long curve(step *s, const bsfit_curve *c, size_t k, int periodic) {
  size_t i, nk = c->n + (size_t)c->degree + 1;
  long first = s->next, id;
  const char *closed = periodic ? ".T." : ".F.";
  for (i = 0; i < c->n; i++) point(s, c->ctrl + i * (size_t)c->dim, c->dim);
  id = s->next++;
  if (c->weights == NULL) {
    bsfit__buf_printf(&s->b, "#%ld=B_SPLINE_CURVE_WITH_KNOTS('curve %zu',%d,", id, k,
                      c->degree);
    put_refs(&s->b, first, c->n);
    bsfit__buf_printf(&s->b, ",.UNSPECIFIED.,%s,.F.,", closed);
    put_knots(&s->b, c->knots, nk);
    bsfit__buf_puts(&s->b, ",.UNSPECIFIED.);\n");
    return id;
  }
  /* a complex instance: the leaf types listed in alphabetical order (Part 21, 11.2.5) */
  bsfit__buf_printf(&s->b, "#%ld=(BOUNDED_CURVE()B_SPLINE_CURVE(%d,", id, c->degree);
  put_refs(&s->b, first, c->n);
  bsfit__buf_printf(&s->b, ",.UNSPECIFIED.,%s,.F.)B_SPLINE_CURVE_WITH_KNOTS(", closed);
  put_knots(&s->b, c->knots, nk);
  bsfit__buf_puts(&s->b, ",.UNSPECIFIED.)CURVE()GEOMETRIC_REPRESENTATION_ITEM()"
                         "RATIONAL_B_SPLINE_CURVE(");
  put_reals(&s->b, c->weights, c->n, 1);
  bsfit__buf_printf(&s->b, ")REPRESENTATION_ITEM('curve %zu'));\n", k);
  return id;
}

bsfit_err bsfit_curves_to_step(const bsfit_curve *const *c, size_t n, const char *name,
                               char **out, size_t *len, const bsfit_allocator *a,
                               bsfit_status *st) {
  step s;
  long ctx, set, rep, *ids;
  size_t k;
  bsfit_err e;
  if (c == NULL || n == 0) return bsfit__fail(st, BSFIT_EINVAL, "no curves to write");
  if (out == NULL) return bsfit__fail(st, BSFIT_EINVAL, "no output for the STEP text");
  for (k = 0; k < n; k++)
    if ((e = check_curve(c[k], k, st)) != BSFIT_OK) return e;
  ids = bsfit__alloc(a, bsfit__mulsize(n, sizeof *ids));
  if (ids == NULL) return bsfit__fail(st, BSFIT_ENOMEM, "out of memory for %zu curves", n);
  bsfit__buf_init(&s.b, a);
  s.next = 1;
  header(&s, name ? name : "bsfit.step", "bsfit: B-spline curves");
  ctx = context(&s);
  for (k = 0; k < n && e == BSFIT_OK; k++) {
    /* clamped (io_clamp.c): OCCT misreads closed unclamped curves with a knot of
    ** multiplicity p at the seam, and no reader is unsure about clamped ones */
    bsfit_curve cl;
    bsfit_curve_init(&cl);
    e = bsfit__curve_clamped(c[k], &cl, a, st);
    if (e == BSFIT_OK) ids[k] = curve(&s, &cl, k, c[k]->periodic);
    bsfit_curve_free(&cl);
  }
  if (e != BSFIT_OK) {
    bsfit__free(a, ids, n * sizeof *ids);
    bsfit__buf_free(&s.b);
    return e;
  }
  set = s.next++;
  bsfit__buf_printf(&s.b, "#%ld=GEOMETRIC_CURVE_SET('curves',(", set);
  for (k = 0; k < n; k++) bsfit__buf_printf(&s.b, k ? ",#%ld" : "#%ld", ids[k]);
  bsfit__buf_puts(&s.b, "));\n");
  bsfit__free(a, ids, n * sizeof *ids);
  rep = entity(&s, "GEOMETRICALLY_BOUNDED_WIREFRAME_SHAPE_REPRESENTATION('bsfit',(#%ld),#%ld);",
               set, ctx);
  product(&s, rep);
  return bsfit__buf_take(&s.b, out, len, st);
}

/* }==================================================================== */

/* {====================================================================
** Surfaces
** ===================================================================== */

/* The control net as a list of rows (outer index u, as STEP's control_points_list),
** after the points themselves. */
static void surface_net(step *s, const bsfit_surface *S, long first) {
  size_t i;
  bsfit__buf_puts(&s->b, "(");
  for (i = 0; i < S->nu; i++) {
    if (i) bsfit__buf_puts(&s->b, ",");
    put_refs(&s->b, first + (long)(i * S->nv), S->nv);
  }
  bsfit__buf_puts(&s->b, ")");
}

/* "(mults_u),(mults_v),(knots_u),(knots_v)" as B_SPLINE_SURFACE_WITH_KNOTS lists them. */
static void surface_knots(step *s, const bsfit_surface *S) {
  size_t nku = S->nu + (size_t)S->degree_u + 1, nkv = S->nv + (size_t)S->degree_v + 1;
  put_mults(&s->b, S->knots_u, nku);
  bsfit__buf_puts(&s->b, ",");
  put_mults(&s->b, S->knots_v, nkv);
  bsfit__buf_puts(&s->b, ",");
  put_distinct(&s->b, S->knots_u, nku);
  bsfit__buf_puts(&s->b, ",");
  put_distinct(&s->b, S->knots_v, nkv);
}

/* One clamped surface; returns its number. uclosed: the original was periodic in u. */
static long surface(step *s, const bsfit_surface *S, int periodic_u) {
  size_t i, np = S->nu * S->nv;
  long first = s->next, id;
  const char *uclosed = periodic_u ? ".T." : ".F.";
  for (i = 0; i < np; i++) point(s, S->ctrl + i * (size_t)S->dim, S->dim);
  id = s->next++;
  if (S->weights == NULL) {
    bsfit__buf_printf(&s->b, "#%ld=B_SPLINE_SURFACE_WITH_KNOTS('surface',%d,%d,", id,
                      S->degree_u, S->degree_v);
    surface_net(s, S, first);
    bsfit__buf_printf(&s->b, ",.UNSPECIFIED.,%s,.F.,.F.,", uclosed);
    surface_knots(s, S);
    bsfit__buf_puts(&s->b, ",.UNSPECIFIED.);\n");
    return id;
  }
  bsfit__buf_printf(&s->b, "#%ld=(BOUNDED_SURFACE()B_SPLINE_SURFACE(%d,%d,", id, S->degree_u,
                    S->degree_v);
  surface_net(s, S, first);
  bsfit__buf_printf(&s->b, ",.UNSPECIFIED.,%s,.F.,.F.)B_SPLINE_SURFACE_WITH_KNOTS(", uclosed);
  surface_knots(s, S);
  bsfit__buf_puts(&s->b, ",.UNSPECIFIED.)GEOMETRIC_REPRESENTATION_ITEM()"
                         "RATIONAL_B_SPLINE_SURFACE((");
  for (i = 0; i < S->nu; i++) {
    if (i) bsfit__buf_puts(&s->b, ",");
    put_reals(&s->b, S->weights + i * S->nv, S->nv, 1);
  }
  bsfit__buf_puts(&s->b, "))REPRESENTATION_ITEM('surface')SURFACE());\n");
  return id;
}

bsfit_err bsfit_surface_to_step(const bsfit_surface *S, const char *name, char **out,
                                size_t *len, const bsfit_allocator *a, bsfit_status *st) {
  step s;
  long ctx, id, set, rep;
  bsfit_surface cl;
  bsfit_err e;
  if (S == NULL) return bsfit__fail(st, BSFIT_EINVAL, "no surface to write");
  if (out == NULL) return bsfit__fail(st, BSFIT_EINVAL, "no output for the STEP text");
  if ((e = bsfit_surface_validate(S, st)) != BSFIT_OK) return e;
  if (S->dim < 2 || S->dim > 3)
    return bsfit__fail(st, BSFIT_EDIM, "STEP holds 2D and 3D surfaces, got dim %d", S->dim);
  if (S->degree_u < 1 || S->degree_v < 1)
    return bsfit__fail(st, BSFIT_EDEGREE, "STEP B-spline surfaces have degrees >= 1, got "
                                          "(%d, %d)", S->degree_u, S->degree_v);
  bsfit__buf_init(&s.b, a);
  s.next = 1;
  header(&s, name ? name : "bsfit.step", "bsfit: B-spline surface");
  ctx = context(&s);
  bsfit_surface_init(&cl);
  e = bsfit__surface_clamped(S, &cl, a, st);
  if (e != BSFIT_OK) {
    bsfit__buf_free(&s.b);
    return e;
  }
  id = surface(&s, &cl, S->periodic_u);
  bsfit_surface_free(&cl);
  set = entity(&s, "GEOMETRIC_SET('surface',(#%ld));", id);
  rep = entity(&s, "GEOMETRICALLY_BOUNDED_SURFACE_SHAPE_REPRESENTATION('bsfit',(#%ld),#%ld);",
               set, ctx);
  product(&s, rep);
  return bsfit__buf_take(&s.b, out, len, st);
}

/* }==================================================================== */

bsfit_err bsfit_curves_write_step(const bsfit_curve *const *c, size_t n, const char *path,
                                  bsfit_status *st) {
  char *text = NULL;
  size_t len = 0;
  bsfit_err e;
  if (path == NULL) return bsfit__fail(st, BSFIT_EINVAL, "no file name to write to");
  e = bsfit_curves_to_step(c, n, path, &text, &len, NULL, st);
  return bsfit__exchange_write(e, text, len, path, st);
}

bsfit_err bsfit_surface_write_step(const bsfit_surface *S, const char *path, bsfit_status *st) {
  char *text = NULL;
  size_t len = 0;
  bsfit_err e;
  if (path == NULL) return bsfit__fail(st, BSFIT_EINVAL, "no file name to write to");
  e = bsfit_surface_to_step(S, path, &text, &len, NULL, st);
  return bsfit__exchange_write(e, text, len, path, st);
}
