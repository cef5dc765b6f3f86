"""scipy_fit_check.py CASES.json: redoes every fit of fit_cases.lua independently and compares.

For each case: the design matrix of the knots bsfit returned comes from scipy's
BSpline.design_matrix (periodic fits: the expanded knots, wrapped columns folded onto
their originals, docs/method.md §1); the weighted least-squares problem min sum w_k |Q_k - C(u_k)|^2
is solved densely with numpy's lstsq on sqrt(w)-scaled rows (QR/SVD, not normal equations),
constrained unknowns (fixed ends, end tangents) moved to the right-hand side. Open fits without
constraints are also fitted by scipy's make_lsq_spline (it squares its weights: w = sqrt(w_k)).
The report (residuals, weighted RMS, max and its index) is recomputed with scipy's BSpline.
Prints a TAP-like line per case and exits non-zero on any disagreement.
"""
import json
import sys

import numpy as np
from scipy.interpolate import BSpline, make_lsq_spline

COEF_TOL = 1e-9   # control points, relative to the size of the data
RES_TOL = 1e-10   # residuals, RMS and maximum, relative to the size of the data


def domain_params(t, p, n_stored, u, periodic):
    """Parameters inside the curve's domain [t_p, t_n] (periodic: wrapped into one period)."""
    a, b = t[p], t[n_stored]
    if not periodic:
        return u
    return a + np.mod(u - a, b - a)


def design(t, p, n_stored, u, periodic, n_distinct):
    """Dense m x n_distinct collocation matrix (periodic: wrapped columns folded)."""
    # beyond the domain of open knots the end pieces continue (bsfit's documented rule)
    B = BSpline.design_matrix(u, t, p, extrapolate=not periodic).toarray()
    assert B.shape[1] == n_stored
    if periodic:
        F = B[:, :n_distinct].copy()
        F[:, : n_stored - n_distinct] += B[:, n_distinct:]
        return F
    return B


def fixed_unknowns(c, t, p, n, Q):
    """Indices and values of the control points the constraints fix (open fits only)."""
    fixed = {}
    if c["fix_ends"] or c["tangent_start"] is not None:
        fixed[0] = Q[0]
    if c["fix_ends"] or c["tangent_end"] is not None:
        fixed[n - 1] = Q[-1]
    if c["tangent_start"] is not None:   # C'(a) = p / (t[p+1] - t[1]) (P1 - P0)
        fixed[1] = Q[0] + (t[p + 1] - t[1]) / p * np.array(c["tangent_start"])
    if c["tangent_end"] is not None:     # C'(b) = p / (t[n+p-1] - t[n-1]) (P_{n-1} - P_{n-2})
        fixed[n - 2] = Q[-1] - (t[n + p - 1] - t[n - 1]) / p * np.array(c["tangent_end"])
    return fixed


def reference_fit(c, t, p, Q, u, w):
    """The independent weighted least-squares control points (distinct ones for periodic)
    and the reciprocal 1-norm condition number of the normal matrix of the free unknowns."""
    n_stored = len(c["ctrl"])
    n = n_stored - p if c["periodic"] else n_stored
    A = design(t, p, n_stored, domain_params(t, p, n_stored, u, c["periodic"]), c["periodic"], n)
    rhs = Q.copy()
    fixed = {} if c["periodic"] else fixed_unknowns(c, t, p, n, Q)
    for j, val in fixed.items():
        rhs -= np.outer(A[:, j], val)
    free = [j for j in range(n) if j not in fixed]
    sw = np.sqrt(w)[:, None]
    sol = np.linalg.lstsq(A[:, free] * sw, rhs * sw, rcond=None)[0]
    P = np.zeros((n, Q.shape[1]))
    P[free] = sol
    for j, val in fixed.items():
        P[j] = val
    M = (A[:, free] * w[:, None]).T @ A[:, free]
    rcond = 1.0 / (np.abs(M).sum(0).max() * np.abs(np.linalg.inv(M)).sum(0).max())
    return P, rcond


