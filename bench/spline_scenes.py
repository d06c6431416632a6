#!/usr/bin/python3
"""Scenes of another kind: cables routed along smooth splines, scanned, for `ewis evaluate --campaign`.

The project's scene generator (src/sim) routes every cable as straight runs joined by circular arcs (and
helices), the shape the inspection's bend refinement models (docs/inspect.md: a line-arc-line fillet). A cable
drawn by a routing tool or another simulator bends along a spline whose curvature changes all the time; its
minimum bend radius is the radius of curvature where the curvature peaks, and no circular arc lies there.
This script builds such scenes independently of src/sim (numpy only):
  - a plate with ribs and blocks along its edges (the rigid CAD the registration holds on);
  - 1-3 cables, each a clamped cubic B-spline through random control points (non-planar), swept as a tube
    of 32 sides (--sides) along rotation-minimising frames, ending in connector boxes and passing through 0-1 clamp
    (all `attached`);
  - the as-built route: the nominal control points moved by up to --deviation-mm (ends fixed), so the scan
    differs from the CAD as a real installation does;
  - the truth: each cable's minimum radius of curvature from the spline's analytic derivatives (dense
    parameter grid), where it is, and the as-built centreline; bend defects are rules stricter than the
    as-built radius (allowed = radius / U(0.6, 0.85)), clean cables have allowed = radius / U(1.2, 1.6);
  - no clearance defects: routes are drawn again until every gap exceeds clearance + 2 mm.
With --bundle (or --bundle 3) each scene holds two (three) cables tied side by side instead (the hard case "touching objects"): cable_B is
cable_A's sideways companion (each point moved horizontally, perpendicular to the tangent, by both radii + the gap),
touching or up to 2 mm apart in odd scenes (a clearance defect at clearance 3 mm; the CAD keeps 4.5 mm) and 5-9 mm
apart in even ones, held by shared connectors at both ends; the truth gap is the least distance between the two
as-built centrelines less both radii, and each cable's truth radius comes from the companion's numerical
derivatives; with 3, cable_C is the companion on A's other side (4-9 mm), its own gap to A. No bend defects there.
Each scene is then scanned by `ewis simulate --cad scene.obj --plan plan.json --asbuilt asbuilt.obj
--scene-truth scene_truth.json` (the project's scanner: noise along the rays, 40 % outliers, a perturbed
pose.txt), which writes truth.json with the camera pose. Evaluate with `ewis evaluate --campaign OUT`.

With --wires they are single wires of 1.5-3 mm (3-6 pixels across at the sensor's 0.5 mm spacing).
With --hoses the tubes are hoses of 18-30 mm instead of cables of 4-13 mm (EWIS hoses: their bends of 3-5 d are long
in millimetres, and often begin right at a clamp or connector).
Usage: spline_scenes.py --ewis build/bin/ewis --out DIR [--scenes 20] [--first 0] [--seed 1] [--deviation-mm 6] [--bundle]
                        [--hoses] [--noise-mm 0.2] [--outliers 0.4]
"""
import argparse
import json
import math
import os
import subprocess
import sys

import numpy as np


# ---------------------------------------------------------------- meshes
def box_mesh(centre, axes, half):
    """Oriented box: centre (3), axes (3 x 3, rows are unit axes), half sizes (3)."""
    c = np.asarray(centre, float)
    a = np.asarray(axes, float)
    v = []
    for sx in (-1, 1):
        for sy in (-1, 1):
            for sz in (-1, 1):
                v.append(c + sx * half[0] * a[0] + sy * half[1] * a[1] + sz * half[2] * a[2])
    # vertex index = 4 sx + 2 sy + sz (0/1 each); faces outward
    f = [(0, 1, 3), (0, 3, 2), (4, 6, 7), (4, 7, 5), (0, 4, 5), (0, 5, 1),
         (2, 3, 7), (2, 7, 6), (0, 2, 6), (0, 6, 4), (1, 5, 7), (1, 7, 3)]
    return np.array(v), np.array(f)


