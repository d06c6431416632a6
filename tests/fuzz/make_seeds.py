#!/usr/bin/python3
"""Seed corpora for the fuzzers, made at run time (nothing binary is committed): small synthetic files of every
variant each parser knows and cut-down copies of the real files in ../shared/realdata. (run.sh adds the
regression inputs as a further corpus once they run clean.)

usage: make_seeds.py OUTDIR [REALDATA]   ->  OUTDIR/<target>/<seed files>
"""
import json
import math
import os
import struct
import sys

HERE = os.path.dirname(os.path.abspath(__file__))


def lzf_compress(data: bytes) -> bytes:
    """A plain LZF encoder (liblzf's format): literal runs (ctrl < 32) and back-references (len, 13-bit offset),
    greedy with a 3-byte hash table, so seeds exercise both kinds of LZF token."""
    out = bytearray()
    lit = bytearray()
    table = {}
    i, n = 0, len(data)

    def flush():
        for k in range(0, len(lit), 32):
            chunk = lit[k:k + 32]
            out.append(len(chunk) - 1)
            out.extend(chunk)
        lit.clear()

    while i < n:
        ref = None
        if i + 2 < n:
            key = data[i:i + 3]
            cand = table.get(key)
            table[key] = i
            if cand is not None and 0 < i - cand <= 8192:
                ref = cand
        if ref is None:
            lit.append(data[i])
            i += 1
            continue
        length = 3
        while i + length < n and length < 264 and data[ref + length] == data[i + length]:
            length += 1
        flush()
        off = i - ref - 1
        l2 = length - 2
        if l2 < 7:
            out.append((l2 << 5) | (off >> 8))
        else:
            out.append((7 << 5) | (off >> 8))
            out.append(l2 - 7)
        out.append(off & 0xFF)
        i += length
    flush()
    return bytes(out)


def pts(n=12):
    return [(math.cos(i * 0.5) * 10, math.sin(i * 0.5) * 10, i * 0.25) for i in range(n)]


# ---------------------------------------------------------------- PLY
def ply_header(fmt, n, props, extra=""):
    h = f"ply\nformat {fmt} 1.0\ncomment seed\nelement vertex {n}\n"
    h += "".join(f"property {t} {name}\n" for t, name in props)
    return (h + extra + "end_header\n").encode()


PLY_PACK = {"float": "f", "double": "d", "uchar": "B", "char": "b", "ushort": "H", "short": "h", "uint": "I",
            "int": "i", "float32": "f", "float64": "d", "uint8": "B", "int32": "i"}


def ply_cloud(fmt, props, points, faces=None):
    extra = ""
    if faces is not None:
        extra = f"element face {len(faces)}\nproperty list uchar int vertex_indices\n"
    body = bytearray()
    end = "<" if fmt == "binary_little_endian" else ">"
    for k, p in enumerate(points):
        vals = []
        for t, name in props:
            if name in "xyz":
                v = p["xyz".index(name)]
            elif name in ("red", "green", "blue"):
                v = (k * 37) % 256
            else:
                v = k * 0.5
            vals.append(v)
        if fmt == "ascii":
            body += (" ".join(str(int(v)) if PLY_PACK[t] not in "fd" else repr(float(v)) for (t, _), v in
                              zip(props, vals)) + "\n").encode()
        else:
            for (t, _), v in zip(props, vals):
                c = PLY_PACK[t]
                body += struct.pack(end + c, v if c in "fd" else int(v))
    for f in faces or []:
        if fmt == "ascii":
            body += (f"{len(f)} " + " ".join(map(str, f)) + "\n").encode()
        else:
            body += struct.pack(end + "B", len(f)) + struct.pack(end + f"{len(f)}i", *f)
    return ply_header(fmt, len(points), props, extra) + bytes(body)


def ply_seeds():
    p = pts()
    xyz = [("float", "x"), ("float", "y"), ("float", "z")]
    rich = xyz + [("float", "nx"), ("float", "ny"), ("float", "nz"), ("uchar", "red"), ("uchar", "green"),
                  ("uchar", "blue"), ("float", "intensity"), ("float", "curvature")]
    s = {}
    for fmt in ("ascii", "binary_little_endian", "binary_big_endian"):
        short = fmt.split("_")[-1] if fmt != "ascii" else "ascii"
        s[f"xyz_{fmt}.ply"] = ply_cloud(fmt, xyz, p)
        s[f"rich_{fmt}.ply"] = ply_cloud(fmt, rich, p)
        s[f"double_{short}.ply"] = ply_cloud(fmt, [("double", "x"), ("double", "y"), ("double", "z")], p)
        s[f"types_{short}.ply"] = ply_cloud(fmt, [("float32", "x"), ("float64", "y"), ("float", "z"),
                                                  ("short", "s"), ("ushort", "us"), ("int32", "i"), ("char", "c")], p)
        s[f"faces_{short}.ply"] = ply_cloud(fmt, xyz, p[:4], faces=[[0, 1, 2], [0, 2, 3]])
    s["nan.ply"] = ply_cloud("ascii", xyz, [(float("nan"), 0, 0), (1, float("inf"), 2), (1, 2, 3)]).replace(
        b"nan", b"nan").replace(b"inf", b"inf")
    s["empty_vertex.ply"] = ply_header("binary_little_endian", 0, xyz)
    return s


