/*
** cmocka_double.h
** Force-included into every C test (see CMakeLists.txt). cmocka 1.1.5 (Debian 12)
** compares assert_float_equal's arguments as `float`, which makes tolerances below
** ~1e-7 meaningless: two doubles differing by 1e-9 would compare equal. This header
** includes cmocka first and redefines assert_float_equal / assert_float_not_equal to
** compare in double precision, |a - b| <= eps (so eps = 0 means bitwise-equal values,
** and a NaN never passes).
*/
#ifndef BSFIT_CMOCKA_DOUBLE_H
#define BSFIT_CMOCKA_DOUBLE_H

#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>
#include <math.h>

static inline void bsfit_test_near(double a, double b, double eps, int want_equal,
                                   const char *as, const char *bs, const char *file, int line) {
  int equal = fabs(a - b) <= eps;
  if (equal != want_equal) {
    print_error("%s = %.17g %s %s = %.17g (|diff| = %.3g, eps = %.3g)\n", as, a,
                   want_equal ? "!=" : "==", bs, b, fabs(a - b), eps);
    _fail(file, line);
  }
}

#undef assert_float_equal
#define assert_float_equal(a, b, eps) \
  bsfit_test_near((double)(a), (double)(b), (double)(eps), 1, #a, #b, __FILE__, __LINE__)
#undef assert_float_not_equal
#define assert_float_not_equal(a, b, eps) \
  bsfit_test_near((double)(a), (double)(b), (double)(eps), 0, #a, #b, __FILE__, __LINE__)

#endif
