#!/usr/bin/env bash
# Installs what is missing (Debian bookworm packages only), then configures and builds csim, its tests
# and benchmarks in ./build. Safe to run again: it installs nothing that is present and rebuilds only
# what changed.
set -euo pipefail
cd "$(dirname "$0")/.."

packages=(g++ cmake make libeigen3-dev libfcl-dev libccd-dev libsundials-dev libsuitesparse-dev libgtest-dev libyaml-cpp-dev libcli11-dev zlib1g-dev gnuplot-nox python3 python3-vtk9 libbullet-dev)
missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if ((${#missing[@]})); then
  echo "setup: installing ${missing[*]}" >&2
  sudo_cmd=()
  [ "$(id -u)" -ne 0 ] && sudo_cmd=(sudo)
  "${sudo_cmd[@]}" apt-get update -qq
  DEBIAN_FRONTEND=noninteractive "${sudo_cmd[@]}" apt-get install -y -qq "${missing[@]}" >/dev/null
fi

jobs=$(nproc 2>/dev/null || echo 2)
cmake -S . -B build -DCMAKE_BUILD_TYPE=Release >/dev/null
if ! cmake --build build -j"$jobs" >build/build.log 2>&1; then
  grep -E "error" -A5 build/build.log | head -60 >&2
  echo "setup: the build failed; the full log is build/build.log" >&2
  exit 1
fi
