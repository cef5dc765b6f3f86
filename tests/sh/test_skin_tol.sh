#!/bin/bash
# test_skin_tol.sh BSFIT SRCDIR: the tolerance skin against an independent measure. Scans of
# vases, bottles, a rounded box, a twisted prism, a twisted tapered ellipse and a wing, as
# meshes at several tessellations and clouds with noise, at several skin tolerances
# (skin_tol_cases.lua); scipy measures the Hausdorff distance between every section and the
# surface through it and checks it against the tolerance and the reported max_deviation
# (skin_tol_check.py). In the sanitizer build (BSFIT_SANITIZED set) only the skins are made.
set -u
BSFIT=$1
SRC=$2
. "$SRC/tests/sh/scipy_common.sh"
"$BSFIT" "$SRC/tests/sh/skin_tol_cases.lua" "$TMP" || { echo "0 passed, 1 failed"; exit 1; }
if [ -n "${BSFIT_SANITIZED:-}" ]; then
  # the sanitizer build: the skins were made clean (ASan/UBSan abort on any error); scipy's
  # 90-second measure of them is the normal build's
  cases=$(wc -l <"$TMP/cases.txt")
  [ "$cases" -gt 0 ] && echo "ok - $cases skins made under the sanitizers" && echo "1 passed, 0 failed" && exit 0
  echo "not ok - no skins made"; echo "0 passed, 1 failed"; exit 1
fi
"$PY" "$SRC/tests/sh/skin_tol_check.py" "$TMP"
