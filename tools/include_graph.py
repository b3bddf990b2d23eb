#!/usr/bin/env python3
"""Include graph between csim's folders, and the layer check (docs/architecture.md, "Layers").

Lists every `#include "..."` arrow between the folders below, with how many includes carry it, and
exits with status 1 if a file of the physics core (engine/, contact/, fem/) includes anything under
tools/: the core must not know the application.

    python3 tools/include_graph.py [repository root]     # default: the folder above this script
"""
import pathlib
import re
import sys

# Most specific first: a path belongs to the first folder it lies in.
FOLDERS = ["engine/bodies", "engine/steppers", "engine/contact_stage", "engine/linear_algebra", "engine", "contact", "fem",
           "tools/scene", "tools/run", "tools/studies", "tools/output", "tools/reference", "tools"]
CORE = ("engine", "contact", "fem")
SOURCE_SUFFIXES = {".h", ".hpp", ".cpp", ".cc"}
INCLUDE = re.compile(r'^\s*#\s*include\s*"([^"]+)"', re.MULTILINE)


def folder_of(relative_path):
    """The folder of FOLDERS a repository-relative path lies in, or None."""
    for folder in FOLDERS:
        if relative_path == folder or relative_path.startswith(folder + "/"):
            return folder
    return None


def source_files(root):
    for top in ("engine", "contact", "fem", "tools"):
        for path in sorted((root / top).rglob("*")):
            if path.is_file() and path.suffix in SOURCE_SUFFIXES:
                yield path


def include_arrows(root):
    """{(from folder, to folder): count} for every include between (or within) folders, and the list
    of (file, included path) that go from the core up into tools/."""
    arrows = {}
    upward = []
    for path in source_files(root):
        relative = path.relative_to(root).as_posix()
        source = folder_of(relative)
        for included in INCLUDE.findall(path.read_text(errors="replace")):
            # Includes are written from the repository root ("engine/world.h"); a bare name is a
            # file of the same folder.
            target = folder_of(included) if "/" in included else source
            if target is None:
                continue
            arrows[(source, target)] = arrows.get((source, target), 0) + 1
            if source.split("/")[0] in CORE and target.split("/")[0] == "tools":
                upward.append((relative, included))
    return arrows, upward


def print_table(arrows, out=sys.stdout):
    width = max(len(f) for f in FOLDERS)
    print(f"{'from':<{width}}  {'to':<{width}}  includes", file=out)
    order = {f: i for i, f in enumerate(sorted(FOLDERS))}
    for (source, target), count in sorted(arrows.items(), key=lambda a: (order[a[0][0]], order[a[0][1]])):
        if source != target:
            print(f"{source:<{width}}  {target:<{width}}  {count:8d}", file=out)


def main():
    root = pathlib.Path(sys.argv[1]) if len(sys.argv) > 1 else pathlib.Path(__file__).resolve().parent.parent
    arrows, upward = include_arrows(root)
    print_table(arrows)
    if upward:
        print(f"\n{len(upward)} upward include(s): the core (engine/, contact/, fem/) must not include tools/",
              file=sys.stderr)
        for relative, included in upward:
            print(f"  {relative}: #include \"{included}\"", file=sys.stderr)
        return 1
    print("\nno upward include: engine/, contact/ and fem/ include nothing under tools/")
    return 0


if __name__ == "__main__":
    sys.exit(main())
