#!/usr/bin/env python3
"""Writes scenes/sphere-drop/scene.yaml: N rigid spheres dropped into a box (a floor and four walls).

The spheres (radius 0.05 m) start on a grid of ceil(cbrt(N)) a side at a spacing of 2.5 radii, the
lowest layer 0.0005 m above the floor, x varying fastest, then y, then the layer; each is moved across
by up to 0.2 radii in x and y, drawn from Python's seeded Mersenne Twister (random.Random(seed)), so
that the columns topple into a pile, while neighbours stay at least 2.1 radii apart (no overlap at the
start). The walls' inner faces are half a spacing from the outer grid lines. This is the layout of
bench/bench_drop.cpp; its draws are not the same numbers (std::mt19937 there).

One entry a body, every sphere in the group `spheres`, two contact laws by group, and checks of the
pile at rest at time.end (static equilibrium of the whole pile, kinetic energy, the energy balance)
that hold for any N once the pile rests. Standard library only, so that a test can rerun it
(tests/scenes/generated_scene_test.py reruns the command written at the top of scene.yaml).

A contact solve of a pile settling against the walls can stall just above the tolerance (1e-6), the
stall of hyperstatic frictional piles that issue 54 keeps open: 24 spheres, seed 1, leave 2 of 2993
solves at 1.2e-6, and 27 spheres, seed 1, 3 of 2993 at up to 3.6e-6, even after their restarts from zero
(engine/contact_stage/contact_solve.h). So a generated scene stops a run only above 1e-5 (failure_residual), and
every solve left above 1e-6 is counted in summary.json (contact_solver.not_converged; none in the
committed scene).

  python3 scenes/sphere-drop/generate.py [--count N] [--seed S] [--mu MU] [--end T] [--shapes] [--out FILE]
"""
import argparse
import math
import os
import random
import sys

RADIUS = 0.05           # m
SPACING = 2.5 * RADIUS  # m, between grid lines
JITTER = 0.2 * RADIUS   # m, the largest move across
LIFT = 1.01             # the lowest layer's centres at LIFT radii


def number(x):
    """The shortest text of x rounded to the micrometre (-0 written as 0)."""
    text = f"{x:.6f}".rstrip("0").rstrip(".")
    return "0" if text in ("-0", "") else text


