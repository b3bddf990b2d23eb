#!/usr/bin/env python3
"""Reads every ParaView file of a run through VTK itself (Debian's python3-vtk9), as ParaView would.

Usage: paraview_vtk_test.py CSIM SCENE OUT [--set KEY=VALUE]... [SHAPE CHECKS]

Runs SCENE three times with output.paraview = ascii, binary and zlib into OUT/<encoding>, then for every
.pvd: its DataSets, in time order, are the folder's .vtu and .vtp files; each is read by
vtkXMLUnstructuredGridReader (.vtu) or vtkXMLPolyDataReader (.vtp) with no error or warning, its
FieldData TimeValue is the .pvd's timestep, and the binary and zlib files hold exactly the ASCII file's
points, cells (connectivity, types) and arrays. Exit 0 when all hold, 1 when one does not or when VTK
cannot be imported: tools/setup.sh installs python3-vtk9, and a read-back that did not happen is not a
pass.

Shape checks, on the shapes' series (output.shapes: bodies.pvd) against the run's own bodies.csv
(output.bodies, set by the script), in every encoding and frame:
  --bodies N          the files draw N bodies (distinct values of the cell data `body`);
  --box NAME H...     the box body NAME (one box shape at its frame's origin, half extents H, 2 or 3
                      of them, m) has as points exactly its corners x + R (±h): R from the row of
                      bodies.csv at the frame's time, each point within 1e-12 m of a corner and every
                      corner met; its polygons enclose 8 hx hy hz (in the plane 4 hx hy) counted
                      positive when they face outward; its point velocities are a rigid body's ((u_i − u_j)·(p_i − p_j) = 0
                      to 1e-9 m²/s) and its cells' body_velocity is the velocity of its origin;
  --sphere NAME R     every point of body NAME is at distance R (m) from its position in bodies.csv,
                      to 1e-12 m (the outline's vertices lie on the sphere, or the circle);
  --halfspace NAME    the fixed body NAME, all halfspaces, is one square (a segment in the plane) per
                      shape, of half side 1.5 times the largest distance from its centre to the points
                      of the first frame of the bodies not named by --halfspace (docs/contract.md), to
                      1e-12 m, in every frame;
and the frames' times are those of bodies.csv's rows (to 1e-12 s: bodies.csv has 15 digits).
"""
import csv
import math
import os
import shutil
import subprocess
import sys
import xml.etree.ElementTree as ElementTree

try:
    import vtk
except ImportError:
    print("paraview_vtk_test: FAILED, no VTK for Python: install Debian's python3-vtk9 (tools/setup.sh does)")
    sys.exit(1)

ENCODINGS = ("ascii", "binary", "zlib")


class ReadError(Exception):
    pass


def read_grid(path):
    reader = vtk.vtkXMLPolyDataReader() if path.endswith(".vtp") else vtk.vtkXMLUnstructuredGridReader()
    messages = []
    for event in ("ErrorEvent", "WarningEvent"):
        reader.AddObserver(event, lambda obj, ev, messages=messages: messages.append(ev))
    # VTK's own messages go to stderr; the observers above make them a failure here.
    reader.SetFileName(path)
    reader.Update()
    if messages or reader.GetErrorCode() != 0:
        raise ReadError(f"{path}: VTK reported {messages or reader.GetErrorCode()}")
    return reader.GetOutput()


def values(array):
    if array is None:
        return None
    n = array.GetNumberOfComponents()
    return [array.GetComponent(i, c) for i in range(array.GetNumberOfTuples()) for c in range(n)]


def content(grid):
    """Everything ParaView shows of a grid, as plain lists."""
    out = {
        "points": values(grid.GetPoints().GetData()) if grid.GetPoints() else [],
        "cells": grid.GetNumberOfCells(),
        "types": [grid.GetCellType(i) for i in range(grid.GetNumberOfCells())],
        "connectivity": [],
    }
    for i in range(grid.GetNumberOfCells()):
        ids = grid.GetCell(i).GetPointIds()
        out["connectivity"].append([ids.GetId(k) for k in range(ids.GetNumberOfIds())])
    for kind, data in (("point", grid.GetPointData()), ("cell", grid.GetCellData()), ("field", grid.GetFieldData())):
        for a in range(data.GetNumberOfArrays()):
            array = data.GetAbstractArray(a)
            if isinstance(array, vtk.vtkStringArray):
                out[f"{kind}:{array.GetName()}"] = [array.GetValue(i) for i in range(array.GetNumberOfValues())]
            else:
                out[f"{kind}:{array.GetName()}"] = values(array)
    return out


