"""Runs of the rolling-ring scenes for the bench scripts, through `csim sweep` (the study runner: under
mpirun when --ranks > 0, docs/scaling-out.md): the cases of one scene go out as one sweep, each case writes
its run into its own folder, and the summary's spins, cost and contact-solver counts are read back. Also the
options every script takes."""
import argparse
import csv
import json
import os
import subprocess
import tempfile
import time


def summary_result(summary, wall=None):
    """The free-rolling spin of the last window and of the one before, the wall time, steps, Newton
    iterations (total and most in a step) and the contact solves (all, over tolerance, largest residual)
    of a run's summary.json; or {"error": ...} when a spin was not evaluated."""
    wall = summary["wall_time"] if wall is None else wall
    checks = {c["name"]: c for c in summary["checks"]}
    for name in ("free_rolling_spin", "free_rolling_spin_earlier"):
        if not checks[name]["evaluated"]:
            return {"error": f"{name}: {checks[name]['note']}", "wall": wall}
    solver = summary["contact_solver"]
    return {"spin": checks["free_rolling_spin"]["value"], "earlier": checks["free_rolling_spin_earlier"]["value"],
            "wall": summary["wall_time"], "steps": summary["steps"],
            "newton": summary["newton"]["iterations"], "newton_max": summary["newton"]["max_per_step"],
            "solves": solver["solves"], "unconverged": solver["not_converged"], "residual": solver["max_residual"]}


def yaml_text(text):
    return '"' + text.replace("\\", "\\\\").replace('"', '\\"') + '"'


def sweep(args, scene, cases, read):
    """Runs `scene` once per case (a list of KEY=VALUE overrides) with `csim sweep`, args.ranks ranks at a
    time (0: serially, without mpirun), and returns [read(folder, row) per case], in case order: folder is
    the case's output folder (absent when its run wrote nothing), row its line of sweep.csv (a dict)."""
    with tempfile.TemporaryDirectory() as work:
        cases_file = os.path.join(work, "cases.yaml")
        with open(cases_file, "w") as f:
            f.write("cases:\n")
            for case in cases:
                f.write("  - [" + ", ".join(yaml_text(setting) for setting in case) + "]\n")
        out = os.path.join(work, "out")
        command = [args.csim, "sweep", scene, "--sweeps", cases_file, "--out", out]
        if args.ranks > 0:
            command = [args.mpirun, "-np", str(args.ranks), "--bind-to", "core"] + command
        env = dict(os.environ, OMPI_ALLOW_RUN_AS_ROOT="1", OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1")
        process = subprocess.run(command, capture_output=True, text=True, env=env)
        table = os.path.join(out, "sweep.csv")
        if process.returncode not in (0, 1) or not os.path.exists(table):
            raise RuntimeError(f"{' '.join(command)}: exit {process.returncode}: {process.stderr.strip()}")
        with open(table) as f:
            rows = list(csv.DictReader(line for line in f if not line.startswith("#")))
        return [read(os.path.join(out, f"case-{int(row['case']):04d}"), row) for row in rows]


def read_rolling(folder, row):
    """summary_result of a case of a sweep, or its error (the row's message) when it wrote no summary."""
    summary_file = os.path.join(folder, "summary.json")
    if not os.path.exists(summary_file):
        return {"error": row["message"] or row["status"], "wall": float(row["wall_time"] or 0)}
    return summary_result(json.load(open(summary_file)))


def rolling_runs(args, scene, cases):
    """The result of summary_result for each case (a list of KEY=VALUE overrides) of `scene`."""
    return sweep(args, scene, cases, read_rolling)


def rolling_run(command):
    """Runs `command` (a `csim run` line, without --out) on its own and returns summary_result of its run, or
    {"error": the last line of csim's message, "wall": ...} when the run wrote no summary. For the scripts
    that have not moved to sweep() (rolling_bulk, rolling_inertia, rolling_speed)."""
    with tempfile.TemporaryDirectory() as out:
        start = time.perf_counter()
        process = subprocess.run(command + ["--out", out], capture_output=True, text=True)
        wall = time.perf_counter() - start
        summary_file = os.path.join(out, "summary.json")
        if not os.path.exists(summary_file):
            return {"error": (process.stderr or process.stdout).strip().splitlines()[-1], "wall": wall}
        return summary_result(json.load(open(summary_file)))


def bench_arguments():
    """The options of every table script: the csim binary, the document written, the MPI ranks."""
    parser = argparse.ArgumentParser()
    parser.add_argument("--csim", default="build/tools/csim")
    parser.add_argument("--out", default="docs/rolling.md")
    parser.add_argument("--ranks", type=int, default=os.cpu_count() or 1,
                        help="MPI ranks, one per core (default: every core); 0: serially, without mpirun")
    parser.add_argument("--mpirun", default="mpirun")
    parser.add_argument("--jobs", type=int, default=2, help="runs at a time (the scripts still on rolling_run)")
    return parser
