"""A harness drawn as one CAD element with a branch (DESIGN "branching harnesses"): a simulated scene's cable_A gets a
straight branch of 0.7 times its diameter, added to its OBJ object in both the CAD and the as-built geometry, is
scanned by `ewis simulate --cad` and inspected. No start of the plan's radius takes the branch, so only the trunk is
traced; the branch's points beside it read as a foreign object 1.0 mm away (a false alarm) until parts of a cable's
own CAD that no run traced were told apart (docs/inspect.md "A branch of the cable's own CAD")."""
import json
import math
import os
import shutil
import unittest

from ewis_cli import run, tmpdir, validate
from scene_fixtures import tube_mesh


def add_branch(src, dst, cable, fraction, angle_deg, length_mm, radius_scale):
    """Copies the scene in src to dst with a branch added to `cable` (OBJ object), leaving its centreline at
    `fraction` of it, angle_deg off it, half-way between sideways and up. Returns the fork point."""
    os.makedirs(dst, exist_ok=True)
    with open(os.path.join(src, "scene_truth.json")) as f:
        truth = json.load(f)
    with open(os.path.join(src, "plan.json")) as f:
        plan = json.load(f)
    line = next(c for c in truth["cables"] if c["name"] == cable)["centerline"]
    radius = 0.5 * next(e for e in plan["elements"] if e["name"] == cable)["diameter_mm"]
    i = int(fraction * (len(line) - 1))
    fork = line[i]
    t = [line[min(i + 2, len(line) - 1)][k] - line[max(i - 2, 0)][k] for k in range(3)]
    n = math.sqrt(sum(x * x for x in t))
    t = [x / n for x in t]
    up = [-t[2] * t[0], -t[2] * t[1], 1.0 - t[2] * t[2]]  # z without its part along t
    n = math.sqrt(sum(x * x for x in up))
    up = [x / n for x in up]
    side = [t[1] * up[2] - t[2] * up[1], t[2] * up[0] - t[0] * up[2], t[0] * up[1] - t[1] * up[0]]
    perp = [math.sqrt(0.5) * (side[k] + up[k]) for k in range(3)]
    a = math.radians(angle_deg)
    d = [math.cos(a) * t[k] + math.sin(a) * perp[k] for k in range(3)]
    verts, tris = tube_mesh(fork, [fork[k] + length_mm * d[k] for k in range(3)], radius_scale * radius)
    for name in ("scene.obj", "asbuilt.obj"):
        with open(os.path.join(src, name)) as f:
            lines = f.read().split("\n")
        base = sum(1 for x in lines if x.startswith("v ")) + 1
        first = next(j for j, x in enumerate(lines) if x.startswith("o "))
        at = lines.index(f"o {cable}")
        vs = [f"v {x:.4f} {y:.4f} {z:.4f}" for x, y, z in verts]
        fs = [f"f {p + base} {q + base} {r + base}" for p, q, r in tris]
        lines = lines[:first] + vs + lines[first:at + 1] + fs + lines[at + 1:]
        with open(os.path.join(dst, name), "w") as f:
            f.write("\n".join(lines))
    for name in ("plan.json", "scene_truth.json"):
        shutil.copy(os.path.join(src, name), dst)
    return fork


class Branch(unittest.TestCase):
    def test_an_untraced_branch_of_another_diameter_is_reported_not_an_interference(self):
        d = tmpdir("branch")
        plain, cad, scan, out = (os.path.join(d, x) for x in ("plain", "cad", "scan", "out"))
        run("simulate", "--out", plain, "--seed", 11, "--scene-only", "--quiet", check=0)
        fork = add_branch(plain, cad, "cable_A", 0.5, 35.0, 70.0, 0.7)
        run("simulate", "--cad", os.path.join(cad, "scene.obj"), "--plan", os.path.join(cad, "plan.json"),
            "--asbuilt", os.path.join(cad, "asbuilt.obj"), "--scene-truth", os.path.join(cad, "scene_truth.json"),
            "--seed", 5, "--out", scan, "--quiet", check=0)
        proc = run("inspect", "--cad", os.path.join(scan, "scene.obj"), "--plan", os.path.join(scan, "plan.json"),
                   "--scan", os.path.join(scan, "scan.ply"), "--pose", os.path.join(scan, "pose.txt"), "--out", out,
                   check=0)
        with open(os.path.join(out, "report.json")) as f:
            report = json.load(f)
        validate(report, "report.schema.json")
        with open(os.path.join(scan, "truth.json")) as f:
            truth = json.load(f)
        shutil.rmtree(d, ignore_errors=True)
        self.assertEqual(report["verdict"], "pass")
        a = next(e for e in report["elements"] if e["name"] == "cable_A")
        self.assertEqual(a["interferences"], [])
        self.assertEqual(len(a["untraced_parts"]), 1)
        self.assertLess(math.dist(a["untraced_parts"][0], fork), 15.0)
        self.assertIn("cable_A: part of its CAD seen at", proc.stderr)
        # the trunk is measured as its truth (the branch is straight)
        t = next(c for c in truth["cables"] if c["name"] == "cable_A")
        self.assertAlmostEqual(a["min_bend_radius_mm"], t["min_bend_radius_mm"], delta=0.05 * t["min_bend_radius_mm"])


if __name__ == "__main__":
    unittest.main()
