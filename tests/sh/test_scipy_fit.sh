#!/usr/bin/env bash
# test_scipy_fit.sh BSFIT SRC: bsfit's weighted least-squares fits, redone independently.
# fit_cases.lua fits open (degrees 1-5, averaging and uniform knots, fixed ends, end
# tangents, shuffled points, shared parameters) and periodic data (degrees 1-5, both closed
# knot rules) with random weights; scipy_fit_check.py solves each problem again with
# scipy's design matrices and a dense lstsq (and make_lsq_spline), and recomputes the report.
set -u
BSFIT=$1
SRC=$2
. "$SRC/tests/sh/scipy_common.sh"
if ! "$BSFIT" "$SRC/tests/sh/fit_cases.lua" "$TMP/cases.json"; then
  echo "not ok - fit_cases.lua"
  echo "0 passed, 1 failed"
  exit 1
fi
exec "$PY" "$SRC/tests/sh/scipy_fit_check.py" "$TMP/cases.json"
