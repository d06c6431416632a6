#!/usr/bin/python3
"""Foreign object debris: small loose parts left on a cable, scanned by the second scanner (second_scanner.py).

The project's simulator leaves spheres of 6-16 mm, boxes of 6-16 mm and tie-like bars of 28-40 mm near a cable.
What an inspector looks for on a harness is often smaller: a washer, a nut, a screw or rivet, a cut-off length of
lock wire, the tail of a cable tie, a ball. This script takes the clean scenes of a `ewis simulate --campaign`, puts
one such part on the camera side of one cable (touching it, or within its clearance), rescans the scene with
second_scanner.py's physics and writes the defect into truth.json:
  - washer: a ring, outer diameter 5-9 mm, inner half of it, 0.8-1.6 mm thick, lying flat on the cable;
  - nut: a hexagonal prism, 5.5-8 mm across the flats, 2.4-4 mm high, lying flat;
  - screw: a cylinder 2.5-4 mm across and 6-14 mm long, lying at any angle to the cable;
  - wire: lock wire, a cylinder 0.8-1.2 mm across and 15-35 mm long, lying at any angle;
  - tie_tail: a strip 2.5-3.6 x 1.0-1.3 mm and 12-25 mm long, lying at any angle;
  - ball: a sphere 3-6 mm across.
The gap in truth.json is measured on the meshes (the part's surface samples against the as-built centreline less
the cable's radius). A part closer than 1 mm to anything else of the scene is moved to another spot; a scene whose
part the scan shows with fewer than 20 points is left out (listed on stderr). Each scene folder also gets
part.obj, the part alone in the CAD's frame (evaluate does not read it). Evaluate with `ewis evaluate --campaign OUT`.

Usage:
  small_objects.py --ewis build/bin/ewis --campaign C --seed S --out OUT [--kinds washer,nut,...]
                   [second_scanner.py's physics: --sigma-mm --outliers --focal-px --mixed --dropout --holes ...]
"""
import argparse
import json
import os
import subprocess
import sys

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import second_scanner as ss  # noqa: E402

KINDS = ['washer', 'nut', 'screw', 'wire', 'tie_tail', 'ball']


def face_owners(path):
    """The object (`o` line) each triangle of second_scanner.read_obj's fan split of an OBJ belongs to."""
    owner, name = [], ''
    with open(path) as fh:
        for line in fh:
            if line.startswith('o '):
                name = line.split(None, 1)[1].strip()
            elif line.startswith('f '):
                owner += [name] * (len(line.split()) - 3)
    return np.array(owner)


def prism(outline, height, inner=None):
    """A closed prism over a convex outline (n x 2, counter-clockwise) from z = 0 to z = height; with `inner`
    (same count), a ring between the two outlines. Returns (verts, faces) in its local frame."""
    n = len(outline)
    if inner is None:
        v = [[x, y, 0.0] for x, y in outline] + [[x, y, height] for x, y in outline] + [[0, 0, 0], [0, 0, height]]
        f = []
        for i in range(n):
            j = (i + 1) % n
            f += [[i, j, n + j], [i, n + j, n + i], [2 * n, j, i], [2 * n + 1, n + i, n + j]]
        return np.array(v), np.array(f)
    v = ([[x, y, 0.0] for x, y in outline] + [[x, y, height] for x, y in outline] +
         [[x, y, 0.0] for x, y in inner] + [[x, y, height] for x, y in inner])
    f = []
    for i in range(n):
        j = (i + 1) % n
        o0, o1, t0, t1 = i, j, n + i, n + j
        i0, i1, u0, u1 = 2 * n + i, 2 * n + j, 3 * n + i, 3 * n + j
        f += [[o0, o1, t1], [o0, t1, t0], [i1, i0, u0], [i1, u0, u1], [t0, t1, u1], [t0, u1, u0],
              [o1, o0, i0], [o1, i0, i1]]
    return np.array(v), np.array(f)


