/*
** test_exchange.c
** The exchange writers at the text level (tests/sh/test_exchange.sh reads the files with
** OpenCASCADE and ezdxf): the STEP and DXF curves (clamped by knot insertion) rebuilt
** from the text are the same curves on the same parameter range, OBJ meshes close around a
** periodic direction with every edge shared by two triangles, SOURCE_DATE_EPOCH gives
** the same bytes, and bad input, out of memory and misuse give their codes.
*/
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <cmocka.h>

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "bsfit.h"
#include "testutil.h"

/* {====================================================================
** Random curves and surfaces
** ===================================================================== */

/* kind 0: open clamped, 1: open unclamped, 2: periodic; rational when rat */
static void random_curve(test_rng *r, int kind, int rat, int dim, bsfit_curve *c) {
  int p = 1 + (int)(rng_uniform(r) * 5);
  size_t n = (size_t)p + 2 + (size_t)(rng_uniform(r) * 8), i;
  double U[64], P[64 * 3], w[64], t[64];
  for (i = 0; i < n * (size_t)dim; i++) P[i] = rng_range(r, -100, 100);
  for (i = 0; i < n; i++) w[i] = rng_range(r, 0.3, 3);
  bsfit_curve_init(c);
  if (kind == 2) {
    t[0] = rng_range(r, -3, 3);
    for (i = 1; i <= n; i++) t[i] = t[i - 1] + rng_range(r, 0.2, 2);
    assert_int_equal(bsfit_curve_new_periodic(c, p, dim, n, t, P, rat ? w : NULL, NULL, NULL),
                     BSFIT_OK);
    return;
  }
  random_knots(r, p, n, kind == 0, U);
  assert_int_equal(bsfit_curve_new(c, p, dim, n, U, P, rat ? w : NULL, 0, NULL, NULL), BSFIT_OK);
}

static double dist(const double *x, const double *y, int dim) {
  double s = 0;
  int t;
  for (t = 0; t < dim; t++) s += (x[t] - y[t]) * (x[t] - y[t]);
  return sqrt(s);
}

/* }==================================================================== */

/* {====================================================================
** STEP
** ===================================================================== */

/* The first curve of a STEP text, rebuilt from its CARTESIAN_POINTs (in order), its
** knots (distinct values expanded by their multiplicities) and its weights. */
static void parse_step_curve(const char *text, bsfit_curve *c) {
  double P[256 * 3], U[256], w[256];
  long mult[128];
  size_t np = 0, nm = 0, nk = 0, nw = 0, i;
  long deg;
  const char *s = text, *k;
  char *end;
  while ((k = strstr(s, "CARTESIAN_POINT('',(")) != NULL) {
    int t;
    s = k + strlen("CARTESIAN_POINT('',(");
    for (t = 0; t < 3; t++, s = end + 1) P[np * 3 + (size_t)t] = strtod(s, &end);
    np++;
  }
  k = strstr(text, "B_SPLINE_CURVE_WITH_KNOTS('curve 0',");
  if (k != NULL) k += strlen("B_SPLINE_CURVE_WITH_KNOTS('curve 0',");
  else k = strstr(text, "B_SPLINE_CURVE(") + strlen("B_SPLINE_CURVE(");
  deg = strtol(k, &end, 10);
  /* the multiplicities follow the flags ".UNSPECIFIED.,.T.|.F.,.F.," or, rational,
  ** "B_SPLINE_CURVE_WITH_KNOTS(" */
  k = strstr(text, "B_SPLINE_CURVE_WITH_KNOTS((");
  k = k ? k + strlen("B_SPLINE_CURVE_WITH_KNOTS((") : strstr(end, ".F.,(") + 5;
  for (; *k != ')'; k = *end == ',' ? end + 1 : end) mult[nm++] = strtol(k, &end, 10);
  for (k += 3, i = 0; i < nm; i++, k = end + 1) {
    double x = strtod(k, &end);
    long m;
    for (m = 0; m < mult[i]; m++) U[nk++] = x;
  }
  k = strstr(text, "RATIONAL_B_SPLINE_CURVE((");
  if (k != NULL)
    for (k += strlen("RATIONAL_B_SPLINE_CURVE(("); *k != ')' && *(k - 1) != ')'; k = end + 1)
      w[nw++] = strtod(k, &end);
  assert_int_equal(nk, np + (size_t)deg + 1);
  bsfit_curve_init(c);
  assert_int_equal(bsfit_curve_new(c, (int)deg, 3, np, U, P, nw ? w : NULL, 0, NULL, NULL),
                   BSFIT_OK);
  assert_int_equal(nw, k ? np : 0);
}

