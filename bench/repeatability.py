#!/usr/bin/env python3
"""Repeatability of the bend-radius measure, as the paper did it (section 5: "evaluated by introducing Gaussian
noise on data"): one simulated scene is scanned N times with fresh sensor noise and outliers (the scene, the
cable routes and the sensor pose stay the same) and inspected each time; the spread (standard deviation) of each
cable's min_bend_radius_mm is reported against its mean and the truth. Issue 6's goal: spread under 2%.

Usage: bench/repeatability.py [--ewis build/bin/ewis] [--seed 7] [--defect bend] [--repeats 20] [--work DIR]
Prints a Markdown table; only Python's standard library is used.
"""
import argparse
import json
import math
import os
import subprocess
import sys


def run(cmd):
    subprocess.run(cmd, check=True, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--ewis", default="build/bin/ewis")
    ap.add_argument("--seed", type=int, default=7)
    ap.add_argument("--defect", default="bend")
    ap.add_argument("--repeats", type=int, default=20)
    ap.add_argument("--work", default="build/repeatability")
    a = ap.parse_args()
    scene = os.path.join(a.work, "scene")
    run([a.ewis, "simulate", "--out", scene, "--seed", str(a.seed), "--defect", a.defect, "--scene-only", "--quiet"])
    truth = json.load(open(os.path.join(scene, "scene_truth.json")))
    truth_radius = {c["name"]: c.get("min_bend_radius_mm") for c in truth.get("cables", [])}
    radii = {}
    for k in range(a.repeats):
        scan_dir = os.path.join(a.work, "scan_%02d" % k)
        out_dir = os.path.join(a.work, "inspect_%02d" % k)
        # the same scene, a fresh sensor seed: new noise and outliers
        run([a.ewis, "simulate", "--out", scan_dir, "--cad", os.path.join(scene, "scene.obj"), "--plan",
             os.path.join(scene, "plan.json"), "--seed", str(1000 + k), "--quiet"])
        run([a.ewis, "inspect", "--cad", os.path.join(scene, "scene.obj"), "--plan", os.path.join(scene, "plan.json"),
             "--scan", os.path.join(scan_dir, "scan.ply"), "--pose", os.path.join(scan_dir, "pose.txt"), "--out",
             out_dir, "--quiet"])
        report = json.load(open(os.path.join(out_dir, "report.json")))
        for e in report["elements"]:
            if e.get("kind") == "cable" and e.get("min_bend_radius_mm") is not None:
                radii.setdefault(e["name"], []).append(e["min_bend_radius_mm"])
        print("repeat %d/%d done" % (k + 1, a.repeats), file=sys.stderr)
    print("| cable | truth (mm) | runs | mean (mm) | spread (sd, mm) | spread (% of mean) | mean error (%) |")
    print("|---|---:|---:|---:|---:|---:|---:|")
    for name in sorted(radii):
        v = radii[name]
        mean = sum(v) / len(v)
        sd = math.sqrt(sum((x - mean) ** 2 for x in v) / (len(v) - 1)) if len(v) > 1 else 0.0
        t = truth_radius.get(name)
        err = "%.2f" % ((mean - t) / t * 100) if t else "n/a"
        print("| %s | %s | %d | %.2f | %.3f | %.2f | %s |" % (name, "%.2f" % t if t else "straight", len(v), mean, sd,
                                                             100 * sd / mean, err))


if __name__ == "__main__":
    main()
