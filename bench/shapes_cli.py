#!/usr/bin/env python3
"""The cost of the shapes' ParaView files (output.shapes) through the command line (docs/output.md).

Usage: shapes_cli.py CSIM FOLDER REPEATS [--set KEY=VALUE]...

Runs `CSIM run scenes/sphere-pile` (25 spheres, 200 steps; with the overrides given, e.g.
`--set output.rate=0` for a frame every step) with the shapes off (the scene's output.paraview: none)
and on in each encoding (output.shapes=true, output.paraview=binary, zlib, ascii), REPEATS times, the
variants alternating, each run into a folder of its own under FOLDER (deleted at the end). Prints per
variant the median wall time of the whole command with its min-max, the median CPU time (user + system)
of the child, the extra over `off` of the medians, and the bytes the ParaView files take.
"""
import os
import resource
import shutil
import statistics
import subprocess
import sys
import time

SCENE = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "scenes", "sphere-pile")
VARIANTS = {"off": [], "binary": ["--set", "output.shapes=true", "--set", "output.paraview=binary"],
            "zlib": ["--set", "output.shapes=true", "--set", "output.paraview=zlib"],
            "ascii": ["--set", "output.shapes=true", "--set", "output.paraview=ascii"]}


def folder_bytes(path):
    return sum(os.path.getsize(os.path.join(d, f)) for d, _, files in os.walk(path) for f in files)


def main():
    csim, folder, repeats, overrides = sys.argv[1], sys.argv[2], int(sys.argv[3]), sys.argv[4:]
    root = os.path.join(folder, "csim-shapes-cli")
    shutil.rmtree(root, ignore_errors=True)
    wall = {v: [] for v in VARIANTS}
    cpu = {v: [] for v in VARIANTS}
    written, frames = {}, 0
    for r in range(repeats):
        for variant, settings in VARIANTS.items():
            out = os.path.join(root, f"{variant}{r}")
            command = [csim, "run", SCENE, "--quiet", "--out", out] + overrides + settings
            before = resource.getrusage(resource.RUSAGE_CHILDREN)
            start = time.perf_counter()
            subprocess.run(command, check=True, stdout=subprocess.DEVNULL)
            wall[variant].append(time.perf_counter() - start)
            after = resource.getrusage(resource.RUSAGE_CHILDREN)
            cpu[variant].append(after.ru_utime + after.ru_stime - before.ru_utime - before.ru_stime)
            paraview = os.path.join(out, "paraview")
            written[variant] = folder_bytes(paraview) if os.path.isdir(paraview) else 0
            if variant == "binary":
                frames = sum(1 for f in os.listdir(paraview) if f.endswith(".vtp"))
    shutil.rmtree(root, ignore_errors=True)
    print(f"sphere-pile {' '.join(overrides)}: {frames} frames, into {folder}; {repeats} runs each, alternating")
    print(f"{'variant':<8} {'median s':>9} {'min-max s':>17} {'CPU s':>7} {'extra wall':>11} {'extra CPU':>10}"
          f" {'MB written':>11}")
    w0, c0 = statistics.median(wall["off"]), statistics.median(cpu["off"])
    for variant in VARIANTS:
        w, c = statistics.median(wall[variant]), statistics.median(cpu[variant])
        print(f"{variant:<8} {w:9.3f} {min(wall[variant]):8.3f} - {max(wall[variant]):<7.3f} {c:7.3f}"
              f" {100 * (w - w0) / w0:10.0f}% {100 * (c - c0) / c0:9.0f}% {written[variant] / 1e6:11.2f}")


if __name__ == "__main__":
    main()