def rmf_frames(points):
    """Rotation-minimising frames (double reflection, Wang et al. 2008) along a polyline."""
    t = np.gradient(points, axis=0)
    t /= np.linalg.norm(t, axis=1)[:, None]
    helper = np.array([0.0, 0.0, 1.0]) if abs(t[0][2]) < 0.9 else np.array([1.0, 0.0, 0.0])
    r = np.cross(t[0], helper)
    r /= np.linalg.norm(r)
    rs = [r]
    for i in range(len(points) - 1):
        v1 = points[i + 1] - points[i]
        c1 = v1 @ v1
        rl = rs[-1] - (2.0 / c1) * (v1 @ rs[-1]) * v1
        tl = t[i] - (2.0 / c1) * (v1 @ t[i]) * v1
        v2 = t[i + 1] - tl
        c2 = v2 @ v2
        rn = rl - (2.0 / c2) * (v2 @ rl) * v2 if c2 > 1e-18 else rl
        rs.append(rn / np.linalg.norm(rn))
    rs = np.array(rs)
    return t, rs, np.cross(t, rs)


def tube_mesh(points, radius, sides=32):
    t, r, s = rmf_frames(points)
    ang = 2.0 * math.pi * np.arange(sides) / sides
    ring = np.cos(ang)[None, :, None] * r[:, None, :] + np.sin(ang)[None, :, None] * s[:, None, :]
    v = (points[:, None, :] + radius * ring).reshape(-1, 3)
    n = len(points)
    f = []
    for i in range(n - 1):
        for k in range(sides):
            a, b = i * sides + k, i * sides + (k + 1) % sides
            c, d = a + sides, b + sides
            f += [(a, c, d), (a, d, b)]
    # flat caps
    v = np.vstack([v, points[0], points[-1]])
    c0, c1 = len(v) - 2, len(v) - 1
    for k in range(sides):
        f.append((c0, (k + 1) % sides, k))
        f.append((c1, (n - 1) * sides + k, (n - 1) * sides + (k + 1) % sides))
    return v, np.array(f)


def write_obj(path, objects):
    with open(path, "w") as fh:
        base = 1
        for name, (v, f) in objects:
            fh.write("o %s\n" % name)
            for p in v:
                fh.write("v %.5f %.5f %.5f\n" % tuple(p))
            for tri in f:
                fh.write("f %d %d %d\n" % (tri[0] + base, tri[1] + base, tri[2] + base))
            base += len(v)


# ---------------------------------------------------------------- splines
def basis(knots, i, p, x):
    """Cox-de Boor recursion: the i-th B-spline basis function of degree p at x (the last span closed)."""
    if p == 0:
        last = (knots[i + 1] == knots[-1]) & (x == knots[-1]) & (knots[i] < knots[-1])
        return (((knots[i] <= x) & (x < knots[i + 1])) | last).astype(float)
    out = np.zeros_like(x)
    d1 = knots[i + p] - knots[i]
    d2 = knots[i + p + 1] - knots[i + 1]
    if d1 > 0:
        out += (x - knots[i]) / d1 * basis(knots, i, p - 1, x)
    if d2 > 0:
        out += (knots[i + p + 1] - x) / d2 * basis(knots, i + 1, p - 1, x)
    return out


def curve(ctrl, p, knots, x):
    return sum(basis(knots, i, p, x)[:, None] * ctrl[i] for i in range(len(ctrl)))


