#!/usr/bin/env python3
"""Issue 53: a file csim cannot write is reported with the system's reason and named in the output folder
the user asked for, never in the temporary folder that is gone when the command ends; a sweep's case that
cannot write its outputs is an `environment failure`, not `bad input`.

The disk is made full for csim alone, without root: RLIMIT_FSIZE caps the size of every file it writes
(SIGXFSZ ignored, so that write(2) fails with EFBIG, "File too large", as a full disk fails with ENOSPC).
The write path is the same: tools/output/atomic_file.cpp (its unit test fills /dev/full for ENOSPC itself).

  run    csim run of an elastic scene with ParaView frames: exit 2, the message names --out and the reason,
         and an earlier run's folder is left as it was
  sweep  csim sweep of two cases whose probes.csv exceeds the cap: each row `environment failure`, exit
         status 2 in the row, the message names the sweep's folder; the sweep exits 1 (some case did not
         pass) and writes sweep.csv (small enough to fit)

usage: full_disk_test.py CSIM SCENES_DIR WORK_DIR CASE
"""
import csv
import io
import os
import resource
import shutil
import signal
import subprocess
import sys


def fail(message):
    print("FAIL: " + message)
    sys.exit(1)


def capped(limit):
    def apply():
        signal.signal(signal.SIGXFSZ, signal.SIG_IGN)  # inherited across exec: write(2) then fails with EFBIG
        resource.setrlimit(resource.RLIMIT_FSIZE, (limit, resource.getrlimit(resource.RLIMIT_FSIZE)[1]))
    return apply


def run(command, limit=None):
    process = subprocess.run(command, capture_output=True, text=True, timeout=300,
                             preexec_fn=capped(limit) if limit else None)
    print(f"$ {' '.join(command)}{f' (files capped at {limit} bytes)' if limit else ''}: exit {process.returncode}")
    print(process.stderr.strip())
    return process


def snapshot(folder):
    out = {}
    for root, _, files in os.walk(folder):
        for name in files:
            path = os.path.join(root, name)
            out[os.path.relpath(path, folder)] = open(path, "rb").read()
    return out


def main():
    csim, scenes, work, case = sys.argv[1:5]
    shutil.rmtree(work, ignore_errors=True)
    os.makedirs(work)
    out = os.path.join(work, "out")
    if case == "run":
        command = [csim, "run", os.path.join(scenes, "sdnv104-quad4"), "--quiet", "--set", "time.end=0.005",
                   "--set", "output.rate=0.001", "--out", out]
        earlier = run(command)
        if earlier.returncode not in (0, 1):
            fail("the earlier run did not write its folder")
        before = snapshot(out)
        process = run(command, limit=5000)  # a frame of the shoe is 7 kB
        if process.returncode != 2:
            fail(f"exit {process.returncode}, expected 2")
        lines = [line for line in process.stderr.splitlines() if line.startswith("csim: ")]
        if not lines or not lines[-1].startswith("csim: " + out + "/") or ": cannot write: File too large" not in lines[-1]:
            fail(f"the message does not name a file in {out} and the system's reason: {lines}")
        if ".tmp" in lines[-1]:
            fail(f"the message names the temporary folder: {lines[-1]}")
        if snapshot(out) != before:
            fail("the earlier run's folder was changed")
    elif case == "sweep":
        process = run([csim, "sweep", os.path.join(scenes, "stress-block"), "--grid", "parameters.mu=0.3,0.4",
                       "--out", out], limit=6000)
        if process.returncode != 1:
            fail(f"exit {process.returncode}, expected 1 (some case did not pass)\n{process.stdout}")
        text = open(os.path.join(out, "sweep.csv")).read()
        rows = list(csv.DictReader(io.StringIO("\n".join(l for l in text.splitlines() if not l.startswith("#")))))
        if len(rows) != 2:
            fail(f"{len(rows)} rows, expected 2")
        for row in rows:
            if row["status"] != "environment failure" or row["exit_status"] != "2":
                fail(f"case {row['case']}: status {row['status']!r}, exit_status {row['exit_status']}, expected "
                     f"'environment failure', 2")
            if not row["message"].startswith(out + "/case-000" + row["case"] + "/") or "File too large" not in row["message"]:
                fail(f"case {row['case']}: the message does not name the case's folder in {out} and the reason: "
                     f"{row['message']!r}")
        if "environment failure" not in text.split("\n# C,")[0]:
            fail("the '#' lines do not explain the status")
    else:
        fail("unknown case " + case)
    left = [name for name in os.listdir(work) if name.startswith(".")]
    if left:
        fail(f"left beside the output folder: {left}")
    print("PASS")


if __name__ == "__main__":
    main()
