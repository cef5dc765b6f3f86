/*
** corners.c
** Sharp corners of a noisy ordered contour: two straight sides meeting near the data
** at a turn much larger than the noise allows (see bsfit_analysis.h). This file holds
** the candidates and the detection; the side models are in corners_sides.c,
** corners_curved.c and corners_slope.c (corners_internal.h).
*/
#include "corners_internal.h"

#include <math.h>
#include <string.h>

typedef struct candidate {
  size_t k, from, to; /* the corner and its window (inclusive, along the traversal) */
  double angle, gap; /* the turn, and the distance from the side lines' meeting point */
  double position;    /* fractional index of the corner along the samples */
  double point[3];    /* where the side lines meet */
} candidate;

static double median_spacing(const contour *c, double *scratch) {
  size_t i, n = c->closed ? c->m : c->m - 1;
  for (i = 0; i < n; i++) scratch[i] = dist(c, i, i + 1);
  return bsfit__select(scratch, n, n / 2);
}

static double bbox_diagonal(const contour *c) {
  double lo[3] = {0, 0, 0}, hi[3] = {0, 0, 0}, s = 0;
  size_t i;
  int d;
  for (d = 0; d < c->dim; d++) lo[d] = hi[d] = c->pts[d];
  for (i = 0; i < c->m; i++)
    for (d = 0; d < c->dim; d++) {
      double v = point(c, i)[d];
      if (v < lo[d]) lo[d] = v;
      if (v > hi[d]) hi[d] = v;
    }
  for (d = 0; d < c->dim; d++) s += (hi[d] - lo[d]) * (hi[d] - lo[d]);
  return sqrt(s);
}

/* The unit axis of a spike, pointing to its tip (left's direction less right's); 0 when
** the sides are parallel and there is none. */
static int spike_axis(const side *left, const side *right, double axis[3]) {
  double na = 0;
  int d;
  for (d = 0; d < 3; d++) {
    axis[d] = left->dir[d] - right->dir[d];
    na += axis[d] * axis[d];
  }
  na = sqrt(na);
  if (!(na > 0)) return 0;
  for (d = 0; d < 3; d++) axis[d] /= na;
  return 1;
}

/* A spike's side lines cross at a shallow angle, so where they meet is poorly known
** along its axis (and curved sides push it outwards): the corner point is kept no
** further out along the axis than the furthest sample of the window, unless the side lines
** put it beyond by more than three standard errors (each line's offset at the tip, twice
** the noise and the side's misfit, over the sine of the half angle of the spike): then it
** lies beyond, where they meet (a triangle of 6 exact samples per side had its tip cut
** back to a sample and placed at it, and the smooth fit through that corner missed the
** samples by 0.4% of the size). Returns 1 when the tip lies there, beyond the samples. */
static int place_spike_corner(const contour *c, size_t k, const side *left, const side *right,
                        double sigma, double *x) {
  double axis[3], top = -INFINITY, half_sin = 0, se;
  long off;
  int d;
  if (!spike_axis(left, right, axis)) return 0;
  for (d = 0; d < 3; d++) {
    double u = left->dir[d] + right->dir[d];
    half_sin += u * u;
  }
  half_sin = 0.5 * sqrt(half_sin);
  for (off = -(long)left->count; off <= (long)right->count; off++) {
    const double *P;
    double pr = 0;
    if (!c->closed && ((long)k + off < 0 || (long)k + off >= (long)c->m)) continue;
    P = point(c, at(c, k, off));
    for (d = 0; d < c->dim; d++) pr += (P[d] - x[d]) * axis[d];
    if (pr > top) top = pr;
  }
  se = 2.0 * (sigma + fmax(left->rms, right->rms)) / fmax(half_sin, 1e-300);
  if (top < 0 && -top > 3.0 * se) return 1;
  /* x lies beyond every sample, by less than the lines tell: back along the axis */
  if (top < 0)
    for (d = 0; d < c->dim; d++) x[d] += top * axis[d];
  return 0;
}

