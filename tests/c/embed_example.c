/*
** embed_example.c
** An example host program for the embedding API (bsfit_engine.h): it builds a
** sandboxed engine with a memory cap and an instruction budget, fits a curve to
** its own point array with a strategy script, uses the curve from C, and shows
** that a misbehaving script is stopped with a message while the host carries on.
**
**   embed_example [STRATEGY]   (a module name or a .lua path returning {run = ...})
**
** Exit status 0 when everything behaved as described, 1 otherwise (ctest runs it).
*/
#include "bsfit.h"
#include "bsfit_engine.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>

#define M 16

int main(int argc, char **argv) {
  const char *strategy = argc > 1 ? argv[1] : "bsfit.strategy.periodic";
  bsfit_engine_opts opts = {0};
  bsfit_engine_report rep;
  bsfit_engine *e;
  bsfit_curve c;
  double pts[2 * M], a, b, p[2];
  int i, failures = 0;
  bsfit_err code;

  /* The host's data: points on a quarter of the unit circle. */
  for (i = 0; i < M; i++) {
    double t = (3.14159265358979323846 / 2) * i / (M - 1);
    pts[2 * i] = cos(t);
    pts[2 * i + 1] = sin(t);
  }

  /* An engine for untrusted strategies: no io/os, 16 MB, 50 million instructions. */
  opts.sandbox = 1;
  opts.mem_limit = 16u << 20;
  opts.instr_budget = 50000000ULL;
  opts.argv0 = argv[0];
  e = bsfit_engine_new(&opts);
  if (e == NULL) {
    fprintf(stderr, "embed_example: cannot create the engine\n");
    return 1;
  }

  /* Fit: the curve comes back as a plain C struct the host owns. */
  bsfit_curve_init(&c);
  /* No weights, default options (a Lua table constructor such as "{ degree = 3 }"). */
  code = bsfit_engine_fit(e, strategy, pts, M, 2, NULL, NULL, &c, &rep);
  if (code != BSFIT_OK) {
    fprintf(stderr, "embed_example: fit failed (%s): %s\n", bsfit_errname(code),
            bsfit_engine_errmsg(e));
    failures++;
  } else {
    bsfit_curve_domain(&c, &a, &b);
    printf("curve: degree %d, %zu control points, domain [%g, %g]\n", c.degree, c.n, a, b);
    printf("report: rms %g, max %g, %zu points, start at %zu\n", rep.rms, rep.max, rep.count,
           rep.start_index);
    for (i = 0; i <= 4; i++) {
      double u = a + (b - a) * i / 4.0;
      bsfit_curve_eval(&c, u, p, NULL);
      printf("  C(%.3f) = (%.6f, %.6f)  |C| = %.6f\n", u, p[0], p[1], hypot(p[0], p[1]));
    }
  }
  bsfit_curve_free(&c);

  /* A script that escapes, loops or hoards is stopped; the host keeps running. */
  {
    static const char *const bad[] = {
      "io.open('/etc/passwd')",                                  /* no io in the sandbox */
      "while true do pcall(function() while true do end end) end", /* instruction budget */
      "local t = {} for i = 1, 1e9 do t[i] = {i} end",           /* memory cap */
    };
    size_t k;
    for (k = 0; k < sizeof bad / sizeof bad[0]; k++) {
      code = bsfit_engine_run_string(e, bad[k], "=untrusted");
      printf("untrusted script %zu stopped: %s\n  %s\n", k + 1, bsfit_errname(code),
             bsfit_engine_errmsg(e));
      if (code == BSFIT_OK) failures++;
    }
  }

  /* Still usable afterwards. */
  code = bsfit_engine_run_string(e, "assert(1 + 1 == 2)", "=after");
  if (code != BSFIT_OK) failures++;
  printf("engine still usable: %s\n", code == BSFIT_OK ? "yes" : "no");

  bsfit_engine_free(e);
  return failures == 0 ? 0 : 1;
}
