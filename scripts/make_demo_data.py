#!/usr/bin/python3
"""make_demo_data.py: generates the demo cross-sections of tests/data/demo and the broken
inputs of tests/data/bad.

Run from anywhere with Debian's python3 (numpy needed):  /usr/bin/python3 scripts/make_demo_data.py
The output is deterministic (fixed seed, fixed formatting), so re-running it gives
byte-identical files.

Every demo file is one closed section: points ordered along the contour, counter-
clockwise, the first point NOT repeated at the end; CSV with a header line `x,y`
(or `x,y,w` with a per-point weight). Units are millimetres.

  cam.csv            a cam: base circle plus one smooth lobe (cosine lift), sampled
                     evenly in angle, so the lobe's flanks are sampled more sparsely
  airfoil.csv        NACA 2412 (closed-trailing-edge form) with cosine spacing: dense at
                     the rounded leading edge, one sharp trailing-edge point
  bracket.csv        a rounded rectangle with a sharp-cornered rectangular notch: long
                     straight runs, tight arcs, right-angle corners
  noisy_blob.csv     a smooth three-lobed blob with Gaussian noise (sigma = 0.5% of size)
  knob_weighted.csv  a five-lobed knob, x,y,w: a few outliers pushed off the contour
                     carry weight 0.05, every other point weight 1
"""

import os

import numpy as np

SEED = 20240521
HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)
DEMO = os.path.join(ROOT, "tests", "data", "demo")
BAD = os.path.join(ROOT, "tests", "data", "bad")


def write_csv(path, xy, w=None):
    """Writes points (and weights) with 6 decimals, '\n' line ends."""
    with open(path, "w", newline="\n") as f:
        f.write("x,y,w\n" if w is not None else "x,y\n")
        for i, (x, y) in enumerate(xy):
            # "+ 0.0" turns -0.0 into 0.0, so no "-0.000000" appears
            row = "%.6f,%.6f" % (round(x, 6) + 0.0, round(y, 6) + 0.0)
            if w is not None:
                row += ",%g" % w[i]
            f.write(row + "\n")


def polar(r, t):
    return np.column_stack((r * np.cos(t), r * np.sin(t)))


def cam(m=180):
    """Base circle of radius 20 with a lobe of lift 8 over 140 degrees."""
    t = 2.0 * np.pi * np.arange(m) / m
    half = np.radians(70.0)
    d = np.angle(np.exp(1j * (t - np.pi / 2)))  # angle from the lobe's axis (90 deg)
    lift = np.where(np.abs(d) < half, 8.0 * 0.5 * (1.0 + np.cos(np.pi * d / half)), 0.0)
    return polar(20.0 + lift, t)


def airfoil(n_side=70, chord=100.0):
    """NACA 2412: m = 0.02, p = 0.4, t = 0.12; the -0.1036 coefficient closes the
    trailing edge. Upper surface from the trailing edge to the leading edge, then the
    lower surface back; the trailing edge appears once, the leading edge once."""
    mc, p, th = 0.02, 0.4, 0.12
    beta = np.linspace(0.0, np.pi, n_side + 1)
    x = 0.5 * (1.0 - np.cos(beta))  # cosine spacing, 0 .. 1
    yt = 5 * th * (0.2969 * np.sqrt(x) - 0.1260 * x - 0.3516 * x**2 + 0.2843 * x**3 - 0.1036 * x**4)
    yc = np.where(x < p, mc / p**2 * (2 * p * x - x**2),
                  mc / (1 - p) ** 2 * ((1 - 2 * p) + 2 * p * x - x**2))
    dyc = np.where(x < p, 2 * mc / p**2 * (p - x), 2 * mc / (1 - p) ** 2 * (p - x))
    phi = np.arctan(dyc)
    xu, yu = x - yt * np.sin(phi), yc + yt * np.cos(phi)
    xl, yl = x + yt * np.sin(phi), yc - yt * np.cos(phi)
    upper = np.column_stack((xu, yu))[::-1]  # trailing edge -> leading edge
    lower = np.column_stack((xl, yl))[1:-1]  # after the leading edge, before the trailing edge
    return chord * np.vstack((upper, lower))


