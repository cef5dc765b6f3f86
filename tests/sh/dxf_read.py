#!/usr/bin/env python3
"""dxf_read.py N FILE...: a test oracle for bsfit's DXF writer.

Reads each FILE with ezdxf, runs ezdxf's auditor (any error or fix is a failure), and prints
every SPLINE evaluated by ezdxf (ezdxf.math.BSpline on the entity's data) at N parameters equally spaced over its knot range, in
occt_read's format:
    curve K SPLINE DEGREE POLES RATIONAL FLAGS FIRST LAST   then N lines "x y z"
    end CURVES 0
into FILE.out (one Python start for many files). Exit status 1 when a file fails.
"""
import sys

import ezdxf
from ezdxf.math import BSpline


def read(path, n, out):
    doc = ezdxf.readfile(path)
    auditor = doc.audit()
    if auditor.has_errors or auditor.has_fixes:
        for e in auditor.errors + auditor.fixes:
            print(f"dxf_read: {path}: audit: {e.message}", file=sys.stderr)
        return False
    splines = doc.modelspace().query("SPLINE")
    for k, s in enumerate(splines, 1):
        knots = list(s.knots)
        first, last = knots[0], knots[-1]
        # ezdxf's evaluator counts parameters from 0: the same spline on knots shifted by
        # -first, evaluated at t - first (exact: a shift of the knots is a shift of t)
        bsp = BSpline(s.control_points, order=s.dxf.degree + 1,
                      knots=[k - first for k in knots],
                      weights=list(s.weights) if len(s.weights) else None)
        rational = int(len(s.weights) > 0)
        print(f"curve {k} SPLINE {s.dxf.degree} {len(s.control_points)} {rational} "
              f"{s.dxf.flags} {first!r} {last!r}", file=out)
        for i in range(n):
            t = first + (last - first) * i / (n - 1)
            p = bsp.point(min(t - first, last - first))
            print(f"{p.x!r} {p.y!r} {p.z!r}", file=out)
    print(f"end {len(splines)} 0", file=out)
    return True


def main():
    n, ok = int(sys.argv[1]), True
    for path in sys.argv[2:]:
        with open(path + ".out", "w") as out:
            try:
                ok = read(path, n, out) and ok
            except Exception as e:  # a reader error is this file's failure, not the run's
                print(f"dxf_read: {path}: {e!r}", file=sys.stderr)
                ok = False
    sys.exit(0 if ok else 1)


if __name__ == "__main__":
    main()
