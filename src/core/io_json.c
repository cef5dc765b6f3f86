/*
** io_json.c
** Curves and surfaces as JSON (docs/formats.md): the writers, and the readers that
** walk the documented keys with the strict reader of io_jsonparse.c and then build
** the object through bsfit_curve_new / bsfit_surface_new (full validation).
*/
#include "io_internal.h"

#include <math.h>
#include <string.h>

/* {====================================================================
** Writers
** ===================================================================== */

static void put_numbers(bsfit__buf *b, const double *x, size_t n) {
  size_t i;
  bsfit__buf_putn(b, "[", 1);
  for (i = 0; i < n; i++) {
    if (i) bsfit__buf_putn(b, ",", 1);
    bsfit__buf_num(b, x[i]);
  }
  bsfit__buf_putn(b, "]", 1);
}

/* n points of dim coordinates: [[x,y],...] */
static void put_points(bsfit__buf *b, const double *x, size_t n, size_t dim) {
  size_t i;
  bsfit__buf_putn(b, "[", 1);
  for (i = 0; i < n; i++) {
    if (i) bsfit__buf_putn(b, ",", 1);
    put_numbers(b, x + i * dim, dim);
  }
  bsfit__buf_putn(b, "]", 1);
}

static void put_domain(bsfit__buf *b, const char *key, const double *U, size_t n, int p) {
  double d[2];
  bsfit_knots_domain(U, n, p, &d[0], &d[1]);
  bsfit__buf_printf(b, ",\"%s\":", key);
  put_numbers(b, d, 2);
}

bsfit_err bsfit_curve_to_json(const bsfit_curve *c, char **out, size_t *len,
                              const bsfit_allocator *a, bsfit_status *st) {
  bsfit__buf b;
  bsfit_err e;
  if (out == NULL) return bsfit__fail(st, BSFIT_EINVAL, "no output for the JSON text");
  e = bsfit_curve_validate(c, st);
  if (e != BSFIT_OK) return e;
  bsfit__buf_init(&b, a);
  bsfit__buf_printf(&b, "{\"type\":\"%s\",\"degree\":%d,\"dim\":%d,\"periodic\":%s,\"knots\":",
                    c->bezier ? "bezier" : c->weights ? "nurbs" : "bspline", c->degree, c->dim,
                    c->periodic ? "true" : "false");
  put_numbers(&b, c->knots, c->n + (size_t)c->degree + 1);
  bsfit__buf_puts(&b, ",\"control_points\":");
  put_points(&b, c->ctrl, c->n, (size_t)c->dim);
  if (c->weights) {
    bsfit__buf_puts(&b, ",\"weights\":");
    put_numbers(&b, c->weights, c->n);
  }
  put_domain(&b, "domain", c->knots, c->n, c->degree);
  bsfit__buf_puts(&b, "}\n");
  return bsfit__buf_take(&b, out, len, st);
}

bsfit_err bsfit_surface_to_json(const bsfit_surface *s, char **out, size_t *len,
                                const bsfit_allocator *a, bsfit_status *st) {
  bsfit__buf b;
  bsfit_err e;
  size_t i, d;
  if (out == NULL) return bsfit__fail(st, BSFIT_EINVAL, "no output for the JSON text");
  e = bsfit_surface_validate(s, st);
  if (e != BSFIT_OK) return e;
  d = (size_t)s->dim;
  bsfit__buf_init(&b, a);
  bsfit__buf_printf(&b, "{\"type\":\"%s\",\"degree_u\":%d,\"degree_v\":%d,\"dim\":%d,",
                    s->bezier ? "bezier_surface" : s->weights ? "nurbs_surface" : "bspline_surface",
                    s->degree_u, s->degree_v, s->dim);
  if (s->periodic_u) bsfit__buf_puts(&b, "\"periodic_u\":true,\"knots_u\":");
  else bsfit__buf_puts(&b, "\"knots_u\":");
  put_numbers(&b, s->knots_u, s->nu + (size_t)s->degree_u + 1);
  bsfit__buf_puts(&b, ",\"knots_v\":");
  put_numbers(&b, s->knots_v, s->nv + (size_t)s->degree_v + 1);
  bsfit__buf_puts(&b, ",\"control_points\":[");
  for (i = 0; i < s->nu; i++) {
    if (i) bsfit__buf_putn(&b, ",", 1);
    put_points(&b, s->ctrl + i * s->nv * d, s->nv, d);
  }
  bsfit__buf_putn(&b, "]", 1);
  if (s->weights) {
    bsfit__buf_puts(&b, ",\"weights\":");
    put_points(&b, s->weights, s->nu, s->nv);
  }
  put_domain(&b, "domain_u", s->knots_u, s->nu, s->degree_u);
  put_domain(&b, "domain_v", s->knots_v, s->nv, s->degree_v);
  bsfit__buf_puts(&b, "}\n");
  return bsfit__buf_take(&b, out, len, st);
}

