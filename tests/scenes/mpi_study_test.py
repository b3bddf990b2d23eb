#!/usr/bin/env python3
"""A study gives the same CSV whatever its placement (issue 33): run serially, under `mpirun -np 1` and under
`mpirun -np 2`, its CSV is the same apart from the wall-time columns and the `# placement` line, which must
name the placement (so that a run that fell back to serial cannot pass for a distributed one).

  stress   the stress-block CI sweep (csim stress ... --sweeps stress-ci.yaml: stability.csv)
  compare  scenes/sdnv104-rigid, moreau-jean at 2 steps and ida at 1 tolerance, 1 repeat (work_precision.csv)
  sweep    csim sweep on the same CI sweeps file, and a grid of mu by integrator (sweep.csv, and every
           case-NNNN/summary.json the same but for its wall time)

  signal-mpirun, signal-ranks
           issue 53: a sweep under `mpirun -np 2` stopped by SIGINT, sent to mpirun (as Ctrl-C or a kill of
           mpirun does) or to the ranks themselves (as srun, scancel or a kill of the ranks does): every rank
           stops at a step boundary and leaves at once, the output folder as it was and nothing left beside
           it. Signalled, OpenMPI's mpirun (4.1) sends its ranks SIGTERM and exits 1 whatever they do (its
           own status, docs/contract.md); when the ranks are signalled, they exit 130 and mpirun reports it.
           A stopped rank must not wait for the launcher, which is taking the job down: MPI_Finalize did,
           until mpirun killed the rank or let it go 1-2 s later. signal-ranks shows it without a clock:
           mpirun is held by SIGSTOP while its ranks are signalled, and they must end all the same (30 s
           allowed; a rank in MPI_Finalize waits for mpirun for ever), before mpirun gets SIGCONT.

usage: mpi_study_test.py CSIM MPIEXEC SCENES_DIR WORK_DIR CASE
"""
import csv
import glob
import io
import json
import os
import shutil
import signal
import subprocess
import sys
import time

WALL_COLUMNS = {"wall_time", "wall_time_median", "wall_times"}


def fail(message):
    print("FAIL: " + message)
    sys.exit(1)


def launchers(mpiexec):
    """Serial, then mpirun with 1 and 2 ranks, one per core (oversubscribed, unbound, on a 1-core machine)."""
    place = ["--bind-to", "core"] if (os.cpu_count() or 1) >= 2 else ["--oversubscribe", "--bind-to", "none"]
    env = dict(os.environ, OMPI_ALLOW_RUN_AS_ROOT="1", OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1",
               OMPI_MCA_rmaps_base_oversubscribe="1" if "--oversubscribe" in place else "0")
    return [("serial", [], "serial (1 process)", os.environ),
            ("np1", [mpiexec, "-np", "1"] + place, "MPI, 1 rank", env),
            ("np2", [mpiexec, "-np", "2"] + place, "MPI, 2 ranks", env)]


def table(path):
    """The '# placement' line and the rows of a CSV without its wall-time columns."""
    text = open(path).read()
    placement = [line for line in text.splitlines() if line.startswith("# placement: ")]
    comments = [line for line in text.splitlines() if line.startswith("#") and not line.startswith("# placement")]
    rows = list(csv.reader(io.StringIO("\n".join(line for line in text.splitlines() if not line.startswith("#")))))
    if not rows:
        fail(f"{path}: no header row")
    keep = [i for i, name in enumerate(rows[0]) if name not in WALL_COLUMNS]
    if len(keep) == len(rows[0]):
        fail(f"{path}: no wall-time column among {rows[0]}")
    return (placement[0] if placement else None), comments, [[row[i] for i in keep] for row in rows]


def summaries(folder):
    """case-NNNN/summary.json without its wall times, by case folder."""
    out = {}
    for name in sorted(os.listdir(folder)):
        if name.startswith("case-"):
            summary = json.load(open(os.path.join(folder, name, "summary.json")))
            for key in ("wall_time", "steps_per_second", "timers"):  # the clock's, not the computation's
                summary.pop(key, None)
            out[name] = summary
    return out


def children(pid):
    """The process ids whose parent is pid."""
    out = []
    for entry in os.listdir("/proc"):
        if entry.isdigit():
            try:
                fields = open(f"/proc/{entry}/stat").read().rsplit(")", 1)[1].split()
            except OSError:
                continue
            if int(fields[1]) == pid:
                out.append(int(entry))
    return out


