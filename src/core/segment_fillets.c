/*
** segment_fillets.c
** Fillets of a segmentation: an arc between two lines it meets tangentially is refitted
** with its circle tangent to both (one unknown, its radius), and takes the samples of the
** lines past its tangent points (docs/auto.md, step 8 "Fillets").
*/
#include "segment_internal.h"

#include <math.h>
#include <string.h>

/* The radius of the circle tangent to two lines (its centre V + u k r) that fits F's
** samples best: Gauss-Newton on the geometric distances, from r. Its residual sum of
** squares into *rss; -1 when it fails. */
static double fillet_radius(const seg_section *s, const bsfit_piece *F, const double *V,
                            const double *u, double k, double r, double *rss) {
  int it;
  size_t j;
  for (it = 0; it < 20; it++) {
    double g = 0, h = 0, step;
    *rss = 0;
    for (j = 0; j < F->count; j++) {
      const double *q = sample(s, F->first + j);
      double dx = q[0] - V[0] - u[0] * k * r, dy = q[1] - V[1] - u[1] * k * r, d = hypot(dx, dy);
      double e = d - r, de = d > 0 ? -(dx * u[0] + dy * u[1]) * k / d - 1.0 : -1.0;
      g += de * e;
      h += de * de;
      *rss += e * e;
    }
    if (!(h > 0)) return -1.0;
    step = -g / h;
    r += step;
    if (!(r > 0)) return -1.0;
    if (fabs(step) <= 1e-15 * r) break;
  }
  return r;
}

/* A fillet: an arc meeting a line tangentially at both ends. Its circle is then known
** from the two lines up to its radius (its centre on the bisector of their corner), so
** it is refitted with that one unknown: a short noisy arc alone leaves its radius
** uncertain by many percent, the lines fix all but one of its parameters. But the lines
** are extrapolated to their corner, and an error there moves the radius by 1/(k - 1)
** times as much (2.4 at a right angle): the refit is taken only when its samples do not
** tell against it, i.e. it adds at most 9 sigma^2 to their residual (the chi-square of its
** two fewer parameters at 99%). The tangent points move to the new circle. */
static void refit_fillet(const seg_section *s, bsfit_piece *A, const seg_model *ma, bsfit_piece *F,
                         seg_model *mf, bsfit_piece *B, const seg_model *mb) {
  double V[2], u[2], k, r, c[2], f[2], t[2], rms = 0, un, cosphi, rss;
  if (!bsfit__meet_lines(&ma->line, &mb->line, V)) return;
  u[0] = mb->line.d[0] - ma->line.d[0];
  u[1] = mb->line.d[1] - ma->line.d[1];
  un = hypot(u[0], u[1]);
  cosphi = -(ma->line.d[0] * mb->line.d[0] + ma->line.d[1] * mb->line.d[1]);
  if (!(un > 1e-12) || cosphi >= 1 - 1e-12) return;
  u[0] /= un, u[1] /= un;
  k = 1.0 / sin(0.5 * acos(fmax(-1.0, fmin(1.0, cosphi))));
  r = fillet_radius(s, F, V, u, k, mf->circle.r, &rss);
  if (!(r > 0) || rss - F->rms * F->rms * (double)F->count > 9.0 * s->unit * s->unit) return;
  c[0] = V[0] + u[0] * k * r;
  c[1] = V[1] + u[1] * k * r;
  mf->circle.c[0] = c[0], mf->circle.c[1] = c[1], mf->circle.r = r;
  F->centre[0] = c[0], F->centre[1] = c[1], F->radius = r;
  bsfit__model_foot(ma, c, f, t);
  memcpy(A->end, f, sizeof f), memcpy(F->start, f, sizeof f);
  bsfit__model_foot(mb, c, f, t);
  memcpy(B->start, f, sizeof f), memcpy(F->end, f, sizeof f);
  bsfit__model_foot(mf, F->start, f, F->t_start);
  bsfit__model_foot(mf, F->end, f, F->t_end);
  F->max = bsfit__circle_max(&mf->circle, &(bsfit__run){s->pts, s->m, F->first, F->count}, &rms);
  F->rms = rms;
}

/* Samples of line A past its tangent point with fillet F (their feet beyond A's end along
** A), and of B before it, lie on the fillet: a line that held them (they were within its
** tolerance) bends the fillet's radius by percents. They go to F; returns how many moved. */
static size_t claim_for_fillet(const seg_section *s, bsfit_piece *A, const seg_model *ma,
                               bsfit_piece *F, bsfit_piece *B, const seg_model *mb) {
  size_t moved = 0;
  while (A->count > s->min_len[LINE]) {
    const double *q = sample(s, A->first + A->count - 1);
    if ((q[0] - A->end[0]) * ma->line.d[0] + (q[1] - A->end[1]) * ma->line.d[1] <= 0) break;
    A->count--, F->first = (F->first + s->m - 1) % s->m, F->count++, moved++;
  }
  while (B->count > s->min_len[LINE]) {
    const double *q = sample(s, B->first);
    if ((q[0] - B->start[0]) * mb->line.d[0] + (q[1] - B->start[1]) * mb->line.d[1] >= 0) break;
    B->first = (B->first + 1) % s->m, B->count--, F->count++, moved++;
  }
  return moved;
}

void bsfit__refit_fillets(const seg_section *s, bsfit_piece *p, seg_model *md, size_t np) {
  size_t i;
  int pass;
  for (pass = 0; pass < 2; pass++)
    for (i = 0; i < np; i++) {
      size_t ia = (i + np - 1) % np, ib = (i + 1) % np;
      if (p[i].kind != ARC || np < 3 || p[ia].kind != LINE || p[ib].kind != LINE) continue;
      if (!s->closed && (i == 0 || i + 1 == np)) continue;
      if (p[i].join != BSFIT_JOIN_TANGENT || p[ib].join != BSFIT_JOIN_TANGENT) continue;
      refit_fillet(s, &p[ia], &md[ia], &p[i], &md[i], &p[ib], &md[ib]);
      /* the second pass places every tangent point on the lines as they end up */
      if (pass == 0 && s->noisy && claim_for_fillet(s, &p[ia], &md[ia], &p[i], &p[ib], &md[ib])) {
        bsfit__segment_refit(s, &p[ia], &md[ia]);
        bsfit__segment_refit(s, &p[ib], &md[ib]);
        refit_fillet(s, &p[ia], &md[ia], &p[i], &md[i], &p[ib], &md[ib]);
      }
    }
}