bsfit_err bsfit_curve_write_json(const bsfit_curve *c, const char *path, bsfit_status *st) {
  bsfit__buf b;
  bsfit_err e;
  bsfit__buf_init(&b, NULL);
  e = bsfit_curve_to_json(c, &b.data, &b.len, NULL, st);
  if (e != BSFIT_OK) return e;
  b.cap = b.len + 1;
  return bsfit__buf_write(&b, path, st);
}

bsfit_err bsfit_surface_write_json(const bsfit_surface *s, const char *path, bsfit_status *st) {
  bsfit__buf b;
  bsfit_err e;
  bsfit__buf_init(&b, NULL);
  e = bsfit_surface_to_json(s, &b.data, &b.len, NULL, st);
  if (e != BSFIT_OK) return e;
  b.cap = b.len + 1;
  return bsfit__buf_write(&b, path, st);
}

/* }==================================================================== */

/* {====================================================================
** Readers: one key table for curves and surfaces
** ===================================================================== */

enum { K_TYPE, K_DEG, K_DEGU, K_DEGV, K_DIM, K_PERIODIC, K_KNOTS, K_KNOTSU, K_KNOTSV, K_CTRL,
       K_WEIGHTS, K_DOMAIN, K_DOMAINU, K_DOMAINV, K_PERIODICU, NKEYS };

static const char *const key_names[NKEYS] = {
  "type", "degree", "degree_u", "degree_v", "dim", "periodic", "knots", "knots_u", "knots_v",
  "control_points", "weights", "domain", "domain_u", "domain_v", "periodic_u"};

typedef struct doc {
  int seen[NKEYS];
  char type[32];
  double num[NKEYS]; /* degree, degree_u, degree_v, dim */
  int periodic, periodic_u;
  bsfit__numarr arr[NKEYS];
  int surface;
} doc;

static void doc_init(doc *d, int surface, const bsfit_allocator *a) {
  int k;
  memset(d, 0, sizeof *d);
  d->surface = surface;
  for (k = 0; k < NKEYS; k++) {
    d->arr[k].a = a;
    d->arr[k].depth = 1;
  }
  d->arr[K_CTRL].depth = surface ? 3 : 2;
  d->arr[K_WEIGHTS].depth = surface ? 2 : 1;
}

static void doc_free(doc *d) {
  int k;
  for (k = 0; k < NKEYS; k++) bsfit__numarr_free(&d->arr[k]);
}

static int find_key(const char *name) {
  int k;
  for (k = 0; k < NKEYS; k++)
    if (strcmp(name, key_names[k]) == 0) return k;
  return -1;
}

static bsfit_err read_value(bsfit__json *j, doc *d, int k) {
  switch (k) {
    case K_TYPE: return bsfit__json_string(j, d->type, sizeof d->type);
    case K_DEG: case K_DEGU: case K_DEGV: case K_DIM: return bsfit__json_number(j, &d->num[k]);
    case K_PERIODIC: return bsfit__json_bool(j, &d->periodic);
    case K_PERIODICU: return bsfit__json_bool(j, &d->periodic_u);
    default: return bsfit__json_numarray(j, &d->arr[k]);
  }
}

static bsfit_err read_object(bsfit__json *j, doc *d) {
  char key[64];
  bsfit_err e = bsfit__json_expect(j, '{');
  if (e != BSFIT_OK) return e;
  if (bsfit__json_peek(j) == '}') {
    j->pos++;
    return bsfit__json_end(j);
  }
  for (;;) {
    size_t at;
    int k;
    (void)bsfit__json_peek(j); /* skip blanks so `at` points at the key */
    at = j->pos;
    e = bsfit__json_string(j, key, sizeof key);
    if (e == BSFIT_OK) e = bsfit__json_expect(j, ':');
    if (e != BSFIT_OK) return e;
    k = find_key(key);
    if (k < 0) {
      e = bsfit__json_skip(j);
    } else if (d->seen[k]) {
      j->pos = at;
      return bsfit__json_fail(j, BSFIT_EFORMAT, "repeated key");
    } else {
      d->seen[k] = 1;
      e = read_value(j, d, k);
    }
    if (e != BSFIT_OK) return e;
    if (bsfit__json_peek(j) != ',') break;
    j->pos++;
  }
  e = bsfit__json_expect(j, '}');
  return e == BSFIT_OK ? bsfit__json_end(j) : e;
}

