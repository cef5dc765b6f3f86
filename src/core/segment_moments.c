/*
** segment_moments.c
** Residuals of a line or a circle fitted to any run of a section in O(1), from prefix
** sums of the samples' moments: what lets the segmentation of a noisy section weigh every
** candidate piece by how well it explains its samples, not only by whether it does.
*/
#include "features_internal.h"

#include <math.h>
#include <string.h>

/* the moments summed: x, y, xx, xy, yy, z, xz, yz, zz with z = xx + yy */
enum { MX, MY, MXX, MXY, MYY, MZ, MXZ, MYZ, MZZ, NMOM };

bsfit_err bsfit__moments_init(bsfit__moments *mo, const double *pts, size_t m,
                              const bsfit_allocator *a) {
  size_t i, n = 2 * m;
  double cx = 0, cy = 0, size = bsfit__segment_size(pts, m);
  memset(mo, 0, sizeof *mo);
  mo->sum = bsfit__alloc(a, bsfit__mulsize(NMOM * (n + 1), sizeof(double)));
  if (mo->sum == NULL) return BSFIT_ENOMEM;
  mo->n = n;
  for (i = 0; i < m; i++) cx += pts[2 * i], cy += pts[2 * i + 1];
  /* about the centroid, in units of the size: the sums stay small and well conditioned */
  mo->c[0] = cx / (double)m, mo->c[1] = cy / (double)m;
  mo->scale = size > 0 ? size : 1.0;
  memset(mo->sum, 0, NMOM * sizeof(double));
  for (i = 0; i < n; i++) {
    const double *q = pts + 2 * (i % m);
    double x = (q[0] - mo->c[0]) / mo->scale, y = (q[1] - mo->c[1]) / mo->scale, z = x * x + y * y;
    double v[NMOM] = {x, y, x * x, x * y, y * y, z, x * z, y * z, z * z};
    const double *prev = mo->sum + NMOM * i;
    double *next = mo->sum + NMOM * (i + 1);
    int k;
    for (k = 0; k < NMOM; k++) next[k] = prev[k] + v[k];
  }
  return BSFIT_OK;
}

void bsfit__moments_free(bsfit__moments *mo, const bsfit_allocator *a) {
  if (mo->sum) bsfit__free(a, mo->sum, (mo->n + 1) * NMOM * sizeof(double));
  mo->sum = NULL;
}

/* the moments of samples first .. first + n - 1 (unwrapped: first + n <= 2m), centred */
typedef struct central {
  double n, mx, my, mz, xx, xy, yy, xz, yz, zz;
} central;

static central central_of(const bsfit__moments *mo, size_t first, size_t n) {
  const double *a = mo->sum + NMOM * first, *b = mo->sum + NMOM * (first + n);
  central c;
  double s[NMOM];
  int k;
  for (k = 0; k < NMOM; k++) s[k] = b[k] - a[k];
  c.n = (double)n;
  c.mx = s[MX] / c.n, c.my = s[MY] / c.n, c.mz = s[MZ] / c.n;
  c.xx = s[MXX] - c.n * c.mx * c.mx;
  c.xy = s[MXY] - c.n * c.mx * c.my;
  c.yy = s[MYY] - c.n * c.my * c.my;
  c.xz = s[MXZ] - c.n * c.mx * c.mz;
  c.yz = s[MYZ] - c.n * c.my * c.mz;
  c.zz = s[MZZ] - c.n * c.mz * c.mz;
  return c;
}

double bsfit__moments_line_rss(const bsfit__moments *mo, size_t first, size_t n) {
  central c;
  double h, e;
  if (n < 2 || first + n > mo->n) return HUGE_VAL;
  c = central_of(mo, first, n);
  /* the smaller eigenvalue of the scatter matrix: the total least-squares residual */
  h = 0.5 * (c.xx + c.yy);
  e = h - hypot(0.5 * (c.xx - c.yy), c.xy);
  return (e > 0 ? e : 0.0) * mo->scale * mo->scale;
}

