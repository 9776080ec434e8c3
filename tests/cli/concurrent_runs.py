#!/usr/bin/env python3
"""One writer per output directory (issue 33, defect 1).

Usage: concurrent_runs.py SOFTFLOW CASE.toml WORK_DIR   (CASE: the coarse drop_short case)

Before the lock, a second `softflow run` into a directory another run was
writing exited 0 and the first run's results vanished.

1. Run A (Ca 0.1) is running; run B (Ca 0.2, same directory) is refused
   with exit 4 naming A's pid and what to do, and so is a restart of the
   directory; B wrote nothing there. A, stopped by SIGTERM, checkpoints
   (exit 5) and its directory holds its own case, not B's.
2. A run refused during A's start-up (meshing): the lock is taken before it.
3. progress.json saying "running" on another host (no lock here): run and
   restart are refused (exit 4) naming the host; `run --overwrite` and
   `restart --force` go ahead.
4. A run killed without any checkpoint: a fresh run says it was killed and
   how to override (exit 1), and --overwrite runs.
5. Two sweeps into one directory: the second is refused (exit 4).
"""
import json
import os
import shutil
import signal
import sys

import cli_support as support
from cli_support import fail, read_json, start, wait_for, write

BUSY = 4
INTERRUPTED = 5


def progress_step(out):
    try:
        with open(os.path.join(out, "progress.json")) as f:
            return json.load(f)["step"]
    except (OSError, ValueError, KeyError):
        return -1


def refused(args, words):
    result = support.run(args, BUSY)
    for w in words:
        if w not in result.stderr:
            fail(f"{' '.join(args)}: the refusal does not name '{w}':\n{result.stderr}")
    return result


def main():
    softflow, case, work = sys.argv[1], sys.argv[2], sys.argv[3]
    shutil.rmtree(work, ignore_errors=True)
    os.makedirs(work)
    with open(case) as f:
        base = f.read()
    long_a = base.replace("end = 1.0", "end = 50.0")
    write(os.path.join(work, "a.toml"), long_a)
    write(os.path.join(work, "b.toml"), long_a.replace("capillary_number = 0.1",
                                                       "capillary_number = 0.2"))
    a_case, b_case = os.path.join(work, "a.toml"), os.path.join(work, "b.toml")
    out = os.path.join(work, "out")

    # 1. A runs; B and a restart are refused; A's results are A's.
    a = start([softflow, "run", a_case, "-o", out, "-q"])
    wait_for(lambda: progress_step(out) >= 2, a, "run A reaching step 2")
    refused([softflow, "run", b_case, "-o", out, "-q"], [str(a.pid), "softflow run", "-o"])
    refused([softflow, "run", b_case, "-o", out, "-q", "--overwrite"], [str(a.pid)])
    refused([softflow, "restart", out, "-q"], [str(a.pid)])
    a.send_signal(signal.SIGTERM)
    a.communicate(timeout=120)
    if a.returncode != INTERRUPTED:
        fail(f"run A stopped by SIGTERM: exit {a.returncode}, expected {INTERRUPTED}")
    with open(os.path.join(out, "case.toml")) as f:
        if "capillary_number = 0.1" not in f.read():
            fail("run A's case.toml was replaced while it ran")
    if read_json(out)["status"] != "interrupted":
        fail("run A's summary does not say interrupted")
    if os.path.exists(out + ".lock"):
        fail("the lock file outlived its run")

    # 2. Refused while A is still meshing: no progress.json yet, the lock is.
    fresh = os.path.join(work, "fresh")
    a = start([softflow, "run", a_case, "-o", fresh, "-q"])
    wait_for(lambda: os.path.exists(fresh + ".lock"), a, "run A taking its lock")
    refused([softflow, "run", b_case, "-o", fresh, "-q"], ["softflow run"])
    a.send_signal(signal.SIGTERM)
    a.communicate(timeout=120)

    # 3. A run recorded as running on another host.
    elsewhere = os.path.join(work, "elsewhere")
    shutil.copytree(out, elsewhere)
    os.remove(os.path.join(elsewhere, "summary.json"))
    progress = read_json(elsewhere, "progress.json")
    progress.update({"status": "running", "host": "node-that-is-not-this-one", "pid": 4242})
    write(os.path.join(elsewhere, "progress.json"), json.dumps(progress))
    refused([softflow, "run", b_case, "-o", elsewhere, "-q"],
            ["node-that-is-not-this-one", "4242", "--overwrite"])
    refused([softflow, "restart", elsewhere, "-q"], ["node-that-is-not-this-one", "--force"])
    short = os.path.join(work, "short.toml")
    write(short, base.replace("end = 1.0", "end = 0.1"))
    copy = elsewhere + "_copy"
    shutil.copytree(elsewhere, copy)
    support.run([softflow, "run", short, "-o", elsewhere, "-q", "--overwrite"], 0)
    if read_json(elsewhere)["status"] != "completed":
        fail("run --overwrite over another host's stale run did not complete")
    restart = start([softflow, "restart", copy, "-q", "--force", "--wall-time-limit", "3"])
    restart.communicate(timeout=120)
    if restart.returncode not in (0, INTERRUPTED):
        fail(f"restart --force: exit {restart.returncode}")

    # 4. Killed before any checkpoint: say so, and --overwrite goes ahead.
    killed = os.path.join(work, "killed")
    a = start([softflow, "run", a_case, "-o", killed, "-q"])
    wait_for(lambda: progress_step(killed) >= 1, a, "run A reaching step 1")
    a.send_signal(signal.SIGKILL)
    a.communicate(timeout=60)
    if os.path.exists(os.path.join(killed, "checkpoint.h5")):
        fail("the killed run had a checkpoint; the test needs one without")
    result = support.run([softflow, "run", short, "-o", killed, "-q"], 1)
    for w in ("killed", "no checkpoint", "--overwrite"):
        if w not in result.stderr:
            fail(f"a run over a killed one without checkpoint does not say '{w}':\n{result.stderr}")
    support.run([softflow, "run", short, "-o", killed, "-q", "--overwrite"], 0)

    # 5. Two sweeps into one directory.
    sweep_text = long_a.replace("capillary_number = 0.1", "capillary_number = [0.1, 0.2]")
    sweep_text = sweep_text.replace('name = "drop_short"', 'name = "sweep"')
    sweep_text += f'\ndirectory = "{os.path.join(work, "sweep")}"\n'
    sweep_file = os.path.join(work, "sweep.toml")
    write(sweep_file, sweep_text)
    first = start([softflow, "sweep", sweep_file, "-q"])
    wait_for(lambda: os.path.exists(os.path.join(work, "sweep.lock")), first, "the first sweep")
    refused([softflow, "sweep", sweep_file, "-q"], ["softflow sweep"])
    first.send_signal(signal.SIGTERM)
    first.communicate(timeout=120)
    print("concurrent runs: every second writer refused; results kept")


if __name__ == "__main__":
    main()
