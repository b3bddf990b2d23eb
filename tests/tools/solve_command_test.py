#!/usr/bin/env python3
"""`csim solve` from the outside (docs/contract.md, "solve"): its line, its exit statuses, its --out file.

A solution is judged by a residual computed here, independently of csim: Siconos' natural-map error
(numerics/src/FrictionContact/fc3d_compute_error.c, fc2d_compute_error.c), reimplemented from its
definition: per contact, r − proj_K(r − ũ) with ũ = u + μ‖u_t‖ e_n (De Saxcé's modified velocity) and K the
Coulomb cone ‖r_t‖ ≤ μ r_n; the error is the 2-norm over all contacts divided by ‖q‖.

usage: solve_command_test.py CSIM SOURCE_DIR WORK_DIR
"""
import math
import os
import re
import subprocess
import sys

CSIM, SOURCE, WORK = sys.argv[1], sys.argv[2], sys.argv[3]
SICONOS = os.path.join(SOURCE, "tests/contact/data/siconos")
OWN = os.path.join(SOURCE, "tests/contact/data")
DATA = os.path.join(SOURCE, "tests/tools/data/solve")
LINE = re.compile(r"^converged=(yes|no) iterations=(\d+) residual=(\S+) time_s=(\S+)\n$")
failures = []


def check(condition, message):
    if not condition:
        failures.append(message)
    return condition


def solve(*arguments):
    result = subprocess.run([CSIM, "solve", *arguments], capture_output=True, text=True, timeout=120)
    return result.returncode, result.stdout, result.stderr


def read_siconos_dense(path):
    """Siconos' format with a dense W (column-major), as frictionContact_printInFile writes it."""
    tokens = open(path).read().split()
    d, nc, storage, n, _ = (int(t) for t in tokens[:5])
    assert storage == 0 and n == d * nc, path
    values = [float(t) for t in tokens[7:7 + n * n]]
    W = [[values[i + j * n] for j in range(n)] for i in range(n)]
    q = [float(t) for t in tokens[7 + n * n:7 + n * n + n]]
    mu = [float(t) for t in tokens[7 + n * n + n:7 + n * n + n + nc]]
    return d, W, q, mu


def read_csim(path):
    """csim's own format (friction_contact_problem.cpp), isotropic friction and no equality rows."""
    tokens = open(path).read().split()
    position = {name: tokens.index(name) for name in ("dimension", "contacts", "equalities", "mu", "q", "W")}
    d = int(tokens[position["dimension"] + 1])
    nc = int(tokens[position["contacts"] + 1])
    assert int(tokens[position["equalities"] + 1]) == 0, path
    n = d * nc
    mu_pairs = [float(t) for t in tokens[position["mu"] + 1:position["mu"] + 1 + 2 * nc]]
    assert all(mu_pairs[2 * c] == mu_pairs[2 * c + 1] for c in range(nc)), path
    q = [float(t) for t in tokens[position["q"] + 1:position["q"] + 1 + n]]
    values = [float(t) for t in tokens[position["W"] + 1:position["W"] + 1 + n * n]]
    W = [values[i * n:(i + 1) * n] for i in range(n)]  # one row a line
    return d, W, q, mu_pairs[0::2]


def project_on_cone(normal, tangent, mu):
    norm_t = math.sqrt(sum(t * t for t in tangent))
    if norm_t <= mu * normal:
        return normal, tangent
    if mu * norm_t <= -normal:
        return 0.0, [0.0] * len(tangent)
    alpha = (normal + mu * norm_t) / (1.0 + mu * mu)
    return alpha, [mu * alpha * t / norm_t for t in tangent]


def natural_map_error(d, W, q, mu, r):
    n = len(q)
    u = [sum(W[i][j] * r[j] for j in range(n)) + q[i] for i in range(n)]
    total = 0.0
    for c, mu_c in enumerate(mu):
        rc, uc = r[d * c:d * c + d], u[d * c:d * c + d]
        modified_normal = uc[0] + mu_c * math.sqrt(sum(t * t for t in uc[1:]))
        normal, tangent = project_on_cone(rc[0] - modified_normal, [rc[k] - uc[k] for k in range(1, d)], mu_c)
        total += (rc[0] - normal) ** 2 + sum((rc[k] - tangent[k - 1]) ** 2 for k in range(1, d))
    norm_q = math.sqrt(sum(x * x for x in q))
    return math.sqrt(total) / (norm_q if norm_q > 2.2e-16 else 1.0)


def read_solution(path, rows):
    text = open(path).read()
    lines = text.split("\n")
    check(text.endswith("\n") and len(lines) == rows + 1, f"{path}: {len(lines) - 1} lines, expected {rows}")
    return [float(x) for x in lines[:-1]]


os.makedirs(WORK, exist_ok=True)

