#!/usr/bin/env bash
# fuzz.sh: run one libFuzzer target of tests/fuzz (clang, ASan + UBSan).
#   scripts/fuzz.sh TARGET SECONDS   fuzz TARGET (points, json, curve, fit, filter, engine)
#                                    for SECONDS; new inputs go to build-fuzz/corpus/TARGET,
#                                    the seeds of tests/fuzz/corpus/TARGET are read too;
#                                    a crash input is copied to tests/fuzz/regressions/TARGET/
#   scripts/fuzz.sh --replay TARGET  run TARGET once on every seed and regression input
#   scripts/fuzz.sh --list           the targets
# Builds build-fuzz/ first when needed (CC=clang, -DBSFIT_FUZZ=ON). Exit status 0 when
# nothing was found, 1 when the target crashed (its input kept), 2 on a usage error.
set -euo pipefail
cd "$(dirname "$0")/.."
build=${BSFIT_FUZZ_BUILD:-build-fuzz}
targets=$(cd tests/fuzz && ls fuzz_*.c | sed 's/^fuzz_//; s/\.c$//')

usage() { sed -n '2,10p' "$0" | sed 's/^# \{0,1\}//' >&2; exit 2; }
[ $# -ge 1 ] || usage
if [ "$1" = "--list" ]; then echo "$targets"; exit 0; fi
replay=0
if [ "$1" = "--replay" ]; then replay=1; shift; fi
target=${1:-}
if ! echo "$targets" | grep -qx -- "$target"; then
  echo "fuzz.sh: unknown target '$target' ($(echo $targets))" >&2
  exit 2
fi

if [ ! -f "$build/CMakeCache.txt" ]; then
  CC=clang cmake -S . -B "$build" -DCMAKE_BUILD_TYPE=RelWithDebInfo -DBSFIT_FUZZ=ON \
    -DBSFIT_TESTS=OFF -DBSFIT_BENCH=OFF >/dev/null
fi
cmake --build "$build" -j 2 --target "fuzz_$target" >/dev/null
bin="$build/fuzz_$target"
seeds="tests/fuzz/corpus/$target"
regress="tests/fuzz/regressions/$target"
export ASAN_OPTIONS=${ASAN_OPTIONS:-detect_leaks=1:abort_on_error=1}
export UBSAN_OPTIONS=${UBSAN_OPTIONS:-print_stacktrace=1:halt_on_error=1}
mkdir -p "$seeds" "$regress"

if [ $replay -eq 1 ]; then
  files=$(find "$seeds" "$regress" -type f ! -name README | sort)
  [ -n "$files" ] || { echo "fuzz.sh: no inputs for $target" >&2; exit 1; }
  # shellcheck disable=SC2086
  "$bin" -timeout=20 -rss_limit_mb=2048 $files >/dev/null 2>"$build/replay_$target.log" ||
    { tail -40 "$build/replay_$target.log" >&2; exit 1; }
  echo "fuzz.sh: $target: $(echo "$files" | wc -l) inputs replayed, no crash"
  exit 0
fi

secs=${2:?usage: fuzz.sh TARGET SECONDS}
work="$build/corpus/$target"
art="$build/artifacts/$target/"
mkdir -p "$work" "$art"
status=0
# FUZZ_SEED and FUZZ_RUNS make a run repeatable (the same inputs on every machine: what CI
# uses, so a green run stays green); without them libFuzzer explores for SECONDS.
repeat=()
[ -n "${FUZZ_SEED:-}" ] && repeat+=(-seed="$FUZZ_SEED")
[ -n "${FUZZ_RUNS:-}" ] && repeat+=(-runs="$FUZZ_RUNS")
"$bin" "$work" "$seeds" -max_total_time="$secs" -timeout=20 -rss_limit_mb=2048 \
  -max_len="${FUZZ_MAX_LEN:-8192}" -artifact_prefix="$art" -print_final_stats=1 \
  "${repeat[@]}" >"$build/fuzz_$target.log" 2>&1 || status=1
# crash-*, leak-*, timeout-*, oom-*: kept as regressions. slow-unit-* (an input slower than
# 10 s under the sanitizers, usually a large but bounded computation) is not a failure:
# left in $art and listed, for a look.
find "$art" -type f ! -name 'slow-unit-*' -exec mv -n {} "$regress/" \;
find "$art" -type f -name 'slow-unit-*' -exec echo "fuzz.sh: $target: slow input (not a failure): {}" \;
grep -E "^(stat::number_of_executed_units|stat::peak_rss_mb)" "$build/fuzz_$target.log" || true
if [ $status -ne 0 ]; then
  grep -E "ERROR|CONTRACT|SUMMARY|#[0-9]+ in " "$build/fuzz_$target.log" | head -30 >&2
  echo "fuzz.sh: $target crashed; input(s) copied to $regress/ (log: $build/fuzz_$target.log)" >&2
  exit 1
fi
echo "fuzz.sh: $target: ${FUZZ_RUNS:+$FUZZ_RUNS inputs (seed ${FUZZ_SEED:-random}), }at most $secs s, nothing found"
