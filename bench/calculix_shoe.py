#!/usr/bin/env python3
"""The elastic SDNV104 shoe (scenes/sdnv104-quad4) in csim and in CalculiX 2.20, wall time of each.

The problem: a 1 m x 1 m plane-strain block (E = 2.1e11 Pa, nu = 0, rho = 7000 kg/m3, thickness 1 m)
meshed N x N in 4-node quadrilaterals, on a rigid plane y = 0, pressed by 70 kPa on its top face and
pushed by 200 kPa on its left face (both ramped linearly over 0.07 s, then held), held back by two
springs of 12 kN/m along x at its corners (1, 0) and (1, 1), Coulomb friction mu = 0.3 between its
bottom nodes and the plane; 0 to 4 s at a fixed step of 0.01 s. The key quantity is the horizontal
displacement of the corner (0, 0): its first two turning points x1 (a maximum, about 14.9 m) and x2 (a
minimum, about 3.5 m); the ramped rigid-shoe solution gives 14.911 and 3.505 (SPEC.md 1.7).

The CalculiX deck this program writes (ccx has no rigid analytical surface, no nonsmooth contact and no
Moreau-Jean stepper; what stands for each), in mm, N, s and tonnes:
  - shoe: N x N CPE4 (plane strain, thickness 1 m, consistent mass; nu = 0 makes plane stress the same
    problem). ccx expands each CPE4 into a C3D8 layer whose nodes it ties to the plane nodes by
    equations, so it solves 2 equations a node, as csim. --element C3D8 writes that layer explicitly
    (uz = 0 at every node, 4 equations a plane node): needed by --automatic, since with CPE4 ccx's
    contact-period estimate (storecontactprop.f) finds no mass at the tied slave nodes and forces every
    automatic increment to the minimum;
  - rigid plane: a strip of fixed elements under y = 0 (x from -3 m to 24 m); its top faces are the
    master surface;
  - contact: *CONTACT PAIR, TYPE=NODE TO SURFACE, slave = the shoe's bottom faces (so each slave node
    carries its tributary area and the penalty is a pressure), master = the strip's top faces. Node to
    surface because csim's contact is node to surface too (each bottom node against the plane); ccx's
    face-to-face (mortar-like) contact spreads each node's force over a face. Penalty *SURFACE BEHAVIOR,
    PRESSURE-OVERCLOSURE=LINEAR, slope 10 E = 2.1e12 Pa/m by default (--penalty; the manual advises 5
    to 50 E): the penetration under 70 kPa is 0.03 um, where csim enforces gap >= 0 exactly;
  - friction: *FRICTION mu with a stick slope a tenth of the normal slope (the manual's advice): an
    elastic stick of 0.1 um under the full friction force, where csim's Coulomb law has no stick slip;
  - springs: SPRING1 on the two corner nodes, DOF 1, 12e3 N/m (C3D8: on front and back, half each);
  - loads: *DLOAD pressures on the top and left faces with a tabular *AMPLITUDE 0 -> 1 at 0.07 s -> 1;
  - time: *DYNAMIC, DIRECT with increment 0.01 s over 4 s: 400 fixed increments of ccx's alpha method
    (HHT, alpha = -0.05), each a Newton iteration to ccx's default tolerances (2 iterations an increment
    here). --automatic gives ccx automatic incrementation from 0.01 s (at most 0.01 s, at least
    --minimum-increment) instead. csim takes one linear Moreau-Jean step (theta = 0.51, as the scene)
    with one frictional contact solve per step;
  - output: the corner's displacement at every increment (*NODE PRINT to the .dat), no field: ccx 2.20
    writes its .frd at the .dat's frequency (every increment: 35 MB at 40 x 40), where csim writes its
    probes every step and 5 fields (output.rate = 1 s); ccx is spared that output.

What ccx 2.20 cannot do here: with friction (the scene's mu = 0.3) its implicit dynamics stops at the
first increment with DIRECT ("solution seems to diverge; please try automatic incrementation"), and
within the first 0.02 s with automatic incrementation ("too many cutbacks"), whatever the penalty (1e9 to
2.1e12 Pa/m tried) and the minimum increment (1e-9 to 1e-3 s tried). Its energy
balance (checkconvergence.c, checkimpacts.f) counts internal, kinetic, contact-spring and contact-damping
energy against the work of the loads, but not the work dissipated by friction, so the sliding shoe's
dissipation reads as an "impact" and every increment is cut until none is left. So this program compares
the two programs at each coefficient in --mu (default: 0.3, where ccx's attempt is reported, and 0, the
same problem without friction, which ccx solves at 0.01 s increments from start to end).
With --automatic and the manual's penalty, ccx also cuts the frictionless problem's increments (to about
0.007 s: checkimpacts.f allows at most 100 periods of the stiffest contact spring).

Both runs are timed as whole processes (reading the input, solving, writing: wall time, and the CPU time
of the process, which the load of a shared machine disturbs less), alternately, N times each;
ccx on one thread (OMP_NUM_THREADS=1, CCX_NPROC_STIFFNESS=1, CCX_NPROC_EQUATION_SOLVER=1,
CCX_NPROC_RESULTS=1, OPENBLAS_NUM_THREADS=1; Debian's ccx solves with SPOOLES). csim's extrema are its
own checks (from every step; docs/contract.md); ccx's are found here the same way (the first two turning
points, refined by the parabola through the turning sample and its two neighbours).

Requires CalculiX 2.20 (Debian bookworm: `apt-get install -y calculix-ccx`; not in tools/setup.sh: the
bench is run by hand). Usage, from the repository's root:
    python3 bench/calculix_shoe.py build/tools/csim [--ccx ccx] [--divisions 40] [--runs 3] [--mu 0.3 0]
        [--element CPE4|C3D8] [--penalty 2.1e12] [--automatic [--minimum-increment 1e-5]] [--keep DIR]
"""
import argparse
import json
import os
import re
import resource
import shutil
import statistics
import subprocess
import tempfile
import time

