/*
** fuzz_curve.c
** Curve construction and every curve operation, chained: knot insertion, refinement,
** split, reverse, degree elevation, derivatives, closest point, arc length, sampling
** and the JSON round trip. Contract: an operation that returns OK gives finite
** numbers and a valid curve, and the operations that keep the curve (insertion,
** refinement, reverse, elevation) keep its points: C'(u') = C(u) up to rounding.
*/
#include "fuzz_curve_make.h"

/* |C(u)| scale for the comparisons: the control points' size. */
static double scale_of(const bsfit_curve *c) {
  double s = 1.0;
  size_t i;
  for (i = 0; i < c->n * (size_t)c->dim; i++) s = fmax(s, fabs(c->ctrl[i]));
  return s;
}

/* Whether u is a knot of c (where a curve of degree 0, or with a knot of full
** multiplicity, may jump: reversed, it takes the other side's value). */
static int at_knot(const bsfit_curve *c, double u) {
  size_t i;
  for (i = 0; i < c->n + (size_t)c->degree + 1; i++)
    if (c->knots[i] == u) return 1;
  return 0;
}

/* d(u) == c(map(u)) at 9 parameters, within tol relative to the control points. */
static void same_curve(const bsfit_curve *c, const bsfit_curve *d, int reversed, double tol,
                       const char *what) {
  double a, b, a2, b2, x[4], y[4], s = scale_of(c);
  int i, k;
  bsfit_knots_domain(c->knots, c->n, c->degree, &a, &b);
  bsfit_knots_domain(d->knots, d->n, d->degree, &a2, &b2);
  for (i = 0; i <= 8; i++) {
    double u = a + (b - a) * i / 8.0, v = reversed ? a2 + b2 - u : u;
    if (reversed && at_knot(c, u)) continue;
    if (bsfit_curve_eval(c, u, x, NULL) != BSFIT_OK || bsfit_curve_eval(d, v, y, NULL) != BSFIT_OK)
      return; /* a domain edge lost to rounding: nothing to compare */
    for (k = 0; k < c->dim; k++)
      if (fz_strict && !(fabs(x[k] - y[k]) <= tol * s)) fz_fail(what, "the curve moved");
  }
}

/* Whether every u[i] lies in the domain: outside it an open curve is extrapolated
** (bsfit_curve_eval's contract), and a polynomial far outside may overflow. */
static int in_domain(const bsfit_curve *c, const double *u, size_t n) {
  double a, b;
  size_t i;
  bsfit_knots_domain(c->knots, c->n, c->degree, &a, &b);
  for (i = 0; i < n; i++)
    if (!(u[i] >= a && u[i] <= b)) return c->periodic && isfinite(u[i]);
  return 1;
}

/* Replaces *c by *d when the operation gave a curve (chains the operations). */
static void take(bsfit_curve *c, bsfit_curve *d) {
  bsfit_curve_free(c);
  *c = *d;
  bsfit_curve_init(d);
}

