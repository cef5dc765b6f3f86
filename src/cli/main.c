/*
** main.c
** The bsfit program.
*/
#include "bsfit.h"

#include <stdio.h>
#include <string.h>

static void print_help(FILE *f) {
  fprintf(f,
          "usage: bsfit [options]\n"
          "  --version   print the version and exit\n"
          "  --help      print this help and exit\n");
}

int main(int argc, char **argv) {
  if (argc > 1 && strcmp(argv[1], "--version") == 0) {
    printf("bsfit %s\n", bsfit_version());
    return 0;
  }
  if (argc > 1 && strcmp(argv[1], "--help") == 0) {
    print_help(stdout);
    return 0;
  }
  print_help(stderr);
  return argc > 1 ? 1 : 0;
}