def bspline(ctrl, u):
    """Clamped uniform cubic B-spline: points and first/second derivatives at parameters u in [0, 1]."""
    ctrl = np.asarray(ctrl, float)
    n, k = len(ctrl) - 1, 3
    knots = np.concatenate([np.zeros(k), np.linspace(0, 1, n - k + 2), np.ones(k)])
    # the derivatives are B-splines of degree 2 and 1 on the inner knots
    d1 = np.array([k * (ctrl[i + 1] - ctrl[i]) / (knots[i + k + 1] - knots[i + 1]) for i in range(n)])
    kn1 = knots[1:-1]
    d2 = np.array([(k - 1) * (d1[i + 1] - d1[i]) / (kn1[i + k] - kn1[i + 1]) for i in range(n - 1)])
    kn2 = kn1[1:-1]
    return curve(ctrl, k, knots, u), curve(d1, k - 1, kn1, u), curve(d2, k - 2, kn2, u)


def resample(points, step):
    seg = np.linalg.norm(np.diff(points, axis=0), axis=1)
    s = np.concatenate([[0.0], np.cumsum(seg)])
    m = max(2, int(round(s[-1] / step)) + 1)
    q = np.linspace(0, s[-1], m)
    return np.stack([np.interp(q, s, points[:, j]) for j in range(3)], axis=1), s[-1]


def min_radius(ctrl):
    u = np.linspace(0, 1, 20001)
    p, d1, d2 = bspline(ctrl, u)
    kappa = np.linalg.norm(np.cross(d1, d2), axis=1) / np.linalg.norm(d1, axis=1) ** 3
    i = int(np.argmax(kappa))
    return 1.0 / kappa[i], p[i]


def companion(ctrl, offset_mm, u):
    """The spline's companion in a bundle: each point moved offset_mm sideways (horizontal, perpendicular to the
    tangent), with its derivatives in u (those of the offset, from the spline's own up to the third order by
    differences of the analytic second derivative)."""
    p, d1, d2 = bspline(ctrl, u)
    up = np.array([0.0, 0.0, 1.0])
    side = np.cross(d1, up)
    side /= np.linalg.norm(side, axis=1)[:, None]
    q = p + offset_mm * side
    dq = np.gradient(q, u, axis=0, edge_order=2)
    ddq = np.gradient(dq, u, axis=0, edge_order=2)
    return q, dq, ddq


def companion_min_radius(ctrl, offset_mm):
    u = np.linspace(0, 1, 40001)
    q, dq, ddq = companion(ctrl, offset_mm, u)
    kappa = np.linalg.norm(np.cross(dq, ddq), axis=1) / np.linalg.norm(dq, axis=1) ** 3
    inner = slice(20, len(u) - 20)  # the differences' one-sided ends left out
    i = int(np.argmax(kappa[inner])) + 20
    return 1.0 / kappa[i], q[i]


# ---------------------------------------------------------------- scene
def seg_dist(a, b):
    """Smallest distance between two point sets (brute force on 2 mm samples)."""
    best = np.inf
    for i in range(0, len(a), 256):
        d = np.linalg.norm(a[i:i + 256, None, :] - b[None, :, :], axis=2)
        best = min(best, d.min())
    return best


def point_box_distance(points, centre, axes, half):
    q = (points - centre) @ np.asarray(axes).T
    d = np.maximum(np.abs(q) - np.asarray(half), 0.0)
    return np.linalg.norm(d, axis=1)


def look_at(eye, target, up):
    z = target - eye
    z /= np.linalg.norm(z)
    x = np.cross(z, up)
    x /= np.linalg.norm(x)
    y = np.cross(z, x)
    m = np.eye(4)
    m[:3, 0], m[:3, 1], m[:3, 2], m[:3, 3] = x, y, z, eye
    return m


# --hoses: the diameters drawn instead (mm, each +- 0.3): hoses, whose bends of 3-5 d are long in millimetres
HOSES = [18.0, 22.0, 26.0, 30.0]
# --wires: single wires of 1.5-3 mm (each +- 0.1), 3-6 pixels across at 0.5 mm spacing
WIRES = [1.5, 2.0, 2.5, 3.0]