def segment(a, b, step):
    """Points from a (included) towards b (excluded), spacing about `step`."""
    a, b = np.asarray(a, float), np.asarray(b, float)
    n = max(1, int(round(np.linalg.norm(b - a) / step)))
    f = np.arange(n)[:, None] / n
    return a + f * (b - a)


def arc(c, r, t0, t1, n):
    """n points of the arc from angle t0 (included) to t1 (excluded)."""
    t = t0 + (t1 - t0) * np.arange(n) / n
    return np.column_stack((c[0] + r * np.cos(t), c[1] + r * np.sin(t)))


def bracket(step=2.0):
    """60 x 30 rectangle, corners rounded with radius 3, and a notch 12 wide and 8 deep
    in the middle of the top side with sharp corners."""
    W, H, R = 60.0, 30.0, 3.0
    q = np.pi / 2
    nl, nr = 24.0, 36.0  # notch x range
    parts = [
        segment((R, 0), (W - R, 0), step),
        arc((W - R, R), R, -q, 0, 4),
        segment((W, R), (W, H - R), step),
        arc((W - R, H - R), R, 0, q, 4),
        segment((W - R, H), (nr, H), step),
        segment((nr, H), (nr, H - 8), step),
        segment((nr, H - 8), (nl, H - 8), step),
        segment((nl, H - 8), (nl, H), step),
        segment((nl, H), (R, H), step),
        arc((R, H - R), R, q, 2 * q, 4),
        segment((0, H - R), (0, R), step),
        arc((R, R), R, 2 * q, 3 * q, 4),
    ]
    return np.vstack(parts)


def noisy_blob(rng, m=200):
    """r = 30 (1 + 0.15 cos 3t + 0.08 sin 2t), noise sigma = 0.005 * 60 = 0.3."""
    t = 2.0 * np.pi * np.arange(m) / m
    xy = polar(30.0 * (1.0 + 0.15 * np.cos(3 * t) + 0.08 * np.sin(2 * t)), t)
    return xy + rng.normal(0.0, 0.005 * 60.0, size=xy.shape)


def knob(rng, m=150, n_out=5):
    """r = 25 + 3 cos 5t; n_out points pushed 3..5 mm outwards or inwards, weight 0.05."""
    t = 2.0 * np.pi * np.arange(m) / m
    r = 25.0 + 3.0 * np.cos(5 * t)
    w = np.ones(m)
    out = np.sort(rng.choice(m, size=n_out, replace=False))
    r[out] += rng.choice([-1.0, 1.0], size=n_out) * rng.uniform(3.0, 5.0, size=n_out)
    w[out] = 0.05
    return polar(r, t), w


def write_bad():
    os.makedirs(BAD, exist_ok=True)
    open(os.path.join(BAD, "empty.csv"), "w").close()
    with open(os.path.join(BAD, "text.csv"), "w", newline="\n") as f:
        f.write("x,y\n0,0\n1,0\n1,abc\n0,1\n")
    with open(os.path.join(BAD, "nan.csv"), "w", newline="\n") as f:
        f.write("x,y\n0,0\n1,0\nnan,1\n0,1\n")
    with open(os.path.join(BAD, "two_points.csv"), "w", newline="\n") as f:
        f.write("x,y\n0,0\n1,0\n")


def main():
    rng = np.random.default_rng(SEED)
    os.makedirs(DEMO, exist_ok=True)
    write_csv(os.path.join(DEMO, "cam.csv"), cam())
    write_csv(os.path.join(DEMO, "airfoil.csv"), airfoil())
    write_csv(os.path.join(DEMO, "bracket.csv"), bracket())
    write_csv(os.path.join(DEMO, "noisy_blob.csv"), noisy_blob(rng))
    xy, w = knob(rng)
    write_csv(os.path.join(DEMO, "knob_weighted.csv"), xy, w)
    write_bad()


if __name__ == "__main__":
    main()
