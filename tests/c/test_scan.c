/*
** test_scan.c
** The scan core: PLY binary of every property type and both byte orders decoded exactly,
** random mutations of valid files (never a crash; a success is a valid mesh), sphere
** sections along random directions against the exact circles, allocation failures
** (BSFIT_ENOMEM, nothing leaked) and the host's interrupt flag (BSFIT_EINTR) for every
** function.
*/

#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <math.h>
#include <cmocka.h>

#include "bsfit.h"
#include "testutil.h"

#define PI 3.14159265358979323846

/* {====================================================================
** Hand-built files
** ===================================================================== */

typedef struct bytes {
  unsigned char b[4096];
  size_t n;
} bytes;

static void put(bytes *o, const void *p, size_t n, int big) {
  size_t k;
  int host_big = *(const unsigned char *)&(const uint16_t){1} == 0;
  for (k = 0; k < n; k++)
    o->b[o->n + k] = ((const unsigned char *)p)[(big != host_big) ? n - 1 - k : k];
  o->n += n;
}

static void puts_(bytes *o, const char *s) {
  memcpy(o->b + o->n, s, strlen(s));
  o->n += strlen(s);
}

/* Vertices (i, -i, i/4) stored as x: short, y: char, z: double, plus skipped properties of
** every other type; faces as uchar-counted ushort lists: a triangle and a quad. */
static void binary_ply(bytes *o, int big) {
  int i;
  o->n = 0;
  puts_(o, big ? "ply\nformat binary_big_endian 1.0\n" : "ply\nformat binary_little_endian 1.0\n");
  puts_(o,
        "comment every type\nelement vertex 5\nproperty uchar a\nproperty short x\n"
        "property char y\nproperty ushort b\nproperty int c\nproperty uint d\nproperty float e\n"
        "property double z\nelement face 2\nproperty list uchar ushort vertex_indices\n"
        "end_header\n");
  for (i = 0; i < 5; i++) {
    unsigned char a = 200;
    int16_t x = (int16_t)(1000 * i);
    int8_t y = (int8_t)(-i);
    uint16_t b = 60000;
    int32_t c = -7;
    uint32_t d = 4000000000u;
    float e = 0.5f;
    double z = i / 4.0;
    put(o, &a, 1, big), put(o, &x, 2, big), put(o, &y, 1, big), put(o, &b, 2, big);
    put(o, &c, 4, big), put(o, &d, 4, big), put(o, &e, 4, big), put(o, &z, 8, big);
  }
  {
    unsigned char three = 3, four = 4;
    uint16_t t[3] = {0, 1, 2}, q[4] = {1, 2, 3, 4};
    put(o, &three, 1, big);
    for (i = 0; i < 3; i++) put(o, &t[i], 2, big);
    put(o, &four, 1, big);
    for (i = 0; i < 4; i++) put(o, &q[i], 2, big);
  }
}

static void test_ply_every_type(void **state) {
  int big, i;
  (void)state;
  for (big = 0; big < 2; big++) {
    bytes o;
    bsfit_scan s;
    bsfit_status st;
    binary_ply(&o, big);
    bsfit_scan_init(&s);
    assert_int_equal(
        bsfit_scan_parse((const char *)o.b, o.n, BSFIT_SCAN_PLY, "t.ply", &s, NULL, &st), BSFIT_OK);
    assert_int_equal(s.nv, 5);
    assert_int_equal(s.nt, 3); /* the quad is a fan of two */
    for (i = 0; i < 5; i++) {
      assert_true(s.xyz[3 * i] == 1000.0 * i && s.xyz[3 * i + 1] == -i &&
                  s.xyz[3 * i + 2] == i / 4.0);
    }
    assert_true(s.tri[3] == 1 && s.tri[4] == 2 && s.tri[5] == 3);
    assert_true(s.tri[6] == 1 && s.tri[7] == 3 && s.tri[8] == 4);
    bsfit_scan_free(&s);
    bsfit_scan_free(&s); /* idempotent */
  }
}