/* A spike (a turn beyond 120 degrees): its tip is the sample furthest along the spike's
** axis. Where the samples there are closer than the noise, all those within 2 sigma of the
** furthest are the tip, and the corner is their mean position (the tip of a thin trailing
** edge cut at random would make the curve cross over). Offsets lo..hi around k. */
static double spike_tip(const contour *c, size_t k, const side *left, const side *right,
                        const double *x, double sigma, long lo, long hi) {
  double axis[3], top = -INFINITY, sum = 0, cnt = 0, proj[256], pos;
  long off;
  int d;
  if (!spike_axis(left, right, axis)) return (double)k; /* no axis: the sample itself */
  for (off = lo; off <= hi; off++) {
    const double *P = point(c, at(c, k, off));
    double pr = 0;
    for (d = 0; d < c->dim; d++) pr += (P[d] - x[d]) * axis[d];
    proj[off - lo] = pr;
    if (pr > top) top = pr;
  }
  for (off = lo; off <= hi; off++)
    if (proj[off - lo] >= top - 2.0 * sigma - 1e-12 * fabs(top)) sum += (double)off, cnt += 1.0;
  pos = (double)k + sum / cnt;
  if (pos < 0) pos += (double)c->m;
  if (pos >= (double)c->m) pos -= (double)c->m;
  if (!c->closed) pos = fmin(fmax(pos, 0.0), (double)(c->m - 1));
  return pos;
}

/* squared distance of P to a side's line */
static double side_dist2(const contour *c, const side *sd, const double *P) {
  double along = 0, n2 = 0;
  int d;
  for (d = 0; d < c->dim; d++) along += (P[d] - sd->centre[d]) * sd->dir[d];
  for (d = 0; d < c->dim; d++) {
    double r = P[d] - sd->centre[d] - along * sd->dir[d];
    n2 += r * r;
  }
  return n2;
}

/* The best split between the sides: cost(split after sample k + off) = the sum over the
** samples up to it of dL^2 - dR^2 (plus a constant). Samples nearer to the corner than
** the noise resolves fit either line: of the splits within 4 sigma^2 of the best, the
** middle one (a thin spike's samples near its tip would otherwise be cut at random, and
** the curve made to cross over). Returns the offset of the last sample before it. */
static long best_split(const contour *c, size_t k, const side *left, const side *right,
                       double sigma, long lo, long hi) {
  double acc = 0, best = INFINITY, cost[256];
  long off, best_off = -1, n, first = 0, last = 0;
  for (off = lo; off <= hi; off++) {
    const double *P = point(c, at(c, k, off));
    acc += side_dist2(c, left, P) - side_dist2(c, right, P);
    cost[off - lo] = acc;
    if (acc < best) best = acc, best_off = off;
  }
  for (n = 0, off = lo; off <= hi; off++)
    if (cost[off - lo] <= best + 4.0 * sigma * sigma) {
      if (n++ == 0) first = off;
      last = off;
    }
  return n > 0 ? first + (last - first) / 2 : best_off;
}

