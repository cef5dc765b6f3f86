/*
** io_svg.c
** A tiny SVG builder for pictures of fits: data points, curve samples, the control
** polygon and labelled markers, over a viewBox fitted to the data with the y axis up.
** Coordinates are mapped to pixels here (rather than by an SVG transform) so that text
** labels stay upright and stroke widths and radii are in pixels.
*/
#include "io_internal.h"

#include <math.h>
#include <string.h>

struct bsfit_svg {
  bsfit__buf b;
  double x0, y1;        /* data coordinates of the top-left corner */
  double scale;         /* pixels per data unit (same in x and y) */
  double width, height; /* pixels */
  int ended;
  int projected;        /* some layer had 3D data: drawn as its x-y projection, said so */
};

#define MARGIN 0.05 /* of the larger side, on each side */

static const char *const default_style =
  "<style>\n"
  ".points{fill:#1f77b4;stroke:none}\n"
  ".curve{fill:none;stroke:#d62728;stroke-width:1.5}\n"
  ".control{fill:none;stroke:#7f7f7f;stroke-width:1;stroke-dasharray:4 3}\n"
  ".marker{fill:#2ca02c;stroke:none}\n"
  ".marker text,text{font:12px sans-serif;fill:#000}\n"
  "</style>\n";

void bsfit_svg_bbox_init(double bbox[4]) {
  bbox[0] = bbox[1] = HUGE_VAL;
  bbox[2] = bbox[3] = -HUGE_VAL;
}

void bsfit_svg_bbox_add(double bbox[4], const double *xy, size_t m, int dim) {
  size_t i, d = (size_t)dim;
  if (xy == NULL || dim < 2) return;
  for (i = 0; i < m; i++) {
    double x = xy[i * d], y = xy[i * d + 1];
    if (!isfinite(x) || !isfinite(y)) continue;
    if (x < bbox[0]) bbox[0] = x;
    if (y < bbox[1]) bbox[1] = y;
    if (x > bbox[2]) bbox[2] = x;
    if (y > bbox[3]) bbox[3] = y;
  }
}

/* A flat box would give an infinite scale: widen it to a unit box around its centre. */
static void widen(double *lo, double *hi) {
  if (*hi - *lo > 0) return;
  *lo -= 0.5;
  *hi += 0.5;
}

bsfit_err bsfit_svg_begin(bsfit_svg **out, const double bbox[4], double width,
                          const bsfit_allocator *a, bsfit_status *st) {
  double xmin, ymin, xmax, ymax, side, margin;
  bsfit_svg *s;
  if (out == NULL || bbox == NULL) return bsfit__fail(st, BSFIT_EINVAL, "no SVG document or box");
  *out = NULL;
  if (!(width > 0) || !isfinite(width))
    return bsfit__fail(st, BSFIT_EINVAL, "SVG width %g must be positive", width);
  if (!bsfit__all_finite(bbox, 4)) {
    if (bbox[0] > bbox[2] || bbox[1] > bbox[3])
      return bsfit__fail(st, BSFIT_EINVAL, "empty bounding box (no data added)");
    return bsfit__fail(st, BSFIT_ENONFINITE, "bounding box is not finite");
  }
  if (bbox[0] > bbox[2] || bbox[1] > bbox[3])
    return bsfit__fail(st, BSFIT_EINVAL, "empty bounding box (min above max)");
  xmin = bbox[0], ymin = bbox[1], xmax = bbox[2], ymax = bbox[3];
  widen(&xmin, &xmax);
  widen(&ymin, &ymax);
  side = fmax(xmax - xmin, ymax - ymin);
  margin = MARGIN * side;
  s = bsfit__alloc(a, sizeof *s);
  if (s == NULL) return bsfit__fail(st, BSFIT_ENOMEM, "out of memory for an SVG document");
  memset(s, 0, sizeof *s);
  bsfit__buf_init(&s->b, a);
  s->x0 = xmin - margin;
  s->y1 = ymax + margin;
  s->width = width;
  s->scale = width / (xmax - xmin + 2 * margin);
  s->height = s->scale * (ymax - ymin + 2 * margin);
  bsfit__buf_printf(&s->b,
                    "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n"
                    "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"%.2f\" height=\"%.2f\" "
                    "viewBox=\"0 0 %.2f %.2f\">\n",
                    s->width, s->height, s->width, s->height);
  bsfit__buf_puts(&s->b, default_style);
  if (s->b.failed) {
    bsfit_svg_free(s);
    return bsfit__fail(st, BSFIT_ENOMEM, "out of memory for an SVG document");
  }
  *out = s;
  return bsfit__ok(st);
}

void bsfit_svg_free(bsfit_svg *s) {
  bsfit_allocator a;
  if (s == NULL) return;
  a = s->b.alloc;
  bsfit__buf_free(&s->b);
  bsfit__free(&a, s, sizeof *s);
}

