#!/usr/bin/env python3
"""The output folder is never left mixed (issue 29), through the real command line.

  sigterm, sigint  a run into a folder that holds a complete earlier run is stopped by the signal once its
                   frames are being written: exit 143 / 130, the earlier files all there and unchanged, no
                   temporary folder, lock or orphan frame left beside or inside it;
  replace          a finished run replaces the folder whole (a stale file of an earlier command goes), a
                   folder holding a file csim did not write is refused untouched, and a numerical failure
                   leaves the folder empty rather than showing an earlier run's results;
  concurrent       two runs into one folder: it ends up holding one of them, whole;
  compare-sigterm  a compare study stopped by SIGTERM during its second run: exit 143, the earlier study's
                   files unchanged.

usage: output_folder_test.py CSIM SCENES_DIR WORK_DIR CASE
"""
import hashlib
import os
import re
import shutil
import signal
import subprocess
import sys
import time

BAR = "fe-free-vibration"  # an elastic bar: ParaView frames, about 1e-4 s of CPU a step
WAIT_LIMIT = 120.0         # s, a bound on waiting for a child to reach a state, never an assertion


def fail(message):
    print("FAIL: " + message)
    sys.exit(1)


def snapshot(folder):
    """Relative path -> SHA-256 of every file under folder."""
    files = {}
    for root, _, names in os.walk(folder):
        for name in names:
            path = os.path.join(root, name)
            with open(path, "rb") as f:
                files[os.path.relpath(path, folder)] = hashlib.sha256(f.read()).hexdigest()
    return files


def leftovers(out):
    """What a command may leave beside OUT: .OUT.tmp-PID, .OUT.old-PID, .OUT.lock."""
    parent, name = os.path.split(out)
    return sorted(n for n in os.listdir(parent) if n.startswith("." + name + "."))


def run(command):
    result = subprocess.run(command, capture_output=True, text=True, timeout=WAIT_LIMIT)
    return result.returncode, result.stdout + result.stderr


def start(command, **options):
    # SIGINT as the default action in the child whatever our own starter ignored: csim keeps an ignored one.
    return subprocess.Popen(command, preexec_fn=lambda: signal.signal(signal.SIGINT, signal.SIG_DFL), **options)


def complete_run(csim, scenes, out, end="3e-4"):
    code, text = run([csim, "run", os.path.join(scenes, BAR), "--quiet", "--out", out, "--set", f"time.end={end}"])
    if code != 0:
        fail(f"the preparatory run exits {code}: {text}")


def frames_are_listed(out):
    """Every .vtu in out/paraview is listed by a .pvd there, and every listed one exists."""
    folder = os.path.join(out, "paraview")
    present = {n for n in os.listdir(folder) if n.endswith(".vtu")}
    listed = set()
    for pvd in (n for n in os.listdir(folder) if n.endswith(".pvd")):
        with open(os.path.join(folder, pvd)) as f:
            listed |= set(re.findall(r'file="([^"]+)"', f.read()))
    if present != listed:
        fail(f"{folder}: frames not listed {sorted(present - listed)[:5]}, listed but missing {sorted(listed - present)[:5]}")
    return len(listed)