/* Where along the samples the corner lies: the split of the samples around k (half of
** each side) between the two side lines that leaves the least squared distance to
** them (samples up to the split on the left line, the others on the right one), then
** the fraction of the path across the split edge before the corner point x. Robust
** where samples are closer than the noise (a thin trailing edge): the corner is not
** simply the sample nearest to x. */
static double split_position(const contour *c, size_t k, const side *left, const side *right,
                             const double *x, double sigma, double turn, int beyond) {
  long lo = -(long)(left->count / 2), hi = (long)(right->count / 2);
  size_t j;
  const double *a, *b;
  double da = 0, db = 0, f, pos;
  int d;
  if (!c->closed) {
    if ((long)k + lo < 0) lo = -(long)k;
    if ((long)k + hi + 1 >= (long)c->m) hi = (long)c->m - 2 - (long)k;
  }
  if (hi <= lo) return (double)k;
  if (-lo > 127) lo = -127;
  if (hi > 127) hi = 127;
  if (turn > 2.0 * PI / 3.0 && !beyond) return spike_tip(c, k, left, right, x, sigma, lo, hi);
  j = at(c, k, best_split(c, k, left, right, sigma, lo, hi));
  a = point(c, j);
  b = point(c, j + 1);
  for (d = 0; d < c->dim; d++) {
    da += (x[d] - a[d]) * (x[d] - a[d]);
    db += (x[d] - b[d]) * (x[d] - b[d]);
  }
  da = sqrt(da);
  db = sqrt(db);
  f = da + db > 0 ? da / (da + db) : 0.0;
  /* a corner at (or within rounding of) a sample is that sample */
  pos = f > 1.0 - 1e-9 ? (double)j + 1.0 : (double)j + (f < 1e-9 ? 0.0 : f);
  if (pos >= (double)c->m) pos -= (double)c->m;
  return pos;
}

/* How far the corner point x lies outside the gap it was placed in (position: after
** sample j, before j + 1): past j + 1 along the right side's direction, or short of j
** along the left side's (0 when inside). Forced through such a point, the curve runs on
** past the sample and turns back to it: a hook (an exact 5-lobed star of 80 samples, its
** noise read from the lobes' curvature, had two of 157 degrees). */
static double outside_gap(const contour *c, double position, const side *left,
                          const side *right, const double *x) {
  size_t j = (size_t)floor(position) % c->m;
  const double *a = point(c, j), *b = point(c, (j + 1) % c->m);
  double past = 0, short_of = 0;
  int d;
  if (!c->closed && j + 1 >= c->m) return 0.0;
  for (d = 0; d < c->dim; d++) {
    past += (x[d] - b[d]) * right->dir[d];
    short_of += (a[d] - x[d]) * left->dir[d];
  }
  return fmax(0.0, fmax(past, short_of));
}

