#!/usr/bin/env python3
"""bench/rolling_table.py run on one row and one configuration (--rows, --configs, --no-studies) rewrites
those cells alone: every other cell of docs/rolling.md's generated block, the other configurations'
columns and the sensitivity table included, stays as it was. Usage: rolling_table_subset_test.py CSIM."""
import os
import shutil
import subprocess
import sys
import tempfile

ROOT = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..")
BEGIN, END = "<!-- generated: begin -->", "<!-- generated: end -->"


def block(path):
    return open(path).read().split(BEGIN, 1)[1].split(END, 1)[0].split("\n")


def main():
    csim = sys.argv[1]
    with tempfile.TemporaryDirectory() as folder:
        out = os.path.join(folder, "rolling.md")
        shutil.copy(os.path.join(ROOT, "docs", "rolling.md"), out)
        before = block(out)
        subprocess.run([sys.executable, os.path.join(ROOT, "bench", "rolling_table.py"), "--csim", csim, "--out", out,
                        "--rows", "2", "--configs", "1", "--no-studies", "--ranks", "0"],
                       cwd=ROOT, check=True, stdout=subprocess.DEVNULL)
        after = block(out)
    failures = []
    if len(before) != len(after):
        failures.append(f"the block has {len(after)} lines, {len(before)} before")
    changed = [(b, a) for b, a in zip(before, after) if b != a]
    # The first line says what this run made; the row run (Mooney–Rivlin δ 0.05, r_i 1, μ 0.02) may
    # change in its first configuration's cells only, which the cost table's wall time does.
    for b, a in changed[1:]:
        cells_b, cells_a = b.split("|"), a.split("|")
        if not b.startswith("| mooney-rivlin | 0.05 | 1 | 0.02 |") or len(cells_b) != len(cells_a):
            failures.append(f"changed: {b!r} -> {a!r}")
            continue
        first = 5 if " s, " in cells_b[5] else 7  # the cost table's first configuration, or the spin table's
        differing = [k for k, (x, y) in enumerate(zip(cells_b, cells_a)) if x != y]
        if any(k != first for k in differing):
            failures.append(f"cells other than the run's changed: {b!r} -> {a!r}")
    if not changed or "This run: q4 34×5 nodes on 1 of the rows" not in changed[0][1]:
        failures.append("the first line does not say what this run made")
    for failure in failures:
        print(failure)
    print(f"{0 if failures else 1} passed, {1 if failures else 0} failed")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
