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

# no INPUT: the demo set; strategies and formats (IGES is part of every build: a
# binding that cannot write it fails here, it is not skipped)
FMT=json,iges
mkdir -p "$TMP/demo-in"
cp "$SRC/tests/data/demo/cam.csv" "$SRC/tests/data/demo/knob_weighted.csv" "$TMP/demo-in/"
BSFIT_DEMO_DIR="$TMP/demo-in" "$BSFIT" reconstruct -o "$TMP/demo" --strategy carvalho \
  --format "$FMT" -q 2> /dev/null
check "demo set (BSFIT_DEMO_DIR) with carvalho: exit code 0" test $? -eq 0
check "demo set: both sections in the summary" test "$(tail -n +2 "$TMP/demo/summary.csv" | wc -l)" -eq 2
check "--format $FMT: no SVG" test ! -e "$TMP/demo/cam.svg"
check "--format json,iges: IGES written" test -s "$TMP/demo/cam.iges"
check "--format json,iges: the IGES file is a curve (entity 126)" grep -q '^ *126,' "$TMP/demo/cam.iges"

# a strategy that exists but fails to load is reported as itself, not as unknown
mkdir -p "$TMP/luadir"
cp -r "$SRC/lua/bsfit" "$TMP/luadir/"
printf 'local x = = 1\n' > "$TMP/luadir/bsfit/strategy/broken.lua"
printf 'require "bsfit.no_such_helper"\nreturn {run = function() end}\n' \
  > "$TMP/luadir/bsfit/strategy/needy.lua"
BSFIT_PATH="$TMP/luadir" "$BSFIT" reconstruct "$TMP/in/good.csv" -o "$TMP/sb" --strategy broken \
  2> "$TMP/err-broken"
check "strategy with a syntax error: exit code 2" test $? -eq 2
check "strategy with a syntax error: the syntax error, not 'unknown strategy'" \
  sh -c "grep -q 'broken.lua:1:' '$TMP/err-broken' && ! grep -q 'unknown strategy' '$TMP/err-broken'"
BSFIT_PATH="$TMP/luadir" "$BSFIT" reconstruct "$TMP/in/good.csv" -o "$TMP/sn" --strategy needy \
  2> "$TMP/err-needy"
check "strategy requiring a missing module: that module is named" \
  sh -c "grep -q \"module 'bsfit.no_such_helper' not found\" '$TMP/err-needy' &&
         ! grep -q 'unknown strategy' '$TMP/err-needy'"
BSFIT_PATH="$TMP/luadir" "$BSFIT" reconstruct "$TMP/in/good.csv" -o "$TMP/sx" --strategy nosuch \
  2> "$TMP/err-nosuch"
check "a strategy that does not exist: unknown strategy" grep -q "unknown strategy 'nosuch'" \
  "$TMP/err-nosuch"

# usage errors exit with 2
"$BSFIT" reconstruct --bogus 2> /dev/null; check "unknown option: exit code 2" test $? -eq 2
"$BSFIT" reconstruct --strategy carvalho --tol 0.1 2> /dev/null; check "--tol with carvalho: exit 2" test $? -eq 2
"$BSFIT" reconstruct --count zero 2> /dev/null; check "--count zero: exit 2" test $? -eq 2
"$BSFIT" reconstruct --help > "$TMP/help"; check "--help prints the usage" grep -q 'usage: bsfit reconstruct' "$TMP/help"

echo "$pass passed, $fail failed"
test "$fail" -eq 0
