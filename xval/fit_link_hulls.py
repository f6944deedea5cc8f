"""Fits the Panda's convex link colliders (robots/src/panda_hulls.rs) to robosuite's collision meshes.

MuJoCo collides each Panda link, and the gripper's hand, as the convex hull of robosuite's collision
mesh (`linkN.stl`, `hand.stl`), and lets every pair of them touch but parent and child. Capsules
could not stand in for those hulls where the arm touches itself (see the limit sequences in docs/measurements.md).
This script keeps, for each hull, a small subset of its corners for rapier (which computes every
collider's bounding box at each step from all its corners): it removes corners one at a time, each time the one whose removal lets the fewest
millimetres of the full hull stick out, while that stays within `--tolerance` or more than
`--max-points` corners are left (link 1's 1,588 corners are first thinned to 160 spread ones). The
joint housings are round, so at 64 corners the full hulls stick out by 1-2.5 mm. The kept corners
are rounded to 0.1 mm and printed as the Rust source of `robots/src/panda_hulls.rs`, with how far
the full hull sticks out of each fitted one (the fitted hull lies inside the full one). The arm's
contacts with itself, soft as MuJoCo's and found only where two bounding boxes overlap, use the
full hull (`<NAME>_FULL`, every corner, rounded to 0.01 mm), and so do the fingers (`FINGER1_FULL`,
`FINGER2_FULL`). Link 1's was once thinned to 160 spread corners, 2 mm inside MuJoCo's: a finger
that MuJoCo saw touch link 1 (`fast_j2_lo_j4_lo`, record 55) stayed 0.25 mm clear of it.

Needs numpy and scipy, and robosuite 1.4's files (found without importing robosuite, which wants
OpenCV):
    python xval/fit_link_hulls.py [robosuite's models/assets folder] > robots/src/panda_hulls.rs
"""

import argparse
import importlib.util
import os
import sys

import numpy as np
from scipy.spatial import ConvexHull

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from fit_link_capsules import stl_vertices  # noqa: E402

# (Rust constant, mesh under models/assets, rotation of the mesh in the collider's body frame as
# MuJoCo's geom quat (w, x, y, z), whether rapier gets a fitted subset): robosuite's link geoms sit at
# their body's origin; the hand's is turned 90° about z in the gripper's root body, the second
# finger's 180°. Link 7 has no collision geom in robosuite. rapier collides the fingers as boxes.
# Corners the greedy removal starts from at most.
DENSE = 160
HULLS = [(f"LINK{k}", f"robots/panda/meshes/link{k}.stl", (1.0, 0.0, 0.0, 0.0), True) for k in range(7)] + [
    ("HAND", "grippers/meshes/panda_gripper/hand.stl", (0.707107, 0.0, 0.0, 0.707107), True),
    ("FINGER1", "grippers/meshes/panda_gripper/finger.stl", (1.0, 0.0, 0.0, 0.0), False),
    ("FINGER2", "grippers/meshes/panda_gripper/finger.stl", (0.0, 0.0, 0.0, 1.0), False),
]


def assets_dir(arg):
    if arg:
        return arg
    spec = importlib.util.find_spec("robosuite")
    if spec is None or not spec.submodule_search_locations:
        sys.exit("robosuite is not installed; pass its models/assets folder")
    return os.path.join(spec.submodule_search_locations[0], "models", "assets")


def rotate(v, q):
    w, x, y, z = q
    r = np.array([[1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)],
                  [2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)],
                  [2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)]])
    return v @ r.T


def sticking_out(points, corners):
    """How far the farthest of `points` lies outside the hull of `corners` (0 when all are inside)."""
    eq = ConvexHull(corners).equations
    return max(0.0, float((points @ eq[:, :3].T + eq[:, 3]).max()))


def farthest_points(points, n):
    """`n` of `points` spread over them (each the farthest from those taken), for dense hulls
    (link 1's has 1,588 corners), where removing corners one at a time would take hours."""
    if len(points) <= n:
        return points
    taken = [int(np.argmax(np.linalg.norm(points - points.mean(0), axis=1)))]
    gap = np.linalg.norm(points - points[taken[0]], axis=1)
    while len(taken) < n:
        taken.append(int(np.argmax(gap)))
        gap = np.minimum(gap, np.linalg.norm(points - points[taken[-1]], axis=1))
    return points[sorted(taken)]


def simplify(full, tolerance, max_points):
    """Corners of the hull `full`, removed greedily while it sticks out by at most `tolerance`."""
    corners = farthest_points(full, DENSE)
    while len(corners) > 5:
        error, i = min((sticking_out(full, np.delete(corners, i, axis=0)), i) for i in range(len(corners)))
        if error > tolerance and len(corners) <= max_points:
            break
        corners = np.delete(corners, i, axis=0)
    return corners


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("assets", nargs="?", help="robosuite's models/assets folder (default: the installed robosuite's)")
    ap.add_argument("--tolerance", type=float, default=0.001, help="how far (m) the full hull may stick out (default 1 mm)")
    ap.add_argument("--max-points", type=int, default=64, help="at most this many corners per hull (default 64)")
    args = ap.parse_args()
    root = assets_dir(args.assets)
    print("//! The Panda's convex link colliders: for each link and the hand, a few corners of the convex")
    print("//! hull MuJoCo collides (robosuite's collision mesh), fitted by `xval/fit_link_hulls.py` (its")
    print("//! docstring says how); body frame, metres. Generated: edit the script, not this file.")
    print()
    for name, path, quat, fitted in HULLS:
        v = rotate(stl_vertices(os.path.join(root, path)), quat)
        full = v[ConvexHull(v).vertices]
        if fitted:
            kept = np.round(simplify(full, args.tolerance, args.max_points), 4)
            out = sticking_out(full, kept)
            print(f"/// {len(kept)} of the hull's {len(full)} corners; the full hull sticks out of these by at most {out * 1e3:.1f} mm.")
            print_points(name, kept)
            print(f"{name}: {len(full)} -> {len(kept)} corners, full hull out by {out * 1e3:.2f} mm", file=sys.stderr)
        exact = np.round(full, 5)
        print(f"/// All {len(exact)} corners of the hull; it sticks out of them by at most {sticking_out(full, exact) * 1e3:.3f} mm.")
        print_points(f"{name}_FULL", exact, 5)


def print_points(name, points, decimals=4):
    print(f"pub(crate) const {name}: &[[f64; 3]] = &[")
    for p in points:
        print("    [" + ", ".join(f"{x + 0.0:.{decimals}f}" for x in p) + "],")  # + 0.0: no -0.0000
    print("];")


if __name__ == "__main__":
    main()
