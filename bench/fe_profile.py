#!/usr/bin/env python3
"""Where the FE shoe's steady step spends its wall-clock time at 13 122 and 51 842 DOFs, function by
function (docs/solver-measurements.md, "The FE step against the mesh size"): sdnv104-quad4 at 80 and 160
divisions, each run for 200 and 1200 steps of 1e-3 s under `perf record -e cpu-clock` (a software clock:
no hardware counters needed, which this VM lacks); a function's time a step is the difference of its
samples over the two runs divided by 1000 steps, so that one-time work (factorization, the first Delassus
entries) cancels. The runs of one repeat alternate the sizes; each cell is the median over the repeats.
The last column is the 52k/13k ratio of a function, against 3.95 (the DOFs') and 4.85
(3.95^1.15, target 3).

usage: bench/fe_profile.py CSIM [REPEATS]   (needs perf: apt-get install linux-perf; CSIM with -g
       for readable names; ROWS=N in the environment lists N functions, 18 by default)
"""
import os
import re
import statistics
import subprocess
import sys
import tempfile

SCENE = os.path.join(os.path.dirname(os.path.abspath(__file__)), '..', 'scenes', 'sdnv104-quad4')
FREQUENCY = 2000  # samples a second
SIZES = (80, 160)
STEPS = (200, 1200)


def samples(csim, divisions, steps, work):
    end = f'{steps * 1e-3:g}'
    data = os.path.join(work, f'perf-{divisions}-{steps}.data')
    command = ['perf', 'record', '-q', '-e', 'cpu-clock', '-F', str(FREQUENCY), '-o', data, '--', csim, 'run', SCENE,
               '--set', f'parameters.divisions={divisions}', '--set', f'time.end={end}',
               '--set', f'checks.seed_x_170.at={end}', '--set', f'checks.seed_x_340.at={end}',
               '--set', 'output.rate=100000', '--out', os.path.join(work, 'out'), '--quiet']
    # The checks' references are at t = 4 s: a shorter run fails them (exit 1); the timing stands.
    subprocess.run(command, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL,
                   env=dict(os.environ, OMP_NUM_THREADS='1'))
    report = subprocess.run(['perf', 'report', '-i', data, '--stdio', '-n', '--no-children', '--sort', 'symbol',
                             '-g', 'none'], capture_output=True, text=True).stdout
    counts = {}
    for line in report.splitlines():
        match = re.match(r'\s*[\d.]+%\s+(\d+)\s+\[\.\]\s+(.*?)\s*$', line)
        if match:
            name = match.group(2)[:64]
            counts[name] = counts.get(name, 0) + int(match.group(1))
    return counts


def main():
    if len(sys.argv) < 2:
        sys.exit(__doc__)
    csim = os.path.abspath(sys.argv[1])
    repeats = int(sys.argv[2]) if len(sys.argv) > 2 else 3
    per_step = {size: [] for size in SIZES}  # per repeat: function -> ms a step
    with tempfile.TemporaryDirectory() as work:
        for _ in range(repeats):
            for size in SIZES:
                short, long = (samples(csim, size, steps, work) for steps in STEPS)
                scale = 1e3 / FREQUENCY / (STEPS[1] - STEPS[0])  # ms a step per sample
                run = {name: (long.get(name, 0) - short.get(name, 0)) * scale for name in set(short) | set(long)}
                run['(the step)'] = sum(run.values())
                per_step[size].append(run)

    def median(size, name):
        return statistics.median(run.get(name, 0.0) for run in per_step[size])

    small, large = SIZES
    rows = int(os.environ.get('ROWS', 18))
    names = sorted(set().union(*per_step[large]), key=lambda name: -median(large, name))[:rows]
    print(f'ms a step, median of {repeats}; ratio = 51 842 / 13 122 DOFs (DOFs 3.95, target 4.85)')
    print(f'{"13 122":>9} {"51 842":>9} {"ratio":>7}  function')
    for name in names:
        a, b = median(small, name), median(large, name)
        ratio = f'{b / a:7.2f}' if a > 0.005 else '       '
        print(f'{a:9.3f} {b:9.3f} {ratio}  {name}')


if __name__ == '__main__':
    main()
