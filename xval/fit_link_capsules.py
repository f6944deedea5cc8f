"""Fits the Panda's link colliders (robots/src/panda.rs) to robosuite's collision meshes.

MuJoCo collides each link as the convex hull of robosuite's `meshes/linkN.stl`. We collide two
capsules per link: this script finds, for links 1-7, the two capsules (in the link's body frame)
whose union differs least in volume from that hull, and prints them as `capsule(...)` lines with
how much of the hull they leave out and how far they overhang it.

Needs numpy and scipy, and robosuite 1.4's files (found without importing robosuite, which wants
OpenCV): `python xval/fit_link_capsules.py [robosuite's models/assets/robots/panda/meshes]`.
"""

import importlib.util
import os
import struct
import sys

import numpy as np
from scipy.optimize import minimize
from scipy.spatial import ConvexHull

SAMPLES = 12000
# Width (m) of the smooth inside/outside step the optimizer sees.
TAU = 0.002


def mesh_dir():
    if len(sys.argv) > 1:
        return sys.argv[1]
    spec = importlib.util.find_spec("robosuite")
    if spec is None or not spec.submodule_search_locations:
        sys.exit("robosuite is not installed; pass its models/assets/robots/panda/meshes folder")
    return os.path.join(spec.submodule_search_locations[0], "models", "assets", "robots", "panda", "meshes")


def stl_vertices(path):
    data = open(path, "rb").read()
    n = struct.unpack("<I", data[80:84])[0]
    if len(data) < 84 + 50 * n:
        sys.exit(f"{path}: not a binary STL of {n} triangles")
    rec = np.frombuffer(data[84:84 + 50 * n], dtype=np.dtype([("n", "<3f4"), ("v", "<9f4"), ("a", "<u2")]))
    return np.unique(rec["v"].reshape(-1, 3).astype(float), axis=0)


def segment_distance(p, a, b):
    d = b - a
    t = np.clip(((p - a) @ d) / max(d @ d, 1e-12), 0.0, 1.0)
    return np.linalg.norm(p - (a + t[:, None] * d), axis=1)


def capsules_distance(p, x, k):
    """Signed distance to the union of k capsules packed as (a, b, r) * k."""
    return np.min([segment_distance(p, x[7 * j:7 * j + 3], x[7 * j + 3:7 * j + 6]) - abs(x[7 * j + 6]) for j in range(k)], axis=0)


def initial_guesses(v, k):
    """Split the vertices along each principal axis and wrap each part in a capsule."""
    c = v.mean(0)
    _, _, axes = np.linalg.svd(v - c)
    for axis in axes:
        s = (v - c) @ axis
        labels = np.digitize(s, np.quantile(s, np.linspace(0, 1, k + 1)[1:-1]))
        x = []
        for j in range(k):
            part = v[labels == j] if (labels == j).sum() >= 2 else v
            cp = part.mean(0)
            _, _, w = np.linalg.svd(part - cp)
            t = (part - cp) @ w[0]
            r = np.linalg.norm((part - cp) - np.outer(t, w[0]), axis=1).mean()
            x += list(cp + (t.min() + r) * w[0]) + list(cp + (t.max() - r) * w[0]) + [r]
        yield np.array(x)


def fit(v, k, rng):
    hull = ConvexHull(v)
    eq = hull.equations
    lo, hi = v.min(0) - 0.02, v.max(0) + 0.02
    samples = rng.uniform(lo, hi, size=(SAMPLES, 3))
    hull_d = (samples @ eq[:, :3].T + eq[:, 3]).max(1)
    sig = lambda z: 1.0 / (1.0 + np.exp(-z))
    target = sig(-hull_d / TAU)
    best = None
    for x0 in initial_guesses(v, k):
        loss = lambda x: np.mean((sig(-capsules_distance(samples, x, k) / TAU) - target) ** 2)
        x = minimize(loss, x0, method="L-BFGS-B", options={"maxiter": 300}).x
        mismatch = np.mean((hull_d <= 0) ^ (capsules_distance(samples, x, k) <= 0)) * np.prod(hi - lo)
        if best is None or mismatch < best[0]:
            best = (mismatch, x)
    mismatch, x = best
    left_out = max(0.0, capsules_distance(v[hull.vertices], x, k).max())
    overhang = 0.0
    for j in range(k):
        a, b, r = x[7 * j:7 * j + 3], x[7 * j + 3:7 * j + 6], abs(x[7 * j + 6])
        d = rng.normal(size=(4000, 3))
        d /= np.linalg.norm(d, axis=1)[:, None]
        p = a + rng.uniform(0, 1, 4000)[:, None] * (b - a) + r * d
        p = p[capsules_distance(p, x, k) > -1e-6]
        if len(p):
            overhang = max(overhang, (p @ eq[:, :3].T + eq[:, 3]).max(1).max())
    return x, mismatch, hull.volume, left_out, overhang


def main():
    folder = mesh_dir()
    rng = np.random.default_rng(0)
    for link in range(1, 8):
        v = stl_vertices(os.path.join(folder, f"link{link}.stl"))
        x, mismatch, volume, left_out, overhang = fit(v, 2, rng)
        print(f"// link{link}: differs from the hull ({volume * 1e3:.2f} L) by {mismatch * 1e3:.2f} L; "
              f"leaves out {left_out * 1e3:.1f} mm, overhangs {overhang * 1e3:.1f} mm")
        for j in range(2):
            a, b, r = x[7 * j:7 * j + 3], x[7 * j + 3:7 * j + 6], abs(x[7 * j + 6])
            fmt = lambda p: ", ".join(f"{c:.4f}" for c in p)
            print(f'capsule("link{link}", {r:.4f}, [{fmt(a)}], [{fmt(b)}]),')


if __name__ == "__main__":
    main()
