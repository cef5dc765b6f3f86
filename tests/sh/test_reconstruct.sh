#!/bin/bash
# test_reconstruct.sh: `bsfit reconstruct` end to end.
# usage: bash test_reconstruct.sh <path-to-bsfit> <source-dir>
# Prints one ok / not ok line per check and a final "N passed, M failed".
BSFIT=${1:?usage: test_reconstruct.sh BSFIT SOURCE_DIR}
SRC=${2:?usage: test_reconstruct.sh BSFIT SOURCE_DIR}
TMP=$(mktemp -d "${TMPDIR:-/tmp}/bsfit-reconstruct.XXXXXX")
trap 'rm -rf "$TMP"' EXIT
pass=0 fail=0
check() { # check NAME CONDITION-COMMAND...
  local name=$1; shift
  if "$@"; then pass=$((pass + 1)); echo "ok - $name"; else fail=$((fail + 1)); echo "not ok - $name"; fi
}

# a directory with one good and one broken section
mkdir -p "$TMP/in"
cp "$SRC/tests/data/demo/cam.csv" "$TMP/in/good.csv"
printf 'x,y\n1,2\nthree,4\n5,6\n' > "$TMP/in/broken.csv"
"$BSFIT" reconstruct "$TMP/in" -o "$TMP/out1" -q 2> "$TMP/err1"
rc=$?
check "one good + one broken: exit code 1" test "$rc" -eq 1
check "the good section has its curve, samples and picture" \
  test -s "$TMP/out1/good.json" -a -s "$TMP/out1/good.csv" -a -s "$TMP/out1/good.svg"
check "the broken section has no curve" test ! -e "$TMP/out1/broken.json"
check "summary: one ok row" test "$(grep -c ',ok,' "$TMP/out1/summary.csv")" -eq 1
check "summary: one error row" test "$(grep -c '^broken,.*,error,' "$TMP/out1/summary.csv")" -eq 1
check "the error is on stderr with the file name" grep -q 'broken.csv' "$TMP/err1"
check "the samples file has a header and 1000 rows" test "$(wc -l < "$TMP/out1/good.csv")" -eq 1001
check "the JSON curve is periodic and cubic" grep -q '"periodic": *true' "$TMP/out1/good.json"
check "no temporary file left behind" test -z "$(find "$TMP/out1" -name '*.tmp*')"

# -j 2 gives the same files as -j 1 (timing.csv holds the only run-dependent numbers)
cp "$SRC/tests/data/demo/bracket.csv" "$SRC/tests/data/demo/airfoil.csv" "$TMP/in/"
"$BSFIT" reconstruct "$TMP/in" -o "$TMP/j1" -j 1 -q 2> /dev/null
"$BSFIT" reconstruct "$TMP/in" -o "$TMP/j2" -j 2 -q 2> /dev/null
rc=$?
check "-j 2: exit code 1 (one broken input)" test "$rc" -eq 1
check "-j 2 output is byte-identical to -j 1" diff -r -x timing.csv "$TMP/j1" "$TMP/j2"
check "-j 2 wrote every section" test "$(ls "$TMP/j2"/*.json | grep -vc summary)" -eq 3

# no INPUT: the demo set; strategies and formats (IGES when the binding writes it)
if "$BSFIT" -e 'local bs = require "bsfit"
  local C = bs.curve.new{degree = 1, control_points = {{0, 0}, {1, 1}}}
  assert(C:write(arg[1] .. "/probe.iges"))' "$TMP" 2> /dev/null; then FMT=json,iges; else FMT=json; fi
mkdir -p "$TMP/demo-in"
cp "$SRC/tests/data/demo/cam.csv" "$SRC/tests/data/demo/knob_weighted.csv" "$TMP/demo-in/"
BSFIT_DEMO_DIR="$TMP/demo-in" "$BSFIT" reconstruct -o "$TMP/demo" --strategy carvalho \
  --format "$FMT" -q 2> /dev/null
check "demo set (BSFIT_DEMO_DIR) with carvalho: exit code 0" test $? -eq 0
check "demo set: both sections in the summary" test "$(tail -n +2 "$TMP/demo/summary.csv" | wc -l)" -eq 2
check "--format $FMT: no SVG" test ! -e "$TMP/demo/cam.svg"
if [ "$FMT" = json,iges ]; then check "--format json,iges: IGES written" test -s "$TMP/demo/cam.iges"
else echo "# skipped: this build's Curve:write has no IGES"; fi

# usage errors exit with 2
"$BSFIT" reconstruct --bogus 2> /dev/null; check "unknown option: exit code 2" test $? -eq 2
"$BSFIT" reconstruct --strategy carvalho --tol 0.1 2> /dev/null; check "--tol with carvalho: exit 2" test $? -eq 2
"$BSFIT" reconstruct --count zero 2> /dev/null; check "--count zero: exit 2" test $? -eq 2
"$BSFIT" reconstruct --help > "$TMP/help"; check "--help prints the usage" grep -q 'usage: bsfit reconstruct' "$TMP/help"

echo "$pass passed, $fail failed"
test "$fail" -eq 0
