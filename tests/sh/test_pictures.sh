#!/bin/bash
# test_pictures.sh: every picture of a demo run renders with rsvg-convert (librsvg, an
# independent SVG implementation) to a non-empty PNG, and its structure is checked with
# Python's XML parser against the input points: the viewBox is in data units and holds
# every point (y up: the data group is flipped, the view box's y is -top), the legend and
# the colour bar are there, the worst residual's label lies inside the view box. A 3D
# section (a tilted noisy ellipse) says it is drawn in its best-fit plane. The overview
# page links every picture. One outline near 0, in survey coordinates and tiny: the same
# curve drawn. Also bsfit filter's picture: before and after both stroked.
# usage: bash test_pictures.sh <path-to-bsfit> <source-dir>
BSFIT=${1:?usage: test_pictures.sh BSFIT SOURCE_DIR}
SRC=${2:?usage: test_pictures.sh BSFIT SOURCE_DIR}
TMP=$(mktemp -d "${TMPDIR:-/tmp}/bsfit-pictures.XXXXXX")
trap 'rm -rf "$TMP"' EXIT
pass=0 fail=0
check() { # check NAME CONDITION-COMMAND...
  local name=$1; shift
  if "$@"; then pass=$((pass + 1)); echo "ok - $name"; else fail=$((fail + 1)); echo "not ok - $name"; fi
}

command -v rsvg-convert > /dev/null || { echo "not ok - rsvg-convert missing (scripts/deps.sh --test)"; exit 1; }

