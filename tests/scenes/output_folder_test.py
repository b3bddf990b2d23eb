#!/usr/bin/env python3
"""The output folder is never left mixed (issue 29), through the real command line.

  sigterm, sigint, sighup
                   a run into a folder that holds a complete earlier run is stopped by the signal once its
                   frames are being written: exit 143 / 130 / 129, the earlier files all there and unchanged,
                   no temporary folder, lock or orphan frame left beside or inside it;
  replace          a finished run replaces the folder whole (a stale file of an earlier command goes), a
                   folder holding a file csim did not write is refused untouched, and a numerical failure
                   leaves no earlier run's results;
  failure          a run stopped by a numerical failure (the contact solver's failure threshold, when the box
                   of box-on-block lands) exits 2 and leaves what it computed: the rows of probes.csv and
                   the frames up to the failure, and a summary.json that says "failed", where and why;
  stale            the .OUT.tmp-PID and .OUT.old-PID folders of a killed process (SIGKILL leaves them) are
                   removed by the next run into OUT, those of a live process and every other name kept;
  concurrent       two runs into one folder: it ends up holding one of them, whole;
  compare-sigterm  a compare study stopped by SIGTERM during its second run: exit 143, the earlier study's
                   files unchanged.

usage: output_folder_test.py CSIM SCENES_DIR WORK_DIR CASE
"""
import hashlib
import json
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

    # A numerical failure at the first step: the folder is swapped in with that run's outputs alone (its
    # t = 0 row, a summary saying it failed), the earlier results gone.
    code, text = run([csim, "run", os.path.join(scenes, "incline"), "--quiet", "--out", out,
                      "--set", "parameters.gravity=1e308", "--set", "parameters.mass=1e300"])
    if code != 2 or "numerical failure" not in text:
        fail(f"the failing run: exit {code}, {text}")
    if not os.path.isdir(out) or sorted(os.listdir(out)) != ["probes.csv", "summary.json"] or leftovers(out):
        fail(f"after a numerical failure {out} holds {os.listdir(out) if os.path.isdir(out) else 'nothing'}")
    with open(os.path.join(out, "summary.json")) as f:
        summary = json.load(f)
    if summary.get("status") != "failed" or summary.get("passed") is not False:
        fail(f"the failed run's summary says status {summary.get('status')}, passed {summary.get('passed')}")


