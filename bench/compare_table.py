"""Runs each step through ewis_steps, pcl_steps and open3d_steps in turn, REPEAT times, and writes the medians, the
ratio to the faster peer and the agreement of the results as a Markdown table into RESULTS.md.
--only KEY,... runs only those rows (a key or a step name, e.g. `icp` or `read`); the table's other rows are kept
from the results file as they were."""
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
p.add_argument("--only", default="", help="comma-separated row keys or step names (default: every row)")
a = p.parse_args()
scene = os.path.join(a.data, "scene")
scan = os.path.join(scene, "scan.ply")
pcd = os.path.join(a.data, "scan_compressed.pcd")
filtered = os.path.join(a.data, "filtered.ply")
mesh = os.path.join(scene, "scene.obj")
data = lambda name: os.path.join(a.data, name)  # inputs written by `ewis_steps prepare`
first_cable = next(e for e in json.load(open(os.path.join(scene, "plan.json")))["elements"] if e["kind"] == "cable")

# (key, label, args, which peers have it)
steps = [
    ("read-ply", "read binary PLY", ["read", scan], ["pcl", "open3d"]),
    ("read-pcd", "read PCD binary_compressed", ["read", pcd], ["pcl", "open3d"]),
    ("resolution", "k-d tree + mean NN distance", ["resolution", scan], ["pcl", "open3d"]),
    ("ror", "radius outlier removal r=2 k=4", ["ror", scan, "2.0", "4"], ["pcl", "open3d"]),
    ("voxel", "voxel down-sampling 2 mm", ["voxel", scan, "2.0"], ["pcl", "open3d"]),
    ("cluster", "Euclidean clustering 1.5 mm", ["cluster", filtered, "1.5"], ["pcl", "open3d"]),
    ("sample", "area-weighted mesh sampling 1 M", ["sample", mesh, "1000000"], ["open3d"]),
    ("icp", "point-to-plane ICP, 48 k scan points onto CAD samples, 3 deg / 15 mm off",
     ["icp", data("icp_source.ply"), data("icp_target.ply"), data("icp_init.txt"), data("truth_pose.txt")],
     ["pcl", "open3d"]),
    ("cylinder", "cylinder fit, straight tube r 5 mm + 40% outliers",
     ["cylinder", data("tube.ply")], ["pcl"]),
    ("raycast", "ray casting 1280x1024 of the CAD (BVH build included)",
     ["raycast", mesh, data("truth_pose.txt")], ["open3d"]),
    ("chain", f"one cable ({first_cable['name']}) as a chain of cylinders from its CAD",
     ["chain", data("chain_scan.ply"), data(f"cad_{first_cable['name']}.ply"), str(first_cable["diameter_mm"] / 2),
      data("truth_pose.txt")], ["pcl"]),
    ("inspect", "whole inspection of the 1.27 M-point scan (PCL: approximation)", ["inspect", a.data], ["pcl"]),
]
only = {k for k in a.only.split(",") if k}
unknown = only - {s[0] for s in steps} - {s[2][0] for s in steps}
if unknown:
    p.error(f"--only: unknown rows {sorted(unknown)}")
selected = [s for s in steps if not only or s[0] in only or s[2][0] in only]


def run(prog, args):
    out = subprocess.run([os.path.join(a.bin, prog), *args], capture_output=True, text=True, timeout=900)
    if out.returncode != 0:
        print(f"{prog} {' '.join(args)}: exit {out.returncode}: {out.stderr.strip()[-300:]}", flush=True)
        return None
    return json.loads(out.stdout.strip().splitlines()[-1])


fmt = lambda v: "n/a" if v is None else f"{v:.1f}"
rows = {}
for key, label, args, peers in selected:
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
    # a peer whose result is marked invalid (e.g. Open3D's ray casting on Debian: no hit) has no speed-up
    valid = [s for s in peers if med[s] is not None and not results[s][1].startswith("invalid")]
    ratio = (min(med[s] for s in valid) / med["ewis"]) if valid and med["ewis"] else None
    agree = "; ".join(f"{s}: {results[s][0]:g}{(' ' + results[s][1]) if results[s][1] else ''}" for s in results)
    rows[label] = (f"| {label} | {fmt(med.get('ewis'))} | {fmt(med.get('pcl'))} | {fmt(med.get('open3d'))} | "
                   f"{'n/a' if ratio is None else f'{ratio:.1f}x'} | {agree} |")
    print(label, med, ratio, agree, flush=True)

text = open(a.results).read() if os.path.exists(a.results) else "# Benchmark results\n"
if only and "<!-- compare:begin -->" in text:  # keep the rows not re-run
    old = text.split("<!-- compare:begin -->", 1)[1].split("<!-- compare:end -->", 1)[0]
    for line in old.splitlines():
        cells = line.split(" | ")
        if line.startswith("| ") and not line.startswith("| step |") and cells[0][2:] not in rows:
            rows[cells[0][2:]] = line
run_line = (f"Run {datetime.date.today().isoformat()} on {platform.node()} ({os.cpu_count()} cores, "
            f"{platform.processor() or platform.machine()}), `bench/compare.sh {a.repeat}`: medians of {a.repeat} runs "
            "each, milliseconds; speed-up = faster peer / ewis.")
if only:
    run_line += f" Rows re-run with `--only {a.only}`; the others are from the previous run."
lines = ["<!-- compare:begin -->", run_line, "",
         "| step | ewis ms | PCL 1.13 ms | Open3D 0.16 ms | speed-up | results (ewis; peers) |",
         "|---|---|---|---|---|---|"]
lines += [rows[label] for _, label, _, _ in steps if label in rows]
lines += [row for label, row in rows.items() if label not in {s[1] for s in steps}]  # rows of older versions
lines.append("<!-- compare:end -->")
block = "\n".join(lines)
if "<!-- compare:begin -->" in text:
    head, rest = text.split("<!-- compare:begin -->", 1)
    tail = rest.split("<!-- compare:end -->", 1)[1]
    text = head + block + tail
else:
    text += "\n## Side by side with PCL and Open3D\n\n" + block + "\n"
open(a.results, "w").write(text)
print(block)
