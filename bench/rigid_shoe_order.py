#!/usr/bin/env python3
"""Order of convergence on the rigid SDNV104 shoe (issue 32): the relative errors of the extrema x1, x2
against the exact stick-slip solution (the scene's checks) at halving steps, per integrator setting,
and the observed order log2(e(h) / e(h/2)). Prints a Markdown table. Usage:
    python3 bench/rigid_shoe_order.py build/tools/csim [--steps 0.01 0.005 0.0025 0.00125]
        [--settings "moreau-jean theta=0.5" "generalized-alpha rho_infinity=0.95" ...]"""
import argparse
import json
import math
import os
import subprocess
import tempfile

DEFAULT_SETTINGS = ["moreau-jean theta=0.5", "moreau-jean theta=0.51", "generalized-alpha rho_infinity=1",
                    "generalized-alpha rho_infinity=0.95", "generalized-alpha rho_infinity=0.5"]


def errors(csim, setting, step):
    words = setting.split()
    command = [csim, "run", "scenes/sdnv104-rigid", "--quiet", f"--set=time.step={step}", "--set=time.end=4",
               f"--set=integrator.type={words[0]}"] + [f"--set=integrator.{w}" for w in words[1:]]
    with tempfile.TemporaryDirectory() as out:
        subprocess.run(command + ["--out", out], capture_output=True)
        checks = {c["name"]: c for c in json.load(open(os.path.join(out, "summary.json")))["checks"]}
    return [abs(checks[n]["error"] / checks[n]["reference"]) for n in ("x1", "x2")]


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("csim")
    parser.add_argument("--steps", nargs="+", type=float, default=[0.01, 0.005, 0.0025, 0.00125])
    parser.add_argument("--settings", nargs="+", default=DEFAULT_SETTINGS)
    args = parser.parse_args()
    print("| integrator | " + " | ".join(f"h = {h:g}: x1, x2" for h in args.steps) + " | order over the range: x1, x2 |")
    print("|---|" + "---|" * (len(args.steps) + 1))
    for setting in args.settings:
        table = [errors(args.csim, setting, h) for h in args.steps]
        span = math.log2(args.steps[0] / args.steps[-1])
        order = [math.log2(table[0][k] / table[-1][k]) / span for k in range(2)]
        cells = " | ".join(f"{e[0]:.1e}, {e[1]:.1e}" for e in table)
        print(f"| {setting} | {cells} | {order[0]:.2f}, {order[1]:.2f} |", flush=True)


if __name__ == "__main__":
    main()
