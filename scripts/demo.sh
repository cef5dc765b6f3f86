#!/usr/bin/env bash
# demo.sh: install what is missing, build, and run the main job: batch
# reconstruction of the demo sections shipped in tests/data/demo, writing JSON,
# SVG, CSV and a summary to out/demo (override with -o DIR; other arguments go
# to `bsfit reconstruct`).
set -euo pipefail
cd "$(dirname "$0")/.."
jobs=$(nproc 2>/dev/null || echo 2)

bash scripts/deps.sh
cmake -S . -B build -DCMAKE_BUILD_TYPE=Release -DBSFIT_TESTS=OFF >/dev/null
cmake --build build -j "$jobs" --target bsfit bsfit_module

out=out/demo
args=()
while [ $# -gt 0 ]; do
  case "$1" in
    -o) out="$2"; shift 2 ;;
    *) args+=("$1"); shift ;;
  esac
done
./build/bsfit reconstruct -o "$out" ${args[@]+"${args[@]}"}
echo "demo: results in $out (open $out/index.html or the SVG files)"
