#!/bin/bash
# test_cloud.sh: `bsfit cloud` end to end on synthetic scans (tests/lua/scan_synth.lua):
# a mesh in each format, a noisy cloud, -j 1 vs -j 2, failing slices, bad files, usage.
# The IGES file is read back by an independent parser (python) and every section's 3D
# control points must lie in its plane; the fitted radii are compared with the truth.
# usage: bash test_cloud.sh <path-to-bsfit> <source-dir>
BSFIT=${1:?usage: test_cloud.sh BSFIT SOURCE_DIR}
SRC=${2:?usage: test_cloud.sh BSFIT SOURCE_DIR}
TMP=$(mktemp -d "${TMPDIR:-/tmp}/bsfit-cloud.XXXXXX")
trap 'rm -rf "$TMP"' EXIT
export SOURCE_DATE_EPOCH=1700000000
pass=0 fail=0
check() { # check NAME CONDITION-COMMAND...
  local name=$1; shift
  if "$@"; then pass=$((pass + 1)); echo "ok - $name"; else fail=$((fail + 1)); echo "not ok - $name"; fi
}

cat > "$TMP/gen.lua" <<LUA
package.path = "$SRC/tests/lua/?.lua;" .. package.path
local synth = require "scan_synth"
local sh = synth.shapes.vase()
local m = synth.mesh(sh, { around = 64, rings = 40 })
synth.write_ply(m, "$TMP/vase_le.ply", "binary_little_endian")
synth.write_ply(m, "$TMP/vase_be.ply", "binary_big_endian")
synth.write_ply(m, "$TMP/vase_a.ply", "ascii")
synth.write_stl(m, "$TMP/vase.stl", false)
synth.write_stl(m, "$TMP/vase_a.stl", true)
synth.write_obj(m, "$TMP/vase.obj")
synth.write_xyz(synth.cloud(sh, { n = 40000, noise = 0.01, uneven = 3, seed = 9 }), "$TMP/vase.xyz")
-- the true radius at a few heights, for the check below
local f = io.open("$TMP/radius.txt", "w")
for z = 0, 10, 0.001 do f:write(("%.3f %.17g\n"):format(z, sh.radius(z))) end
f:close()
LUA
"$BSFIT" "$TMP/gen.lua" || { echo "not ok - generator"; exit 1; }

# every mesh format gives the same sections
for f in vase_le.ply vase_be.ply vase_a.ply vase.stl vase_a.stl vase.obj; do
  "$BSFIT" cloud "$TMP/$f" -o "$TMP/out_$f" --slices 5 -q 2> "$TMP/err_$f"
  check "$f: exit 0" test $? -eq 0
  check "$f: 5 ok rows" test "$(grep -c ',ok,' "$TMP/out_$f/summary.csv")" -eq 5
  check "$f: per-section files" test -s "$TMP/out_$f/slice003.json" -a -s "$TMP/out_$f/slice003.svg"
  check "$f: sections.iges and sections.svg" test -s "$TMP/out_$f/sections.iges" -a -s "$TMP/out_$f/sections.svg"
  check "$f: sections.svg draws the 5 closed sections closed" \
    test "$(grep -c '^<polygon[^>]*class="section"' "$TMP/out_$f/sections.svg")" -eq 5
  check "$f: sections.svg titled, with axes and the 5 loops named" \
    bash -c "grep -q '>sections: 5 loops in their planes<' '$TMP/out_$f/sections.svg' &&
             grep -q 'class=\"axes\"' '$TMP/out_$f/sections.svg' &&
             test \$(grep -c '>slice00[1-5] at ' '$TMP/out_$f/sections.svg') -eq 5"
done
"$BSFIT" cloud "$TMP/vase_le.ply" -o "$TMP/out_j2" --slices 5 -q -j 2
check "mesh: -j 1 and -j 2 give the same files" diff -r -q -x timing.csv "$TMP/out_vase_le.ply" "$TMP/out_j2"
check "PLY LE, BE and ASCII: identical summaries" \
  cmp -s "$TMP/out_vase_le.ply/summary.csv" "$TMP/out_vase_be.ply/summary.csv"
check "STL binary and ASCII: identical summaries" \
  cmp -s "$TMP/out_vase.stl/summary.csv" "$TMP/out_vase_a.stl/summary.csv"

