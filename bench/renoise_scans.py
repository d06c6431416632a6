#!/usr/bin/python3
"""Other sensor noise models over a campaign's scans: copies a campaign to a new folder with every scan.ply re-noised.

The project's scanners put the noise along the camera rays (src/sim) or isotropic per axis (bench/second_scanner.py)
and draw their outliers from a sensor's physics (mixed pixels at depth edges, flying pixels, wrong depths along seen
rays). A simulator written by someone else may do neither. Start from a noise-free campaign (`ewis simulate --campaign N
--noise-free`: no noise, no outliers; the truth stays valid, only scan.ply changes) and choose:
  iso     isotropic Gaussian noise (sigma per axis); outliers (a fraction of the output): half uniform in the scan's
          bounding box grown by 50 mm, half near the surface (a surface point moved 1-8 mm in a random direction);
  isobox  isotropic Gaussian noise; all outliers uniform in the grown bounding box (the textbook model);
  ray     Gaussian noise along each point's ray from the sensor (constant sigma, whatever the range); outliers on
          surface points' rays at a uniformly random 0.7-1.3 times their range (a wrong stereo match).
Points are shuffled (no raster order). Evaluate with `ewis evaluate --campaign DST`.

Usage: renoise_scans.py SRC DST MODE SIGMA_MM OUTLIER_FRACTION SEED
"""
import os
import shutil
import sys

import numpy as np


def read_ply(path):
    data = open(path, 'rb').read()
    end = data.index(b'end_header\n') + len(b'end_header\n')
    header = data[:end].decode()
    if 'binary_little_endian' not in header:
        raise SystemExit(f'{path}: only binary little-endian PLY (as ewis simulate writes)')
    n = int(next(l for l in header.split('\n') if l.startswith('element vertex')).split()[2])
    props = [l.split() for l in header.split('\n') if l.startswith('property')]
    if [p[1:] for p in props] != [['float', 'x'], ['float', 'y'], ['float', 'z']]:
        raise SystemExit(f'{path}: expected float x y z only')
    return np.frombuffer(data[end:end + 12 * n], dtype='<f4').reshape(n, 3).astype(np.float64)


def write_ply(path, points):
    with open(path, 'wb') as f:
        f.write(b'ply\nformat binary_little_endian 1.0\ncomment re-noised by bench/renoise_scans.py, units mm\n'
                b'element vertex %d\nproperty float x\nproperty float y\nproperty float z\nend_header\n' % len(points))
        f.write(points.astype('<f4').tobytes())


def renoise(x, mode, sigma, fraction, rng):
    n = len(x)
    n_out = int(round(n * fraction / (1.0 - fraction)))
    if mode in ('iso', 'isobox'):
        seen = x + rng.normal(0.0, sigma, x.shape)
        lo, hi = x.min(0) - 50.0, x.max(0) + 50.0
        n_box = n_out if mode == 'isobox' else n_out // 2
        box = lo + rng.random((n_box, 3)) * (hi - lo)
        base = x[rng.integers(0, n, n_out - n_box)]
        away = rng.normal(size=base.shape)
        away /= np.linalg.norm(away, axis=1)[:, None]
        near = base + away * rng.uniform(1.0, 8.0, len(base))[:, None]
        out = np.vstack([seen, box, near])
    elif mode == 'ray':
        rng_mm = np.linalg.norm(x, axis=1)
        ray = x / rng_mm[:, None]
        seen = x + ray * rng.normal(0.0, sigma, n)[:, None]
        k = rng.integers(0, n, n_out)
        out = np.vstack([seen, ray[k] * (rng_mm[k] * rng.uniform(0.7, 1.3, n_out))[:, None]])
    else:
        raise SystemExit(f'unknown mode {mode} (iso, isobox, ray)')
    return out[rng.permutation(len(out))]


def main():
    if len(sys.argv) != 7:
        raise SystemExit(__doc__)
    src, dst, mode = sys.argv[1:4]
    sigma, fraction, seed = float(sys.argv[4]), float(sys.argv[5]), int(sys.argv[6])
    if not 0.0 <= fraction < 1.0:
        raise SystemExit('OUTLIER_FRACTION must be in [0, 1)')
    rng = np.random.default_rng(seed)
    for scene in sorted(os.listdir(src)):
        s = os.path.join(src, scene)
        if not os.path.isfile(os.path.join(s, 'scan.ply')):
            continue
        d = os.path.join(dst, scene)
        shutil.copytree(s, d, dirs_exist_ok=True)
        x = read_ply(os.path.join(s, 'scan.ply'))
        out = renoise(x, mode, sigma, fraction, rng)
        write_ply(os.path.join(d, 'scan.ply'), out)
        print(f'{scene}: {len(x)} points -> {len(out)}', flush=True)


if __name__ == '__main__':
    main()
