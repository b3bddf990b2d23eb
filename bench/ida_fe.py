#!/usr/bin/env python3
"""IDA against Moreau-Jean on the elastic SDNV104 shoe (sdnv104-quad4), mesh by mesh: IDA's cost per
internal step and per simulated second at rtol 1e-6, and Moreau-Jean's cost at the time step whose x1
error matches IDA's (the largest of --steps that does). Medians of --repeats runs, one at a time.

usage: python3 bench/ida_fe.py [--divisions 10,20,40,80] [--steps 1e-3,5e-4,2e-4,1e-4] [--repeats 3]
       [--csim build/tools/csim] [--budget 600]   (a run over --budget seconds is reported as such)
"""
import argparse
import json
import statistics
import subprocess
import tempfile


def run(csim, overrides, budget):
    with tempfile.TemporaryDirectory() as out:
        command = [csim, "run", "scenes/sdnv104-quad4", "--quiet", "--out", out]
        for o in overrides:
            command += ["--set", o]
        try:
            subprocess.run(command, capture_output=True, text=True, timeout=budget)
        except subprocess.TimeoutExpired:
            return None
        try:
            with open(f"{out}/summary.json") as f:
                return json.load(f)
        except FileNotFoundError:
            return None


def x1_error(summary):
    for c in summary["checks"]:
        if c["name"] == "x1":
            return abs(c["error"] / c["reference"])
    return float("nan")


def median_runs(csim, overrides, repeats, budget):
    runs = [run(csim, overrides, budget) for _ in range(repeats)]
    if any(r is None for r in runs):
        return None, None
    walls = [r["wall_time"] for r in runs]
    return runs[0], (statistics.median(walls), min(walls), max(walls))


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("--divisions", default="10,20,40,80")
    parser.add_argument("--steps", default="1e-3,5e-4,2e-4,1e-4")
    parser.add_argument("--repeats", type=int, default=3)
    parser.add_argument("--csim", default="build/tools/csim")
    parser.add_argument("--budget", type=float, default=600)
    a = parser.parse_args()
    print("| mesh | unknowns | IDA steps | IDA s/step (µs) | IDA wall s (min–max) | IDA x1 error | "
          "MJ h matching it | MJ wall s (min–max) | MJ x1 error |")
    print("|---|---|---|---|---|---|---|---|---|")
    for n in [int(x) for x in a.divisions.split(",")]:
        mesh = [f"parameters.divisions={n}"]
        ida, ida_wall = median_runs(a.csim, mesh + ["integrator.type=ida"], a.repeats, a.budget)
        unknowns = 2 * 2 * (n + 1) ** 2
        if ida is None:
            print(f"| {n}×{n} | {unknowns} | over {a.budget:.0f} s | | | | | | |")
            continue
        error = x1_error(ida)
        steps = ida["ida"]["steps"]
        chosen = None
        for h in [float(x) for x in a.steps.split(",")]:
            mj, mj_wall = median_runs(a.csim, mesh + [f"time.step={h!r}"], a.repeats, a.budget)
            if mj is None:
                break
            chosen = (h, mj, mj_wall)
            if x1_error(mj) <= error:
                break
        mj_cells = "| | |"
        if chosen:
            h, mj, mj_wall = chosen
            mj_cells = f"{h:g} | {mj_wall[0]:.2f} ({mj_wall[1]:.2f}–{mj_wall[2]:.2f}) | {x1_error(mj):.1e} |"
        print(f"| {n}×{n} | {unknowns} | {steps} | {1e6 * ida_wall[0] / steps:.1f} | "
              f"{ida_wall[0]:.2f} ({ida_wall[1]:.2f}–{ida_wall[2]:.2f}) | {error:.1e} | {mj_cells}", flush=True)


if __name__ == "__main__":
    main()
