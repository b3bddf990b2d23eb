#!/usr/bin/env python3
"""A generated scene is what its generator writes: reruns the command named at the top of SCENE/scene.yaml
into a temporary folder and compares the two files byte for byte, so that the committed file and its
generator cannot drift apart.

  python3 tests/scenes/generated_scene_test.py REPOSITORY SCENE_NAME

scene.yaml's second line names the command: `#   python3 scenes/NAME/generate.py ARGS...` (run from the
repository's root); the test adds `--out TEMPORARY/scene.yaml` to it. Exit 0 equal, 1 different (the first
line that differs is printed), 2 a header without the command.
"""
import os
import shlex
import subprocess
import sys
import tempfile


def main():
    if len(sys.argv) != 3:
        print(__doc__, file=sys.stderr)
        return 2
    root, name = sys.argv[1], sys.argv[2]
    scene = os.path.join(root, "scenes", name, "scene.yaml")
    with open(scene, encoding="utf-8") as f:
        committed = f.read()
    header = committed.splitlines()[1] if committed.count("\n") >= 2 else ""
    words = shlex.split(header.lstrip("#").strip())
    generator = f"scenes/{name}/generate.py"
    if len(words) < 2 or words[0] != "python3" or words[1] != generator:
        print(f"{scene}:2: expected '#   python3 {generator} ARGS...' naming the command that wrote the file",
              file=sys.stderr)
        return 2
    with tempfile.TemporaryDirectory() as folder:
        out = os.path.join(folder, "scene.yaml")
        subprocess.run([sys.executable, os.path.join(root, generator), *words[2:], "--out", out], check=True)
        with open(out, encoding="utf-8") as f:
            written = f.read()
    if written == committed:
        print(f"{scene}: the same as `{' '.join(words)}` writes ({len(committed.splitlines())} lines)")
        return 0
    for number, (a, b) in enumerate(zip(committed.splitlines(), written.splitlines()), start=1):
        if a != b:
            print(f"{scene}:{number}: differs from what the generator writes:\n  file:      {a}\n  generator: {b}")
            return 1
    print(f"{scene}: {len(committed.splitlines())} lines, the generator writes {len(written.splitlines())}")
    return 1


if __name__ == "__main__":
    sys.exit(main())