def parse_shape_checks(arguments):
    """Splits the command line after SCENE OUT into csim's overrides and the shape checks."""
    overrides, checks = [], {"bodies": None, "boxes": [], "spheres": [], "halfspaces": []}
    i = 0
    while i < len(arguments):
        if arguments[i] == "--bodies":
            checks["bodies"] = int(arguments[i + 1])
            i += 2
        elif arguments[i] == "--halfspace":
            checks["halfspaces"].append(arguments[i + 1])
            i += 2
        elif arguments[i] in ("--box", "--sphere"):
            j = i + 2
            while j < len(arguments) and not arguments[j].startswith("--"):
                j += 1
            name, numbers = arguments[i + 1], [float(x) for x in arguments[i + 2:j]]
            checks["boxes" if arguments[i] == "--box" else "spheres"].append((name, numbers))
            i = j
        else:
            overrides.append(arguments[i])
            i += 1
    return overrides, checks


def read_poses(path):
    """bodies.csv as {time: {body: (position, rotation matrix)}}, 3D or plane."""
    poses = {}
    with open(path, newline="") as f:
        for row in csv.DictReader(f):
            t = float(row["t"])
            if "qw" in row:
                position = [float(row[k]) for k in ("x", "y", "z")]
                w, x, y, z = (float(row[k]) for k in ("qw", "qx", "qy", "qz"))
                rotation = [[1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)],
                            [2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)],
                            [2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)]]
            else:
                position = [float(row["x"]), float(row["y"]), 0.0]
                c, s = math.cos(float(row["angle"])), math.sin(float(row["angle"]))
                rotation = [[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]]
            poses.setdefault(t, {})[row["body"]] = (position, rotation)
    return poses


def pose_at(poses, t):
    """The rows of bodies.csv at time t (s), which has 15 significant digits."""
    for time, rows in poses.items():
        if abs(time - t) <= 1e-12 * max(1.0, abs(t)):
            return rows
    return None


def body_points(data, body):
    """The point ids (sorted) of the cells of `body` in a PolyData."""
    cell_body = data.GetCellData().GetArray("body")
    ids = set()
    for c in range(data.GetNumberOfCells()):
        if int(cell_body.GetValue(c)) == body:
            cell_ids = data.GetCell(c).GetPointIds()
            ids.update(cell_ids.GetId(k) for k in range(cell_ids.GetNumberOfIds()))
    return sorted(ids)


def check_halfspaces(data, first, name, checks):
    """The halfspaces' patches of one frame, sized from the first frame's other points."""
    failures = []
    names = data.GetFieldData().GetAbstractArray("body_name")
    index = {names.GetValue(i): i for i in range(names.GetNumberOfValues())}
    for body in checks["halfspaces"]:
        halfspaces = {index[h] for h in checks["halfspaces"]}
        others = [first.GetPoint(i) for b in set(index.values()) - halfspaces for i in body_points(first, b)]
        cell_body = data.GetCellData().GetArray("body")
        cells = [c for c in range(data.GetNumberOfCells()) if int(cell_body.GetValue(c)) == index[body]]
        if not cells:
            failures.append(f"{name}: {body}: not drawn")
        for c in cells:
            ids = data.GetCell(c).GetPointIds()
            corners = [data.GetPoint(ids.GetId(k)) for k in range(ids.GetNumberOfIds())]
            centre = [sum(p[r] for p in corners) / len(corners) for r in range(3)]
            half = 1.5 * max(math.dist(p, centre) for p in others)
            sides = [math.dist(corners[k], corners[(k + 1) % len(corners)]) for k in range(len(corners))]
            sides = sides[:1] if len(corners) == 2 else sides
            if len(corners) not in (2, 4) or any(abs(x - 2 * half) > 1e-12 * max(1.0, half) for x in sides):
                failures.append(f"{name}: {body}: cell {c} has sides {sides}, expected {2 * half!r}")
    return failures