/* The turn at k if it is a corner, else a negative value; its window (from, to), the
** distance from Q_k to the corner (for thinning), where the corner lies along the
** samples and the corner point. The tests, cheapest first:
**   - the sides turn: by min_angle at least and by six standard errors;
**   - both sides are straight to the noise (plus 2% of the scale for clean data);
**   - the outer halves' lines meet near the data: a rounded fillet's tangents do not
**     (the allowance: three standard errors of where they meet, as the lines are known
**     from noisy samples, and how far curved sides bend away from their lines);
**   - the polygon turns at the corner's samples, not beyond them;
**   - the turn is a slope jump: with the sides grown as long as they stay straight, a
**     smooth join (join_models) explains them worse by 25 sigma^2 at least;
**   - a corner turns as much at half the scale; a bend turns less, in proportion. */
static double corner_turn(const contour *c, size_t k, double scale, double sigma,
                          double min_angle, double cap, size_t *from, size_t *to,
                          double *gap_out, double *position, double *meet_point) {
  side left, right, half_left, half_right, gl, gr;
  double angle, half, se, x[3] = {0, 0, 0}, gap = 0, lim, r0, r1;
  size_t half_from, half_to, n;
  int d, beyond;
  *position = (double)k;
  angle = bsfit__corner_turn_at_scale(c, k, scale, &left, &right, from, to);
  if (angle < 0) return -1.0;
  /* standard error of a line direction fitted to n points spread over `extent` */
  se = sigma * sqrt(12.0 / (double)left.count) / left.extent +
       sigma * sqrt(12.0 / (double)right.count) / right.extent;
  if (angle < min_angle || angle < 6.0 * se) return -1.0;
  if (left.rms > 2.5 * sigma + 0.02 * scale || right.rms > 2.5 * sigma + 0.02 * scale) return -1.0;
  if (!bsfit__corner_meet(&left, &right, c->dim, x)) return -1.0;
  /* the corner itself: where the curved sides meet (x stays where the outer lines
  ** meet, for the fillet test) */
  memcpy(meet_point, x, sizeof x);
  bsfit__corner_refine_meet(c, &left, &right, meet_point);
  beyond = angle > 2.0 * PI / 3.0 && place_spike_corner(c, k, &left, &right, sigma, meet_point);
  for (d = 0; d < c->dim; d++)
    gap += (meet_point[d] - point(c, k)[d]) * (meet_point[d] - point(c, k)[d]);
  *gap_out = sqrt(gap);
  *position = split_position(c, k, &left, &right, meet_point, sigma, angle, beyond);
  lim = 3.0 * sqrt(2.0 * sigma * sigma + bsfit__corner_meet_variance(&left, &right, x, sigma)) +
        bsfit__corner_bend_allowance(c, &left, &right, x, angle) + 0.005 * scale;
  if (bsfit__corner_edge_distance(c, k, x, angle) > lim) return -1.0;
  /* a spike's tip lies beyond its samples; any other corner lies between two, to the noise */
  if (!beyond && angle <= 2.0 * PI / 3.0 &&
      outside_gap(c, *position, &left, &right, meet_point) > 3.0 * sigma + 1e-9 * scale)
    return -1.0;
  if (!bsfit__corner_turn_concentrated(c, *position, &left, &right, sigma)) return -1.0;
  gl = left;
  gr = right;
  bsfit__corner_grow_side(c, k, 0, scale, sigma, cap, &gl);
  bsfit__corner_grow_side(c, k, 1, scale, sigma, cap, &gr);
  n = bsfit__corner_join_models(c, &gl, &gr, meet_point, &r0, &r1);
  if (n == 0 && gl.count >= 4 && gr.count >= 4) return -1.0; /* no smooth model fits: no evidence */
  if (n > 0) {
    /* the noise, or the corner model's own misfit when larger (clean data) */
    double s2 = fmax(fmax(sigma * sigma, r0 / (double)(n > 8 ? n - 6 : 2)), 1e-6 * scale * scale);
    /* 25 sigma^2, and more over many points: the smooth model's own shortfall on a
    ** smooth bend adds up point by point (a 5-lobed star's valley of radius 12 sigma,
    ** seen through 400 points, falls short by 30 sigma^2) */
    if (r1 - r0 < (25.0 + 0.03 * (double)n) * s2) return -1.0;
  }
  half = bsfit__corner_turn_at_scale(c, k, 0.5 * scale, &half_left, &half_right, &half_from,
                                     &half_to);
  if (half >= 0 && half < 0.75 * angle) return -1.0;
  return angle;
}

/* Is k strictly inside w's window (from, to), walking forward, possibly across the
** end? The far ends are excluded: a corner may stand at the end of its neighbour's
** side (a notch as deep as the scale), since both sides passed the straightness test. */
static int in_window(const candidate *w, size_t k, size_t m) {
  size_t len = (w->to + m - w->from) % m, off = (k + m - w->from) % m;
  return off > 0 && off < len;
}

/* Keeps the candidates nearest to where their side lines meet (the neighbours of a
** corner pass the tests too, with a larger gap); a kept corner suppresses the
** candidates in its window. */
static size_t thin_candidates(candidate *cand, size_t nc, size_t m) {
  size_t i, j, kept = 0;
  /* insertion sort by increasing gap: the candidates are few */
  for (i = 1; i < nc; i++) {
    candidate t = cand[i];
    for (j = i; j > 0 && cand[j - 1].gap > t.gap; j--) cand[j] = cand[j - 1];
    cand[j] = t;
  }
  for (i = 0; i < nc; i++) {
    int free_ = 1;
    for (j = 0; j < kept && free_; j++)
      if (in_window(&cand[j], cand[i].k, m) || in_window(&cand[i], cand[j].k, m)) free_ = 0;
    if (free_) cand[kept++] = cand[i];
  }
  /* back to contour order */
  for (i = 1; i < kept; i++) {
    candidate t = cand[i];
    for (j = i; j > 0 && cand[j - 1].k > t.k; j--) cand[j] = cand[j - 1];
    cand[j] = t;
  }
  return kept;
}

