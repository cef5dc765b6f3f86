#!/usr/bin/env bash
# test_install.sh BSFIT SRC: `cmake --install` into a temporary prefix P, then, with only
# what is under P:
#  (a) a C host built with `pkg-config --cflags --libs bsfit-engine` (and one on the core
#      alone, `bsfit`) fits an ellipse through the installed engine and strategies;
#  (b) the same host built by a five-line CMake project: find_package(bsfit), bsfit::engine;
#  (c) Debian's lua5.4, its module paths being its /usr/local defaults moved to P, requires
#      bsfit and bsfit.strategy.auto from P and fits;
#  (d) the installed bsfit reads the installed modules and `bsfit reconstruct` without
#      input runs the installed demo set;
# plus the man page, LICENSE, the .pc files and the CMake package files are installed.
set -u
BSFIT=$(cd "$(dirname "$1")" && pwd)/$(basename "$1")
SRC=$(cd "$2" && pwd)
BUILD=$(dirname "$BSFIT")
TMP=$(mktemp -d)
trap 'rm -rf "$TMP"' EXIT
pass=0
fail=0
check() { # name, then a command that must succeed
  local name=$1
  shift
  if "$@"; then echo "ok - $name"; pass=$((pass + 1)); else echo "not ok - $name"; fail=$((fail + 1)); fi
}
P=$TMP/p
if ! cmake --install "$BUILD" --prefix "$P" >"$TMP/install.log" 2>&1; then
  cat "$TMP/install.log"
  echo "0 passed, 1 failed"
  exit 1
fi
cd "$TMP" || exit 1
unset BSFIT_PATH BSFIT_DEMO_DIR LUA_PATH LUA_CPATH LUA_PATH_5_4 LUA_CPATH_5_4 PKG_CONFIG_PATH

# A sanitizer build installs instrumented libraries: hosts link the sanitizer runtimes and
# stock lua5.4 gets them preloaded (it is not instrumented itself).
SAN_FLAGS=""
SAN_PRELOAD=""
if grep -q '^BSFIT_SANITIZE:BOOL=ON' "$BUILD/CMakeCache.txt"; then
  SAN_FLAGS="-fsanitize=address,undefined"
  SAN_PRELOAD="$(cc -print-file-name=libasan.so) $(cc -print-file-name=libubsan.so)"
  export ASAN_OPTIONS="${ASAN_OPTIONS:+$ASAN_OPTIONS:}detect_leaks=0"
fi
LIBDIR=$(dirname "$(find "$P" -name 'libbsfit_engine.so' | head -1)")
check "libbsfit and libbsfit_engine, shared and static, in P/lib ($LIBDIR)" \
  test -f "$LIBDIR/libbsfit.so" -a -f "$LIBDIR/libbsfit.a" -a -f "$LIBDIR/libbsfit_engine.so" \
  -a -f "$LIBDIR/libbsfit_engine.a"
check "the engine library provides bsfit_engine_new" \
  sh -c "nm -D --defined-only '$LIBDIR/libbsfit_engine.so' | grep -q ' T bsfit_engine_new\$'"
check "the core library does not depend on Lua" \
  sh -c "! ldd '$LIBDIR/libbsfit.so' | grep -q liblua"
for f in include/bsfit.h include/bsfit_engine.h include/bsfit_lua.h share/man/man1/bsfit.1 \
         share/doc/bsfit/LICENSE lib/cmake/bsfit/bsfitConfig.cmake \
         lib/cmake/bsfit/bsfitConfigVersion.cmake; do
  check "installed: $f" test -f "$P/$f"
done
check "man finds the installed page" sh -c "MANPATH='$P/share/man' man -w bsfit | grep -q '^$P/'"

# ---------------------------------------------------------------------------
# The host: the core's own evaluation and an engine fit of an ellipse (semi-axes 3 and 1).
cat >"$TMP/host.c" <<'HOST'
#include "bsfit.h"
#include "bsfit_engine.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

#define M 60

