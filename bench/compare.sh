#!/usr/bin/env bash
# Side-by-side comparison of ewis with PCL 1.13 and Open3D 0.16 (Debian's packages) on the same inputs and parameters.
# Installs the peers (apt), builds bench/peers apart from the main build (build-peers/), makes the inputs with the
# virtual scanner, runs every step of each side REPEAT times in turn and writes the table of medians into
# bench/RESULTS.md (between the "compare" markers). Never run by the tests or CI.
# Usage: bench/compare.sh [REPEAT]   (default 5). Single rows: python3 bench/compare_table.py --bin build-peers/bin
# --data build-peers/data --repeat 1 --results /tmp/compare_test.md --only icp,cylinder (after one compare.sh run).
set -euo pipefail
cd "$(dirname "$0")/.."
repeat=${1:-5}
bash scripts/setup.sh
if ! dpkg-query -W -f='${Status}' libpcl-dev 2>/dev/null | grep -q "install ok installed" ||
   ! dpkg-query -W -f='${Status}' libopen3d-dev 2>/dev/null | grep -q "install ok installed"; then
  apt-get update -qq
  DEBIAN_FRONTEND=noninteractive apt-get install -y -qq --no-install-recommends libpcl-dev libopen3d-dev libboost-dev >/dev/null
fi
cmake -G Ninja -S bench/peers -B build-peers -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build build-peers -j "$(nproc)" --target ewis ewis_steps pcl_steps open3d_steps
bin=build-peers/bin
data=build-peers/data
mkdir -p "$data"
if [ ! -f "$data/scene/scan.ply" ]; then
  "$bin/ewis" simulate --out "$data/scene" --seed 11 --quiet
fi
"$bin/ewis_steps" convert-pcd "$data/scene/scan.ply" "$data/scan_compressed.pcd" >/dev/null
"$bin/ewis" filter --scan "$data/scene/scan.ply" --out "$data/filtered.ply" --quiet >/dev/null
# the shared inputs of the ICP, cylinder, ray-casting, chain and inspection rows (bench/RESULTS.md notes)
"$bin/ewis_steps" prepare "$data/scene" "$data/filtered.ply" "$data"
python3 bench/compare_table.py --bin "$bin" --data "$data" --repeat "$repeat" --results bench/RESULTS.md
