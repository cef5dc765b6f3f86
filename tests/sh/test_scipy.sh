#!/usr/bin/env bash
# test_scipy.sh BSFIT SRC: the curve JSON of `bsfit reconstruct` (SPEC 4) is read by an
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
    s = BSpline(np.array(j["knots"]), np.array(j["control_points"]), j["degree"])
    pts = np.loadtxt(path[:-5] + ".csv", delimiter=",", skiprows=1)
    a, b = j["domain"]
    n = len(pts)
    u = a + (b - a) * np.arange(n) / (n if j["periodic"] else n - 1)
    size = np.ptp(pts, axis=0).max()
    worst = max(worst, np.abs(s(u) - pts[:, :j["dim"]]).max() / size)
sys.exit(0 if worst < 1e-12 else 1)
PYEOF
  then echo "ok - scipy evaluates the $s curves as bsfit does"; pass=$((pass + 1))
  else echo "not ok - scipy disagrees with bsfit on the $s curves"; fail=$((fail + 1)); fi
done
echo "$pass passed, $fail failed"
[ "$fail" -eq 0 ]
