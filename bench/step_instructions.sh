#!/bin/bash
# Instructions a step of the three lumped benchmark scenes (bench/lumped_vs_bullet.md), counted by
# callgrind: MoreauJean::step inclusive over 20 000 steps (h 1e-5 for 0.2 s; sdnd100-a h 2e-6 for
# 0.04 s), divided by the steps. Deterministic where the wall clock of a shared host is not; compare
# builds configured alike (Release with -g), since the same code built elsewhere counts up to 1 %
# differently.
# usage: bench/step_instructions.sh CSIM [OUT_DIR]   (needs valgrind; CSIM built with -g)
set -euo pipefail
csim=$1
out=${2:-$(mktemp -d)}
scenes=$(cd "$(dirname "$0")/../scenes" && pwd)
mkdir -p "$out"
for scene in incline-3d sdnv104-rigid sdnd100-a; do
  if [ "$scene" = sdnd100-a ]; then overrides=(--set time.step=2e-6 --set time.end=0.04)
  else overrides=(--set time.step=1e-5 --set time.end=0.2); fi
  valgrind --tool=callgrind --callgrind-out-file="$out/$scene.callgrind" "$csim" run "$scenes/$scene" \
    "${overrides[@]}" --out "$out/$scene" --quiet > /dev/null 2>&1 ||
    true  # a run this short leaves some checks unevaluated: csim exits 1, the count stands
  callgrind_annotate --inclusive=yes "$out/$scene.callgrind" 2>/dev/null |
    awk -v scene="$scene" '/MoreauJean::step\(csim::State&\) \[/ { gsub(",", "", $1); step = $1 }
      END { printf "%-14s %6.0f instructions a step\n", scene, step / 20000 }'
done