def circle(r, n):
    a = np.linspace(0, 2 * np.pi, n, endpoint=False)
    return np.stack([r * np.cos(a), r * np.sin(a)], 1)


def sphere(r, n=16):
    v, f = [], []
    for i in range(n + 1):
        th = np.pi * i / n
        for j in range(2 * n):
            ph = np.pi * j / n
            v.append([r * np.sin(th) * np.cos(ph), r * np.sin(th) * np.sin(ph), r * np.cos(th)])
    for i in range(n):
        for j in range(2 * n):
            a, b = i * 2 * n + j, i * 2 * n + (j + 1) % (2 * n)
            c, d = a + 2 * n, b + 2 * n
            f += [[a, c, d], [a, d, b]]
    return np.array(v), np.array(f)


def make_part(kind, rng):
    """(verts, faces, description) of a part in its local frame: its lowest point at z = 0, centred on the z axis;
    x along its length for the long ones."""
    if kind == 'washer':
        od, th = rng.uniform(5, 9), rng.uniform(0.8, 1.6)
        v, f = prism(circle(od / 2, 32), th, circle(od / 4, 32))
        return v, f, f'washer {od:.1f} x {th:.1f} mm'
    if kind == 'nut':
        af, h = rng.uniform(5.5, 8), rng.uniform(2.4, 4)
        v, f = prism(circle(af / np.sqrt(3), 6), h)
        return v, f, f'nut {af:.1f} mm across, {h:.1f} mm high'
    if kind in ('screw', 'wire'):
        d, length = (rng.uniform(2.5, 4), rng.uniform(6, 14)) if kind == 'screw' else \
            (rng.uniform(0.8, 1.2), rng.uniform(15, 35))
        v, f = prism(circle(d / 2, 16), length)  # along z: turned to lie along x, its side down
        v = v[:, [2, 0, 1]] - [length / 2, 0, 0] + [0, 0, d / 2]  # a cyclic swap of the axes: a turn, faces still out
        return v, f, f'{kind} {d:.1f} x {length:.1f} mm'
    if kind == 'tie_tail':
        w, t, length = rng.uniform(2.5, 3.6), rng.uniform(1.0, 1.3), rng.uniform(12, 25)
        v, f = prism(np.array([[-length / 2, -w / 2], [length / 2, -w / 2], [length / 2, w / 2],
                               [-length / 2, w / 2]]), t)
        return v, f, f'tie tail {w:.1f} x {t:.1f} x {length:.1f} mm'
    d = rng.uniform(3, 6)
    v, f = sphere(d / 2)
    return v + [0, 0, d / 2], f, f'ball {d:.1f} mm'


def surface_samples(verts, faces, per_mm2, rng):
    a, b, c = verts[faces[:, 0]], verts[faces[:, 1]], verts[faces[:, 2]]
    area = 0.5 * np.linalg.norm(np.cross(b - a, c - a), axis=1)
    n = np.maximum(1, np.ceil(area * per_mm2)).astype(int)
    rep = np.repeat(np.arange(len(faces)), n)
    r1, r2 = rng.random(len(rep)), rng.random(len(rep))
    s = np.sqrt(r1)
    return np.concatenate([(1 - s)[:, None] * a[rep] + (s * (1 - r2))[:, None] * b[rep] + (s * r2)[:, None] * c[rep],
                           verts])


def distance_to_polyline(points, line):
    """For each point: its distance to the polyline and the closest point on it."""
    best = np.full(len(points), np.inf)
    where = np.zeros((len(points), 3))
    a, b = line[:-1], line[1:]
    ab = b - a
    den = np.maximum((ab * ab).sum(1), 1e-12)
    for k in range(0, len(points), 256):
        p = points[k:k + 256]
        t = np.clip(((p[:, None, :] - a[None]) * ab[None]).sum(2) / den[None], 0, 1)
        q = a[None] + t[..., None] * ab[None]
        d = np.linalg.norm(p[:, None, :] - q, axis=2)
        i = d.argmin(1)
        best[k:k + 256] = d[np.arange(len(p)), i]
        where[k:k + 256] = q[np.arange(len(p)), i]
    return best, where


