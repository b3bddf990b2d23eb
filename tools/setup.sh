#!/usr/bin/env bash
# Installs what is missing (Debian bookworm packages only), then configures and builds in ./build.
#   bash tools/setup.sh csim   the main job: the packages `csim` needs to build and run, and the `csim` target
#   bash tools/setup.sh        everything: also the test and benchmark packages, and every target
# Safe to run again: it installs nothing that is present and rebuilds only what changed.
# With CSIM_SETUP_DRY_RUN=1 it installs and builds nothing, and prints what it would do: a line
# `packages: …` (every package of the mode, installed or not) and a line `build: …` (the targets).
set -euo pipefail
cd "$(dirname "$0")/.."

mode=${1:-all}
case "$mode" in
  csim | all) ;;
  *) echo "setup: unknown mode '$mode' (use 'csim' for the main job, or nothing for tests and benchmarks)" >&2
     exit 2 ;;
esac

# What `csim` needs: the compiler and the libraries it links; gnuplot draws `csim compare`'s figure.
packages=(g++ cmake make libeigen3-dev libfcl-dev libccd-dev libsundials-dev libsuitesparse-dev libhdf5-dev
          libyaml-cpp-dev libcli11-dev zlib1g-dev gnuplot-nox)
# What the tests and benchmarks add: GoogleTest, Python with VTK for the ParaView read-back, Bullet.
[ "$mode" = all ] && packages+=(libgtest-dev python3 python3-vtk9 libbullet-dev)

if [ "$mode" = csim ]; then
  configure=(-DCSIM_BUILD_TESTS=OFF -DCSIM_BUILD_BENCH=OFF)
  targets=(--target csim)
else
  configure=(-DCSIM_BUILD_TESTS=ON -DCSIM_BUILD_BENCH=ON)
  targets=()
fi

if [ "${CSIM_SETUP_DRY_RUN:-0}" = 1 ]; then
  echo "packages: ${packages[*]}"
  echo "build: ${targets[*]:-all}"
  exit 0
fi

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
cmake -S . -B build -DCMAKE_BUILD_TYPE=Release "${configure[@]}" >/dev/null
if ! cmake --build build -j"$jobs" "${targets[@]}" >build/build.log 2>&1; then
  grep -E "error" -A5 build/build.log | head -60 >&2
  echo "setup: the build failed; the full log is build/build.log" >&2
  exit 1
fi
