"""A scan written in another camera convention than the contract's (z forward, x right, y down) is inspected as the
same scan: looking along -z with y up (OpenGL's and Blender's) or along +x with z up (a body frame, as ROS's
camera_link). `inspect` turns it (register/sensor_origin.hpp `scan_convention`, InspectionResult::scan_to_sensor),
says so, and reports the transform of the scan as given; `ewis info` gives `looks_along`. Before, a -z scan read as no
depth image from its origin (100 % of its points "behind" others on their ray), and every check along the sensor's
rays was left out."""
import array
import json
import os
import unittest

from ewis_cli import run, validate
from scene_fixtures import SimulatedDemo, pose_error


def read_xyz(src):
    """The header and the float x y z of a binary little-endian PLY."""
    with open(src, "rb") as f:
        data = f.read()
    end = data.index(b"end_header\n") + len(b"end_header\n")
    header = data[:end]
    assert b"format binary_little_endian" in header and header.count(b"property") == 3, header
    xyz = array.array("f")
    xyz.frombytes(data[end:])
    return header, xyz


def write_turned(src, dst, axes):
    """Writes the scan `src` with its coordinates (x, y, z) replaced by `axes`: three (index, sign) pairs."""
    header, xyz = read_xyz(src)
    out = array.array("f", bytes(len(xyz) * 4))
    for k, (i, sign) in enumerate(axes):
        out[k::3] = array.array("f", (sign * v for v in xyz[i::3]))
    with open(dst, "wb") as f:
        f.write(header)
        f.write(out.tobytes())


def turned_pose(src, dst, axes):
    """The pose file `src` (scan to CAD) for the scan written by write_turned(axes): P R^T, R the turn."""
    with open(src) as f:
        m = [float(v) for v in f.read().split()]
    # R maps given -> turned: turned[k] = sign_k * given[i_k]; P' = P R^T: column i_k of P' ... column k of P'
    # is P's column i_k times sign_k.
    out = [0.0] * 16
    for r in range(4):
        out[4 * r + 3] = m[4 * r + 3]
        for k, (i, sign) in enumerate(axes):
            out[4 * r + k] = sign * m[4 * r + i]
    with open(dst, "w") as f:
        f.write("\n".join(" ".join(repr(v) for v in out[4 * r:4 * r + 4]) for r in range(4)) + "\n")


GL = ((0, 1), (1, -1), (2, -1))        # x right, y up, z backward (OpenGL, Blender)
ROS_BODY = ((2, 1), (0, -1), (1, -1))  # x forward, y left, z up (ROS camera_link)


class ScanConventions(SimulatedDemo, unittest.TestCase):
    scratch = "scan_conventions"

    def findings(self, report):
        return [(e["name"], e["found"], [i["with"] for i in e.get("interferences", [])])
                for e in report["elements"] if e.get("kind") == "cable"]

    def given(self):
        if not hasattr(type(self), "given_report"):
            s = self.scene
            type(self).given_report = self.inspect_demo("given")
        return type(self).given_report

    def assert_inspected_as_given(self, axes, name, looks_along):
        s = self.scene
        scan, pose = os.path.join(self.dir, f"scan_{name}.ply"), os.path.join(self.dir, f"pose_{name}.txt")
        write_turned(os.path.join(s, "scan.ply"), scan, axes)
        turned_pose(os.path.join(s, "pose.txt"), pose, axes)
        given, given_err = self.given()
        report, err = self.inspect_demo(name, scan=scan, pose=pose)
        self.assertNotIn("looks along", given_err)
        self.assertIn(f"looks along {looks_along}", err)
        self.assertNotIn("not a depth image", err)
        self.assertTrue(report["scan"]["sensor_frame"])
        self.assertEqual(report["verdict"], given["verdict"])
        self.assertEqual(self.findings(report), self.findings(given))
        # The reported transform maps the scan as given: the truth's, turned (its columns as the pose's).
        truth = dict(self.truth)
        t = truth["camera_to_cad"]
        truth["camera_to_cad"] = [[sign * row[i] for i, sign in axes] + [row[3]] for row in t]
        angle, offset = pose_error(report, truth)
        self.assertLess(angle, 0.05)
        self.assertLess(offset, 0.3)
        for e, e_given in zip(report["elements"], given["elements"]):
            if e.get("kind") == "cable" and e.get("min_bend_radius_mm") is not None:
                self.assertAlmostEqual(e["min_bend_radius_mm"], e_given["min_bend_radius_mm"],
                                       delta=0.02 * e_given["min_bend_radius_mm"])
        info = json.loads(run("info", "--scan", scan, check=0).stdout)
        validate(info, "info.schema.json")
        self.assertEqual(info["looks_along"], looks_along)
        self.assertLess(info["occluded_from_origin"], 0.5)

    def test_a_camera_frame_looking_along_minus_z_with_y_up(self):
        self.assert_inspected_as_given(GL, "gl", "-z")

    def test_a_body_frame_x_forward_z_up(self):
        self.assert_inspected_as_given(ROS_BODY, "body", "+x")

    def test_info_of_the_scan_as_given(self):
        info = json.loads(run("info", "--scan", os.path.join(self.scene, "scan.ply"), check=0).stdout)
        self.assertEqual(info["looks_along"], "+z")
        self.assertLess(info["occluded_from_origin"], 0.5)

if __name__ == "__main__":
    unittest.main()