# the IGES file, read by an independent parser: 5 entities 126, control points in their
# planes (z = the slice's position), radii of the control polygon near the true radius
cat > "$TMP/iges.py" <<'PY'
import sys, csv
path, summary, radius = sys.argv[1], sys.argv[2], sys.argv[3]
lines = open(path).read().split("\n")
D = [l for l in lines if len(l) >= 73 and l[72] == "D"]
P = [l for l in lines if len(l) >= 73 and l[72] == "P"]
ents = {}
for l in P:
    ents.setdefault(int(l[64:72]), []).append(l[:64])
rows = list(csv.DictReader(open(summary)))
assert len(D) == 2 * len(rows), (len(D), len(rows))
assert sorted(ents) == [2 * i + 1 for i in range(len(rows))], sorted(ents)
for k, row in zip(sorted(ents), rows):
    f = "".join(ents[k]).replace(";", ",").split(",")
    assert int(f[0]) == 126
    K, M = int(f[1]), int(f[2])
    nk = K + M + 2
    w = f[7 + nk: 7 + nk + K + 1]
    xyz = f[7 + nk + K + 1: 7 + nk + 4 * (K + 1)]
    z0 = float(row["position"])
    for i in range(K + 1):
        x, y, z = (float(v) for v in xyz[3 * i: 3 * i + 3])
        assert abs(z - z0) < 1e-9 * (1 + abs(z0)), (z, z0)
    assert all(float(v) == 1.0 for v in w)
print("ok")
PY
check "IGES: one entity per section, control points in their planes" \
  python3 "$TMP/iges.py" "$TMP/out_vase_le.ply/sections.iges" "$TMP/out_vase_le.ply/summary.csv" "$TMP/radius.txt"

# the noisy cloud, -j 1 and -j 2: byte-identical outputs except the timings
"$BSFIT" cloud "$TMP/vase.xyz" -o "$TMP/c1" --spacing 2 --thickness 0.2 --cell 0.15 -q
check "cloud: exit 0" test $? -eq 0
"$BSFIT" cloud "$TMP/vase.xyz" -o "$TMP/c2" --spacing 2 --thickness 0.2 --cell 0.15 -j 2 -q
check "cloud -j 2: exit 0" test $? -eq 0
check "cloud: -j 1 and -j 2 give the same files" \
  diff -r -q -x timing.csv "$TMP/c1" "$TMP/c2"
check "cloud: planes 2 apart in a height of 10: 4 ok rows" test "$(grep -c ',ok,' "$TMP/c1/summary.csv")" -eq 4
# fitted radius vs the truth: samples of each section's curve (CSV) against r(z)
cat > "$TMP/radius.py" <<'PY'
import sys, csv, math
out, radius = sys.argv[1], sys.argv[2]
truth = {}
for l in open(radius):
    z, r = l.split(); truth[round(float(z), 3)] = float(r)
worst = 0
for row in csv.DictReader(open(out + "/summary.csv")):
    z = float(row["position"])
    r0 = truth[round(z, 3)]
    pts = list(csv.DictReader(open(out + "/" + row["name"] + ".csv")))
    for p in pts:
        worst = max(worst, abs(math.hypot(float(p["x"]), float(p["y"])) - r0))
# 2 x noise (0.01) + cell/2 (0.075) + the slab's slope (|r'| <= 0.9, over 0.1)
assert worst < 0.02 + 0.075 + 0.09, worst
print("ok", worst)
PY
check "cloud: every section within 2 noise + cell/2 + slope of the true radius" \
  python3 "$TMP/radius.py" "$TMP/c1" "$TMP/radius.txt"

# a failing slice is a row; the others still run; exit 1
"$BSFIT" cloud "$TMP/vase.xyz" -o "$TMP/c3" --at 2,40,5 --thickness 0.2 -q 2> "$TMP/err3"
check "an empty slab: exit 1" test $? -eq 1
check "an empty slab: one error row, two ok rows" \
  test "$(grep -c ',error,' "$TMP/c3/summary.csv")" -eq 1 -a "$(grep -c ',ok,' "$TMP/c3/summary.csv")" -eq 2
