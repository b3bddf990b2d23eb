#!/usr/bin/env python3
"""Runs scenes/rolling-ring on every row of the Abaqus/Faria free-rolling table and writes docs/rolling.md.

Reference values: Abaqus Benchmarks Manual 6.6, section 1.5.1, Table 2 (seeds/SPEC.md section 3.7),
Faria's values from L. O. Faria, Tire Modeling by Finite Elements, PhD thesis, UT Austin, 1989.
Each row runs on the benchmark's meshes (34 x 5 quad4, 18 x 3 quad8) and on meshes twice as fine in
both directions (the mesh-convergence columns), with node and smoothed contact on quad4, and on quad4
four times as fine (136 x 20) with node contact. Every run is a case of one `csim sweep` (under
`mpirun -np RANKS --bind-to core`, docs/scaling-out.md). The script
replaces only the block between the generated markers of docs/rolling.md; a run of some --rows or
--configs keeps the block's other cells as they were (and says so in its first line). Usage:
    python3 bench/rolling_table.py [--csim build/tools/csim] [--out docs/rolling.md] [--rows 1,5,...]
                                   [--configs 1,3,...] [--no-studies] [--ranks N]
"""
import os
import sys
import time

from generated_block import replace_block
from rolling_run import bench_arguments, rolling_run, rolling_runs

# material, indentation, inner radius, mu, Faria, Abaqus, Abaqus's % difference (Table 2)
ROWS = [
    ("mooney-rivlin", 0.05, 0.2, 0.02, 0.99349, 0.99219, 0.13),
    ("mooney-rivlin", 0.05, 1.0, 0.02, 0.97977, 0.98053, 0.08),
    ("mooney-rivlin", 0.05, 1.7, 0.02, 0.87183, 0.84974, 2.53),
    ("mooney-rivlin", 0.05, 1.0, 0.20, 0.98066, 0.98212, 0.15),
    ("mooney-rivlin", 0.10, 0.2, 0.02, 0.98558, 0.98422, 0.14),
    ("mooney-rivlin", 0.10, 1.0, 0.02, 0.95009, 0.95059, 0.05),
    ("mooney-rivlin", 0.10, 1.7, 0.02, 0.73057, 0.65790, 9.95),
    ("mooney-rivlin", 0.10, 1.0, 0.20, 0.95195, 0.95100, 0.10),
    ("linear-elastic", 0.05, 0.2, 0.02, 1.02180, 1.02332, 0.15),
    ("linear-elastic", 0.05, 1.0, 0.02, 1.02415, 1.02574, 0.16),
    ("linear-elastic", 0.05, 1.7, 0.02, 1.00297, 1.00263, 0.03),
    ("linear-elastic", 0.10, 0.2, 0.02, 1.02970, 1.03410, 0.43),
    ("linear-elastic", 0.10, 1.0, 0.02, 1.02810, 1.02872, 0.06),
    ("linear-elastic", 0.10, 1.7, 0.02, 0.99156, 0.99542, 0.39),
]
# Configurations: element, divisions (circumferential x radial), contact surface. 34 x 5 quad4 and
# 18 x 3 quad8 are the benchmark's meshes; the others are twice as fine (the mesh-convergence columns),
# and quad4 four times as fine with node contact (the third mesh of the convergence study).
CONFIGS = [
    ("q4 34×5 nodes", "quad4", 34, 5, "nodes"),
    ("q4 34×5 smoothed", "quad4", 34, 5, "smoothed"),
    ("q4 68×10 nodes", "quad4", 68, 10, "nodes"),
    ("q4 68×10 smoothed", "quad4", 68, 10, "smoothed"),
    ("q8 18×3 nodes", "quad8", 18, 3, "nodes"),
    ("q8 36×6 nodes", "quad8", 36, 6, "nodes"),
    ("q4 136×20 nodes", "quad4", 136, 20, "nodes"),
]
# Sensitivity of one Mooney-Rivlin and one elastic row (q4 34 x 5, node contact): pseudo-time step
# (the quasi-static run has no inertia; the step only resolves the loading path), incompressibility,
# finite-strain law.
STUDIES = [
    (ROWS[5], "step 0.02", ["--set", "parameters.step=0.02"]),
    (ROWS[5], "step 0.01 (default)", []),
    (ROWS[5], "step 0.005", ["--set", "parameters.step=0.005"]),
    (ROWS[5], "K / mu0 = 100", ["--set", "parameters.bulk_ratio=100"]),
    (ROWS[5], "K / mu0 = 1000 (default)", []),
    (ROWS[5], "K / mu0 = 10000", ["--set", "parameters.bulk_ratio=10000"]),
    (ROWS[12], "neo-Hookean (default)", []),
    (ROWS[12], "St Venant-Kirchhoff", ["--set", "parameters.elastic_law=saint-venant-kirchhoff"]),
    (ROWS[12], "step 0.005", ["--set", "parameters.step=0.005"]),
]
def settings(row, config):
    """The overrides of scenes/rolling-ring for one row of the table on one configuration."""
    material, delta, r_i, mu, faria = row[:5]
    _, element, circumferential, radial, surface = config
    return [f"parameters.material={material}", f"parameters.indentation={delta}",
            f"parameters.inner_radius={r_i}", f"parameters.mu={mu}", f"parameters.reference_spin={faria}",
            f"parameters.element={element}", f"parameters.divisions_circumferential={circumferential}",
            f"parameters.divisions_radial={radial}", f"parameters.contact_surface={surface}"]


