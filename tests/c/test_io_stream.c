/*
** test_io_stream.c
** The streaming point reader (bsfit_points_read reads line by line through a fixed
** window: memory follows the points, a bad line stops the reading) checked against
** the in-memory parser on random files whose lines cross the window's edges; and the
** directory functions of io_dir.c (listing with any byte in a name, kinds, mkdir -p).
*/

#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <dirent.h>
#include <sys/stat.h>
#include <unistd.h>
#include <cmocka.h>

#include "bsfit.h"
#include "testutil.h"

/* {====================================================================
** Helpers
** ===================================================================== */

static char tmpdir[512];

static int setup(void **state) {
  (void)state;
  snprintf(tmpdir, sizeof tmpdir, "%s/test_io_stream_tmp.%ld", BSFIT_BINARY_DIR, (long)getpid());
  return mkdir(tmpdir, 0777) == 0 ? 0 : -1;
}

/* rm -r of tmpdir, two levels deep (what the tests make) */
static void remove_tree(const char *dir, int depth) {
  DIR *d = opendir(dir);
  struct dirent *e;
  char p[2048];
  while (d && (e = readdir(d)) != NULL) {
    if (strcmp(e->d_name, ".") == 0 || strcmp(e->d_name, "..") == 0) continue;
    if (strlen(dir) + strlen(e->d_name) + 2 > sizeof p) continue;
    memcpy(p, dir, strlen(dir));
    p[strlen(dir)] = '/';
    memcpy(p + strlen(dir) + 1, e->d_name, strlen(e->d_name) + 1);
    if (remove(p) != 0 && depth > 0) remove_tree(p, depth - 1);
  }
  if (d) closedir(d);
  rmdir(dir);
}

static int teardown(void **state) {
  (void)state;
  remove_tree(tmpdir, 4);
  return 0;
}

static const char *tmp(const char *name) {
  static char p[1024];
  snprintf(p, sizeof p, "%s/%s", tmpdir, name);
  return p;
}

static void write_text(const char *path, const char *s, size_t n) {
  FILE *f = fopen(path, "wb");
  assert_non_null(f);
  assert_int_equal(fwrite(s, 1, n, f), n);
  assert_int_equal(fclose(f), 0);
}

/* An allocator that records the peak of live bytes. */
typedef struct peak {
  long long live, max;
} peak;

static void *peak_alloc(void *ud, void *p, size_t osz, size_t nsz) {
  peak *c = (peak *)ud;
  if (nsz == 0) {
    if (p) c->live -= (long long)osz;
    free(p);
    return NULL;
  }
  p = realloc(p, nsz);
  if (p) {
    c->live += (long long)nsz - (long long)osz;
    if (c->live > c->max) c->max = c->live;
  }
  return p;
}

/* }==================================================================== */

/* {====================================================================
** Point files
** ===================================================================== */

/* Random text of point lines (2 or 3 columns, CRLF or LF, comments up to 64 KiB
** so that lines cross the reader's window) written to a file and read back: the
** same points, bit for bit, as the in-memory parser gives for the same text. */
static void test_stream_matches_parse(void **state) {
  test_rng r = {0x5eed1234abcdULL};
  int trial;
  (void)state;
  for (trial = 0; trial < 12; trial++) {
    size_t cap = 1 << 22, len = 0, m1, m2, lines = 20 + (size_t)(rng_uniform(&r) * 3000);
    char *s = malloc(cap);
    int dim = rng_uniform(&r) < 0.5 ? 2 : 3, d1, d2;
    double *xy1, *xy2;
    size_t i;
    bsfit_status st;
    assert_non_null(s);
    for (i = 0; i < lines && len + 110000 < cap; i++) {
      double u = rng_uniform(&r);
      if (u < 0.01) {                                    /* a long comment */
        size_t k, n = (size_t)(rng_uniform(&r) * 65000); /* the limit is 65536 */
        s[len++] = '#';
        for (k = 0; k < n; k++) s[len++] = (char)('a' + k % 26);
      } else if (u < 0.05) {
        len += (size_t)sprintf(s + len, "   ");
      } else if (dim == 2) {
        len +=
            (size_t)sprintf(s + len, "%.17g,%.17g", rng_range(&r, -1e3, 1e3), rng_range(&r, -1, 1));
      } else {
        len += (size_t)sprintf(s + len, "%.17g %.17g\t%.17g", rng_range(&r, -1e3, 1e3),
                               rng_range(&r, -1, 1), rng_range(&r, -1e-3, 1e-3));
      }
      if (rng_uniform(&r) < 0.3) s[len++] = '\r';
      s[len++] = '\n';
    }
    len += (size_t)sprintf(s + len, dim == 2 ? "1,2" : "1 2 3");
    if (trial % 2) s[len++] = '\n'; /* the last line's newline is optional */
    write_text(tmp("r.csv"), s, len);
    if (bsfit_points_parse(s, len, &xy1, &m1, &d1, NULL, NULL, &st) != BSFIT_OK)
      fail_msg("%s", st.msg);
    if (bsfit_points_read(tmp("r.csv"), &xy2, &m2, &d2, NULL, NULL, &st) != BSFIT_OK)
      fail_msg("%s", st.msg);
    assert_int_equal(m1, m2);
    assert_int_equal(d1, d2);
    assert_memory_equal(xy1, xy2, m1 * (size_t)d1 * sizeof(double));
    bsfit_points_free(xy1, m1, d1, NULL, NULL);
    bsfit_points_free(xy2, m2, d2, NULL, NULL);
    free(s);
  }
}

