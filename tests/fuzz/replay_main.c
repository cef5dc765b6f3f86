/*
** replay_main.c
** Runs a fuzz target without libFuzzer: LLVMFuzzerTestOneInput once on every file of
** the directories (or files) given, in name order. ctest runs each target this way on
** its seeds and regression inputs in the normal and sanitizer builds, so every crash
** the fuzzers found stays a test. A broken contract aborts (exit by signal).
*/
#include <dirent.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

static int run_file(const char *path) {
  FILE *f = fopen(path, "rb");
  uint8_t *buf;
  long n;
  if (f == NULL || fseek(f, 0, SEEK_END) != 0 || (n = ftell(f)) < 0) {
    fprintf(stderr, "replay: cannot read %s\n", path);
    if (f) fclose(f);
    return 1;
  }
  rewind(f);
  buf = malloc((size_t)n + 1);
  if (buf == NULL || fread(buf, 1, (size_t)n, f) != (size_t)n) {
    fprintf(stderr, "replay: cannot read %s\n", path);
    free(buf);
    fclose(f);
    return 1;
  }
  fclose(f);
  fprintf(stderr, "replay: %s\n", path);
  LLVMFuzzerTestOneInput(buf, (size_t)n);
  free(buf);
  return 0;
}

static int by_name(const void *a, const void *b) {
  return strcmp(*(char *const *)a, *(char *const *)b);
}

static int run_dir(const char *dir, int *count) {
  DIR *d = opendir(dir);
  struct dirent *e;
  char **names = NULL;
  size_t n = 0, i;
  int bad = 0;
  if (d == NULL) return run_file(dir) == 0 ? (++*count, 0) : 1;
  while ((e = readdir(d)) != NULL) {
    char **more;
    if (e->d_name[0] == '.' || strcmp(e->d_name, "README") == 0) continue;
    more = realloc(names, (n + 1) * sizeof *names);
    if (more == NULL) break;
    names = more;
    names[n] = malloc(strlen(dir) + strlen(e->d_name) + 2);
    if (names[n] == NULL) break;
    sprintf(names[n], "%s/%s", dir, e->d_name);
    n++;
  }
  closedir(d);
  if (n > 1) qsort(names, n, sizeof *names, by_name);
  for (i = 0; i < n; i++) {
    bad |= run_file(names[i]);
    ++*count;
    free(names[i]);
  }
  free(names);
  return bad;
}

int main(int argc, char **argv) {
  int i, bad = 0, count = 0;
  for (i = 1; i < argc; i++) bad |= run_dir(argv[i], &count);
  printf("replayed %d inputs\n", count);
  return bad || count == 0 ? EXIT_FAILURE : EXIT_SUCCESS;
}