def check_shapes(data, name, t, poses, checks):
    """The shape checks of one .vtp frame; returns the failures."""
    failures = []
    names = data.GetFieldData().GetAbstractArray("body_name")
    index = {names.GetValue(i): i for i in range(names.GetNumberOfValues())}
    cell_body = data.GetCellData().GetArray("body")
    drawn = {int(cell_body.GetValue(c)) for c in range(data.GetNumberOfCells())}
    if checks["bodies"] is not None and len(drawn) != checks["bodies"]:
        failures.append(f"{name}: {len(drawn)} bodies drawn, expected {checks['bodies']}")
    rows = pose_at(poses, t)
    if rows is None:
        return failures + [f"{name}: no row of bodies.csv at t = {t!r}"]
    points = data.GetPoints().GetData()
    velocity = data.GetPointData().GetArray("velocity")
    for body, radius in ((b, n[0]) for b, n in checks["spheres"]):
        centre = rows[body][0]
        ids = body_points(data, index[body])
        worst = max(abs(math.dist(points.GetTuple3(i), centre) - radius) for i in ids)
        if not ids or worst > 1e-12:
            failures.append(f"{name}: {body}: {len(ids)} points, off the sphere by up to {worst:.3g} m")
    for body, half in checks["boxes"]:
        position, rotation = rows[body]
        h = list(half) + [0.0] * (3 - len(half))
        signs = [(a, b, c) for a in (-1, 1) for b in (-1, 1) for c in ((-1, 1) if len(half) == 3 else (0,))]
        corners = [[position[r] + sum(rotation[r][k] * s[k] * h[k] for k in range(3)) for r in range(3)]
                   for s in signs]
        ids = body_points(data, index[body])
        met, worst = set(), 0.0
        for i in ids:
            distances = [math.dist(points.GetTuple3(i), corner) for corner in corners]
            nearest = min(range(len(corners)), key=distances.__getitem__)
            met.add(nearest)
            worst = max(worst, distances[nearest])
        if len(ids) != len(corners) or len(met) != len(corners) or worst > 1e-12:
            failures.append(f"{name}: {body}: {len(ids)} points meeting {len(met)} of {len(corners)} corners, "
                            f"up to {worst:.3g} m away")
        # Its polygons close a solid seen from outside: signed volume (divergence theorem, each polygon a
        # fan of triangles) 8 hx hy hz, or in the plane the signed area 4 hx hy (counter-clockwise).
        measure = 0.0
        for c in range(data.GetNumberOfCells()):
            if int(cell_body.GetValue(c)) != index[body] or data.GetCellType(c) not in (vtk.VTK_POLYGON, vtk.VTK_QUAD):
                continue
            cell_ids = data.GetCell(c).GetPointIds()
            corner = [points.GetTuple3(cell_ids.GetId(k)) for k in range(cell_ids.GetNumberOfIds())]
            for k in range(1, len(corner) - 1):
                a, b, d = corner[0], corner[k], corner[k + 1]
                if len(half) == 3:
                    measure += (a[0] * (b[1] * d[2] - b[2] * d[1]) - a[1] * (b[0] * d[2] - b[2] * d[0])
                                + a[2] * (b[0] * d[1] - b[1] * d[0])) / 6.0
                else:
                    measure += ((b[0] - a[0]) * (d[1] - a[1]) - (b[1] - a[1]) * (d[0] - a[0])) / 2.0
        expected = math.prod(2.0 * x for x in half)
        if abs(measure - expected) > 1e-12 * max(1.0, max(abs(x) for x in position) ** len(half)):
            failures.append(f"{name}: {body}: its polygons enclose {measure!r}, expected {expected!r} (outward)")
        for i in ids:
            for j in ids:
                p = [a - b for a, b in zip(points.GetTuple3(i), points.GetTuple3(j))]
                u = [a - b for a, b in zip(velocity.GetTuple3(i), velocity.GetTuple3(j))]
                if abs(sum(a * b for a, b in zip(p, u))) > 1e-9:
                    failures.append(f"{name}: {body}: points {i} and {j} move apart: not a rigid body's velocity")
        # The origin's velocity from the corners: their mean, as the origin is their centroid.
        mean = [sum(velocity.GetTuple3(i)[r] for i in ids) / len(ids) for r in range(3)] if ids else None
        body_velocity = data.GetCellData().GetArray("body_velocity")
        for c in range(data.GetNumberOfCells()):
            if int(cell_body.GetValue(c)) == index[body] and mean is not None:
                if math.dist(body_velocity.GetTuple3(c), mean) > 1e-12 * max(1.0, math.hypot(*mean)):
                    failures.append(f"{name}: {body}: body_velocity {body_velocity.GetTuple3(c)} is not the "
                                    f"corners' mean velocity {mean}")
                    break
    return failures


