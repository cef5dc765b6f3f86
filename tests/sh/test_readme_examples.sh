#!/usr/bin/env bash
# test_readme_examples.sh BSFIT SRC: the README's examples never rot. Every fenced block
# ```lua whose first line is `-- example: NAME` and ```c whose first line is
# `/* example: NAME */` is extracted and run on every demo section: the Lua one under bsfit
# and under stock lua5.4, the C one compiled against the build tree. Each must write a curve
# JSON that scipy's BSpline (an independent evaluator) finds as close to the points as the
# example printed (its max distance, recomputed by projecting every point on the curve),
# closed, and the three hosts must agree on the unweighted sections.
set -u
BSFIT=$(cd "$(dirname "$1")" && pwd)/$(basename "$1")
SRC=$(cd "$2" && pwd)
BUILD=$(dirname "$BSFIT")
. "$SRC/tests/sh/scipy_common.sh"
pass=0
fail=0
check() { # name, then a command that must succeed
  local name=$1
  shift
  if "$@"; then echo "ok - $name"; pass=$((pass + 1)); else echo "not ok - $name"; fail=$((fail + 1)); fi
}

# extract: the blocks' bodies to $TMP/ex/NAME.lua and NAME.c
mkdir -p "$TMP/ex"
awk -v dir="$TMP/ex" '
  /^```(lua|c) *$/ { lang = substr($0, 4); sub(/ *$/, "", lang); first = 1; out = ""; next }
  /^```/ { if (out != "") close(out); lang = ""; out = ""; next }
  lang != "" && first {
    first = 0
    if (lang == "lua" && match($0, /^-- example: [A-Za-z0-9_]+$/)) out = dir "/" substr($0, 13) ".lua"
    if (lang == "c" && match($0, /^\/\* example: [A-Za-z0-9_]+ \*\/$/)) {
      name = $0; sub(/^\/\* example: /, "", name); sub(/ \*\/$/, "", name); out = dir "/" name ".c"
    }
  }
  lang != "" && out != "" { print > out }' "$SRC/README.md"
lua_ex=("$TMP"/ex/*.lua)
c_ex=("$TMP"/ex/*.c)
check "the README has Lua examples (${lua_ex[*]##*/})" test -f "${lua_ex[0]}"
check "the README has C examples (${c_ex[*]##*/})" test -f "${c_ex[0]}"

# A sanitizer build: the C example links the runtimes, and stock lua5.4 (not instrumented)
# gets them preloaded to load the instrumented bsfit.so.
SAN_FLAGS=""
SAN_PRELOAD=""
if grep -q '^BSFIT_SANITIZE:BOOL=ON' "$BUILD/CMakeCache.txt"; then
  SAN_FLAGS="-fsanitize=address,undefined"
  SAN_PRELOAD="$(cc -print-file-name=libasan.so) $(cc -print-file-name=libubsan.so)"
fi
for f in "${c_ex[@]}"; do
  [ -f "$f" ] || continue
  # shellcheck disable=SC2046
  cc -std=c11 -Wall -Wextra -Werror $SAN_FLAGS -I"$SRC/src" -o "${f%.c}" "$f" \
     "$BUILD/libbsfit_lua.a" "$BUILD/libbsfit.a" $(pkg-config --libs lua5.4 lapacke) \
     -lm -lpthread -ldl 2>"$TMP/cc.log"
  check "${f##*/} compiles with -Wall -Wextra -Werror ($(head -c 400 "$TMP/cc.log"))" test -x "${f%.c}"
done

