#!/usr/bin/python3
"""A campaign's scans written or framed another way, for checking that the inspection does not depend on how our own
simulator writes them. Each variant copies the campaign (CAD, plan and truth linked, not copied) with scan.ply (and
for xfwd pose.txt) replaced; scans must be binary little-endian PLY of float x y z (as `ewis simulate` writes them):
  - window U0 U1 V0 V1: only the points the sensor saw within that part of its image (fractions of its width and
    height, the plan's 1280 x 1024 px, 58 deg): the cables and the structure leave the view at its edges, and less of
    the rigid CAD is seen (a view of part of a larger assembly);
  - shuffle: the points in a random order (a scan that is not in raster order: merged, filtered or converted);
  - xfwd: the sensor frame turned to look along x (ROS's body convention: x forward, y left, z up) with pose.txt
    turned with it (truth.json's camera_to_cad is left as it was: evaluate's registration error is then not
    meaningful, the verdicts and measures are).
Usage: scan_variants.py CAMPAIGN OUT window 0.2 0.8 0.15 0.85 | shuffle | xfwd [--scenes N] [--seed S]
"""
import argparse
import math
import os

import numpy as np

# x-forward frame: (x, y, z) of the camera -> (z, -x, -y)
X_FORWARD = np.array([[0, 0, 1], [-1, 0, 0], [0, -1, 0]], dtype=float)


def read_ply(path):
    raw = open(path, 'rb').read()
    k = raw.index(b'end_header\n') + len(b'end_header\n')
    header = raw[:k].decode('ascii', 'replace')
    if 'binary_little_endian' not in header or header.count('property') != 3 or 'property float x' not in header:
        raise SystemExit('%s: only binary little-endian PLY of float x y z is read here' % path)
    return np.frombuffer(raw[k:], dtype='<f4').reshape(-1, 3).astype(np.float64)


def write_ply(path, P):
    with open(path, 'wb') as o:
        o.write(b'ply\nformat binary_little_endian 1.0\nelement vertex %d\nproperty float x\nproperty float y\n'
                b'property float z\nend_header\n' % len(P))
        o.write(P.astype('<f4').tobytes())


def main():
    ap = argparse.ArgumentParser(description=__doc__.split('\n')[0])
    ap.add_argument('campaign')
    ap.add_argument('out')
    ap.add_argument('variant', choices=['window', 'shuffle', 'xfwd'])
    ap.add_argument('window', nargs='*', type=float, help='U0 U1 V0 V1 (window)')
    ap.add_argument('--scenes', type=int, default=0, help='the first N scenes only (0: all)')
    ap.add_argument('--seed', type=int, default=45)
    a = ap.parse_args()
    if a.variant == 'window' and len(a.window) != 4:
        raise SystemExit('window needs U0 U1 V0 V1')
    rng = np.random.default_rng(a.seed)
    width, height = 1280, 1024
    f = (width / 2) / math.tan(math.radians(29.0))
    scenes = sorted(d for d in os.listdir(a.campaign) if os.path.exists(os.path.join(a.campaign, d, 'scan.ply')))
    if a.scenes:
        scenes = scenes[:a.scenes]
    for name in scenes:
        src, dst = os.path.join(a.campaign, name), os.path.join(a.out, name)
        os.makedirs(dst, exist_ok=True)
        replaced = {'scan.ply'} | ({'pose.txt'} if a.variant == 'xfwd' else set())
        for fn in os.listdir(src):
            if fn not in replaced and not os.path.exists(os.path.join(dst, fn)):
                os.symlink(os.path.abspath(os.path.join(src, fn)), os.path.join(dst, fn))
        P = read_ply(os.path.join(src, 'scan.ply'))
        if a.variant == 'window':
            u0, u1, v0, v1 = a.window
            with np.errstate(divide='ignore', invalid='ignore'):
                u = f * P[:, 0] / P[:, 2] + width / 2
                v = f * P[:, 1] / P[:, 2] + height / 2
            P = P[(P[:, 2] > 0) & (u >= u0 * width) & (u < u1 * width) & (v >= v0 * height) & (v < v1 * height)]
        elif a.variant == 'shuffle':
            P = P[rng.permutation(len(P))]
        else:
            P = P @ X_FORWARD.T
            T = np.loadtxt(os.path.join(src, 'pose.txt')).reshape(4, 4)
            M = np.eye(4)
            M[:3, :3] = X_FORWARD
            np.savetxt(os.path.join(dst, 'pose.txt'), T @ np.linalg.inv(M), fmt='%.12g')
        write_ply(os.path.join(dst, 'scan.ply'), P)


if __name__ == '__main__':
    main()
