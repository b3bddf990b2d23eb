#!/usr/bin/env python3
"""The elastic SDNV104 shoe at a large step (issue 32): for each integrator setting and mesh, the
relative errors of the extrema x1 and x2 against the exact ramped rigid-shoe solution (the scenes'
checks), the contact's normal force range after the ramp, and its step-to-step oscillation (the
median and the largest |N_{k+1} − 2 N_k + N_{k−1}| / 70 kN after t = 0.2 s: θ = ½ leaves a period-two
oscillation that nothing damps). Prints a Markdown table. Usage:
    python3 bench/elastic_shoe_table.py build/tools/csim [--step 0.01] [--meshes q4:5 q4:10 q4:20 q4:40 q8:5]
        [--settings "moreau-jean theta=0.5" "generalized-alpha rho_infinity=0.95" ...]
A setting is an integrator type followed by its integrator.KEY=VALUE overrides."""
import argparse
import csv
import json
import os
import statistics
import subprocess
import tempfile

DEFAULT_SETTINGS = ["moreau-jean theta=0.5", "moreau-jean theta=0.51", "generalized-alpha rho_infinity=1",
                    "generalized-alpha rho_infinity=0.95", "generalized-alpha rho_infinity=0.9",
                    "generalized-alpha rho_infinity=0.8", "generalized-alpha rho_infinity=0.5"]


def run(csim, setting, mesh, step):
    element, divisions = mesh.split(":")
    scene = "scenes/sdnv104-quad4" if element == "q4" else "scenes/sdnv104-quad8"
    words = setting.split()
    overrides = [f"integrator.type={words[0]}"] + [f"integrator.{w}" for w in words[1:]]
    command = [csim, "run", scene, "--quiet", f"--set=parameters.divisions={divisions}", f"--set=time.step={step}",
               "--set=time.end=4", "--set=output.rate=0", "--set=output.paraview=none"]
    command += [f"--set={o}" for o in overrides]
    with tempfile.TemporaryDirectory() as out:
        process = subprocess.run(command + ["--out", out], capture_output=True, text=True)
        if not os.path.exists(os.path.join(out, "summary.json")):
            return None, (process.stderr or process.stdout).strip().splitlines()[-1]
        summary = json.load(open(os.path.join(out, "summary.json")))
        rows = list(csv.DictReader(open(os.path.join(out, "probes.csv"))))
    checks = {c["name"]: c for c in summary["checks"]}
    times = [float(r["t"]) for r in rows]
    force = [float(r["normal_force"]) for r in rows]
    second = [abs(force[k + 1] - 2 * force[k] + force[k - 1]) / 70e3 for k in range(1, len(force) - 1) if times[k] > 0.2]
    after_ramp = [f for t, f in zip(times, force) if t > 0.2]
    return {"x1": checks["x1"]["error"] / checks["x1"]["reference"], "x2": checks["x2"]["error"] / checks["x2"]["reference"],
            "low": min(after_ramp), "high": max(after_ramp), "median": statistics.median(second), "largest": max(second),
            "wall": summary["wall_time"]}, None


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("csim")
    parser.add_argument("--step", type=float, default=0.01)
    parser.add_argument("--meshes", nargs="+", default=["q4:5", "q4:10", "q4:20", "q4:40", "q8:5"])
    parser.add_argument("--settings", nargs="+", default=DEFAULT_SETTINGS)
    args = parser.parse_args()
    print(f"time.step = {args.step}; errors relative to the exact ramped solution; N in kN (70 exact)\n")
    print("| integrator | mesh | x1 | x2 | N after the ramp (kN) | step-to-step oscillation of N: median, largest | wall (s) |")
    print("|---|---|---|---|---|---|---|")
    for setting in args.settings:
        for mesh in args.meshes:
            result, error = run(args.csim, setting, mesh, args.step)
            if result is None:
                print(f"| {setting} | {mesh} | stopped: {error} | | | | |", flush=True)
                continue
            print(f"| {setting} | {mesh} | {result['x1']:+.2e} | {result['x2']:+.2e} | {result['low'] / 1e3:.1f}–"
                  f"{result['high'] / 1e3:.1f} | {result['median']:.1e}, {result['largest']:.1e} | {result['wall']:.2f} |",
                  flush=True)


if __name__ == "__main__":
    main()
