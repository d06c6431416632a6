#!/usr/bin/python3
"""Scans from the viewpoints `ewis plan` chooses, as a campaign for `ewis evaluate --campaign`.

The project's campaigns (`ewis simulate --campaign`) scan every scene from one kind of view: the sensor above
the plate, looking down at the defect's place. A robot following the offline plan (the paper's first half)
scans from the views `ewis plan` picks instead: the best single view of the cables and the covering set,
whose later views look at the cables' sides, often at a grazing angle over the plate's edge, with few points
of the rigid parts to register on. This script makes such scans:
  1. `ewis simulate --scene-only --campaign N` (scene.obj, plan.json, asbuilt.obj, scene_truth.json; half
     the scenes with a defect, as a campaign has);
  2. `ewis plan --element all-cables --measurable` per scene (the best views and the covering set);
  3. per scene, a scan from the best view (rank 1) and from the covering set's views of order 2 and 3
     (`--views`), each by `ewis simulate --cad --plan --viewpoints` (the project's scanner: noise along the
     rays, outliers, a perturbed pose.txt), into OUT/scene_III_vK (K: 1 best, 2 and 3 the cover's).
The truth's defects are the scene's whatever the view sees: a defect the view does not show is counted as a
miss by `ewis evaluate`, so read the misses with the scan's picture (scan.png) beside them.

Usage: planned_views.py --ewis build/bin/ewis --out DIR [--scenes 10] [--seed 1] [--cables 3] [--views 1,2,3]
                        [--noise-mm 0.2] [--outliers 0.4] [--step 10]
"""
import argparse
import json
import os
import subprocess
import sys


def run(cmd):
    r = subprocess.run(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    if r.returncode != 0:
        sys.exit("failed (%d): %s\n%s" % (r.returncode, " ".join(cmd), r.stderr))
    return r


def view_poses(viewpoints, orders):
    """{order: camera_to_cad}: order 1 is the best single view, order k > 1 the covering set's k-th view."""
    poses = {}
    for k in orders:
        if k == 1:
            poses[k] = viewpoints["best"][0]["camera_to_cad"]
            continue
        cover = viewpoints.get("coverage_set", {}).get("viewpoints", [])
        match = [v for v in cover if v.get("order") == k]
        if match:
            poses[k] = match[0]["camera_to_cad"]
    return poses


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--ewis", required=True)
    ap.add_argument("--out", required=True)
    ap.add_argument("--scenes", type=int, default=10)
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--cables", type=int, default=3)
    ap.add_argument("--views", default="1,2,3", help="1: the best view; k > 1: the covering set's k-th view")
    ap.add_argument("--noise-mm", type=float, default=0.2)
    ap.add_argument("--outliers", type=float, default=0.4)
    ap.add_argument("--step", type=float, default=10.0, help="the plan's angular step (deg)")
    a = ap.parse_args()
    orders = [int(v) for v in a.views.split(",")]
    work = os.path.join(a.out, "_work")
    os.makedirs(work, exist_ok=True)
    run([a.ewis, "simulate", "--scene-only", "--seed", str(a.seed), "--campaign", str(a.scenes),
         "--cables", str(a.cables), "--out", os.path.join(work, "scenes"), "-q"])
    for i in range(a.scenes):
        scene = os.path.join(work, "scenes", "scene_%03d" % i)
        plan_dir = os.path.join(work, "plan_%03d" % i)
        vp_path = os.path.join(plan_dir, "viewpoints.json")
        if not os.path.exists(vp_path):
            run([a.ewis, "plan", "--cad", os.path.join(scene, "scene.obj"), "--plan", os.path.join(scene, "plan.json"),
                 "--element", "all-cables", "--measurable", "--step", str(a.step), "--out", plan_dir, "-q"])
        with open(vp_path) as f:
            poses = view_poses(json.load(f), orders)
        for k, pose in sorted(poses.items()):
            one = os.path.join(plan_dir, "view_%d.json" % k)
            with open(one, "w") as f:
                json.dump({"best": [{"rank": 1, "camera_to_cad": pose}]}, f)
            out = os.path.join(a.out, "scene_%03d_v%d" % (i, k))
            run([a.ewis, "simulate", "--cad", os.path.join(scene, "scene.obj"), "--plan", os.path.join(scene, "plan.json"),
                 "--viewpoints", one, "--rank", "1", "--seed", str(a.seed * 1000 + i * 10 + k),
                 "--noise-mm", str(a.noise_mm), "--outliers", str(a.outliers), "--out", out, "-q"])
        print("scene %d: views %s" % (i, ",".join(str(k) for k in sorted(poses))), flush=True)


if __name__ == "__main__":
    main()
