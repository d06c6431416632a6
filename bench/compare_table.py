"""Runs each step through ewis_steps, pcl_steps and open3d_steps in turn, REPEAT times, and writes the medians, the
ratio to the faster peer and the agreement of the results as a Markdown table into RESULTS.md."""
import argparse
import datetime
import json
import os
import platform
import statistics
import subprocess

p = argparse.ArgumentParser()
p.add_argument("--bin", required=True)
p.add_argument("--data", required=True)
p.add_argument("--repeat", type=int, default=5)
p.add_argument("--results", required=True)
a = p.parse_args()
scan = os.path.join(a.data, "scene", "scan.ply")
pcd = os.path.join(a.data, "scan_compressed.pcd")
filtered = os.path.join(a.data, "filtered.ply")
mesh = os.path.join(a.data, "scene", "scene.obj")

# (label, args, which peers have it)
steps = [
    ("read binary PLY", ["read", scan], ["pcl", "open3d"]),
    ("read PCD binary_compressed", ["read", pcd], ["pcl", "open3d"]),
    ("k-d tree + mean NN distance", ["resolution", scan], ["pcl", "open3d"]),
    ("radius outlier removal r=2 k=4", ["ror", scan, "2.0", "4"], ["pcl", "open3d"]),
    ("voxel down-sampling 2 mm", ["voxel", scan, "2.0"], ["pcl", "open3d"]),
    ("Euclidean clustering 1.5 mm", ["cluster", filtered, "1.5"], ["pcl", "open3d"]),
    ("area-weighted mesh sampling 1 M", ["sample", mesh, "1000000"], ["open3d"]),
]


def run(prog, args):
    out = subprocess.run([os.path.join(a.bin, prog), *args], capture_output=True, text=True, timeout=900)
    if out.returncode != 0:
        return None
    return json.loads(out.stdout.strip().splitlines()[-1])


rows = []
for label, args, peers in steps:
    sides = ["ewis"] + peers
    times = {s: [] for s in sides}
    results = {}
    for _ in range(a.repeat):
        for s in sides:
            r = run(f"{s}_steps", args)
            if r is None:
                continue
            times[s].append(r["ms"])
            results[s] = (r["result"], r.get("detail", ""))
    med = {s: statistics.median(t) if t else None for s, t in times.items()}
    peer_meds = [med[s] for s in peers if med[s] is not None]
    ratio = (min(peer_meds) / med["ewis"]) if peer_meds and med["ewis"] else None
    agree = "; ".join(f"{s}: {results[s][0]:g}{(' ' + results[s][1]) if results[s][1] else ''}" for s in results)
    rows.append((label, med, ratio, agree))
    print(label, med, ratio, agree, flush=True)

fmt = lambda v: "n/a" if v is None else f"{v:.1f}"
lines = ["<!-- compare:begin -->",
         f"Run {datetime.date.today().isoformat()} on {platform.node()} ({os.cpu_count()} cores, "
         f"{platform.processor() or platform.machine()}), `bench/compare.sh {a.repeat}`: medians of {a.repeat} runs "
         "each, milliseconds; speed-up = faster peer / ewis.",
         "",
         "| step | ewis ms | PCL 1.13 ms | Open3D 0.16 ms | speed-up | results (ewis; peers) |",
         "|---|---|---|---|---|---|"]
for label, med, ratio, agree in rows:
    lines.append(f"| {label} | {fmt(med.get('ewis'))} | {fmt(med.get('pcl'))} | {fmt(med.get('open3d'))} | "
                 f"{'n/a' if ratio is None else f'{ratio:.1f}x'} | {agree} |")
lines.append("<!-- compare:end -->")
block = "\n".join(lines)
text = open(a.results).read() if os.path.exists(a.results) else "# Benchmark results\n"
if "<!-- compare:begin -->" in text:
    head, rest = text.split("<!-- compare:begin -->", 1)
    tail = rest.split("<!-- compare:end -->", 1)[1]
    text = head + block + tail
else:
    text += "\n## Side by side with PCL and Open3D\n\n" + block + "\n"
open(a.results, "w").write(text)
print(block)
