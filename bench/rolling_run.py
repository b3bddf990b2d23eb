"""One run of a rolling-ring scene for the bench scripts: csim writes into a temporary folder, and the
summary's spins, cost and contact-solver counts are read back. Also the options every script takes."""
import argparse
import json
import os
import subprocess
import tempfile
import time


def rolling_run(command):
    """Runs `command` (a `csim run` line, without --out) and returns the free-rolling spin of the last
    window and of the one before, the wall time, steps, Newton iterations (total and most in a step)
    and the contact solves (all, over tolerance, largest residual); or {"error": the last line of
    csim's message, "wall": ...} when the run wrote no summary."""
    with tempfile.TemporaryDirectory() as out:
        start = time.perf_counter()
        process = subprocess.run(command + ["--out", out], capture_output=True, text=True)
        wall = time.perf_counter() - start
        summary_file = os.path.join(out, "summary.json")
        if not os.path.exists(summary_file):
            return {"error": (process.stderr or process.stdout).strip().splitlines()[-1], "wall": wall}
        summary = json.load(open(summary_file))
    checks = {c["name"]: c for c in summary["checks"]}
    for name in ("free_rolling_spin", "free_rolling_spin_earlier"):
        if not checks[name]["evaluated"]:
            return {"error": f"{name}: {checks[name]['note']}", "wall": wall}
    solver = summary["contact_solver"]
    return {"spin": checks["free_rolling_spin"]["value"], "earlier": checks["free_rolling_spin_earlier"]["value"],
            "wall": summary["wall_time"], "steps": summary["steps"],
            "newton": summary["newton"]["iterations"], "newton_max": summary["newton"]["max_per_step"],
            "solves": solver["solves"], "unconverged": solver["not_converged"], "residual": solver["max_residual"]}


def bench_arguments():
    """The options of every table script: the csim binary, the document written, runs at a time."""
    parser = argparse.ArgumentParser()
    parser.add_argument("--csim", default="build/tools/csim")
    parser.add_argument("--out", default="docs/rolling.md")
    parser.add_argument("--jobs", type=int, default=2)
    return parser