/* Numbers of every textual form read as strtod reads them, bit for bit (the ASCII readers
** have a fast path for short decimals). */
static void test_ascii_numbers(void **state) {
  static const char *fixed[] = {"-0",
                                "0",
                                "1.",
                                ".5",
                                "+3",
                                "00012.50",
                                "1e5",
                                "1E-7",
                                "-2.5e+3",
                                "123456789012345",
                                "1234567890123456",
                                "0.1",
                                "0.3",
                                "1e22",
                                "1e23",
                                "9007199254740993",
                                "4.9e-324",
                                "1.7976931348623157e308",
                                "0.000000000000000000000000000123",
                                "2.2250738585072014e-308"};
  static const char *fmts[] = {"%.17g", "%.6f", "%g", "%.3e", "%.15g", "%.0f", "%.9g"};
  test_rng r = {77};
  char text[200000];
  size_t len = 0, nv = 0, i;
  bsfit_scan s;
  bsfit_status st;
  (void)state;
  for (i = 0; i < sizeof fixed / sizeof fixed[0]; i++)
    len += (size_t)snprintf(text + len, sizeof text - len, "v %s 0 0\n", fixed[i]), nv++;
  for (i = 0; i < 3000; i++) {
    double v = (rng_uniform(&r) - 0.5) * pow(10, rng_range(&r, -30, 30));
    char num[64];
    snprintf(num, sizeof num, fmts[i % 7], v);
    len += (size_t)snprintf(text + len, sizeof text - len, "v %s 1 2\n", num), nv++;
  }
  bsfit_scan_init(&s);
  assert_int_equal(bsfit_scan_parse(text, len, BSFIT_SCAN_OBJ, "n.obj", &s, NULL, &st), BSFIT_OK);
  assert_int_equal(s.nv, nv);
  {
    const char *p = text;
    for (i = 0; i < nv; i++) {
      char *end;
      double want = strtod(p + 2, &end);
      assert_memory_equal(&s.xyz[3 * i], &want, sizeof want);
      p = strchr(p, '\n') + 1;
    }
  }
  bsfit_scan_free(&s);
}

/* }==================================================================== */

/* {====================================================================
** Mutations: never a crash, a success is a valid mesh
** ===================================================================== */

static const char *ascii_ply =
    "ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\nproperty float "
    "z\n"
    "element face 2\nproperty list uchar int vertex_indices\nend_header\n"
    "0 0 0\n1 0 0\n1 1 0\n0 1 1\n3 0 1 2\n3 0 2 3\n";
static const char *ascii_stl =
    "solid t\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\nvertex 1 1 0\nendloop\n"
    "endfacet\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 1 0\nvertex 0 1 1\nendloop\n"
    "endfacet\nendsolid t\n";
static const char *obj = "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 1\nvt 0 0\nf 1/1 2/1 3/1\nf -4 -2 -1\n";

static void binary_stl(bytes *o) {
  float v[2][9] = {{0, 0, 0, 1, 0, 0, 1, 1, 0}, {0, 0, 0, 1, 1, 0, 0, 1, 1}};
  uint32_t n = 2;
  uint16_t attr = 0;
  float nrm[3] = {0, 0, 1};
  int t;
  o->n = 0;
  memset(o->b, 'x', 80);
  o->n = 80;
  put(o, &n, 4, 0);
  for (t = 0; t < 2; t++) {
    put(o, nrm, 12, 0);
    put(o, v[t], 36, 0);
    put(o, &attr, 2, 0);
  }
}

static void check_valid(const bsfit_scan *s) {
  size_t i;
  assert_true(s->nv >= 1);
  for (i = 0; i < 3 * s->nv; i++) assert_true(isfinite(s->xyz[i]));
  for (i = 0; i < 3 * s->nt; i++) assert_true(s->tri[i] < s->nv);
}

static void mutate_and_parse(const unsigned char *src, size_t n, bsfit_scan_format fmt,
                             test_rng *r) {
  unsigned char buf[2048];
  int round;
  for (round = 0; round < 3000; round++) {
    size_t len = n, k, edits = 1 + (size_t)(rng_uniform(r) * 4);
    bsfit_scan s;
    bsfit_status st;
    bsfit_err e;
    memcpy(buf, src, n);
    for (k = 0; k < edits; k++) {
      double c = rng_uniform(r);
      size_t at = (size_t)(rng_uniform(r) * (double)len);
      if (c < 0.5 && len > 0)
        buf[at % len] = (unsigned char)(rng_uniform(r) * 256);
      else if (c < 0.7)
        len = at;
      else if (c < 0.85 && len > 0)
        buf[at % len] = (unsigned char)"0123456789-. \n/e"[(int)(rng_uniform(r) * 16)];
      else if (len > 1) {
        memmove(buf + at % len, buf + at % len + 1, len - at % len - 1);
        len--;
      }
    }
    bsfit_scan_init(&s);
    e = bsfit_scan_parse((const char *)buf, len, fmt, "m", &s, NULL, &st);
    if (e == BSFIT_OK)
      check_valid(&s);
    else
      assert_true(e == BSFIT_EFORMAT || e == BSFIT_ENONFINITE || e == BSFIT_ETOOFEW ||
                  e == BSFIT_EINVAL);
    bsfit_scan_free(&s);
  }
}