/* 4 MB of comments around 3 points: the reader's memory stays far below the file's
** size (the whole-file reader held all of it). */
static void test_stream_memory_follows_points(void **state) {
  size_t n = 4u << 20, i, m;
  char *s = malloc(n);
  peak pk = {0, 0};
  bsfit_allocator a;
  double *xy;
  int dim;
  bsfit_status st;
  (void)state;
  assert_non_null(s);
  memset(&a, 0, sizeof a);
  a.fn = peak_alloc;
  a.ud = &pk;
  for (i = 0; i < n; i++) s[i] = (i % 1000 == 999) ? '\n' : (i % 1000 == 0 ? '#' : 'c');
  memcpy(s + 1000, "0,0\n1,0\n0,1\n#", 13);
  write_text(tmp("comments.csv"), s, n);
  free(s);
  assert_int_equal(bsfit_points_read(tmp("comments.csv"), &xy, &m, &dim, NULL, &a, &st), BSFIT_OK);
  assert_int_equal(m, 3);
  assert_true(pk.max < 256 * 1024);
  bsfit_points_free(xy, m, dim, NULL, &a);
  assert_int_equal(pk.live, 0);
}

/* A bad line after many good ones: the error names it, and nothing is left allocated. */
static void test_stream_first_bad_line(void **state) {
  size_t m = 0, i, len = 0, bad = 54321;
  char *s = malloc(bad * 16 + 64);
  counting c = {0, 0, 0};
  bsfit_allocator a;
  double *xy = (double *)&c;
  int dim;
  bsfit_status st;
  char want[64];
  (void)state;
  assert_non_null(s);
  memset(&a, 0, sizeof a);
  a.fn = counting_alloc;
  a.ud = &c;
  for (i = 1; i < bad; i++) len += (size_t)sprintf(s + len, "%zu,%zu\n", i % 97, i % 89);
  len += (size_t)sprintf(s + len, "1,2,3\n4,5\n");
  write_text(tmp("bad.csv"), s, len);
  free(s);
  assert_int_equal(bsfit_points_read(tmp("bad.csv"), &xy, &m, &dim, NULL, &a, &st), BSFIT_EFORMAT);
  snprintf(want, sizeof want, "bad.csv:%zu: expected 2 columns, got 3", bad);
  assert_non_null(strstr(st.msg, want));
  assert_null(xy);
  assert_int_equal(c.live, 0);
}

/* Binary data: a file without line breaks stops after the window, not at its end; a
** NUL or control byte is named; a UTF-8 byte order mark is skipped. */
static void test_stream_binary(void **state) {
  size_t n = 1u << 20, m;
  char *s = calloc(n, 1);
  double *xy;
  int dim;
  bsfit_status st;
  (void)state;
  assert_non_null(s);
  write_text(tmp("zeros.csv"), s, n);
  free(s);
  assert_int_equal(bsfit_points_read(tmp("zeros.csv"), &xy, &m, &dim, NULL, NULL, &st),
                   BSFIT_EFORMAT);
  assert_non_null(strstr(st.msg, "zeros.csv:1: line longer than 65536 bytes"));
  write_text(tmp("nul.csv"), "1,2\n3,\0004\n", 10);
  assert_int_equal(bsfit_points_read(tmp("nul.csv"), &xy, &m, &dim, NULL, NULL, &st),
                   BSFIT_EFORMAT);
  assert_non_null(strstr(st.msg, "nul.csv:2: binary data (byte 0x00 at column 3)"));
  write_text(tmp("bom.csv"), "\xEF\xBB\xBFx,y\n1,2\n3,4\n", 15);
  assert_int_equal(bsfit_points_read(tmp("bom.csv"), &xy, &m, &dim, NULL, NULL, &st), BSFIT_OK);
  assert_int_equal(m, 2);
  assert_true(xy[0] == 1 && xy[3] == 4);
  bsfit_points_free(xy, m, dim, NULL, NULL);
  write_text(tmp("comma.csv"), "1,5;2,5\n", 8);
  assert_int_equal(bsfit_points_read(tmp("comma.csv"), &xy, &m, &dim, NULL, NULL, &st),
                   BSFIT_EFORMAT);
  assert_non_null(strstr(st.msg, "decimal comma"));
  assert_int_equal(bsfit_points_read(tmpdir, &xy, &m, &dim, NULL, NULL, &st), BSFIT_EIO);
  assert_non_null(strstr(st.msg, "Is a directory"));
}

