"""Helpers for the CLI tests: run build/bin/ewis, validate JSON against ../shared/schemas, make test files."""
import json
import os
import struct
import subprocess
import tempfile
import unittest

EWIS = os.environ.get("EWIS_BIN", os.path.join(os.path.dirname(__file__), "../../build/bin/ewis"))
SCHEMAS = os.environ.get("EWIS_SCHEMAS", os.path.join(os.path.dirname(__file__), "../../../shared/schemas"))
REALDATA = os.environ.get("EWIS_REALDATA", os.path.join(os.path.dirname(__file__), "../../../shared/realdata"))
TMP_ROOT = os.environ.get("EWIS_TMP", tempfile.gettempdir())


def run(*args, timeout=600, check=None):
    """Runs ewis with args; returns CompletedProcess (text). check: expected exit code."""
    proc = subprocess.run([EWIS, *map(str, args)], capture_output=True, text=True, timeout=timeout)
    if check is not None and proc.returncode != check:
        raise AssertionError(f"ewis {' '.join(map(str, args))} exited {proc.returncode}, expected {check}\n"
                             f"stdout: {proc.stdout[-2000:]}\nstderr: {proc.stderr[-2000:]}")
    return proc


def validate(instance, schema_name):
    """Validates a JSON value against ../shared/schemas/<schema_name>; skips when the schemas are absent."""
    path = os.path.join(SCHEMAS, schema_name)
    if not os.path.exists(path):
        raise unittest.SkipTest(f"schema {path} absent")
    import jsonschema
    with open(path) as f:
        schema = json.load(f)
    jsonschema.validate(instance, schema)


def tmpdir(name):
    os.makedirs(TMP_ROOT, exist_ok=True)
    return tempfile.mkdtemp(prefix=name + "-", dir=TMP_ROOT)


def realdata(*parts):
    path = os.path.join(REALDATA, *parts)
    if not os.path.exists(path):
        raise unittest.SkipTest(f"real data {path} absent")
    return path


def write_ply_binary(path, points, extra=None):
    """Binary little-endian PLY with float x y z and optional extra float properties {name: [values]}."""
    extra = extra or {}
    names = list(extra)
    with open(path, "wb") as f:
        header = "ply\nformat binary_little_endian 1.0\n" + f"element vertex {len(points)}\n"
        header += "property float x\nproperty float y\nproperty float z\n"
        header += "".join(f"property float {n}\n" for n in names) + "end_header\n"
        f.write(header.encode())
        for i, p in enumerate(points):
            f.write(struct.pack("<3f", *p))
            for n in names:
                f.write(struct.pack("<f", extra[n][i]))


def write_xyz(path, points):
    with open(path, "w") as f:
        for p in points:
            f.write(f"{p[0]} {p[1]} {p[2]}\n")


def read_ply_header(path):
    with open(path, "rb") as f:
        data = f.read()
    end = data.index(b"end_header\n")
    return data[:end].decode().splitlines()


def grid(n, spacing, z=0.0):
    return [(i * spacing, j * spacing, z) for i in range(n) for j in range(n)]
