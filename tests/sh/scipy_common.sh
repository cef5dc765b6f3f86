# scipy_common.sh, sourced by the scipy cross-checks (test_scipy*.sh): Debian's python3 as
# PY, a temporary directory TMP removed on exit, and a failed run when scipy is missing.
PY=/usr/bin/python3
TMP=$(mktemp -d)
trap 'rm -rf "$TMP"' EXIT
if ! "$PY" -c "import scipy" 2>/dev/null; then
  echo "scipy not installed (apt-get install python3-scipy): cannot cross-check" >&2
  echo "0 passed, 1 failed"
  exit 1
fi
