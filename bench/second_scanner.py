#!/usr/bin/python3
"""A second, independent virtual scanner: rescans a `ewis simulate --campaign` with other physics.

The project's own scanner (src/sim) ray-casts with Embree, puts the noise along the camera rays and draws its
outliers its own way. Tuning the inspection to it alone would go unnoticed, so this script scans the same
as-built scenes differently, in numpy only:
  - a pinhole camera of its own size and focal length (default 1280 x 1024 px, f = 1150 px: ~0.52 mm pixels
    at 600 mm), rendered by splatting dense samples of every triangle into a z-buffer, then each pixel's
    point computed exactly on the winning triangle's plane;
  - isotropic Gaussian noise (per axis, mm), not along the rays;
  - mixed pixels at depth edges (a depth between the near and the far surface);
  - outliers: half uniform in the view frustum, half a wrong depth (3-40 mm off) along a seen pixel's ray;
  - optionally a floor and boxes around the scene that the CAD does not have (clutter the registration must
    ignore);
  - optionally depth noise along the rays correlated over neighbouring pixels (a stereo matcher's window makes
    its errors smooth over a few pixels, which independent noise does not model), and dropouts: pixels that
    return nothing, more often at glancing incidence, and holes (blobs of a few pixels) where the pattern is
    lost.
Each scene of the campaign keeps its scene.obj, plan.json, pose.txt and truth.json (the camera pose is the
same, so the truth holds); only scan.ply is new. Evaluate the result with `ewis evaluate --campaign OUT`.

Usage:
  second_scanner.py --ewis build/bin/ewis --campaign C --seed S --out OUT [--first I --last J]
                    [--sigma-mm 0.15] [--outliers 0.4] [--focal-px 1150] [--width 1280] [--height 1024]
                    [--mixed 0.5] [--floor-z Z] [--clutter N] [--ray-sigma-mm S --ray-corr-px R]
                    [--dropout D] [--holes H]
`--seed` (and `--cable-diameter-mm`, if any) must be those the campaign C was simulated with: the as-built meshes are made again with
`ewis simulate --scene-only` into OUT_asbuilt (a campaign does not keep them) and checked against C's truth.
"""
import argparse
import json
import os
import subprocess
import sys

import numpy as np


def read_obj(path):
    verts, faces = [], []
    with open(path) as fh:
        for line in fh:
            if line.startswith('v '):
                verts.append([float(x) for x in line.split()[1:4]])
            elif line.startswith('f '):
                idx = [int(t.split('/')[0]) for t in line.split()[1:]]
                idx = [i - 1 if i > 0 else len(verts) + i for i in idx]
                for k in range(1, len(idx) - 1):
                    faces.append([idx[0], idx[k], idx[k + 1]])
    return np.array(verts, float), np.array(faces, np.int64)


def read_floor(floor_z):
    """A floor: a grid of 50 mm cells over +-1200 mm (small triangles keep the splatting bounded)."""
    g = np.arange(-1200.0, 1200.1, 50.0)
    m = len(g)
    verts = [[x, y, floor_z] for y in g for x in g]
    faces = []
    for j in range(m - 1):
        for i in range(m - 1):
            q = j * m + i
            faces += [[q, q + 1, q + m + 1], [q, q + m + 1, q + m]]
    return np.array(verts, float), np.array(faces, np.int64)


def add_clutter(verts, faces, count, base_z, rng):
    """`count` boxes (30-150 mm, turned about z) standing on z = base_z around the CAD's footprint, not in the
    CAD: the robot cell, tools, the rest of the aircraft, with corners and edges like the scene's brackets."""
    lo, hi = verts.min(0), verts.max(0)
    vs, fs = [verts], [faces]
    n = len(verts)
    unit = np.array([[x, y, z] for z in (0, 1) for y in (0, 1) for x in (0, 1)], float) - [0.5, 0.5, 0]
    quads = [(0, 2, 3, 1), (4, 5, 7, 6), (0, 1, 5, 4), (2, 6, 7, 3), (0, 4, 6, 2), (1, 3, 7, 5)]
    for _ in range(count):
        size = rng.uniform(30, 150, 3)
        side = rng.integers(4)  # which side of the footprint, 20-120 mm beyond it
        gap = rng.uniform(20, 120) + size[:2].max() / 2
        t = rng.random()
        cx = [lo[0] - gap, hi[0] + gap, lo[0] + t * (hi[0] - lo[0]), lo[0] + t * (hi[0] - lo[0])][side]
        cy = [lo[1] + t * (hi[1] - lo[1]), lo[1] + t * (hi[1] - lo[1]), lo[1] - gap, hi[1] + gap][side]
        a = rng.uniform(0, np.pi)
        rot = np.array([[np.cos(a), -np.sin(a), 0], [np.sin(a), np.cos(a), 0], [0, 0, 1]])
        vs.append((unit * size) @ rot.T + [cx, cy, base_z])
        for q in quads:
            fs.append(np.array([[n + q[0], n + q[1], n + q[2]], [n + q[0], n + q[2], n + q[3]]]))
        n += 8
    return np.concatenate(vs), np.concatenate(fs)


