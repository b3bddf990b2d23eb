#!/usr/bin/env python3
"""The speed-up of the study runner: a reduced rolling table (bench/rolling_table.py --rows ... --configs ...
--no-studies, written to a scratch file) regenerated on 1 rank and on N ranks (`csim sweep` under
`mpirun --bind-to core`), alternately, REPEATS times each. Prints the wall times, median [min–max], their
ratio and the load average before and after (the machine may be shared). Usage:
    python3 bench/rolling_ranks.py [--csim build/tools/csim] [--rows 1,5,9,13] [--configs 1,3] [--ranks 2]
                                   [--repeats 3]
"""
import argparse
import os
import statistics
import subprocess
import sys
import tempfile
import time


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("--csim", default="build/tools/csim")
    parser.add_argument("--rows", default="1,5,9,13")
    parser.add_argument("--configs", default="1,3")
    parser.add_argument("--ranks", type=int, default=os.cpu_count() or 2)
    parser.add_argument("--repeats", type=int, default=3)
    args = parser.parse_args()
    here = os.path.dirname(os.path.abspath(__file__))
    times = {1: [], args.ranks: []}
    load_before = os.getloadavg()
    with tempfile.TemporaryDirectory() as work:
        scratch = os.path.join(work, "table.md")
        for repeat in range(args.repeats):
            for ranks in (1, args.ranks) if repeat % 2 == 0 else (args.ranks, 1):
                open(scratch, "w").write("<!-- generated: begin -->\n<!-- generated: end -->\n")
                command = [sys.executable, os.path.join(here, "rolling_table.py"), "--csim", args.csim,
                           "--rows", args.rows, "--configs", args.configs, "--no-studies", "--ranks", str(ranks),
                           "--out", scratch]
                start = time.perf_counter()
                subprocess.run(command, check=True, capture_output=True, env=dict(os.environ, OMP_NUM_THREADS="1",
                               OPENBLAS_NUM_THREADS="1"))
                times[ranks].append(time.perf_counter() - start)
                print(f"repeat {repeat + 1}, {ranks} rank(s): {times[ranks][-1]:.1f} s", file=sys.stderr, flush=True)
    load_after = os.getloadavg()
    one, many = statistics.median(times[1]), statistics.median(times[args.ranks])
    print(f"reduced rolling table (--rows {args.rows} --configs {args.configs} --no-studies), {args.repeats} "
          f"alternated repeats, load average {load_before[0]:.1f} before, {load_after[0]:.1f} after:\n")
    print("| ranks | wall (s), median [min–max] |")
    print("|---|---|")
    for ranks in (1, args.ranks):
        print(f"| {ranks} | {statistics.median(times[ranks]):.1f} [{min(times[ranks]):.1f}–{max(times[ranks]):.1f}] |")
    print(f"\nspeed-up of {args.ranks} ranks over 1: {one / many:.2f} (medians; "
          f"{min(times[1]) / max(times[args.ranks]):.2f}–{max(times[1]) / min(times[args.ranks]):.2f} over the spreads)")


if __name__ == "__main__":
    main()