/* Taubin's circle (the algebraic fit normalised by the mean squared gradient, nearly free
** of the bias that draws Kasa's fit to small circles on short noisy arcs), from the run's
** moments about its own centroid: Newton on its characteristic cubic from 0 (Chernov,
** "Circular and linear regression", 2010). Its residual is then the algebraic one over
** 4 r^2, the geometric one to first order for samples near the circle, which is all the
** runs the segmentation admits (each within its tolerance of a geometric fit). */
typedef struct own {
  double mxx, mxy, myy, mxz, myz, mzz, mz; /* means, about the run's centroid */
} own;

static own own_moments(const central *c) {
  /* z' = z - 2 mx x - 2 my y + mx^2 + my^2 about the run's centroid (mx, my); in sums:
  ** S(x' z') = S(xz)' below, S(z'^2) likewise, from the section-centred sums */
  own o;
  double n = c->n;
  o.mxx = c->xx / n, o.mxy = c->xy / n, o.myy = c->yy / n;
  o.mz = o.mxx + o.myy;
  /* x' = x - mx: S(x' z') = S(x' (z - mz)) - 2 mx S(x' x') - 2 my S(x' y') */
  o.mxz = (c->xz - 2 * c->mx * c->xx - 2 * c->my * c->xy) / n;
  o.myz = (c->yz - 2 * c->mx * c->xy - 2 * c->my * c->yy) / n;
  /* z' - mean z' = (z - mz) - 2 mx x' - 2 my y' */
  o.mzz = (c->zz + 4 * c->mx * c->mx * c->xx + 4 * c->my * c->my * c->yy +
           8 * c->mx * c->my * c->xy - 4 * c->mx * c->xz - 4 * c->my * c->yz) / n + o.mz * o.mz;
  return o;
}

double bsfit__moments_arc_rss(const bsfit__moments *mo, size_t first, size_t n) {
  central c;
  own o;
  double cov, var_z, a0, a1, a2, a3, x = 0, y, det, xc, yc, r2, e;
  int it;
  if (n < 3 || first + n > mo->n) return HUGE_VAL;
  c = central_of(mo, first, n);
  o = own_moments(&c);
  cov = o.mxx * o.myy - o.mxy * o.mxy;
  var_z = o.mzz - o.mz * o.mz;
  a3 = 4 * o.mz;
  a2 = -3 * o.mz * o.mz - o.mzz;
  a1 = var_z * o.mz + 4 * cov * o.mz - o.mxz * o.mxz - o.myz * o.myz;
  a0 = o.mxz * (o.mxz * o.myy - o.myz * o.mxy) + o.myz * (o.myz * o.mxx - o.mxz * o.mxy) -
       var_z * cov;
  y = a0;
  for (it = 0; it < 30; it++) {
    double dy = a1 + x * (2 * a2 + 3 * a3 * x), xn, yn;
    if (!(dy != 0)) break;
    xn = x - y / dy;
    yn = a0 + xn * (a1 + xn * (a2 + xn * a3));
    if (!(fabs(yn) < fabs(y))) break;
    x = xn, y = yn;
  }
  det = x * x - x * o.mz + cov;
  if (!(fabs(det) > 0)) return HUGE_VAL;
  xc = (o.mxz * (o.myy - x) - o.myz * o.mxy) / det / 2;
  yc = (o.myz * (o.mxx - x) - o.mxz * o.mxy) / det / 2;
  r2 = xc * xc + yc * yc + o.mz;
  if (!(r2 > 0) || !isfinite(r2)) return HUGE_VAL;
  /* sum of (|p - c|^2 - r^2)^2 = sum of ((z' - mz) - 2 xc x' - 2 yc y')^2 */
  e = (o.mzz - o.mz * o.mz) + 4 * xc * xc * o.mxx + 4 * yc * yc * o.myy + 8 * xc * yc * o.mxy -
      4 * xc * o.mxz - 4 * yc * o.myz;
  return (e > 0 ? e : 0.0) * c.n / (4 * r2) * mo->scale * mo->scale;
}
