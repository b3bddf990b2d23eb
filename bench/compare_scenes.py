#!/usr/bin/env python3
"""Runs every scene (or those named) with two csim binaries and compares their outputs: summary.json
without its timers, and probes.csv column by column. A scene whose outputs agree to the bit is marked
IDENTICAL; otherwise the largest relative differences of the summary's values are listed, and the
probe column whose largest difference, relative to the column's largest magnitude, is the largest.
Used to state that a change moves the results "to round-off" (bench/lumped_vs_bullet.md).

usage: bench/compare_scenes.py CSIM_A CSIM_B OUT_DIR [scene ...]
"""
import csv
import json
import math
import os
import subprocess
import sys

ROOT = os.path.join(os.path.dirname(os.path.abspath(__file__)), '..', 'scenes')
TIMING_KEYS = ('seconds', 'wall', 'timer', 'time_s', 'elapsed', 'per_second')


def run(binary, scene, out):
    os.makedirs(out, exist_ok=True)
    return subprocess.run([binary, 'run', os.path.join(ROOT, scene), '--out', out, '--quiet'],
                          capture_output=True, text=True).returncode


def leaves(node, path=''):
    if isinstance(node, dict):
        for key, value in node.items():
            yield from leaves(value, f'{path}.{key}')
    elif isinstance(node, list):
        for i, value in enumerate(node):
            yield from leaves(value, f'{path}[{i}]')
    else:
        yield path, node


def summary(directory):
    path = os.path.join(directory, 'summary.json')
    return dict(leaves(json.load(open(path)))) if os.path.exists(path) else {}


def summary_differences(a, b):
    differences = []
    for key in sorted(set(a) | set(b)):
        if any(word in key for word in TIMING_KEYS):
            continue
        va, vb = a.get(key, '<absent>'), b.get(key, '<absent>')
        if va == vb:
            continue
        numbers = all(isinstance(v, (int, float)) and not isinstance(v, bool) for v in (va, vb))
        relative = abs(va - vb) / max(abs(va), abs(vb), 1e-300) if numbers else math.inf
        differences.append((relative, key, va, vb))
    return sorted(differences, key=lambda d: -d[0])


def probe_difference(da, db):
    pa, pb = os.path.join(da, 'probes.csv'), os.path.join(db, 'probes.csv')
    if not (os.path.exists(pa) and os.path.exists(pb)):
        return 0.0, '' if os.path.exists(pa) == os.path.exists(pb) else 'probes.csv in one run only'
    A, B = list(csv.reader(open(pa))), list(csv.reader(open(pb)))
    if len(A) != len(B) or A[0] != B[0]:
        return math.inf, f'rows {len(A)} against {len(B)}'
    largest, column = 0.0, ''
    for j, name in enumerate(A[0]):
        col_a = [float(r[j]) for r in A[1:]]
        col_b = [float(r[j]) for r in B[1:]]
        scale = max([abs(x) for x in col_a] + [1e-300])
        d = max([abs(x - y) for x, y in zip(col_a, col_b)] + [0.0]) / scale
        if d > largest:
            largest, column = d, name
    return largest, column


def main():
    if len(sys.argv) < 4:
        sys.exit(__doc__)
    binary_a, binary_b, out = sys.argv[1:4]
    scenes = sys.argv[4:] or sorted(os.listdir(ROOT))
    identical = 0
    for scene in scenes:
        da, db = os.path.join(out, 'a', scene), os.path.join(out, 'b', scene)
        ra, rb = run(binary_a, scene, da), run(binary_b, scene, db)
        differences = summary_differences(summary(da), summary(db))
        largest, column = probe_difference(da, db)
        same = ra == rb and not differences and largest == 0.0
        identical += same
        print(f'{scene:24s} exit {ra}/{rb} {"IDENTICAL" if same else ""} summary differences {len(differences)} '
              f'probes largest relative {largest:.2e} {column}')
        for relative, key, va, vb in differences[:6]:
            print(f'    {key}: {va} -> {vb} ({relative:.2e})')
    print(f'{identical} of {len(scenes)} scenes the same to the bit')


if __name__ == '__main__':
    main()
