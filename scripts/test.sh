#!/usr/bin/env bash
# test.sh: install what is missing, build, and run every test twice:
# a normal build (build/) and an AddressSanitizer + UBSan build (build-asan/).
set -euo pipefail
cd "$(dirname "$0")/.."
jobs=$(nproc 2>/dev/null || echo 2)

bash scripts/deps.sh --test

echo "== normal build (build/)"
cmake -S . -B build -DCMAKE_BUILD_TYPE=Release -DBSFIT_TESTS=ON -DBSFIT_WERROR=ON >/dev/null
cmake --build build -j "$jobs"
(cd build && ctest --output-on-failure -j "$jobs")

# -O1, as the sanitizers' own documentation advises: every check stays, and the suite runs
# in half the time of -O0 (CI's budget is 15 minutes)
echo "== sanitizer build (build-asan/: AddressSanitizer + UBSan, -O1)"
cmake -S . -B build-asan -DCMAKE_BUILD_TYPE=Debug -DCMAKE_C_FLAGS_DEBUG="-g -O1" -DBSFIT_SANITIZE=ON -DBSFIT_TESTS=ON -DBSFIT_WERROR=ON -DBSFIT_BENCH=OFF >/dev/null
cmake --build build-asan -j "$jobs"
(cd build-asan && ASAN_OPTIONS=detect_leaks=1:abort_on_error=1 UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1 \
  ctest --output-on-failure -j "$jobs")

# {====================================================================
# Fuzz smoke (tests/fuzz, scripts/fuzz.sh): builds the libFuzzer targets in build-fuzz/
# (clang, ASan + UBSan), replays every seed and regression input of each target, then
# fuzzes each from its corpus for a fixed number of inputs with a fixed seed: the same
# inputs on every machine, so CI is repeatable (scripts/fuzz.sh TARGET SECONDS explores
# freely). About 2 minutes with the build.
echo "== fuzz smoke (build-fuzz/: libFuzzer + ASan + UBSan)"
for t in $(bash scripts/fuzz.sh --list); do
  bash scripts/fuzz.sh --replay "$t"
  FUZZ_MAX_LEN=4096 FUZZ_SEED=1 FUZZ_RUNS="${BSFIT_FUZZ_SMOKE_RUNS:-1500}" \
    bash scripts/fuzz.sh "$t" 120
done
# }====================================================================
