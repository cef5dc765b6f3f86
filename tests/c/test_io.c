/*
** test_io.c
** File formats: point files (parse, read, write, every malformed case), atomic writing,
** curve and surface JSON (bit-exact round trips, strict reader errors), SVG structure
** and coordinate mapping, and IGES files parsed back column by column.
*/

#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <math.h>
#include <dirent.h>
#include <sys/stat.h>
#include <unistd.h>
#include <cmocka.h>

#include "bsfit.h"
#include "testutil.h"

#define DATA BSFIT_TEST_DATA "/io/"

/* {====================================================================
** Helpers
** ===================================================================== */


static char tmpdir[512];

static int setup(void **state) {
  (void)state;
  snprintf(tmpdir, sizeof tmpdir, "%s/test_io_tmp.%ld", BSFIT_BINARY_DIR, (long)getpid());
  return mkdir(tmpdir, 0777) == 0 ? 0 : -1;
}

static int teardown(void **state) {
  DIR *d = opendir(tmpdir);
  struct dirent *e;
  char p[1024];
  (void)state;
  while (d && (e = readdir(d)) != NULL) {
    if (e->d_name[0] == '.') continue;
    snprintf(p, sizeof p, "%s/%s", tmpdir, e->d_name);
    if (remove(p) != 0) rmdir(p);
  }
  if (d) closedir(d);
  rmdir(tmpdir);
  return 0;
}

static const char *tmp(const char *name) {
  static char p[1024];
  snprintf(p, sizeof p, "%s/%s", tmpdir, name);
  return p;
}

/* Number of entries in tmpdir whose name contains `part`. */
static int count_files(const char *part) {
  DIR *d = opendir(tmpdir);
  struct dirent *e;
  int n = 0;
  while (d && (e = readdir(d)) != NULL)
    if (strstr(e->d_name, part)) n++;
  if (d) closedir(d);
  return n;
}

static char *slurp(const char *path, size_t *len) {
  FILE *f = fopen(path, "rb");
  char *s;
  long n;
  assert_non_null(f);
  fseek(f, 0, SEEK_END);
  n = ftell(f);
  fseek(f, 0, SEEK_SET);
  s = malloc((size_t)n + 1);
  assert_non_null(s);
  assert_int_equal(fread(s, 1, (size_t)n, f), (size_t)n);
  s[n] = '\0';
  fclose(f);
  if (len) *len = (size_t)n;
  return s;
}

static bsfit_err parse_str(const char *text, double **xy, size_t *m, int *dim, double **w,
                           bsfit_status *st) {
  return bsfit_points_parse(text, strlen(text), xy, m, dim, w, NULL, st);
}

/* A 2D cubic NURBS, a 3D quadratic B-spline, a periodic cubic, a rational Bézier. */
static void make_curves(bsfit_curve c[4]) {
  static const double U[] = {0, 0, 0, 0, 0.1, 1.0 / 3, 0.7, 1, 1, 1, 1};
  double ctrl[7 * 3], w[7];
  unsigned i;
  for (i = 0; i < 21; i++) ctrl[i] = sin(1.7 * i) * (i % 3 ? 1e-7 : 3e5) + 1.0 / 3;
  for (i = 0; i < 7; i++) w[i] = 0.5 + i / 7.0;
  for (i = 0; i < 4; i++) bsfit_curve_init(&c[i]);
  assert_int_equal(bsfit_curve_new(&c[0], 3, 2, 7, U, ctrl, w, 0, NULL, NULL), BSFIT_OK);
  assert_int_equal(bsfit_curve_new(&c[1], 2, 3, 5, NULL, ctrl, NULL, 0, NULL, NULL), BSFIT_OK);
  assert_int_equal(bsfit_curve_new_periodic(&c[2], 3, 2, 6, NULL, ctrl, NULL, NULL, NULL), BSFIT_OK);
  assert_int_equal(bsfit_curve_new_bezier(&c[3], 2, 4, ctrl, w, NULL, NULL), BSFIT_OK);
}

static void free_curves(bsfit_curve c[4]) {
  int i;
  for (i = 0; i < 4; i++) bsfit_curve_free(&c[i]);
}

static void assert_same_curve(const bsfit_curve *a, const bsfit_curve *b) {
  assert_int_equal(a->degree, b->degree);
  assert_int_equal(a->dim, b->dim);
  assert_int_equal(a->n, b->n);
  assert_int_equal(a->periodic, b->periodic);
  assert_int_equal(a->bezier, b->bezier);
  assert_memory_equal(a->knots, b->knots, (a->n + (size_t)a->degree + 1) * sizeof(double));
  assert_memory_equal(a->ctrl, b->ctrl, a->n * (size_t)a->dim * sizeof(double));
  assert_int_equal(a->weights == NULL, b->weights == NULL);
  if (a->weights) assert_memory_equal(a->weights, b->weights, a->n * sizeof(double));
}

/* }==================================================================== */

/* {====================================================================
** Points
** ===================================================================== */

static void test_points_header_any_order(void **state) {
  double *xy, *w;
  size_t m;
  int dim;
  bsfit_status st;
  (void)state;
  /* given: a file with comments, a blank line and a "W; Y ; X" header */
  assert_int_equal(bsfit_points_read(DATA "points_header.csv", &xy, &m, &dim, &w, NULL, &st),
                   BSFIT_OK);
  /* then: the columns land where the header says */
  assert_int_equal(m, 2);
  assert_int_equal(dim, 2);
  assert_non_null(w);
  assert_true(xy[0] == 10 && xy[1] == 2 && w[0] == 1.5);
  assert_true(xy[2] == 11 && xy[3] == -35 && w[1] == 0.25);
  bsfit_points_free(xy, m, dim, w, NULL);
}

