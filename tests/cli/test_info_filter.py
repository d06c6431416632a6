"""ewis info and ewis filter as CONTRACT.md fixes them: outputs, schemas, exit codes, error lines."""
import json
import math
import os
import unittest

from ewis_cli import grid, read_ply_header, realdata, run, tmpdir, validate, write_ply_binary, write_xyz


class InfoTest(unittest.TestCase):
    def test_grid_spacing_and_bounds(self):
        d = tmpdir("info")
        path = os.path.join(d, "grid.ply")
        write_ply_binary(path, grid(50, 0.5), {"intensity": [1.0] * 2500})
        out = run("info", "--scan", path, check=0)
        info = json.loads(out.stdout)
        validate(info, "info.schema.json")
        self.assertEqual(info["points"], 2500)
        self.assertEqual(info["dropped_nonfinite"], 0)
        self.assertEqual(info["fields"], ["x", "y", "z", "intensity"])
        self.assertAlmostEqual(info["resolution_mm"], 0.5, places=5)
        self.assertEqual(info["bounds_min"], [0, 0, 0])
        self.assertAlmostEqual(info["bounds_max"][0], 24.5, places=4)

    def test_units_and_nonfinite(self):
        d = tmpdir("info")
        path = os.path.join(d, "m.xyz")
        pts = [(0.001 * i, 0.0, 0.0) for i in range(10)] + [(float("nan"), 0.0, 0.0), (0.0, float("inf"), 1.0)]
        write_xyz(path, pts)
        info = json.loads(run("info", "--scan", path, "--scan-units", "m", check=0).stdout)
        validate(info, "info.schema.json")
        self.assertEqual(info["points"], 10)
        self.assertEqual(info["dropped_nonfinite"], 2)
        self.assertAlmostEqual(info["resolution_mm"], 1.0, places=4)
        self.assertAlmostEqual(info["bounds_max"][0], 9.0, places=4)

    def test_real_pcd_with_nans(self):
        path = realdata("pcl", "table_scene_mug_stereo_textured.pcd")
        info = json.loads(run("info", "--scan", path, "--scan-units", "m", check=0).stdout)
        validate(info, "info.schema.json")
        self.assertEqual(info["points"] + info["dropped_nonfinite"], 640 * 480)
        self.assertGreater(info["dropped_nonfinite"], 0)
        self.assertIn("rgba", info["fields"])
        # a table-top scene about a metre from the camera, in mm
        self.assertGreater(info["bounds_max"][2], 500)
        self.assertLess(info["bounds_max"][2], 3000)

    def test_real_files_counts(self):
        expected = {("pcl", "bun0.pcd"): 397, ("pcl", "bun4.pcd"): 361, ("pcl", "chef.pcd"): 5092,
                    ("pcl", "milk.pcd"): 13704, ("pcl", "rs1.pcd"): 289541,
                    ("stanford_bunny", "bun000.ply"): 40256, ("adtree_trees", "tree1.xyz"): 11855}  # README counts newlines; the last line has none
        for parts, count in expected.items():
            path = realdata(*parts)
            info = json.loads(run("info", "--scan", path, check=0).stdout)
            validate(info, "info.schema.json")
            self.assertEqual(info["points"] + info["dropped_nonfinite"], count, parts)

    def test_errors_exit_2_with_one_line(self):
        d = tmpdir("info-bad")
        empty = os.path.join(d, "empty.ply")
        open(empty, "w").close()
        truncated = os.path.join(d, "trunc.ply")
        write_ply_binary(truncated, grid(10, 1.0))
        with open(truncated, "r+b") as f:
            f.truncate(os.path.getsize(truncated) - 7)
        liar = os.path.join(d, "liar.ply")
        with open(liar, "wb") as f:
            f.write(b"ply\nformat binary_little_endian 1.0\nelement vertex 1000000000000\n"
                    b"property float x\nproperty float y\nproperty float z\nend_header\n" + b"\0" * 24)
        garbage = os.path.join(d, "garbage.xyz")
        with open(garbage, "w") as f:
            f.write("1 2 3\n4 five 6\n")
        for path in [os.path.join(d, "missing.ply"), d, empty, truncated, liar, garbage]:
            proc = run("info", "--scan", path, timeout=60)
            self.assertEqual(proc.returncode, 2, path)
            lines = proc.stderr.strip().splitlines()
            self.assertEqual(len(lines), 1, proc.stderr)
            self.assertIn(os.path.basename(path.rstrip("/")), lines[0])
            self.assertEqual(proc.stdout, "")

    def test_help(self):
        for cmd in ["inspect", "plan", "tubes", "info", "filter", "register", "simulate", "evaluate"]:
            proc = run(cmd, "--help", check=0)
            self.assertIn("--threads", proc.stdout)
        self.assertEqual(run("--help").returncode, 0)
        self.assertEqual(run("info").returncode, 2)  # missing --scan
        self.assertEqual(run("no-such-command").returncode, 2)


class FilterTest(unittest.TestCase):
    def test_planted_outliers_removed_and_nothing_else(self):
        d = tmpdir("filter")
        src = os.path.join(d, "in.ply")
        surface = grid(80, 0.5)
        outliers = [(100.0 + 7 * i, -50.0 - 3 * i, 20.0 + 5 * i) for i in range(40)]
        pts = surface + outliers
        write_ply_binary(src, pts, {"intensity": [float(i) for i in range(len(pts))]})
        out = os.path.join(d, "out.ply")
        proc = run("filter", "--scan", src, "--out", out, check=0)
        line = json.loads(proc.stdout.strip().splitlines()[-1])
        validate(line, "filter.schema.json")
        self.assertEqual(line["points_in"], len(pts))
        self.assertEqual(line["points_out"], len(surface))
        header = read_ply_header(out)
        self.assertIn("element vertex %d" % len(surface), header)
        self.assertIn("property float intensity", header)

    def test_explicit_parameters(self):
        d = tmpdir("filter")
        src = os.path.join(d, "line.xyz")
        write_xyz(src, [(float(i), 0, 0) for i in range(10)] + [(50.0, 0, 0)])
        out = os.path.join(d, "out.ply")
        line = json.loads(run("filter", "--scan", src, "--out", out, "--radius-mm", "1.5",
                              "--min-neighbors", "2", check=0).stdout)
        validate(line, "filter.schema.json")
        # both end points of the line have only one neighbour within 1.5 mm; the far point none
        self.assertEqual(line["points_out"], 8)
        self.assertEqual(line["radius_mm"], 1.5)
        self.assertEqual(line["min_neighbors"], 2)

    def test_bad_input_leaves_no_output(self):
        d = tmpdir("filter-bad")
        out = os.path.join(d, "out.ply")
        proc = run("filter", "--scan", os.path.join(d, "nope.pcd"), "--out", out)
        self.assertEqual(proc.returncode, 2)
        self.assertFalse(os.path.exists(out))


if __name__ == "__main__":
    unittest.main()