# Solved problems: Siconos' dense 3D (unsymmetric W) and 2D, csim's own 3D. r satisfies the law to 1e-8.
solved = [(os.path.join(SICONOS, "Rover4396.dat"), read_siconos_dense),
          (os.path.join(SICONOS, "FC2D_SliderCrankLagrangian00000.dat"), read_siconos_dense),
          (os.path.join(SICONOS, "FrictionContactProblem00394.dat"), read_siconos_dense),
          (os.path.join(OWN, "box_on_four_vertices_3d.txt"), read_csim)]
for path, reader in solved:
    name = os.path.basename(path)
    out = os.path.join(WORK, name + ".r")
    if os.path.exists(out):
        os.remove(out)
    status, stdout, stderr = solve(path, "--tolerance", "1e-10", "--out", out)
    match = LINE.match(stdout)
    if not (check(status == 0, f"{name}: exit {status}, expected 0; {stderr}") and
            check(match is not None, f"{name}: printed {stdout!r}") and check(stderr == "", f"{name}: {stderr}")):
        continue
    check(match.group(1) == "yes" and float(match.group(3)) <= 1e-10, f"{name}: {stdout}")
    d, W, q, mu = reader(path)
    r = read_solution(out, len(q))
    error = natural_map_error(d, W, q, mu, r)
    check(error <= 1e-8, f"{name}: natural-map error {error:.3e} > 1e-8")
    check(not os.path.exists(out + ".tmp"), f"{name}: {out}.tmp left behind")
    print(f"{name}: {stdout.strip()}, natural-map error {error:.2e}")

# No solution exists (tests/tools/data/solve/README.md): exit 1, and r is still written whole.
out = os.path.join(WORK, "infeasible.r")
status, stdout, stderr = solve(os.path.join(DATA, "infeasible_2d.txt"), "--out", out)
check(status == 1, f"infeasible: exit {status}, expected 1; {stderr}")
check(LINE.match(stdout) is not None and stdout.startswith("converged=no "), f"infeasible: printed {stdout!r}")
check(os.path.exists(out) and len(read_solution(out, 4)) == 4, "infeasible: r not written")
print(f"infeasible_2d.txt: {stdout.strip()}")

# Bad input: exit 2, one message naming the file and the line; nothing on stdout, --out untouched.
kept = os.path.join(WORK, "kept.r")
for name, pattern in [("malformed_number_siconos.dat", r"malformed_number_siconos\.dat:8: malformed number 'x' in W"),
                      ("short_matrix.txt", r"short_matrix\.txt:12: malformed number 'end' in W"),
                      ("missing.txt", r"missing\.txt: cannot open the problem file")]:
    with open(kept, "w") as f:
        f.write("an earlier solution\n")
    status, stdout, stderr = solve(os.path.join(DATA, name), "--out", kept)
    check(status == 2, f"{name}: exit {status}, expected 2")
    check(re.search(r"^csim: .*" + pattern, stderr) is not None and stderr.count("\n") == 1,
          f"{name}: stderr {stderr!r} does not match {pattern!r}")
    check(stdout == "", f"{name}: printed {stdout!r}")
    check(open(kept).read() == "an earlier solution\n", f"{name}: --out was touched")

# --out in a folder that does not exist: exit 2 naming the path, and no file.
missing_folder = os.path.join(WORK, "no-such-folder", "r.txt")
status, stdout, stderr = solve(os.path.join(SICONOS, "Rover4396.dat"), "--out", missing_folder)
check(status == 2 and "no-such-folder/r.txt" in stderr, f"--out in a missing folder: exit {status}, {stderr!r}")
check(not os.path.exists(os.path.dirname(missing_folder)), "--out in a missing folder: a folder was created")

# A sparse-block problem (W stored by blocks, contact/sparse_pgs.h): solved and judged like the others.
path = os.path.join(SICONOS, "FC3D_Example1_SBM.dat")
out = os.path.join(WORK, "sbm.r")
status, stdout, stderr = solve(path, "--tolerance", "1e-10", "--out", out)
check(status == 0 and LINE.match(stdout) is not None, f"sparse-block: exit {status}, {stdout!r} {stderr!r}")
if status == 0:
    d, W, q, mu = read_siconos_dense(os.path.join(SICONOS, "FC3D_Example1.dat"))  # the same problem, dense
    error = natural_map_error(d, W, q, mu, read_solution(out, len(q)))
    check(error <= 1e-8, f"sparse-block: natural-map error {error:.3e} > 1e-8")
print(f"FC3D_Example1_SBM.dat: exit {status}: {(stdout or stderr).strip()}")

# An FCLib HDF5 file (W by compressed rows, stored by blocks): solved to its tolerance.
path = os.path.join(SICONOS, "LMGC_100_PR_PerioBox-i00361-60-03000.hdf5")
status, stdout, stderr = solve(path, "--tolerance", "1e-8")
check(status == 0 and LINE.match(stdout) is not None, f"FCLib: exit {status}, {stdout!r} {stderr!r}")
print(f"LMGC_100_PR_PerioBox-i00361-60-03000.hdf5: exit {status}: {(stdout or stderr).strip()}")

for failure in failures:
    print("FAIL:", failure)
sys.exit(1 if failures else 0)