# ---------------------------------------------------------------- PCD
def pcd_cloud(data, fields, sizes, types, counts, points, width=None, height=1, version="0.7"):
    n = len(points)
    width = n if width is None else width
    h = f"# .PCD v{version} - seed\nVERSION {version}\nFIELDS {' '.join(fields)}\nSIZE {' '.join(map(str, sizes))}\n"
    h += f"TYPE {' '.join(types)}\nCOUNT {' '.join(map(str, counts))}\nWIDTH {width}\nHEIGHT {height}\n"
    if version == "0.7":
        h += "VIEWPOINT 0 0 0 1 0 0 0\n"
    h += f"POINTS {n}\nDATA {data}\n"
    codes = {("F", 4): "f", ("F", 8): "d", ("U", 1): "B", ("U", 2): "H", ("U", 4): "I", ("I", 1): "b",
             ("I", 2): "h", ("I", 4): "i"}

    def value(k, f, c):
        if f in "xyz":
            return points[k]["xyz".index(f)]
        return (k * 7 + c) % 100

    if data == "ascii":
        lines = []
        for k in range(n):
            vals = []
            for f, sz, t, cnt in zip(fields, sizes, types, counts):
                for c in range(cnt):
                    v = value(k, f, c)
                    vals.append(repr(float(v)) if t == "F" else str(int(v)))
            lines.append(" ".join(vals))
        return h.encode() + ("\n".join(lines) + "\n").encode()
    if data == "binary":
        body = bytearray()
        for k in range(n):
            for f, sz, t, cnt in zip(fields, sizes, types, counts):
                for c in range(cnt):
                    v = value(k, f, c)
                    body += struct.pack("<" + codes[(t, sz)], v if t == "F" else int(v))
        return h.encode() + bytes(body)
    # binary_compressed: field-major arrays, LZF, preceded by compressed and raw sizes
    raw = bytearray()
    for f, sz, t, cnt in zip(fields, sizes, types, counts):
        for k in range(n):
            for c in range(cnt):
                v = value(k, f, c)
                raw += struct.pack("<" + codes[(t, sz)], v if t == "F" else int(v))
    comp = lzf_compress(bytes(raw))
    return h.encode() + struct.pack("<II", len(comp), len(raw)) + comp


def pcd_seeds():
    p = pts()
    s = {}
    layouts = {
        "xyz": (["x", "y", "z"], [4, 4, 4], ["F", "F", "F"], [1, 1, 1]),
        "xyzrgb": (["x", "y", "z", "rgb"], [4, 4, 4, 4], ["F", "F", "F", "F"], [1, 1, 1, 1]),
        "xyzrgba": (["x", "y", "z", "rgba"], [4, 4, 4, 4], ["F", "F", "F", "U"], [1, 1, 1, 1]),
        "normals": (["x", "y", "z", "normal_x", "normal_y", "normal_z", "curvature"], [4] * 7, ["F"] * 7, [1] * 7),
        "mixed": (["x", "y", "z", "intensity", "ring", "_", "fpfh"], [8, 8, 8, 4, 2, 1, 4],
                  ["F", "F", "F", "F", "U", "I", "F"], [1, 1, 1, 1, 1, 3, 4]),
    }
    for data in ("ascii", "binary", "binary_compressed"):
        for name, (f, sz, t, c) in layouts.items():
            s[f"{name}_{data}.pcd"] = pcd_cloud(data, f, sz, t, c, p)
        organised = [(float("nan"),) * 3 if k % 3 == 0 else q for k, q in enumerate(p)]
        s[f"organised_{data}.pcd"] = pcd_cloud(data, *layouts["xyz"], organised, width=4, height=3)
    s["v05_ascii.pcd"] = pcd_cloud("ascii", *layouts["xyz"], p, version=".5")
    s["zero_binary_compressed.pcd"] = pcd_cloud("binary_compressed", *layouts["xyz"], [])
    return s


