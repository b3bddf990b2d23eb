#!/usr/bin/env python3
"""Writes quarter_disk.msh (Gmsh MSH 4.1 ASCII): the quarter disk x >= 0, y <= R of the disk of radius R
centred at (0, R), touching the plane y = 0 at the origin, in QUAD4 (plane strain).

A Coons patch between its four corners A = (0, 0) (the contact point), B (the arc at -45 degrees),
C = (R, R) and D = (0, R) (the centre), graded towards A: n_uniform elements of size h0 along the arc from A
and down the axis from A, then growing by the ratio g. Physical groups: the surface "disk"; the curves
"axis" (x = 0, A to D), "top" (y = R, D to C) and "arc" (A to B to C); the points "contact" (A) and
"centre" (D).

    python3 make_mesh.py [R h0 n_uniform g]   (defaults 0.1 2.5e-4 16 1.2: a/h0 = 8 at the scene's load)
"""
import math
import sys


def graded(length, h0, n_uniform, ratio):
    """Fractions 0 = t_0 < ... < t_n = 1 of a side of that length: n_uniform steps h0, then steps growing
    by ratio, the geometric part scaled so that the last node lands on the end."""
    steps = [h0] * n_uniform
    rest = length - h0 * n_uniform
    step = h0
    grown = []
    while sum(grown) < rest:
        step *= ratio
        grown.append(step)
    scale = rest / sum(grown)
    steps += [s * scale for s in grown]
    t = [0.0]
    for s in steps:
        t.append(t[-1] + s)
    return [x / length for x in t]


def main():
    R, h0, n_uniform, ratio = 0.1, 2.5e-4, 16, 1.2
    if len(sys.argv) == 5:
        R, h0, n_uniform, ratio = float(sys.argv[1]), float(sys.argv[2]), int(sys.argv[3]), float(sys.argv[4])
    arc = math.pi * R / 4.0  # A to B
    u = graded(arc, h0, n_uniform, ratio)
    v = graded(R, h0, n_uniform, ratio)
    nu, nv = len(u) - 1, len(v) - 1

    def ab(t):  # A to B along the arc: theta from -90 to -45 degrees about (0, R)
        th = -math.pi / 2 + t * math.pi / 4
        return (R * math.cos(th), R + R * math.sin(th))

    def bc(t):  # B to C along the arc: theta from -45 to 0 degrees
        th = -math.pi / 4 + t * math.pi / 4
        return (R * math.cos(th), R + R * math.sin(th))

    def dc(t):
        return (R * t, R)

    def ad(t):
        return (0.0, R * t)

    A, B, C, D = ab(0), ab(1), (R, R), (0.0, R)
    nodes = {}
    tag = 0
    grid = [[0] * (nv + 1) for _ in range(nu + 1)]
    coords = []
    for j in range(nv + 1):
        for i in range(nu + 1):
            s, t = u[i], v[j]
            p = [(1 - t) * ab(s)[k] + t * dc(s)[k] + (1 - s) * ad(t)[k] + s * bc(t)[k]
                 - ((1 - s) * (1 - t) * A[k] + s * (1 - t) * B[k] + (1 - s) * t * D[k] + s * t * C[k])
                 for k in range(2)]
            if i == 0:
                p[0] = 0.0  # exactly on the axis
            if j == nv:
                p[1] = R  # exactly on the top
            tag += 1
            grid[i][j] = tag
            coords.append((tag, p[0], p[1]))
    xy = {c[0]: (c[1], c[2]) for c in coords}
    quads = []
    for j in range(nv):
        for i in range(nu):
            q = (grid[i][j], grid[i + 1][j], grid[i + 1][j + 1], grid[i][j + 1])
            # the Jacobian's sign at each corner (counter-clockwise: positive)
            for k in range(4):
                a, b, c = xy[q[k - 1]], xy[q[k]], xy[q[(k + 1) % 4]]
                area = (b[0] - a[0]) * (c[1] - b[1]) - (b[1] - a[1]) * (c[0] - b[0])
                assert area > 0.0, (i, j, k)
            quads.append(q)
    axis = [(grid[0][j], grid[0][j + 1]) for j in range(nv)]
    top = [(grid[i][nv], grid[i + 1][nv]) for i in range(nu)]
    arc_lines = [(grid[i][0], grid[i + 1][0]) for i in range(nu)] + [(grid[nu][j], grid[nu][j + 1]) for j in range(nv)]

    out = []
    out += ["$MeshFormat", "4.1 0 8", "$EndMeshFormat"]
    out += ["$PhysicalNames", "6", '0 1 "contact"', '0 2 "centre"', '1 3 "axis"', '1 4 "top"', '1 5 "arc"',
            '2 6 "disk"', "$EndPhysicalNames"]
    out += ["$Entities", "2 3 1 0",
            "1 0 0 0 1 1", f"2 0 {R!r} 0 1 2",
            f"1 0 0 0 0 {R!r} 0 1 3 2 1 -2",
            f"2 0 {R!r} 0 {R!r} {R!r} 0 1 4 0",
            f"3 0 0 0 {R!r} {R!r} 0 1 5 0",
            f"1 0 0 0 {R!r} {R!r} 0 1 6 3 1 2 3",
            "$EndEntities"]
    out += ["$Nodes", f"1 {len(coords)} 1 {len(coords)}", f"2 1 0 {len(coords)}"]
    out += [str(c[0]) for c in coords]
    out += [f"{c[1]!r} {c[2]!r} 0" for c in coords]
    out += ["$EndNodes"]
    blocks = [(0, 1, 15, [(grid[0][0],)]), (0, 2, 15, [(grid[0][nv],)]), (1, 1, 1, axis), (1, 2, 1, top),
              (1, 3, 1, arc_lines), (2, 1, 3, quads)]
    total = sum(len(b[3]) for b in blocks)
    out += ["$Elements", f"{len(blocks)} {total} 1 {total}"]
    element = 0
    for dim, entity, kind, items in blocks:
        out.append(f"{dim} {entity} {kind} {len(items)}")
        for item in items:
            element += 1
            out.append(" ".join(str(x) for x in (element,) + tuple(item)))
    out += ["$EndElements"]
    with open("quarter_disk.msh", "w") as f:
        f.write("\n".join(out) + "\n")
    print(f"{len(coords)} nodes, {len(quads)} quad4 ({nu} x {nv}); h0 = {h0}, R = {R}", file=sys.stderr)


if __name__ == "__main__":
    main()
