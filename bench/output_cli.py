#!/usr/bin/env python3
"""Before/after of the ParaView output through the command line (docs/output.md).

Usage: output_cli.py FOLDER REPEATS NAME=CSIM[:SETTING] ...

Each NAME runs `CSIM run scenes/sdnv104-quad4` on the 40 x 40 shoe (parameters.divisions=40,
time.step=0.01, time.end=4: 401 frames at the scene's output rate), with `--set output.paraview=SETTING`
when a SETTING is given (a csim from before the key has none), REPEATS times, the NAMEs alternating,
each run into a folder of its own under FOLDER (deleted at the end: see docs/output.md on ext4's cost of
creating files soon after deleting others). Prints the median wall time of the whole command (start,
scene, run, output folder swap) with its min-max, and the median CPU time (user + system) of the
child.
"""
import os
import resource
import shutil
import statistics
import subprocess
import sys
import time

SCENE = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "scenes", "sdnv104-quad4")


def main():
    folder, repeats, variants = sys.argv[1], int(sys.argv[2]), sys.argv[3:]
    root = os.path.join(folder, "csim-output-cli")
    shutil.rmtree(root, ignore_errors=True)
    wall = {v: [] for v in variants}
    cpu = {v: [] for v in variants}
    for r in range(repeats):
        for variant in variants:
            name, spec = variant.split("=", 1)
            csim, _, setting = spec.partition(":")
            command = [csim, "run", SCENE, "--quiet", "--out", os.path.join(root, f"{name}{r}"),
                       "--set", "parameters.divisions=40", "--set", "time.step=0.01", "--set", "time.end=4"]
            if setting:
                command += ["--set", f"output.paraview={setting}"]
            before = resource.getrusage(resource.RUSAGE_CHILDREN)
            start = time.perf_counter()
            subprocess.run(command, check=True, stdout=subprocess.DEVNULL)
            wall[variant].append(time.perf_counter() - start)
            after = resource.getrusage(resource.RUSAGE_CHILDREN)
            cpu[variant].append(after.ru_utime + after.ru_stime - before.ru_utime - before.ru_stime)
    shutil.rmtree(root, ignore_errors=True)
    print(f"sdnv104-quad4 40 x 40, step 0.01 s to 4 s, 401 frames, into {folder}; {repeats} runs each, alternating")
    print(f"{'variant':<10} {'median s':>9} {'min-max s':>17} {'CPU s':>7}")
    for variant in variants:
        w = wall[variant]
        print(f"{variant.split('=')[0]:<10} {statistics.median(w):9.3f} {min(w):8.3f} - {max(w):<7.3f}"
              f" {statistics.median(cpu[variant]):7.3f}")


if __name__ == "__main__":
    main()