static void test_mutations(void **state) {
  test_rng r = {0x9E3779B97F4A7C15ull};
  bytes o;
  (void)state;
  mutate_and_parse((const unsigned char *)ascii_ply, strlen(ascii_ply), BSFIT_SCAN_PLY, &r);
  mutate_and_parse((const unsigned char *)ascii_stl, strlen(ascii_stl), BSFIT_SCAN_STL, &r);
  mutate_and_parse((const unsigned char *)obj, strlen(obj), BSFIT_SCAN_OBJ, &r);
  binary_ply(&o, 0);
  mutate_and_parse(o.b, o.n, BSFIT_SCAN_PLY, &r);
  binary_ply(&o, 1);
  mutate_and_parse(o.b, o.n, BSFIT_SCAN_PLY, &r);
  binary_stl(&o);
  mutate_and_parse(o.b, o.n, BSFIT_SCAN_STL, &r);
}

/* }==================================================================== */

/* {====================================================================
** Sphere sections along random directions
** ===================================================================== */

/* A UV sphere of radius R centred at c: nlat rings, nlon around, outward triangles. */
static void sphere(bsfit_scan *s, double R, const double c[3], size_t nlat, size_t nlon) {
  size_t i, j, v = 0, t = 0;
  s->nv = (nlat - 1) * nlon + 2;
  s->nt = 2 * nlon * (nlat - 1);
  s->xyz = malloc(s->nv * 3 * sizeof(double));
  s->tri = malloc(s->nt * 3 * sizeof(uint32_t));
  for (i = 1; i < nlat; i++)
    for (j = 0; j < nlon; j++, v++) {
      double th = PI * (double)i / (double)nlat, ph = 2 * PI * (double)j / (double)nlon;
      s->xyz[3 * v] = c[0] + R * sin(th) * cos(ph);
      s->xyz[3 * v + 1] = c[1] + R * sin(th) * sin(ph);
      s->xyz[3 * v + 2] = c[2] + R * cos(th);
    }
  s->xyz[3 * v] = c[0], s->xyz[3 * v + 1] = c[1], s->xyz[3 * v + 2] = c[2] + R; /* north: v */
  s->xyz[3 * v + 3] = c[0], s->xyz[3 * v + 4] = c[1], s->xyz[3 * v + 5] = c[2] - R;
#define ID(i, j) ((uint32_t)(((i)-1) * nlon + ((j) % nlon)))
  for (j = 0; j < nlon; j++) {
    uint32_t *T = s->tri + 3 * t++;
    T[0] = (uint32_t)v, T[1] = ID(1, j), T[2] = ID(1, j + 1);
    T = s->tri + 3 * t++;
    T[0] = (uint32_t)v + 1, T[1] = ID(nlat - 1, j + 1), T[2] = ID(nlat - 1, j);
  }
  for (i = 1; i + 1 < nlat; i++)
    for (j = 0; j < nlon; j++) {
      uint32_t *T = s->tri + 3 * t++;
      T[0] = ID(i, j), T[1] = ID(i + 1, j), T[2] = ID(i + 1, j + 1);
      T = s->tri + 3 * t++;
      T[0] = ID(i, j), T[1] = ID(i + 1, j + 1), T[2] = ID(i, j + 1);
    }
#undef ID
}

