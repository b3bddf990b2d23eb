#!/bin/bash
# Instructions a steady step of the FE shoe at 13 122 and 51 842 DOFs, and their slope against the DOFs
# (docs/solver-measurements.md, "The FE step against the mesh size"): sdnv104-quad4 at 80 and 160
# divisions, callgrind's MoreauJean::step inclusive over runs of 200 and 300 steps of 1e-3 s, the
# difference divided by 100 steps, so that the factorization and the first contacts' W cancel. The work
# of the algorithm, which the host's caches do not change: bench_fe's slope in time is this one plus what
# memory adds at 52k. About 10 minutes.
# usage: bench/fe_instructions.sh CSIM [OUT_DIR]   (needs valgrind; CSIM built with -g)
set -euo pipefail
csim=$1
out=${2:-$(mktemp -d)}
scene=$(cd "$(dirname "$0")/../scenes" && pwd)/sdnv104-quad4
mkdir -p "$out"
count() {  # divisions, end time: MoreauJean::step's inclusive instructions
  local run="$out/$1-$2"
  # The checks' references are at t = 4 s: moved to the run's end, they fail (exit 1); the count stands.
  valgrind --tool=callgrind --callgrind-out-file="$run.callgrind" "$csim" run "$scene" \
    --set parameters.divisions="$1" --set time.end="$2" --set checks.seed_x_170.at="$2" \
    --set checks.seed_x_340.at="$2" --set output.rate=1000 --out "$run" --quiet > /dev/null 2>&1 || true
  callgrind_annotate --inclusive=yes "$run.callgrind" 2>/dev/null |
    awk '/MoreauJean::step\(csim::State&\) \[/ { gsub(",", "", $1); print $1 }'
}
declare -A per_step
for divisions in 80 160; do
  short=$(count "$divisions" 0.2)
  long=$(count "$divisions" 0.3)
  per_step[$divisions]=$(( (long - short) / 100 ))
  printf '%4d divisions %7d DOFs %12d instructions a step\n' "$divisions" $(( 2 * (divisions + 1) ** 2 )) \
    "${per_step[$divisions]}"
done
awk -v a="${per_step[80]}" -v b="${per_step[160]}" \
  'BEGIN { printf "ratio %.3f, slope %.3f against the DOFs (target 3: 1.15)\n", b / a, log(b / a) / log(51842 / 13122) }'
