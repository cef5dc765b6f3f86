#!/usr/bin/env bash
# test_docs_examples.sh BSFIT SRC: the examples of docs/*.md never rot. Every fenced block
# ```c whose first line is `/* example: NAME */` is compiled against the build tree with
# -std=c11 -Wall -Wextra -Werror and run; every ```lua block whose first line is
# `-- example: NAME` runs under bsfit and under stock lua5.4. Each example checks its own
# result against mathematics and exits non-zero when it is wrong.
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
SAN_FLAGS=""
SAN_PRELOAD=""
if grep -q '^BSFIT_SANITIZE:BOOL=ON' "$BUILD/CMakeCache.txt"; then
  SAN_FLAGS="-fsanitize=address,undefined"
  SAN_PRELOAD="$(cc -print-file-name=libasan.so) $(cc -print-file-name=libubsan.so)"
fi

n=0
for md in "$SRC"/docs/*.md; do
  doc=$(basename "$md" .md)
  mkdir -p "$TMP/$doc"
  awk -v dir="$TMP/$doc" '
    /^```(lua|c) *$/ { lang = substr($0, 4); sub(/ *$/, "", lang); first = 1; out = ""; next }
    /^```/ { if (out != "") close(out); lang = ""; out = ""; next }
    lang != "" && first {
      first = 0
      if (lang == "lua" && match($0, /^-- example: [A-Za-z0-9_]+$/)) out = dir "/" substr($0, 13) ".lua"
      if (lang == "c" && match($0, /^\/\* example: [A-Za-z0-9_]+ \*\/$/)) {
        name = $0; sub(/^\/\* example: /, "", name); sub(/ \*\/$/, "", name); out = dir "/" name ".c"
      }
    }
    lang != "" && out != "" { print > out }' "$md"
  for f in "$TMP/$doc"/*.c; do
    [ -f "$f" ] || continue
    n=$((n + 1))
    ex="$doc.md: ${f##*/}"
    # shellcheck disable=SC2046
    if cc -std=c11 -D_DEFAULT_SOURCE -Wall -Wextra -Werror $SAN_FLAGS -I"$SRC/src" -o "${f%.c}" \
         "$f" "$BUILD/libbsfit_lua.a" "$BUILD/libbsfit.a" $(pkg-config --libs lua5.4 lapacke) \
         -lm -lpthread -ldl 2>"$TMP/cc.log"; then
      check "$ex compiles with -Wall -Wextra -Werror" true
      (cd "$TMP" && "${f%.c}") >"$TMP/run.log" 2>&1
      check "$ex runs and checks out ($(tail -c 300 "$TMP/run.log" | tr '\n' ' '))" test $? -eq 0
    else
      check "$ex compiles with -Wall -Wextra -Werror ($(head -c 600 "$TMP/cc.log"))" false
    fi
  done
  for f in "$TMP/$doc"/*.lua; do
    [ -f "$f" ] || continue
    n=$((n + 1))
    ex="$doc.md: ${f##*/}"
    (cd "$TMP" && "$BSFIT" "$f") >"$TMP/run.log" 2>&1
    check "$ex under bsfit ($(tail -c 300 "$TMP/run.log" | tr '\n' ' '))" test $? -eq 0
    (cd "$TMP" && env LD_PRELOAD="$SAN_PRELOAD" \
       ASAN_OPTIONS="${ASAN_OPTIONS:+$ASAN_OPTIONS:}detect_leaks=0" LUA_CPATH="$BUILD/?.so" \
       LUA_PATH="$SRC/lua/?.lua;$SRC/lua/?/init.lua" lua5.4 "$f") >"$TMP/run.log" 2>&1
    check "$ex under stock lua5.4 ($(tail -c 300 "$TMP/run.log" | tr '\n' ' '))" test $? -eq 0
  done
done
check "the C API guide and the Lua reference have examples ($n)" \
  sh -c "ls '$TMP/c-api/'*.c >/dev/null 2>&1 && ls '$TMP/lua-api/'*.lua >/dev/null 2>&1"
echo "$pass passed, $fail failed"
[ "$fail" -eq 0 ]
