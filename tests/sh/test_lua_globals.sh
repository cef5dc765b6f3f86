#!/bin/bash
# test_lua_globals.sh: no module under lua/ reads or writes a global it does not mean to. The
# compiler's listing (luac5.4 -l) names every access to _ENV: a write is always a mistake
# (a forgotten `local`), a read must be one of Lua 5.4's own globals (a misspelt or
# out-of-scope local reads nil and fails only when that line runs: svg_surface.lua once read
# an `l` it no longer declared).
# usage: bash test_lua_globals.sh <path-to-bsfit> <source-dir>
SRC=${2:?usage: test_lua_globals.sh BSFIT SOURCE_DIR}
LUAC=$(command -v luac5.4 || command -v luac) || { echo "not ok - luac5.4 missing (package lua5.4)"; exit 1; }
STD=" _G _VERSION arg assert collectgarbage coroutine debug dofile error getmetatable io ipairs load
loadfile math next os package pairs pcall print rawequal rawget rawlen rawset require select
setmetatable string table tonumber tostring type utf8 warn xpcall "
pass=0 fail=0
for f in $(find "$SRC/lua" -name '*.lua' | sort); do
  rel=${f#"$SRC"/}
  if ! listing=$("$LUAC" -l -p "$f" 2>&1); then
    fail=$((fail + 1)); echo "not ok - $rel: does not compile"; echo "# $listing"; continue
  fi
  bad=$(echo "$listing" | awk -v std=" $(echo $STD) " '
    /[GS]ETTABUP.*; _ENV "/ {
      match($0, /_ENV "[^"]*"/); name = substr($0, RSTART + 6, RLENGTH - 7)
      line = $2; gsub(/[][]/, "", line)
      if ($3 == "SETTABUP") print "line " line ": writes global " name
      else if (index(std, " " name " ") == 0) print "line " line ": reads global " name
    }')
  if [ -z "$bad" ]; then pass=$((pass + 1))
  else fail=$((fail + 1)); echo "not ok - $rel"; echo "$bad" | sed 's/^/#   /'; fi
done
[ "$fail" -eq 0 ] && echo "ok - $pass modules read only Lua's own globals and write none"
echo "$pass passed, $fail failed"
[ "$fail" -eq 0 ]