# ---------------------------------------------------------------- XYZ
def xyz_seeds():
    return {
        "plain.xyz": "".join(f"{x} {y} {z}\n" for x, y, z in pts()).encode(),
        "columns.txt": "".join(f"{x:.6e}\t{y:.3f}\t{z}\t255 0 12\n" for x, y, z in pts()).encode(),
        "csv.csv": ("x,y,z,i\n" + "".join(f"{x},{y},{z},{i}\n" for i, (x, y, z) in enumerate(pts()))).encode(),
        "comments.xyz": b"# comment\n// other\n1 2 3\n\n  4 5 6  \r\n7e2 -8.5E-1 +9\nnan 1 2\n1 inf 2\n-inf 0 0\n",
        "no_newline.xyz": b"1 2 3\n4 5 6",
    }


# ---------------------------------------------------------------- plan and pose
def plan_seeds():
    full = {"units": "mm", "sensor": {"width_px": 1280, "height_px": 1024, "hfov_deg": 58.0, "standoff_mm": 600.0},
            "elements": [
                {"name": "cable_A", "kind": "cable", "diameter_mm": 10.0, "min_bend_radius_mm": 60.0,
                 "clearance_mm": 5.0, "attached": ["clamp_1", "connector_J2"]},
                {"name": "cable_B", "kind": "cable", "diameter_mm": 6.5, "min_bend_ratio": 8,
                 "clearance_mm": 0, "bend_radius_reference": "inner"},
                {"name": "bracket_1", "kind": "rigid"}, {"name": "clamp_1", "kind": "rigid"}]}
    minimal = {"elements": [{"name": "c", "kind": "cable", "diameter_mm": 1, "min_bend_ratio": 1}]}
    return {
        "full.json": json.dumps(full, indent=2).encode(),
        "minimal.json": json.dumps(minimal).encode(),
        "rigid_only.json": b'{"units":"mm","elements":[{"name":"\\u00e9l\\u00e9ment","kind":"rigid"}]}',
        "centreline.json": json.dumps({"units": "mm", "elements": [
            {"name": "h", "kind": "cable", "diameter_mm": 2e1, "min_bend_radius_mm": 1.5e2, "clearance_mm": 3,
             "bend_radius_reference": "centreline", "attached": []}]}).encode(),
    }


def pose_seeds():
    return {
        "identity.txt": b"1 0 0 0\n0 1 0 0\n0 0 1 0\n0 0 0 1\n",
        "rotated.txt": (b"0.8660254037844387 -0.5 0 12.5\n0.5 0.8660254037844387 0 -3e1\n"
                        b"0 0 1 600\n0 0 0 1\n"),
        "json.txt": b"[[1,0,0,0],[0,1,0,0],[0,0,1,0],[0,0,0,1]]",
        "comment.txt": b"# camera_to_cad\n1,0,0,0; 0,-1,0,0; 0,0,-1,0; 0,0,0,1 # flip\n",
    }


# ---------------------------------------------------------------- meshes
def box(cx, cy, cz, s):
    v = [(cx + dx * s, cy + dy * s, cz + dz * s) for dx in (0, 1) for dy in (0, 1) for dz in (0, 1)]
    f = [(0, 1, 3, 2), (4, 6, 7, 5), (0, 4, 5, 1), (2, 3, 7, 6), (0, 2, 6, 4), (1, 5, 7, 3)]
    return v, f


def obj_seeds():
    v1, f1 = box(0, 0, 0, 10)
    v2, f2 = box(20, 0, 0, 5)
    text = "# seed\nmtllib none.mtl\no bracket_1\n" + "".join(f"v {x} {y} {z}\n" for x, y, z in v1)
    text += "".join("f " + " ".join(str(i + 1) for i in q) + "\n" for q in f1)
    text += "g cable_A\nusemtl red\n" + "".join(f"v {x} {y} {z}\n" for x, y, z in v2)
    text += "vn 0 0 1\nvt 0.5 0.5\n"
    text += "".join("f " + " ".join(f"{i - 8}/1/1" for i in q) + "\n" for q in f2)
    tri = "o t\nv 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\nf 1 2 3\nf 1 1 2\nf 2//1 4//1 3//1\nl 1 2\np 3\n"
    return {"scene.obj": text.encode(), "degenerate.obj": tri.encode(),
            "noname.obj": b"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n"}