YOUNG, DENSITY, MU = 2.1e11, 7000.0, 0.3
TOP_PRESSURE, SIDE_PRESSURE, SPRING, RAMP = 70e3, 200e3, 12e3, 0.07
STEP, END = 0.01, 4.0
STICK_FRACTION = 0.1              # ccx's stick slope over its normal slope (the manual's advice)
TENSION_AT_CLEARANCE = 0.25        # Pa, ccx's sigma_infinity (tension at large clearance): nothing against 70 kPa
STRIP = (-3.0, 24.0, 27)           # the rigid plane's strip: x from, x to, elements
SINGLE_THREAD = {"OMP_NUM_THREADS": "1", "CCX_NPROC_STIFFNESS": "1", "CCX_NPROC_EQUATION_SOLVER": "1",
                 "CCX_NPROC_RESULTS": "1", "NUMBER_OF_CPUS": "1", "OPENBLAS_NUM_THREADS": "1"}


def lines_of(ids, per_line=8):
    return [", ".join(str(i) for i in ids[k:k + per_line]) for k in range(0, len(ids), per_line)]


def calculix_deck(n, element_type, normal_slope, minimum_increment, mu):
    """The .inp text of the shoe meshed n x n, 1 m thick, in mm, N, s and tonnes: CPE4 (plane strain), or
    one layer of C3D8 with uz = 0 at every node; a fixed increment (DIRECT) where minimum_increment is
    None, else automatic incrementation. The shoe's node (i, j) at (i/n, j/n) m is 1 + i + j (n + 1),
    its back node (C3D8) that plus (n + 1)^2."""
    mm, pa, n_per_m = 1e3, 1e-6, 1e-3        # m -> mm, Pa -> N/mm2, N/m -> N/mm
    solid = element_type == "C3D8"
    layers = 2 if solid else 1
    layer = (n + 1) ** 2
    node = lambda i, j, k=0: 1 + i + j * (n + 1) + k * layer
    element = lambda i, j: 1 + i + j * n
    z = lambda k: f", {mm * k:g}" if solid else ""
    # faces: bottom, top, left of a quadrilateral (CPE4: edges 1-2, 3-4, 4-1) or a brick (C3D8)
    bottom, top, left = ("S3", "S5", "S6") if solid else ("S1", "S3", "S4")
    cell = lambda a, b, c, d: [a, b, c, d] + ([x + layer for x in (a, b, c, d)] if solid else [])
    deck = ["** SDNV104 elastic shoe, written by bench/calculix_shoe.py (mm, N, s, t)", "*NODE, NSET=NSHOE"]
    deck += [f"{node(i, j, k)}, {mm * i / n:.12g}, {mm * j / n:.12g}{z(k)}"
             for k in range(layers) for j in range(n + 1) for i in range(n + 1)]
    deck.append(f"*ELEMENT, TYPE={element_type}, ELSET=SHOE")
    deck += [", ".join(str(x) for x in [element(i, j)] + cell(node(i, j), node(i + 1, j), node(i + 1, j + 1),
                                                              node(i, j + 1)))
             for j in range(n) for i in range(n)]
    # The rigid plane: one row of fixed elements under y = 0; their top faces are the master surface.
    first_node, first_element = layers * layer + 1, n * n + 1
    x0, x1, count = STRIP
    row = count + 1
    plane_node = lambda k, upper, back=0: first_node + k + upper * row + back * 2 * row
    deck.append("*NODE, NSET=NPLANE")
    for back in range(layers):
        for upper in range(2):
            deck += [f"{plane_node(k, upper, back)}, {mm * (x0 + (x1 - x0) * k / count):.12g}, "
                     f"{-mm * (1 - upper):g}{z(back)}" for k in range(row)]
    deck.append(f"*ELEMENT, TYPE={element_type}, ELSET=PLANE")
    for k in range(count):
        corners = [plane_node(k, 0), plane_node(k + 1, 0), plane_node(k + 1, 1), plane_node(k, 1)]
        deck.append(", ".join(str(x) for x in [first_element + k] + corners
                              + ([c + 2 * row for c in corners] if solid else [])))
    spring_element = first_element + count
    springs = [node(n, 0, k) for k in range(layers)] + [node(n, n, k) for k in range(layers)]
    deck += ["*ELEMENT, TYPE=SPRING1, ELSET=SPRINGS"] + [f"{spring_element + k}, {x}" for k, x in enumerate(springs)]
    deck += ["*NSET, NSET=CORNER", f"{node(0, 0)}",
             "*SURFACE, NAME=SHOE_BOTTOM"] + [f"{element(i, 0)}, {bottom}" for i in range(n)]
    deck += ["*SURFACE, NAME=PLANE_TOP"] + [f"{first_element + k}, {top}" for k in range(count)]
    thickness = [] if solid else [f"{mm:.1f}"]
    deck += ["*MATERIAL, NAME=STEEL", "*ELASTIC", f"{YOUNG * pa:.6e}, 0", "*DENSITY", f"{DENSITY * 1e-12:.6e}",
             "*SOLID SECTION, ELSET=SHOE, MATERIAL=STEEL", *thickness,
             "*SOLID SECTION, ELSET=PLANE, MATERIAL=STEEL", *thickness,
             # each spring of the scene, split between the front and back nodes of a C3D8 layer; a
             # decimal point marks a stiffness, not a DOF
             "*SPRING, ELSET=SPRINGS", "1", f"{SPRING * n_per_m / layers:.6e}",
             "*SURFACE INTERACTION, NAME=SHOE_ON_PLANE",
             "*SURFACE BEHAVIOR, PRESSURE-OVERCLOSURE=LINEAR",
             f"{normal_slope * 1e-9:.6e}, {TENSION_AT_CLEARANCE * pa:.6e}",
             *(["*FRICTION", f"{mu:g}, {normal_slope * STICK_FRACTION * 1e-9:.6e}"] if mu > 0 else []),
             "*CONTACT PAIR, INTERACTION=SHOE_ON_PLANE, TYPE=NODE TO SURFACE", "SHOE_BOTTOM, PLANE_TOP",
             "*BOUNDARY", f"NPLANE, 1, {3 if solid else 2}", *(["NSHOE, 3, 3"] if solid else []),
             "*AMPLITUDE, NAME=RAMP", f"0., 0., {RAMP:g}, 1., {END * 10:g}, 1.",
             "*STEP, INC=1000000",
             *(["*DYNAMIC, DIRECT", f"{STEP:g}, {END:g}"] if minimum_increment is None else
               ["*DYNAMIC", f"{STEP:g}, {END:g}, {minimum_increment:g}, {STEP:g}"]),
             "*DLOAD, AMPLITUDE=RAMP"]
    deck += [f"{element(i, n - 1)}, P{top[1]}, {TOP_PRESSURE * pa:.6e}" for i in range(n)]
    deck += [f"{element(0, j)}, P{left[1]}, {SIDE_PRESSURE * pa:.6e}" for j in range(n)]
    # no *NODE FILE: ccx 2.20 writes the .frd at the .dat's frequency (every increment, 35 MB at 40 x 40)
    deck += ["*NODE PRINT, NSET=CORNER, FREQUENCY=1", "U", "*END STEP"]
    return "\n".join(deck) + "\n"