static bsfit_err need(const doc *d, int k, bsfit_status *st) {
  if (!d->seen[k]) return bsfit__fail(st, BSFIT_EFORMAT, "JSON: missing key \"%s\"", key_names[k]);
  return BSFIT_OK;
}

/* A degree-like field: an integer in range (the object constructors check the rest). */
static bsfit_err get_int(const doc *d, int k, int lo, int hi, bsfit_err code, int *out,
                         bsfit_status *st) {
  double x = d->num[k];
  if (x != floor(x))
    return bsfit__fail(st, BSFIT_EFORMAT, "JSON: \"%s\" must be an integer, got %.17g",
                       key_names[k], x);
  if (x < lo || x > hi)
    return bsfit__fail(st, code, "JSON: \"%s\" = %.17g out of range %d..%d", key_names[k], x, lo,
                       hi);
  *out = (int)x;
  return BSFIT_OK;
}

static bsfit_err check_count(const doc *d, int k, size_t want, bsfit_err code,
                             bsfit_status *st) {
  if (d->arr[k].n != want)
    return bsfit__fail(st, code, "JSON: \"%s\" has %zu values, %zu expected", key_names[k],
                       d->arr[k].n, want);
  return BSFIT_OK;
}

/* A redundant domain, when given, must be the one the knots define. */
static bsfit_err check_domain(const doc *d, int k, const double *U, size_t n, int p,
                              bsfit_status *st) {
  double a, b;
  if (!d->seen[k]) return BSFIT_OK;
  bsfit_knots_domain(U, n, p, &a, &b);
  if (d->arr[k].n != 2 || d->arr[k].v[0] != a || d->arr[k].v[1] != b)
    return bsfit__fail(st, BSFIT_EFORMAT, "JSON: \"%s\" does not match the knots [%.17g, %.17g]",
                       key_names[k], a, b);
  return BSFIT_OK;
}

/* dim (optional) must agree with the length of a point; returns the point length. */
static bsfit_err point_dim(const doc *d, int level, int *dim, bsfit_status *st) {
  size_t pd = d->arr[K_CTRL].n ? d->arr[K_CTRL].shape[level] : 0;
  if (d->arr[K_CTRL].n == 0)
    return bsfit__fail(st, BSFIT_ETOOFEW, "JSON: \"control_points\" is empty");
  if (pd < 1 || pd > 4)
    return bsfit__fail(st, BSFIT_EDIM, "JSON: control points have %zu coordinates (1..4)", pd);
  if (d->seen[K_DIM] && d->num[K_DIM] != (double)pd)
    return bsfit__fail(st, BSFIT_EDIM, "JSON: \"dim\" is %.17g but points have %zu coordinates",
                       d->num[K_DIM], pd);
  *dim = (int)pd;
  return BSFIT_OK;
}

/* Bézier objects are evaluated from their end knots only, so interior knots would be
** silently ignored: require the clamped single-span vector. */
static bsfit_err check_bezier_knots(const double *U, int p, bsfit_status *st) {
  int i;
  for (i = 0; i <= p; i++)
    if (U[i] != U[0] || U[p + 1 + i] != U[p + 1])
      return bsfit__fail(st, BSFIT_EFORMAT, "JSON: Bezier knots must be [a]*(p+1) + [b]*(p+1)");
  return BSFIT_OK;
}

static bsfit_err parse_doc(const char *s, size_t len, doc *d, bsfit_status *st) {
  bsfit__json j;
  if (s == NULL) return bsfit__fail(st, BSFIT_EINVAL, "no JSON text");
  j.s = s;
  j.len = len;
  j.pos = 0;
  j.depth = 0;
  j.st = st;
  return read_object(&j, d);
}

/* }==================================================================== */

/* {====================================================================
** Curve reader
** ===================================================================== */