static void one_op(fuzz_in *in, bsfit_curve *c) {
  bsfit_curve d, e;
  bsfit_status st;
  double out[8 * 4 * 9], u, X[8], len, q[4];
  size_t i, nx;
  int op = fz_byte(in) % 11, k;
  bsfit_curve_init(&d);
  bsfit_curve_init(&e);
  switch (op) {
    case 0:
      if (bsfit_curve_insert_knot(c, fz_param(in, c), 1 + fz_byte(in) % 4, &d, &st) == BSFIT_OK) {
        fz_check_curve(&d, "insert");
        same_curve(c, &d, 0, 1e-9, "insert");
        take(c, &d);
      }
      break;
    case 1:
      nx = fz_byte(in) % 8;
      for (i = 0; i < nx; i++) X[i] = fz_param(in, c);
      for (i = 1; i < nx; i++) /* sorted */
        for (k = (int)i; k > 0 && X[k - 1] > X[k]; k--) u = X[k], X[k] = X[k - 1], X[k - 1] = u;
      if (bsfit_curve_refine(c, X, nx, &d, &st) == BSFIT_OK) {
        fz_check_curve(&d, "refine");
        same_curve(c, &d, 0, 1e-9, "refine");
        take(c, &d);
      }
      break;
    case 2:
      if (bsfit_curve_split(c, fz_param(in, c), &d, &e, &st) == BSFIT_OK) {
        int periodic = c->periodic; /* cut open: one curve, right emptied */
        fz_check_curve(&d, "split left");
        if (!periodic) fz_check_curve(&e, "split right");
        take(c, periodic || fz_byte(in) % 2 ? &d : &e);
      }
      break;
    case 3:
      if (bsfit_curve_reverse(c, &d, &st) == BSFIT_OK) {
        fz_check_curve(&d, "reverse");
        /* a + b - u rounds: on a steep short span (slope 1e7) that moves C by 1e-9 */
        same_curve(c, &d, 1, 1e-6, "reverse");
        take(c, &d);
      }
      break;
    case 4:
      if (bsfit_curve_elevate(c, 1 + fz_byte(in) % 3, &d, &st) == BSFIT_OK) {
        fz_check_curve(&d, "elevate");
        same_curve(c, &d, 0, 1e-6, "elevate");
        take(c, &d);
      }
      break;
    case 5:
      k = fz_byte(in) % 5;
      u = fz_param(in, c);
      if (bsfit_curve_derivs(c, u, k, out, &st) == BSFIT_OK && in_domain(c, &u, 1))
        fz_check_finite(out, (size_t)(k + 1) * (size_t)c->dim, "derivs");
      break;
    case 6:
      for (k = 0; k < c->dim; k++) q[k] = fz_double(in);
      if (bsfit_curve_closest(c, q, &u, &len, NULL, &st) == BSFIT_OK && fz_strict &&
          fz_tame(q, (size_t)c->dim) && (!isfinite(u) || !isfinite(len)))
        fz_fail("closest", "not finite");
      break;
    case 7:
      if (bsfit_curve_length(c, fz_param(in, c), fz_param(in, c), &len, &st) == BSFIT_OK &&
          fz_strict && !(isfinite(len) && len >= 0))
        fz_fail("length", "not finite or negative");
      break;
    case 8:
      k = 2 + fz_byte(in) % 7;
      if (bsfit_curve_sample(c, (size_t)k, out, NULL, &st) == BSFIT_OK)
        fz_check_finite(out, (size_t)k * (size_t)c->dim, "sample");
      break;
    case 9: {
      char *s = NULL;
      size_t n = 0;
      if (bsfit_curve_to_json(c, &s, &n, NULL, &st) == BSFIT_OK) {
        if (bsfit_curve_from_json(s, n, &d, NULL, &st) != BSFIT_OK) fz_fail("json reread", st.msg);
        fz_check_curve(&d, "json");
        same_curve(c, &d, 0, 0.0, "json");
      }
      free(s);
      break;
    }
    default:
      for (i = 0; i < 8; i++) X[i] = fz_param(in, c);
      if (bsfit_curve_eval_many(c, X, 8, out, &st) == BSFIT_OK && in_domain(c, X, 8))
        fz_check_finite(out, 8 * (size_t)c->dim, "eval_many");
      break;
  }
  bsfit_curve_free(&d);
  bsfit_curve_free(&e);
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size) {
  fuzz_in in = {data, size};
  bsfit_curve c;
  bsfit_status st;
  int ops;
  bsfit_curve_init(&c);
  if (fz_make_curve(&in, &c, &st) == BSFIT_OK) {
    fz_strict = fz_tame(c.ctrl, c.n * (size_t)c.dim) &&
                fz_tame(c.knots, c.n + (size_t)c.degree + 1) &&
                (c.weights == NULL || fz_tame(c.weights, c.n));
    fz_check_curve(&c, "construction");
    for (ops = 0; ops < 6 && in.n > 0 && c.n < 4096; ops++)
      one_op(&in, &c);
  }
  bsfit_curve_free(&c);
  return 0;
}
