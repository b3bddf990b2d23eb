#!/usr/bin/env python3
"""Mesh convergence of the free-rolling table (scenes/rolling-ring): every row of Table 2 on three quad4
meshes with node contact, 68 x 10 (the scene's default), 136 x 20 and 204 x 30, and from the three an
estimate of the mesh-converged spin and of its uncertainty.

With h the element size (1 / divisions) and phi = phi_0 + C h^p through the three meshes:
  - monotone convergence with an observed order p within a factor 2 of the formal order P_FORMAL:
    Richardson's extrapolation phi_0 and the fine mesh's grid convergence index
    GCI = 1.25 |phi_1 - phi_2| / (r^p - 1) / |phi_1| (Celik et al., "Procedure for estimation and
    reporting of uncertainty due to discretization in CFD applications", J. Fluids Eng. 130 (2008)
    078001);
  - monotone, with an order outside that band (not yet in the asymptotic range): the finest value, with
    Roache's fallback, the GCI of the two finest meshes with the formal order and a safety factor 3
    (Roache, Verification and Validation in Computational Science and Engineering, 1998);
  - oscillatory (differences of opposite signs): the finest value, with half the range of the three
    (Stern et al., J. Fluids Eng. 123 (2001) 793).
The formal order is 1: node-to-surface contact puts the ends of the contact patch and of its stick zone
at nodes, O(h) from where the continuum has them. Writes the block between the "generated convergence"
markers of docs/rolling.md; --results keeps the runs in a JSON file, read back instead of running when
it exists (to re-render the block). Usage:
    python3 bench/rolling_convergence.py [--csim build/tools/csim] [--out docs/rolling.md] [--ranks N]
                                         [--results runs.json]
"""
import json
import os
import sys

from generated_block import replace_block
from rolling_run import bench_arguments
from rolling_table import ROWS, cost_table, percent, runs

# Coarse to fine; every mesh keeps the benchmark's aspect (34 x 5), so h scales with 1 / divisions.
MESHES = [
    ("q4 68×10", "quad4", 68, 10, "nodes"),
    ("q4 136×20", "quad4", 136, 20, "nodes"),
    ("q4 204×30", "quad4", 204, 30, "nodes"),
]
P_FORMAL = 1.0
SAFETY, SAFETY_FALLBACK = 1.25, 3.0
BEGIN, END = "<!-- generated convergence: begin -->", "<!-- generated convergence: end -->"


def difference_ratio(p, r21, r32):
    """(phi_3 - phi_2) / (phi_2 - phi_1) for phi = phi_0 + C h^p, with h_2 = r21 h_1, h_3 = r32 h_2
    (mesh 1 the finest). Increasing in p, from ln r32 / ln r21 at p -> 0."""
    return r21 ** p * (r32 ** p - 1.0) / (r21 ** p - 1.0)


def observed_order(ratio, r21, r32, low=1e-6, high=20.0):
    """The p > 0 with difference_ratio(p) = ratio, or None when there is none in (low, high)."""
    if not difference_ratio(low, r21, r32) < ratio < difference_ratio(high, r21, r32):
        return None
    for _ in range(200):  # bisection: the ratio is monotone in p
        p = 0.5 * (low + high)
        low, high = (p, high) if difference_ratio(p, r21, r32) < ratio else (low, p)
    return 0.5 * (low + high)


def richardson(coarse, medium, fine, r21, r32):
    """Estimate of the converged value from three values, coarse to fine: {"how", "order" (observed, or
    None), "value", "uncertainty" (a fraction of |value|)}."""
    e21, e32 = medium - fine, coarse - medium
    if e21 * e32 < 0.0:
        half_range = 0.5 * (max(coarse, medium, fine) - min(coarse, medium, fine))
        return {"how": "oscillatory", "order": None, "value": fine, "uncertainty": half_range / abs(fine)}
    p = observed_order(e32 / e21, r21, r32) if e21 != 0.0 else None
    if p is not None and 0.5 * P_FORMAL <= p <= 2.0 * P_FORMAL:
        extrapolated = (r21 ** p * fine - medium) / (r21 ** p - 1.0)
        gci = SAFETY * abs(e21 / fine) / (r21 ** p - 1.0)
        return {"how": "Richardson", "order": p, "value": extrapolated, "uncertainty": gci}
    gci = SAFETY_FALLBACK * abs(e21 / fine) / (r21 ** P_FORMAL - 1.0)
    return {"how": "finest, F_s 3", "order": p, "value": fine, "uncertainty": gci}