static void test_points_whitespace_no_header(void **state) {
  double *xy, *w;
  size_t m;
  int dim;
  (void)state;
  assert_int_equal(bsfit_points_read(DATA "points_ws.txt", &xy, &m, &dim, &w, NULL, NULL), BSFIT_OK);
  assert_int_equal(m, 3);
  assert_int_equal(dim, 3);
  assert_null(w);
  assert_true(xy[3] == 1 && xy[4] == 2 && xy[5] == 3 && xy[8] == 6);
  bsfit_points_free(xy, m, dim, w, NULL);
  /* 2 columns x,y; 4 columns x,y,z,w; commas; header case-insensitive with quotes */
  assert_int_equal(parse_str("1,2\n3,4\n", &xy, &m, &dim, &w, NULL), BSFIT_OK);
  assert_true(m == 2 && dim == 2 && w == NULL && xy[3] == 4);
  bsfit_points_free(xy, m, dim, w, NULL);
  assert_int_equal(parse_str("1 2 3 0.5\n", &xy, &m, &dim, &w, NULL), BSFIT_OK);
  assert_true(m == 1 && dim == 3 && w != NULL && w[0] == 0.5 && xy[2] == 3);
  bsfit_points_free(xy, m, dim, w, NULL);
  assert_int_equal(parse_str("\"Z\",\"x\",y\n3,1,2", &xy, &m, &dim, NULL, NULL), BSFIT_OK);
  assert_true(m == 1 && dim == 3 && xy[0] == 1 && xy[1] == 2 && xy[2] == 3);
  bsfit_points_free(xy, m, dim, NULL, NULL);
}

static void expect_points_error(const char *text, bsfit_err code, const char *in_msg) {
  double *xy = (double *)1, *w = (double *)1;
  size_t m = 9;
  int dim = 9;
  bsfit_status st;
  assert_int_equal(parse_str(text, &xy, &m, &dim, &w, &st), code);
  assert_int_equal(st.code, code);
  assert_null(xy);
  assert_null(w);
  assert_int_equal(m, 0);
  if (in_msg && !strstr(st.msg, in_msg)) fail_msg("message '%s' lacks '%s'", st.msg, in_msg);
}

static void test_points_malformed_strings(void **state) {
  (void)state;
  expect_points_error("x,y,q\n1,2,3\n", BSFIT_EFORMAT, "line 1: unknown column name 'q'");
  expect_points_error("x,x\n1,2\n", BSFIT_EFORMAT, "repeated");
  expect_points_error("x,z\n1,2\n", BSFIT_EFORMAT, "x and y");
  expect_points_error("x,y\n1,2\n3,abc\n", BSFIT_EFORMAT, "line 3: not a number: 'abc'");
  expect_points_error("1,2\n3,\n", BSFIT_EFORMAT, "line 2");
  expect_points_error("1,2\n3,4e\n", BSFIT_EFORMAT, "'4e'");
  expect_points_error("x,y\n1,2\nnan,4\n", BSFIT_ENONFINITE, "line 3");
  expect_points_error("1 2\n1e999 4\n", BSFIT_ENONFINITE, "line 2");
  expect_points_error("1,2\n3,4,5\n", BSFIT_EFORMAT, "line 2: expected 2 columns, got 3");
  expect_points_error("1,2,3\n4,5\n", BSFIT_EFORMAT, "expected 3 columns, got 2");
  expect_points_error("", BSFIT_ETOOFEW, "no data");
  expect_points_error("# nothing\n\n  \n", BSFIT_ETOOFEW, NULL);
  expect_points_error("x,y,w\n", BSFIT_ETOOFEW, NULL);
  expect_points_error("x,y,w\n1,2,1\n3,4,0\n", BSFIT_EWEIGHT, "line 3");
  expect_points_error("1 2 3 -1\n", BSFIT_EWEIGHT, "line 1");
  expect_points_error("5\n", BSFIT_EFORMAT, "1 column");
  expect_points_error("1 2 3 4 5\n", BSFIT_EFORMAT, "more than 4");
  expect_points_error("x,y,z,w,x\n", BSFIT_EFORMAT, "more than 4");
  {
    double *xy;
    size_t m;
    int dim;
    bsfit_status st;
    assert_int_equal(bsfit_points_parse(NULL, 3, &xy, &m, &dim, NULL, NULL, &st), BSFIT_EINVAL);
    assert_int_equal(bsfit_points_parse("1 2", 3, NULL, &m, &dim, NULL, NULL, &st), BSFIT_EINVAL);
  }
}

static void expect_file_error(const char *name, bsfit_err code, const char *in_msg) {
  double *xy = NULL, *w = NULL;
  size_t m;
  int dim;
  bsfit_status st;
  char path[512];
  snprintf(path, sizeof path, DATA "%s", name);
  assert_int_equal(bsfit_points_read(path, &xy, &m, &dim, &w, NULL, &st), code);
  assert_null(xy);
  assert_null(w);
  if (!strstr(st.msg, name)) fail_msg("message '%s' lacks the file name", st.msg);
  if (in_msg && !strstr(st.msg, in_msg)) fail_msg("message '%s' lacks '%s'", st.msg, in_msg);
}

static void test_points_malformed_files(void **state) {
  (void)state;
  expect_file_error("missing.csv", BSFIT_EIO, "No such file");
  expect_file_error("bad_unknown_column.csv", BSFIT_EFORMAT, "bad_unknown_column.csv:1:");
  expect_file_error("bad_text.csv", BSFIT_EFORMAT, "bad_text.csv:3:");
  expect_file_error("bad_nan.csv", BSFIT_ENONFINITE, ":3:");
  expect_file_error("bad_ragged.csv", BSFIT_EFORMAT, ":2:");
  expect_file_error("empty.csv", BSFIT_ETOOFEW, NULL);
  expect_file_error("bad_zero_weight.csv", BSFIT_EWEIGHT, ":3:");
}