def stopped_run(csim, scenes, work, signal_number):
    out = os.path.join(work, "out")
    complete_run(csim, scenes, out)
    before = snapshot(out)
    # Long enough never to finish here (1e7 steps); a frame every 100 steps.
    process = start([csim, "run", os.path.join(scenes, BAR), "--quiet", "--out", out, "--set", "time.end=10",
                     "--set", "output.rate=1e-4"], stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    frames = os.path.join(work, f".out.tmp-{process.pid}", "paraview")
    waited = 0.0
    while not (os.path.isdir(frames) and len(os.listdir(frames)) > 4):  # the time loop is writing frames
        if process.poll() is not None or waited > WAIT_LIMIT:
            process.kill()
            fail(f"the run never wrote frames into {frames} (exit {process.poll()}): {process.communicate()}")
        time.sleep(0.05)
        waited += 0.05
    process.send_signal(signal_number)
    stdout, stderr = process.communicate(timeout=WAIT_LIMIT)
    expected = 128 + signal_number
    if process.returncode != expected:
        fail(f"exit {process.returncode} after signal {signal_number}, expected {expected}: {stderr}")
    if "stopped by" not in stderr:
        fail(f"no message saying the run was stopped: {stderr}")
    if leftovers(out):
        fail(f"left beside {out}: {leftovers(out)}")
    after = snapshot(out)
    if after != before:
        changed = sorted(set(before) ^ set(after) | {k for k in before if after.get(k) != before[k]})
        fail(f"the earlier run's files changed: {changed[:10]}")
    frames_are_listed(out)


def replace(csim, scenes, work):
    out = os.path.join(work, "out")
    complete_run(csim, scenes, out)
    # A stale file of an earlier command (compare writes work_precision.csv) and an orphan frame.
    open(os.path.join(out, "work_precision.csv"), "w").write("stale\n")
    open(os.path.join(out, "paraview", "bar_000099.vtu"), "w").write("stale\n")
    complete_run(csim, scenes, out, end="2e-4")
    for stale in ("work_precision.csv", os.path.join("paraview", "bar_000099.vtu")):
        if os.path.exists(os.path.join(out, stale)):
            fail(f"{stale} of an earlier command survived a complete run")
    if frames_are_listed(out) != 2 * 21:  # bar and contacts, t = 0 and every 1e-5 s to 2e-4 s
        fail("the new run's frames are not all there")
    if leftovers(out):
        fail(f"left beside {out}: {leftovers(out)}")

    # A file of the user's: refused before any step, the folder untouched.
    open(os.path.join(out, "notes.txt"), "w").write("mine\n")
    before = snapshot(out)
    code, text = run([csim, "run", os.path.join(scenes, BAR), "--quiet", "--out", out, "--set", "time.end=3e-4"])
    if code != 2 or "holds notes.txt, which csim did not write" not in text:
        fail(f"a folder with a file of the user's: exit {code}, {text}")
    if snapshot(out) != before or leftovers(out):
        fail("the refused folder was touched")
    os.remove(os.path.join(out, "notes.txt"))

    # A numerical failure (run.h: no outputs): the folder is swapped in empty, the earlier results gone.
    code, text = run([csim, "run", os.path.join(scenes, "incline"), "--quiet", "--out", out,
                      "--set", "parameters.gravity=1e308", "--set", "parameters.mass=1e300"])
    if code != 2 or "numerical failure" not in text:
        fail(f"the failing run: exit {code}, {text}")
    if not os.path.isdir(out) or os.listdir(out) or leftovers(out):
        fail(f"after a numerical failure {out} holds {os.listdir(out) if os.path.isdir(out) else 'nothing'}")


def concurrent(csim, scenes, work):
    out = os.path.join(work, "out")
    runs = [start([csim, "run", os.path.join(scenes, BAR), "--quiet", "--out", out, "--set", f"time.end={end}"],
                  stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True) for end in ("3e-4", "2e-4")]
    for process in runs:
        _, stderr = process.communicate(timeout=WAIT_LIMIT)
        if process.returncode != 0:
            fail(f"a concurrent run exits {process.returncode}: {stderr}")
    frames = frames_are_listed(out)
    with open(os.path.join(out, "probes.csv")) as f:
        rows = len(f.readlines()) - 1
    if frames != 2 * rows or rows not in (21, 31):
        fail(f"{out} mixes two runs: {frames} frames for {rows} rows of probes.csv")
    if leftovers(out):
        fail(f"left beside {out}: {leftovers(out)}")


def compare_stopped(csim, scenes, work):
    out = os.path.join(work, "out")
    scene = os.path.join(scenes, "incline")
    code, text = run([csim, "compare", scene, "--integrators", "moreau-jean", "--steps", "1e-2", "--repeats", "1",
                      "--out", out])
    if code != 0:
        fail(f"the preparatory compare exits {code}: {text}")
    before = snapshot(out)
    # The second configuration takes 1e8 steps: the signal comes while it runs.
    process = start([csim, "compare", scene, "--integrators", "moreau-jean", "--steps", "1e-2,1e-6", "--repeats", "1",
                     "--set", "time.end=100", "--out", out], stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    for line in process.stdout:
        if line.startswith("moreau-jean"):  # the first configuration's row: the second one is running
            break
    process.send_signal(signal.SIGTERM)
    _, stderr = process.communicate(timeout=WAIT_LIMIT)
    if process.returncode != 143:
        fail(f"compare exits {process.returncode} after SIGTERM, expected 143: {stderr}")
    if snapshot(out) != before or leftovers(out):
        fail(f"the earlier study's files changed, or {leftovers(out)} left beside them")


def main():
    csim, scenes, work, case = sys.argv[1:5]
    shutil.rmtree(work, ignore_errors=True)
    os.makedirs(work)
    if case == "sigterm":
        stopped_run(csim, scenes, work, signal.SIGTERM)
    elif case == "sigint":
        stopped_run(csim, scenes, work, signal.SIGINT)
    elif case == "replace":
        replace(csim, scenes, work)
    elif case == "concurrent":
        concurrent(csim, scenes, work)
    elif case == "compare-sigterm":
        compare_stopped(csim, scenes, work)
    else:
        fail(f"unknown case {case}")
    print(f"{case}: ok")


if __name__ == "__main__":
    main()