def turning_points(times, values, count=2):
    """The first `count` turning points of a sampled signal: the vertex of the parabola through each
    turning sample and its two neighbours (the sample itself where the three are not a parabola)."""
    found = []
    for k in range(1, len(values) - 1):
        rise, fall = values[k] - values[k - 1], values[k + 1] - values[k]
        if rise * fall < 0 or (rise != 0 and fall == 0):
            a, b, c = values[k - 1], values[k], values[k + 1]
            curvature = a - 2 * b + c
            shift = 0.5 * (a - c) / curvature if curvature != 0 else 0.0
            if abs(shift) > 1:
                shift = 0.0
            step = times[k + 1] - times[k]
            found.append((times[k] + shift * step, b - 0.25 * (a - c) * shift))
            if len(found) == count:
                break
    return found


def read_calculix_history(dat):
    """(times, ux) of the corner from ccx's .dat: one block per increment."""
    times, ux, now = [0.0], [0.0], None
    for line in open(dat):
        heading = re.match(r"\s*displacements \(vx,vy,vz\) for set CORNER and time\s+(\S+)", line)
        if heading:
            now = float(heading.group(1))
            continue
        fields = line.split()
        if now is not None and len(fields) == 4:
            times.append(now)
            ux.append(float(fields[1]) / 1e3)  # mm -> m
            now = None
    return times, ux


