"""skin_tol_check.py DIR: the tolerance skin's distances measured independently (scipy).

For every case of DIR/cases.txt (written by skin_tol_cases.lua) with a light surface (count
> 0), the Hausdorff distance between each section and the surface's iso-curve S(., v_k) is
measured with scipy's B-splines: the samples of each curve (6000 evenly, its knots, where
its corners are, 4 inside each knot span, and more wherever two neighbours lie farther apart
than 1/96000 of its size) to the 4 nearest samples of the other (a k-d tree), each refined by
a golden-section search of the exact point-to-curve distance on either side of it, up to its
neighbours. It must be within the case's tolerance, no more than the reported
max_deviation, and the report no more than a fifth of the tolerance above it (the true
distance, not a loose bound). Exact surfaces (count 0) must pass through their sections
(1e-9 of the size). The meshes of smooth objects (vase, bottle, ellipse sweep: dense mesh
loops, a C0 knot per facet) must skin light at the default tolerance (they fell back to the
exact surface when the check was parametric).
Prints one line per case and a TAP-like summary; exits 1 on any failure.
"""
import json
import sys

import numpy as np
from scipy.interpolate import BSpline
from scipy.spatial import cKDTree

SAMPLES = 6000
WINDOWS = 4  # nearest samples searched around (across a sharp edge one can be nearer)
GOLD = (np.sqrt(5.0) - 1) / 2


def section(path):
    d = json.load(open(path))
    t, p = np.array(d["knots"], float), d["degree"]
    B = BSpline(t, np.array(d["control_points"], float), p)
    return B, t[p], t[len(t) - p - 1], t


def iso(path, v):
    d = json.load(open(path))
    P = np.array(d["control_points"], float)  # nu x nv x 3
    kv, q = np.array(d["knots_v"], float), d["degree_v"]
    rows = np.array([BSpline(kv, P[i], q)(v) for i in range(P.shape[0])])
    ku, p = np.array(d["knots_u"], float), d["degree_u"]
    return BSpline(ku, rows, p), ku[p], ku[len(ku) - p - 1]


def curve_fn(B, a, b):
    """x in [0, 1) (any real, wrapped) -> points."""
    return lambda x: B(a + (b - a) * np.mod(x, 1.0))


def params(knots):
    """Parameters of a curve's samples in [0, 1): SAMPLES evenly, its knots (given in [0, 1))
    and 4 inside each of its knot spans, so that a sliver span (auto leaves C0 knots 1e-13
    apart, and its piece can carry shape) has samples of its own; sorted."""
    k = np.unique(np.concatenate([knots, [1.0]]))
    inner = (k[:-1, None] + (k[1:] - k[:-1])[:, None] * np.array([0.2, 0.4, 0.6, 0.8])).ravel()
    x = np.unique(np.concatenate([np.arange(SAMPLES) / SAMPLES, k[:-1], inner]))
    return x[(x >= 0) & (x < 1)]


def spread(g, x):
    """x (sorted, in [0, 1)) with samples added between neighbours whose points are farther
    apart than the curve's size / (16 SAMPLES): where the curve is fast in its parameter (a
    trailing edge between corners) the nearest samples were all on the other side of the
    edge. Returns the parameters and their points."""
    G = g(x)
    hmax = np.ptp(G, axis=0).max() / (16 * SAMPLES)
    for _ in range(20):
        step = np.linalg.norm(np.diff(np.vstack([G, G[:1]]), axis=0), axis=1)
        far = np.nonzero(step > hmax)[0]
        if len(far) == 0:
            break
        nxt = np.where(far + 1 < len(x), x[(far + 1) % len(x)], x[0] + 1.0)
        mid = np.mod(0.5 * (x[far] + nxt), 1.0)
        order = np.argsort(np.concatenate([x, mid]), kind="stable")
        x = np.concatenate([x, mid])[order]
        G = np.vstack([G, g(mid)])[order]
    return x, G


