#!/usr/bin/env bash
# test_luarocks.sh BSFIT SRC: Debian's luarocks builds the rockspec of a copy of the
# checkout (`luarocks --lua-version 5.4 make`, build type cmake) into a temporary tree, and
# stock lua5.4, with only that tree's paths (`luarocks path`), requires bsfit and a strategy
# from it and fits an ellipse.
set -u
SRC=$(cd "$2" && pwd)
TMP=$(mktemp -d)
trap 'rm -rf "$TMP"' EXIT
pass=0
fail=0
check() { # name, then a command that must succeed
  local name=$1
  shift
  if "$@"; then echo "ok - $name"; pass=$((pass + 1)); else echo "not ok - $name"; fail=$((fail + 1)); fi
}
rockspecs=("$SRC"/bsfit-*.rockspec)
check "one rockspec at the top of the tree (${rockspecs[*]##*/})" test ${#rockspecs[@]} -eq 1 -a -f "${rockspecs[0]}"
version=$(sed -n 's/^project(bsfit VERSION \([0-9.]*\).*/\1/p' "$SRC/CMakeLists.txt")
check "the rockspec's version is the project's ($version)" \
  grep -q "^version = \"$version-[0-9]*\"" "${rockspecs[0]}"

# a clean copy of the checkout: luarocks builds in the source directory (build.luarocks)
mkdir -p "$TMP/src" "$TMP/home"
tar -C "$SRC" --exclude='./build*' --exclude='./out' --exclude='./.git' -cf - . | tar -C "$TMP/src" -xf -
export HOME=$TMP/home # luarocks's cache and config stay in the test's directory
unset LUA_PATH LUA_CPATH LUA_PATH_5_4 LUA_CPATH_5_4 BSFIT_PATH
(cd "$TMP/src" && nice luarocks --lua-version 5.4 make --tree "$TMP/tree" "${rockspecs[0]##*/}") \
  >"$TMP/make.log" 2>&1
status=$?
check "luarocks make into a temporary tree: exit 0" test $status -eq 0
[ $status -eq 0 ] || tail -30 "$TMP/make.log"
check "luarocks lists bsfit $version in the tree" \
  sh -c "luarocks --lua-version 5.4 --tree '$TMP/tree' list --porcelain | grep -q '^bsfit	$version-'"

eval "$(luarocks --lua-version 5.4 --tree "$TMP/tree" path --no-bin)"
fit='local bs = require "bsfit"
local auto = require "bsfit.strategy.auto"
local P = bs.points.new(60, 2)
for k = 1, 60 do local a = 2 * math.pi * k / 60; P:set(k, 3 * math.cos(a), math.sin(a)) end
local C, rep = auto.run(P)
local a, b = C:domain()
local worst = 0
for i = 0, 99 do
  local x, y = C:eval(a + (b - a) * i / 100)
  worst = math.max(worst, math.abs(math.sqrt((x / 3) ^ 2 + y ^ 2) - 1))
end
print(bs.version, worst < 1e-3, package.searchpath("bsfit", package.cpath),
      package.searchpath("bsfit.strategy.auto", package.path))'
out=$(cd "$TMP" && lua5.4 -e "$fit" 2>&1)
want="$version	true	$TMP/tree/lib/lua/5.4/bsfit.so	$TMP/tree/share/lua/5.4/bsfit/strategy/auto.lua"
check "lua5.4 requires bsfit and bsfit.strategy.auto from the tree and fits ($out)" \
  test "$out" = "$want"
echo "$pass passed, $fail failed"
[ "$fail" -eq 0 ]