/* {====================================================================
** Layers
** ===================================================================== */

static int valid_class(const char *c) {
  size_t i, n = strlen(c);
  if (n == 0 || n > 64) return 0;
  for (i = 0; i < n; i++) {
    char ch = c[i];
    if (!((ch >= 'a' && ch <= 'z') || (ch >= 'A' && ch <= 'Z') || (ch >= '0' && ch <= '9') ||
          ch == '-' || ch == '_'))
      return 0;
  }
  return 1;
}

/* Checks common to every layer; *cls gets the default when css_class is NULL. */
static bsfit_err check_layer(const bsfit_svg *s, const char **cls, const char *def,
                             bsfit_status *st) {
  if (s == NULL) return bsfit__fail(st, BSFIT_EINVAL, "no SVG document");
  if (s->ended) return bsfit__fail(st, BSFIT_EINVAL, "the SVG document is already ended");
  if (*cls == NULL) *cls = def;
  if (!valid_class(*cls))
    return bsfit__fail(st, BSFIT_EINVAL, "bad CSS class name (letters, digits, - and _ only)");
  return BSFIT_OK;
}

static bsfit_err check_points(const double *xy, size_t m, int dim, bsfit_status *st) {
  size_t i, d = (size_t)dim;
  if (dim < 2 || dim > 4) return bsfit__fail(st, BSFIT_EDIM, "SVG needs 2D or 3D points, got dim %d", dim);
  if (xy == NULL && m > 0) return bsfit__fail(st, BSFIT_EINVAL, "no points");
  for (i = 0; i < m; i++)
    if (!isfinite(xy[i * d]) || !isfinite(xy[i * d + 1]))
      return bsfit__fail(st, BSFIT_ENONFINITE, "point %zu is not finite", i);
  return BSFIT_OK;
}

static double px(const bsfit_svg *s, double x) { return (x - s->x0) * s->scale; }
static double py(const bsfit_svg *s, double y) { return (s->y1 - y) * s->scale; } /* y up */

static bsfit_err layer_done(bsfit_svg *s, bsfit_status *st) {
  if (s->b.failed) return bsfit__fail(st, BSFIT_ENOMEM, "out of memory for the SVG document");
  return bsfit__ok(st);
}

bsfit_err bsfit_svg_points(bsfit_svg *s, const double *xy, size_t m, int dim, double radius,
                           const char *css_class, bsfit_status *st) {
  size_t i, d = (size_t)dim;
  bsfit_err e = check_layer(s, &css_class, "points", st);
  if (e == BSFIT_OK) e = check_points(xy, m, dim, st);
  if (e != BSFIT_OK) return e;
  if (!(radius > 0) || !isfinite(radius)) radius = 2.0;
  if (dim >= 3) s->projected = 1;
  bsfit__buf_printf(&s->b, "<g class=\"%s\">\n", css_class);
  for (i = 0; i < m; i++)
    bsfit__buf_printf(&s->b, "<circle cx=\"%.3f\" cy=\"%.3f\" r=\"%.3g\"/>\n", px(s, xy[i * d]),
                      py(s, xy[i * d + 1]), radius);
  bsfit__buf_puts(&s->b, "</g>\n");
  return layer_done(s, st);
}

bsfit_err bsfit_svg_polyline(bsfit_svg *s, const double *xy, size_t m, int dim, int closed,
                             const char *css_class, bsfit_status *st) {
  size_t i, d = (size_t)dim;
  bsfit_err e = check_layer(s, &css_class, "curve", st);
  if (e == BSFIT_OK) e = check_points(xy, m, dim, st);
  if (e != BSFIT_OK) return e;
  if (dim >= 3) s->projected = 1;
  bsfit__buf_printf(&s->b, "<%s class=\"%s\" fill=\"none\" points=\"", closed ? "polygon" : "polyline",
                    css_class);
  for (i = 0; i < m; i++)
    bsfit__buf_printf(&s->b, "%s%.3f,%.3f", i ? " " : "", px(s, xy[i * d]), py(s, xy[i * d + 1]));
  bsfit__buf_puts(&s->b, "\"/>\n");
  return layer_done(s, st);
}

static bsfit_err check_curve(const bsfit_curve *c, bsfit_status *st) {
  bsfit_err e = bsfit_curve_validate(c, st);
  if (e == BSFIT_OK && c->dim < 2)
    return bsfit__fail(st, BSFIT_EDIM, "SVG needs a 2D or 3D curve, got dim %d", c->dim);
  return e;
}