def make_scene(rng, index, deviation_mm, bundle=0, sides=32, hoses=False, wires=False):
    plate_half = np.array([300.0, 200.0, 3.0])
    rigid = [("structure", (np.array([0, 0, -3.0]), np.eye(3), plate_half))]
    # ribs along the long edges, a cross rib at each end, blocks in two corners: features in every direction
    rigid.append(("rib_1", (np.array([0, -185.0, 15.0]), np.eye(3), np.array([280.0, 4.0, 15.0]))))
    rigid.append(("rib_2", (np.array([0, 185.0, 20.0]), np.eye(3), np.array([280.0, 4.0, 20.0]))))
    rigid.append(("frame_1", (np.array([-290.0, 0, 25.0]), np.eye(3), np.array([5.0, 150.0, 25.0]))))
    rigid.append(("frame_2", (np.array([290.0, 0, 12.0]), np.eye(3), np.array([5.0, 150.0, 12.0]))))
    a = rng.uniform(0, math.pi / 2)
    rot = np.array([[math.cos(a), math.sin(a), 0], [-math.sin(a), math.cos(a), 0], [0, 0, 1.0]])
    rigid.append(("block_1", (np.array([-230.0, -140.0, 18.0]), rot, np.array([22.0, 14.0, 18.0]))))
    rigid.append(("block_2", (np.array([235.0, 135.0, 10.0]), np.eye(3), np.array([15.0, 25.0, 10.0]))))

    ncables = bundle if bundle else int(rng.integers(1, 4))
    defect_scene = index % 2 == 1
    defect_cable = int(rng.integers(0, ncables)) if defect_scene and not bundle else -1
    if bundle:
        return make_bundle_scene(rng, index, deviation_mm, rigid, defect_scene, bundle, sides)
    cables, nominal_objs, built_objs, plan_elems, truth_cables, defects = [], [], [], [], [], []
    attached_objs = []
    lanes = rng.permutation([-95.0, 0.0, 95.0])[:ncables]
    for c in range(ncables):
        name = "cable_" + "ABC"[c]
        for attempt in range(200):
            if wires:
                d = float(rng.choice(WIRES) + rng.uniform(-0.1, 0.1))
            else:
                d = float(rng.choice(HOSES if hoses else [4.0, 5.5, 7.0, 9.0, 11.0, 13.0]) + rng.uniform(-0.3, 0.3))
            r = d / 2
            n_ctrl = int(rng.integers(6, 9))
            xs = np.linspace(-230, 230, n_ctrl) + np.concatenate([[0], rng.uniform(-25, 25, n_ctrl - 2), [0]])
            ys = lanes[c] + np.concatenate([[0], rng.uniform(-45, 45, n_ctrl - 2), [0]])
            zs = np.concatenate([[30.0], rng.uniform(20 + r, 75, n_ctrl - 2), [30.0]])
            ctrl = np.stack([xs, ys, zs], axis=1)
            # one control point pair pulled together now and then: a tighter bend
            if rng.uniform() < 0.5:
                j = int(rng.integers(2, n_ctrl - 2))
                ctrl[j] += rng.uniform(-1, 1, 3) * np.array([20.0, 35.0, 15.0])
                ctrl[j][2] = max(ctrl[j][2], 20 + r)
            built = ctrl.copy()
            built[2:-2] += rng.uniform(-1, 1, (n_ctrl - 4, 3)) * deviation_mm
            built[2:-2, 2] = np.maximum(built[2:-2, 2], 20 + r)
            rn, _ = min_radius(ctrl)
            rb, loc = min_radius(built)
            if rn < 3.0 * d or rb < 2.5 * d:  # too tight to route (the CAD keeps >= 3 d)
                continue
            u = np.linspace(0, 1, 6001)
            pn, _ = resample(bspline(ctrl, u)[0], 0.5)
            pb, length = resample(bspline(built, u)[0], 0.5)
            if pb[:, 2].min() < r + 5.0 + 3.0 or pn[:, 2].min() < r + 5.0 + 3.0:
                continue  # gap to the plate above clearance + 2
            if np.abs(pb[:, 1]).max() > 150 or np.abs(pn[:, 1]).max() > 150:
                continue
            ok = True
            for (o_name, o_r, o_pts, o_ptsn) in cables:
                if seg_dist(pb[::4], o_pts[::4]) < r + o_r + 3.0 + 2.0 + 2.0 or \
                        seg_dist(pn[::4], o_ptsn[::4]) < r + o_r + 3.0 + 2.0 + 2.0:
                    ok = False
            if ok:
                break
        else:
            raise RuntimeError("no route found for %s" % name)
        cables.append((name, r, pb, pn))
        # connectors at both ends (the cable enters 8 mm), a clamp at 30-70 % of the length half the time
        attached = []
        for end, (p, t) in enumerate([(pb[0], pb[0] - pb[1]), (pb[-1], pb[-1] - pb[-2])]):
            t = t / np.linalg.norm(t)
            side = np.cross(t, [0, 0, 1.0])
            side /= np.linalg.norm(side)
            axes = np.stack([t, side, np.cross(t, side)])
            cname = "connector_%s%d" % ("ABC"[c], end + 1)
            attached_objs.append((cname, (p + t * (12.0 - 8.0), axes, np.array([12.0, r + 6.0, r + 6.0]))))
            attached.append(cname)
        if rng.uniform() < 0.5:
            i = int(len(pb) * rng.uniform(0.3, 0.7))
            t = pb[i + 1] - pb[i - 1]
            t /= np.linalg.norm(t)
            side = np.cross(t, [0, 0, 1.0])
            side /= np.linalg.norm(side)
            axes = np.stack([t, side, np.cross(t, side)])
            cname = "clamp_%s" % "ABC"[c]
            attached_objs.append((cname, (pb[i], axes, np.array([5.0, r + 1.5, r + 1.5]))))
            attached.append(cname)
        nominal_objs.append((name, tube_mesh(pn, r, sides)))
        built_objs.append((name, tube_mesh(pb, r, sides)))
        if c == defect_cable:
            allowed = rb / rng.uniform(0.6, 0.85)
            defects.append({"kind": "bend", "element": name, "radius_mm": round(rb, 4),
                            "location": [round(x, 4) for x in loc]})
        else:
            allowed = rb / rng.uniform(1.2, 1.6)
        plan_elems.append({"name": name, "kind": "cable", "diameter_mm": round(d, 3),
                           "min_bend_radius_mm": round(allowed, 2), "clearance_mm": 3.0, "attached": attached})
        truth_cables.append({"name": name, "diameter_mm": round(d, 3), "min_bend_radius_mm": round(rb, 4),
                             "min_bend_location": [round(x, 4) for x in loc],
                             "nominal_min_bend_radius_mm": round(rn, 4),
                             "allowed_bend_radius_mm": round(allowed, 2), "clearance_mm": 3.0,
                             "attached": attached, "length_mm": round(length, 4),
                             "centerline": [[round(x, 4) for x in p] for p in pb[::2]]})
    # attached parts must not crowd the other cables (a clamp of A beside B would be a clearance defect)
    for (aname, box) in attached_objs:
        for (name, r, pb, pn) in cables:
            if aname[-2] == name[-1] or aname[-1] == name[-1]:
                continue
            if point_box_distance(pb, *box).min() < r + 3.0 + 2.0:
                return None
    for (name, r, pb, pn) in cables:
        for (rname, box) in rigid:
            if point_box_distance(pb, *box).min() < r + 3.0 + 2.0 or point_box_distance(pn, *box).min() < r + 5.0:
                return None
    return finish_scene(rng, index, rigid, attached_objs, nominal_objs, built_objs, plan_elems, truth_cables, defects,
                        "bend" if defect_scene else "none")