static bsfit_err curve_kind(const doc *d, int *rational, int *bezier, bsfit_status *st) {
  bsfit_err e = need(d, K_TYPE, st);
  if (e != BSFIT_OK) return e;
  *bezier = strcmp(d->type, "bezier") == 0;
  if (strcmp(d->type, "nurbs") == 0) {
    e = need(d, K_WEIGHTS, st);
    *rational = 1;
  } else if (strcmp(d->type, "bspline") == 0 || *bezier) {
    *rational = d->seen[K_WEIGHTS];
    if (*rational && !*bezier)
      return bsfit__fail(st, BSFIT_EFORMAT, "JSON: a \"bspline\" has no weights (use \"nurbs\")");
  } else {
    return bsfit__fail(st, BSFIT_EFORMAT, "JSON: unknown curve type \"%s\"", d->type);
  }
  return e;
}

static bsfit_err build_curve(const doc *d, bsfit_curve *c, const bsfit_allocator *a,
                             bsfit_status *st) {
  int p = 0, dim = 0, rational = 0, bezier = 0;
  size_t n;
  bsfit_err e = curve_kind(d, &rational, &bezier, st);
  if (e == BSFIT_OK) e = need(d, K_DEG, st);
  if (e == BSFIT_OK) e = need(d, K_KNOTS, st);
  if (e == BSFIT_OK) e = need(d, K_CTRL, st);
  if (e == BSFIT_OK) e = get_int(d, K_DEG, 0, BSFIT_MAX_DEGREE, BSFIT_EDEGREE, &p, st);
  if (e == BSFIT_OK) e = point_dim(d, 1, &dim, st);
  if (e != BSFIT_OK) return e;
  n = d->arr[K_CTRL].shape[0];
  if (n < (size_t)p + 1)
    return bsfit__fail(st, BSFIT_EDEGREE, "JSON: degree %d needs at least %d control points, got %zu",
                       p, p + 1, n);
  e = check_count(d, K_KNOTS, n + (size_t)p + 1, BSFIT_ENKNOTS, st);
  if (e == BSFIT_OK && rational) e = check_count(d, K_WEIGHTS, n, BSFIT_EFORMAT, st);
  if (e == BSFIT_OK && bezier) {
    if (n != (size_t)p + 1 || (d->seen[K_PERIODIC] && d->periodic))
      return bsfit__fail(st, BSFIT_EFORMAT, "JSON: a Bezier curve of degree %d has %d control points and is not periodic",
                         p, p + 1);
    e = check_bezier_knots(d->arr[K_KNOTS].v, p, st);
  }
  if (e == BSFIT_OK) e = check_domain(d, K_DOMAIN, d->arr[K_KNOTS].v, n, p, st);
  if (e != BSFIT_OK) return e;
  e = bsfit_curve_new(c, p, dim, n, d->arr[K_KNOTS].v, d->arr[K_CTRL].v,
                      rational ? d->arr[K_WEIGHTS].v : NULL, d->periodic, a, st);
  if (e == BSFIT_OK) c->bezier = bezier;
  return e;
}

bsfit_err bsfit_curve_from_json(const char *s, size_t len, bsfit_curve *c,
                                const bsfit_allocator *a, bsfit_status *st) {
  doc d;
  bsfit_err e;
  bsfit_curve_free(c);
  doc_init(&d, 0, a);
  e = parse_doc(s, len, &d, st);
  if (e == BSFIT_OK) e = build_curve(&d, c, a, st);
  doc_free(&d);
  return e;
}

bsfit_err bsfit_curve_read_json(const char *path, bsfit_curve *c, const bsfit_allocator *a,
                                bsfit_status *st) {
  bsfit__buf b;
  bsfit_err e;
  bsfit_curve_free(c);
  bsfit__buf_init(&b, a);
  e = bsfit__read_file(path, &b, st);
  if (e == BSFIT_OK) e = bsfit_curve_from_json(b.data ? b.data : "", b.len, c, a, st);
  bsfit__buf_free(&b);
  return e;
}

/* }==================================================================== */

/* {====================================================================
** Surface reader
** ===================================================================== */

static bsfit_err surface_kind(const doc *d, int *rational, int *bezier, bsfit_status *st) {
  bsfit_err e = need(d, K_TYPE, st);
  if (e != BSFIT_OK) return e;
  *bezier = strcmp(d->type, "bezier_surface") == 0;
  if (strcmp(d->type, "nurbs_surface") == 0) {
    e = need(d, K_WEIGHTS, st);
    *rational = 1;
  } else if (strcmp(d->type, "bspline_surface") == 0 || *bezier) {
    *rational = d->seen[K_WEIGHTS];
    if (*rational && !*bezier)
      return bsfit__fail(st, BSFIT_EFORMAT,
                         "JSON: a \"bspline_surface\" has no weights (use \"nurbs_surface\")");
  } else {
    return bsfit__fail(st, BSFIT_EFORMAT, "JSON: unknown surface type \"%s\"", d->type);
  }
  return e;
}

