#!/usr/bin/env bash
# The demo: installs dependencies, builds ewis, simulates a scene with defects, inspects it, prints the report path.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup.sh
bash scripts/build.sh ewis
out=${DEMO_DIR:-out/demo}
rm -rf "$out"
mkdir -p "$out"
ewis=build/bin/ewis
echo "demo: simulating a scene with defects into $out/scene"
$ewis simulate --out "$out/scene" --seed 7 --defect clearance
echo "demo: scan statistics"
$ewis info --scan "$out/scene/scan.ply"
echo "demo: inspecting"
$ewis inspect --cad "$out/scene/scene.obj" --plan "$out/scene/plan.json" --scan "$out/scene/scan.ply" \
  --pose "$out/scene/pose.txt" --out "$out/inspection"
python3 - "$out/inspection/report.json" "$out/scene/truth.json" <<'PY'
import json, sys
r = json.load(open(sys.argv[1]))
truth = json.load(open(sys.argv[2]))
for d in truth["defects"]:
    print(f"demo: defect put into the scene: {d['kind']} on {d['element']}" + (f" with {d.get('with')}" if d['kind'] != 'bend' else "")
          + (f", gap {d['gap_mm']:.2f} mm" if 'gap_mm' in d else f", radius {d.get('radius_mm', 0):.1f} mm"))
print(f"demo: verdict {r['verdict']}")
for e in r["elements"]:
    if e.get("kind") != "cable":
        continue
    bend = e.get("min_bend_radius_mm")
    bend = "straight" if bend is None else f"{bend:.1f} mm"
    print(f"  {e['name']}: found={e['found']} diameter={e.get('diameter_mm')} min bend radius {bend} "
          f"bend_ok={e.get('bend_ok')} clearance_ok={e.get('clearance_ok')}")
    for i in e.get("interferences", []):
        print(f"    interference with {i['with']}: {i['min_distance_mm']:.2f} mm, {i['points']} points")
PY
echo "demo: truth of the scene: $out/scene/truth.json"
echo "demo: report: $(realpath "$out/inspection/report.html")"