bsfit_err bsfit_svg_curve(bsfit_svg *s, const bsfit_curve *c, size_t samples,
                          const char *css_class, bsfit_status *st) {
  double a, b, *xy;
  size_t i, d;
  bsfit_err e = check_layer(s, &css_class, "curve", st);
  if (e == BSFIT_OK) e = check_curve(c, st);
  if (e != BSFIT_OK) return e;
  if (samples < 2 || bsfit__mulsize(samples, (size_t)c->dim * sizeof(double)) == 0)
    return bsfit__fail(st, BSFIT_EINVAL, "need at least 2 curve samples, got %zu", samples);
  d = (size_t)c->dim;
  xy = bsfit__alloc(&s->b.alloc, samples * d * sizeof(double));
  if (xy == NULL) return bsfit__fail(st, BSFIT_ENOMEM, "out of memory for %zu samples", samples);
  bsfit_curve_domain(c, &a, &b);
  /* a closed curve's last sample would repeat the first: the polygon closes it instead */
  for (i = 0; i < samples; i++) {
    double t = c->periodic ? (double)i / (double)samples : (double)i / (double)(samples - 1);
    bsfit__curve_eval_unchecked(c, i + 1 == samples && !c->periodic ? b : a + (b - a) * t,
                                xy + i * d);
  }
  e = bsfit_svg_polyline(s, xy, samples, c->dim, c->periodic, css_class, st);
  bsfit__free(&s->b.alloc, xy, samples * d * sizeof(double));
  return e;
}

bsfit_err bsfit_svg_control_polygon(bsfit_svg *s, const bsfit_curve *c, const char *css_class,
                                    bsfit_status *st) {
  bsfit_err e = check_layer(s, &css_class, "control", st);
  if (e == BSFIT_OK) e = check_curve(c, st);
  if (e != BSFIT_OK) return e;
  return bsfit_svg_polyline(s, c->ctrl, bsfit_curve_distinct(c), c->dim, c->periodic, css_class,
                            st);
}

static void put_escaped(bsfit__buf *b, const char *t) {
  for (; *t; t++) {
    switch (*t) {
      case '&': bsfit__buf_puts(b, "&amp;"); break;
      case '<': bsfit__buf_puts(b, "&lt;"); break;
      case '>': bsfit__buf_puts(b, "&gt;"); break;
      case '"': bsfit__buf_puts(b, "&quot;"); break;
      case '\'': bsfit__buf_puts(b, "&apos;"); break;
      default: bsfit__buf_putn(b, t, 1);
    }
  }
}

bsfit_err bsfit_svg_marker(bsfit_svg *s, double x, double y, const char *label,
                           const char *css_class, bsfit_status *st) {
  bsfit_err e = check_layer(s, &css_class, "marker", st);
  if (e != BSFIT_OK) return e;
  if (!isfinite(x) || !isfinite(y))
    return bsfit__fail(st, BSFIT_ENONFINITE, "marker position (%g, %g) is not finite", x, y);
  bsfit__buf_printf(&s->b, "<g class=\"%s\"><circle cx=\"%.3f\" cy=\"%.3f\" r=\"4\"/>", css_class,
                    px(s, x), py(s, y));
  if (label != NULL && label[0] != '\0') {
    bsfit__buf_printf(&s->b, "<text x=\"%.3f\" y=\"%.3f\">", px(s, x) + 6, py(s, y) - 6);
    put_escaped(&s->b, label);
    bsfit__buf_puts(&s->b, "</text>");
  }
  bsfit__buf_puts(&s->b, "</g>\n");
  return layer_done(s, st);
}

/* }==================================================================== */

bsfit_err bsfit_svg_end(bsfit_svg *s, char **out, size_t *len, bsfit_status *st) {
  bsfit_err e;
  if (s == NULL || out == NULL) return bsfit__fail(st, BSFIT_EINVAL, "no SVG document");
  if (s->ended) return bsfit__fail(st, BSFIT_EINVAL, "the SVG document is already ended");
  s->ended = 1;
  /* a 3D layer is not silently a 2D picture: the picture says what it shows */
  if (s->projected)
    bsfit__buf_puts(&s->b, "<text class=\"note\" x=\"4\" y=\"14\">3D data drawn as its x-y "
                           "projection (z not shown)</text>\n");
  bsfit__buf_puts(&s->b, "</svg>\n");
  e = bsfit__buf_take(&s->b, out, len, st);
  return e;
}

bsfit_err bsfit_svg_write(bsfit_svg *s, const char *path, bsfit_status *st) {
  bsfit__buf b;
  bsfit_err e;
  if (s == NULL) return bsfit__fail(st, BSFIT_EINVAL, "no SVG document");
  bsfit__buf_init(&b, &s->b.alloc);
  e = bsfit_svg_end(s, &b.data, &b.len, st);
  if (e != BSFIT_OK) return e;
  b.cap = b.len + 1;
  return bsfit__buf_write(&b, path, st);
}
