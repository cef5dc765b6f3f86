#!/usr/bin/env bash
# test_cli.sh
# Tests of the bsfit program: bash test_cli.sh <path-to-bsfit> <source-dir>.
# Each check runs the program and looks at its exit status, stdout and stderr.
# Prints one line per check and a final "N passed, M failed"; exits non-zero on failure.

BSFIT=${1:?usage: test_cli.sh <path-to-bsfit> <source-dir>}
SRC=${2:?usage: test_cli.sh <path-to-bsfit> <source-dir>}
TMP=$(mktemp -d)
trap 'rm -rf "$TMP"' EXIT
unset BSFIT_PATH

pass=0
fail=0
ok() { pass=$((pass + 1)); echo "ok   - $1"; }
bad() { fail=$((fail + 1)); echo "FAIL - $1"; echo "  status=$rc"; echo "  stdout: $(head -c 600 "$TMP/out")"; echo "  stderr: $(head -c 600 "$TMP/err")"; }

# run ARGS...: runs bsfit, keeping status in rc, output in $TMP/out and $TMP/err
run() { "$BSFIT" "$@" >"$TMP/out" 2>"$TMP/err"; rc=$?; }
# check NAME CONDITION: a condition evaluated by bash after run
check() { if eval "$2"; then ok "$1"; else bad "$1"; fi; }
has() { grep -qF -- "$2" "$TMP/$1"; }

# --version, -v
run --version
check "--version prints the version, exit 0" '[ $rc -eq 0 ] && grep -qE "^bsfit [0-9]+\.[0-9]+\.[0-9]+ \(Lua 5\.4" "$TMP/out"'

# --help and no arguments: usage on stdout, exit 0
run --help
check "--help prints usage, exit 0" '[ $rc -eq 0 ] && has out "usage: bsfit" && has out "--sandbox"'
run
check "no arguments prints help, exit 0" '[ $rc -eq 0 ] && has out "usage: bsfit"'

# a bad option: usage on stderr, exit 1
run --frobnicate
check "unknown option: message and exit 1" '[ $rc -eq 1 ] && has err "unrecognized option '"'"'--frobnicate'"'"'"'
run --mem-limit
check "--mem-limit without a value: exit 1" '[ $rc -eq 1 ] && has err "needs a positive number"'

# -e runs code with bsfit preloaded and lua/ on the path
run -e 'local bs = require "bsfit"; print(type(bs), package.path:find("lua/?.lua", 1, true) ~= nil)'
check "-e runs code, bsfit preloaded, lua/ on package.path" '[ $rc -eq 0 ] && has out "table	true"'
run -e 'x = 20' -e 'print(x + 22)'
check "several -e run in order" '[ $rc -eq 0 ] && has out "42"'
run -e 'error("nope")'
check "-e error: exit 1 with the chunk name" '[ $rc -eq 1 ] && has err "bsfit: (command line):1: nope"'