static void test_points_write_read_roundtrip(void **state) {
  double xy[3 * 50], w[50], *rxy, *rw;
  size_t i, m;
  int dim;
  (void)state;
  for (i = 0; i < 150; i++) xy[i] = tan(0.37 * (double)i) * pow(10.0, (double)(i % 40) - 20);
  for (i = 0; i < 50; i++) w[i] = 1.0 / (1.0 + (double)i);
  /* 3D with weights, then 2D without: bit-exact through %.17g */
  assert_int_equal(bsfit_points_write(tmp("p3.csv"), xy, 50, 3, w, NULL), BSFIT_OK);
  assert_int_equal(bsfit_points_read(tmp("p3.csv"), &rxy, &m, &dim, &rw, NULL, NULL), BSFIT_OK);
  assert_true(m == 50 && dim == 3 && rw != NULL);
  assert_memory_equal(rxy, xy, sizeof xy);
  assert_memory_equal(rw, w, sizeof w);
  bsfit_points_free(rxy, m, dim, rw, NULL);
  assert_int_equal(bsfit_points_write(tmp("p2.csv"), xy, 75, 2, NULL, NULL), BSFIT_OK);
  assert_int_equal(bsfit_points_read(tmp("p2.csv"), &rxy, &m, &dim, &rw, NULL, NULL), BSFIT_OK);
  assert_true(m == 75 && dim == 2 && rw == NULL);
  assert_memory_equal(rxy, xy, 150 * sizeof(double));
  bsfit_points_free(rxy, m, dim, rw, NULL);
  /* writer errors */
  {
    bsfit_status st;
    double bad[4] = {1, 2, NAN, 4}, zero[2] = {1, 0};
    assert_int_equal(bsfit_points_write(tmp("x.csv"), xy, 10, 4, NULL, &st), BSFIT_EDIM);
    assert_int_equal(bsfit_points_write(tmp("x.csv"), bad, 2, 2, NULL, &st), BSFIT_ENONFINITE);
    assert_int_equal(bsfit_points_write(tmp("x.csv"), xy, 2, 2, zero, &st), BSFIT_EWEIGHT);
    assert_int_equal(bsfit_points_write(tmp("x.csv"), xy, 0, 2, NULL, &st), BSFIT_EINVAL);
    assert_int_equal(count_files("x.csv"), 0);
  }
}

static void test_points_allocation_failures(void **state) {
  /* enough rows to make the arrays grow several times */
  char text[20000];
  size_t len = 0, m;
  long n;
  int i, dim;
  (void)state;
  len += (size_t)snprintf(text, sizeof text, "x,y,w\n");
  for (i = 0; i < 700; i++) len += (size_t)snprintf(text + len, sizeof text - len, "%d,%d,1\n", i, -i);
  for (n = 1; n < 100; n++) {
    counting c = {0, n, 0};
    bsfit_allocator a = {counting_alloc, &c, NULL};
    double *xy, *w;
    bsfit_err e = bsfit_points_parse(text, len, &xy, &m, &dim, &w, &a, NULL);
    if (e == BSFIT_OK) {
      assert_true(m == 700 && xy[2 * 699 + 1] == -699 && w[699] == 1);
      bsfit_points_free(xy, m, dim, w, &a);
      assert_int_equal(c.live, 0);
      break;
    }
    assert_int_equal(e, BSFIT_ENOMEM);
    assert_int_equal(c.live, 0);
  }
  assert_true(n > 3 && n < 100);
}

/* }==================================================================== */

/* {====================================================================
** Atomic writing
** ===================================================================== */

static void test_atomic_write(void **state) {
  bsfit_status st;
  char *s;
  size_t len;
  char target[1024];
  (void)state;
  /* replacing an existing file */
  assert_int_equal(bsfit_write_file_atomic(tmp("a.txt"), "old", 3, &st), BSFIT_OK);
  assert_int_equal(bsfit_write_file_atomic(tmp("a.txt"), "new text", 8, &st), BSFIT_OK);
  s = slurp(tmp("a.txt"), &len);
  assert_int_equal(len, 8);
  assert_memory_equal(s, "new text", 8);
  free(s);
  /* a directory in the way: rename fails, the target stays, no temporary is left */
  snprintf(target, sizeof target, "%s", tmp("adir"));
  assert_int_equal(mkdir(target, 0777), 0);
  assert_int_equal(bsfit_write_file_atomic(target, "data", 4, &st), BSFIT_EIO);
  assert_non_null(strstr(st.msg, "adir"));
  assert_int_equal(count_files(".tmp."), 0);
  {
    struct stat sb;
    assert_int_equal(stat(target, &sb), 0);
    assert_true(S_ISDIR(sb.st_mode));
  }
  /* a missing directory */
  assert_int_equal(bsfit_write_file_atomic(tmp("nodir/x.txt"), "data", 4, &st), BSFIT_EIO);
  assert_non_null(strstr(st.msg, "nodir"));
  assert_int_equal(bsfit_write_file_atomic(NULL, "data", 4, &st), BSFIT_EINVAL);
  assert_int_equal(bsfit_write_file_atomic("", "data", 4, &st), BSFIT_EINVAL);
  assert_int_equal(bsfit_write_file_atomic(tmp("b.txt"), NULL, 4, &st), BSFIT_EINVAL);
  /* a stale temporary with the first name does not block the writer */
  {
    char stale[1200];
    FILE *f;
    snprintf(stale, sizeof stale, "%s.tmp.%ld.0", tmp("c.txt"), (long)getpid());
    f = fopen(stale, "w");
    assert_non_null(f);
    fclose(f);
    assert_int_equal(bsfit_write_file_atomic(tmp("c.txt"), "ok", 2, &st), BSFIT_OK);
    remove(stale);
  }
  assert_int_equal(count_files(".tmp."), 0);
}

/* }==================================================================== */

/* {====================================================================
** JSON
** ===================================================================== */

