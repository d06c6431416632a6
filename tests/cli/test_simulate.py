"""ewis simulate as CONTRACT.md fixes it: the scene folder, truth and plan valid against the schemas, seeds."""
import filecmp
import json
import os
import unittest

from ewis_cli import run, tmpdir, validate

FILES = ["scene.obj", "plan.json", "scan.ply", "pose.txt", "truth.json"]


def load(path):
    with open(path) as f:
        return json.load(f)


class SimulateTest(unittest.TestCase):
    def test_scene_folder_and_schemas(self):
        d = tmpdir("sim")
        run("simulate", "--out", d, "--seed", "3", "--defect", "clearance", "--quiet", check=0)
        for f in FILES:
            self.assertTrue(os.path.getsize(os.path.join(d, f)) > 0, f)
        self.assertTrue(any(f.endswith(".png") for f in os.listdir(d)))
        truth = load(os.path.join(d, "truth.json"))
        validate(truth, "truth.schema.json")
        plan = load(os.path.join(d, "plan.json"))
        validate(plan, "plan.schema.json")
        self.assertEqual({x["kind"] for x in truth["defects"]}, {"clearance"})
        cables = {e["name"] for e in plan["elements"] if e["kind"] == "cable"}
        self.assertEqual({c["name"] for c in truth["cables"]}, cables)
        # the scan is in the sensor frame: ewis info sees points about 600 mm in front of the sensor
        info = json.loads(run("info", "--scan", os.path.join(d, "scan.ply"), check=0).stdout)
        self.assertGreater(info["points"], 100000)
        self.assertLess(info["resolution_mm"], 2.0)  # the mean, inflated by the 40% outliers

    def test_same_seed_same_bytes_any_threads(self):
        a, b = tmpdir("sim-a"), tmpdir("sim-b")
        run("simulate", "--out", a, "--seed", "5", "--threads", "1", "--quiet", check=0)
        run("simulate", "--out", b, "--seed", "5", "--threads", "2", "--quiet", check=0)
        for f in FILES:
            self.assertTrue(filecmp.cmp(os.path.join(a, f), os.path.join(b, f), shallow=False), f)

    def test_campaign_half_with_defects(self):
        d = tmpdir("campaign")
        run("simulate", "--out", d, "--seed", "1", "--campaign", "4", "--quiet", check=0)
        scenes = sorted(x for x in os.listdir(d) if os.path.isdir(os.path.join(d, x)))
        self.assertEqual(len(scenes), 4)
        with_defects = sum(1 for s in scenes if load(os.path.join(d, s, "truth.json"))["defects"])
        self.assertEqual(with_defects, 2)

    def test_evaluate_a_small_campaign(self):
        # CONTRACT "ewis evaluate": each scene inspected with its pose, compared with its truth; evaluation.json valid
        # against its schema; --no-html and --no-clouds leave report.json alone in each scene's folder.
        camp, out = tmpdir("eval-camp"), tmpdir("eval-out")
        run("simulate", "--out", camp, "--seed", "1", "--campaign", "2", "--quiet", check=0)
        run("evaluate", "--campaign", camp, "--out", out, "--no-html", "--no-clouds", "--quiet", check=0)
        ev = load(os.path.join(out, "evaluation.json"))
        validate(ev, "evaluation.schema.json")
        self.assertEqual(ev["scenes"], 2)
        self.assertEqual(ev["failed_runs"], 0)
        self.assertEqual(ev["verdicts"]["correct"], 2)
        self.assertTrue(os.path.getsize(os.path.join(out, "evaluation.md")) > 0)
        for s in sorted(x for x in os.listdir(camp) if os.path.isdir(os.path.join(camp, x))):
            self.assertEqual(sorted(os.listdir(os.path.join(out, s))), ["report.json"], s)
            validate(load(os.path.join(out, s, "report.json")), "report.schema.json")

    def test_cable_diameters_drawn_from_the_range_asked(self):
        # --cable-diameter-mm LO HI: every cable's diameter in [LO, HI] (single wires), scenes still valid; without it
        # the same seed draws the defaults (3-30 mm)
        for seed in ("4", "9"):
            d = tmpdir("sim-wires-" + seed)
            run("simulate", "--out", d, "--seed", seed, "--cables", "3", "--cable-diameter-mm", "1.5", "3",
                "--scene-only", "--quiet", check=0)
            plan = load(os.path.join(d, "plan.json"))
            validate(plan, "plan.schema.json")
            diameters = [e["diameter_mm"] for e in plan["elements"] if e["kind"] == "cable"]
            self.assertEqual(len(diameters), 3)
            for x in diameters:
                self.assertTrue(1.5 <= x <= 3.0, diameters)
        for bad in (["3", "1.5"], ["0.1", "2"], ["1"]):
            proc = run("simulate", "--out", tmpdir("sim-wires-bad"), "--cable-diameter-mm", *bad, "--quiet")
            self.assertEqual(proc.returncode, 2, bad)
            self.assertEqual(len(proc.stderr.strip().splitlines()), 1, proc.stderr)

    def test_bad_option_exit_2(self):
        d = tmpdir("sim-bad")
        proc = run("simulate", "--out", d, "--defect", "nonsense")
        self.assertEqual(proc.returncode, 2)


if __name__ == "__main__":
    unittest.main()
