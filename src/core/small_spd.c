/*
** small_spd.c
** Cholesky factorisation and solve of tiny dense SPD systems (n <= 5: the local
** polynomial fits of the noise estimate and the corner tests, thousands per section),
** where a LAPACK call would cost more than the arithmetic.
*/
#include "internal.h"

#include <math.h>

int bsfit__small_cholesky(int n, double A[BSFIT__SMALL][BSFIT__SMALL]) {
  int i, j, k;
  double tr = 0;
  for (i = 0; i < n; i++) tr += A[i][i];
  for (j = 0; j < n; j++) {
    double d = A[j][j];
    for (k = 0; k < j; k++) d -= A[j][k] * A[j][k];
    if (!(d > 1e-13 * tr)) return 0;
    A[j][j] = sqrt(d);
    for (i = j + 1; i < n; i++) {
      double s = A[i][j];
      for (k = 0; k < j; k++) s -= A[i][k] * A[j][k];
      A[i][j] = s / A[j][j];
    }
  }
  return 1;
}

void bsfit__small_chol_solve(int n, const double L[BSFIT__SMALL][BSFIT__SMALL], double *b) {
  int i, k;
  for (i = 0; i < n; i++) {
    for (k = 0; k < i; k++) b[i] -= L[i][k] * b[k];
    b[i] /= L[i][i];
  }
  for (i = n - 1; i >= 0; i--) {
    for (k = i + 1; k < n; k++) b[i] -= L[k][i] * b[k];
    b[i] /= L[i][i];
  }
}
