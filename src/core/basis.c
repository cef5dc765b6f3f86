/*
** basis.c
** B-spline basis functions and derivatives (Cox-de Boor, NURBS Book A2.2/A2.3)
** and Bernstein polynomials. Only the p+1 non-zero functions are ever computed.
*/
#include "internal.h"

void bsfit_basis_funs(size_t s, double u, int p, const double *U, double *N) {
  double left[BSFIT_MAX_DEGREE + 1], right[BSFIT_MAX_DEGREE + 1];
  int j, r;
  N[0] = 1.0;
  for (j = 1; j <= p; j++) {
    double saved = 0.0;
    left[j] = u - U[s + 1 - (size_t)j];
    right[j] = U[s + (size_t)j] - u;
    for (r = 0; r < j; r++) {
      double den = right[r + 1] + left[j - r];
      double tmp = den != 0.0 ? N[r] / den : 0.0; /* 0/0 = 0 at repeated knots */
      N[r] = saved + right[r + 1] * tmp;
      saved = left[j - r] * tmp;
    }
    N[j] = saved;
  }
}

void bsfit_basis_ders(size_t s, double u, int p, int nd, const double *U, double *ders) {
  double ndu[BSFIT_MAX_DEGREE + 1][BSFIT_MAX_DEGREE + 1];
  double a[2][BSFIT_MAX_DEGREE + 1];
  double left[BSFIT_MAX_DEGREE + 1], right[BSFIT_MAX_DEGREE + 1];
  int j, r, k, stride = p + 1, top = nd < p ? nd : p;

  /* ndu: lower triangle knot differences, upper triangle basis values */
  ndu[0][0] = 1.0;
  for (j = 1; j <= p; j++) {
    double saved = 0.0;
    left[j] = u - U[s + 1 - (size_t)j];
    right[j] = U[s + (size_t)j] - u;
    for (r = 0; r < j; r++) {
      double tmp;
      ndu[j][r] = right[r + 1] + left[j - r];
      tmp = ndu[j][r] != 0.0 ? ndu[r][j - 1] / ndu[j][r] : 0.0;
      ndu[r][j] = saved + right[r + 1] * tmp;
      saved = left[j - r] * tmp;
    }
    ndu[j][j] = saved;
  }
  for (j = 0; j <= p; j++) ders[j] = ndu[j][p];

  for (r = 0; r <= p; r++) {
    int s1 = 0, s2 = 1;
    a[0][0] = 1.0;
    for (k = 1; k <= top; k++) {
      double d = 0.0;
      int rk = r - k, pk = p - k, j1, j2, tmp;
      if (r >= k) {
        a[s2][0] = ndu[pk + 1][rk] != 0.0 ? a[s1][0] / ndu[pk + 1][rk] : 0.0;
        d = a[s2][0] * ndu[rk][pk];
      }
      j1 = rk >= -1 ? 1 : -rk;
      j2 = (r - 1 <= pk) ? k - 1 : p - r;
      for (j = j1; j <= j2; j++) {
        a[s2][j] = ndu[pk + 1][rk + j] != 0.0
                       ? (a[s1][j] - a[s1][j - 1]) / ndu[pk + 1][rk + j]
                       : 0.0;
        d += a[s2][j] * ndu[rk + j][pk];
      }
      if (r <= pk) {
        a[s2][k] = ndu[pk + 1][r] != 0.0 ? -a[s1][k - 1] / ndu[pk + 1][r] : 0.0;
        d += a[s2][k] * ndu[r][pk];
      }
      ders[k * stride + r] = d;
      tmp = s1;
      s1 = s2;
      s2 = tmp;
    }
  }
  /* multiply by p!/(p-k)! */
  {
    double f = (double)p;
    for (k = 1; k <= top; k++) {
      for (j = 0; j <= p; j++) ders[k * stride + j] *= f;
      f *= (double)(p - k);
    }
  }
  for (k = top + 1; k <= nd; k++)
    for (j = 0; j <= p; j++) ders[k * stride + j] = 0.0;
}

void bsfit_bernstein(int n, double u, double *B) {
  double u1 = 1.0 - u;
  int j, k;
  /* NURBS Book A1.3 for all n+1 functions at once */
  B[0] = 1.0;
  for (j = 1; j <= n; j++) {
    double saved = 0.0;
    for (k = 0; k < j; k++) {
      double tmp = B[k];
      B[k] = saved + u1 * tmp;
      saved = u * tmp;
    }
    B[j] = saved;
  }
}