def make_bundle_scene(rng, index, deviation_mm, rigid, defect_scene, count=2, sides=32):
    """Cables side by side along their whole length (a bundle): cable_B the sideways companion of cable_A's spline,
    cable_C (count 3) the companion on A's other side; each touching A or nearly (gap 0-2 mm, a clearance defect at
    clearance 3 mm) in odd scenes, 5-9 mm from A in even ones. Shared connectors hold the ends (attached to all)."""
    clearance = 3.0
    u = np.linspace(0, 1, 6001)
    for attempt in range(500):
        da = float(rng.choice([4.0, 5.5, 7.0, 9.0, 11.0]) + rng.uniform(-0.3, 0.3))
        db = float(rng.choice([4.0, 5.5, 7.0, 9.0, 11.0]) + rng.uniform(-0.3, 0.3))
        ra = da / 2
        side_d = [db]
        side_gap = [rng.uniform(0.0, clearance - 1.0) if defect_scene else rng.uniform(clearance + 2.0, clearance + 6.0)]
        n_ctrl = int(rng.integers(6, 9))
        xs = np.linspace(-230, 230, n_ctrl) + np.concatenate([[0], rng.uniform(-25, 25, n_ctrl - 2), [0]])
        ys = rng.uniform(-30, 30) + np.concatenate([[0], rng.uniform(-40, 40, n_ctrl - 2), [0]])
        r_max = max(ra, db / 2)
        zs = np.concatenate([[30.0], rng.uniform(20 + r_max, 70, n_ctrl - 2), [30.0]])
        ctrl = np.stack([xs, ys, zs], axis=1)
        built = ctrl.copy()
        built[2:-2] += rng.uniform(-1, 1, (n_ctrl - 4, 3)) * deviation_mm
        built[2:-2, 2] = np.maximum(built[2:-2, 2], 20 + r_max)
        if count == 3:
            side_d.append(float(rng.choice([4.0, 5.5, 7.0, 9.0]) + rng.uniform(-0.3, 0.3)))
            side_gap.append(rng.uniform(0.0, clearance - 1.0) if defect_scene else
                            rng.uniform(clearance + 2.0, clearance + 6.0))
            r_max = max(r_max, side_d[1] / 2)
            built[2:-2, 2] = np.maximum(built[2:-2, 2], 20 + r_max)
        # cable_B at +offset (left of A's tangent, seen from above), cable_C at -offset
        offsets = [ra + d / 2 + g for d, g in zip(side_d, side_gap)]
        if count == 3:
            offsets[1] = -offsets[1]
        cables = [("cable_A", da, 0.0)] + [("cable_" + "BC"[k], side_d[k], offsets[k]) for k in range(count - 1)]
        ok = True
        routes = []
        for name, d, off in cables:
            if off == 0.0:
                rn, _ = min_radius(ctrl)
                rb, loc = min_radius(built)
                pn, _ = resample(bspline(ctrl, u)[0], 0.5)
                pb, length = resample(bspline(built, u)[0], 0.5)
            else:
                rn, _ = companion_min_radius(ctrl, off)
                rb, loc = companion_min_radius(built, off)
                pn, _ = resample(companion(ctrl, off, u)[0], 0.5)
                pb, length = resample(companion(built, off, u)[0], 0.5)
            if rn / d < 3.0 or rb / d < 2.5:
                ok = False
            if min(pb[:, 2].min(), pn[:, 2].min()) - d / 2 < clearance + 5.0:
                ok = False  # gap to the plate above clearance + 2
            if max(np.abs(pb[:, 1]).max(), np.abs(pn[:, 1]).max()) > 150:
                ok = False
            routes.append([name, d, off, rn, rb, loc, pn, pb, length])
        if not ok:
            continue
        # the true gaps to A: the least distance between the as-built centrelines less both radii (a companion may
        # come closer than its offset where the spline bends towards it)
        gaps = [seg_dist(routes[0][7], r[7]) - ra - r[1] / 2 for r in routes[1:]]
        nominal_gaps = [seg_dist(routes[0][6], r[6]) - ra - r[1] / 2 for r in routes[1:]]
        if defect_scene and not all(0.0 <= g <= clearance - 1.0 for g in gaps):
            continue
        if not defect_scene and not all(g >= clearance + 2.0 for g in gaps):
            continue
        if not defect_scene and not all(g >= clearance + 0.5 for g in nominal_gaps):
            continue
        break
    else:
        raise RuntimeError("no bundle route found")
    if defect_scene:
        # the nominal (CAD) bundle keeps the clearance; the as-built one was tied tighter
        for r in routes[1:]:
            wide = (ra + r[1] / 2 + clearance + 1.5) * (1.0 if r[2] > 0 else -1.0)
            r[6], _ = resample(companion(ctrl, wide, u)[0], 0.5)
    attached_objs, attached = [], []
    pa_b = routes[0][7]
    for end in (0, 1):
        k = 0 if end == 0 else -1
        t = (pa_b[1] - pa_b[0]) if end == 0 else (pa_b[-2] - pa_b[-1])
        t = -t / np.linalg.norm(t)
        ends = np.array([r[7][k] for r in routes])
        mid = 0.5 * (ends.min(axis=0) + ends.max(axis=0)) if count == 2 else ends[0]
        side = ends[1] - ends[0]
        side -= (side @ t) * t
        side /= np.linalg.norm(side)
        axes = np.stack([t, side, np.cross(t, side)])
        reach = 0.5 * np.linalg.norm(ends[1] - ends[0]) if count == 2 else max(abs((e - mid) @ side) for e in ends)
        half_side = reach + r_max + 6.0
        cname = "connector_%s%d" % ("AB" if count == 2 else "ABC", end + 1)
        attached_objs.append((cname, (mid + t * (12.0 - 8.0), axes, np.array([12.0, half_side, r_max + 6.0]))))
        attached.append(cname)
    nominal_objs = [(r[0], tube_mesh(r[6], r[1] / 2, sides)) for r in routes]
    built_objs = [(r[0], tube_mesh(r[7], r[1] / 2, sides)) for r in routes]
    plan_elems, truth_cables, defects = [], [], []
    for name, d, off, rnom, rbuilt, loc, pn, pts, length in routes:
        allowed = rbuilt / rng.uniform(1.2, 1.6)
        plan_elems.append({"name": name, "kind": "cable", "diameter_mm": round(d, 3),
                           "min_bend_radius_mm": round(allowed, 2), "clearance_mm": clearance, "attached": attached})
        truth_cables.append({"name": name, "diameter_mm": round(d, 3), "min_bend_radius_mm": round(rbuilt, 4),
                             "min_bend_location": [round(x, 4) for x in loc],
                             "nominal_min_bend_radius_mm": round(rnom, 4),
                             "allowed_bend_radius_mm": round(allowed, 2), "clearance_mm": clearance,
                             "attached": attached, "length_mm": round(length, 4),
                             "centerline": [[round(x, 4) for x in p] for p in pts[::2]]})
    if defect_scene:
        for r, g in zip(routes[1:], gaps):
            defects.append({"kind": "clearance", "element": "cable_A", "with": r[0], "gap_mm": round(g, 4)})
    for r in routes:
        for (rname, box) in rigid:
            if point_box_distance(r[7], *box).min() < r[1] / 2 + clearance + 2.0:
                return None
    return finish_scene(rng, index, rigid, attached_objs, nominal_objs, built_objs, plan_elems, truth_cables, defects,
                        "clearance" if defect_scene else "none")