mkdir -p "$TMP/in"
cp "$SRC"/tests/data/demo/*.csv "$TMP/in/"
/usr/bin/python3 - "$TMP/in/tilted3d.csv" << 'EOF'
import math, random, sys
random.seed(4)
with open(sys.argv[1], "w") as f:
    f.write("x,y,z\n")
    for k in range(240):
        t = 2 * math.pi * k / 240
        u, v = 30 * math.cos(t), 12 * math.sin(t) + random.gauss(0, 0.05)
        # the plane through (5, -3, 40) spanned by (1, 1, 1)/sqrt3 and (1, -1, 0)/sqrt2
        a, b = u / math.sqrt(3), v / math.sqrt(2)
        f.write("%.12g,%.12g,%.12g\n" % (5 + a + b, -3 + a - b, 40 + a))
EOF
# One outline three times: near 0 (size 12), in survey coordinates (UTM-like, 4e6 from 0)
# and of size 6e-4 a million units from 0: the same picture but for its labels.
/usr/bin/python3 - "$TMP/in" << 'EOF'
import math, sys
for name, (cx, cy), s in [("plain", (0, 0), 1), ("survey", (512345.6, 4123456.7), 1),
                          ("micro", (1e6, -3e5), 5e-5)]:
    with open("%s/%s.csv" % (sys.argv[1], name), "w") as f:
        f.write("x,y\n")
        for k in range(60):
            t = 2 * math.pi * k / 60
            r = 6 * (1 + 0.15 * math.cos(3 * t))
            f.write("%.17g,%.17g\n" % (cx + s * r * math.cos(t), cy + s * 0.6 * r * math.sin(t)))
EOF
"$BSFIT" reconstruct "$TMP/in" -o "$TMP/out" -q 2> "$TMP/err"
check "demo run with a 3D section: exit 0" test $? -eq 0

for svg in "$TMP"/out/*.svg; do
  name=$(basename "$svg" .svg)
  rsvg-convert "$svg" -o "$TMP/$name.png" 2> "$TMP/$name.rsvg"
  check "$name: rsvg-convert renders it" test $? -eq 0 -a -s "$TMP/$name.png" -a ! -s "$TMP/$name.rsvg"
  /usr/bin/python3 - "$svg" "$TMP/in/$name.csv" "$TMP/out/summary.json" << 'EOF'
import csv, json, math, re, sys
import xml.etree.ElementTree as ET
svg, data, summary = sys.argv[1:4]
NS = "{http://www.w3.org/2000/svg}"
root = ET.parse(svg).getroot()
vb = [float(v) for v in root.get("viewBox").split()]
# the numbers written are the data's less an origin, in a unit: x = ox + unit * v
ox, oy = (float(v) for v in root.get("data-origin").split())
unit = 10.0 ** int(root.get("data-unit")[2:])
X = lambda v: ox + unit * v
Y = lambda v: oy - unit * v  # outside the flipped data group
left, top, right, bottom = X(vb[0]), Y(vb[1]), X(vb[0] + vb[2]), Y(vb[1] + vb[3])  # data y up
rows = list(csv.DictReader(open(data)))
three_d = "z" in rows[0]
errors = []
def need(cond, what):
    if not cond:
        errors.append(what)
# width/height in pixels, in proportion to the view box (one scale for x and y)
w, h = float(root.get("width")), float(root.get("height"))
need(abs(w / vb[2] - h / vb[3]) <= 0.01 * w / vb[2], "one scale for x and y")
groups = {g.get("class"): g for g in root.iter(NS + "g")}
need(groups.get("data") is not None and groups["data"].get("transform") == "scale(1,-1)",
     "the data group is flipped (y up)")
need("legend" in groups and "colorbar" in groups, "legend and colour bar")
need(any(s.get("fill") == "url(#viridis)" for s in root.iter(NS + "rect")), "the colour bar's gradient")
texts = "".join("".join(t.itertext()) for t in root.iter(NS + "text"))
# text is laid out in pixels and scaled to its place (hinted at 0.1 px it is garbled)
need(all(8 <= float(t.get("font-size")) <= 20 for t in root.iter(NS + "text")),
     "every text laid out at 8 to 20 pixels")
if not three_d:
    # the viewBox is in data units: it holds every point, and not much more than them
    xs = [float(r["x"]) for r in rows]; ys = [float(r["y"]) for r in rows]
    need(min(xs) > left and max(xs) < right and min(ys) > bottom and max(ys) < top,
         "every point inside the view box")
    side = max(max(xs) - min(xs), max(ys) - min(ys))
    need(right - left < 4 * side and top - bottom < 6 * side, "the view box is near the data's size")
    # the drawn points: circles inside the data group at the points' own coordinates
    drawn = {(c.get("cx"), c.get("cy")) for c in groups["points"].iter(NS + "circle")}
    dec = len(next(iter(drawn))[0].split(".")[1])
    fmt = "%%.%df" % dec
    need(all((fmt % ((x - ox) / unit), fmt % ((y - oy) / unit)) in drawn for x, y in zip(xs, ys)),
         "every point drawn at its coordinates")
    # single-precision renderers and librsvg's smallest view box: numbers of the picture's size
    need(0.01 <= max(vb[2], vb[3]) <= 1e7, "the view box is 0.01 to 1e7 wide: %g" % vb[2])
    need(all(abs(float(v)) <= 2000 * max(vb[2], vb[3]) for c in drawn for v in c),
         "every point written as a number of the picture's size")
else:
    need("best-fit plane" in texts, "the 3D section says it is drawn in its best-fit plane")
# the worst residual: labelled with its value, inside the view box
row = [s for s in json.load(open(summary))["sections"] if svg.endswith("/" + s["name"] + ".svg")][0]
label = [t for t in root.iter(NS + "text") if t.get("class") == "max-label"]
need(len(label) == 1, "one max label")
if label:
    t = label[0]
    m = re.fullmatch(r"translate\(([^,]*),([^)]*)\) scale\(([^)]*)\)", t.get("transform"))
    x, y = X(float(m.group(1))), Y(float(m.group(2)))
    fs = float(t.get("font-size")) * float(m.group(3)) * unit  # in data units
    width = len(t.text) * 0.62 * fs
    need(x >= left and x + width <= right and y - 0.3 * fs >= bottom and y + fs <= top,
         "the max label inside the view box")
    need(("%.3g" % row["max"]) in t.text, "the label gives the max value %.3g: %s" % (row["max"], t.text))
for e in errors:
    print("# " + e)
sys.exit(1 if errors else 0)
EOF
  check "$name: data units, y up, legend, colour bar, max label inside" test $? -eq 0
done

/usr/bin/python3 - "$TMP/out/index.html" "$TMP/out" << 'EOF'
import os, re, sys
html = open(sys.argv[1]).read()
links = set(re.findall(r'<a href="([^"]+\.svg)"', html))
svgs = {f for f in os.listdir(sys.argv[2]) if f.endswith(".svg")}
sys.exit(0 if links == svgs and "<table>" in html and "<script>" in html else 1)
EOF
check "index.html: a table linking every picture, sort script inline" test $? -eq 0

# far from 0 and tiny: drawn as near 0 (a single-precision renderer shakes a curve written
# as 4e6-sized numbers by pixels; librsvg draws nothing in a view box of 0.001). The red
# pixels of the curve (#d62728), counted in rsvg-convert's PNGs, decoded here.
/usr/bin/python3 - "$TMP/plain.png" "$TMP/survey.png" "$TMP/micro.png" << 'EOF'
import struct, sys, zlib
def red_pixels(path):
    data = open(path, "rb").read()
    pos, idat, w = 8, b"", 0
    while pos < len(data):
        n, kind = struct.unpack(">I4s", data[pos:pos + 8])
        body = data[pos + 8:pos + 8 + n]
        if kind == b"IHDR":
            w, h, depth, colour = struct.unpack(">IIBB", body[:10])
            assert depth == 8 and colour == 6, "rsvg-convert writes 8-bit RGBA"
        elif kind == b"IDAT":
            idat += body
        pos += 12 + n
    raw, bpp, stride = zlib.decompress(idat), 4, 4 * w
    prev, count, i = bytearray(stride), 0, 0
    for _ in range(h):  # undo the PNG row filters (none, sub, up, average, Paeth)
        f, row = raw[i], bytearray(raw[i + 1:i + 1 + stride])
        i += 1 + stride
        for x in range(stride):
            a = row[x - bpp] if x >= bpp else 0
            b, c = prev[x], prev[x - bpp] if x >= bpp else 0
            if f == 1: row[x] = (row[x] + a) & 255
            elif f == 2: row[x] = (row[x] + b) & 255
            elif f == 3: row[x] = (row[x] + (a + b) // 2) & 255
            elif f == 4:
                p = a + b - c
                pa, pb, pc = abs(p - a), abs(p - b), abs(p - c)
                row[x] = (row[x] + (a if pa <= pb and pa <= pc else b if pb <= pc else c)) & 255
        count += sum(1 for x in range(0, stride, 4)
                     if abs(row[x] - 214) < 30 and row[x + 1] < 90 and row[x + 2] < 90 and row[x + 3] > 200)
        prev = row
    return count
ref, survey, micro = (red_pixels(p) for p in sys.argv[1:4])
print("# red curve pixels: plain %d, survey %d, micro %d" % (ref, survey, micro))
sys.exit(0 if ref > 1000 and all(abs(c - ref) <= 0.03 * ref for c in (survey, micro)) else 1)
EOF
check "survey coordinates and a tiny section: the curve drawn as near 0" test $? -eq 0

# --polygon: auto draws it up to 60 control points, on and off force it
cam_cp=$(awk -F, '$1 == "cam" {print $4}' "$TMP/out/summary.csv")
br_cp=$(awk -F, '$1 == "bracket" {print $4}' "$TMP/out/summary.csv")
has_polygon() { grep -q 'class="control"' "$1"; }
if [ "$cam_cp" -gt 60 ]; then check "auto: no polygon on cam ($cam_cp control points)" bash -c "! grep -q 'class=\"control\"' '$TMP/out/cam.svg'"
else check "auto: polygon on cam ($cam_cp control points)" has_polygon "$TMP/out/cam.svg"; fi
"$BSFIT" reconstruct "$TMP/in/cam.csv" "$TMP/in/bracket.csv" -o "$TMP/on" --polygon on -q
check "--polygon on: drawn on cam" has_polygon "$TMP/on/cam.svg"
"$BSFIT" reconstruct "$TMP/in/cam.csv" "$TMP/in/bracket.csv" -o "$TMP/off" --polygon off -q
check "--polygon off: not drawn on bracket ($br_cp control points)" bash -c "! grep -q 'class=\"control\"' '$TMP/off/bracket.svg'"
"$BSFIT" reconstruct "$TMP/in/cam.csv" -o "$TMP/bad" --polygon maybe -q 2> /dev/null
check "--polygon maybe: usage error" test $? -eq 2

# bsfit filter: the before and after curves are both stroked, with a legend (the noisy
# blob: a polynomial curve; the cam's base circle is an exact arc, rational, which the box
# filter refuses)
"$BSFIT" filter "$TMP/out/noisy_blob.json" -k 3 -o "$TMP/blob_f.json" > /dev/null
check "filter: exit 0" test $? -eq 0
rsvg-convert "$TMP/blob_f.svg" -o "$TMP/blob_f.png"
check "filter: its picture renders" test $? -eq 0 -a -s "$TMP/blob_f.png"
/usr/bin/python3 - "$TMP/blob_f.svg" << 'EOF'
import sys
import xml.etree.ElementTree as ET
NS = "{http://www.w3.org/2000/svg}"
root = ET.parse(sys.argv[1]).getroot()
curves = {e.get("class"): e for e in root.iter() if e.get("class") in ("before", "after")}
ok = all(k in curves and curves[k].get("stroke") not in (None, "none") and
         float(curves[k].get("stroke-width", "0")) > 0 for k in ("before", "after"))
legend = any(g.get("class") == "legend" for g in root.iter(NS + "g"))
sys.exit(0 if ok and legend else 1)
EOF
check "filter: before and after both stroked, legend" test $? -eq 0

echo "$pass passed, $fail failed"
test "$fail" -eq 0