static void test_curve_json_roundtrip(void **state) {
  bsfit_curve c[4], r;
  int i;
  (void)state;
  make_curves(c);
  bsfit_curve_init(&r);
  for (i = 0; i < 4; i++) {
    char *js;
    size_t len;
    bsfit_status st;
    assert_int_equal(bsfit_curve_to_json(&c[i], &js, &len, NULL, &st), BSFIT_OK);
    assert_int_equal(strlen(js), len);
    /* structure: the keys of docs/formats.md, weights only when rational */
    assert_non_null(strstr(js, "\"knots\":["));
    assert_non_null(strstr(js, "\"control_points\":[["));
    assert_non_null(strstr(js, "\"domain\":["));
    assert_true((strstr(js, "\"weights\":[") != NULL) == (c[i].weights != NULL));
    assert_non_null(strstr(js, i == 0 ? "\"type\":\"nurbs\"" : i == 3 ? "\"type\":\"bezier\""
                                                                      : "\"type\":\"bspline\""));
    assert_non_null(strstr(js, i == 2 ? "\"periodic\":true" : "\"periodic\":false"));
    /* round trip: bit for bit */
    assert_int_equal(bsfit_curve_from_json(js, len, &r, NULL, &st), BSFIT_OK);
    assert_same_curve(&c[i], &r);
    free(js);
  }
  /* through a file */
  assert_int_equal(bsfit_curve_write_json(&c[0], tmp("c.json"), NULL), BSFIT_OK);
  assert_int_equal(bsfit_curve_read_json(tmp("c.json"), &r, NULL, NULL), BSFIT_OK);
  assert_same_curve(&c[0], &r);
  bsfit_curve_free(&r);
  free_curves(c);
}

static void test_curve_json_handwritten(void **state) {
  /* blanks, escapes, unknown keys of every kind, keys in any order */
  const char *js =
    " {\n \"comment\" : \"a \\\"quoted\\\" \\u00e9 \\n text\", \"extra\": {\"a\": [1, {\"b\": null}],"
    " \"c\": [true, false, -0.5e-3]},\n \"control_points\": [[0, 0], [1, 2], [3, 1e0]],"
    " \"knots\": [0, 0, 0, 1, 1, 1], \"degree\": 2.0, \"type\": \"bspline\", \"big\": 1e999 }\n";
  bsfit_curve c;
  double P[2];
  bsfit_status st;
  (void)state;
  bsfit_curve_init(&c);
  assert_int_equal(bsfit_curve_from_json(js, strlen(js), &c, NULL, &st), BSFIT_OK);
  assert_true(c.degree == 2 && c.dim == 2 && c.n == 3 && c.weights == NULL && !c.periodic);
  /* a quadratic Bézier-shaped B-spline: C(1/2) = (P0 + 2 P1 + P2) / 4 */
  assert_int_equal(bsfit_curve_eval(&c, 0.5, P, NULL), BSFIT_OK);
  assert_float_equal(P[0], 5.0 / 4, 1e-15);
  assert_float_equal(P[1], 5.0 / 4, 1e-15);
  bsfit_curve_free(&c);
}

static void expect_json_error(const char *js, bsfit_err code, const char *in_msg) {
  bsfit_curve c;
  bsfit_status st;
  bsfit_curve_init(&c);
  assert_int_equal(bsfit_curve_from_json(js, strlen(js), &c, NULL, &st), code);
  assert_int_equal(st.code, code);
  assert_null(c.ctrl);
  if (in_msg && !strstr(st.msg, in_msg)) fail_msg("message '%s' lacks '%s'", st.msg, in_msg);
}

#define GOOD_HEAD "{\"type\":\"bspline\",\"degree\":1,"
static void test_curve_json_errors(void **state) {
  (void)state;
  expect_json_error("{\"type\":\"bspline\",\"degree\":1,\"control_points\":[[0,0],[1,1]]}",
                    BSFIT_EFORMAT, "missing key \"knots\"");
  expect_json_error("{\"degree\":1,\"knots\":[0,0,1,1],\"control_points\":[[0,0],[1,1]]}",
                    BSFIT_EFORMAT, "missing key \"type\"");
  expect_json_error("{\"type\":\"nurbs\",\"degree\":1,\"knots\":[0,0,1,1],\"control_points\":[[0,0],[1,1]]}",
                    BSFIT_EFORMAT, "\"weights\"");
  expect_json_error("{\"type\":\"spline\",\"degree\":1,\"knots\":[0,0,1,1],\"control_points\":[[0,0],[1,1]]}",
                    BSFIT_EFORMAT, "unknown curve type");
  expect_json_error("{\"type\":\"bspline\",\"degree\":1.5,\"knots\":[0,0,1,1],\"control_points\":[[0,0],[1,1]]}",
                    BSFIT_EFORMAT, "integer");
  expect_json_error("{\"type\":\"bspline\",\"degree\":-1,\"knots\":[0,0,1,1],\"control_points\":[[0,0],[1,1]]}",
                    BSFIT_EDEGREE, NULL);
  expect_json_error("{\"type\":\"bspline\",\"degree\":2,\"knots\":[0,0,1,1],\"control_points\":[[0,0],[1,1]]}",
                    BSFIT_EDEGREE, NULL);
  expect_json_error("{\"type\":\"bspline\",\"degree\":\"1\",\"knots\":[0,0,1,1],\"control_points\":[[0,0],[1,1]]}",
                    BSFIT_EFORMAT, "expected a number");
  expect_json_error(GOOD_HEAD "\"knots\":[0,0,1],\"control_points\":[[0,0],[1,1]]}", BSFIT_ENKNOTS,
                    "3 values, 4 expected");
  expect_json_error(GOOD_HEAD "\"knots\":[0,1,0,1],\"control_points\":[[0,0],[1,1]]}",
                    BSFIT_EKNOTS_DECR, NULL);
  expect_json_error(GOOD_HEAD "\"knots\":[0,0,1,1],\"control_points\":[[0,0],[1]]}", BSFIT_EFORMAT,
                    "ragged");
  expect_json_error(GOOD_HEAD "\"knots\":[0,0,1,1],\"control_points\":[]}", BSFIT_ETOOFEW, NULL);
  expect_json_error(GOOD_HEAD "\"dim\":3,\"knots\":[0,0,1,1],\"control_points\":[[0,0],[1,1]]}",
                    BSFIT_EDIM, NULL);
  expect_json_error(GOOD_HEAD "\"knots\":[0,0,1,1],\"control_points\":[[0,0],[1,1]],\"domain\":[0,2]}",
                    BSFIT_EFORMAT, "domain");
  expect_json_error(GOOD_HEAD "\"knots\":[0,0,1,1],\"control_points\":[[0,0],[1,1]],\"weights\":[1,1]}",
                    BSFIT_EFORMAT, "no weights");
  expect_json_error("{\"type\":\"nurbs\",\"degree\":1,\"knots\":[0,0,1,1],\"control_points\":[[0,0],[1,1]],\"weights\":[1,0]}",
                    BSFIT_EWEIGHT, NULL);
  expect_json_error("{\"type\":\"nurbs\",\"degree\":1,\"knots\":[0,0,1,1],\"control_points\":[[0,0],[1,1]],\"weights\":[1]}",
                    BSFIT_EFORMAT, "weights");
  expect_json_error("{\"type\":\"bezier\",\"degree\":1,\"knots\":[0,0.5,1,1],\"control_points\":[[0,0],[1,1]]}",
                    BSFIT_EFORMAT, "Bezier");
  expect_json_error(GOOD_HEAD "\"periodic\":true,\"knots\":[0,0,1,1],\"control_points\":[[0,0],[1,1]]}",
                    BSFIT_ENOTPERIODIC, NULL);
  /* grammar */
  expect_json_error(GOOD_HEAD "\"knots\":[0,0,1,1,],\"control_points\":[[0,0],[1,1]]}",
                    BSFIT_EFORMAT, "byte 46: expected a number");
  expect_json_error(GOOD_HEAD "\"knots\":[0,0,1,01],\"control_points\":[[0,0],[1,1]]}",
                    BSFIT_EFORMAT, "byte");
  expect_json_error(GOOD_HEAD "\"knots\":[0,0,1,1],\"control_points\":[[0,0],[1,1]]} x",
                    BSFIT_EFORMAT, "trailing");
  expect_json_error(GOOD_HEAD "\"degree\":1,\"knots\":[0,0,1,1],\"control_points\":[[0,0],[1,1]]}",
                    BSFIT_EFORMAT, "repeated key");
  expect_json_error("{\"x\":tru}", BSFIT_EFORMAT, "invalid literal");
  expect_json_error("{\"x\":\"a\tb\"}", BSFIT_EFORMAT, "control character");
  expect_json_error("{\"x\":\"\\q\"}", BSFIT_EFORMAT, "bad escape");
  expect_json_error("[1,2]", BSFIT_EFORMAT, "expected '{'");
  expect_json_error("", BSFIT_EFORMAT, "end of text");
  expect_json_error(GOOD_HEAD "\"knots\":[0,0,1,1e999],\"control_points\":[[0,0],[1,1]]}",
                    BSFIT_ENONFINITE, NULL);
  {
    /* nesting deeper than the reader allows, in a skipped value */
    char deep[300];
    int i;
    strcpy(deep, "{\"x\":");
    for (i = 0; i < 100; i++) strcat(deep, "[");
    expect_json_error(deep, BSFIT_EFORMAT, "too deep");
  }
  {
    bsfit_curve c;
    bsfit_curve_init(&c);
    assert_int_equal(bsfit_curve_from_json(NULL, 0, &c, NULL, NULL), BSFIT_EINVAL);
    assert_int_equal(bsfit_curve_read_json(tmp("none.json"), &c, NULL, NULL), BSFIT_EIO);
  }
}