def main():
    csim, scene, out = sys.argv[1:4]
    overrides, shape_checks = parse_shape_checks(sys.argv[4:])
    shapes = any(shape_checks[k] for k in ("boxes", "spheres", "halfspaces")) or shape_checks["bodies"] is not None
    if shapes:
        overrides += ["--set", "output.shapes=true", "--set", "output.bodies=true"]
    for encoding in ENCODINGS:
        folder = os.path.join(out, encoding)
        shutil.rmtree(folder, ignore_errors=True)
        subprocess.run([csim, "run", scene, "--quiet", "--out", folder, "--set", f"output.paraview={encoding}"]
                       + overrides, check=False, stdout=subprocess.DEVNULL)
    failures = []
    ascii_folder = os.path.join(out, "ascii", "paraview")
    collections = sorted(f for f in os.listdir(ascii_folder) if f.endswith(".pvd"))
    if not collections:
        failures.append("no .pvd written")
    files = 0
    nonzero = set()  # the collections with some nonzero point data: the comparison is not of zeros only
    for collection in collections:
        for encoding in ENCODINGS:
            folder = os.path.join(out, encoding, "paraview")
            sets = ElementTree.parse(os.path.join(folder, collection)).getroot().find("Collection")
            times = [float(s.get("timestep")) for s in sets]
            if times != sorted(times) or len(times) < 2:
                failures.append(f"{encoding}/{collection}: timesteps {times[:5]}... not increasing")
            poses = read_poses(os.path.join(out, encoding, "bodies.csv")) if collection == "bodies.pvd" else None
            if shapes and collection == "bodies.pvd" and len(poses) != len(times):
                failures.append(f"{encoding}: bodies.csv has {len(poses)} times, bodies.pvd {len(times)}")
            first = None
            for data_set in sets:
                name = data_set.get("file")
                try:
                    grid = read_grid(os.path.join(folder, name))
                    reference = read_grid(os.path.join(ascii_folder, name))
                except ReadError as error:
                    failures.append(str(error))
                    continue
                files += 1
                got, expected = content(grid), content(reference)
                if got["field:TimeValue"] != [float(data_set.get("timestep"))]:
                    failures.append(f"{encoding}/{name}: TimeValue {got['field:TimeValue']} is not the .pvd's")
                if shapes and collection == "bodies.pvd":
                    failures += check_shapes(grid, f"{encoding}/{name}", float(data_set.get("timestep")), poses,
                                             shape_checks)
                    first = first or grid
                    failures += check_halfspaces(grid, first, f"{encoding}/{name}", shape_checks)
                if got != expected:
                    differing = sorted(k for k in set(got) | set(expected) if got.get(k) != expected.get(k))
                    failures.append(f"{encoding}/{name}: differs from the ASCII file in {differing}")
                if got["points"] and any(x != 0.0 for k, v in got.items() if k.startswith("point:") for x in v):
                    nonzero.add(collection)
    if shapes and "bodies.pvd" not in collections:
        failures.append("no bodies.pvd: the shapes' series was not written")
    if collections and not nonzero:
        failures.append("every point array of every frame is zero")
    for f in failures[:20]:
        print("FAIL", f)
    print(f"paraview_vtk_test: {files} files read through VTK {vtk.vtkVersion.GetVTKVersion()}, "
          f"{len(failures)} failures")
    sys.exit(1 if failures or files == 0 else 0)


if __name__ == "__main__":
    main()