static void test_sphere_sections(void **state) {
  test_rng r = {12345};
  int trial;
  (void)state;
  for (trial = 0; trial < 40; trial++) {
    double c[3] = {rng_range(&r, -5, 5), rng_range(&r, -5, 5), rng_range(&r, -5, 5)};
    double R = rng_range(&r, 0.5, 3), dir[3], n[3], len, pos[5];
    size_t nlat = 12 + (size_t)(rng_uniform(&r) * 40), nlon = 12 + (size_t)(rng_uniform(&r) * 60);
    /* the mesh lies within the sphere, at most the sagitta of its coarsest chord inside */
    double tess = R * (1 - cos(PI / (double)(nlat < nlon / 2 ? nlat : nlon / 2))) * 2 + 1e-12;
    bsfit_scan s;
    bsfit_sections out;
    bsfit_status st;
    size_t k, q;
    int a;
    sphere(&s, R, c, nlat, nlon);
    for (a = 0; a < 3; a++) dir[a] = rng_range(&r, -1, 1);
    len = sqrt(dir[0] * dir[0] + dir[1] * dir[1] + dir[2] * dir[2]);
    for (a = 0; a < 3; a++) n[a] = dir[a] / len;
    for (k = 0; k < 5; k++)
      pos[k] = n[0] * c[0] + n[1] * c[1] + n[2] * c[2] + R * rng_range(&r, -0.8, 0.8);
    bsfit_sections_init(&out);
    assert_int_equal(bsfit_mesh_slice(&s, dir, pos, 5, 0, &out, NULL, &st), BSFIT_OK);
    assert_int_equal(out.nslices, 5);
    for (k = 0; k < 5; k++) {
      const bsfit_plane *p = &out.planes[k];
      double d = pos[k] - (n[0] * c[0] + n[1] * c[1] + n[2] * c[2]), rho = sqrt(R * R - d * d);
      /* the circle's centre in the plane's (u, v) frame */
      double cu = (c[0] - p->origin[0]) * p->u[0] + (c[1] - p->origin[1]) * p->u[1] +
                  (c[2] - p->origin[2]) * p->u[2];
      double cv = (c[0] - p->origin[0]) * p->v[0] + (c[1] - p->origin[1]) * p->v[1] +
                  (c[2] - p->origin[2]) * p->v[2];
      double area = 0;
      size_t j = out.first_part[k], m;
      assert_int_equal(out.first_part[k + 1] - j, 1);
      assert_true(out.closed[j]);
      m = out.part_start[j + 1] - out.part_start[j];
      for (q = 0; q < m; q++) {
        const double *P = out.uv + 2 * (out.part_start[j] + q),
                     *Q = out.uv + 2 * (out.part_start[j] + (q + 1) % m);
        double rr = hypot(P[0] - cu, P[1] - cv);
        assert_true(rr <= rho + 1e-9 && rr >= rho - tess - 1e-9);
        area += P[0] * Q[1] - Q[0] * P[1];
      }
      assert_true(area > 0); /* counter-clockwise seen from +n */
      /* the frame: orthonormal, u x v = n */
      assert_true(fabs(p->u[1] * p->v[2] - p->u[2] * p->v[1] - n[0]) < 1e-12);
      assert_true(fabs(p->u[0] * p->u[0] + p->u[1] * p->u[1] + p->u[2] * p->u[2] - 1) < 1e-12);
    }
    bsfit_sections_free(&out);
    free(s.xyz);
    free(s.tri);
  }
}

/* }==================================================================== */

/* {====================================================================
** Allocation failures and interruption
** ===================================================================== */

/* Calls f with an allocator failing the 1st, 2nd, ... allocation: ENOMEM and nothing
** leaked until it succeeds (then cleanup is called and nothing is left either). */
#define ENOMEM_LOOP(call, cleanup)                     \
  do {                                                 \
    long n_;                                           \
    for (n_ = 1; n_ < 500; n_++) {                     \
      counting c_ = {0, n_, 0};                        \
      bsfit_allocator a = {counting_alloc, &c_, NULL}; \
      bsfit_err e_ = (call);                           \
      if (e_ == BSFIT_OK) {                            \
        cleanup;                                       \
        assert_int_equal(c_.live, 0);                  \
        break;                                         \
      }                                                \
      assert_int_equal(e_, BSFIT_ENOMEM);              \
      assert_int_equal(c_.live, 0);                    \
    }                                                  \
    assert_true(n_ > 1 && n_ < 500);                   \
  } while (0)