static void test_curve_json_truncated(void **state) {
  /* every proper prefix of a valid document is malformed, and leaks nothing */
  bsfit_curve c[4], r;
  char *js;
  size_t len, n;
  (void)state;
  make_curves(c);
  bsfit_curve_init(&r);
  assert_int_equal(bsfit_curve_to_json(&c[0], &js, &len, NULL, NULL), BSFIT_OK);
  for (n = 0; n + 1 < len; n++) {  /* the last byte is the newline */
    bsfit_status st;
    bsfit_err e = bsfit_curve_from_json(js, n, &r, NULL, &st);
    if (e != BSFIT_EFORMAT) fail_msg("prefix of %zu bytes gave %s", n, bsfit_errname(e));
  }
  assert_int_equal(bsfit_curve_from_json(js, len - 1, &r, NULL, NULL), BSFIT_OK);
  bsfit_curve_free(&r);
  free(js);
  free_curves(c);
}

static void test_json_allocation_failures(void **state) {
  bsfit_curve c[4], r;
  long n;
  (void)state;
  make_curves(c);
  for (n = 1; n < 200; n++) {
    counting k = {0, n, 0};
    bsfit_allocator a = {counting_alloc, &k, NULL};
    char *js = NULL;
    size_t len = 0;
    bsfit_err e;
    bsfit_curve_init(&r);
    e = bsfit_curve_to_json(&c[0], &js, &len, &a, NULL);
    if (e == BSFIT_OK) e = bsfit_curve_from_json(js, len, &r, &a, NULL);
    assert_true(e == BSFIT_OK || e == BSFIT_ENOMEM);
    bsfit_curve_free(&r);
    if (js) a.fn(a.ud, js, len + 1, 0);
    assert_int_equal(k.live, 0);
    if (e == BSFIT_OK) break;
  }
  assert_true(n > 2 && n < 200);
  free_curves(c);
}

