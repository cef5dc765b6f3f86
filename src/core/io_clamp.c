/*
** io_clamp.c
** The clamped form of curves and surfaces, for the STEP and DXF writers: knot insertion
** to multiplicity p at both ends of the domain [a, b], then only the control points the
** domain uses are kept. Same points at the same parameters, but every reader agrees on
** what it means: unclamped knot vectors are read differently (ezdxf evaluates from the
** first knot; OpenCASCADE turns a closed unclamped STEP curve into a periodic one and
** gets it wrong when a knot of multiplicity p sits at the seam).
** A periodic curve's expanded form is, on its domain, an open unclamped B-spline: it is
** clamped the same way, which cuts it open where its period starts.
*/
#include "io_internal.h"

#include <string.h>

/* With s the last knot equal to a and f the first equal to b (after refinement), the
** domain's spans are s..f-1: control points s-p..f-1 remain, with the knots
** [a]*(p+1), R[s+1..f-1], [b]*(p+1). */
bsfit_err bsfit__curve_clamped(const bsfit_curve *c, bsfit_curve *out, const bsfit_allocator *al,
                               bsfit_status *st) {
  int p = c->degree, m, t;
  double a, b, X[2 * BSFIT_MAX_DEGREE];
  size_t nx = 0, s, f, n, d = (size_t)c->dim, i, nk = c->n + (size_t)p + 1;
  bsfit_curve r;
  bsfit_err e;
  bsfit_curve_domain(c, &a, &b);
  for (m = bsfit_knots_multiplicity(c->knots, nk, a), t = m; t < p; t++) X[nx++] = a;
  for (m = bsfit_knots_multiplicity(c->knots, nk, b), t = m; t < p; t++) X[nx++] = b;
  bsfit_curve_init(&r);
  e = bsfit_curve_copy(c, &r, al, st); /* r's operations allocate with al */
  r.periodic = 0;
  if (e == BSFIT_OK) e = bsfit_curve_refine(&r, X, nx, &r, st);
  if (e != BSFIT_OK) {
    bsfit_curve_free(&r);
    return e;
  }
  for (s = (size_t)p; r.knots[s + 1] == a; s++) continue;
  for (f = r.n; r.knots[f - 1] == b; f--) continue;
  n = f - (s - (size_t)p);
  e = bsfit_curve_alloc(out, p, c->dim, n, c->weights != NULL, al, st);
  if (e == BSFIT_OK) {
    for (i = 0; i <= (size_t)p; i++) {
      out->knots[i] = a;
      out->knots[n + i] = b;
    }
    for (i = s + 1; i < f; i++) out->knots[(size_t)p + 1 + i - (s + 1)] = r.knots[i];
    memcpy(out->ctrl, r.ctrl + (s - (size_t)p) * d, n * d * sizeof(double));
    if (r.weights) memcpy(out->weights, r.weights + (s - (size_t)p), n * sizeof(double));
    e = bsfit_curve_validate(out, st);
  }
  bsfit_curve_free(&r);
  return e;
}

/* Line k of the net along direction u (along_u: the points (i, k), i = 0..nu-1) or v
** (the points (k, j)) as a curve, or back into the net of out. */
static size_t net_index(const bsfit_surface *s, int along_u, size_t k, size_t i) {
  return along_u ? i * s->nv + k : k * s->nv + i;
}

static bsfit_err line_curve(const bsfit_surface *s, int along_u, size_t k, bsfit_curve *c,
                            const bsfit_allocator *al, bsfit_status *st) {
  size_t n = along_u ? s->nu : s->nv, i, d = (size_t)s->dim;
  int p = along_u ? s->degree_u : s->degree_v;
  bsfit_err e = bsfit_curve_alloc(c, p, s->dim, n, s->weights != NULL, al, st);
  if (e != BSFIT_OK) return e;
  memcpy(c->knots, along_u ? s->knots_u : s->knots_v, (n + (size_t)p + 1) * sizeof(double));
  for (i = 0; i < n; i++) {
    size_t idx = net_index(s, along_u, k, i);
    memcpy(c->ctrl + i * d, s->ctrl + idx * d, d * sizeof(double));
    if (s->weights) c->weights[i] = s->weights[idx];
  }
  return BSFIT_OK;
}

/* out = s clamped in one direction: every line of the net clamped as a curve (they share
** the knots, so they share the result's knots). */
static bsfit_err clamp_direction(const bsfit_surface *s, int along_u, bsfit_surface *out,
                                 const bsfit_allocator *al, bsfit_status *st) {
  size_t lines = along_u ? s->nv : s->nu, k, i, d = (size_t)s->dim;
  bsfit_curve c, cl;
  bsfit_err e = BSFIT_OK;
  bsfit_curve_init(&c);
  bsfit_curve_init(&cl);
  for (k = 0; k < lines && e == BSFIT_OK; k++) {
    e = line_curve(s, along_u, k, &c, al, st);
    if (e == BSFIT_OK) e = bsfit__curve_clamped(&c, &cl, al, st);
    if (e == BSFIT_OK && k == 0)
      e = bsfit_surface_alloc(out, s->degree_u, s->degree_v, s->dim, along_u ? cl.n : s->nu,
                              along_u ? s->nv : cl.n, s->weights != NULL, al, st);
    if (e != BSFIT_OK) break;
    if (k == 0) {
      memcpy(out->knots_u, along_u ? cl.knots : s->knots_u,
             (out->nu + (size_t)s->degree_u + 1) * sizeof(double));
      memcpy(out->knots_v, along_u ? s->knots_v : cl.knots,
             (out->nv + (size_t)s->degree_v + 1) * sizeof(double));
    }
    for (i = 0; i < cl.n; i++) {
      size_t idx = net_index(out, along_u, k, i);
      memcpy(out->ctrl + idx * d, cl.ctrl + i * d, d * sizeof(double));
      if (out->weights) out->weights[idx] = cl.weights[i];
    }
  }
  bsfit_curve_free(&c);
  bsfit_curve_free(&cl);
  if (e == BSFIT_OK) e = bsfit_surface_validate(out, st);
  if (e != BSFIT_OK) bsfit_surface_free(out);
  return e;
}

bsfit_err bsfit__surface_clamped(const bsfit_surface *s, bsfit_surface *out,
                                 const bsfit_allocator *al, bsfit_status *st) {
  bsfit_surface t;
  bsfit_err e;
  bsfit_surface_init(&t);
  e = clamp_direction(s, 1, &t, al, st);
  if (e == BSFIT_OK) e = clamp_direction(&t, 0, out, al, st);
  bsfit_surface_free(&t);
  return e;
}