int main(void) {
  double xy[2 * M], q[2], worst = 0;
  bsfit_engine_opts eo;
  bsfit_engine_report rep;
  bsfit_curve c;
  bsfit_engine *e;
  int i;
  for (i = 0; i < M; i++) {
    double a = 2 * 3.14159265358979323846 * i / M;
    xy[2 * i] = 3 * cos(a);
    xy[2 * i + 1] = sin(a);
  }
  memset(&eo, 0, sizeof eo);
  if ((e = bsfit_engine_new(&eo)) == NULL) return 1;
  bsfit_curve_init(&c);
  if (bsfit_engine_fit(e, "bsfit.strategy.auto", xy, M, 2, NULL, NULL, &c, &rep) != BSFIT_OK) {
    fprintf(stderr, "host: %s\n", bsfit_engine_errmsg(e));
    return 1;
  }
  for (i = 0; i < 100; i++) { /* the curve stays on the ellipse: |(x/3, y)| = 1 */
    double a, b;
    bsfit_curve_domain(&c, &a, &b);
    if (bsfit_curve_eval(&c, a + (b - a) * i / 100, q, NULL) != BSFIT_OK) return 1;
    worst = fmax(worst, fabs(hypot(q[0] / 3, q[1]) - 1));
  }
  printf("%s %d %.3g %s\n", bsfit_version(), worst < 1e-3, rep.max, bsfit_engine_luadir(e));
  bsfit_curve_free(&c);
  bsfit_engine_free(e);
  return 0;
}
HOST
cat >"$TMP/core.c" <<'CORE'
#include "bsfit.h"

#include <math.h>
#include <stdio.h>

int main(void) { /* a quarter circle as a rational quadratic: its middle is on the circle */
  double ctrl[] = {1, 0, 1, 1, 0, 1}, w[] = {1, sqrt(0.5), 1}, q[2];
  bsfit_curve c;
  bsfit_curve_init(&c);
  if (bsfit_curve_new(&c, 2, 2, 3, NULL, ctrl, w, 0, NULL, NULL) != BSFIT_OK) return 1;
  if (bsfit_curve_eval(&c, 0.5, q, NULL) != BSFIT_OK) return 1;
  bsfit_curve_free(&c);
  printf("%d\n", fabs(hypot(q[0], q[1]) - 1) < 1e-15);
  return 0;
}
CORE
expect="$(cat "$SRC/CMakeLists.txt" | sed -n 's/^project(bsfit VERSION \([0-9.]*\).*/\1/p') 1"
luadir_ok() { # the output of host: version, ellipse ok, max, the engine's Lua directory
  local out=$1
  set -- $out
  [ "$1 $2" = "$expect" ] && [ "$(cd "$4" 2>/dev/null && pwd -P)" = "$(cd "$P/share/lua/5.4" && pwd -P)" ]
}
export PKG_CONFIG_PATH=$LIBDIR/pkgconfig
check "pkg-config knows bsfit and bsfit-engine" pkg-config --exists bsfit bsfit-engine
# shellcheck disable=SC2046
cc $SAN_FLAGS -o "$TMP/core_pc" "$TMP/core.c" $(pkg-config --cflags --libs bsfit) -lm \
   -Wl,-rpath,"$LIBDIR" 2>"$TMP/cc.log"
check "(a) a core-only host built with pkg-config bsfit runs ($(head -c 300 "$TMP/cc.log"))" \
  test "$("$TMP/core_pc" 2>&1)" = "1"
# shellcheck disable=SC2046
cc $SAN_FLAGS -o "$TMP/host_pc" "$TMP/host.c" $(pkg-config --cflags --libs bsfit-engine) -lm \
   -Wl,-rpath,"$LIBDIR" 2>"$TMP/cc.log"
out=$("$TMP/host_pc" 2>&1)
check "(a) a host built with pkg-config bsfit-engine fits with the installed strategies ($out)" \
  luadir_ok "$out"
check "(a) it runs on the installed libraries" \
  sh -c "ldd '$TMP/host_pc' | grep -q '$LIBDIR/libbsfit_engine.so'"