# runs every example on every demo section: out/<host>-<example>/<section>.json and .txt
run_all() { # host, example, then the command (input and output are appended)
  local host=$1 ex=$2 dir s
  shift 2
  dir=$TMP/out/$host-$ex
  mkdir -p "$dir"
  for s in "$SRC"/tests/data/demo/*.csv; do
    s=$(basename "$s" .csv)
    (cd "$SRC" && "$@" "tests/data/demo/$s.csv" "$dir/$s.json") >"$dir/$s.txt" 2>"$dir/$s.err" ||
      { echo "$host $ex $s: $(head -c 400 "$dir/$s.err")"; return 1; }
  done
}
for f in "${lua_ex[@]}"; do
  [ -f "$f" ] || continue
  ex=$(basename "$f" .lua)
  check "lua example $ex under bsfit on every demo section" run_all bsfit "$ex" "$BSFIT" "$f"
  check "lua example $ex under stock lua5.4" run_all lua5.4 "$ex" env LD_PRELOAD="$SAN_PRELOAD" \
    ASAN_OPTIONS="${ASAN_OPTIONS:+$ASAN_OPTIONS:}detect_leaks=0" \
    LUA_CPATH="$BUILD/?.so" LUA_PATH="$SRC/lua/?.lua;$SRC/lua/?/init.lua" lua5.4 "$f"
done
for f in "${c_ex[@]}"; do
  [ -x "${f%.c}" ] || continue
  ex=$(basename "$f" .c)
  check "C example $ex on every demo section" run_all c "$ex" "${f%.c}"
done

# scipy: each JSON is a closed curve whose distance to the points is what the example printed
for d in "$TMP"/out/*; do
  [ -d "$d" ] || continue
  "$PY" - "$d" "$SRC/tests/data/demo" >"$TMP/py.log" 2>&1 <<'PYEOF'
import glob, json, os, re, sys
import numpy as np
from scipy.interpolate import BSpline
out, demo = sys.argv[1], sys.argv[2]
bad = []
for path in sorted(glob.glob(out + "/*.json")):
    name = os.path.basename(path)[:-5]
    j = json.load(open(path))
    P = np.array(j["control_points"])
    w = np.array(j["weights"]) if j.get("weights") is not None else None
    # a NURBS (auto writes circular arcs exactly): the B-spline of the homogeneous
    # points (w P, w), divided by its last coordinate
    H = P if w is None else np.column_stack([P * w[:, None], w])
    sh = BSpline(np.array(j["knots"]), H, j["degree"])
    s = sh if w is None else (lambda t: (lambda v: v[..., :-1] / v[..., -1:])(sh(t)))
    a, b = j["domain"]
    # the end of the period, from the left: in the expanded periodic form a corner at the
    # seam puts a multiple knot at b, where scipy would pick the span after the period
    b = np.nextafter(b, a)
    text = open(path[:-5] + ".txt").read()
    got = float(re.search(r"max ([0-9.eE+-]+)", text).group(1))
    P = np.genfromtxt(demo + "/" + name + ".csv", delimiter=",", names=True)
    xy = np.column_stack([P["x"], P["y"]])
    size = np.ptp(xy, axis=0).max()
    # the samples include the knots: a corner's foot point is a knot, and the bounded
    # zoom below starts from the nearest sample
    kn = np.array(j["knots"])
    u = np.unique(np.concatenate([np.linspace(a, b, 20001), kn[(kn >= a) & (kn <= b)]]))
    S = s(u)
    h = np.diff(u).max()
    # nearest sample, then zoom: 21 parameters across the bracket around the best one, the
    # bracket narrowed tenfold per round down to rounding. Not a library minimiser: scipy's
    # bounded Brent stops at a parameter step of sqrt(eps) |u| (4e-9 here), which on a
    # point lying on the curve (an exact section) is a distance of |C'| times that, 4.6e-7
    # on the bracket, where the true distance is below 1e-13.
    k = np.argmin(((S[None, :, :] - xy[:, None, :]) ** 2).sum(axis=2), axis=1)
    ub, d2 = u[k], ((S[k] - xy) ** 2).sum(axis=1)
    for _ in range(16):
        t = np.clip(ub[:, None] + h * np.linspace(-1, 1, 21)[None, :], a, b)
        St = s(t.ravel()).reshape(len(xy), 21, -1)
        e = ((St - xy[:, None, :]) ** 2).sum(axis=2)
        jb = np.argmin(e, axis=1)
        better = e[np.arange(len(xy)), jb] < d2
        ub = np.where(better, t[np.arange(len(xy)), jb], ub)
        d2 = np.where(better, e[np.arange(len(xy)), jb], d2)
        h /= 10
    worst = np.sqrt(d2.max())
    closed = np.abs(s(a) - s(b)).max() <= 1e-12 * size
    # the example prints %.3g: 3 significant digits
    # and 1e-12 of the size: an exact section's distances are rounding
    if not (closed and abs(worst - got) <= 6e-3 * worst + 1e-12 * size):
        bad.append(f"{name}: closed {closed}, max {worst:.6g} printed {got:.6g}")
print("; ".join(bad))
sys.exit(1 if bad else 0)
PYEOF
  status=$?
  check "scipy: ${d##*/} curves are closed at the printed distance ($(head -c 400 "$TMP/py.log"))" \
    test $status -eq 0
done

# the hosts agree (unweighted sections: the C example drops a w column)
for d in "$TMP"/out/*; do
  [ -d "$d" ] || continue
  for other in "$TMP"/out/*; do
    [ "$other" \> "$d" ] || continue
    same=1
    for j in "$d"/*.json; do
      s=$(basename "$j" .json)
      grep -q -i '^[^#]*\bw\b' "$SRC/tests/data/demo/$s.csv" 2>/dev/null && continue
      cmp -s "$j" "$other/$s.json" || same=0
    done
    check "${d##*/} and ${other##*/} write the same curves" test $same -eq 1
  done
done
echo "$pass passed, $fail failed"
[ "$fail" -eq 0 ]
