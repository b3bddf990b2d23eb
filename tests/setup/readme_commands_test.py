#!/usr/bin/env python3
"""The README's two commands and .ci/run (issue 53, item 14), checked without installing or building:

  - the README starts with exactly two commands: the first sets up and runs the main job on a scene, the
    second sets up and runs the tests; .ci/run runs the second, word for word;
  - the first command's setup (`tools/setup.sh csim`, asked for its plan with CSIM_SETUP_DRY_RUN=1) builds
    the `csim` target alone and installs no package that only the tests or benchmarks use;
  - the second command's setup builds everything, tests and benchmarks, with their packages.

usage: readme_commands_test.py REPOSITORY_ROOT
"""
import os
import re
import subprocess
import sys

TEST_ONLY_PACKAGES = {"libgtest-dev", "python3-vtk9", "libbullet-dev"}


def fail(message):
    print("FAIL: " + message)
    sys.exit(1)


def setup_plan(root, setup_command):
    """Runs the setup part of a README command in dry-run mode: {'packages': set, 'build': str}."""
    environment = dict(os.environ, CSIM_SETUP_DRY_RUN="1")
    result = subprocess.run(["bash", "-c", setup_command], cwd=root, env=environment,
                            capture_output=True, text=True, timeout=60)
    if result.returncode != 0:
        fail(f"'{setup_command}' in dry-run mode exited {result.returncode}: {result.stderr.strip()}")
    plan = {}
    for line in result.stdout.splitlines():
        key, _, value = line.partition(": ")
        plan[key] = value
    if "packages" not in plan or "build" not in plan:
        fail(f"'{setup_command}' printed no plan in dry-run mode (got {result.stdout!r})")
    return {"packages": set(plan["packages"].split()), "build": plan["build"].strip()}


def main():
    root = sys.argv[1]
    with open(os.path.join(root, "README.md"), encoding="utf-8") as readme:
        text = readme.read()
    block = re.match(r"```sh\n(.*?)```", text, re.S)
    if not block:
        fail("README.md does not start with a ```sh block")
    commands = [line for line in block.group(1).splitlines() if line.strip()]
    if len(commands) != 2:
        fail(f"README.md starts with {len(commands)} commands, not 2")
    first, second = commands

    with open(os.path.join(root, ".ci", "run"), encoding="utf-8") as ci:
        ci_lines = [line.strip() for line in ci if line.strip() and not line.startswith("#")]
    if second.strip() not in ci_lines:
        fail(f".ci/run does not run the README's second command '{second}'")

    setup_first, _, job = first.partition(" && ")
    if "csim run" not in job:
        fail(f"the README's first command does not run a scene: '{first}'")
    plan = setup_plan(root, setup_first)
    if plan["build"] != "--target csim":
        fail(f"the first command builds '{plan['build']}', not the csim target alone")
    extra = sorted(plan["packages"] & TEST_ONLY_PACKAGES)
    if extra:
        fail(f"the first command installs test-only packages: {', '.join(extra)}")

    setup_second, _, tests = second.partition(" && ")
    if "ctest" not in tests:
        fail(f"the README's second command does not run ctest: '{second}'")
    plan = setup_plan(root, setup_second)
    if plan["build"] != "all":
        fail(f"the second command builds '{plan['build']}', not every target")
    missing = sorted(TEST_ONLY_PACKAGES - plan["packages"])
    if missing:
        fail(f"the second command does not install {', '.join(missing)}")
    print("readme_commands_test: the first command builds csim alone, the second everything; .ci/run is the second")


if __name__ == "__main__":
    main()