static void test_allocation_failures(void **state) {
  bytes o;
  bsfit_scan s, sp;
  bsfit_sections sec;
  bsfit_order_result ord;
  double c[3] = {0, 0, 0}, z[3] = {0, 0, 1}, pos[3] = {-0.5, 0, 0.5}, xy[2 * 200], rxy[400],
         rw[200], cell;
  size_t i, rm;
  (void)state;
  binary_ply(&o, 1);
  bsfit_scan_init(&s);
  ENOMEM_LOOP(bsfit_scan_parse((const char *)o.b, o.n, BSFIT_SCAN_PLY, "t", &s, &a, NULL),
              bsfit_scan_free(&s));
  ENOMEM_LOOP(bsfit_scan_parse(ascii_stl, strlen(ascii_stl), BSFIT_SCAN_STL, "t", &s, &a, NULL),
              bsfit_scan_free(&s));
  ENOMEM_LOOP(bsfit_scan_parse(obj, strlen(obj), BSFIT_SCAN_OBJ, "t", &s, &a, NULL),
              bsfit_scan_free(&s));
  bsfit_scan_init(&sp);
  sphere(&sp, 1, c, 10, 16);
  bsfit_sections_init(&sec);
  ENOMEM_LOOP(bsfit_mesh_slice(&sp, z, pos, 3, 0, &sec, &a, NULL), bsfit_sections_free(&sec));
  ENOMEM_LOOP(bsfit_cloud_slice(sp.xyz, sp.nv, z, pos, 3, 0.2, &sec, &a, NULL),
              bsfit_sections_free(&sec));
  for (i = 0; i < 200; i++) {
    xy[2 * i] = cos(2 * PI * (double)i / 200) * (1 + 0.3 * (i % 2));
    xy[2 * i + 1] = sin(2 * PI * (double)i / 200);
  }
  ENOMEM_LOOP(bsfit_reduce_grid(xy, 200, NULL, 0.1, rxy, rw, &rm, &a, NULL), (void)0);
  ENOMEM_LOOP(bsfit_reduce_target(xy, 200, NULL, 50, &cell, rxy, rw, &rm, &a, NULL), (void)0);
  bsfit_order_result_init(&ord);
  ENOMEM_LOOP(bsfit_order(xy, 200, NULL, &ord, &a, NULL), bsfit_order_result_free(&ord));
  free(sp.xyz);
  free(sp.tri);
}

static void test_interrupt(void **state) {
  volatile int stop = 1;
  bsfit_allocator a = {NULL, NULL, &stop};
  bytes o;
  bsfit_scan s, sp;
  bsfit_sections sec;
  bsfit_order_result ord;
  double c[3] = {0, 0, 0}, z[3] = {0, 0, 1}, pos[1] = {0}, xy[40], rxy[40], rw[20];
  size_t i, rm;
  (void)state;
  binary_ply(&o, 0);
  bsfit_scan_init(&s);
  assert_int_equal(bsfit_scan_parse((const char *)o.b, o.n, BSFIT_SCAN_PLY, "t", &s, &a, NULL),
                   BSFIT_EINTR);
  bsfit_scan_init(&sp);
  sphere(&sp, 1, c, 10, 16);
  bsfit_sections_init(&sec);
  assert_int_equal(bsfit_mesh_slice(&sp, z, pos, 1, 0, &sec, &a, NULL), BSFIT_EINTR);
  assert_int_equal(bsfit_cloud_slice(sp.xyz, sp.nv, z, pos, 1, 0.1, &sec, &a, NULL), BSFIT_EINTR);
  for (i = 0; i < 20; i++) xy[2 * i] = cos((double)i), xy[2 * i + 1] = sin((double)i);
  assert_int_equal(bsfit_reduce_grid(xy, 20, NULL, 0.1, rxy, rw, &rm, &a, NULL), BSFIT_EINTR);
  bsfit_order_result_init(&ord);
  assert_int_equal(bsfit_order(xy, 20, NULL, &ord, &a, NULL), BSFIT_EINTR);
  free(sp.xyz);
  free(sp.tri);
}

/* }==================================================================== */

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_ply_every_type),      cmocka_unit_test(test_ascii_numbers),
      cmocka_unit_test(test_mutations),           cmocka_unit_test(test_sphere_sections),
      cmocka_unit_test(test_allocation_failures), cmocka_unit_test(test_interrupt),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