/* c and d: the same domain exactly, the same points at 100 parameters within 1e-12 of
** the size (d, read from a file, is clamped and 3D). */
static void same_curve(const bsfit_curve *c, const bsfit_curve *d) {
  double a, b, da, db, size = 0;
  int i, j;
  bsfit_curve_domain(c, &a, &b);
  bsfit_curve_domain(d, &da, &db);
  assert_true(da == a && db == b);
  for (j = 0; j <= d->degree; j++) { /* clamped */
    assert_true(d->knots[j] == a);
    assert_true(d->knots[d->n + (size_t)j] == b);
  }
  for (i = 0; i < (int)c->n * c->dim; i++) size = fmax(size, fabs(c->ctrl[i]));
  for (i = 0; i < 100; i++) {
    double u = a + (b - a) * i / 99.0, x[3] = {0, 0, 0}, y[3];
    bsfit_curve_eval(c, u, x, NULL);
    bsfit_curve_eval(d, u, y, NULL);
    assert_true(dist(x, y, 3) <= 1e-12 * size);
  }
}

static void test_step_exact(void **state) {
  test_rng r = {2024};
  int trial;
  (void)state;
  for (trial = 0; trial < 60; trial++) {
    bsfit_curve c, d;
    const bsfit_curve *one[1] = {&c};
    char *text;
    size_t len;
    random_curve(&r, trial % 3, (trial / 3) % 2, 2 + trial % 2, &c);
    assert_int_equal(bsfit_curves_to_step(one, 1, "t.step", &text, &len, NULL, NULL), BSFIT_OK);
    assert_int_equal(strlen(text), len);
    assert_non_null(strstr(text, "ISO-10303-21;"));
    assert_non_null(strstr(text, "END-ISO-10303-21;"));
    assert_non_null(
        strstr(text, c.weights ? "RATIONAL_B_SPLINE_CURVE(" : "B_SPLINE_CURVE_WITH_KNOTS('"));
    assert_non_null(strstr(text, c.periodic ? ".T.,.F." : ".F.,.F.")); /* closed_curve */
    parse_step_curve(text, &d);
    same_curve(&c, &d);
    bsfit_curve_free(&d);
    free(text);
    bsfit_curve_free(&c);
  }
}

