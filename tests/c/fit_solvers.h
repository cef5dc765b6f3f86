/*
** fit_solvers.h
** The fitter tests run twice, once per solver (the group's setup picks it): every
** property they check must hold for the normal equations and for the QR alike.
*/
#ifndef BSFIT_FIT_SOLVERS_H
#define BSFIT_FIT_SOLVERS_H

#include "bsfit.h"

static bsfit_solver solver_under_test = BSFIT_SOLVER_CHOLESKY;

/* bsfit_fit_opts_init with the solver of this run */
static void opts_init(bsfit_fit_opts *o) {
  bsfit_fit_opts_init(o);
  o->solver = solver_under_test;
}

static int use_cholesky(void **state) {
  (void)state;
  solver_under_test = BSFIT_SOLVER_CHOLESKY;
  return 0;
}

static int use_qr(void **state) {
  (void)state;
  solver_under_test = BSFIT_SOLVER_QR;
  return 0;
}

/* Runs a group of tests with each solver; non-zero when any failed. */
#define run_with_each_solver(tests)                                      \
  (cmocka_run_group_tests_name("cholesky", tests, use_cholesky, NULL) | \
   cmocka_run_group_tests_name("qr", tests, use_qr, NULL))

#endif
