#!/usr/bin/env python3
"""The contact's normal force history of the elastic SDNV104 shoe under several integrators (issue 32),
one run each at the same step and mesh, plotted together with gnuplot (exact value: 70 kN after the
0.07 s ramp). Usage:
    python3 bench/elastic_shoe_force.py build/tools/csim OUT.png [--step 0.01] [--divisions 20]
        [--settings "moreau-jean theta=0.5" ...]"""
import argparse
import os
import subprocess
import tempfile

DEFAULT_SETTINGS = ["moreau-jean theta=0.5", "moreau-jean theta=0.51", "generalized-alpha rho_infinity=0.95",
                    "generalized-alpha rho_infinity=0.8"]


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("csim")
    parser.add_argument("png")
    parser.add_argument("--step", type=float, default=0.01)
    parser.add_argument("--divisions", type=int, default=20)
    parser.add_argument("--settings", nargs="+", default=DEFAULT_SETTINGS)
    args = parser.parse_args()
    with tempfile.TemporaryDirectory() as work:
        plots = []
        for k, setting in enumerate(args.settings):
            words = setting.split()
            out = os.path.join(work, str(k))
            command = [args.csim, "run", "scenes/sdnv104-quad4", "--quiet", f"--set=time.step={args.step}",
                       f"--set=parameters.divisions={args.divisions}", "--set=time.end=4", "--set=output.rate=0",
                       "--set=output.paraview=none", f"--set=integrator.type={words[0]}"]
            command += [f"--set=integrator.{w}" for w in words[1:]]
            subprocess.run(command + ["--out", out], capture_output=True, check=False)
            data = os.path.join(out, "probes.csv")
            if os.path.exists(data):
                plots.append(f"'{data}' using 1:($3/1000) with lines title '{setting}'")
        script = (f"set terminal pngcairo size 1100,600 noenhanced; set output '{args.png}'; set datafile separator ',';"
                  f"set key autotitle columnhead; set xlabel 't (s)'; set ylabel 'normal force (kN)';"
                  f"set title 'SDNV104 elastic shoe, {args.divisions} x {args.divisions} QUAD4, dt = {args.step} s';"
                  f"set yrange [40:100]; plot " + ", ".join(plots))
        subprocess.run(["gnuplot", "-e", script], check=True)


if __name__ == "__main__":
    main()