/* }==================================================================== */

/* {====================================================================
** Directories
** ===================================================================== */

static void test_dir_list(void **state) {
  static const char *const made[] = {"b.csv", "a.csv", "with\nnewline.csv", "Z", " space", "é"};
  char **names;
  size_t n, i;
  bsfit_status st;
  peak pk = {0, 0};
  bsfit_allocator a;
  (void)state;
  memset(&a, 0, sizeof a);
  a.fn = peak_alloc;
  a.ud = &pk;
  assert_int_equal(mkdir(tmp("d"), 0777), 0);
  assert_int_equal(bsfit_dir_list(tmp("d"), &names, &n, &a, &st), BSFIT_OK);
  assert_int_equal(n, 0);
  bsfit_dir_free(names, n, &a);
  for (i = 0; i < sizeof made / sizeof made[0]; i++) {
    char p[1100];
    snprintf(p, sizeof p, "%s/%s", tmp("d"), made[i]);
    write_text(p, "", 0);
  }
  assert_int_equal(bsfit_dir_list(tmp("d"), &names, &n, &a, &st), BSFIT_OK);
  assert_int_equal(n, sizeof made / sizeof made[0]);
  for (i = 0; i + 1 < n; i++) assert_true(strcmp(names[i], names[i + 1]) < 0);
  for (i = 0; i < n && strcmp(names[i], "with\nnewline.csv") != 0; i++) continue;
  assert_true(i < n);
  bsfit_dir_free(names, n, &a);
  assert_int_equal(pk.live, 0);
  assert_int_equal(bsfit_dir_list("/nonexistent/dir/", &names, &n, NULL, &st), BSFIT_EIO);
  assert_non_null(strstr(st.msg, "/nonexistent/dir/: No such file or directory"));
  assert_null(names);
  assert_int_equal(bsfit_dir_list(tmp("d/a.csv"), &names, &n, NULL, &st), BSFIT_EIO);
  assert_non_null(strstr(st.msg, "Not a directory"));
  assert_int_equal(bsfit_dir_list("", &names, &n, NULL, &st), BSFIT_EINVAL);
}

static void test_dir_kind_make(void **state) {
  bsfit_status st;
  (void)state;
  assert_int_equal(bsfit_path_kind(tmpdir), BSFIT_PATH_DIR);
  assert_int_equal(bsfit_path_kind("/dev/null"), BSFIT_PATH_OTHER);
  assert_int_equal(bsfit_path_kind(tmp("none")), BSFIT_PATH_NONE);
  assert_int_equal(bsfit_dir_make(tmp("m/n//o/"), NULL, &st), BSFIT_OK);
  assert_int_equal(bsfit_path_kind(tmp("m/n/o")), BSFIT_PATH_DIR);
  assert_int_equal(bsfit_dir_make(tmp("m/n/o"), NULL, &st), BSFIT_OK); /* exists: fine */
  write_text(tmp("m/f"), "x", 1);
  assert_int_equal(bsfit_path_kind(tmp("m/f")), BSFIT_PATH_FILE);
  assert_int_equal(bsfit_dir_make(tmp("m/f/g"), NULL, &st), BSFIT_EIO);
  assert_non_null(strstr(st.msg, "m/f is not a directory"));
  assert_int_equal(bsfit_dir_make(NULL, NULL, &st), BSFIT_EINVAL);
}

/* }==================================================================== */

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_stream_matches_parse),
      cmocka_unit_test(test_stream_memory_follows_points),
      cmocka_unit_test(test_stream_first_bad_line),
      cmocka_unit_test(test_stream_binary),
      cmocka_unit_test(test_dir_list),
      cmocka_unit_test(test_dir_kind_make),
  };
  return cmocka_run_group_tests(tests, setup, teardown);
}
