/*
** quadrature.c
** Gauss-Legendre rules (quadrature.h).
*/
#include "quadrature.h"

#include <math.h>

void bsfit__gauss_legendre(int n, double *x, double *w) {
  int i, j, it;
  for (i = 0; i < (n + 1) / 2; i++) {
    /* Chebyshev-like start for the i-th largest root, then Newton on P_n */
    double z = cos(3.14159265358979323846 * ((double)i + 0.75) / ((double)n + 0.5)), dp = 1.0;
    for (it = 0; it < 100; it++) {
      double p0 = 1.0, p1 = z, dz;
      for (j = 2; j <= n; j++) {
        double p2 = ((2.0 * j - 1.0) * z * p1 - (j - 1.0) * p0) / (double)j;
        p0 = p1;
        p1 = p2;
      }
      dp = (double)n * (z * p1 - p0) / (z * z - 1.0);
      dz = p1 / dp;
      z -= dz;
      if (fabs(dz) <= 1e-16) break;
    }
    x[i] = -z;
    x[n - 1 - i] = z;
    w[i] = w[n - 1 - i] = 2.0 / ((1.0 - z * z) * dp * dp);
  }
}
