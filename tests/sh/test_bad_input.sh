#!/usr/bin/env bash
# test_bad_input.sh BSFIT SRCDIR: the bad-input matrix of the command line. Each row
# of tests/data/bad_input/cases.tsv is a case: name, expected exit status, a fragment
# the message must hold, what the output directory may hold afterwards, and the
# command line (@D: the data directory, @T: inputs generated here, @O: the case's
# output directory, @N1: the line after the large input's last point). Every case must
# also: exit by itself (no signal, no timeout), print no Lua traceback and no internal
# file:line of a .lua module, and leave no temporary file (*.tmp*) behind. Large inputs
# (10^7 points, 10^6 under the sanitizers; a sparse 2 GB file, a file name with a
# newline) are generated here.
set -u
BSFIT=$(cd "$(dirname "$1")" && pwd)/$(basename "$1")
SRC=$(cd "$2" && pwd)
D="$SRC/tests/data/bad_input"
TMP=$(mktemp -d)
trap 'rm -rf "$TMP"' EXIT
T="$TMP/gen"
mkdir -p "$T"
fails=0
count=0

# {======================================================================
# Inputs made at run time
# =======================================================================
# 10^7 points of a circle (awk: a few seconds), and the same with a bad last line
# 10^7 points; 10^6 in the sanitizer build (the same code, and ASan's minute on the
# larger file measures nothing a sanitizer adds: scale is the normal build's test)
N=10000000
[ -n "${BSFIT_SANITIZED:-}" ] && N=1000000
awk -v n=$N 'BEGIN { for (i = 0; i < n; i++) { a = 6.283185307179586 * i / n;
       printf "%.9f,%.9f\n", 10 * cos(a), 5 * sin(a) } }' >"$T/many.csv"
cp "$T/many.csv" "$T/many_bad_last.csv"
echo "1,2,oops" >>"$T/many_bad_last.csv"
truncate -s 2G "$T/sparse_2g.csv"          # all NUL bytes, no line break
mkdir -p "$T/newline_dir" "$T/empty_dir" "$T/dir.json" "$T/with_subdir/sub.csv"
cp "$D/circle.csv" "$T/with_subdir/good.csv"
cp "$D/circle.csv" "$T/newline_dir/$(printf 'scan\nsection.csv')"
cp "$D/circle.csv" "$T/newline_dir/plain.csv"
echo "not a directory" >"$T/a_file"
ln -s "$T/nowhere.csv" "$T/dangling.csv"
# }======================================================================

# Files an output directory may hold after a run whose sections all failed.
only_summaries() {
  local f
  [ -d "$1" ] || return 0
  for f in "$1"/* "$1"/.[!.]*; do
    [ -e "$f" ] || continue
    case "${f##*/}" in summary.csv|summary.json|timing.csv|index.html) ;; *) return 1 ;; esac
  done
}

check_case() { # name want fragment outcheck args...
  local name=$1 want=$2 frag=$3 outcheck=$4
  shift 4
  local O="$TMP/out/$name" out="$TMP/$name.out" err="$TMP/$name.err" rc why=""
  rm -rf "$O"
  mkdir -p "$TMP/out"
  (cd "$TMP" && timeout 120 "$BSFIT" "$@" >"$out" 2>"$err"); rc=$?
  count=$((count + 1))
  [ $rc -eq 124 ] && why="$why timeout;"
  [ $rc -ge 128 ] && why="$why killed by signal $((rc - 128));"
  [ $rc -ne "$want" ] && why="$why exit $rc, want $want;"
  grep -qF -- "$frag" "$out" "$err" || why="$why message lacks '$frag';"
  grep -q "stack traceback" "$err" && why="$why Lua traceback;"
  grep -qE '/bsfit/[A-Za-z_/]*\.lua:[0-9]+:' "$err" &&
    why="$why internal file:line of a bsfit module;"
  grep -qE "bad argument #[0-9]+ to '" "$err" && why="$why a Lua argument error;"
  [ -n "$(find "$TMP" -name '*.tmp*' 2>/dev/null)" ] && why="$why temporary file left;"
  case "$outcheck" in
    none) only_summaries "$O" || why="$why section files left in the output;" ;;
    json) ls "$O"/*.json 2>/dev/null | grep -qv summary.json || why="$why no curve written;" ;;
    -) ;;
    *) why="$why bad outcheck '$outcheck';" ;;
  esac
  if [ -n "$why" ]; then
    fails=$((fails + 1))
    echo "FAIL $name:$why"
    sed 's/^/    stderr: /' "$err" | head -5
  else
    echo "ok   $name"
  fi
}

while IFS=$'\t' read -r name want frag outcheck cmd; do
  case "$name" in ''|'#'*) continue ;; esac
  cmd=${cmd//@D/$D}
  cmd=${cmd//@T/$T}
  cmd=${cmd//@O/$TMP/out/$name}
  frag=${frag//@T/$T}
  frag=${frag//@N1/$((N + 1))}
  frag=${frag//@D/$D}
  eval "set -- $cmd"
  check_case "$name" "$want" "$frag" "$outcheck" "$@"
done <"$D/cases.tsv"

# the newline in a file name survives into the summary (quoted CSV field)
grep -q '^scan_section,' "$TMP/out/dir_name_with_newline/summary.csv" 2>/dev/null ||
  { echo "FAIL dir_name_with_newline: the summary lacks the section"; fails=$((fails + 1)); }

echo "$count cases, $fails failed"
[ "$count" -ge 60 ] || { echo "FAIL: fewer than 60 cases"; exit 1; }
[ $fails -eq 0 ]
