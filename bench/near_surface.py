#!/usr/bin/python3
"""Cables running close in front of a surface: a panel put behind a cable, as seen from the sensor, then scanned.

The project's simulator lays its cables 40-100 mm over the structure's plate; an installation often runs them along
a panel, a frame or a duct a few millimetres away, where the sensor sees the surface right behind the cable's
silhouette (mixed pixels between the two, the panel's points beside the cable within the cable's reach). This script
takes the scenes of `ewis simulate --scene-only --campaign N` (scene.obj, asbuilt.obj, plan.json, scene_truth.json),
puts a rigid panel `panel_1` (a 3 mm plate, 50-90 mm along the cable, 30-50 mm across) behind one cable, facing the
sensor, and scans each scene with `ewis simulate --cad ... --asbuilt ... --scene-truth ...` (the project's scanner:
noise along the rays, 40 % outliers, a perturbed pose.txt):
  - every scene: the panel `clearance + 1.5 to 5 mm` from the cable (its least distance over the whole as-built
    centreline, less the radius): nothing to report;
  - with --defects, in the scenes that have no defect yet (the even ones): `0.15 to 0.7 x clearance` instead, and a
    clearance defect `cable / panel_1` in the truth (`seen`: false, the gap lies behind the cable).
The panel keeps clearance + 1.5 mm from every other cable, or the scene gets none (said on stderr).
Usage:
  ewis simulate --out SRC --seed S --campaign N --scene-only
  near_surface.py --ewis build/bin/ewis --campaign SRC --seed S --out OUT [--defects] [--noise-mm ..] [--outliers ..]
Evaluate with `ewis evaluate --campaign OUT`.
"""
import argparse
import json
import math
import os
import shutil
import subprocess
import sys

import numpy as np


def box_mesh(centre, axes, half):
    """A closed box (8 vertices, 12 triangles wound outward) around `centre` with unit `axes` (rows) and `half` sizes."""
    v = []
    for sx in (-1, 1):
        for sy in (-1, 1):
            for sz in (-1, 1):
                v.append(centre + sx * half[0] * axes[0] + sy * half[1] * axes[1] + sz * half[2] * axes[2])
    # corner index = 4 * (sx > 0) + 2 * (sy > 0) + (sz > 0)
    quads = [(0, 1, 3, 2), (4, 6, 7, 5), (0, 4, 5, 1), (2, 3, 7, 6), (0, 2, 6, 4), (1, 5, 7, 3)]
    f = []
    for a, b, c, d in quads:
        f += [(a, b, c), (a, c, d)]
    v = np.array(v)
    # outward: turn any face whose normal points towards the centre
    out = []
    for a, b, c in f:
        n = np.cross(v[b] - v[a], v[c] - v[a])
        out.append((a, b, c) if n.dot((v[a] + v[b] + v[c]) / 3 - centre) > 0 else (a, c, b))
    return v, out


def box_distance(points, centre, axes, half):
    """Each point's distance to the solid box, and the box's closest point to each."""
    local = (points - centre) @ axes.T
    clamped = np.clip(local, -half, half)
    closest = centre + clamped @ axes
    return np.linalg.norm(points - closest, axis=1), closest


def append_obj(path, name, verts, faces):
    """Adds an object to an OBJ file (its vertices numbered after the file's)."""
    with open(path) as fh:
        count = sum(1 for line in fh if line.startswith('v '))
    with open(path, 'a') as fh:
        fh.write('o %s\n' % name)
        for p in verts:
            fh.write('v %.6f %.6f %.6f\n' % tuple(p))
        for f in faces:
            fh.write('f %d %d %d\n' % tuple(count + 1 + i for i in f))


