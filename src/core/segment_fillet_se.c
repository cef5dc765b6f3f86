/*
** segment_fillet_se.c
** The standard error of a fillet's radius, its lines' own errors included
** (bsfit__fillet_radius_se; docs/auto.md, "radius_se").
*/
#include "segment_internal.h"

#include <math.h>
#include <stddef.h>

/* the frame of the fillet between lines a and b (fillet_frame); 0 when they frame none */
typedef struct fillet_frame_of {
  double V[2], u[2], k;
} fillet_frame_of;

static int frame_of(const bsfit__line *a, const bsfit__line *b, fillet_frame_of *f) {
  seg_model ma, mb;
  ma.kind = mb.kind = LINE, ma.line = *a, mb.line = *b;
  return bsfit__fillet_frame(&ma, &mb, f->V, f->u, &f->k);
}

/* sample q's distance to the circle of radius r of frame f, minus r */
static double frame_residual(const fillet_frame_of *f, const double *q, double r) {
  return hypot(q[0] - f->V[0] - f->u[0] * f->k * r, q[1] - f->V[1] - f->u[1] * f->k * r) - r;
}

/* a line through its samples' centroid x turned by dphi and moved by dc along its normal:
** the perturbations whose variances are sigma^2 / S_tt and sigma^2 / n */
static bsfit__line moved_line(const bsfit__line *L, const double *x, double dphi, double dc) {
  bsfit__line M;
  double c = cos(dphi), sn = sin(dphi);
  M.d[0] = c * L->d[0] - sn * L->d[1];
  M.d[1] = sn * L->d[0] + c * L->d[1];
  M.p[0] = x[0] - M.d[1] * dc;
  M.p[1] = x[1] + M.d[0] * dc;
  return M;
}

/* the centroid x of line piece l's samples (its foot on L); returns the spread of their
** places along it, S_tt */
static double line_spread(const seg_section *s, const bsfit_piece *l, const bsfit__line *L,
                          double *x) {
  double stt = 0, tm = 0;
  size_t j;
  for (j = 0; j < l->count; j++) {
    const double *q = sample(s, l->first + j);
    tm += ((q[0] - L->p[0]) * L->d[0] + (q[1] - L->p[1]) * L->d[1]) / (double)l->count;
  }
  x[0] = L->p[0] + tm * L->d[0], x[1] = L->p[1] + tm * L->d[1];
  for (j = 0; j < l->count; j++) {
    const double *q = sample(s, l->first + j);
    double t = (q[0] - x[0]) * L->d[0] + (q[1] - x[1]) * L->d[1];
    stt += t * t;
  }
  return stt;
}

/* The four line parameters' perturbed frames (each line's direction and offset, by +h and
** -h: up[k], down[k]) and their variances over sigma^2; 0 when one frames no fillet. */
static int perturbed_frames(const seg_section *s, const bsfit_piece *A, const bsfit__line *la,
                            const bsfit_piece *B, const bsfit__line *lb, fillet_frame_of *up,
                            fillet_frame_of *down, double *h, double *var) {
  const bsfit__line *L[2] = {la, lb};
  const bsfit_piece *lp[2] = {A, B};
  int side, par;
  for (side = 0; side < 2; side++) {
    double x[2], stt = line_spread(s, lp[side], L[side], x);
    for (par = 0; par < 2; par++) {
      int k = 2 * side + par;
      bsfit__line lu, ld;
      h[k] = par == 0 ? 1e-7 : 1e-7 * s->size;
      var[k] = par == 0 ? (stt > 0 ? 1.0 / stt : HUGE_VAL) : 1.0 / (double)lp[side]->count;
      lu = moved_line(L[side], x, par == 0 ? h[k] : 0, par == 1 ? h[k] : 0);
      ld = moved_line(L[side], x, par == 0 ? -h[k] : 0, par == 1 ? -h[k] : 0);
      if (!frame_of(side ? la : &lu, side ? &lu : lb, &up[k]) ||
          !frame_of(side ? la : &ld, side ? &ld : lb, &down[k]))
        return 0;
    }
  }
  return 1;
}

/* segment_internal.h. The radius is fitted to F's samples with the lines held (r solves
** sum e_j de_j/dr = 0), and the lines are fitted to their own samples: by the delta
** method its variance is sigma^2 / I (I = sum (de_j/dr)^2, its own samples) plus, for
** each of the four line parameters theta (each line's direction and offset at its
** centroid, independent, of variances sigma^2 / S_tt and sigma^2 / n), (g / I)^2 Var(theta)
** with g = sum de_j/dtheta de_j/dr: how far an error of the lines moves the fitted radius
** (1 / (k - 1) times their offset, more at a gentle turn). Derivatives by central
** differences; no scratch memory. */
double bsfit__fillet_radius_se(const seg_section *s, const bsfit_piece *A, const seg_model *ma,
                               const bsfit_piece *F, const bsfit_piece *B, const seg_model *mb) {
  fillet_frame_of f, up[4], down[4];
  double h[4], var[4], g[4] = {0, 0, 0, 0}, I = 0, r = F->radius, hr = 1e-6 * F->radius, v;
  size_t j;
  int k;
  if (!s->noisy) return 0.0;
  if (F->count == 0 || !(r > 0) || !frame_of(&ma->line, &mb->line, &f) ||
      !perturbed_frames(s, A, &ma->line, B, &mb->line, up, down, h, var))
    return HUGE_VAL;
  for (j = 0; j < F->count; j++) {
    const double *q = sample(s, F->first + j);
    double dr = (frame_residual(&f, q, r + hr) - frame_residual(&f, q, r - hr)) / (2 * hr);
    I += dr * dr;
    for (k = 0; k < 4; k++)
      g[k] += (frame_residual(&up[k], q, r) - frame_residual(&down[k], q, r)) / (2 * h[k]) * dr;
  }
  if (!(I > 0)) return HUGE_VAL;
  v = 1.0 / I;
  for (k = 0; k < 4; k++) v += (g[k] / I) * (g[k] / I) * var[k];
  return v < HUGE_VAL ? s->unit * sqrt(v) : HUGE_VAL;
}
