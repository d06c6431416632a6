#!/usr/bin/python3
"""Depth noise: a campaign's scans with a share of their pixels given a wrong range along the sensor's ray, as other
simulators make outliers (a halo about every surface) and as a structured-light sensor errs (a mismatched stripe, a
lost correspondence), for `ewis evaluate --campaign OUT`.

Each scene of --campaign (the layout `ewis simulate --campaign` writes: scan.ply in the sensor's frame, the sensor at
the origin) is copied to --out with --fraction of its points moved along their own ray (--direction ray), in any
direction (any) or across their ray only (across) by
  - gauss:   a Gaussian of --scale mm (sigma; per axis for any and across);
  - uniform: a uniform draw in [-scale, scale] mm (along a random direction for any and across).
With --add the moved points are copies (the scan grows by fraction / (1 - fraction) of its points, every pixel keeps
its right range too: the cloud of a simulator that adds outliers); without it they replace the points they came from
(one range a pixel, as a sensor gives). --fraction 1 --mode gauss is more sensor noise on every point. Everything else
(the CAD, plan, truth, pose) is copied as it is; the truth stays right: no surface moved. numpy only; reads and writes
binary little-endian PLY with float x y z, as `ewis simulate` writes.

Usage: depth_noise.py --campaign C --out DIR --fraction 0.4 --mode gauss --scale 1.5 [--direction ray|any|across]
                      [--add] [--scenes N] [--seed 1]
"""
import argparse
import os
import shutil
import sys

import numpy as np

from dark_cables import read_scan


def offsets(ray, mode, scale, direction, rng):
    """The moves of points whose unit rays are `ray` (m x 3)."""
    m = len(ray)
    if direction == "ray":
        size = rng.normal(0.0, scale, m) if mode == "gauss" else rng.uniform(-scale, scale, m)
        return ray * size[:, None]
    if mode == "gauss":
        move = rng.normal(0.0, scale, (m, 3))
    else:
        unit = rng.normal(0.0, 1.0, (m, 3))
        unit /= np.maximum(np.linalg.norm(unit, axis=1), 1e-12)[:, None]
        move = unit * rng.uniform(-scale, scale, m)[:, None]
    if direction == "across":
        move -= ray * (move * ray).sum(1)[:, None]
    return move


def add_noise(src, dst, fraction, mode, scale, direction, add, rng):
    os.makedirs(dst, exist_ok=True)
    for f in os.listdir(src):
        if f != "scan.ply" and os.path.isfile(os.path.join(src, f)):
            shutil.copy(os.path.join(src, f), dst)
    header, n, pts = read_scan(os.path.join(src, "scan.ply"))
    if add:
        m = int(round(n * fraction / (1.0 - fraction)))
        pick = rng.integers(0, n, m)
    else:
        m = int(round(n * fraction))
        pick = rng.permutation(n)[:m]
    Q = pts[pick].astype(np.float64)
    ray = Q / np.maximum(np.linalg.norm(Q, axis=1), 1e-9)[:, None]
    Q += offsets(ray, mode, scale, direction, rng)
    if add:
        out = np.vstack([pts, Q.astype(np.float32)])
        out = out[rng.permutation(len(out))]
    else:
        out = pts.copy()
        out[pick] = Q.astype(np.float32)
    with open(os.path.join(dst, "scan.ply"), "wb") as fh:
        fh.write(header.replace("element vertex %d" % n, "element vertex %d" % len(out)).encode())
        fh.write(np.ascontiguousarray(out, dtype="<f4").tobytes())
    return n, m


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--campaign", required=True)
    ap.add_argument("--out", required=True)
    ap.add_argument("--fraction", type=float, required=True, help="share of the points moved (0-1; below 1 with --add)")
    ap.add_argument("--mode", choices=["gauss", "uniform"], required=True)
    ap.add_argument("--scale", type=float, required=True, help="mm: the Gaussian's sigma, or the uniform's half range")
    ap.add_argument("--direction", choices=["ray", "any", "across"], default="ray",
                    help="along the point's ray (a sensor's wrong range), in any direction, or across the ray")
    ap.add_argument("--add", action="store_true", help="the moved points are copies added to the scan")
    ap.add_argument("--scenes", type=int, default=0, help="the first N scenes (0: all)")
    ap.add_argument("--seed", type=int, default=1)
    a = ap.parse_args()
    if not 0.0 <= a.fraction <= 1.0 or (a.add and a.fraction >= 1.0):
        sys.exit("--fraction must be in [0, 1] (below 1 with --add)")
    scenes = sorted(d for d in os.listdir(a.campaign) if d.startswith("scene_"))
    if a.scenes > 0:
        scenes = scenes[:a.scenes]
    for i, s in enumerate(scenes):
        rng = np.random.default_rng([a.seed, i])
        n, m = add_noise(os.path.join(a.campaign, s), os.path.join(a.out, s), a.fraction, a.mode, a.scale, a.direction,
                         a.add, rng)
        print("%s: %d points, %d moved%s" % (s, n, m, " (added)" if a.add else ""), file=sys.stderr)


if __name__ == "__main__":
    main()
