#!/usr/bin/env bash
# test_install.sh BSFIT SRC: `cmake --install` into a temporary prefix; the installed bsfit
# reads the installed Lua modules (not the source tree it was built from), runs a strategy,
# and Debian's lua5.4 finds the installed module with the installed strategies.
set -u
BSFIT=$1
SRC=$2
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
if ! cmake --install "$BUILD" --prefix "$TMP/p" >"$TMP/install.log" 2>&1; then
  cat "$TMP/install.log"
  echo "0 passed, 1 failed"
  exit 1
fi
strategy_path='print(package.searchpath("bsfit.strategy.periodic", package.path))'
fit='local bs = require "bsfit"
local P = bs.points.new(40, 2)
for k = 1, 40 do local a = 2 * math.pi * k / 40; P:set(k, 2 * math.cos(a), math.sin(a)) end
local C, rep = require("bsfit.strategy.periodic").run(P)
assert(C and rep.max < 1e-2, "fit")
print("fitted")'
got=$(env -u BSFIT_PATH "$TMP/p/bin/bsfit" -e "$strategy_path" 2>&1)
check "installed bsfit reads the installed modules ($got)" \
  test "$got" = "$TMP/p/bin/../share/bsfit/lua/bsfit/strategy/periodic.lua"
check "installed bsfit runs a strategy" \
  test "$(env -u BSFIT_PATH "$TMP/p/bin/bsfit" -e "$fit" 2>&1)" = "fitted"
got=$("$BSFIT" -e "$strategy_path" 2>&1)
check "the build tree's bsfit reads the source tree ($got)" \
  test "$got" = "$SRC/lua/bsfit/strategy/periodic.lua"
# (a sanitizer build's module cannot load into an uninstrumented lua5.4)
if [ -f "$TMP/p/lib/lua/5.4/bsfit.so" ] && command -v lua5.4 >/dev/null &&
   ! ldd "$TMP/p/lib/lua/5.4/bsfit.so" | grep -q -E 'libasan|libubsan'; then
  out=$(LUA_CPATH="$TMP/p/lib/lua/5.4/?.so" LUA_PATH="$TMP/p/share/bsfit/lua/?.lua;;" \
        lua5.4 -e "$fit" 2>&1)
  check "lua5.4 requires the installed module ($out)" test "$out" = "fitted"
fi
echo "$pass passed, $fail failed"
[ "$fail" -eq 0 ]
