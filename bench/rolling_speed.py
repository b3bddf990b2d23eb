#!/usr/bin/env python3
"""Wall time of the rolling rings' default rows with two csim binaries (before and after a change),
runs alternating one at a time, one thread: the median and the spread (min–max) of each, their ratio,
and whether both gave the same spin and Newton iterations; the same for the CPU time (user + system),
which depends less on what else the machine runs. Prints a Markdown table. Usage:
    OMP_NUM_THREADS=1 python3 bench/rolling_speed.py BEFORE_CSIM AFTER_CSIM [--runs 3]
        [--scenes rolling-ring rolling-ring-3d]
The default plane row is scenes/rolling-ring as it stands (Mooney–Rivlin δ 0.1, r_i 1, μ 0.02 on
68 × 10); the default 3D row scenes/rolling-ring-3d as it stands (pstc38siefc: elastic δ 0.05, r_i 0.2,
μ 0.02, cornering at R_c = 100, 68 × 10 × 1)."""
import argparse
import os
import resource
import statistics

from rolling_run import rolling_run


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("before")
    parser.add_argument("after")
    parser.add_argument("--runs", type=int, default=3)
    parser.add_argument("--scenes", nargs="+", default=["rolling-ring", "rolling-ring-3d"])
    args = parser.parse_args()
    os.environ.setdefault("OMP_NUM_THREADS", "1")
    os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")
    print("| scene | wall before (s) | wall after (s) | ratio | CPU before (s) | CPU after (s) | ratio | same spin and Newton iterations |")
    print("|---|---|---|---|---|---|---|---|")
    for scene in args.scenes:
        runs = {"before": [], "after": []}
        for _ in range(args.runs):
            for which in ("before", "after"):
                used = resource.getrusage(resource.RUSAGE_CHILDREN)
                run = rolling_run([getattr(args, which), "run", f"scenes/{scene}", "--quiet"])
                now = resource.getrusage(resource.RUSAGE_CHILDREN)
                run["cpu"] = now.ru_utime + now.ru_stime - used.ru_utime - used.ru_stime
                runs[which].append(run)
        cells = []
        for key in ("wall", "cpu"):
            for which in ("before", "after"):
                times = [r[key] for r in runs[which]]
                cells.append((statistics.median(times), min(times), max(times)))
        same = all(r.get("spin") == runs["before"][0].get("spin") and r.get("newton") == runs["before"][0].get("newton")
                   for r in runs["before"] + runs["after"])
        row = f"| {scene} |"
        for before, after in ((cells[0], cells[1]), (cells[2], cells[3])):
            row += (f" {before[0]:.2f} ({before[1]:.2f}–{before[2]:.2f}) | {after[0]:.2f} ({after[1]:.2f}–{after[2]:.2f}) |"
                    f" {before[0] / after[0]:.2f} |")
        print(row + f" {'yes' if same else 'NO'} (spin {runs['after'][0].get('spin'):.8f}) |", flush=True)


if __name__ == "__main__":
    main()
