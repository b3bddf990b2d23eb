#!/usr/bin/env python3
"""The peak pressure of a run of this scene against Hertz's p0, from its last contacts file:

    csim run scenes/hertz-quarter-disk --set output.paraview=ascii [--set parameters.spring=1e-7] --out OUT
    python3 scenes/hertz-quarter-disk/peak_pressure.py OUT [young poisson radius half_width step]

p = 2 F0 / h0, F0 the normal force of the node at x = 0 (its impulse / time.step), h0 the next node's x;
p0 = sqrt(P E* / (pi R)), P = pi E* a^2 / (4 R), E* = E / (1 - nu^2) (Johnson, Contact Mechanics, 4.3).
Defaults: the scene's parameters (2e11 0.3 0.1 2e-3) and time.step 0.5.
"""
import glob
import math
import re
import sys


def main():
    out = sys.argv[1]
    E, nu, R, a, h = (float(x) for x in (sys.argv[2:7] if len(sys.argv) >= 7 else (2e11, 0.3, 0.1, 2e-3, 0.5)))
    text = open(sorted(glob.glob(out + "/paraview/contacts_*.vtu"))[-1]).read()
    points = [float(x) for x in re.search(r"<Points>.*?>([^<]*)<", text, re.S).group(1).split()]
    impulse = [float(x) for x in re.search(r'Name="impulse"[^>]*>([^<]*)<', text).group(1).split()]
    n = len(points) // 3
    d = len(impulse) // n
    nodes = sorted((points[3 * i], impulse[d * i] / h) for i in range(n))
    E_star = E / (1 - nu * nu)
    P = math.pi * E_star * a * a / (4 * R)
    p0 = math.sqrt(P * E_star / (math.pi * R))
    peak = 2 * nodes[0][1] / nodes[1][0]
    print(f"{len(nodes)} contact nodes; peak pressure {peak:.6g} Pa, Hertz p0 {p0:.6g} Pa: {100 * (peak / p0 - 1):+.3f} %")


if __name__ == "__main__":
    main()