def layout(count, seed):
    """The spheres' centres (m) and the walls' distance from the box's axis (m)."""
    per_side = 1
    while per_side ** 3 < count:
        per_side += 1
    half_width = 0.5 * per_side * SPACING
    draw = random.Random(seed)
    centres = []
    for k in range(count):
        i, j, layer = k % per_side, (k // per_side) % per_side, k // (per_side * per_side)
        x = (i + 0.5) * SPACING - half_width + JITTER * draw.uniform(-1.0, 1.0)
        y = (j + 0.5) * SPACING - half_width + JITTER * draw.uniform(-1.0, 1.0)
        z = LIFT * RADIUS + layer * SPACING
        centres.append((x, y, z))
    return centres, half_width


def command_line(args):
    words = ["python3", "scenes/sphere-drop/generate.py", "--count", str(args.count), "--seed",
             str(args.seed), "--mu", repr(args.mu), "--end", repr(args.end)]
    if args.shapes:
        words.append("--shapes")
    return " ".join(words)


def scene_text(args):
    centres, half_width = layout(args.count, args.seed)
    n = args.count
    lines = [
        "# Written by generate.py (beside this file): do not edit, regenerate with",
        "#   " + command_line(args),
        "# (tests/scenes: scene.sphere-drop-generator checks that this file is what that command writes).",
        "description: >",
        f"  {n} rigid spheres of radius {number(RADIUS)} m dropped from a jittered grid into a box (a floor and",
        "  four walls: one fixed body) come to rest as a pile, friction mu on every contact. At rest the",
        "  pile is in static equilibrium: the box's contact forces on the spheres (floor and walls, normal",
        "  and friction) add up to the pile's weight, N m g, vertically, however the hyperstatic contact",
        "  set shares it out. The contacts between spheres cancel in that sum (action and reaction).",
        "",
        "dimension: 3",
        "",
        "parameters:",
        "  mass: 1           # kg, each sphere",
        f"  mu: {args.mu!r}",
        "  gravity: 9.81     # m/s2",
        "",
        "gravity: [0, 0, =-gravity]",
        "",
        "bodies:",
    ]
    for k, (x, y, z) in enumerate(centres):
        lines.append(f"  s{k}: {{type: rigid, mass: =mass, position: [{number(x)}, {number(y)}, {number(z)}], "
                     f"shapes: {{ball: {{type: sphere, radius: {number(RADIUS)}}}}}, group: spheres}}")
    w = number(-half_width)
    lines += [
        "  box:",
        "    type: fixed",
        "    shapes:",
        "      floor: {type: halfspace, normal: [0, 0, 1], offset: 0}",
        f"      west: {{type: halfspace, normal: [1, 0, 0], offset: {w}}}",
        f"      east: {{type: halfspace, normal: [-1, 0, 0], offset: {w}}}",
        f"      south: {{type: halfspace, normal: [0, 1, 0], offset: {w}}}",
        f"      north: {{type: halfspace, normal: [0, -1, 0], offset: {w}}}",
        "",
        "contacts:",
        "  pile: {between: [spheres, spheres], mu: =mu}",
        "  in_box: {between: [box, spheres], mu: =mu}",
        "",
        f"time: {{end: {args.end!r}, step: 1e-3}}",
        "integrator: {type: moreau-jean, theta: 0.5}",
        "# A solve left above the tolerance is counted (summary.json contact_solver.not_converged); one left",
        "# above failure_residual stops the run (exit 2). See generate.py on the stall between the two.",
        "contact_solver: {tolerance: 1e-6, max_iterations: 20000, failure_residual: 1e-5}",
        "output: {rate: 0.01, paraview: " + ("binary, shapes: true" if args.shapes else "none") +
        ", bodies: true}",
        "",
        "probes:",
        "  # The box's contact forces on the spheres (floor and walls, normal and friction): the law's",
        "  # first body is the box, and a probe reads the force on it, so scale -1 gives the spheres' side.",
        "  lift: {contact_force: {contact: in_box, component: z, scale: -1}}",
        "  push_x: {contact_force: {contact: in_box, component: x, scale: -1}}",
        "  push_y: {contact_force: {contact: in_box, component: y, scale: -1}}",
        "  kinetic: {energy: kinetic}",
        "  balance: {energy: balance}",
        "",
        "# Read at time.end as written (at:, not final:, so that a shorter window leaves them unjudged).",
        "# The tolerances: the momentum balance of the whole pile over a step makes the box's resultant",
        "# minus the weight exactly sum(m dv)/h (the spheres' mutual impulses cancel in pairs), and at rest",
        "# dv is what the contact solver's relative tolerance (1e-6) leaves of the step's velocities, of",
        "# order g h: hence 1e-6 of the weight. At rest: the kinetic energy below that of every sphere at",
        "# 1 micrometre a second, m (1e-6)^2 / 2 a body. The discrete energy balance is an identity on the",
        "# impulses and velocities computed (contact_dissipation is formed from them), so it closes to the",
        "# round-off of its sums over the steps, about steps x 1e-16 x the work of gravity (1e-11 J here):",
        "# 1e-9 J leaves a factor of 100.",
        "checks:",
        "  box_carries_the_pile:",
        "    probe: lift",
        f"    at: {args.end!r}",
        f"    reference: ={n}*mass*gravity",
        "    tolerance: {relative: 1e-6}",
        "    kind: analytical",
        f"    source: \"static equilibrium of the {n} spheres: the box's vertical resultant on them is their weight, N m g\"",
        "  no_horizontal_resultant_x:",
        "    probe: push_x",
        f"    at: {args.end!r}",
        "    reference: 0",
        f"    tolerance: {{absolute: ={n}*mass*gravity*1e-6}}",
        "    kind: analytical",
        "    source: \"static equilibrium of the spheres: no horizontal load, so the walls' and floor's forces cancel\"",
        "  no_horizontal_resultant_y:",
        "    probe: push_y",
        f"    at: {args.end!r}",
        "    reference: 0",
        f"    tolerance: {{absolute: ={n}*mass*gravity*1e-6}}",
        "    kind: analytical",
        "    source: \"static equilibrium of the spheres: no horizontal load, so the walls' and floor's forces cancel\"",
        "  at_rest:",
        "    probe: kinetic",
        f"    at: {args.end!r}",
        "    reference: 0",
        f"    tolerance: {{absolute: ={n}*mass*0.5e-12}}",
        "    kind: analytical",
        "    source: \"a pile at rest: every sphere slower than 1e-6 m/s on average\"",
        "  balance_closes:",
        "    probe: balance",
        f"    at: {args.end!r}",
        "    reference: 0",
        "    tolerance: {absolute: 1e-9}",
        "    kind: analytical",
        "    source: \"discrete energy balance of the theta-method: kinetic - work of gravity + contact dissipation = 0\"",
    ]
    return "\n".join(lines) + "\n"


def main():
    here = os.path.dirname(os.path.abspath(__file__))
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--count", type=int, default=125, help="spheres (default 125)")
    parser.add_argument("--seed", type=int, default=1, help="the jitter's seed (default 1)")
    parser.add_argument("--mu", type=float, default=0.5, help="Coulomb friction on every contact (default 0.5)")
    parser.add_argument("--end", type=float, default=3.0, help="time.end, s (default 3)")
    parser.add_argument("--shapes", action="store_true", help="write ParaView shapes (output.shapes: true)")
    parser.add_argument("--out", default=os.path.join(here, "scene.yaml"), help="default: scene.yaml beside this script")
    args = parser.parse_args()
    if args.count < 1:
        parser.error("--count must be at least 1")
    if not (args.end > 0 and math.isfinite(args.end)):
        parser.error("--end must be a finite time > 0 (s)")
    if not (args.mu >= 0 and math.isfinite(args.mu)):
        parser.error("--mu must be a finite number >= 0")
    with open(args.out, "w", encoding="utf-8") as f:
        f.write(scene_text(args))
    return 0


if __name__ == "__main__":
    sys.exit(main())