static void test_step_errors_and_epoch(void **state) {
  test_rng r = {5};
  bsfit_curve c, line;
  const bsfit_curve *one[2] = {&c, NULL};
  double P[3] = {1, 2, 3};
  char *t1, *t2;
  size_t l1, l2;
  bsfit_status st;
  (void)state;
  random_curve(&r, 0, 0, 3, &c);
  assert_int_equal(bsfit_curves_to_step(one, 0, NULL, &t1, &l1, NULL, &st), BSFIT_EINVAL);
  assert_int_equal(bsfit_curves_to_step(NULL, 1, NULL, &t1, &l1, NULL, &st), BSFIT_EINVAL);
  assert_int_equal(bsfit_curves_to_step(one, 2, NULL, &t1, &l1, NULL, &st), BSFIT_EINVAL);
  assert_non_null(strstr(st.msg, "curve 1 is NULL"));
  assert_int_equal(bsfit_curves_to_step(one, 1, NULL, NULL, &l1, NULL, &st), BSFIT_EINVAL);
  bsfit_curve_init(&line);
  assert_int_equal(bsfit_curve_new(&line, 0, 3, 1, NULL, P, NULL, 0, NULL, NULL), BSFIT_OK);
  one[0] = &line;
  assert_int_equal(bsfit_curves_to_step(one, 1, NULL, &t1, &l1, NULL, &st), BSFIT_EDEGREE);
  assert_int_equal(bsfit_curves_to_dxf(one, 1, &t1, &l1, NULL, &st), BSFIT_EDEGREE);
  bsfit_curve_free(&line);
  assert_int_equal(bsfit_curve_new(&line, 0, 1, 3, NULL, P, NULL, 0, NULL, NULL), BSFIT_OK);
  assert_int_equal(bsfit_curves_to_step(one, 1, NULL, &t1, &l1, NULL, &st), BSFIT_EDIM);
  assert_int_equal(bsfit_curves_to_dxf(one, 1, &t1, &l1, NULL, &st), BSFIT_EDIM);
  bsfit_curve_free(&line);
  /* SOURCE_DATE_EPOCH: the same bytes, the epoch's time */
  one[0] = &c;
  setenv("SOURCE_DATE_EPOCH", "86400", 1);
  assert_int_equal(bsfit_curves_to_step(one, 1, "dir/x.step", &t1, &l1, NULL, NULL), BSFIT_OK);
  assert_int_equal(bsfit_curves_to_step(one, 1, "dir/x.step", &t2, &l2, NULL, NULL), BSFIT_OK);
  assert_int_equal(l1, l2);
  assert_memory_equal(t1, t2, l1);
  assert_non_null(strstr(t1, "FILE_NAME('x.step','1970-01-02T00:00:00'"));
  unsetenv("SOURCE_DATE_EPOCH");
  free(t1);
  free(t2);
  bsfit_curve_free(&c);
}

/* }==================================================================== */

/* {====================================================================
** DXF: the clamped splines are the same curves
** ===================================================================== */

/* Reads the next SPLINE's group codes from *s into c (clamped, as written). */
static void parse_spline(const char **s, bsfit_curve *c) {
  double U[256], P[256 * 3], w[256];
  long deg = 0, nk = 0, np = 0, flags = 0;
  size_t ik = 0, iw = 0, ip = 0;
  const char *q = strstr(*s, "\nSPLINE\n");
  assert_non_null(q);
  q += 8;
  for (;;) {
    char *end;
    long code = strtol(q, &end, 10);
    const char *val = end + 1, *eol = strchr(val, '\n');
    if (code == 0) break;
    if (code == 70) flags = strtol(val, NULL, 10);
    if (code == 71) deg = strtol(val, NULL, 10);
    if (code == 72) nk = strtol(val, NULL, 10);
    if (code == 73) np = strtol(val, NULL, 10);
    if (code == 40) U[ik++] = strtod(val, NULL);
    if (code == 41) w[iw++] = strtod(val, NULL);
    if (code == 10 || code == 20 || code == 30) P[ip++] = strtod(val, NULL);
    q = eol + 1;
  }
  *s = q;
  assert_int_equal(ik, nk);
  assert_int_equal(ip, 3 * np);
  assert_int_equal(iw, (flags & 4) ? np : 0);
  bsfit_curve_init(c);
  assert_int_equal(bsfit_curve_new(c, (int)deg, 3, (size_t)np, U, P, iw ? w : NULL, 0, NULL, NULL),
                   BSFIT_OK);
}

static void test_dxf_same_curves(void **state) {
  test_rng r = {31337};
  bsfit_curve c[30];
  const bsfit_curve *ptr[30];
  char *text;
  const char *s;
  size_t len, k;
  (void)state;
  for (k = 0; k < 30; k++) {
    random_curve(&r, (int)k % 3, (int)(k / 3) % 2, 2 + (int)k % 2, &c[k]);
    ptr[k] = &c[k];
  }
  {
    bsfit_status st0;
    bsfit_err e0 = bsfit_curves_to_dxf(ptr, 30, &text, &len, NULL, &st0);
    if (e0 != BSFIT_OK) fail_msg("%s", st0.msg);
  }
  assert_non_null(strstr(text, "AC1015"));
  s = text;
  for (k = 0; k < 30; k++) {
    bsfit_curve d;
    parse_spline(&s, &d);
    same_curve(&c[k], &d);
    bsfit_curve_free(&d);
  }
  free(text);
  for (k = 0; k < 30; k++) bsfit_curve_free(&c[k]);
}