def children_cpu():
    """CPU seconds (user + system) of the finished child processes so far."""
    usage = resource.getrusage(resource.RUSAGE_CHILDREN)
    return usage.ru_utime + usage.ru_stime


def run_calculix(ccx, deck, work):
    """(wall s, CPU s, times, ux, why it stopped early or None, increments done)."""
    with open(os.path.join(work, "shoe.inp"), "w") as out:
        out.write(deck)
    environment = dict(os.environ, **SINGLE_THREAD)
    start, cpu = time.perf_counter(), children_cpu()
    process = subprocess.run([ccx, "-i", "shoe"], cwd=work, capture_output=True, text=True, env=environment)
    wall, cpu = time.perf_counter() - start, children_cpu() - cpu
    times, ux = read_calculix_history(os.path.join(work, "shoe.dat"))
    stopped = None
    if process.returncode != 0 or abs(times[-1] - END) > 1e-6:
        lines = process.stdout.splitlines()
        errors = [" ".join(lines[k:k + 2]).split() for k, line in enumerate(lines) if "*ERROR" in line]
        stopped = f"stopped at t = {times[-1]:.4g} s: {' '.join(errors[-1]) if errors else f'exit {process.returncode}'}"
    increments = sum(1 for line in open(os.path.join(work, "shoe.sta")) if re.match(r"\s+1\s+\d+\s+\d+\s", line))
    return wall, cpu, times, ux, stopped, increments


def run_csim(csim, divisions, mu, work):
    command = [csim, "run", "scenes/sdnv104-quad4", "--quiet", f"--set=parameters.divisions={divisions}",
               f"--set=parameters.mu={mu:g}", f"--set=time.step={STEP:g}", f"--set=time.end={END:g}",
               "--set=output.rate=1", "--out", work]
    start, cpu = time.perf_counter(), children_cpu()
    process = subprocess.run(command, capture_output=True, text=True)
    wall, cpu = time.perf_counter() - start, children_cpu() - cpu
    if not os.path.exists(os.path.join(work, "summary.json")):
        raise SystemExit(f"csim failed (exit {process.returncode}): {(process.stderr or process.stdout).strip()}")
    summary = json.load(open(os.path.join(work, "summary.json")))
    checks = {c["name"]: c for c in summary["checks"]}
    return wall, cpu, checks, summary["wall_time"], summary["steps"]


def spread(values):
    return f"{statistics.median(values):.3g} ({min(values):.3g}–{max(values):.3g})"


