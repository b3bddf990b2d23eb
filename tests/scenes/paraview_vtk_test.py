#!/usr/bin/env python3
"""Reads every ParaView file of a run through VTK itself (Debian's python3-vtk9), as ParaView would.

Usage: paraview_vtk_test.py CSIM SCENE OUT [--set KEY=VALUE]...

Runs SCENE three times with output.paraview = ascii, binary and zlib into OUT/<encoding>, then for every
.pvd: its DataSets, in time order, are the folder's .vtu files; each is read by
vtkXMLUnstructuredGridReader with no error or warning, its FieldData TimeValue is the .pvd's timestep,
and the binary and zlib files hold exactly the ASCII file's points, cells (connectivity, types) and
arrays. Exit 0 when all hold, 1 when one does not or when VTK cannot be imported: tools/setup.sh
installs python3-vtk9, and a read-back that did not happen is not a pass.
"""
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
    reader = vtk.vtkXMLUnstructuredGridReader()
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
            out[f"{kind}:{array.GetName()}"] = values(array)
    return out


def main():
    csim, scene, out = sys.argv[1:4]
    overrides = sys.argv[4:]
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
                if got != expected:
                    differing = sorted(k for k in set(got) | set(expected) if got.get(k) != expected.get(k))
                    failures.append(f"{encoding}/{name}: differs from the ASCII file in {differing}")
                if got["points"] and any(x != 0.0 for k, v in got.items() if k.startswith("point:") for x in v):
                    nonzero.add(collection)
    if collections and not nonzero:
        failures.append("every point array of every frame is zero")
    for f in failures[:20]:
        print("FAIL", f)
    print(f"paraview_vtk_test: {files} files read through VTK {vtk.vtkVersion.GetVTKVersion()}, "
          f"{len(failures)} failures")
    sys.exit(1 if failures or files == 0 else 0)


if __name__ == "__main__":
    main()