def one_way(f, xs, g, gk):
    """max over the points f(xs) of their exact distance to the closed curve g (knots gk in
    [0, 1)): the WINDOWS nearest samples of g, each refined between its neighbours."""
    X0 = f(xs)
    gx, G = spread(g, params(gk))
    n = len(gx)
    _, j = cKDTree(G).query(X0, k=WINDOWS)
    X = np.repeat(X0, WINDOWS, axis=0)
    j = j.reshape(-1)
    lo = np.where(j > 0, gx[(j - 1) % n], gx[-1] - 1.0)
    hi = np.where(j < n - 1, gx[(j + 1) % n], gx[0] + 1.0)

    def dist(y):
        return np.linalg.norm(g(y) - X, axis=1)

    def golden(lo, hi):
        c, d = hi - GOLD * (hi - lo), lo + GOLD * (hi - lo)
        fc, fd = dist(c), dist(d)
        for _ in range(30):
            left = fc < fd
            hi = np.where(left, d, hi)
            lo = np.where(left, lo, c)
            c, d = hi - GOLD * (hi - lo), lo + GOLD * (hi - lo)
            fc, fd = dist(c), dist(d)
        return np.minimum(fc, fd)

    # each side of the sample apart: the distance need not be unimodal across a corner, and
    # corners (knots) are samples
    near = np.minimum(np.minimum(golden(lo, gx[j]), golden(gx[j], hi)), dist(gx[j]))
    return near.reshape(-1, WINDOWS).min(axis=1).max()


def hausdorff(sec, S):
    B, a, b, t = sec
    f, g = curve_fn(B, a, b), curve_fn(S[0], S[1], S[2])
    knots = (t[(t >= a) & (t < b)] - a) / (b - a)
    ku = S[0].t
    sk = (ku[(ku >= S[1]) & (ku < S[2])] - S[1]) / (S[2] - S[1])
    xs = np.concatenate([params(knots) + 0.37 / SAMPLES, knots])
    ys = np.concatenate([params(sk) + 0.61 / SAMPLES, sk])
    return max(one_way(f, np.mod(xs, 1.0), g, sk), one_way(g, np.mod(ys, 1.0), f, knots))


def main(d):
    fails, light, exact, worst_gap = 0, 0, 0, 0.0
    for line in open(d + "/cases.txt"):
        w = line.split()
        name, tol, count, dev, K = w[0], float(w[1]), int(w[2]), float(w[3]), int(w[4])
        v = [float(x) for x in w[5:5 + K]]
        measured, size = 0.0, 0.0
        for k in range(K):
            sec = section("%s/%s.section%d.json" % (d, name, k + 1))
            pts = sec[0](np.linspace(sec[1], sec[2], 64))
            size = max(size, float(np.ptp(pts, axis=0).max()))
            measured = max(measured, hausdorff(sec, iso("%s/%s.surface.json" % (d, name), v[k])))
        if count > 0:
            light += 1
            ok = measured <= tol * (1 + 1e-9) and measured <= dev * (1 + 1e-6) + 1e-13 \
                and dev <= tol and dev - measured <= 0.2 * tol
            worst_gap = max(worst_gap, (dev - measured) / tol)
        else:
            exact += 1
            ok = measured <= 1e-9 * size
        if name.split("-")[0] in ("vase", "bottle", "ellipse") and "-m" in name \
                and name.endswith("-x1") and count == 0:
            ok = False
        fails += not ok
        print("%s %s: tol %.4g, %s, measured %.6g, reported %.6g" % (
            "ok" if ok else "not ok", name, tol, "%d columns" % (count + 3) if count else "exact",
            measured, dev))
    print("# %d light, %d exact; the report above the measured distance by at most %.3g of tol"
          % (light, exact, worst_gap))
    print("%d passed, %d failed" % (light + exact - fails, fails))
    return 1 if fails else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1]))