def compare(args, mu, scratch):
    """Runs ccx and csim alternately args.runs times on the problem with friction coefficient mu and
    prints its table."""
    deck = calculix_deck(args.divisions, args.element, args.penalty,
                         args.minimum_increment if args.automatic else None, mu)
    ccx_walls, csim_walls, csim_inner, ccx_cpus, csim_cpus = [], [], [], [], []
    for run in range(args.runs):  # alternate, so that the machine's load falls on both alike
        ccx_dir, csim_dir = (os.path.join(scratch, f"{name}-mu{mu:g}-{run}") for name in ("ccx", "csim"))
        os.makedirs(ccx_dir)
        wall, cpu, ccx_t, ccx_x, stopped, increments = run_calculix(args.ccx, deck, ccx_dir)
        ccx_walls.append(wall)
        ccx_cpus.append(cpu)
        wall, cpu, checks, inner, steps = run_csim(args.csim, args.divisions, mu, csim_dir)
        csim_walls.append(wall)
        csim_cpus.append(cpu)
        csim_inner.append(inner)
        print(f"mu = {mu:g}, run {run + 1}: ccx {ccx_walls[-1]:.3f} s, csim {csim_walls[-1]:.3f} s", flush=True)
    if args.keep:
        target = os.path.join(args.keep, f"mu{mu:g}")
        shutil.copytree(ccx_dir, os.path.join(target, "ccx"), dirs_exist_ok=True)
        shutil.copytree(csim_dir, os.path.join(target, "csim"), dirs_exist_ok=True)
    extrema = turning_points(ccx_t, ccx_x)
    ccx_cells = " | ".join(f"{v:.4f} at {t:.3f}" for t, v in extrema) if not stopped else f"{stopped} | "
    print(f"\nmu = {mu:g}: {args.divisions} x {args.divisions} quadrilaterals, 0 to {END:g} s, {args.runs} "
          f"alternating runs, wall time median (min–max)\n")
    print("| program | steps | wall time (s) | CPU time (s) | x1 (m) at t (s) | x2 (m) at t (s) |")
    print("|---|---|---|---|---|---|")
    print(f"| CalculiX 2.20 (ccx, 1 thread) | {increments} | {spread(ccx_walls)} | {spread(ccx_cpus)} | {ccx_cells} |")
    print(f"| csim (process) | {steps} | {spread(csim_walls)} | {spread(csim_cpus)} | "
          + " | ".join(f"{checks[n]['value']:.4f} at {checks[n]['time']:.3f}" for n in ("x1", "x2")) + " |")
    print(f"| csim (its summary's wall_time) | | {spread(csim_inner)} | | | |")
    print(f"| ramped rigid shoe (exact) | | | | {checks['x1']['reference']:.4f} | {checks['x2']['reference']:.4f} |")
    for what, ccx_times, csim_times in (("wall", ccx_walls, csim_walls), ("CPU", ccx_cpus, csim_cpus)):
        ratios = [a / b for a, b in zip(ccx_times, csim_times)]
        print(f"\nccx / csim {what} time, run by run: {', '.join(f'{r:.0f}' for r in ratios)}"
              + (" (ccx stopped early: no ratio for the whole run)" if stopped else
                 f"; ratio of the medians {statistics.median(ccx_times) / statistics.median(csim_times):.0f}"))


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("csim")
    parser.add_argument("--ccx", default="ccx")
    parser.add_argument("--divisions", type=int, default=40)
    parser.add_argument("--runs", type=int, default=3)
    parser.add_argument("--mu", type=float, nargs="+", default=[MU, 0.0],
                        help="friction coefficients to compare at (the scene's 0.3, and 0)")
    parser.add_argument("--penalty", type=float, default=10 * YOUNG, help="ccx's normal penalty slope (Pa/m)")
    parser.add_argument("--element", choices=["CPE4", "C3D8"], default="CPE4",
                        help="ccx's element: CPE4, or a C3D8 layer with uz = 0 (needed by --automatic)")
    parser.add_argument("--automatic", action="store_true", help="ccx's automatic incrementation, not DIRECT")
    parser.add_argument("--minimum-increment", type=float, default=1e-5,
                        help="ccx's smallest increment (s) under --automatic")
    parser.add_argument("--keep", help="a directory to keep the last run's files of each program in")
    args = parser.parse_args()
    if shutil.which(args.ccx) is None:
        raise SystemExit(f"{args.ccx} not found: apt-get install -y calculix-ccx")
    banner = subprocess.run([args.ccx, "-v"], capture_output=True, text=True).stdout.strip()
    print(f"{banner}; {args.element}, penalty {args.penalty:g} Pa/m, stick slope {args.penalty * STICK_FRACTION:g} Pa/m, "
          + (f"automatic increments from {STEP:g} s" if args.automatic else f"fixed increments (DIRECT) of {STEP:g} s"))
    with tempfile.TemporaryDirectory() as scratch:
        for mu in args.mu:
            compare(args, mu, scratch)


if __name__ == "__main__":
    main()