def signal_test(csim, mpiexec, scenes, work, target):
    """A sweep of long cases stopped by SIGINT to mpirun or to its ranks (see the file's header)."""
    block = os.path.join(scenes, "stress-block")
    out = os.path.join(work, "sweep")
    earlier = subprocess.run([csim, "sweep", block, "--set", "time.end=0.01", "--grid", "parameters.mu=0.3",
                              "--out", out], capture_output=True, text=True, timeout=120)
    if earlier.returncode not in (0, 1):  # it wrote its folder; its checks are not the point
        fail(f"the earlier serial sweep: exit {earlier.returncode}\n{earlier.stderr}")
    before = open(os.path.join(out, "sweep.csv")).read()
    _, launcher, _, env = launchers(mpiexec)[2]  # mpiexec -np 2, one rank per core
    command = (launcher + [csim, "sweep", block,
               "--set", "time.end=1e4", "--grid", "parameters.mu=0.1,0.2,0.3,0.4", "--out", out])
    process = subprocess.Popen(command, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, env=env)
    temporary = os.path.join(work, ".sweep.tmp-*")
    for _ in range(600):  # the study has opened its folder: MPI is up on rank 0
        if glob.glob(temporary) or process.poll() is not None:
            break
        time.sleep(0.1)
    time.sleep(1.0)  # the cases under way on both ranks (a stop before them is handled alike)
    if process.poll() is not None:
        fail(f"the sweep ended before the signal: exit {process.returncode}\n{process.communicate()}")
    ranks = children(process.pid)
    if len(ranks) != 2:
        fail(f"mpirun {process.pid} has {len(ranks)} children, expected 2 ranks")
    if target == "ranks":
        process.send_signal(signal.SIGSTOP)  # the launcher answers nothing until SIGCONT
        for pid in ranks:
            os.kill(pid, signal.SIGINT)
    else:
        process.send_signal(signal.SIGINT)

    def running(pid):  # neither gone nor a zombie
        try:
            return open(f"/proc/{pid}/stat").read().rsplit(")", 1)[1].split()[0] != "Z"
        except OSError:
            return False
    for _ in range(300):
        if not any(running(pid) for pid in ranks):
            break
        time.sleep(0.1)
    hung = [pid for pid in ranks if running(pid)]
    if target == "ranks":
        process.send_signal(signal.SIGCONT)
    try:
        stdout, stderr = process.communicate(timeout=60)
    except subprocess.TimeoutExpired:
        process.kill()
        stdout, stderr = process.communicate()
        fail(f"mpirun did not return within 60 s of SIGINT to the {target}\n{stderr}")
    if hung:
        fail(f"ranks {hung} still ran 30 s after SIGINT to the {target} (waiting for mpirun in MPI's shutdown)"
             f"\n{stderr}")
    print(f"SIGINT to the {target}: exit {process.returncode}\n{stderr.strip()}")
    expected = 1 if target == "mpirun" else 128 + signal.SIGINT
    if process.returncode != expected:
        fail(f"exit {process.returncode}, expected {expected}\n{stdout}\n{stderr}")
    said = "csim: stopped by " + ("SIGTERM" if target == "mpirun" else "SIGINT")  # mpirun sends SIGTERM
    if said not in stderr:
        fail(f"rank 0 did not say '{said}':\n{stderr}")
    left = [name for name in os.listdir(work) if name.startswith(".")]
    if left:
        fail(f"left beside the output folder: {left}")
    if open(os.path.join(out, "sweep.csv")).read() != before:
        fail("the earlier sweep.csv was changed")
    print(f"PASS: SIGINT to the {target}: exit {process.returncode}, the output folder as it was")


def main():
    csim, mpiexec, scenes, work, case = sys.argv[1:6]
    shutil.rmtree(work, ignore_errors=True)
    os.makedirs(work)
    if case.startswith("signal-"):
        signal_test(csim, mpiexec, scenes, work, case[len("signal-"):])
        return
    block, rigid = os.path.join(scenes, "stress-block"), os.path.join(scenes, "sdnv104-rigid")
    ci = os.path.join(block, "stress-ci.yaml")
    if case == "stress":
        arguments, written, expected_status = ["stress", block, "--sweeps", ci], "stability.csv", 0
    elif case == "compare":
        arguments = ["compare", rigid, "--integrators", "moreau-jean,ida", "--steps", "1e-3,5e-4",
                     "--tolerances", "1e-6", "--repeats", "1"]
        written, expected_status = "work_precision.csv", 0
    elif case == "sweep":
        arguments, written, expected_status = ["sweep", block, "--sweeps", ci], "sweep.csv", 1
    elif case == "sweep-grid":
        arguments = ["sweep", block, "--grid", "parameters.mu=0,0.3,10", "--grid", "integrator.type=moreau-jean,ida",
                     "--set", "time.end=0.5"]
        written, expected_status = "sweep.csv", None
    else:
        fail("unknown case " + case)
    results = []
    for name, launcher, placement, env in launchers(mpiexec):
        out = os.path.join(work, name)
        process = subprocess.run(launcher + [csim] + arguments + ["--out", out], capture_output=True, text=True,
                                 env=env, timeout=600)
        print(f"{name}: exit {process.returncode}; {process.stdout.strip().splitlines()[-1:]}")
        if expected_status is not None and process.returncode != expected_status:
            fail(f"{name}: exit {process.returncode}, expected {expected_status}\n{process.stdout}\n{process.stderr}")
        if expected_status is None:
            expected_status = process.returncode
        if process.returncode != expected_status:
            fail(f"{name}: exit {process.returncode}, the serial run's was {expected_status}\n{process.stderr}")
        found, comments, rows = table(os.path.join(out, written))
        if not found or not found.startswith("# placement: " + placement):
            fail(f"{name}: placement line {found!r}, expected it to start with '# placement: {placement}'")
        if name == "np2" and "rank 1" not in found:
            fail(f"{name}: the placement names no rank 1: {found!r}")
        results.append((name, comments, rows, summaries(out)))
    serial = results[0]
    if len(serial[2]) < 3:
        fail(f"the serial table has {len(serial[2]) - 1} rows")
    for name, comments, rows, cases in results[1:]:
        if comments != serial[1]:
            fail(f"{name}: the comment lines differ from the serial run's:\n{comments}\n{serial[1]}")
        if rows != serial[2]:
            for a, b in zip(rows, serial[2]):
                if a != b:
                    fail(f"{name}: a row differs from the serial run's:\n{a}\n{b}")
            fail(f"{name}: {len(rows)} rows, the serial run has {len(serial[2])}")
        if cases != serial[3]:
            fail(f"{name}: the case folders differ from the serial run's ({sorted(cases)} vs {sorted(serial[3])})")
    if case.startswith("sweep") and len(serial[3]) != len(serial[2]) - 1:
        fail(f"{len(serial[3])} case folders for {len(serial[2]) - 1} cases")
    print(f"PASS: {len(serial[2]) - 1} rows, identical serially and on 1 and 2 ranks but for the wall times")


if __name__ == "__main__":
    main()