static bsfit_err surface_shape(const doc *d, int *pu, int *pv, int *dim, bsfit_status *st) {
  bsfit_err e = need(d, K_DEGU, st);
  if (e == BSFIT_OK) e = need(d, K_DEGV, st);
  if (e == BSFIT_OK) e = need(d, K_KNOTSU, st);
  if (e == BSFIT_OK) e = need(d, K_KNOTSV, st);
  if (e == BSFIT_OK) e = need(d, K_CTRL, st);
  if (e == BSFIT_OK) e = get_int(d, K_DEGU, 0, BSFIT_MAX_DEGREE, BSFIT_EDEGREE, pu, st);
  if (e == BSFIT_OK) e = get_int(d, K_DEGV, 0, BSFIT_MAX_DEGREE, BSFIT_EDEGREE, pv, st);
  if (e == BSFIT_OK) e = point_dim(d, 2, dim, st);
  return e;
}

static bsfit_err build_surface(const doc *d, bsfit_surface *s, const bsfit_allocator *a,
                               bsfit_status *st) {
  int pu = 0, pv = 0, dim = 0, rational = 0, bezier = 0;
  size_t nu, nv;
  bsfit_err e = surface_kind(d, &rational, &bezier, st);
  if (e == BSFIT_OK) e = surface_shape(d, &pu, &pv, &dim, st);
  if (e != BSFIT_OK) return e;
  nu = d->arr[K_CTRL].shape[0];
  nv = d->arr[K_CTRL].shape[1];
  if (nu < (size_t)pu + 1 || nv < (size_t)pv + 1)
    return bsfit__fail(st, BSFIT_EDEGREE, "JSON: degrees (%d, %d) need %d x %d control points, got %zu x %zu",
                       pu, pv, pu + 1, pv + 1, nu, nv);
  e = check_count(d, K_KNOTSU, nu + (size_t)pu + 1, BSFIT_ENKNOTS, st);
  if (e == BSFIT_OK) e = check_count(d, K_KNOTSV, nv + (size_t)pv + 1, BSFIT_ENKNOTS, st);
  if (e == BSFIT_OK && rational)
    e = (d->arr[K_WEIGHTS].shape[0] != nu || d->arr[K_WEIGHTS].shape[1] != nv)
            ? bsfit__fail(st, BSFIT_EFORMAT, "JSON: \"weights\" must be %zu arrays of %zu", nu, nv)
            : BSFIT_OK;
  if (e == BSFIT_OK && bezier) {
    if (nu != (size_t)pu + 1 || nv != (size_t)pv + 1)
      return bsfit__fail(st, BSFIT_EFORMAT, "JSON: a Bezier surface needs %d x %d control points",
                         pu + 1, pv + 1);
    e = check_bezier_knots(d->arr[K_KNOTSU].v, pu, st);
    if (e == BSFIT_OK) e = check_bezier_knots(d->arr[K_KNOTSV].v, pv, st);
  }
  if (e == BSFIT_OK) e = check_domain(d, K_DOMAINU, d->arr[K_KNOTSU].v, nu, pu, st);
  if (e == BSFIT_OK) e = check_domain(d, K_DOMAINV, d->arr[K_KNOTSV].v, nv, pv, st);
  if (e != BSFIT_OK) return e;
  e = bsfit_surface_new(s, pu, pv, dim, nu, nv, d->arr[K_KNOTSU].v, d->arr[K_KNOTSV].v,
                        d->arr[K_CTRL].v, rational ? d->arr[K_WEIGHTS].v : NULL, a, st);
  if (e == BSFIT_OK) s->bezier = bezier;
  if (e == BSFIT_OK && d->periodic_u) {
    /* the expanded periodic form in u, checked like a periodic curve's */
    s->periodic_u = 1;
    e = bsfit_surface_validate(s, st);
    if (e != BSFIT_OK) bsfit_surface_free(s);
  }
  return e;
}

bsfit_err bsfit_surface_from_json(const char *text, size_t len, bsfit_surface *s,
                                  const bsfit_allocator *a, bsfit_status *st) {
  doc d;
  bsfit_err e;
  bsfit_surface_free(s);
  doc_init(&d, 1, a);
  e = parse_doc(text, len, &d, st);
  if (e == BSFIT_OK) e = build_surface(&d, s, a, st);
  doc_free(&d);
  return e;
}

/* }==================================================================== */
