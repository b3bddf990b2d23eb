#!/usr/bin/env python3
"""Combines runs of bench_siconos (its markdown output, one file a run) into one table.

    bench/siconos_rounds.py --after A1.md A2.md A3.md [--before B1.md B2.md B3.md]

For each problem in every run: csim's and NSGS's time, the median of the runs' medians, ± half the range
of those medians (relative); and csim/NSGS, the median of the runs' ratios with their range. With
--before (runs of another build, alternated with the --after ones on the same machine), a column of its
ratios beside. Timed-out or failed rows (no number in a time column) are left out of that problem's
medians. Why several runs: on a shared machine a run's repeats share its load; the runs, alternated
between the two builds, spread it across both (docs/contact-problems.md).
"""
import argparse
import statistics


def read_run(path):
    """problem -> (csim seconds, NSGS seconds) from one bench_siconos output."""
    rows = {}
    with open(path) as run:
        for line in run:
            cells = [cell.strip() for cell in line.strip().strip("|").split("|")]
            if len(cells) != 12 or cells[0] in ("problem", "---"):
                continue
            try:
                rows[cells[0]] = (float(cells[5].split()[0]), float(cells[8].split()[0]))
            except ValueError:
                continue
    return rows


def spread(values):
    middle = statistics.median(values)
    half_range = (max(values) - min(values)) / 2
    return middle, (100.0 * half_range / middle if middle > 0 else 0.0)


def ratios(runs, problem):
    return [run[problem][0] / run[problem][1] for run in runs if problem in run and run[problem][1] > 0]


def ratio_text(values):
    if not values:
        return "–"
    def number(value):
        return f"{value:.2f}" if value >= 0.1 else f"{value:.2g}"
    return f"{number(statistics.median(values))} [{number(min(values))}, {number(max(values))}]"


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--after", nargs="+", required=True)
    parser.add_argument("--before", nargs="*", default=[])
    arguments = parser.parse_args()
    after = [read_run(path) for path in arguments.after]
    before = [read_run(path) for path in arguments.before]
    problems = sorted(set().union(*after))
    header = "| problem | csim s | NSGS s | csim/NSGS |"
    rule = "|---|---|---|---|"
    if before:
        header = "| problem | csim s | NSGS s | csim/NSGS before | csim/NSGS |"
        rule = "|---|---|---|---|---|"
    print(header)
    print(rule)
    for problem in problems:
        csim, csim_spread = spread([run[problem][0] for run in after if problem in run])
        nsgs, nsgs_spread = spread([run[problem][1] for run in after if problem in run])
        cells = [problem, f"{csim:.3g} ±{csim_spread:.0f}%", f"{nsgs:.3g} ±{nsgs_spread:.0f}%"]
        if before:
            cells.append(ratio_text(ratios(before, problem)))
        cells.append(ratio_text(ratios(after, problem)))
        print("| " + " | ".join(cells) + " |")


if __name__ == "__main__":
    main()