/* How far the sides of the current point reach, in index steps back and forth; moved
** along with the point (two pointers), so the scan is O(m) whatever the window. */
typedef struct window {
  size_t back, fwd;
} window;


/* Moves the window to point k: each side ends at the first point (going outwards) that
** is `scale` away, found from the previous ends. 0 when a side is cut by an open end. */
static int move_window(const contour *c, size_t k, double scale, window *w) {
  size_t limit = c->closed ? c->m / 2 : c->m;
  if (w->fwd == 0) w->fwd = w->back = 1; /* first point */
  else { w->back++; if (w->fwd > 1) w->fwd--; }
  while (w->fwd > 1 && dist(c, k, at(c, k, (long)w->fwd - 1)) >= scale) w->fwd--;
  while (w->fwd < limit && dist(c, k, at(c, k, (long)w->fwd)) < scale) w->fwd++;
  if (w->back > limit) w->back = limit;
  while (w->back > 1 && dist(c, k, at(c, k, -((long)w->back - 1))) >= scale) w->back--;
  while (w->back < limit && dist(c, k, at(c, k, -(long)w->back)) < scale) w->back++;
  if (!c->closed && (k < w->back || k + w->fwd >= c->m)) return 0;
  return 1;
}

/* A cheap first test from the two-pointer window and prefix sums, O(1) per point:
** both sides long enough, turning enough and straight enough. The exact test
** (corner_turn) runs only where this passes. */
static double quick_candidate(const contour *c, size_t k, double scale, double sigma,
                              double min_angle, window *w) {
  moments ml, mr;
  side left, right;
  double hint_l[3] = {0, 0, 0}, hint_r[3] = {0, 0, 0}, cosang = 0, angle;
  size_t first_l, first_r;
  int d;
  if (!move_window(c, k, scale, w) || w->back < 3 || w->fwd < 3) return -1.0;
  first_l = at(c, k, -(long)w->back);
  first_r = at(c, k, 1);
  ml = bsfit__corner_run_moments(c, first_l, at(c, k, -1));
  mr = bsfit__corner_run_moments(c, first_r, at(c, k, (long)w->fwd));
  for (d = 0; d < c->dim; d++) {
    hint_l[d] = point(c, k)[d] - point(c, first_l)[d];
    hint_r[d] = point(c, at(c, k, (long)w->fwd))[d] - point(c, k)[d];
  }
  bsfit__corner_fit_line(c, &ml, hint_l, &left);
  bsfit__corner_fit_line(c, &mr, hint_r, &right);
  for (d = 0; d < 3; d++) cosang += left.dir[d] * right.dir[d];
  angle = acos(fmax(-1.0, fmin(1.0, cosang)));
  /* generous: the exact test decides; this only skips the plainly smooth points */
  if (angle < 0.8 * min_angle) return -1.0;
  if (left.rms > 4.0 * sigma + 0.04 * scale || right.rms > 4.0 * sigma + 0.04 * scale) return -1.0;
  return angle;
}

/* Is the quick turn at k the largest within r samples either way (ties to the first)?
** A corner's neighbours see the same corner off-centre, with a smaller turn: only the
** peak and the samples next to it are worth the exact test. */
static int turn_peak(const contour *c, const double *turn, size_t k, size_t r) {
  long off;
  for (off = -(long)r; off <= (long)r; off++) {
    size_t j;
    if (off == 0) continue;
    if (!c->closed && ((long)k + off < 0 || (long)k + off >= (long)c->m)) continue;
    j = at(c, k, off);
    if (turn[j] > turn[k] || (turn[j] == turn[k] && off < 0)) return 0;
  }
  return 1;
}