def scene_command(csim, row, config):
    """csim's `run` line for one row on one configuration (without --out), for rolling_bulk.py."""
    return [csim, "run", "scenes/rolling-ring", "--quiet"] + [w for s in settings(row, config) for w in ("--set", s)]


def run(csim, row, config, extra):
    return rolling_run(scene_command(csim, row, config) + extra)


def extra_settings(extra):
    """["--set", "K=V", ...] as ["K=V", ...]."""
    return [item for item in extra if item != "--set"]


def runs(args, jobs):
    """rolling_runs of scenes/rolling-ring for (row, config, extra) jobs, in order."""
    return rolling_runs(args, "scenes/rolling-ring",
                        [settings(row, config) + extra_settings(extra) for row, config, extra in jobs])


def percent(value, reference):
    return 100.0 * (value - reference) / reference


def locked(result):
    """Whether a run's ring slid without rolling: its hub did not turn (a rolling ring's spin is 0.6-1.1)."""
    return "spin" in result and abs(result["spin"]) < 1e-3


def spin_cell(result, faria):
    if "spin" not in result:
        return "failed¹"
    if locked(result):
        return "locked²"
    return f"{result['spin']:.5f} ({percent(result['spin'], faria):+.2f})"


def cost_cell(r):
    """Steadiness, wall time and Newton iterations of one run."""
    if "spin" not in r:
        return f"failed, {r['wall']:.1f} s"
    return f"{abs(r['spin'] - r['earlier']):.0e}, {r['wall']:.1f} s, {r['newton']} ({r['newton_max']})"


def cost_table(results, labels, heading_end=""):
    """The lines of the table of steadiness, wall time and Newton iterations: one line per (row, runs),
    one column per label; a run is a result (cost_cell) or a cell already written."""
    lines = ["Steadiness (the change of the spin from the window before the last), wall time (s) and Newton "
             f"iterations (total, and the most in one step){heading_end}:\n",
             "| material | δ | r_i | μ | " + " | ".join(labels) + " |",
             "|" + "---|" * (4 + len(labels))]
    for row, result in results:
        cells = [row[0], f"{row[1]:g}", f"{row[2]:g}", f"{row[3]:g}"]
        cells += [r if isinstance(r, str) else cost_cell(r) for r in result]
        lines.append("| " + " | ".join(cells) + " |")
    return lines


BEGIN, END = "<!-- generated: begin -->", "<!-- generated: end -->"


def kept_cells(path):
    """The cells of the block now in `path`, by table (0: spins, 1: costs), row (material, δ, r_i, μ as
    printed) and column heading, and the lines of its sensitivity table (key "studies"): what a run of
    some rows or configurations keeps of the others."""
    text = open(path).read()
    if BEGIN not in text or END not in text:
        return {}
    cells, table = {"studies": []}, -1
    for line in text.split(BEGIN, 1)[1].split(END, 1)[0].split("\n"):
        if line.startswith("| row | setting |"):
            table = 2
        elif table == 2 and line.startswith("| ") and not line.startswith("|---"):
            cells["studies"].append(line)
        elif line.startswith("| material |"):
            table += 1
            headings = [c.strip() for c in line.strip().strip("|").split("|")]
        elif line.startswith("| ") and table in (0, 1) and not line.startswith("|---"):
            values = [c.strip() for c in line.strip().strip("|").split("|")]
            for heading, value in zip(headings[4:], values[4:]):
                cells[(table, tuple(values[:4]), heading)] = value
    return cells