def place_panel(truth, plan, rng, defect):
    """The panel's box (centre, axes, half sizes), its cable, the gap and the closest points; None when no place
    was found in 30 tries."""
    clearance = {e['name']: e.get('clearance_mm', 0.0) for e in plan['elements'] if e.get('kind') == 'cable'}
    cables = [c for c in truth['cables'] if len(c['centerline']) > 20]
    sensor = np.array(truth['camera_to_cad'])[:3, 3]
    for _ in range(30):
        cable = cables[rng.integers(len(cables))]
        line = np.array(cable['centerline'])
        r = cable['diameter_mm'] / 2
        seg = np.linalg.norm(np.diff(line, axis=0), axis=1)
        s = np.concatenate([[0], np.cumsum(seg)])
        i = int(np.searchsorted(s, rng.uniform(0.3, 0.7) * s[-1]))
        i = min(max(i, 3), len(line) - 4)
        p = line[i]
        t = line[i + 3] - line[i - 3]
        t /= np.linalg.norm(t)
        v = sensor - p
        v /= np.linalg.norm(v)
        n = v - v.dot(t) * t
        if np.linalg.norm(n) < 0.3:
            continue  # the cable runs towards the sensor there
        n /= np.linalg.norm(n)
        axes = np.array([t, np.cross(n, t), n])
        half = np.array([rng.uniform(25, 45), rng.uniform(15, 25), 1.5])
        c0 = clearance.get(cable['name'], 0.0)
        want = c0 * rng.uniform(0.15, 0.7) if defect else c0 + rng.uniform(1.5, 5.0)

        def gap_at(offset):
            centre = p - n * (r + half[2] + offset)
            d, _ = box_distance(line, centre, axes, half)
            return d.min() - r

        lo, hi = -r, 150.0
        if gap_at(hi) < want:
            continue
        for _ in range(60):
            mid = 0.5 * (lo + hi)
            lo, hi = (mid, hi) if gap_at(mid) < want else (lo, mid)
        centre = p - n * (r + half[2] + hi)
        d, closest = box_distance(line, centre, axes, half)
        k = int(np.argmin(d))
        gap = d[k] - r
        if abs(gap - want) > 0.05:
            continue
        # clear of every other cable
        ok = True
        for other in truth['cables']:
            if other is cable:
                continue
            od, _ = box_distance(np.array(other['centerline']), centre, axes, half)
            if od.min() - other['diameter_mm'] / 2 < clearance.get(other['name'], 0.0) + 1.5:
                ok = False
        if not ok:
            continue
        towards = closest[k] - line[k]
        on_cable = line[k] + towards / np.linalg.norm(towards) * r
        return {'centre': centre, 'axes': axes, 'half': half, 'cable': cable['name'], 'gap_mm': float(gap),
                'location': line[k].tolist(), 'ends': [on_cable.tolist(), closest[k].tolist()]}
    return None


def main():
    ap = argparse.ArgumentParser(description=__doc__.split('\n')[0])
    ap.add_argument('--ewis', default='build/bin/ewis')
    ap.add_argument('--campaign', required=True, help='a `ewis simulate --scene-only --campaign` folder')
    ap.add_argument('--out', required=True)
    ap.add_argument('--seed', type=int, default=1)
    ap.add_argument('--defects', action='store_true', help='clearance defects with the panel in the clean scenes')
    ap.add_argument('--noise-mm', type=float, default=None)
    ap.add_argument('--outliers', type=float, default=None)
    a = ap.parse_args()
    os.makedirs(a.out, exist_ok=True)
    scenes = sorted(d for d in os.listdir(a.campaign) if os.path.exists(os.path.join(a.campaign, d, 'scene_truth.json')))
    for k, name in enumerate(scenes):
        src = os.path.join(a.campaign, name)
        cad = os.path.join(a.out, name + '_cad')
        os.makedirs(cad, exist_ok=True)
        for f in ('scene.obj', 'asbuilt.obj', 'plan.json', 'scene_truth.json'):
            shutil.copy(os.path.join(src, f), os.path.join(cad, f))
        truth = json.load(open(os.path.join(cad, 'scene_truth.json')))
        plan = json.load(open(os.path.join(cad, 'plan.json')))
        rng = np.random.default_rng([a.seed, k])
        defect = a.defects and not truth['defects']
        panel = place_panel(truth, plan, rng, defect)
        if panel is None:
            print('%s: no place for a panel; left as it was' % name, file=sys.stderr)
        else:
            verts, faces = box_mesh(panel['centre'], panel['axes'], panel['half'])
            for f in ('scene.obj', 'asbuilt.obj'):
                append_obj(os.path.join(cad, f), 'panel_1', verts, faces)
            plan['elements'].append({'name': 'panel_1', 'kind': 'rigid'})
            json.dump(plan, open(os.path.join(cad, 'plan.json'), 'w'), indent=1)
            if defect:
                truth['defects'].append({'kind': 'clearance', 'element': panel['cable'], 'with': 'panel_1',
                                         'gap_mm': round(panel['gap_mm'], 4), 'location': panel['location'],
                                         'ends': panel['ends'], 'seen': False})
                truth['requested_defect'] = 'clearance'
            truth['panel'] = {'cable': panel['cable'], 'gap_mm': round(panel['gap_mm'], 4),
                              'centre': panel['centre'].tolist(), 'half_mm': panel['half'].tolist()}
            json.dump(truth, open(os.path.join(cad, 'scene_truth.json'), 'w'), indent=1)
        cmd = [a.ewis, 'simulate', '--out', os.path.join(a.out, name), '--cad', os.path.join(cad, 'scene.obj'),
               '--plan', os.path.join(cad, 'plan.json'), '--asbuilt', os.path.join(cad, 'asbuilt.obj'),
               '--scene-truth', os.path.join(cad, 'scene_truth.json'), '--seed', str(a.seed * 1000 + k), '--quiet']
        if a.noise_mm is not None:
            cmd += ['--noise-mm', str(a.noise_mm)]
        if a.outliers is not None:
            cmd += ['--outliers', str(a.outliers)]
        subprocess.run(cmd, check=True)
        if panel:
            print('%s: panel %.2f mm behind %s%s' % (name, panel['gap_mm'], panel['cable'],
                                                     ' (a clearance defect)' if defect else ''), file=sys.stderr)


if __name__ == '__main__':
    main()