/* }==================================================================== */

/* {====================================================================
** OBJ
** ===================================================================== */

/* Every edge (i < j) of the triangles counted; returns how many are used once. */
static size_t boundary_edges(const size_t *f, size_t nf, size_t nvert) {
  size_t *cnt = calloc(nvert * nvert, sizeof *cnt), i, once = 0;
  assert_non_null(cnt);
  for (i = 0; i < nf; i++) {
    int e;
    for (e = 0; e < 3; e++) {
      size_t x = f[i * 3 + e] - 1, y = f[i * 3 + (e + 1) % 3] - 1;
      size_t lo = x < y ? x : y, hi = x < y ? y : x;
      cnt[lo * nvert + hi]++;
    }
  }
  for (i = 0; i < nvert * nvert; i++) {
    assert_true(cnt[i] <= 2);
    once += cnt[i] == 1;
  }
  free(cnt);
  return once;
}

static void check_obj(const bsfit_surface *S, size_t nu, size_t nv) {
  char *text;
  const char *s;
  size_t len, nvert = 0, nf = 0, cols = S->periodic_u ? nu : nu - 1;
  double (*V)[3] = malloc(nu * nv * sizeof *V), ua, ub, va, vb;
  size_t *F = malloc(2 * nu * nv * 3 * sizeof *F), i, j;
  assert_int_equal(bsfit_surface_to_obj(S, nu, nv, &text, &len, NULL, NULL), BSFIT_OK);
  for (s = text; *s; s = strchr(s, '\n') + 1) {
    if (s[0] == 'v') {
      assert_int_equal(sscanf(s, "v %lf %lf %lf", &V[nvert][0], &V[nvert][1], &V[nvert][2]), 3);
      nvert++;
    } else if (s[0] == 'f') {
      assert_int_equal(sscanf(s, "f %zu %zu %zu", &F[nf * 3], &F[nf * 3 + 1], &F[nf * 3 + 2]), 3);
      for (i = 0; i < 3; i++) assert_true(F[nf * 3 + i] >= 1 && F[nf * 3 + i] <= nu * nv);
      nf++;
    }
  }
  assert_int_equal(nvert, nu * nv);
  assert_int_equal(nf, 2 * cols * (nv - 1));
  bsfit_surface_domain(S, &ua, &ub, &va, &vb);
  for (i = 0; i < nu; i++)
    for (j = 0; j < nv; j++) {
      double x[3] = {0, 0, 0};
      double u = ua + (ub - ua) * (double)i / (double)(S->periodic_u ? nu : nu - 1);
      bsfit_surface_eval(S, u, va + (vb - va) * (double)j / (double)(nv - 1), x, NULL);
      assert_true(dist(x, V[i * nv + j], 3) <= 1e-12 * (1 + fabs(x[0]) + fabs(x[1]) + fabs(x[2])));
    }
  /* closed around u: only the two v ends are boundary; open: the whole rim */
  assert_int_equal(boundary_edges(F, nf, nvert),
                   S->periodic_u ? 2 * nu : 2 * (nu - 1) + 2 * (nv - 1));
  free(text);
  free(V);
  free(F);
}