mkdir -p "$TMP/cm"
cp "$TMP/host.c" "$TMP/cm/host.c"
cat >"$TMP/cm/CMakeLists.txt" <<'CM'
cmake_minimum_required(VERSION 3.16)
project(host C)
find_package(bsfit 0.1 REQUIRED)
add_executable(host host.c)
target_link_libraries(host PRIVATE bsfit::engine m)
CM
cmake -S "$TMP/cm" -B "$TMP/cm/build" -DCMAKE_PREFIX_PATH="$P" -DCMAKE_C_FLAGS="$SAN_FLAGS" \
  -DCMAKE_EXE_LINKER_FLAGS="$SAN_FLAGS" >"$TMP/cm.log" 2>&1 &&
  cmake --build "$TMP/cm/build" >>"$TMP/cm.log" 2>&1
out=$("$TMP/cm/build/host" 2>&1)
check "(b) a host built with find_package(bsfit) and bsfit::engine fits ($out)" luadir_ok "$out"
[ -x "$TMP/cm/build/host" ] || tail -20 "$TMP/cm.log"

# ---------------------------------------------------------------------------
# (c) stock lua5.4 with its own /usr/local defaults moved under P and nothing else
lpath=$(lua5.4 -E -e 'print(package.path)')
lcpath=$(lua5.4 -E -e 'print(package.cpath)')
under_p() { # keeps the /usr/local/ entries of a search path, moved to P
  tr ';' '\n' <<<"$1" | grep '^/usr/local/' | grep -v loadall | sed "s|^/usr/local/|$P/|" |
    paste -sd ';'
}
fit='local bs = require "bsfit"
local auto = require "bsfit.strategy.auto"
local P = bs.points.new(40, 2)
for k = 1, 40 do local a = 2 * math.pi * k / 40; P:set(k, 2 * math.cos(a), math.sin(a)) end
local C, rep = auto.run(P)
assert(C and rep.max < 1e-2, "fit")
print(package.searchpath("bsfit.strategy.auto", package.path))'
out=$(LD_PRELOAD="$SAN_PRELOAD" LUA_PATH="$(under_p "$lpath")" LUA_CPATH="$(under_p "$lcpath")" \
      lua5.4 -e "$fit" 2>&1)
check "(c) lua5.4 on Debian's /usr/local paths moved to P requires bsfit and auto ($out)" \
  test "$out" = "$P/share/lua/5.4/bsfit/strategy/auto.lua"

# ---------------------------------------------------------------------------
# (d) the installed program
strategy_path='print(package.searchpath("bsfit.strategy.periodic", package.path))'
got=$("$P/bin/bsfit" -e "$strategy_path" 2>&1)
check "(d) installed bsfit reads the installed modules ($got)" \
  test "$got" = "$P/bin/../share/lua/5.4/bsfit/strategy/periodic.lua"
got=$("$BSFIT" -e "$strategy_path" 2>&1)
check "the build tree's bsfit reads the source tree ($got)" \
  test "$got" = "$SRC/lua/bsfit/strategy/periodic.lua"
"$P/bin/bsfit" reconstruct -q -o "$TMP/demo" >"$TMP/demo.log" 2>&1
check "(d) installed bsfit reconstruct without input: exit 0 ($(head -c 300 "$TMP/demo.log"))" \
  test $? -eq 0
want=$(cd "$P/share/bsfit/demo" && ls | sed 's/\.[^.]*$//' | sort | paste -sd ' ')
got=$(tail -n +2 "$TMP/demo/summary.csv" 2>/dev/null | cut -d, -f1 | sort | paste -sd ' ')
check "(d) it fitted the installed demo set ($got)" test -n "$want" -a "$got" = "$want"
ok_rows=$(tail -n +2 "$TMP/demo/summary.csv" 2>/dev/null | awk -F, '$10 == "ok"' | wc -l)
check "(d) every demo section ok ($ok_rows)" test "$ok_rows" -eq "$(wc -w <<<"$want")"
inputs_in() { # every input of the summary is a file of directory $1
  local f
  for f in $(tail -n +2 "$TMP/demo/summary.csv" | cut -d, -f2); do
    [ "$(cd "$(dirname "$f")" && pwd -P)" = "$(cd "$1" && pwd -P)" ] || return 1
  done
}
check "(d) its inputs are the installed files" inputs_in "$P/share/bsfit/demo"
echo "$pass passed, $fail failed"
[ "$fail" -eq 0 ]
