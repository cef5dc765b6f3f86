#!/bin/bash
# test_batch.sh: what `bsfit reconstruct` says while a batch runs, and sharding.
# - stderr not a terminal: no progress line (no "\r"), each failure on one line with its
#   path once, no Lua position or traceback, then the final line;
# - on a terminal (script(1) gives one): the progress line for -j 1 and -j 2, the
#   failures before the last progress update, nothing but failures with -q;
# - --debug: the traceback; a strategy's internal error reads as one;
# - --shard I/N on GNU parallel (localhost, two shards) + bsfit merge: the merged
#   summary.csv, summary.json and index.html equal a single run's byte for byte, every
#   per-section file is there; the shards partition the inputs.
# usage: bash test_batch.sh <path-to-bsfit> <source-dir>
BSFIT=${1:?usage: test_batch.sh BSFIT SOURCE_DIR}
SRC=${2:?usage: test_batch.sh BSFIT SOURCE_DIR}
TMP=$(mktemp -d "${TMPDIR:-/tmp}/bsfit-batch.XXXXXX")
trap 'rm -rf "$TMP"' EXIT
pass=0 fail=0
check() { # check NAME CONDITION-COMMAND...
  local name=$1; shift
  if "$@"; then pass=$((pass + 1)); echo "ok - $name"; else fail=$((fail + 1)); echo "not ok - $name"; fi
}
for tool in parallel script; do
  command -v $tool > /dev/null || { echo "not ok - $tool missing (scripts/deps.sh --test)"; exit 1; }
done

