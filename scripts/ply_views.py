#!/usr/bin/env python3
"""Three orthographic views (front x-z, side y-z, top x-y) of a coloured point cloud PLY, side by side in one PNG,
for a person to look at (e.g. the tubes.ply of `ewis tubes`, or a traced tree). Grey points are drawn first and
small, coloured points last and larger, so a traced tube shows through the rest. Standard library only.

Usage: scripts/ply_views.py IN.ply OUT.png [--size 600] [--crop-colored MARGIN_MM]
"""
import argparse
import struct
import sys
import zlib

TYPES = {"char": "b", "int8": "b", "uchar": "B", "uint8": "B", "short": "h", "int16": "h", "ushort": "H",
         "uint16": "H", "int": "i", "int32": "i", "uint": "I", "uint32": "I", "float": "f", "float32": "f",
         "double": "d", "float64": "d"}


def read_ply(path):
    with open(path, "rb") as f:
        data = f.read()
    end = data.index(b"end_header")
    end = data.index(b"\n", end) + 1
    header = data[:end].decode("ascii", "replace").splitlines()
    fmt, count, props, in_vertex = None, 0, [], False
    for line in header:
        w = line.split()
        if not w:
            continue
        if w[0] == "format":
            fmt = w[1]
        elif w[0] == "element":
            in_vertex = w[1] == "vertex"
            if in_vertex:
                count = int(w[2])
        elif w[0] == "property" and in_vertex:
            if w[1] == "list":
                sys.exit(f"{path}: list properties in the vertex element are not supported")
            props.append((w[2], TYPES[w[1]]))
    names = [n for n, _ in props]
    if not all(k in names for k in ("x", "y", "z")):
        sys.exit(f"{path}: no x y z properties")
    rows = []
    if fmt == "ascii":
        lines = data[end:].decode("ascii", "replace").split("\n")
        for line in lines[:count]:
            v = line.split()
            if len(v) >= len(props):
                rows.append([float(t) for t in v[:len(props)]])
    else:
        order = "<" if fmt == "binary_little_endian" else ">"
        rec = struct.Struct(order + "".join(t for _, t in props))
        for i in range(count):
            rows.append(rec.unpack_from(data, end + i * rec.size))
    ix, iy, iz = names.index("x"), names.index("y"), names.index("z")
    ic = [names.index(c) if c in names else None for c in ("red", "green", "blue")]
    pts = []
    for r in rows:
        col = tuple(int(r[k]) for k in ic) if None not in ic else (128, 128, 128)
        pts.append((r[ix], r[iy], r[iz], col))
    return pts


def write_png(path, width, height, pixels):
    raw = b"".join(b"\x00" + bytes(pixels[y * width * 3:(y + 1) * width * 3]) for y in range(height))

    def chunk(tag, body):
        return struct.pack(">I", len(body)) + tag + body + struct.pack(">I", zlib.crc32(tag + body) & 0xFFFFFFFF)

    with open(path, "wb") as f:
        f.write(b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", width, height, 8, 2, 0, 0, 0)) +
                chunk(b"IDAT", zlib.compress(raw, 6)) + chunk(b"IEND", b""))


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("ply")
    ap.add_argument("png")
    ap.add_argument("--size", type=int, default=600, help="pixels per view")
    ap.add_argument("--crop-colored", type=float, default=None,
                    help="frame the views on the coloured (non-grey) points plus this margin (mm)")
    a = ap.parse_args()
    pts = read_ply(a.ply)
    if not pts:
        sys.exit(f"{a.ply}: no points")
    is_grey = lambda c: c[0] == c[1] == c[2]
    frame = [p for p in pts if not is_grey(p[3])] if a.crop_colored is not None else pts
    frame = frame or pts
    m = a.crop_colored or 0.0
    lo = [min(p[k] for p in frame) - m for k in range(3)]
    hi = [max(p[k] for p in frame) + m for k in range(3)]
    ext = max(hi[k] - lo[k] for k in range(3)) or 1.0
    s, gap = a.size, 8
    width, height = 3 * s + 2 * gap, s
    pix = bytearray([255] * (width * height * 3))
    views = [(0, 2), (1, 2), (0, 1)]  # front x-z, side y-z, top x-y (up is the second axis)

    def put(x, y, c, r):
        for dy in range(-r, r + 1):
            for dx in range(-r, r + 1):
                xx, yy = x + dx, y + dy
                if 0 <= xx < width and 0 <= yy < height:
                    o = (yy * width + xx) * 3
                    pix[o:o + 3] = bytes(c)

    for grey_pass in (True, False):
        for p in pts:
            if is_grey(p[3]) != grey_pass:
                continue
            for v, (u, w) in enumerate(views):
                fu = (p[u] - lo[u]) / ext
                fw = (p[w] - lo[w]) / ext
                if not (0 <= fu <= 1 and 0 <= fw <= 1):
                    continue
                x = v * (s + gap) + int(fu * (s - 1))
                y = (s - 1) - int(fw * (s - 1))
                put(x, y, (190, 190, 190) if grey_pass else p[3], 0 if grey_pass else 1)
    for v in range(1, 3):
        for y in range(height):
            for x in range(v * (s + gap) - gap, v * (s + gap)):
                o = (y * width + x) * 3
                pix[o:o + 3] = b"\x00\x00\x00"
    write_png(a.png, width, height, pix)
    print(f"{a.png}: {len(pts)} points, views x-z | y-z | x-y, {ext:.0f} mm across")


if __name__ == "__main__":
    main()
