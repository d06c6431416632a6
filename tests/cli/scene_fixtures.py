"""Small CAD scenes, plans, poses and scans for the bad-input, plan and determinism CLI tests (issue 9), plus
helpers to run ewis under a memory limit and to check the error contract (exit 2, one stderr line naming the file).
"""
import json
import math
import os
import resource
import shutil
import struct
import subprocess

from ewis_cli import EWIS, run, tmpdir, validate, write_ply_binary

NOT_AVAILABLE = "not available in this build yet"


def run_limited(args, as_bytes=2_000_000_000, timeout=120):
    """Runs ewis with an address-space limit (a header that lies must not make it allocate)."""
    def limit():
        resource.setrlimit(resource.RLIMIT_AS, (as_bytes, as_bytes))
    return subprocess.run([EWIS, *map(str, args)], capture_output=True, text=True, timeout=timeout,
                          preexec_fn=limit)


def error_line(test, proc, path, code=2):
    """Asserts the CONTRACT's error: exit `code`, nothing on stdout, one stderr line naming `path`'s file."""
    test.assertEqual(proc.returncode, code, f"exit {proc.returncode}, expected {code}; stderr: {proc.stderr[-1500:]}")
    lines = proc.stderr.strip().splitlines()
    test.assertEqual(len(lines), 1, f"expected one stderr line, got: {proc.stderr[-1500:]}")
    if path:
        test.assertIn(os.path.basename(str(path).rstrip("/")), lines[0])
    return lines[0]


def skip_if_not_available(test, proc):
    if proc.returncode == 3 and NOT_AVAILABLE in proc.stderr:
        test.skipTest("command " + NOT_AVAILABLE)


# ------------------------------------------------------------------ meshes
def box_mesh(lo, hi):
    (x0, y0, z0), (x1, y1, z1) = lo, hi
    v = [(x, y, z) for x in (x0, x1) for y in (y0, y1) for z in (z0, z1)]
    quads = [(0, 1, 3, 2), (4, 6, 7, 5), (0, 4, 5, 1), (2, 3, 7, 6), (0, 2, 6, 4), (1, 5, 7, 3)]
    f = []
    for a, b, c, d in quads:
        f += [(a, b, c), (a, c, d)]
    return v, f


def tube_mesh(start, end, radius, sides=24, rings=2):
    """A closed-side cylinder from start to end (open ends)."""
    s, e = [float(x) for x in start], [float(x) for x in end]
    axis = [e[i] - s[i] for i in range(3)]
    n = math.sqrt(sum(a * a for a in axis))
    axis = [a / n for a in axis]
    helper = (1.0, 0.0, 0.0) if abs(axis[0]) < 0.9 else (0.0, 1.0, 0.0)
    u = [axis[1] * helper[2] - axis[2] * helper[1], axis[2] * helper[0] - axis[0] * helper[2],
         axis[0] * helper[1] - axis[1] * helper[0]]
    un = math.sqrt(sum(a * a for a in u))
    u = [a / un for a in u]
    w = [axis[1] * u[2] - axis[2] * u[1], axis[2] * u[0] - axis[0] * u[2], axis[0] * u[1] - axis[1] * u[0]]
    v, f = [], []
    for r in range(rings + 1):
        t = r / rings
        c = [s[i] + (e[i] - s[i]) * t for i in range(3)]
        for k in range(sides):
            a = 2 * math.pi * k / sides
            v.append(tuple(c[i] + radius * (math.cos(a) * u[i] + math.sin(a) * w[i]) for i in range(3)))
    for r in range(rings):
        for k in range(sides):
            a, b = r * sides + k, r * sides + (k + 1) % sides
            c, d = a + sides, b + sides
            f += [(a, b, d), (a, d, c)]
    return v, f


def write_obj(path, elements):
    """elements: list of (name, vertices, triangles); one `o NAME` per element."""
    lines, base = [], 1
    for name, verts, tris in elements:
        lines.append(f"o {name}")
        lines += [f"v {x:.6f} {y:.6f} {z:.6f}" for x, y, z in verts]
        lines += [f"f {a + base} {b + base} {c + base}" for a, b, c in tris]
        base += len(verts)
    with open(path, "w") as fh:
        fh.write("\n".join(lines) + "\n")


def small_scene_elements():
    """A bracket plate, a straight cable lying 20 mm above it and a pipe beside it (mm)."""
    return [("bracket_1", *box_mesh((-80, -40, -5), (80, 40, 0))),
            ("cable_A", *tube_mesh((-70, 0, 20), (70, 0, 20), 5.0, sides=24, rings=8)),
            ("pipe_1", *tube_mesh((-60, 30, 15), (60, 30, 15), 8.0, sides=24, rings=4))]


def plan_doc(**cable_overrides):
    cable = {"name": "cable_A", "kind": "cable", "diameter_mm": 10.0, "min_bend_radius_mm": 60.0,
             "clearance_mm": 5.0}
    cable.update(cable_overrides)
    return {"units": "mm", "sensor": {"width_px": 160, "height_px": 128, "hfov_deg": 58.0, "standoff_mm": 400.0},
            "elements": [cable, {"name": "bracket_1", "kind": "rigid"}, {"name": "pipe_1", "kind": "rigid"}]}


def write_json(path, doc):
    with open(path, "w") as fh:
        json.dump(doc, fh, indent=1)
    return path


def write_text(path, text, mode="w"):
    with open(path, mode) as fh:
        fh.write(text)
    return path