mkdir -p "$TMP/in"
cp "$SRC"/tests/data/demo/*.csv "$TMP/in/"
printf 'x,y\n1,2\nthree,4\n5,6\n' > "$TMP/in/broken.csv"
printf 'x,y\n0,0\n1,1\n' > "$TMP/in/tiny.csv"
# 5 points, 3 distinct: too few for degree 3 (5 distinct points now fit: one datum per span)
printf 'x,y\n0,0\n1,0\n1,0\n0,1\n0,1\n' > "$TMP/in/sq.csv"
cat > "$TMP/buggy.lua" << 'EOF'
return { run = function(P, o) local t = nil; return t.curve end }
EOF
N=$(ls "$TMP/in" | wc -l)

# -- stderr not a terminal
"$BSFIT" reconstruct "$TMP/in" -o "$TMP/o1" 2> "$TMP/e1"
check "exit 1 when a section fails" test $? -eq 1
check "no progress line when stderr is not a terminal" test "$(tr -cd '\r' < "$TMP/e1" | wc -c)" -eq 0
check "the broken file: one line, its path once" \
  test "$(grep -c 'broken.csv' "$TMP/e1")" -eq 1 -a "$(grep 'broken.csv' "$TMP/e1" | grep -o 'broken.csv' | wc -l)" -eq 1
check "the broken file's line names the line and the problem" grep -q "broken.csv:3: not a number: 'three'" "$TMP/e1"
check "the too-small file: one line, its path once" \
  test "$(grep 'tiny.csv' "$TMP/e1" | grep -o 'tiny.csv' | wc -l)" -eq 1
check "no Lua positions or tracebacks" bash -c "! grep -qE '\\.lua:[0-9]+:|stack traceback' '$TMP/e1'"
check "the 5-point file: the reason, not the Lua function's argument" \
  bash -c "grep -qE 'sq.csv: (auto: )?(knots failed: )?5 points leave too few knot spans for degree 3( \(ETOOFEW\))?\$' '$TMP/e1' && ! grep -q 'bad argument' '$TMP/e1'"
check "final line" grep -qE "^bsfit reconstruct: $N sections: $((N - 3)) ok, 3 failed, [0-9]+ with warnings, in [0-9.]+ s; outputs in $TMP/o1\$" "$TMP/e1"
check "failures come before the final line" test "$(grep -n 'broken.csv' "$TMP/e1" | cut -d: -f1)" -lt "$(grep -n 'sections:' "$TMP/e1" | cut -d: -f1)"
"$BSFIT" reconstruct "$TMP/in" -o "$TMP/oq" -q 2> "$TMP/eq"
check "-q: only the failures" test "$(wc -l < "$TMP/eq")" -eq 3

# -- an internal error in a strategy: in the user's terms, traceback only with --debug
"$BSFIT" reconstruct "$TMP/in/cam.csv" --strategy "$TMP/buggy.lua" -o "$TMP/ob" 2> "$TMP/eb"
check "internal error: one line, says so, no position" \
  bash -c "test \$(wc -l < '$TMP/eb') -eq 2 && grep -q 'cam.csv: internal error (attempt to index a nil value' '$TMP/eb' && ! grep -q 'buggy.lua:' '$TMP/eb'"
"$BSFIT" reconstruct "$TMP/in/cam.csv" --strategy "$TMP/buggy.lua" -o "$TMP/ob" --debug 2> "$TMP/ebd"
check "--debug: the traceback and the position" bash -c "grep -q 'stack traceback' '$TMP/ebd' && grep -q 'buggy.lua:1:' '$TMP/ebd'"

# -- a strategy's warnings: one line each as the section ends, the summary, the final count
cat > "$TMP/warns.lua" << 'EOF2'
local auto = require "bsfit.strategy.auto"
return { run = function(P, o)
  local C, rep = auto.run(P, o)
  if C and #P > 150 then rep.warnings = { "tol 0.001 not met", "second" } end
  return C, rep
end }
EOF2
"$BSFIT" reconstruct "$TMP/in/cam.csv" "$TMP/in/bracket.csv" "$TMP/in/noisy_blob.csv" -j 2 \
  --strategy "$TMP/warns.lua" -o "$TMP/ow" 2> "$TMP/ew"
check "warnings: one line per section that has them" \
  test "$(grep -c ': warning: tol 0.001 not met; second$' "$TMP/ew")" -eq 2
check "warnings: in the summary" test "$(grep -c ',tol 0.001 not met; second,' "$TMP/ow/summary.csv")" -eq 2
check "warnings: counted in the final line" grep -q '3 sections: 3 ok, 0 failed, 2 with warnings' "$TMP/ew"
check "warnings: on the overview page" grep -q '2 with warnings' "$TMP/ow/index.html"

# -- on a terminal: progress for any -j
for j in 1 2; do
  script -qec "'$BSFIT' reconstruct '$TMP/in' -o '$TMP/t$j' -j $j 2>&1 >/dev/null" /dev/null > "$TMP/tty$j"
  check "-j $j on a terminal: progress line to [$N/$N], rewritten with \\r" \
    bash -c "grep -q '\[$N/$N\] 100%, 3 failed' '$TMP/tty$j' && test \$(tr -cd '\r' < '$TMP/tty$j' | wc -c) -gt $N"
  last=$(grep -ob "\[$N/$N\]" "$TMP/tty$j" | tail -1 | cut -d: -f1)
  broken=$(grep -ob 'broken.csv' "$TMP/tty$j" | head -1 | cut -d: -f1)
  check "-j $j: the failure is reported before the last section ends" test "${broken:-999999}" -lt "${last:-0}"
  if [ "$j" = 1 ]; then # broken.csv is the 3rd input: reported before the 4th section ends
    fourth=$(grep -ob "\[4/$N\]" "$TMP/tty$j" | head -1 | cut -d: -f1)
    check "-j 1: the failure is reported as it happens" test "${broken:-999999}" -lt "${fourth:-0}"
  fi
  check "-j $j: a progress update counts sections/s" grep -q 'sections/s' "$TMP/tty$j"
done
script -qec "'$BSFIT' reconstruct '$TMP/in' -o '$TMP/tq' -j 2 -q 2>&1 >/dev/null" /dev/null > "$TMP/ttyq"
check "-q on a terminal: no progress line" bash -c "! grep -q '%, ' '$TMP/ttyq' && ! grep -q 'sections:' '$TMP/ttyq'"

# -- sharding on GNU parallel (localhost), merged, against a single run
"$BSFIT" reconstruct "$TMP/in" -o "$TMP/single" -q 2> /dev/null
parallel --halt never "$BSFIT" reconstruct "$TMP/in" -o "$TMP/shard{}" -q --shard {}/2 2> /dev/null ::: 0 1
"$BSFIT" merge "$TMP/merged" "$TMP/shard0" "$TMP/shard1" 2> "$TMP/em"
check "merge: exit 0" test $? -eq 0
for f in summary.csv summary.json index.html; do
  check "merged $f equals a single run's byte for byte" cmp -s "$TMP/single/$f" "$TMP/merged/$f"
done
check "merged directory equals the single run (timing.csv aside)" diff -r -x timing.csv "$TMP/single" "$TMP/merged"
names() { tail -n +2 "$1/summary.csv" | cut -d, -f1 | sort; }
check "the shards partition the inputs" \
  bash -c "test \"\$(cat <(tail -n +2 '$TMP/shard0/summary.csv') <(tail -n +2 '$TMP/shard1/summary.csv') | cut -d, -f1 | sort)\" = \"\$(tail -n +2 '$TMP/single/summary.csv' | cut -d, -f1 | sort)\" && test -z \"\$(comm -12 <(tail -n +2 '$TMP/shard0/summary.csv' | cut -d, -f1 | sort) <(tail -n +2 '$TMP/shard1/summary.csv' | cut -d, -f1 | sort))\""
check "shards are balanced" test $(( $(names "$TMP/shard0" | wc -l) - $(names "$TMP/shard1" | wc -l) )) -le 1
cp -r "$TMP/shard0" "$TMP/into0"
"$BSFIT" merge "$TMP/into0" "$TMP/into0" "$TMP/shard1" 2> /dev/null
check "merge into one of the shards: the same result" diff -r -x timing.csv "$TMP/single" "$TMP/into0"
"$BSFIT" reconstruct "$TMP/in" -o "$TMP/x" --shard 2/2 2> /dev/null; check "--shard 2/2: usage error" test $? -eq 2
"$BSFIT" reconstruct "$TMP/in" -o "$TMP/x" --shard 1 2> /dev/null; check "--shard 1: usage error" test $? -eq 2
"$BSFIT" merge "$TMP/m2" "$TMP/shard0" "$TMP/shard0" 2> "$TMP/ed"
check "merge of the same shard twice: refused, says which section" \
  bash -c "test $? -eq 1 && grep -q 'is in both' '$TMP/ed'"
"$BSFIT" merge "$TMP/m3" "$TMP/nonexistent" 2> /dev/null; check "merge of a missing directory: exit 1" test $? -eq 1
"$BSFIT" merge "$TMP/m4" "$TMP/shard1" 2> "$TMP/e4"
check "merge without shard 0: refused, names the missing shard" \
  bash -c "test $? -eq 1 && grep -q 'shard 0/2 is missing' '$TMP/e4'"
"$BSFIT" reconstruct "$TMP/in" -o "$TMP/s3_0" -q --shard 0/3 2> /dev/null
"$BSFIT" merge "$TMP/m5" "$TMP/s3_0" "$TMP/shard1" 2> "$TMP/e5"
check "merge of shards of different jobs: refused" bash -c "test $? -eq 1 && grep -q 'not one job' '$TMP/e5'"
"$BSFIT" merge 2> /dev/null; check "merge without arguments: exit 2" test $? -eq 2

echo "$pass passed, $fail failed"
test "$fail" -eq 0