def target(r_i):
    """Issue 5's target, % from Faria: 0.5 for r_i 0.2 and 1.0, 3 for the thin ring."""
    return 3.0 if r_i > 1.5 else 0.5


def verdict(low, high, bound):
    if -bound <= low and high <= bound:
        return "inside"
    if high < -bound or low > bound:
        return "outside"
    return "straddles"


def main():
    parser = bench_arguments()
    parser.add_argument("--results", default="")
    args = parser.parse_args()
    if args.results and os.path.exists(args.results):
        results = list(zip(ROWS, json.load(open(args.results))))
    else:
        # One sweep, the finest meshes first: the runner hands the cases out in order, so that the long
        # runs do not wait at the end for a free rank.
        order = [(i, m) for m in reversed(range(len(MESHES))) for i in range(len(ROWS))]
        done = dict(zip(order, runs(args, [(ROWS[i], MESHES[m], []) for i, m in order])))
        results = []
        for i, row in enumerate(ROWS):
            results.append((row, [done[(i, m)] for m in range(len(MESHES))]))
            print(row[:4], [r.get("spin", "failed") for r in results[-1][1]], file=sys.stderr, flush=True)
        if args.results:
            json.dump([result for _, result in results], open(args.results, "w"), indent=1)

    r21 = MESHES[2][2] / MESHES[1][2]
    r32 = MESHES[1][2] / MESHES[0][2]
    lines = [f"Generated by `python3 bench/rolling_convergence.py` (node contact; `csim sweep` on {args.ranks or 1} MPI "
             f"rank(s), one per core, on {os.cpu_count()} cores; wall times are per run). Free spin (err % from Faria) on three "
             f"meshes; the observed order p; the estimated mesh-converged spin (err % from Faria) ± its "
             f"uncertainty, and how it was estimated (see the script's header); against the target:\n"]
    lines.append("| material | δ | r_i | μ | Faria | Abaqus (err %) | " + " | ".join(m[0] for m in MESHES) +
                 " | p | converged (err %) | ± | estimate | target |")
    lines.append("|" + "---|" * (11 + len(MESHES)))
    for row, result in results:
        material, delta, r_i, mu, faria, abaqus, abaqus_diff = row
        cells = [material, f"{delta:g}", f"{r_i:g}", f"{mu:g}", f"{faria:.5f}", f"{abaqus:.5f} ({abaqus_diff:.2f})"]
        cells += [f"{r['spin']:.5f} ({percent(r['spin'], faria):+.2f})" if "spin" in r else f"failed: `{r['error']}`"
                  for r in result]
        if not all("spin" in r for r in result):
            lines.append("| " + " | ".join(cells + ["–"] * 5) + " |")
            continue
        fit = richardson(*(r["spin"] for r in result), r21, r32)
        error = percent(fit["value"], faria)
        spread = 100.0 * fit["uncertainty"] * abs(fit["value"]) / faria
        cells += [f"{fit['order']:.2f}" if fit["order"] is not None else "–",
                  f"{fit['value']:.5f} ({error:+.2f})", f"{spread:.2f} %", fit["how"],
                  f"{verdict(error - spread, error + spread, target(r_i))} ±{target(r_i):g} %"]
        lines.append("| " + " | ".join(cells) + " |")
    lines.append("")
    lines += cost_table(results, [m[0] for m in MESHES])
    replace_block(args.out, BEGIN, END, lines)
    print("\n".join(lines))


if __name__ == "__main__":
    main()