def failure(csim, scenes, work):
    out = os.path.join(work, "out")
    scene = os.path.join(scenes, "box-on-block")
    rate = 2e-3  # s: a row every 2 steps of 1e-3 s
    code, text = run([csim, "run", scene, "--quiet", "--out", out, "--set", "time.end=0.1"])
    if code not in (0, 1):  # its checks read the end of a 1 s run: judged on 0.1 s, some fail
        fail(f"the preparatory run exits {code}: {text}")
    with open(os.path.join(out, "summary.json")) as f:
        if json.load(f).get("status") != "completed":
            fail("a finished run's summary.json does not say \"status\": \"completed\"")
    # One PGS sweep and a threshold no sweep meets: the first solve with contacts fails, at the landing
    # (the box falls 1 mm: t = sqrt(2e-3 / 9.81) = 0.0143 s).
    code, text = run([csim, "run", scene, "--quiet", "--out", out, "--set", "time.end=0.1",
                      "--set", f"output.rate={rate}", "--set", "contact_solver.max_iterations=1",
                      "--set", "contact_solver.tolerance=1e-300", "--set", "contact_solver.failure_residual=1e-300"])
    if code != 2 or "numerical failure" not in text or "contact solver failed" not in text:
        fail(f"the failing run: exit {code}, {text}")
    if "outputs up to the failure are in " + out not in text:
        fail(f"the message does not say where the outputs up to the failure are: {text}")
    if leftovers(out):
        fail(f"left beside {out}: {leftovers(out)}")
    with open(os.path.join(out, "summary.json")) as f:
        summary = json.load(f)
    where = summary.get("failure", {})
    if summary.get("status") != "failed" or summary.get("passed") is not False:
        fail(f"summary.json: status {summary.get('status')}, passed {summary.get('passed')}, expected failed, false")
    if "contact solver failed" not in where.get("reason", ""):
        fail(f"summary.json: failure reason {where.get('reason')!r}")
    t_fail, step = where.get("time", -1.0), where.get("step", -1)
    if not (0.0143 <= t_fail <= 0.0143 + 2e-3) or abs(step * 1e-3 - t_fail) > 1e-9:
        fail(f"summary.json: failure at t = {t_fail} s, step {step}; expected the landing, t = 0.0143 s, t = step x 1e-3")
    counts = summary.get("check_counts", {})
    if counts.get("passed") != 0 or counts.get("failed") != 0 or not all(
            c["evaluated"] is False and (c["skipped"] or "numerical failure" in c["note"]) for c in summary["checks"]):
        fail(f"summary.json: a check of the failed run was judged: {counts}")
    with open(os.path.join(out, "probes.csv")) as f:
        times = [float(line.split(",")[0]) for line in f.readlines()[1:]]
    expected = [k * rate for k in range(int((t_fail - 1e-3) / rate + 1e-9) + 1)]  # every row before the failing step
    if len(times) != len(expected) or any(abs(a - b) > 1e-12 for a, b in zip(times, expected)):
        fail(f"probes.csv rows at {times}, expected {expected} (up to the step before the failure at {t_fail} s)")
    if abs(where.get("last_row_time", -1.0) - times[-1]) > 1e-12:
        fail(f"summary.json: last_row_time {where.get('last_row_time')}, probes.csv's last row at {times[-1]}")
    if frames_are_listed(out) != 2 * len(times):  # block and contacts, at the rows of probes.csv
        fail(f"{out}/paraview: not a frame of each series per row of probes.csv")


def stale(csim, scenes, work):
    out = os.path.join(work, "out")
    complete_run(csim, scenes, out)
    dead = subprocess.Popen(["true"])
    dead.wait()
    try:
        os.kill(dead.pid, 0)
        fail(f"process {dead.pid} exists again: cannot make a dead process id")
    except ProcessLookupError:
        pass
    live = os.getpid()
    removed = [f".out.tmp-{dead.pid}", f".out.old-{dead.pid}"]
    kept = [f".out.tmp-{live}", f".out.old-{live}", f".out.tmp-{dead.pid}x", f".out.tmp-0{dead.pid}",
            f".other.tmp-{dead.pid}", f".out.tmp{dead.pid}", f".out.new-{dead.pid}"]
    for name in removed + kept:  # as a killed run leaves them: frames and a summary inside
        os.makedirs(os.path.join(work, name, "paraview"))
        open(os.path.join(work, name, "paraview", "bar_000000.vtu"), "w").write("frame\n")
        open(os.path.join(work, name, "summary.json"), "w").write("{}\n")
    complete_run(csim, scenes, out)
    present = set(os.listdir(work))
    if present & set(removed):
        fail(f"the folders of dead process {dead.pid} are still there: {sorted(present & set(removed))}")
    if set(kept) - present:
        fail(f"removed what is not a dead process's folder: {sorted(set(kept) - present)}")
    # No destination: an old folder is the only copy of the earlier outputs (a swap cut short), kept.
    lost = os.path.join(work, "lost")
    os.makedirs(os.path.join(work, f".lost.old-{dead.pid}"))
    os.makedirs(os.path.join(work, f".lost.tmp-{dead.pid}"))
    complete_run(csim, scenes, lost)
    present = set(os.listdir(work))
    if f".lost.old-{dead.pid}" not in present or f".lost.tmp-{dead.pid}" in present:
        fail(f"beside a new destination: {sorted(n for n in present if n.startswith('.lost.'))}")


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
    elif case == "sighup":
        stopped_run(csim, scenes, work, signal.SIGHUP)
    elif case == "failure":
        failure(csim, scenes, work)
    elif case == "stale":
        stale(csim, scenes, work)
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