def main():
    parser = bench_arguments()
    parser.add_argument("--rows", default="")
    parser.add_argument("--configs", default="", help="1-based indices into CONFIGS (default: all)")
    parser.add_argument("--no-studies", action="store_true", help="leave out the sensitivity studies")
    args = parser.parse_args()
    rows = ROWS if not args.rows else [ROWS[int(i) - 1] for i in args.rows.split(",")]
    configs = CONFIGS if not args.configs else [CONFIGS[int(i) - 1] for i in args.configs.split(",")]
    studies = [] if args.no_studies else STUDIES
    jobs = [(row, config, []) for row in rows for config in configs]
    jobs += [(row, CONFIGS[0], extra) for row, _, extra in studies]
    start = time.perf_counter()
    done = runs(args, jobs)
    elapsed = time.perf_counter() - start
    results = [(row, done[i * len(configs):(i + 1) * len(configs)]) for i, row in enumerate(rows)]
    study_results = done[len(rows) * len(configs):]
    for row, result in results:
        print(row[:4], [r.get("spin", "failed") for r in result], file=sys.stderr, flush=True)
    print(f"{len(jobs)} runs in {elapsed:.1f} s on {args.ranks or 'no'} MPI ranks", file=sys.stderr)

    # A run of some rows or configurations keeps the other cells of the block as they were.
    kept = kept_cells(args.out) if (args.rows or args.configs or args.no_studies) else {}
    ran = {(row[:4], config[0]): r for row, result in results for config, r in zip(configs, result)}
    key = lambda row: (row[0], f"{row[1]:g}", f"{row[2]:g}", f"{row[3]:g}")
    shown = [c for c in CONFIGS if c in configs or any((0, key(row), f"{c[0]} (err %)") in kept for row in ROWS)]
    shown_rows = [row for row in ROWS if row in rows or any(k[1] == key(row) for k in kept if k != "studies")]

    def cell(table, row, config):
        if (row[:4], config[0]) in ran:
            r = ran[(row[:4], config[0])]
            return spin_cell(r, row[4]) if table == 0 else cost_cell(r)
        return kept.get((table, key(row), f"{config[0]} (err %)" if table == 0 else config[0]), "–")

    lines = []
    subset = ""
    if kept and (args.rows or args.configs):
        subset = (" This run: " + ", ".join(c[0] for c in configs) + (f" on {len(rows)} of the rows" if args.rows else "") +
                  "; the other cells are kept from the run before.")
    lines.append(f"Generated by `python3 bench/rolling_table.py` (`csim sweep` on {args.ranks or 1} MPI rank(s), one "
                 f"per core, on this machine's {os.cpu_count()} cores; wall times are per run).{subset}\n")
    lines.append("| material | δ | r_i | μ | Faria | Abaqus (err %) | " +
                 " | ".join(f"{c[0]} (err %)" for c in shown) + " |")
    lines.append("|" + "---|" * (6 + len(shown)))
    for row in shown_rows:
        material, delta, r_i, mu, faria, abaqus, abaqus_diff = row
        cells = [material, f"{delta:g}", f"{r_i:g}", f"{mu:g}", f"{faria:.5f}", f"{abaqus:.5f} ({abaqus_diff:.2f})"]
        cells += [cell(0, row, c) for c in shown]
        lines.append("| " + " | ".join(cells) + " |")
    lines.append("")
    if any("locked²" in line for line in lines):
        lines.append("² locked: the hub does not turn (|spin| < 1e-3 v/R); the ring slides without rolling "
                     "(\"Locked rows\" below).  ")
    failures = [(row, config, r["error"]) for row, result in results for config, r in zip(configs, result) if "error" in r]
    for row, config, error in failures:
        lines.append(f"¹ {row[0]} δ={row[1]:g} r_i={row[2]:g} μ={row[3]:g}, {config[0]}: `{error}`  ")
    lines.append("")
    lines += cost_table([(row, [cell(1, row, c) for c in shown]) for row in shown_rows], [c[0] for c in shown],
                        ", per configuration")
    lines.append("")
    lines.append("Sensitivity (q4 34×5 nodes):\n")
    lines.append("| row | setting | spin | change from the default |")
    lines.append("|---|---|---|---|")
    base = {row[:4]: r.get("spin") for (row, _, extra), r in zip(studies, study_results) if not extra}
    if not studies:
        lines += kept.get("studies", [])
    for (row, label, extra), r in zip(studies, study_results):
        name = f"{row[0]} δ={row[1]:g} r_i={row[2]:g} μ={row[3]:g}"
        value = f"{r['spin']:.5f}" if "spin" in r else "failed"
        reference = base.get(row[:4])
        change = f"{percent(r['spin'], reference):+.3f} %" if "spin" in r and reference else "–"
        lines.append(f"| {name} | {label} | {value} | {change} |")

    # Only the generated block is replaced: the text around it is written by hand.
    replace_block(args.out, BEGIN, END, lines)
    print("\n".join(lines))


if __name__ == "__main__":
    main()
