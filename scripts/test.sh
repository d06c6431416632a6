#!/usr/bin/env bash
# Installs the dependencies (apt), builds everything and runs every test (unit tests and CLI tests) with CTest.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup.sh
bash scripts/build.sh
jobs=$(nproc 2>/dev/null || echo 2)
ctest --test-dir build --output-on-failure -j "$jobs" --timeout 900