def distance_to_triangles(points, verts, faces):
    """Smallest distance from any of `points` to the triangles (their dense samples, 0.2 mm apart at most)."""
    if len(faces) == 0:
        return np.inf
    lo, hi = points.min(0) - 5, points.max(0) + 5
    a, b, c = verts[faces[:, 0]], verts[faces[:, 1]], verts[faces[:, 2]]
    near = ((np.minimum.reduce([a, b, c]) <= hi) & (np.maximum.reduce([a, b, c]) >= lo)).all(1)
    if not near.any():
        return np.inf
    s = surface_samples(verts, faces[near], 25.0, np.random.default_rng(0))
    s = s[((s >= lo) & (s <= hi)).all(1)]
    if len(s) == 0:
        return np.inf
    best = np.inf
    for k in range(0, len(points), 128):
        d = np.linalg.norm(points[k:k + 128, None, :] - s[None], axis=2)
        best = min(best, d.min())
    return best


def place(cable, part, cam, rng):
    """The part put on the cable's camera side at a random spot: (world verts, gap asked)."""
    line = np.array(cable['centerline'], float)
    seg = np.linalg.norm(np.diff(line, axis=0), axis=1)
    s = np.concatenate([[0], np.cumsum(seg)])
    at = rng.uniform(0.2, 0.8) * s[-1]
    i = min(int(np.searchsorted(s, at)), len(line) - 2)
    p = line[i] + (at - s[i]) / max(seg[i], 1e-9) * (line[i + 1] - line[i])
    t = (line[min(i + 3, len(line) - 1)] - line[max(i - 2, 0)])
    t /= np.linalg.norm(t)
    n = cam - p
    n -= t * t.dot(n)
    n /= np.linalg.norm(n)
    tilt = np.radians(rng.uniform(-30, 30))  # off the top, toward either flank
    b = np.cross(t, n)
    n = np.cos(tilt) * n + np.sin(tilt) * b
    b = np.cross(t, n)
    rc = cable['diameter_mm'] / 2
    gap = 0.0 if rng.random() < 0.3 else rng.uniform(0.2, max(0.3, cable['clearance_mm'] - 0.8))
    spin = rng.uniform(0, np.pi)
    x = np.cos(spin) * t + np.sin(spin) * b
    y = np.cross(n, x)
    rot = np.stack([x, y, n], 1)
    return part[0] @ rot.T + p + n * (rc + gap), gap


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument('--ewis', required=True)
    ap.add_argument('--campaign', required=True)
    ap.add_argument('--seed', type=int, required=True, help='the seed the campaign was made with')
    ap.add_argument('--out', required=True)
    ap.add_argument('--kinds', default=','.join(KINDS))
    ap.add_argument('--sigma-mm', type=float, default=0.15)
    ap.add_argument('--outliers', type=float, default=0.4)
    ap.add_argument('--focal-px', type=float, default=1150.0)
    ap.add_argument('--width', type=int, default=1280)
    ap.add_argument('--height', type=int, default=1024)
    ap.add_argument('--mixed', type=float, default=0.5)
    ap.add_argument('--max-incidence-deg', type=float, default=78.0)
    ap.add_argument('--dropout', type=float, default=0.0)
    ap.add_argument('--holes', type=float, default=0.0)
    a = ap.parse_args()
    a.ray_sigma_mm, a.ray_corr_px = 0.0, 0.0
    kinds = a.kinds.split(',')
    for k in kinds:
        if k not in KINDS:
            sys.exit(f'unknown kind {k!r} (one of {", ".join(KINDS)})')
    scenes = sorted(d for d in os.listdir(a.campaign) if d.startswith('scene_'))
    built = a.out.rstrip('/') + '_asbuilt'
    if not os.path.isdir(built):
        subprocess.run([a.ewis, 'simulate', '--out', built, '--seed', str(a.seed), '--campaign', str(len(scenes)),
                        '--scene-only', '-q'], check=True)
    made = 0
    for i, name in enumerate(scenes):
        src, dst = os.path.join(a.campaign, name), os.path.join(a.out, name)
        truth = json.load(open(os.path.join(src, 'truth.json')))
        if truth['defects']:
            continue
        rng = np.random.default_rng([a.seed, i, 44])
        obj = os.path.join(built, name, 'asbuilt.obj')
        verts, faces = ss.read_obj(obj)
        owner = face_owners(obj)
        cam = np.array(truth['camera_to_cad'])[:3, 3]
        kind = kinds[made % len(kinds)]
        for attempt in range(40):
            cable = truth['cables'][rng.integers(len(truth['cables']))]
            part = make_part(kind, rng)
            pv, gap = place(cable, part, cam, rng)
            samples = surface_samples(pv, part[1], 20.0, rng)
            others = faces[owner != cable['name']]
            if distance_to_triangles(samples, verts, others) < 1.0:
                continue
            d, q = distance_to_polyline(samples, np.array(cable['centerline'], float))
            k = d.argmin()
            true_gap = d[k] - cable['diameter_mm'] / 2
            if true_gap < -0.05:
                continue  # into the cable where it curves: another spot
            break
        else:
            print(f'{name}: no free spot for a {kind}', file=sys.stderr)
            continue
        spot = q[k] + (samples[k] - q[k]) / max(d[k], 1e-9) * cable['diameter_mm'] / 2
        all_v = np.concatenate([verts, pv])
        all_f = np.concatenate([faces, part[1] + len(verts)])
        srng = np.random.default_rng([a.seed, i])
        pts, _, _ = ss.scan(all_v, all_f, np.array(truth['camera_to_cad']), a, srng)
        # the part's points in the scan (camera frame -> CAD)
        c2w = np.array(truth['camera_to_cad'])
        w = pts[:, :3].astype(float) @ c2w[:3, :3].T + c2w[:3, 3]
        lo, hi = pv.min(0) - 0.5, pv.max(0) + 0.5
        box = ((w >= lo) & (w <= hi)).all(1)
        on_part = 0
        if box.any():
            dd = np.linalg.norm(w[box][:, None, :] - samples[None, ::4], axis=2).min(1)
            on_part = int((dd < 0.6).sum())
        if on_part < 20:
            print(f'{name}: the {part[2]} shows {on_part} points: left out', file=sys.stderr)
            continue
        os.makedirs(dst, exist_ok=True)
        for f in ('scene.obj', 'plan.json', 'pose.txt'):
            link = os.path.join(dst, f)
            if not os.path.exists(link):
                os.symlink(os.path.abspath(os.path.join(src, f)), link)
        truth['requested_defect'] = 'foreign_object'
        truth['defects'] = [{'element': cable['name'], 'kind': 'foreign_object', 'gap_mm': round(float(true_gap), 4),
                             'location': [round(float(x), 4) for x in spot], 'seen': False, 'with': None,
                             'part': part[2], 'part_points': on_part}]
        truth['foreign_objects'] = [{'name': 'foreign_1', 'part': part[2]}]
        with open(os.path.join(dst, 'truth.json'), 'w') as fh:
            json.dump(truth, fh, indent=1)
        ss.write_ply(os.path.join(dst, 'scan.ply'), pts)
        with open(os.path.join(dst, 'part.obj'), 'w') as fh:  # the part alone, CAD frame (not read by evaluate)
            fh.write(f'# {part[2]}\no foreign_1\n')
            fh.writelines(f'v {x:.5f} {y:.5f} {z:.5f}\n' for x, y, z in pv)
            fh.writelines(f'f {i + 1} {j + 1} {k + 1}\n' for i, j, k in part[1])
        made += 1
        print(f'{name}: {part[2]} on {cable["name"]} ({cable["diameter_mm"]} mm), gap {true_gap:.2f} mm '
              f'(asked {gap:.2f}), {on_part} points on it', file=sys.stderr)


if __name__ == '__main__':
    main()