# a script with arguments: arg as lua sets it, and ... too
cat >"$TMP/args.lua" <<'LUA'
print(#arg, arg[0]:match("[^/]*$"), arg[1], arg[2], select("#", ...), (...))
print(arg[-1] ~= nil)
LUA
run "$TMP/args.lua" one two
check "script arguments in arg and ..." '[ $rc -eq 0 ] && has out "2	args.lua	one	two	2	one" && has out "true"'

# a script that errors halfway: what ran printed, file:line and traceback on stderr
cat >"$TMP/halfway.lua" <<'LUA'
print("before")
local function deep() local t = nil; return t.field end
deep()
print("after")
LUA
run "$TMP/halfway.lua"
check "erroring script: exit 1" '[ $rc -eq 1 ]'
check "erroring script: lines before the error ran, not after" 'has out "before" && ! has out "after"'
check "erroring script: file:line on stderr" 'has err "halfway.lua:2: attempt to index a nil value"'
check "erroring script: no traceback without --debug" '! has err "stack traceback:"'
run --debug "$TMP/halfway.lua"
check "erroring script: traceback on stderr with --debug" 'has err "stack traceback:" && has err "halfway.lua:3: in main chunk"'

# syntax error and missing file
printf 'x = = 1\n' >"$TMP/syntax.lua"
run "$TMP/syntax.lua"
check "syntax error: exit 1 with file:line" '[ $rc -eq 1 ] && has err "syntax.lua:1:"'
run "$TMP/missing.lua"
check "missing script: exit 1, names the file" '[ $rc -eq 1 ] && has err "missing.lua"'

# stdin as the script
echo 'print("from stdin", 6 * 7)' | "$BSFIT" - >"$TMP/out" 2>"$TMP/err"; rc=$?
check "- runs stdin" '[ $rc -eq 0 ] && has out "from stdin	42"'

# subcommands: unknown word, and a module of BSFIT_PATH's bsfit/cli/
run frobnicate
check "unknown command: message, exit 1" '[ $rc -eq 1 ] && has err "unknown command '"'"'frobnicate'"'"'"'
mkdir -p "$TMP/lua/bsfit/cli"
cat >"$TMP/lua/bsfit/cli/hello.lua" <<'LUA'
local M = {}
function M.main(args)
  print("hello", #args, args[1], args[2], type(require("bsfit")))
  return tonumber(args[2]) or 0
end
return M
LUA
BSFIT_PATH="$TMP/lua" "$BSFIT" hello world 3 >"$TMP/out" 2>"$TMP/err"; rc=$?
check "subcommand from BSFIT_PATH: main(args), its return is the exit status" '[ $rc -eq 3 ] && has out "hello	2	world	3	table"'
BSFIT_PATH="$TMP/lua" "$BSFIT" hello >"$TMP/out" 2>"$TMP/err"; rc=$?
check "subcommand returning nothing: exit 0" '[ $rc -eq 0 ] && has out "hello	0"'
BSFIT_PATH="$TMP/lua" "$BSFIT" -E hello >"$TMP/out" 2>"$TMP/err"; rc=$?
check "-E ignores BSFIT_PATH" '[ $rc -eq 1 ] && has err "unknown command '"'"'hello'"'"'"'
cat >"$TMP/lua/bsfit/cli/broken.lua" <<'LUA'
return { main = function(args) error("broken subcommand") end }
LUA
BSFIT_PATH="$TMP/lua" "$BSFIT" broken >"$TMP/out" 2>"$TMP/err"; rc=$?
check "failing subcommand: exit 1 with file:line, no traceback" '[ $rc -eq 1 ] && has err "broken.lua:1: broken subcommand" && ! has err "stack traceback:"'
BSFIT_PATH="$TMP/lua" "$BSFIT" --debug broken >"$TMP/out" 2>"$TMP/err"; rc=$?
check "failing subcommand with --debug: traceback" '[ $rc -eq 1 ] && has err "stack traceback:"'

# limits and sandbox flags
run --instr-limit 100000 -e 'while true do pcall(function() while true do end end) end'
check "--instr-limit stops an endless loop" '[ $rc -eq 1 ] && has err "instruction budget exceeded"'
run --mem-limit 4m -e 'local t = {} for i = 1, 1e9 do t[i] = {i} end'
check "--mem-limit stops a memory bomb" '[ $rc -eq 1 ] && has err "not enough memory"'
run --sandbox -e 'print(io, os, debug, dofile, require("bsfit") ~= nil)'
check "--sandbox: no io, os, debug, dofile; bsfit still there" '[ $rc -eq 0 ] && has out "nil	nil	nil	nil	true"'

# Ctrl-C (SIGINT) stops a running script with a message, exit 1
"$BSFIT" --debug -e 'while true do end' >"$TMP/out" 2>"$TMP/err" &
pid=$!
sleep 0.5
kill -INT "$pid"
wait "$pid"; rc=$?
check "SIGINT interrupts a running script: message and exit 1" '[ $rc -eq 1 ] && has err "interrupted" && has err "stack traceback:"'

# -l loads a module into a global
mkdir -p "$TMP/mods"
echo 'return { answer = 42 }' >"$TMP/mods/mymod.lua"
BSFIT_PATH="$TMP/mods" "$BSFIT" -l mymod -e 'print(mymod.answer)' >"$TMP/out" 2>"$TMP/err"; rc=$?
check "-l mod sets global mod" '[ $rc -eq 0 ] && has out "42"'

echo "$pass passed, $fail failed"
[ "$fail" -eq 0 ]
