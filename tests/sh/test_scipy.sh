#!/usr/bin/env bash
# test_scipy.sh BSFIT SRC: the curve JSON of `bsfit reconstruct` (docs/formats.md) is read by an
# independent evaluator: scipy's BSpline on the JSON's knots, control points and degree
# must reproduce the CSV samples bsfit wrote, for every demo section and every strategy.
set -u
BSFIT=$1
SRC=$2
. "$SRC/tests/sh/scipy_common.sh"
pass=0
fail=0
for s in auto periodic carvalho; do
  if ! "$BSFIT" reconstruct "$SRC/tests/data/demo" -o "$TMP/$s" --strategy "$s" --format json,csv -q; then
    echo "not ok - reconstruct --strategy $s"; fail=$((fail + 1)); continue
  fi
  if "$PY" - "$TMP/$s" <<'PYEOF'
import glob, json, sys
import numpy as np
from scipy.interpolate import BSpline
worst = 0.0
for path in sorted(glob.glob(sys.argv[1] + "/*.json")):
    if path.endswith("summary.json"):
        continue
    j = json.load(open(path))
    P = np.array(j["control_points"])
    w = np.array(j["weights"]) if j.get("weights") is not None else None
    # a NURBS (auto's curves with circular arcs): the B-spline of the homogeneous points
    # (w P, w), divided by its last coordinate
    H = P if w is None else np.column_stack([P * w[:, None], w])
    s = BSpline(np.array(j["knots"]), H, j["degree"])
    pts = np.loadtxt(path[:-5] + ".csv", delimiter=",", skiprows=1)
    a, b = j["domain"]
    n = len(pts)
    u = a + (b - a) * np.arange(n) / (n if j["periodic"] else n - 1)
    size = np.ptp(pts, axis=0).max()
    v = s(u)
    if w is not None:
        v = v[:, :-1] / v[:, -1:]
    worst = max(worst, np.abs(v - pts[:, :j["dim"]]).max() / size)
sys.exit(0 if worst < 1e-12 else 1)
PYEOF
  then echo "ok - scipy evaluates the $s curves as bsfit does"; pass=$((pass + 1))
  else echo "not ok - scipy disagrees with bsfit on the $s curves"; fail=$((fail + 1)); fi
done
echo "$pass passed, $fail failed"
[ "$fail" -eq 0 ]
