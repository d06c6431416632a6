#!/usr/bin/python3
"""A campaign's CAD written or built another way, for checking that the inspection does not depend on how our own
simulator writes it. Each variant copies the campaign (scan, plan, pose and truth linked, not copied) with scene.obj
(or scene.stl) replaced:
  - round D: every vertex written with D decimals (many exporters do; vertices that were 1e-7 mm apart coincide,
    e.g. the walls standing on the structure's plate);
  - stl: ASCII STL, one `solid NAME` per element (CONTRACT); `ewis evaluate` reads scene.obj only, so run
    `ewis inspect --cad scene.stl` per scene;
  - groups: `g NAME` instead of `o NAME`, a `usemtl` per element, a vertex normal per face and `f v//vn`;
  - soup: every triangle with its own three vertices;
  - displace A: each cable's CAD moved horizontally by up to A mm (a smooth bump pinned at its attached clamps and
    connectors, 10-90 mm around them; a random direction per cable), as if it had been routed elsewhere; the as-built
    cable (the scan, the truth) stays.
Usage: cad_variants.py CAMPAIGN OUT round 5 | stl | groups | soup | displace 10 [--seed S] [--scenes N]
"""
import argparse
import json
import math
import os
import random

import numpy as np


def read_obj(path):
    """Vertex lines (as written), objects [name, faces (0-based vertex indices)] in file order."""
    vlines, objs, cur = [], [], None
    with open(path) as fh:
        for line in fh:
            if line.startswith('v '):
                vlines.append(line.split()[1:4])
            elif line.startswith('o ') or line.startswith('g '):
                cur = [line.split(None, 1)[1].strip(), []]
                objs.append(cur)
            elif line.startswith('f ') and cur is not None:
                cur[1].append([int(t.split('/')[0]) - 1 for t in line.split()[1:]])
    return vlines, objs


def face_normal(V, f):
    n = np.cross(V[f[1]] - V[f[0]], V[f[2]] - V[f[0]])
    length = np.linalg.norm(n)
    return n / length if length > 0 else n


def displaced(V, objs, plan, amp_mm, rng):
    """V with each cable's vertices moved by amp_mm x a smooth weight, 0 within 10 mm of an attached element's
    centre, 1 beyond 90 mm, horizontally in a random direction per cable."""
    V = V.copy()
    by_name = {name: sorted({i for f in faces for i in f}) for name, faces in objs}
    for e in plan['elements']:
        if e.get('kind') != 'cable' or e['name'] not in by_name:
            continue
        ids = np.array(by_name[e['name']])
        P = V[ids]
        w = np.ones(len(ids))
        for a in e.get('attached', []):
            if a not in by_name:
                continue
            centre = V[np.array(by_name[a])].mean(axis=0)
            x = np.clip((np.linalg.norm(P - centre, axis=1) - 10.0) / 80.0, 0, 1)
            w = np.minimum(w, x * x * (3 - 2 * x))
        az = rng.uniform(0, 2 * math.pi)
        V[ids] = P + amp_mm * w[:, None] * np.array([math.cos(az), math.sin(az), 0.0])
    return V


def main():
    ap = argparse.ArgumentParser(description=__doc__.split('\n')[0])
    ap.add_argument('campaign')
    ap.add_argument('out')
    ap.add_argument('variant', choices=['round', 'stl', 'groups', 'soup', 'displace'])
    ap.add_argument('value', nargs='?', type=float, default=None, help='decimals (round) or mm (displace)')
    ap.add_argument('--seed', type=int, default=45)
    ap.add_argument('--scenes', type=int, default=0, help='the first N scenes only (0: all)')
    a = ap.parse_args()
    scenes = sorted(d for d in os.listdir(a.campaign) if os.path.exists(os.path.join(a.campaign, d, 'scene.obj')))
    if a.scenes:
        scenes = scenes[:a.scenes]
    for k, name in enumerate(scenes):
        src, dst = os.path.join(a.campaign, name), os.path.join(a.out, name)
        os.makedirs(dst, exist_ok=True)
        for f in os.listdir(src):
            if f != 'scene.obj' and not os.path.exists(os.path.join(dst, f)):
                os.symlink(os.path.abspath(os.path.join(src, f)), os.path.join(dst, f))
        vlines, objs = read_obj(os.path.join(src, 'scene.obj'))
        V = np.array([[float(x) for x in v] for v in vlines])
        if a.variant == 'round':
            digits = int(a.value if a.value is not None else 5)
            vlines = [['%.*f' % (digits, x) for x in v] for v in V]
        if a.variant == 'displace':
            plan = json.load(open(os.path.join(src, 'plan.json')))
            moved = displaced(V, objs, plan, a.value if a.value is not None else 10.0, random.Random(a.seed * 1000 + k))
            changed = np.abs(moved - V).max(axis=1) > 0
            vlines = [['%.5f' % x for x in moved[i]] if changed[i] else vlines[i] for i in range(len(V))]
            V = moved
        with open(os.path.join(dst, 'scene.stl' if a.variant == 'stl' else 'scene.obj'), 'w') as o:
            if a.variant == 'stl':
                for name_, faces in objs:
                    o.write('solid %s\n' % name_)
                    for f in faces:
                        o.write('  facet normal %e %e %e\n    outer loop\n' % tuple(face_normal(V, f)))
                        for i in f:
                            o.write('      vertex %s %s %s\n' % tuple(vlines[i]))
                        o.write('    endloop\n  endfacet\n')
                    o.write('endsolid %s\n' % name_)
            elif a.variant == 'soup':
                count = 0
                for name_, faces in objs:
                    o.write('o %s\n' % name_)
                    for f in faces:
                        for i in f:
                            o.write('v %s %s %s\n' % tuple(vlines[i]))
                        o.write('f %d %d %d\n' % (count + 1, count + 2, count + 3))
                        count += 3
            else:
                for v in vlines:
                    o.write('v %s %s %s\n' % tuple(v))
                normals = 0
                for name_, faces in objs:
                    if a.variant == 'groups':
                        o.write('g %s\nusemtl m_%s\n' % (name_, name_))
                    else:
                        o.write('o %s\n' % name_)
                    for f in faces:
                        if a.variant == 'groups':
                            normals += 1
                            o.write('vn %.6f %.6f %.6f\n' % tuple(face_normal(V, f)))
                            o.write('f ' + ' '.join('%d//%d' % (i + 1, normals) for i in f) + '\n')
                        else:
                            o.write('f ' + ' '.join(str(i + 1) for i in f) + '\n')


if __name__ == '__main__':
    main()