static void test_obj_mesh(void **state) {
  test_rng r = {8};
  bsfit_curve C[3];
  const bsfit_curve *ptr[3] = {&C[0], &C[1], &C[2]};
  double P[6 * 3], t[7], U[16], net[5 * 4 * 3];
  bsfit_surface S, O;
  size_t k, i;
  (void)state;
  for (k = 0; k < 3; k++) {
    for (i = 0; i < 6; i++) {
      P[i * 3] = (3 + (double)k) * cos(i * 1.0472) + rng_range(&r, -0.2, 0.2);
      P[i * 3 + 1] = (3 + (double)k) * sin(i * 1.0472);
      P[i * 3 + 2] = 2.0 * (double)k;
    }
    for (i = 0; i <= 6; i++) t[i] = (double)i;
    bsfit_curve_init(&C[k]);
    assert_int_equal(bsfit_curve_new_periodic(&C[k], 3, 3, 6, t, P, NULL, NULL, NULL), BSFIT_OK);
  }
  bsfit_surface_init(&S);
  assert_int_equal(bsfit_surface_skin(ptr, 3, NULL, &S, NULL, NULL, NULL), BSFIT_OK);
  check_obj(&S, 24, 7);
  check_obj(&S, 3, 2);
  for (i = 0; i < 5 * 4 * 3; i++) net[i] = rng_range(&r, -5, 5);
  random_knots(&r, 2, 5, 1, U);
  bsfit_surface_init(&O);
  assert_int_equal(bsfit_surface_new(&O, 2, 1, 3, 5, 4, U, NULL, net, NULL, NULL, NULL), BSFIT_OK);
  check_obj(&O, 10, 9);
  {
    char *text;
    size_t len;
    assert_int_equal(bsfit_surface_to_obj(&O, 1, 9, &text, &len, NULL, NULL), BSFIT_EINVAL);
    assert_int_equal(bsfit_surface_to_obj(&O, 5, 5, NULL, &len, NULL, NULL), BSFIT_EINVAL);
  }
  bsfit_surface_free(&S);
  bsfit_surface_free(&O);
  for (k = 0; k < 3; k++) bsfit_curve_free(&C[k]);
}

/* }==================================================================== */

/* {====================================================================
** Out of memory: every writer returns ENOMEM and leaks nothing
** ===================================================================== */

static void test_enomem(void **state) {
  test_rng r = {44};
  bsfit_curve c[3];
  const bsfit_curve *ptr[3] = {&c[0], &c[1], &c[2]};
  bsfit_surface S;
  int which;
  (void)state;
  random_curve(&r, 0, 1, 3, &c[0]);
  random_curve(&r, 1, 0, 2, &c[1]);
  random_curve(&r, 2, 1, 3, &c[2]);
  bsfit_surface_init(&S);
  {
    double net[4 * 3 * 3];
    size_t i;
    for (i = 0; i < 36; i++) net[i] = rng_range(&r, -1, 1);
    assert_int_equal(bsfit_surface_new(&S, 2, 1, 3, 4, 3, NULL, NULL, net, NULL, NULL, NULL),
                     BSFIT_OK);
  }
  for (which = 0; which < 4; which++) {
    long n;
    for (n = 1;; n++) {
      counting cnt = {0, n, 0};
      bsfit_allocator a = {counting_alloc, &cnt, NULL};
      char *text = NULL;
      size_t len = 0;
      bsfit_err e;
      if (which == 0) e = bsfit_curves_to_step(ptr, 3, NULL, &text, &len, &a, NULL);
      else if (which == 1) e = bsfit_curves_to_dxf(ptr, 3, &text, &len, &a, NULL);
      else if (which == 2) e = bsfit_surface_to_step(&S, NULL, &text, &len, &a, NULL);
      else e = bsfit_surface_to_obj(&S, 8, 8, &text, &len, &a, NULL);
      if (e == BSFIT_OK) {
        counting_alloc(&cnt, text, len + 1, 0);
        assert_int_equal(cnt.live, 0);
        break;
      }
      assert_int_equal(e, BSFIT_ENOMEM);
      assert_int_equal(cnt.live, 0);
    }
  }
  bsfit_surface_free(&S);
  for (which = 0; which < 3; which++) bsfit_curve_free(&c[which]);
}

/* }==================================================================== */

int main(void) {
  const struct CMUnitTest tests[] = {
    cmocka_unit_test(test_step_exact),
    cmocka_unit_test(test_step_errors_and_epoch),
    cmocka_unit_test(test_dxf_same_curves),
    cmocka_unit_test(test_obj_mesh),
    cmocka_unit_test(test_enomem),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
