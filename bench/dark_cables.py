#!/usr/bin/python3
"""Dark cables: a campaign's scans with points taken off the cables, as a structured-light sensor loses them on
black or glossy jackets, for `ewis evaluate --campaign OUT`.

Each scene of --campaign (the layout `ewis simulate --campaign` writes: scan.ply in the sensor's frame, truth.json
with `camera_to_cad` and each cable's as-built centreline and diameter) is copied to --out with its scan thinned:
a scan point is a cable point when it lies within the cable's radius + 1 mm of its truth centreline (in CAD
coordinates), and of those
  - random:  each is kept with probability --keep;
  - patch:   blobs of 1.5-4 mm radius centred on cable points are taken away until --keep of them remain (holes);
  - grazing: those whose surface normal (from the centreline) makes an angle with the sensor's ray whose cosine is
             under --keep are taken away (the flanks, where a dark surface returns too little light);
  - grazing-random: as grazing, and half of the rest at random.
Everything else in the scene (the CAD, plan, truth, pose) is copied as it is; the truth stays right, since only
points are removed. numpy only. Binary little-endian PLY with float x y z first, as `ewis simulate` writes.

Usage: dark_cables.py --campaign C --out DIR --keep 0.5 --mode patch [--scenes 20] [--seed 1]
"""
import argparse
import json
import os
import shutil
import sys

import numpy as np


def read_scan(path):
    with open(path, "rb") as fh:
        data = fh.read()
    end = data.index(b"end_header\n") + len(b"end_header\n")
    header = data[:end].decode()
    lines = header.splitlines()
    if "format binary_little_endian 1.0" not in lines:
        sys.exit("%s: not a binary little-endian PLY" % path)
    n = int([l for l in lines if l.startswith("element vertex")][0].split()[2])
    props = [l.split()[-1] for l in lines if l.startswith("property")]
    if props != ["x", "y", "z"] or any(l.split()[1] != "float" for l in lines if l.startswith("property")):
        sys.exit("%s: expected float x y z only, found %s" % (path, props))
    pts = np.frombuffer(data[end:end + 12 * n], dtype="<f4").reshape(n, 3)
    return header, n, pts


def cable_points(P, truth, eye):
    """Which points lie on a cable, and the cosine between each one's surface normal and its ray."""
    n = len(P)
    on = np.zeros(n, bool)
    cosv = np.ones(n)
    for c in truth["cables"]:
        cl = np.array(c["centerline"])
        r = c["diameter_mm"] / 2 + 1.0
        lo, hi = cl.min(0) - r, cl.max(0) + r
        idx = np.where(np.all((P >= lo) & (P <= hi), axis=1))[0]
        for s in range(0, len(idx), 20000):
            ii = idx[s:s + 20000]
            dd = ((P[ii, None, :] - cl[None, :, :]) ** 2).sum(-1)
            j = dd.argmin(1)
            sel = dd[np.arange(len(ii)), j] <= r * r
            nrm = P[ii] - cl[j]
            nrm /= np.linalg.norm(nrm, axis=1)[:, None] + 1e-12
            ray = P[ii] - eye
            ray /= np.linalg.norm(ray, axis=1)[:, None]
            cv = np.abs((nrm * ray).sum(1))
            cosv[ii[sel]] = np.minimum(cosv[ii[sel]], cv[sel])
            on[ii[sel]] = True
    return on, cosv


def darken(src, dst, keep, mode, rng):
    os.makedirs(dst, exist_ok=True)
    for f in os.listdir(src):
        if f != "scan.ply" and os.path.isfile(os.path.join(src, f)):
            shutil.copy(os.path.join(src, f), dst)
    truth = json.load(open(os.path.join(src, "truth.json")))
    header, n, pts = read_scan(os.path.join(src, "scan.ply"))
    T = np.array(truth["camera_to_cad"])
    P = pts.astype(np.float64) @ T[:3, :3].T + T[:3, 3]
    on, cosv = cable_points(P, truth, T[:3, 3])
    drop = np.zeros(n, bool)
    if mode == "random":
        drop = on & (rng.random(n) > keep)
    elif mode in ("grazing", "grazing-random"):
        drop = on & (cosv < keep)
        if mode == "grazing-random":
            drop |= on & (rng.random(n) > 0.5)
    else:  # patch
        cand = np.where(on)[0]
        target = int((1 - keep) * len(cand))
        while len(cand) and drop[cand].sum() < target:
            c0 = P[rng.choice(cand)]
            rad = rng.uniform(1.5, 4.0)
            drop[cand[((P[cand] - c0) ** 2).sum(1) <= rad * rad]] = True
    kept = pts[~drop]
    with open(os.path.join(dst, "scan.ply"), "wb") as fh:
        fh.write(header.replace("element vertex %d" % n, "element vertex %d" % len(kept)).encode())
        fh.write(np.ascontiguousarray(kept, dtype="<f4").tobytes())
    return int(on.sum()), int(drop.sum())


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--campaign", required=True)
    ap.add_argument("--out", required=True)
    ap.add_argument("--keep", type=float, required=True)
    ap.add_argument("--mode", choices=["random", "patch", "grazing", "grazing-random"], required=True)
    ap.add_argument("--scenes", type=int, default=0, help="the first N scenes (0: all)")
    ap.add_argument("--seed", type=int, default=1)
    a = ap.parse_args()
    scenes = sorted(d for d in os.listdir(a.campaign) if d.startswith("scene_"))
    if a.scenes > 0:
        scenes = scenes[:a.scenes]
    for i, s in enumerate(scenes):
        rng = np.random.default_rng([a.seed, i])
        on, dropped = darken(os.path.join(a.campaign, s), os.path.join(a.out, s), a.keep, a.mode, rng)
        print("%s: %d cable points, %d taken away" % (s, on, dropped), file=sys.stderr)


if __name__ == "__main__":
    main()