def check(c):
    p = c["degree"]
    t = np.array(c["knots"])
    Q = np.array(c["points"])
    u = np.array(c["u"])
    w = np.array(c["w"])
    ctrl = np.array(c["ctrl"])
    size = np.ptp(Q, axis=0).max()
    errors = []
    n_stored = len(ctrl)
    if c["periodic"]:
        if not np.array_equal(ctrl[n_stored - p:], ctrl[:p]):
            errors.append("wrapped control points differ from the first p")
        spans, N = np.diff(t), n_stored - p   # span i + N repeats span i
        if np.abs(spans[N:] - spans[: len(spans) - N]).max() > 1e-13 * (t[-1] - t[0]):
            errors.append("expanded knot spans do not repeat with the period")
    ref, rcond = reference_fit(c, t, p, Q, u, w)
    mine = ctrl[: len(ref)]
    err = np.abs(mine - ref).max() / size
    if err > COEF_TOL:
        errors.append("control points differ from the dense lstsq by %.2e" % err)
    unconstrained = not c["periodic"] and not c["fix_ends"] and c["tangent_start"] is None \
        and c["tangent_end"] is None
    order = np.argsort(u, kind="stable")
    inside = t[p] <= u.min() and u.max() <= t[n_stored]
    if unconstrained and inside and np.all(np.diff(u[order]) > 0):  # scipy's own conditions
        s = make_lsq_spline(u[order], Q[order], t, p, w=np.sqrt(w[order]))
        err2 = np.abs(s.c - ctrl).max() / size
        if err2 > COEF_TOL:
            errors.append("control points differ from make_lsq_spline by %.2e" % err2)
    curve = BSpline(t, ctrl, p)
    ud = domain_params(t, p, n_stored, u, c["periodic"])
    r = np.linalg.norm(curve(ud) - Q, axis=1)
    if np.abs(r - np.array(c["residuals"])).max() / size > RES_TOL:
        errors.append("residuals differ")
    rms = np.sqrt((w * r * r).sum() / w.sum())
    if abs(rms - c["rms"]) / size > RES_TOL or abs(r.max() - c["max"]) / size > RES_TOL:
        errors.append("rms %.6g / max %.6g, scipy %.6g / %.6g" % (c["rms"], c["max"], rms, r.max()))
    if abs(r[c["max_index"] - 1] - r.max()) / size > RES_TOL:
        errors.append("max_index %d is not where the maximum is" % c["max_index"])
    if c["tangent_start"] is not None:
        d = curve.derivative()(t[p])
        if np.abs(d - np.array(c["tangent_start"])).max() > 1e-9 * np.abs(d).max():
            errors.append("C'(a) = %s, asked %s" % (d, c["tangent_start"]))
    if c["tangent_end"] is not None:
        d = curve.derivative()(t[n_stored])
        if np.abs(d - np.array(c["tangent_end"])).max() > 1e-9 * np.abs(d).max():
            errors.append("C'(b) = %s, asked %s" % (d, c["tangent_end"]))
    if c["fix_ends"] or c["tangent_start"] is not None:
        if np.abs(curve(t[p]) - Q[0]).max() > 1e-12 * size:
            errors.append("the curve does not start at Q_0")
    # rcond: exact for open fits inside the domain (the normal matrix is totally
    # nonnegative); periodic ones an estimate from above, within the estimators' factor
    inside = t[p] <= u.min() and u.max() <= t[n_stored]
    ratio = c["rcond"] / rcond
    if not c["periodic"] and inside and abs(ratio - 1) > 1e-6:
        errors.append("rcond %.6g, exact %.6g" % (c["rcond"], rcond))
    if c["periodic"] and not (1 - 1e-9 <= ratio <= 3):
        errors.append("rcond %.6g, exact %.6g: not an estimate from above within 3x" % (c["rcond"], rcond))
    if not (0 < c["rcond"] <= 1):
        errors.append("rcond %g out of (0, 1]" % c["rcond"])
    return errors


def main():
    cases = json.load(open(sys.argv[1]))
    passed = failed = 0
    for c in cases:
        errors = check(c)
        if errors:
            failed += 1
            print("not ok - %s: %s" % (c["name"], "; ".join(errors)))
        else:
            passed += 1
            print("ok - %s agrees with scipy" % c["name"])
    print("%d passed, %d failed" % (passed, failed))
    return 1 if failed or not cases else 0


if __name__ == "__main__":
    sys.exit(main())
