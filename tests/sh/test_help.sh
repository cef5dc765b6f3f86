#!/usr/bin/env bash
# test_help.sh BSFIT SRC: `bsfit -h`, `bsfit --help` and `bsfit CMD --help` (every command
# in lua/bsfit/cli/) print their usage to stdout and exit 0; the man page docs/bsfit.1
# renders without a warning, and every option each --help lists is in the man page (an
# interpreter option anywhere, a command's option in that command's subsection).
set -u
BSFIT=$1
SRC=$2
TMP=$(mktemp -d)
trap 'rm -rf "$TMP"' EXIT
pass=0
fail=0
check() { # name, then a command that must succeed
  local name=$1
  shift
  if "$@"; then echo "ok - $name"; pass=$((pass + 1)); else echo "not ok - $name"; fail=$((fail + 1)); fi
}
MAN=$SRC/docs/bsfit.1

# usage to stdout, nothing on stderr, exit 0
help_ok() { # out-file, then the arguments
  local out=$1
  shift
  "$BSFIT" "$@" >"$out" 2>"$TMP/err" && [ ! -s "$TMP/err" ] && grep -q '^usage: bsfit' "$out"
}
check "bsfit -h" help_ok "$TMP/h.txt" -h
check "bsfit --help" help_ok "$TMP/main.txt" --help
check "-h and --help print the same" cmp -s "$TMP/h.txt" "$TMP/main.txt"
commands=()
for f in "$SRC"/lua/bsfit/cli/*.lua; do commands+=("$(basename "$f" .lua)"); done
check "there are commands (${commands[*]})" test ${#commands[@]} -ge 2
for c in "${commands[@]}"; do
  check "bsfit $c --help" help_ok "$TMP/$c.txt" "$c" --help
  check "bsfit $c -h" help_ok "$TMP/$c.h.txt" "$c" -h
  check "bsfit $c: -h and --help print the same" cmp -s "$TMP/$c.txt" "$TMP/$c.h.txt"
done

# the man page: no warning from groff (all of them on) nor from man
groff -man -Tascii -ww -z "$MAN" 2>"$TMP/groff.err"
check "groff renders bsfit.1 without warnings ($(head -c 300 "$TMP/groff.err"))" \
  test ! -s "$TMP/groff.err"
MANWIDTH=100 LC_ALL=C.UTF-8 man --warnings -E ascii -l "$MAN" 2>"$TMP/man.err" >/dev/null
# the text as man shows it, without overstrike (grotty -c -b -u)
groff -man -Tascii -rLL=100n -P-cbu "$MAN" >"$TMP/man.txt" 2>/dev/null
check "man -l renders bsfit.1 without warnings ($(head -c 300 "$TMP/man.err"))" \
  test ! -s "$TMP/man.err"
for h in NAME SYNOPSIS DESCRIPTION OPTIONS COMMANDS 'EXIT STATUS' ENVIRONMENT FILES EXAMPLES; do
  check "the man page has a section $h" grep -q -x -F -e "$h" "$TMP/man.txt"
done
check "the man page documents BSFIT_PATH" grep -q 'BSFIT_PATH' "$TMP/man.txt"

# The options a usage text lists: words starting with - or -- at the start of a line
# (after spaces) or after ", ", "[", "(" or "|".
options_of() {
  grep -o -E '(^ *|, |\[|\(|\| )--?[A-Za-z][-A-Za-z]*' "$1" | sed -E 's/^[][ ,(|]*//' | sort -u
}
# The rendered man page's subsection of a command (an indented heading line "   CMD").
section_of() {
  awk -v c="$1" '$0 ~ "^   " c "$" {on = 1; next} on && /^   [a-z]+$/ {on = 0} on && /^[A-Z]/ {on = 0} on' \
    "$TMP/man.txt"
}
for o in $(options_of "$TMP/main.txt"); do
  check "man page: bsfit $o" grep -q -F -e "$o" "$TMP/man.txt"
done
for c in "${commands[@]}"; do
  section_of "$c" >"$TMP/sec.$c"
  check "man page: a subsection for $c" test -s "$TMP/sec.$c"
  n=0
  for o in $(options_of "$TMP/$c.txt"); do
    n=$((n + 1))
    check "man page: bsfit $c $o" grep -q -E -e "(^|[^-A-Za-z])$o([^-A-Za-z]|\$)" "$TMP/sec.$c"
  done
  check "bsfit $c --help lists options ($n)" test "$n" -ge 2
done
echo "$pass passed, $fail failed"
[ "$fail" -eq 0 ]
