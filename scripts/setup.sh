#!/usr/bin/env bash
# Installs everything ewis-inspect needs to build and test, from Debian 12's packages only.
set -euo pipefail
packages=(
  g++ cmake ninja-build pkg-config
  libeigen3-dev libnanoflann-dev libembree-dev libtbb-dev libassimp-dev libcli11-dev nlohmann-json3-dev
  libspdlog-dev libfmt-dev liblzf-dev libstb-dev zlib1g-dev
  libgtest-dev libgmock-dev libbenchmark-dev
  python3 python3-jsonschema python3-numpy
  chromium fonts-dejavu-core
)
missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -gt 0 ]; then
  SUDO=""
  [ "$(id -u)" -ne 0 ] && SUDO="sudo"
  echo "setup: installing ${missing[*]}"
  $SUDO apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
fi
