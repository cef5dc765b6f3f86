#!/usr/bin/env bash
# test_exchange.sh
# CAD exchange files read back by real readers: bash test_exchange.sh <bsfit> <source-dir>.
# bsfit writes curves of every kind (open, unclamped, periodic, rational, 2D/3D, degrees
# 1-5, Bezier, rational circles) and surfaces (polynomial, rational, a skinned surface
# closed around u) as STEP, IGES and DXF (tests/sh/exchange_cases.lua). OpenCASCADE
# (tests/occt/occt_read, built next to bsfit) reads the STEP and IGES files, ezdxf
# (tests/sh/dxf_read.py, with ezdxf's auditor) the DXF files; every object must match
# bsfit's own evaluation at 100 parameters (surfaces: a 10 x 10 grid) within 1e-9 of the
# size of its control net, on the same parameter range. Nothing is skipped: a missing
# reader is a failure.
BSFIT=${1:?usage: test_exchange.sh <path-to-bsfit> <source-dir>}
SRC=${2:?usage: test_exchange.sh <path-to-bsfit> <source-dir>}
OCCT_READ=$(dirname "$BSFIT")/occt_read
PY=/usr/bin/python3
TMP=$(mktemp -d)
trap 'rm -rf "$TMP"' EXIT
CASES=$SRC/tests/sh/exchange_cases.lua
TOL=1e-9

pass=0
fail=0
ok() { pass=$((pass + 1)); echo "ok   - $1"; }
bad() { fail=$((fail + 1)); echo "FAIL - $1"; }

[ -x "$OCCT_READ" ] || { echo "FAIL - $OCCT_READ missing (install libocct-data-exchange-dev, reconfigure)"; exit 1; }
"$PY" -c 'import ezdxf' 2>/dev/null || { echo "FAIL - python3-ezdxf missing (scripts/deps.sh --test)"; exit 1; }

export SOURCE_DATE_EPOCH=1700000000
if "$BSFIT" "$CASES" gen "$TMP" >"$TMP/gen.log" 2>&1; then ok "bsfit writes every case"
else bad "bsfit writes every case: $(cat "$TMP/gen.log")"; echo "0 passed"; exit 1; fi

# compare NAME FILE OUTPUT: the reader's output checked against bsfit's evaluation
compare() {
  if "$BSFIT" "$CASES" check "$TMP" "$1" "$3" "$TOL" >"$TMP/check.log" 2>&1; then ok "$2: $(head -c 150 "$TMP/check.log")"
  else bad "$2"; cat "$TMP/check.log"; fi
}

# ezdxf once for every DXF file (a Python start costs more than the reading)
"$PY" "$SRC/tests/sh/dxf_read.py" 100 "$TMP"/*.dxf 2>"$TMP/dxf.err"
dxf_rc=$?

while read -r kind name; do
  for ext in step iges; do
    if "$OCCT_READ" "$TMP/$name.$ext" 100 10 >"$TMP/$name.$ext.out" 2>"$TMP/$name.$ext.err"; then
      compare "$name" "OCCT reads $name.$ext" "$TMP/$name.$ext.out"
    else bad "OCCT reads $name.$ext: $(cat "$TMP/$name.$ext.err")"; fi
  done
  if [ "$kind" = curve ]; then
    if grep -q "$TMP/$name.dxf:" "$TMP/dxf.err"; then bad "ezdxf reads $name.dxf: $(grep "$name.dxf:" "$TMP/dxf.err")"
    else compare "$name" "ezdxf reads and audits $name.dxf" "$TMP/$name.dxf.out"; fi
  fi
done <"$TMP/cases.txt"

# several curves in one file, in order
"$OCCT_READ" "$TMP/all.step" 100 10 >"$TMP/all.step.out" 2>"$TMP/all.step.err"
compare all "OCCT reads every curve of all.step" "$TMP/all.step.out"
compare all "ezdxf reads every curve of all.dxf" "$TMP/all.dxf.out"

if [ $dxf_rc -eq 0 ]; then ok "ezdxf: every DXF file read, audited without errors or fixes"
else bad "ezdxf: $(cat "$TMP/dxf.err")"; fi

# bsfit reconstruct --format step,dxf: NAME.step and NAME.dxf per section of the demo set,
# read back and compared with the section's NAME.json
REC=$TMP/rec
if "$BSFIT" reconstruct -q -o "$REC" --format json,step,dxf "$SRC/tests/data/demo" >"$TMP/rec.log" 2>&1; then
  ok "reconstruct --format json,step,dxf"
else bad "reconstruct --format json,step,dxf: $(cat "$TMP/rec.log")"; fi
: >"$REC/cases.txt"
for f in "$REC"/*.step; do echo "curve $(basename "$f" .step)" >>"$REC/cases.txt"; done
[ -s "$REC/cases.txt" ] || bad "reconstruct wrote no section"
"$PY" "$SRC/tests/sh/dxf_read.py" 100 "$REC"/*.dxf 2>"$TMP/rec_dxf.err" || bad "ezdxf: $(cat "$TMP/rec_dxf.err")"
while read -r kind name; do
  "$OCCT_READ" "$REC/$name.step" 100 10 >"$REC/$name.step.out" 2>/dev/null
  if "$BSFIT" "$CASES" check "$REC" "$name" "$REC/$name.step.out" "$TOL" >"$TMP/check.log" 2>&1 &&
     "$BSFIT" "$CASES" check "$REC" "$name" "$REC/$name.dxf.out" "$TOL" >>"$TMP/check.log" 2>&1; then
    ok "reconstruct's $name.step (OCCT) and $name.dxf (ezdxf) are its curve"
  else bad "reconstruct's $name.step / $name.dxf"; cat "$TMP/check.log"; fi
done <"$REC/cases.txt"

# reproducible bytes with SOURCE_DATE_EPOCH
cp "$TMP/all.step" "$TMP/first.step"
"$BSFIT" "$CASES" gen "$TMP" >/dev/null 2>&1
if cmp -s "$TMP/all.step" "$TMP/first.step"; then ok "SOURCE_DATE_EPOCH: the same bytes twice"
else bad "SOURCE_DATE_EPOCH: the same bytes twice"; fi
if grep -q "FILE_NAME('all.step','2023-11-14T22:13:20'" "$TMP/all.step"; then ok "FILE_NAME holds the epoch's time"
else bad "FILE_NAME holds the epoch's time: $(grep FILE_NAME "$TMP/all.step")"; fi

echo "$pass passed, $fail failed"
[ "$fail" -eq 0 ]