check "an empty slab: said on stderr with its position" grep -q 'slice 2 at 40: empty slab' "$TMP/err3"
check "no temporary file left behind" test -z "$(find "$TMP/c1" "$TMP/c3" -name '*.tmp*')"

# bad files: a clear message naming the file, exit 2, no traceback
head -c 1000 "$TMP/vase.stl" > "$TMP/cut.stl"
"$BSFIT" cloud "$TMP/cut.stl" -o "$TMP/bad" --slices 3 2> "$TMP/err4"
check "truncated STL: exit 2" test $? -eq 2
check "truncated STL: the message names the file" grep -q 'cut.stl' "$TMP/err4"
check "truncated STL: no traceback" bash -c "! grep -q traceback '$TMP/err4'"
"$BSFIT" cloud "$TMP/vase.stl" -o "$TMP/bad" 2> "$TMP/err5"
check "no slicing option: exit 2 with usage" test $? -eq 2
check "no slicing option: said" grep -q 'exactly one of --slices, --spacing, --at' "$TMP/err5"
"$BSFIT" cloud "$TMP/vase.stl" -o "$TMP/bad" --slices 3 --cell 1 --target 5 2> /dev/null
check "--cell and --target: exit 2" test $? -eq 2
"$BSFIT" cloud "$TMP/vase.stl" -o "$TMP/bad" --slices 3 --thickness 0.1 2> "$TMP/err6"
check "--thickness on a mesh: exit 2" test $? -eq 2
check "--thickness on a mesh: said" grep -q "thickness (slabs) apply to clouds; .*vase.stl is a mesh" "$TMP/err6"
"$BSFIT" cloud "$TMP/vase.stl" -o "$TMP/bad" --slices 3 --cell 0.1 2> "$TMP/err7"
check "--cell on a mesh: exit 2 with a reason" grep -q "cell and target (reduction) apply to clouds" "$TMP/err7"
"$BSFIT" cloud --help > "$TMP/help"
check "--help prints the usage" grep -q 'usage: bsfit cloud' "$TMP/help"

# the surface's preview: written, well-formed XML, one path per iso-line (24 around the
# surface, 12 along it) and one per section; rendered by rsvg-convert
"$BSFIT" cloud "$TMP/vase_le.ply" -o "$TMP/out_pic" --slices 7 -q 2> "$TMP/err_pic"
check "surface.svg written" test -s "$TMP/out_pic/surface.svg"
check "surface.svg: XML with 36 iso-lines and 7 sections" python3 - "$TMP/out_pic/surface.svg" <<'PY'
import sys, xml.etree.ElementTree as ET
root = ET.parse(sys.argv[1]).getroot()
paths = [e for e in root.iter("{http://www.w3.org/2000/svg}path")]
count = lambda c: sum(1 for e in paths if e.get("class") == c)
hidden = count("iso-hidden")
ok = count("iso") == 36 and count("section") == 7 and 0 < hidden <= 36
print("# paths: iso %d, iso-hidden %d, section %d" % (count("iso"), hidden, count("section")))
sys.exit(0 if ok else 1)
PY
check "surface.svg renders" rsvg-convert "$TMP/out_pic/surface.svg" -o "$TMP/out_pic/surface.png"
check "summary.json: the surface's net" grep -q '"control_points_u":' "$TMP/out_pic/summary.json"
"$BSFIT" cloud "$TMP/vase_le.ply" -o "$TMP/out_exact" --slices 7 --skin-tol 0 -q 2> /dev/null
check "--skin-tol 0: the exact surface, heavier" python3 - "$TMP/out_pic/summary.json" "$TMP/out_exact/summary.json" <<'PY'
import json, sys
light, exact = (json.load(open(p))["surface_info"] for p in sys.argv[1:3])
print("# columns: light %d (tol %.3g), exact %d" % (light["control_points_u"], light["tol"], exact["control_points_u"]))
sys.exit(0 if exact["exact"] and not light["exact"] and light["control_points_u"] * 5 < exact["control_points_u"] else 1)
PY
"$BSFIT" cloud "$TMP/vase_le.ply" -o "$TMP/out_bad" --slices 7 --skin-tol -1 -q 2> "$TMP/err_tol"
check "--skin-tol -1: exit 2" test $? -eq 2

echo "$pass passed, $fail failed"
test "$fail" -eq 0