def stl_seeds():
    def facet(a, b, c):
        return (f"facet normal 0 0 1\n outer loop\n  vertex {a[0]} {a[1]} {a[2]}\n  vertex {b[0]} {b[1]} {b[2]}\n"
                f"  vertex {c[0]} {c[1]} {c[2]}\n endloop\nendfacet\n")
    ascii_ = ("solid pipe_1\n" + facet((0, 0, 0), (1, 0, 0), (0, 1, 0)) + facet((1, 0, 0), (1, 1, 0), (0, 1, 0)) +
              "endsolid pipe_1\nsolid clamp_1\n" + facet((0, 0, 1), (1, 0, 1), (0, 1, 1)) + "endsolid clamp_1\n")
    tris = [((0, 0, 0), (1, 0, 0), (0, 1, 0)), ((1, 0, 0), (1, 1, 0), (0, 1, 0)), ((0, 0, 0), (0, 0, 0), (1, 1, 1))]
    binary = b"binary seed".ljust(80, b" ") + struct.pack("<I", len(tris))
    for t in tris:
        binary += struct.pack("<3f", 0, 0, 1) + b"".join(struct.pack("<3f", *p) for p in t) + b"\0\0"
    return {"two_solids.stl": ascii_.encode(), "binary.stl": binary}


def mesh_ply_seeds():
    v, quads = box(0, 0, 0, 10)
    xyz = [("float", "x"), ("float", "y"), ("float", "z")]
    s = {}
    for fmt in ("ascii", "binary_little_endian", "binary_big_endian"):
        s[f"box_{fmt}.ply"] = ply_cloud(fmt, xyz, v, faces=[list(q) for q in quads])
    s["tri_strip.ply"] = (b"ply\nformat ascii 1.0\nelement vertex 3\nproperty double x\nproperty double y\n"
                          b"property double z\nproperty uchar red\nelement face 1\n"
                          b"property list uint8 uint32 vertex_index\nend_header\n0 0 0 1\n1 0 0 2\n0 1 0 3\n3 0 1 2\n")
    return s


# ---------------------------------------------------------------- real data, cut down
def ascii_ply_head(path, keep):
    """The header and first `keep` vertices of an ASCII PLY, counts rewritten (other elements dropped)."""
    with open(path, "rb") as f:
        data = f.read()
    nl = b"\r\n" if b"ply\r\n" in data[:8] else b"\n"  # the Stanford scans have CRLF lines: keep them
    end = data.index(b"end_header" + nl) + len(b"end_header" + nl)
    head = data[:end].decode("latin-1").split(nl.decode())[:-1]
    out, in_vertex = [], False
    for line in head:
        w = line.split()
        if w[:1] == ["element"]:
            in_vertex = w[1] == "vertex"
            if not in_vertex:
                continue
            line = f"element vertex {keep}"
        elif w[:1] == ["property"] and not in_vertex:
            continue
        out.append(line)
    body = data[end:].split(nl)[:keep]
    return nl.join(x.encode("latin-1") for x in out) + nl + nl.join(body) + nl


def realdata_seeds(root):
    cloud = {"ply": {}, "pcd": {}, "xyz": {}}
    if not root or not os.path.isdir(root):
        return cloud
    small_pcd = ["pcl/bun4.pcd", "pcl/bun0.pcd", "pcl/milk.pcd"]
    for rel in small_pcd:
        p = os.path.join(root, rel)
        if os.path.exists(p) and os.path.getsize(p) < 128 * 1024:
            with open(p, "rb") as f:
                cloud["pcd"]["real_" + os.path.basename(p)] = f.read()
    p = os.path.join(root, "stanford_bunny/bun000.ply")
    if os.path.exists(p):
        cloud["ply"]["real_bun000_head.ply"] = ascii_ply_head(p, 300)
    for rel in ["adtree_trees/tree13.xyz", "cylsegment_tree/maple_tree_demo.txt"]:
        p = os.path.join(root, rel)
        if os.path.exists(p):
            with open(p, "rb") as f:
                lines = f.read().split(b"\n")[:300]
            cloud["xyz"]["real_" + os.path.basename(p)] = b"\n".join(lines) + b"\n"
    return cloud


def main():
    out = sys.argv[1]
    real = realdata_seeds(sys.argv[2] if len(sys.argv) > 2 else None)
    sets = {"ply": {**ply_seeds(), **real["ply"]}, "pcd": {**pcd_seeds(), **real["pcd"]},
            "xyz": {**xyz_seeds(), **real["xyz"]}, "plan": plan_seeds(), "pose": pose_seeds(),
            "mesh_obj": obj_seeds(), "mesh_stl": stl_seeds(), "mesh_ply": mesh_ply_seeds()}
    for target, files in sets.items():
        d = os.path.join(out, target)
        os.makedirs(d, exist_ok=True)
        for name, data in files.items():
            with open(os.path.join(d, name), "wb") as f:
                f.write(data)
        print(f"{target}: {len(os.listdir(d))} seeds")


if __name__ == "__main__":
    main()
