#!/usr/bin/env python3
"""Peak memory of reading a large Gmsh mesh (fem/gmsh_reader.cpp): writes an N x N QUAD4 plate as MSH 4.1
ASCII (physical surface "body", physical lines "bottom" and "top"), then runs under /usr/bin/time
bench_read_gmsh (the reader alone) and `csim validate` on a scene that loads it (the reader, then the
elastic body's setup), and prints the file size and each peak resident set size.

  cmake --build build --target csim bench_read_gmsh
  python3 bench/gmsh_memory.py [--build build] [--n 700] [--dir /tmp/gmsh_memory]
"""
import argparse
import os
import subprocess


def write_mesh(path, n):
    nodes = (n + 1) * (n + 1)

    def tag(i, j):
        return j * (n + 1) + i + 1

    with open(path, "w") as f:
        f.write("$MeshFormat\n4.1 0 8\n$EndMeshFormat\n")
        f.write('$PhysicalNames\n3\n1 1 "bottom"\n1 2 "top"\n2 3 "body"\n$EndPhysicalNames\n')
        f.write("$Entities\n0 2 1 0\n")
        f.write("1 0 0 0 1 0 0 1 1 0\n2 0 1 0 1 1 0 1 2 0\n")
        f.write("1 0 0 0 1 1 0 1 3 0\n$EndEntities\n")
        # One node block on the surface (gmsh would split them by entity; the reader does not care).
        f.write("$Nodes\n1 %d 1 %d\n2 1 0 %d\n" % (nodes, nodes, nodes))
        for t in range(1, nodes + 1):
            f.write("%d\n" % t)
        h = 1.0 / n
        for j in range(n + 1):
            for i in range(n + 1):
                f.write("%.16g %.16g 0\n" % (i * h, j * h))
        f.write("$EndNodes\n")
        quads = n * n
        f.write("$Elements\n3 %d 1 %d\n" % (quads + 2 * n, quads + 2 * n))
        f.write("1 1 1 %d\n" % n)
        for i in range(n):
            f.write("%d %d %d\n" % (quads + i + 1, tag(i, 0), tag(i + 1, 0)))
        f.write("1 2 1 %d\n" % n)
        for i in range(n):
            f.write("%d %d %d\n" % (quads + n + i + 1, tag(i + 1, n), tag(i, n)))
        f.write("2 1 3 %d\n" % quads)
        e = 0
        for j in range(n):
            for i in range(n):
                e += 1
                f.write("%d %d %d %d %d\n" % (e, tag(i, j), tag(i + 1, j), tag(i + 1, j + 1), tag(i, j + 1)))
        f.write("$EndElements\n")


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("--build", default="build")
    parser.add_argument("--n", type=int, default=700)
    parser.add_argument("--dir", default="/tmp/gmsh_memory")
    args = parser.parse_args()
    os.makedirs(args.dir, exist_ok=True)
    mesh = os.path.join(args.dir, "plate.msh")
    if not os.path.exists(mesh):
        write_mesh(mesh, args.n)
    scene = os.path.join(args.dir, "scene.yaml")
    with open(scene, "w") as f:
        f.write("dimension: 2\nbodies:\n  plate:\n    type: elastic\n    mesh: {file: plate.msh}\n"
                "    material: {young: 1e6, poisson: 0.3, density: 1000}\n"
                "time: {end: 1e-3, step: 1e-3}\n")
    size = os.path.getsize(mesh)
    print("mesh %s: %.1f MB (%d x %d quad4)" % (mesh, size / 1e6, args.n, args.n))
    for name, command in (("bench_read_gmsh", [os.path.join(args.build, "bench", "bench_read_gmsh"), mesh]),
                          ("csim validate", [os.path.join(args.build, "tools", "csim"), "validate", scene])):
        result = subprocess.run(["/usr/bin/time", "-f", "%M"] + command, capture_output=True, text=True)
        peak_kib = int(result.stderr.strip().splitlines()[-1])
        print("  %-16s exit %d, peak RSS %7.1f MB (%.2f x the file)"
              % (name, result.returncode, peak_kib * 1024 / 1e6, peak_kib * 1024 / size))
        if result.returncode != 0:
            print(result.stdout + result.stderr)

if __name__ == "__main__":
    main()