def smooth_field(shape, sigma_px, rng):
    """Unit-variance Gaussian noise over an image, correlated over a Gaussian of sigma_px pixels (FFT)."""
    w = rng.normal(size=shape)
    if sigma_px <= 0:
        return w
    fy = np.fft.fftfreq(shape[0])[:, None]
    fx = np.fft.rfftfreq(shape[1])[None, :]
    g = np.exp(-2.0 * (np.pi * sigma_px) ** 2 * (fx ** 2 + fy ** 2))
    f = np.fft.irfft2(np.fft.rfft2(w) * g, s=shape)
    return f / f.std()


def scan(verts, faces, camera_to_cad, a, rng):
    """Points (camera frame, mm) of one scan; returns (points, surface count, mixed count)."""
    cad_to_cam = np.linalg.inv(camera_to_cad)
    vc = verts @ cad_to_cam[:3, :3].T + cad_to_cam[:3, 3]
    A, B, C = vc[faces[:, 0]], vc[faces[:, 1]], vc[faces[:, 2]]
    cx, cy, f = a.width / 2.0, a.height / 2.0, a.focal_px

    def project(p):
        return f * p[:, 0] / p[:, 2] + cx, f * p[:, 1] / p[:, 2] + cy

    front = (A[:, 2] > 10) & (B[:, 2] > 10) & (C[:, 2] > 10)
    A, B, C = A[front], B[front], C[front]
    ua, va = project(A)
    ub, vb = project(B)
    uc, vc2 = project(C)
    inside = ((np.maximum.reduce([ua, ub, uc]) >= 0) & (np.minimum.reduce([ua, ub, uc]) < a.width) &
              (np.maximum.reduce([va, vb, vc2]) >= 0) & (np.minimum.reduce([va, vb, vc2]) < a.height))
    A, B, C = A[inside], B[inside], C[inside]
    area_px = 0.5 * np.abs((ub - ua) * (vc2 - va) - (uc - ua) * (vb - va))[inside]
    # z-buffer by splatting ~6 random samples per pixel of each triangle, in chunks of ~4 M samples
    n = np.ceil(area_px * 6).astype(np.int64) + 3
    zbuf = np.full(a.width * a.height, np.inf)
    tbuf = np.full(a.width * a.height, -1, np.int64)
    cum = np.cumsum(n)
    start = 0
    while start < len(A):
        stop = max(int(np.searchsorted(cum, (cum[start - 1] if start else 0) + 4_000_000, 'right')), start + 1)
        rep = start + np.repeat(np.arange(stop - start), n[start:stop])
        r1, r2 = rng.random(len(rep)), rng.random(len(rep))
        s = np.sqrt(r1)
        p = (1 - s)[:, None] * A[rep] + (s * (1 - r2))[:, None] * B[rep] + (s * r2)[:, None] * C[rep]
        u, v = project(p)
        ok = (u >= 0) & (u < a.width) & (v >= 0) & (v < a.height)
        pix = v[ok].astype(np.int64) * a.width + u[ok].astype(np.int64)
        z, tri = p[ok, 2], rep[ok]
        order = np.lexsort((z, pix))
        pix, z, tri = pix[order], z[order], tri[order]
        first = np.ones(len(pix), bool)
        first[1:] = pix[1:] != pix[:-1]
        pix, z, tri = pix[first], z[first], tri[first]
        better = z < zbuf[pix]
        zbuf[pix[better]] = z[better]
        tbuf[pix[better]] = tri[better]
        start = stop
    pix = np.nonzero(tbuf >= 0)[0]
    tri = tbuf[pix]
    # each pixel's ray (through its centre) on the winning triangle's plane
    px, py = (pix % a.width) + 0.5, (pix // a.width) + 0.5
    d = np.stack([(px - cx) / f, (py - cy) / f, np.ones_like(px)], 1)
    nrm = np.cross(B[tri] - A[tri], C[tri] - A[tri])
    nrm /= np.linalg.norm(nrm, axis=1)[:, None] + 1e-300
    denom = (nrm * d).sum(1)
    t = (nrm * A[tri]).sum(1) / np.where(np.abs(denom) < 1e-12, 1e-12, denom)
    pts = d * t[:, None]
    dn = d / np.linalg.norm(d, axis=1)[:, None]
    incidence = np.degrees(np.arccos(np.clip(np.abs((nrm * dn).sum(1)), 0, 1)))
    keep = (incidence <= a.max_incidence_deg) & (t > 0)
    if a.dropout > 0:  # a pixel returns less often the more glancing its surface: dropout x (incidence / max)^2
        keep &= rng.random(len(pix)) >= a.dropout * (incidence / a.max_incidence_deg) ** 2
    if a.holes > 0:  # blobs of ~4 px where the pattern is lost, covering `holes` of the image
        field = smooth_field((a.height, a.width), 2.0, rng).reshape(-1)
        keep &= field[pix] < np.quantile(field, 1.0 - a.holes)
    pts, pix, dn = pts[keep], pix[keep], dn[keep]
    # mixed pixels: a pixel whose 4-neighbour is over 8 mm deeper may read a depth in between
    depth = np.full(a.width * a.height, np.nan)
    depth[pix] = pts[:, 2]
    img = depth.reshape(a.height, a.width)
    nb = np.full((4, a.height, a.width), -np.inf)
    nb[0, 1:, :], nb[1, :-1, :] = img[:-1, :], img[1:, :]
    nb[2, :, 1:], nb[3, :, :-1] = img[:, :-1], img[:, 1:]
    far = np.nanmax(np.where(np.isnan(nb), -np.inf, nb), 0).reshape(-1)[pix]
    edge = (far - pts[:, 2] > 8.0) & (rng.random(len(pix)) < a.mixed)
    frac = rng.random(edge.sum())
    pts[edge] *= (1 + frac * (far[edge] / pts[edge, 2] - 1))[:, None]
    pts = pts + rng.normal(0, a.sigma_mm, pts.shape)
    if a.ray_sigma_mm > 0:  # depth noise along the rays, correlated over ray_corr_px pixels
        field = smooth_field((a.height, a.width), a.ray_corr_px, rng).reshape(-1)
        pts += dn * (a.ray_sigma_mm * field[pix])[:, None]
    # outliers
    n_out = int(round(a.outliers / (1 - a.outliers) * len(pts)))
    zmin, zmax = pts[:, 2].min() - 50, pts[:, 2].max() + 50
    n1 = n_out // 2
    uo, vo, zo = rng.random(n1) * a.width, rng.random(n1) * a.height, rng.uniform(zmin, zmax, n1)
    o1 = np.stack([(uo - cx) / f * zo, (vo - cy) / f * zo, zo], 1)
    pick = rng.integers(0, len(pts), n_out - n1)
    scale = 1 + rng.choice([-1, 1], len(pick)) * rng.uniform(3, 40, len(pick)) / pts[pick, 2]
    o2 = pts[pick] * scale[:, None]
    out = np.concatenate([pts, o1, o2]).astype(np.float32)
    return out[rng.permutation(len(out))], len(pts), int(edge.sum())


def write_ply(path, pts):
    with open(path, 'wb') as fh:
        fh.write(('ply\nformat binary_little_endian 1.0\ncomment second_scanner.py, units mm\n'
                  'element vertex %d\nproperty float x\nproperty float y\nproperty float z\nend_header\n'
                  % len(pts)).encode())
        fh.write(pts.tobytes())


def main():
    ap = argparse.ArgumentParser(description=__doc__.split('\n')[0])
    ap.add_argument('--ewis', required=True, help='the ewis binary (to make the as-built meshes again)')
    ap.add_argument('--campaign', required=True, help='folder of `ewis simulate --campaign`')
    ap.add_argument('--seed', type=int, required=True, help='the seed that campaign was made with')
    ap.add_argument('--cable-diameter-mm', nargs=2, default=None, metavar=('LO', 'HI'),
                    help="the campaign's --cable-diameter-mm, when it was made with one")
    ap.add_argument('--out', required=True)
    ap.add_argument('--first', type=int, default=0)
    ap.add_argument('--last', type=int, default=-1, help='last scene index (default: all)')
    ap.add_argument('--sigma-mm', type=float, default=0.15, help='isotropic noise, per axis')
    ap.add_argument('--outliers', type=float, default=0.4, help='outlier fraction of the scan')
    ap.add_argument('--focal-px', type=float, default=1150.0)
    ap.add_argument('--width', type=int, default=1280)
    ap.add_argument('--height', type=int, default=1024)
    ap.add_argument('--mixed', type=float, default=0.5, help='chance that a depth-edge pixel is mixed')
    ap.add_argument('--max-incidence-deg', type=float, default=78.0)
    ap.add_argument('--floor-z', type=float, default=None, help='a floor at this CAD z, not in the CAD')
    ap.add_argument('--clutter', type=int, default=0,
                    help='boxes around the scene, not in the CAD (standing on the floor, or level with the CAD\'s base)')
    ap.add_argument('--ray-sigma-mm', type=float, default=0.0,
                    help='depth noise along the rays (mm), correlated over --ray-corr-px pixels')
    ap.add_argument('--ray-corr-px', type=float, default=0.0, help='correlation length of that noise (Gaussian sigma, px)')
    ap.add_argument('--dropout', type=float, default=0.0,
                    help='chance a pixel at the largest incidence returns nothing (scaled by (incidence / max)^2)')
    ap.add_argument('--holes', type=float, default=0.0, help='fraction of the image lost in blobs of a few pixels')
    a = ap.parse_args()
    scenes = sorted(d for d in os.listdir(a.campaign) if d.startswith('scene_'))
    last = len(scenes) - 1 if a.last < 0 else min(a.last, len(scenes) - 1)
    built = a.out.rstrip('/') + '_asbuilt'  # beside OUT, not in it (evaluate reads every folder of OUT)
    if not os.path.isdir(built):
        extra = ['--cable-diameter-mm', *a.cable_diameter_mm] if a.cable_diameter_mm else []
        subprocess.run([a.ewis, 'simulate', '--out', built, '--seed', str(a.seed), '--campaign', str(len(scenes)),
                        *extra, '--scene-only', '-q'], check=True)
    for i in range(a.first, last + 1):
        name = scenes[i]
        src, dst = os.path.join(a.campaign, name), os.path.join(a.out, name)
        truth = json.load(open(os.path.join(src, 'truth.json')))
        again = json.load(open(os.path.join(built, name, 'scene_truth.json')))
        if [c['centerline'] for c in truth['cables']] != [c['centerline'] for c in again['cables']]:
            sys.exit(f'{name}: the as-built scene differs from {src}/truth.json (wrong --seed?)')
        os.makedirs(dst, exist_ok=True)
        for f in ('scene.obj', 'plan.json', 'pose.txt', 'truth.json'):
            link = os.path.join(dst, f)
            if not os.path.exists(link):
                os.symlink(os.path.abspath(os.path.join(src, f)), link)
        rng = np.random.default_rng([a.seed, i])
        verts, faces = read_obj(os.path.join(built, name, 'asbuilt.obj'))
        if a.clutter > 0:
            base = a.floor_z if a.floor_z is not None else verts[:, 2].min()
            verts, faces = add_clutter(verts, faces, a.clutter, base, np.random.default_rng([a.seed, i, 7]))
        if a.floor_z is not None:
            fv, ff = read_floor(a.floor_z)
            verts, faces = np.concatenate([verts, fv]), np.concatenate([faces, ff + len(verts)])
        pts, surface, mixed = scan(verts, faces, np.array(truth['camera_to_cad']), a, rng)
        write_ply(os.path.join(dst, 'scan.ply'), pts)
        print(f'{name}: {surface} surface points ({mixed} mixed), {len(pts) - surface} outliers', file=sys.stderr)


if __name__ == '__main__':
    main()