/* Checks the options and the points, and finds sigma when the caller did not give it. */
static bsfit_err check_input(const double *pts, size_t m, int dim, const bsfit_corner_opts *o,
                             double *sigma, bsfit_status *st) {
  if (o->scale < 0 || !isfinite(o->scale) || !isfinite(o->sigma) || o->min_angle_deg < 0 ||
      o->min_angle_deg >= 180 || !isfinite(o->min_angle_deg))
    return bsfit__fail(st, BSFIT_EINVAL,
                       "corner options: scale %g, sigma %g, min_angle_deg %g out of range",
                       o->scale, o->sigma, o->min_angle_deg);
  *sigma = o->sigma;
  if (*sigma <= 0) return bsfit_noise_sigma(pts, m, dim, o->closed, sigma, NULL, st);
  if (dim != 2 && dim != 3)
    return bsfit__fail(st, BSFIT_EDIM, "corner detection needs 2D or 3D points, got dim %d", dim);
  if (pts == NULL || m < 6)
    return bsfit__fail(st, BSFIT_ETOOFEW, "corner detection needs at least 6 points, got %zu", m);
  if (!bsfit__all_finite(pts, m * (size_t)dim))
    return bsfit__fail(st, BSFIT_ENONFINITE, "points contain NaN or Inf");
  return BSFIT_OK;
}

/* The detector's settings and scratch (through the caller's allocator). */
typedef struct detector {
  double sigma, scale, min_angle, reach_cap;
  double *turn;         /* the quick turn of every sample (-1: cannot be a corner) */
  size_t *span;         /* how far a peak of it rules: its shorter side */
  size_t *queue, nq;    /* the samples to examine */
  unsigned char *state; /* 1 once queued as a peak's, 2 as found by another's examination */
  candidate *cand;
  size_t nc;
} detector;

static int detector_alloc(detector *d, size_t m, const bsfit_allocator *al) {
  memset(d, 0, sizeof *d);
  d->cand = bsfit__alloc(al, m * sizeof(candidate));
  d->turn = bsfit__alloc(al, m * sizeof(double));
  d->span = bsfit__alloc(al, m * sizeof(size_t));
  d->queue = bsfit__alloc(al, m * sizeof(size_t));
  d->state = bsfit__alloc(al, m);
  if (d->state) memset(d->state, 0, m);
  return d->cand && d->turn && d->span && d->queue && d->state;
}

static void detector_free(detector *d, size_t m, const bsfit_allocator *al) {
  bsfit__free(al, d->cand, m * sizeof(candidate));
  bsfit__free(al, d->turn, m * sizeof(double));
  bsfit__free(al, d->span, m * sizeof(size_t));
  bsfit__free(al, d->queue, m * sizeof(size_t));
  bsfit__free(al, d->state, m);
}

/* queues the samples around `centre` not queued yet, marking them `mark` */
static void queue_around(const contour *c, detector *d, long centre, unsigned char mark) {
  long off;
  for (off = -1; off <= 1; off++) {
    size_t j;
    if (!c->closed && (centre + off < 0 || centre + off >= (long)c->m)) continue;
    j = at(c, (size_t)(centre < 0 ? 0 : centre) % c->m, off);
    if (!d->state[j]) d->state[j] = mark, d->queue[d->nq++] = j;
  }
}

/* The quick turn of every sample and the peaks of it, queued with their neighbours. */
static bsfit_err queue_peaks(const contour *c, detector *d, const bsfit_allocator *al) {
  window reach = {0, 0};
  size_t k;
  for (k = 0; k < c->m; k++) {
    if ((k & 4095) == 4095 && bsfit__interrupted(al)) return BSFIT_EINTR;
    d->turn[k] = quick_candidate(c, k, d->scale, d->sigma, d->min_angle, &reach);
    d->span[k] = reach.back < reach.fwd ? reach.back : reach.fwd;
  }
  for (k = 0; k < c->m; k++)
    if (d->turn[k] >= 0 && turn_peak(c, d->turn, k, d->span[k] / 4 > 1 ? d->span[k] / 4 : 1))
      queue_around(c, d, (long)k, 1);
  return BSFIT_OK;
}