def finish_scene(rng, index, rigid, attached_objs, nominal_objs, built_objs, plan_elems, truth_cables, defects,
                 requested):
    rigid_objs = [(n, box_mesh(*b)) for n, b in rigid + attached_objs]
    plan = {"units": "mm", "elements": plan_elems + [{"name": n, "kind": "rigid"} for n, _ in rigid + attached_objs]}
    # the sensor 560-640 mm from the scene's middle, within 30 deg of straight down
    tilt = rng.uniform(0, math.radians(30))
    az = rng.uniform(0, 2 * math.pi)
    dirv = np.array([math.sin(tilt) * math.cos(az), math.sin(tilt) * math.sin(az), math.cos(tilt)])
    target = np.array([rng.uniform(-20, 20), rng.uniform(-20, 20), 30.0])
    eye = target + dirv * rng.uniform(560, 640)
    roll = rng.uniform(0, 2 * math.pi)
    cam = look_at(eye, target, np.array([math.cos(roll), math.sin(roll), 0.0]))
    truth = {"seed": int(index), "requested_defect": requested, "cables": truth_cables,
             "defects": defects, "foreign_objects": [], "camera_to_cad": cam.tolist(),
             "generator": "bench/spline_scenes.py"}
    return rigid_objs, nominal_objs, built_objs, plan, truth


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--ewis", default="build/bin/ewis")
    ap.add_argument("--out", required=True)
    ap.add_argument("--scenes", type=int, default=20)
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--first", type=int, default=0,
                    help="index of the first scene (scene i is the same whatever --first and --scenes)")
    ap.add_argument("--deviation-mm", type=float, default=6.0)
    ap.add_argument("--noise-mm", type=float, default=None)
    ap.add_argument("--outliers", type=float, default=None)
    ap.add_argument("--bundle", type=int, nargs="?", const=2, default=0, choices=[2, 3],
                    help="2 or 3 cables side by side (touching or nearly in odd scenes: clearance defects)")
    ap.add_argument("--hoses", action="store_true",
                    help="hoses of 18-30 mm instead of cables of 4-13 mm (not with --bundle)")
    ap.add_argument("--wires", action="store_true",
                    help="single wires of 1.5-3 mm instead of cables of 4-13 mm (not with --bundle)")
    ap.add_argument("--sides", type=int, default=32,
                    help="sides of each cable's mesh (a coarse CAD export: 8-12; the truth keeps the vertices' radius)")
    a = ap.parse_args()
    os.makedirs(a.out, exist_ok=True)
    for i in range(a.first, a.first + a.scenes):
        rng = np.random.default_rng([a.seed, i])
        made = None
        while made is None:
            made = make_scene(rng, i, a.deviation_mm, a.bundle, a.sides, a.hoses, a.wires)
        rigid_objs, nominal_objs, built_objs, plan, truth = made
        src = os.path.join(a.out, "scene_%03d_cad" % i)
        dst = os.path.join(a.out, "scene_%03d" % i)
        os.makedirs(src, exist_ok=True)
        write_obj(os.path.join(src, "scene.obj"), nominal_objs + rigid_objs)
        write_obj(os.path.join(src, "asbuilt.obj"), built_objs + rigid_objs)
        json.dump(plan, open(os.path.join(src, "plan.json"), "w"), indent=1)
        json.dump(truth, open(os.path.join(src, "scene_truth.json"), "w"), indent=1)
        cmd = [a.ewis, "simulate", "--out", dst, "--cad", os.path.join(src, "scene.obj"), "--plan",
               os.path.join(src, "plan.json"), "--asbuilt", os.path.join(src, "asbuilt.obj"), "--scene-truth",
               os.path.join(src, "scene_truth.json"), "--seed", str(a.seed * 1000 + i), "--quiet"]
        if a.noise_mm is not None:
            cmd += ["--noise-mm", str(a.noise_mm)]
        if a.outliers is not None:
            cmd += ["--outliers", str(a.outliers)]
        subprocess.run(cmd, check=True)
        print("scene %d/%d: %d cable(s), %s" % (i - a.first + 1, a.scenes, len(truth["cables"]),
                                               ", ".join("%s %.1f mm (%.1f d)" % (c["name"], c["min_bend_radius_mm"],
                                                                                  c["min_bend_radius_mm"] / c["diameter_mm"])
                                                         for c in truth["cables"])), file=sys.stderr)


if __name__ == "__main__":
    main()