static void test_surface_json_roundtrip(void **state) {
  static const double U[] = {0, 0, 0, 0.4, 1, 1, 1}, V[] = {0, 0, 0.5, 1, 1};
  double ctrl[4 * 3 * 3], w[12];
  bsfit_surface s, r;
  char *js;
  size_t len, i;
  int rational;
  (void)state;
  for (i = 0; i < 36; i++) ctrl[i] = cos(0.9 * (double)i) / 3;
  for (i = 0; i < 12; i++) w[i] = 1 + (double)i / 9;
  bsfit_surface_init(&s);
  bsfit_surface_init(&r);
  for (rational = 0; rational <= 1; rational++) {
    assert_int_equal(bsfit_surface_new(&s, 2, 1, 3, 4, 3, U, V, ctrl, rational ? w : NULL, NULL,
                                       NULL), BSFIT_OK);
    assert_int_equal(bsfit_surface_to_json(&s, &js, &len, NULL, NULL), BSFIT_OK);
    assert_non_null(strstr(js, rational ? "\"nurbs_surface\"" : "\"bspline_surface\""));
    assert_non_null(strstr(js, "\"control_points\":[[["));
    assert_true((strstr(js, "\"weights\":[[") != NULL) == rational);
    assert_int_equal(bsfit_surface_from_json(js, len, &r, NULL, NULL), BSFIT_OK);
    assert_true(r.nu == 4 && r.nv == 3 && r.degree_u == 2 && r.degree_v == 1 && r.dim == 3);
    assert_memory_equal(r.ctrl, ctrl, sizeof ctrl);
    assert_memory_equal(r.knots_u, U, sizeof U);
    assert_memory_equal(r.knots_v, V, sizeof V);
    if (rational) assert_memory_equal(r.weights, w, sizeof w);
    else assert_null(r.weights);
    free(js);
  }
  assert_int_equal(bsfit_surface_write_json(&s, tmp("s.json"), NULL), BSFIT_OK);
  assert_int_equal(count_files("s.json"), 1);
  /* a Bézier surface keeps its type; a ragged net is refused */
  assert_int_equal(bsfit_surface_new_bezier(&s, 3, 3, 3, ctrl, NULL, NULL, NULL), BSFIT_OK);
  assert_int_equal(bsfit_surface_to_json(&s, &js, &len, NULL, NULL), BSFIT_OK);
  assert_int_equal(bsfit_surface_from_json(js, len, &r, NULL, NULL), BSFIT_OK);
  assert_true(r.bezier == 1 && r.degree_u == 2);
  free(js);
  {
    const char *bad = "{\"type\":\"bspline_surface\",\"degree_u\":1,\"degree_v\":1,"
                      "\"knots_u\":[0,0,1,1],\"knots_v\":[0,0,1,1],"
                      "\"control_points\":[[[0,0,0],[1,0,0]],[[0,1,0]]]}";
    bsfit_status st;
    assert_int_equal(bsfit_surface_from_json(bad, strlen(bad), &r, NULL, &st), BSFIT_EFORMAT);
    assert_non_null(strstr(st.msg, "ragged"));
  }
  bsfit_surface_free(&s);
  bsfit_surface_free(&r);
}

/* }==================================================================== */

/* {====================================================================
** SVG
** ===================================================================== */

static int count_str(const char *s, const char *needle) {
  int n = 0;
  while ((s = strstr(s, needle)) != NULL) n++, s++;
  return n;
}

static void test_svg(void **state) {
  const double pts[] = {0, 0, 10, 0, 10, 5, 0, 5, 5, 2.5};
  double bbox[4], vb[4];
  bsfit_curve c[4];
  bsfit_svg *s;
  char *doc;
  size_t len;
  const char *p;
  double x0, y0, x1, y1;
  (void)state;
  make_curves(c);
  bsfit_svg_bbox_init(bbox);
  bsfit_svg_bbox_add(bbox, pts, 5, 2);
  assert_true(bbox[0] == 0 && bbox[1] == 0 && bbox[2] == 10 && bbox[3] == 5);
  assert_int_equal(bsfit_svg_begin(&s, bbox, 800, NULL, NULL), BSFIT_OK);
  assert_int_equal(bsfit_svg_points(s, pts, 5, 2, 2, NULL, NULL), BSFIT_OK);
  assert_int_equal(bsfit_svg_polyline(s, pts, 2, 2, 0, "edge", NULL), BSFIT_OK);
  assert_int_equal(bsfit_svg_curve(s, &c[2], 64, NULL, NULL), BSFIT_OK);
  assert_int_equal(bsfit_svg_control_polygon(s, &c[2], NULL, NULL), BSFIT_OK);
  assert_int_equal(bsfit_svg_marker(s, 10, 5, "worst <r&d>", NULL, NULL), BSFIT_OK);
  assert_int_equal(bsfit_svg_end(s, &doc, &len, NULL), BSFIT_OK);
  assert_int_equal(strlen(doc), len);
  /* structure */
  assert_non_null(strstr(doc, "<svg xmlns=\"http://www.w3.org/2000/svg\""));
  assert_non_null(strstr(doc, "</svg>\n"));
  assert_int_equal(count_str(doc, "<circle"), 5 + 1);
  assert_int_equal(count_str(doc, "<polyline class=\"edge\""), 1);
  assert_int_equal(count_str(doc, "<polygon class=\"curve\""), 1);   /* periodic: closed */
  assert_int_equal(count_str(doc, "<polygon class=\"control\""), 1);
  assert_non_null(strstr(doc, ".control{fill:none;stroke:#7f7f7f;stroke-width:1;stroke-dasharray"));
  assert_non_null(strstr(doc, ">worst &lt;r&amp;d&gt;</text>"));
  /* the mapping: y points up and the data box sits inside the viewBox with a margin */
  p = strstr(doc, "viewBox=\"");
  assert_int_equal(sscanf(p, "viewBox=\"%lf %lf %lf %lf\"", &vb[0], &vb[1], &vb[2], &vb[3]), 4);
  {
    const char *head = "<polyline class=\"edge\" fill=\"none\" points=\"";
    p = strstr(doc, head);
    assert_non_null(p);
    assert_int_equal(sscanf(p + strlen(head), "%lf,%lf %lf,%lf", &x0, &y0, &x1, &y1), 4);
  }
  assert_true(x1 > x0);                      /* (0,0) -> (10,0): x grows */
  assert_float_equal(y1, y0, 1e-9);
  p = strstr(doc, "<circle cx=\"");
  {
    double cx[4], cy[4];
    int i;
    for (i = 0; i < 4; i++) {
      assert_int_equal(sscanf(p, "<circle cx=\"%lf\" cy=\"%lf\"", &cx[i], &cy[i]), 2);
      p = strstr(p + 1, "<circle cx=\"");
    }
    assert_true(cy[2] < cy[1]);              /* (10,5) is above (10,0): smaller SVG y */
    assert_float_equal((cx[1] - cx[0]) / 10, (cy[1] - cy[2]) / 5, 1e-6); /* same scale */
    assert_true(cx[0] > 0 && cx[1] < vb[2] && cy[2] > 0 && cy[0] < vb[3]);
    assert_float_equal(cx[0], vb[2] - cx[1], 1e-6); /* equal margins */
  }
  free(doc);
  /* errors */
  {
    bsfit_status st;
    double empty[4], nanbox[4] = {0, 0, NAN, 1};
    assert_int_equal(bsfit_svg_end(s, &doc, &len, &st), BSFIT_EINVAL); /* already ended */
    assert_int_equal(bsfit_svg_points(s, pts, 5, 2, 2, NULL, &st), BSFIT_EINVAL);
    bsfit_svg_free(s);
    bsfit_svg_bbox_init(empty);
    assert_int_equal(bsfit_svg_begin(&s, empty, 800, NULL, &st), BSFIT_EINVAL);
    assert_null(s);
    assert_int_equal(bsfit_svg_begin(&s, nanbox, 800, NULL, &st), BSFIT_ENONFINITE);
    assert_int_equal(bsfit_svg_begin(&s, bbox, 0, NULL, &st), BSFIT_EINVAL);
    assert_int_equal(bsfit_svg_begin(&s, bbox, 400, NULL, &st), BSFIT_OK);
    assert_int_equal(bsfit_svg_points(s, pts, 5, 2, 2, "bad class", &st), BSFIT_EINVAL);
    assert_int_equal(bsfit_svg_polyline(s, pts, 2, 1, 0, NULL, &st), BSFIT_EDIM);
    assert_int_equal(bsfit_svg_marker(s, NAN, 0, "x", NULL, &st), BSFIT_ENONFINITE);
    assert_int_equal(bsfit_svg_curve(s, &c[0], 1, NULL, &st), BSFIT_EINVAL);
    assert_int_equal(bsfit_svg_write(s, tmp("pic.svg"), &st), BSFIT_OK);
    bsfit_svg_free(s);
    doc = slurp(tmp("pic.svg"), &len);
    assert_non_null(strstr(doc, "</svg>"));
    free(doc);
  }
  free_curves(c);
}