/* The queued samples examined, each at most once; where one finds the corner elsewhere (a
** peak leans towards a curved side, whose turn adds to the corner's), the samples around
** that place are examined too, and must then find the corner at themselves. */
static bsfit_err examine_queue(const contour *c, detector *d, const bsfit_allocator *al) {
  while (d->nq > 0) {
    size_t from, to, kk = d->queue[--d->nq];
    double gap = 0, pos = (double)kk, x[3] = {0, 0, 0}, a, moved;
    int second = d->state[kk] == 2;
    if ((d->nq & 255) == 0 && bsfit__interrupted(al)) return BSFIT_EINTR;
    a = corner_turn(c, kk, d->scale, d->sigma, d->min_angle, d->reach_cap, &from, &to, &gap, &pos,
                    x);
    moved = fabs(pos - (double)kk);
    if (c->closed) moved = fmin(moved, (double)c->m - moved);
    if (second && moved >= 1.5) a = -1.0;
    if (moved >= 1.5 && !second) queue_around(c, d, (long)floor(pos + 0.5), 2);
    if (a >= 0) {
      candidate *cd = &d->cand[d->nc++];
      cd->k = kk, cd->from = from, cd->to = to;
      cd->angle = a, cd->gap = gap, cd->position = pos;
      memcpy(cd->point, x, sizeof x);
    }
  }
  return BSFIT_OK;
}

bsfit_err bsfit_corners_detect(const double *pts, size_t m, int dim,
                               const bsfit_corner_opts *opts, bsfit_corner *corners,
                               size_t cap, size_t *count, const bsfit_allocator *al,
                               bsfit_status *st) {
  contour c;
  detector d;
  size_t k, kept, bytes_prefix = (m + 1) * 10 * sizeof(double);
  bsfit_corner_opts o;
  bsfit_err e;
  memset(&o, 0, sizeof o);
  if (opts) o = *opts;
  *count = 0;
  if ((e = check_input(pts, m, dim, &o, &d.sigma, st)) != BSFIT_OK) return e;
  memset(&c, 0, sizeof c);
  c.pts = pts, c.m = m, c.dim = dim, c.closed = o.closed != 0;
  memcpy(c.origin, pts, (size_t)dim * sizeof(double));
  c.prefix = bsfit__alloc(al, bytes_prefix);
  {
    double sigma = d.sigma;
    if (!detector_alloc(&d, m, al) || c.prefix == NULL) {
      e = bsfit__fail(st, BSFIT_ENOMEM, "out of memory for corner detection of %zu points", m);
      goto done;
    }
    d.sigma = sigma;
  }
  bsfit__corner_build_prefix(&c);
  d.reach_cap = 0.4 * bbox_diagonal(&c);
  d.scale = o.scale > 0 ? o.scale
                        : fmin(fmax(40.0 * d.sigma, 4.0 * median_spacing(&c, d.turn)),
                               0.25 * d.reach_cap);
  d.min_angle = (o.min_angle_deg > 0 ? o.min_angle_deg : 30.0) * PI / 180.0;
  if ((e = queue_peaks(&c, &d, al)) != BSFIT_OK || (e = examine_queue(&c, &d, al)) != BSFIT_OK) {
    e = bsfit__fail(st, e, "corner detection interrupted");
    goto done;
  }
  kept = thin_candidates(d.cand, d.nc, m);
  for (k = 0; k < kept && k < cap; k++) {
    /* the sample nearest to where the corner lies */
    size_t near = (size_t)floor(d.cand[k].position + 0.5);
    corners[k].index = near >= m ? near - m : near;
    corners[k].angle = d.cand[k].angle * 180.0 / PI;
    corners[k].position = d.cand[k].position;
    memcpy(corners[k].point, d.cand[k].point, sizeof d.cand[k].point);
  }
  *count = kept;
  e = bsfit__ok(st);
done:
  bsfit__free(al, c.prefix, bytes_prefix);
  detector_free(&d, m, al);
  return e;
}
