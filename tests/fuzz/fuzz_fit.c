/*
** fuzz_fit.c
** The fitter: open and periodic, both solvers (and auto), every knot rule or fixed
** knots, fixed ends, end tangents, weights, parameters from bsfit_params or raw, and
** a refit with the same fitter. Contract: OK => the curve is valid with every number
** finite, the report's rms, max, rcond and the residuals are finite, and max is the
** largest residual.
*/
#include "fuzz_util.h"

#define MAXM 64

typedef struct problem {
  double pts[MAXM * 3], u[MAXM], w[MAXM], knots[MAXM + 16], t0[3], t1[3];
  size_t m;
  int dim, use_w;
} problem;

static void make_points(fuzz_in *in, problem *pb) {
  size_t i;
  int shape = fz_byte(in) % 3;
  pb->dim = 2 + fz_byte(in) % 2;
  pb->m = (size_t)(1 + fz_byte(in) % MAXM);
  for (i = 0; i < pb->m; i++) {
    double t = 6.283185307179586 * (double)i / (double)pb->m;
    int k;
    for (k = 0; k < pb->dim; k++) { /* a circle plus fuzzed offsets, or fuzzed points */
      double base = shape == 0 ? (k == 0 ? cos(t) : k == 1 ? sin(t) : 0) : 0;
      pb->pts[i * (size_t)pb->dim + (size_t)k] =
          base + (shape == 0 ? fz_double(in) / 4096 : fz_double(in));
    }
    pb->w[i] = fz_byte(in) < 245 ? 0.125 + (double)fz_byte(in) / 16.0 : fz_double(in);
  }
  pb->use_w = fz_byte(in) % 2;
}

/* rcond is exact only while the parameters lie in the knots' domain (bsfit_fit_report):
** outside, the basis is extrapolated and may be negative. */
static int params_in_domain(const problem *pb, const bsfit_curve *c) {
  double a, b;
  size_t i;
  if (c->periodic) return 1;
  bsfit_knots_domain(c->knots, c->n, c->degree, &a, &b);
  for (i = 0; i < pb->m; i++)
    if (!(pb->u[i] >= a && pb->u[i] <= b)) return 0;
  return 1;
}

static void check_fit(const problem *pb, const bsfit_curve *c, const bsfit_fit_report *rep,
                      const double *res) {
  size_t i;
  double mx = 0, top;
  fz_check_curve(c, "fit: curve");
  if (!fz_strict) return;
  top = params_in_domain(pb, c) ? 1 + 1e-9 : INFINITY;
  if (!isfinite(rep->rms) || !isfinite(rep->max) ||
      !(rep->rcond >= 0 && rep->rcond <= top)) { /* 1 + rounding */
    char d[160];
    snprintf(d, sizeof d, "rms %g max %g rcond %.17g, m %zu n %zu p %d periodic %d solver %d",
             rep->rms, rep->max, rep->rcond, pb->m, c->n, c->degree, c->periodic, (int)rep->solver);
    fz_fail("fit: report", d);
  }
  fz_check_finite(res, pb->m, "fit: residuals");
  for (i = 0; i < pb->m; i++) mx = fmax(mx, res[i]);
  if (mx != rep->max) fz_fail("fit: max is not the largest residual", NULL);
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size) {
  fuzz_in in = {data, size};
  problem pb;
  bsfit_fit_opts o;
  bsfit_fitter *f = NULL;
  bsfit_fit_report rep;
  bsfit_curve c;
  bsfit_status st;
  double res[MAXM];
  size_t i, nk;
  int pass;
  memset(&pb, 0, sizeof pb);
  make_points(&in, &pb);
  bsfit_fit_opts_init(&o);
  o.degree = 1 + fz_byte(&in) % 5;
  o.periodic = fz_byte(&in) % 2;
  o.count = (size_t)(1 + fz_byte(&in) % (pb.m + 2));
  o.rule = (bsfit_knot_rule)(fz_byte(&in) % 5);
  o.solver = (bsfit_solver)(fz_byte(&in) % 3);
  if (!o.periodic && fz_byte(&in) % 3 == 0) o.fix_ends = 1;
  if (!o.periodic && fz_byte(&in) % 4 == 0) {
    for (i = 0; i < 3; i++) pb.t0[i] = fz_double(&in), pb.t1[i] = fz_double(&in);
    o.tangent_start = pb.t0;
    o.tangent_end = fz_byte(&in) % 2 ? pb.t1 : NULL;
    o.tangent_dim = pb.dim;
  }
  if (fz_byte(&in) % 4 == 0) { /* fixed knots: steps from the bytes */
    double x = 0;
    nk = o.periodic ? o.count + 1 : o.count + (size_t)o.degree + 1;
    if (nk > MAXM + 16) nk = MAXM + 16;
    for (i = 0; i < nk; i++) pb.knots[i] = x, x += (double)(fz_byte(&in) % 8) / 4.0;
    o.knots = pb.knots;
    o.nknots = nk;
  }
  if (fz_byte(&in) % 4 == 0) {
    for (i = 0; i < pb.m; i++) pb.u[i] = fz_double(&in);
  } else if (bsfit_params(pb.pts, pb.m, pb.dim, (bsfit_param_kind)(fz_byte(&in) % 3), o.periodic,
                          pb.u, &st) != BSFIT_OK) {
    return 0;
  } else {
    fz_check_finite(pb.u, pb.m, "params"); /* item 8: chords that underflow gave NaN */
  }
  fz_strict = fz_tame(pb.pts, pb.m * (size_t)pb.dim) && (!pb.use_w || fz_tame(pb.w, pb.m)) &&
              (o.tangent_start == NULL || fz_tame(pb.t0, (size_t)pb.dim)) &&
              (o.tangent_end == NULL || fz_tame(pb.t1, (size_t)pb.dim));
  if (getenv("FUZZ_DEBUG")) { /* what the input asks for, to turn a finding into a test */
    fprintf(
        stderr,
        "m %zu dim %d p %d count %zu periodic %d rule %d solver %d fix %d tan %d knots %zu w %d\n",
        pb.m, pb.dim, o.degree, o.count, o.periodic, (int)o.rule, (int)o.solver, o.fix_ends,
        o.tangent_start != NULL, o.knots ? o.nknots : 0, pb.use_w);
    for (i = 0; i < pb.m; i++)
      fprintf(stderr, "  %.17g %.17g u %.17g w %.17g\n", pb.pts[i * (size_t)pb.dim],
              pb.pts[i * (size_t)pb.dim + 1], pb.u[i], pb.w[i]);
    for (i = 0; o.knots && i < o.nknots; i++) fprintf(stderr, " k %.17g", pb.knots[i]);
  }
  if (bsfit_fitter_new(&f, &o, NULL, &st) != BSFIT_OK) return 0;
  bsfit_curve_init(&c);
  for (pass = 0; pass < 2; pass++) { /* the second fit reuses the workspace and the curve */
    if (bsfit_fitter_fit(f, pb.pts, pb.m, pb.dim, pb.u, pb.use_w ? pb.w : NULL, &c, &rep, res,
                         &st) == BSFIT_OK)
      check_fit(&pb, &c, &rep, res);
    else if (c.n != 0)
      fz_fail("fit: curve not emptied on error", st.msg);
  }
  bsfit_curve_free(&c);
  bsfit_fitter_free(f);
  return 0;
}