/* }==================================================================== */

/* {====================================================================
** IGES: parsed back by the rules of the fixed format
** ===================================================================== */

typedef struct iges_file {
  char lines[400][82];
  int n;
  int count[5]; /* S G D P T */
  char pdata[20000];
} iges_file;

static void iges_parse(const char *text, iges_file *f) {
  const char *letters = "SGDPT";
  int last = 0;
  memset(f, 0, sizeof *f);
  while (*text) {
    const char *nl = strchr(text, '\n');
    char *L = f->lines[f->n];
    int sec;
    long seq;
    assert_non_null(nl);
    assert_int_equal(nl - text, 80); /* 80 columns, every record */
    memcpy(L, text, 80);
    L[80] = '\0';
    sec = (int)(strchr(letters, L[72]) - letters);
    assert_true(L[72] != '\0' && strchr(letters, L[72]) != NULL);
    assert_true(sec >= last); /* sections in order */
    last = sec;
    seq = strtol(L + 73, NULL, 10);
    assert_int_equal(seq, ++f->count[sec]); /* numbered from 1 per section */
    if (L[72] == 'P') {
      assert_int_equal(strtol(L + 65, NULL, 10), 1); /* back pointer to DE 1 */
      assert_true(L[64] == ' ');
      strncat(f->pdata, L, 64);
    }
    f->n++;
    text = nl + 1;
  }
  assert_int_equal(f->count[4], 1);
}

/* Checks DE fields and the Terminate counts; returns the P-data values. */
static size_t iges_check(const iges_file *f, int type, double *vals, size_t cap) {
  const char *T = f->lines[f->n - 1], *D1 = f->lines[f->count[0] + f->count[1]];
  char field[9];
  size_t n = 0;
  char *tok, *save, *p;
  char buf[20000];
  assert_int_equal(f->count[2], 2);
  memcpy(field, D1, 8);
  field[8] = 0;
  assert_int_equal(atoi(field), type);
  memcpy(field, D1 + 8, 8);
  assert_int_equal(atoi(field), 1); /* parameter data starts at P1 */
  memcpy(field, f->lines[f->count[0] + f->count[1] + 1] + 24, 8);
  assert_int_equal(atoi(field), f->count[3]); /* parameter line count */
  {
    char want[40];
    snprintf(want, sizeof want, "S%7dG%7dD%7dP%7d", f->count[0], f->count[1], f->count[2],
             f->count[3]);
    assert_memory_equal(T, want, 32);
  }
  /* global section: delimiters as the first two parameters, ends with ';' */
  assert_memory_equal(f->lines[f->count[0]], "1H,,1H;,", 8);
  strcpy(buf, f->pdata);
  p = strchr(buf, ';');
  assert_non_null(p);
  *p = '\0';
  for (tok = buf; tok != NULL; tok = save) {
    save = strchr(tok, ',');
    if (save) *save++ = '\0';
    assert_true(n < cap);
    assert_non_null(strpbrk(tok, "0123456789"));
    vals[n++] = strtod(tok, NULL);
  }
  return n;
}

