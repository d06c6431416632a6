"""A scan written in a camera frame looking along -z with y up (OpenGL's and Blender's convention) is inspected as the
same scan in the contract's frame (z forward, y down): `inspect` turns it 180 deg about x (inspect/pipeline.hpp
`InspectionResult::scan_to_sensor`), says so, and reports the transform of the scan as given. Before, it read as no
depth image from its origin (100 % of its points "behind" others on their ray), and every check along the sensor's
rays was left out."""
import array
import json
import math
import os
import shutil
import unittest

from ewis_cli import run, tmpdir, validate
from test_cad_winding import pose_error


def to_gl_frame(src, dst):
    """Writes the binary little-endian float x y z PLY `src` with y and z negated (180 deg about x)."""
    with open(src, "rb") as f:
        data = f.read()
    end = data.index(b"end_header\n") + len(b"end_header\n")
    header = data[:end].decode()
    assert "format binary_little_endian" in header and header.count("property") == 3, header
    xyz = array.array("f")
    xyz.frombytes(data[end:])
    xyz[1::3] = array.array("f", (-v for v in xyz[1::3]))
    xyz[2::3] = array.array("f", (-v for v in xyz[2::3]))
    with open(dst, "wb") as f:
        f.write(data[:end])
        f.write(xyz.tobytes())


def turned_pose(src, dst):
    """The pose file `src` (scan to CAD) for the scan turned 180 deg about x: its second and third columns negated."""
    with open(src) as f:
        m = [float(v) for v in f.read().split()]
    for r in range(4):
        m[4 * r + 1] = -m[4 * r + 1]
        m[4 * r + 2] = -m[4 * r + 2]
    with open(dst, "w") as f:
        f.write("\n".join(" ".join(repr(v) for v in m[4 * r:4 * r + 4]) for r in range(4)) + "\n")


class ScanConventions(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.dir = tmpdir("scan_conventions")
        cls.scene = os.path.join(cls.dir, "scene")
        run("simulate", "--out", cls.scene, "--seed", "7", "--defect", "clearance", "--quiet", check=0)
        with open(os.path.join(cls.scene, "truth.json")) as f:
            cls.truth = json.load(f)

    @classmethod
    def tearDownClass(cls):
        shutil.rmtree(cls.dir, ignore_errors=True)

    def inspect(self, scan, pose, name):
        out = os.path.join(self.dir, name)
        s = self.scene
        proc = run("inspect", "--cad", os.path.join(s, "scene.obj"), "--plan", os.path.join(s, "plan.json"), "--scan",
                   scan, "--pose", pose, "--out", out, "--quiet", check=0)
        with open(os.path.join(out, "report.json")) as f:
            report = json.load(f)
        validate(report, "report.schema.json")
        return report, proc.stderr

    def findings(self, report):
        return [(e["name"], e["found"], [i["with"] for i in e.get("interferences", [])])
                for e in report["elements"] if e.get("kind") == "cable"]

    def test_a_scan_looking_along_minus_z_is_inspected_as_the_same_scan(self):
        s = self.scene
        gl_scan, gl_pose = os.path.join(self.dir, "scan_gl.ply"), os.path.join(self.dir, "pose_gl.txt")
        to_gl_frame(os.path.join(s, "scan.ply"), gl_scan)
        turned_pose(os.path.join(s, "pose.txt"), gl_pose)
        given, given_err = self.inspect(os.path.join(s, "scan.ply"), os.path.join(s, "pose.txt"), "given")
        gl, gl_err = self.inspect(gl_scan, gl_pose, "gl")
        self.assertNotIn("looks along -z", given_err)
        self.assertIn("looks along -z", gl_err)
        self.assertNotIn("not a depth image", gl_err)
        self.assertTrue(gl["scan"]["sensor_frame"])
        self.assertEqual(gl["verdict"], given["verdict"])
        self.assertEqual(self.findings(gl), self.findings(given))
        # The reported transform maps the scan as given: the truth's, turned.
        truth = dict(self.truth)
        t = truth["camera_to_cad"]
        truth["camera_to_cad"] = [[row[0], -row[1], -row[2], row[3]] for row in t]
        angle, offset = pose_error(gl, truth)
        self.assertLess(angle, 0.05)
        self.assertLess(offset, 0.3)
        for e_gl, e_given in zip(gl["elements"], given["elements"]):
            if e_gl.get("kind") == "cable" and e_gl.get("min_bend_radius_mm") is not None:
                self.assertAlmostEqual(e_gl["min_bend_radius_mm"], e_given["min_bend_radius_mm"],
                                       delta=0.02 * e_given["min_bend_radius_mm"])

    def test_info_measures_it_turned(self):
        s = self.scene
        gl_scan = os.path.join(self.dir, "scan_gl_info.ply")
        to_gl_frame(os.path.join(s, "scan.ply"), gl_scan)
        given = json.loads(run("info", "--scan", os.path.join(s, "scan.ply"), check=0).stdout)
        gl = json.loads(run("info", "--scan", gl_scan, check=0).stdout)
        validate(gl, "info.schema.json")
        self.assertEqual(given["looks_along"], "+z")
        self.assertEqual(gl["looks_along"], "-z")
        self.assertAlmostEqual(gl["occluded_from_origin"], given["occluded_from_origin"], delta=0.01)
        self.assertLess(gl["occluded_from_origin"], 0.5)

if __name__ == "__main__":
    unittest.main()
