#!/usr/bin/env bash
# bench.sh: build in Release and run every benchmark (tests/bench/bench_*.c programs and
# tests/bench/bench_*.lua scripts). The numbers in the README come from this command.
set -euo pipefail
cd "$(dirname "$0")/.."
jobs=$(nproc 2>/dev/null || echo 2)

bash scripts/deps.sh
cmake -S . -B build -DCMAKE_BUILD_TYPE=Release -DBSFIT_BENCH=ON >/dev/null
cmake --build build -j "$jobs"
for b in build/bench_*; do
  [ -x "$b" ] || continue
  echo "== $(basename "$b")"
  "$b"
done
for s in tests/bench/bench_*.lua; do
  [ -f "$s" ] || continue
  echo "== $(basename "$s")"
  ./build/bsfit "$s"
done