static void test_iges_curve(void **state) {
  bsfit_curve c[4];
  static iges_file f;
  double v[200];
  int i;
  (void)state;
  make_curves(c);
  for (i = 0; i < 3; i++) {
    const bsfit_curve *k = &c[i];
    size_t n = k->n, p = (size_t)k->degree, nk = n + p + 1, j, at, cnt;
    char *text;
    size_t len;
    double a, b;
    assert_int_equal(bsfit_curve_to_iges(k, &text, &len, NULL, NULL), BSFIT_OK);
    iges_parse(text, &f);
    cnt = iges_check(&f, 126, v, 200);
    /* 126, K, M, PROP1..4, knots, weights, points, V0, V1, normal */
    assert_int_equal(cnt, 7 + nk + n + 3 * n + 2 + 3);
    assert_true(v[0] == 126 && v[1] == (double)(n - 1) && v[2] == (double)p);
    assert_true(v[3] == (k->dim <= 2));           /* planar */
    assert_true(v[4] == (k->periodic ? 1 : 0));   /* closed (these open curves are not) */
    assert_true(v[5] == (k->weights == NULL));    /* polynomial */
    assert_true(v[6] == k->periodic);
    at = 7;
    for (j = 0; j < nk; j++) assert_true(v[at + j] == k->knots[j]);
    at += nk;
    for (j = 0; j < n; j++) assert_true(v[at + j] == (k->weights ? k->weights[j] : 1.0));
    at += n;
    for (j = 0; j < n; j++) {
      int t;
      for (t = 0; t < 3; t++)
        assert_true(v[at + 3 * j + (size_t)t] == (t < k->dim ? k->ctrl[j * (size_t)k->dim + (size_t)t] : 0.0));
    }
    at += 3 * n;
    bsfit_curve_domain(k, &a, &b);
    assert_true(v[at] == a && v[at + 1] == b);
    free(text);
  }
  { /* SOURCE_DATE_EPOCH fixes the date: reproducible bytes (a bad value is ignored) */
    char *t1, *t2;
    size_t l1, l2;
    assert_int_equal(setenv("SOURCE_DATE_EPOCH", "1700000000", 1), 0);
    assert_int_equal(bsfit_curve_to_iges(&c[0], &t1, &l1, NULL, NULL), BSFIT_OK);
    assert_int_equal(bsfit_curve_to_iges(&c[0], &t2, &l2, NULL, NULL), BSFIT_OK);
    assert_int_equal(l1, l2);
    assert_memory_equal(t1, t2, l1);
    assert_non_null(strstr(t1, "15H20231114.221320")); /* 1700000000 s, UTC */
    free(t1);
    assert_int_equal(setenv("SOURCE_DATE_EPOCH", "soon", 1), 0);
    assert_int_equal(bsfit_curve_to_iges(&c[0], &t1, &l1, NULL, NULL), BSFIT_OK);
    assert_null(strstr(t1, "15H20231114.221320"));
    assert_non_null(strstr(t1, "15H2")); /* the time of writing */
    free(t1);
    free(t2);
    assert_int_equal(unsetenv("SOURCE_DATE_EPOCH"), 0);
  }
  assert_int_equal(bsfit_curve_write_iges(&c[0], tmp("c.igs"), NULL), BSFIT_OK);
  {
    char *text = slurp(tmp("c.igs"), NULL);
    iges_parse(text, &f);
    assert_non_null(strstr(f.lines[f.count[0]], "5Hc.igs"));
    free(text);
  }
  {
    bsfit_curve c4;
    bsfit_status st;
    double P[8] = {0};
    bsfit_curve_init(&c4);
    assert_int_equal(bsfit_curve_new(&c4, 1, 4, 2, NULL, P, NULL, 0, NULL, NULL), BSFIT_OK);
    assert_int_equal(bsfit_curve_write_iges(&c4, tmp("d.igs"), &st), BSFIT_EDIM);
    assert_int_equal(count_files("d.igs"), 0);
    bsfit_curve_free(&c4);
  }
  free_curves(c);
}

static void test_iges_surface(void **state) {
  static const double U[] = {0, 0, 0, 0.4, 1, 1, 1}, V[] = {0, 0, 0.5, 1, 1};
  static iges_file f;
  double ctrl[4 * 3 * 3], w[12], v[300];
  bsfit_surface s;
  char *text;
  size_t len, i, j, cnt, at;
  (void)state;
  for (i = 0; i < 36; i++) ctrl[i] = sin(0.3 * (double)i) * 7;
  for (i = 0; i < 12; i++) w[i] = 1 + (double)i / 5;
  bsfit_surface_init(&s);
  assert_int_equal(bsfit_surface_new(&s, 2, 1, 3, 4, 3, U, V, ctrl, w, NULL, NULL), BSFIT_OK);
  assert_int_equal(bsfit_surface_to_iges(&s, &text, &len, NULL, NULL), BSFIT_OK);
  iges_parse(text, &f);
  cnt = iges_check(&f, 128, v, 300);
  assert_int_equal(cnt, 10 + 7 + 5 + 12 + 36 + 4);
  assert_true(v[0] == 128 && v[1] == 3 && v[2] == 2 && v[3] == 2 && v[4] == 1 && v[7] == 0);
  for (i = 0; i < 7; i++) assert_true(v[10 + i] == U[i]);
  for (i = 0; i < 5; i++) assert_true(v[17 + i] == V[i]);
  at = 22;
  /* the first index (u) runs fastest */
  for (j = 0; j < 3; j++)
    for (i = 0; i < 4; i++) assert_true(v[at++] == w[i * 3 + j]);
  for (j = 0; j < 3; j++)
    for (i = 0; i < 4; i++) {
      int t;
      for (t = 0; t < 3; t++) assert_true(v[at++] == ctrl[(i * 3 + j) * 3 + (size_t)t]);
    }
  assert_true(v[at] == 0 && v[at + 1] == 1 && v[at + 2] == 0 && v[at + 3] == 1);
  free(text);
  assert_int_equal(bsfit_surface_write_iges(&s, tmp("s.igs"), NULL), BSFIT_OK);
  assert_int_equal(count_files("s.igs"), 1);
  bsfit_surface_free(&s);
}

/* }==================================================================== */

int main(void) {
  const struct CMUnitTest tests[] = {
    cmocka_unit_test(test_points_header_any_order),
    cmocka_unit_test(test_points_whitespace_no_header),
    cmocka_unit_test(test_points_malformed_strings),
    cmocka_unit_test(test_points_malformed_files),
    cmocka_unit_test(test_points_write_read_roundtrip),
    cmocka_unit_test(test_points_allocation_failures),
    cmocka_unit_test(test_atomic_write),
    cmocka_unit_test(test_curve_json_roundtrip),
    cmocka_unit_test(test_curve_json_handwritten),
    cmocka_unit_test(test_curve_json_errors),
    cmocka_unit_test(test_curve_json_truncated),
    cmocka_unit_test(test_json_allocation_failures),
    cmocka_unit_test(test_surface_json_roundtrip),
    cmocka_unit_test(test_svg),
    cmocka_unit_test(test_iges_curve),
    cmocka_unit_test(test_iges_surface),
  };
  return cmocka_run_group_tests(tests, setup, teardown);
}
