/*
** shapes.h
** Synthetic sections with known truth for the tests: smooth closed shapes given by a
** radius function r(theta), polygons with sharp corners, Gaussian noise.
*/
#ifndef BSFIT_TEST_SHAPES_H
#define BSFIT_TEST_SHAPES_H

#include <math.h>
#include <stddef.h>

#include "testutil.h"

#define SHAPE_PI 3.14159265358979323846

static inline double rng_gauss(test_rng *r) {
  double u1 = rng_uniform(r), u2 = rng_uniform(r);
  if (u1 < 1e-300) u1 = 1e-300;
  return sqrt(-2.0 * log(u1)) * cos(2.0 * SHAPE_PI * u2);
}

typedef enum { SHAPE_CIRCLE, SHAPE_ELLIPSE, SHAPE_STAR, SHAPE_SUPERELLIPSE } smooth_shape;

/* a point of a smooth closed shape of size ~1 at angle t */
static inline void shape_point(smooth_shape s, double t, double *xy) {
  double c = cos(t), sn = sin(t);
  switch (s) {
    case SHAPE_CIRCLE: xy[0] = c; xy[1] = sn; break;
    case SHAPE_ELLIPSE: xy[0] = 1.0 * c; xy[1] = 0.5 * sn; break;
    case SHAPE_STAR: {
      double r = 1.0 + 0.15 * cos(5.0 * t); /* valley radius of curvature 0.25 */
      xy[0] = r * c;
      xy[1] = r * sn;
      break;
    }
    case SHAPE_SUPERELLIPSE: { /* |x|^4 + |y|^4 = 1 */
      xy[0] = (c < 0 ? -1 : 1) * sqrt(fabs(c));
      xy[1] = (sn < 0 ? -1 : 1) * sqrt(fabs(sn));
      break;
    }
  }
}

/* m points of shape s, uneven spacing when `uneven`, isotropic noise sigma */
static inline void make_shape(test_rng *r, smooth_shape s, size_t m, int uneven, double sigma,
                              double *xy) {
  size_t i;
  for (i = 0; i < m; i++) {
    double t = 2.0 * SHAPE_PI * (double)i / (double)m;
    if (uneven) t += 0.5 * sin(t) * (2.0 * SHAPE_PI / (double)m) * 1.8 + 0.3 * sin(2.0 * t);
    shape_point(s, t, xy + 2 * i);
    xy[2 * i] += sigma * rng_gauss(r);
    xy[2 * i + 1] += sigma * rng_gauss(r);
  }
}

/* m points walking along a closed polygon (vertices v, nv of them), evenly in arc
** length, with isotropic noise sigma */
static inline void make_polygon(test_rng *r, const double *v, size_t nv, size_t m,
                                double sigma, double *xy) {
  double per = 0, step, pos = 0;
  size_t i, e = 0;
  double acc = 0;
  for (i = 0; i < nv; i++) {
    const double *a = v + 2 * i, *b = v + 2 * ((i + 1) % nv);
    per += hypot(b[0] - a[0], b[1] - a[1]);
  }
  step = per / (double)m;
  for (i = 0; i < m; i++, pos += step) {
    const double *a, *b;
    double len;
    for (;;) {
      a = v + 2 * e;
      b = v + 2 * ((e + 1) % nv);
      len = hypot(b[0] - a[0], b[1] - a[1]);
      if (pos <= acc + len || e + 1 == nv) break;
      acc += len;
      e++;
    }
    {
      double f = (pos - acc) / len;
      xy[2 * i] = a[0] + f * (b[0] - a[0]) + sigma * rng_gauss(r);
      xy[2 * i + 1] = a[1] + f * (b[1] - a[1]) + sigma * rng_gauss(r);
    }
  }
}

#endif