IDENTITY = "1 0 0 0\n0 1 0 0\n0 0 1 0\n0 0 0 1\n"
# The small scene's sensor: 400 mm above the plate looking down (camera z forward = CAD -z, x = CAD x, y = CAD -y).
CAMERA_TO_CAD = "1 0 0 0\n0 -1 0 0\n0 0 -1 400\n0 0 0 1\n"
SEED_ON_CABLE = "0,0,375"  # the top of cable_A (CAD 0,0,25) in the camera frame


def to_camera(points):
    """CAD coordinates -> the small scene's camera frame (the inverse of CAMERA_TO_CAD)."""
    return [(x, -y, 400.0 - z) for x, y, z in points]


def cable_scan_points(spacing=1.0):
    """Points on the visible (upper) half of cable_A and on the bracket top, in CAD coordinates (to_camera gives
    the scan)."""
    pts = []
    n_len = int(140 / spacing)
    for i in range(n_len + 1):
        x = -70 + i * spacing
        for k in range(16):
            a = math.pi * k / 15  # upper half
            pts.append((x, 5.0 * math.cos(a), 20 + 5.0 * math.sin(a)))
    for i in range(int(160 / (2 * spacing)) + 1):
        for j in range(int(80 / (2 * spacing)) + 1):
            pts.append((-80 + 2 * spacing * i, -40 + 2 * spacing * j, 0.0))
    return pts


class SmallScene:
    """scene.obj + plan.json + scan.ply (camera frame, sensor 400 mm above the plate) + pose.txt (its exact
    camera_to_cad) in a folder."""

    def __init__(self, folder):
        os.makedirs(folder, exist_ok=True)
        self.dir = folder
        self.cad = os.path.join(folder, "scene.obj")
        self.plan = os.path.join(folder, "plan.json")
        self.scan = os.path.join(folder, "scan.ply")
        self.pose = os.path.join(folder, "pose.txt")
        write_obj(self.cad, small_scene_elements())
        write_json(self.plan, plan_doc())
        write_ply_binary(self.scan, to_camera(cable_scan_points()))
        write_text(self.pose, CAMERA_TO_CAD)


def ply_ascii(points, extra_header=""):
    head = f"ply\nformat ascii 1.0\nelement vertex {len(points)}\nproperty float x\nproperty float y\n" \
           f"property float z\n{extra_header}end_header\n"
    return head + "".join(f"{x} {y} {z}\n" for x, y, z in points)


def pcd(points, data="binary", count=None):
    n = len(points) if count is None else count
    head = ("# .PCD v0.7\nVERSION 0.7\nFIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nCOUNT 1 1 1\n"
            f"WIDTH {n}\nHEIGHT 1\nVIEWPOINT 0 0 0 1 0 0 0\nPOINTS {n}\nDATA {data}\n").encode()
    if data == "ascii":
        return head + "".join(f"{x} {y} {z}\n" for x, y, z in points).encode()
    if data == "binary":
        return head + b"".join(struct.pack("<3f", *p) for p in points)
    # binary_compressed with literal-only LZF runs (valid LZF; enough for header/size tests)
    raw = b"".join(struct.pack("<f", p[k]) for k in range(3) for p in points)
    comp = b"".join(bytes([len(raw[i:i + 32]) - 1]) + raw[i:i + 32] for i in range(0, len(raw), 32))
    return head + struct.pack("<II", len(comp), len(raw)) + comp


# ------------------------------------------------------------------ the demo scene, simulated
class SimulatedDemo:
    """Test-class mixin: the README's demo scene (`ewis simulate --seed 7 --defect clearance`) simulated once per class
    into a scratch folder (`scene`, with its `truth`), and `inspect` of it with any CAD, scan or pose."""
    scratch = "demo"

    @classmethod
    def setUpClass(cls):
        cls.dir = tmpdir(cls.scratch)
        cls.scene = os.path.join(cls.dir, "scene")
        run("simulate", "--out", cls.scene, "--seed", "7", "--defect", "clearance", "--quiet", check=0)
        with open(os.path.join(cls.scene, "truth.json")) as f:
            cls.truth = json.load(f)

    @classmethod
    def tearDownClass(cls):
        shutil.rmtree(cls.dir, ignore_errors=True)

    def inspect_demo(self, name, cad=None, scan=None, pose=None):
        """Inspects the scene (its own files where not given) into <scratch>/name: the schema-checked report.json
        and the stderr."""
        s, out = self.scene, os.path.join(self.dir, name)
        proc = run("inspect", "--cad", cad or os.path.join(s, "scene.obj"), "--plan", os.path.join(s, "plan.json"),
                   "--scan", scan or os.path.join(s, "scan.ply"), "--pose", pose or os.path.join(s, "pose.txt"),
                   "--out", out, "--quiet", check=0)
        with open(os.path.join(out, "report.json")) as f:
            report = json.load(f)
        validate(report, "report.schema.json")
        return report, proc.stderr


def pose_error(report, truth):
    """Rotation (deg) and translation (mm) between the report's scan-to-CAD transform and the truth's."""
    a = report["registration"]["transform"]
    t = truth["camera_to_cad"]
    t = [t[4 * i:4 * i + 4] for i in range(4)] if len(t) == 16 else t
    # R_t^T R_a
    trace = sum(t[k][i] * a[k][i] for i in range(3) for k in range(3))
    angle = math.degrees(math.acos(max(-1.0, min(1.0, (trace - 1.0) / 2.0))))
    offset = math.sqrt(sum((a[i][3] - t[i][3]) ** 2 for i in range(3)))
    return angle, offset
