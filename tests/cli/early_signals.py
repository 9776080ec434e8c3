#!/usr/bin/env python3
"""Stop requests during start-up (issue 33, defect 4).

Usage: early_signals.py SOFTFLOW CASE.toml WORK_DIR   (CASE: the coarse drop_short case)

Before, SIGTERM while a run was meshing or setting up ended it with exit 143
and no message, and a sweep called the case "failed (exit code 143)".

1. `run`, SIGTERM once it holds its lock (meshing): exit 5, one line naming
   the signal and start-up; no output directory, no lock file left.
2. `restart` of an interrupted run, SIGTERM during its set-up: exit 5; the
   run's files are as they were, and a restart afterwards continues it.
3. `sweep`, SIGTERM while its first case is starting: the sweep exits 5 and
   reports the case "interrupted", not "failed".
"""
import os
import shutil
import signal
import subprocess
import sys

import cli_support as support
from cli_support import fail, start, wait_for, write

INTERRUPTED = 5


def signal_when(path, process, what, timeout=60):
    """SIGTERM to `process` as soon as `path` exists."""
    wait_for(lambda: os.path.exists(path), process, what, timeout)
    process.send_signal(signal.SIGTERM)
    out, err = process.communicate(timeout=120)
    return process.returncode, out + err


def main():
    softflow, case, work = sys.argv[1], sys.argv[2], sys.argv[3]
    shutil.rmtree(work, ignore_errors=True)
    os.makedirs(work)
    with open(case) as f:
        base = f.read()
    # A finer mesh: meshing takes a few seconds, long enough to be caught in.
    slow = base.replace("equator_nodes = 16", "equator_nodes = 48").replace("far_size = 2.0",
                                                                              "far_size = 1.0")
    slow_case = os.path.join(work, "slow.toml")
    write(slow_case, slow)

    # 1. A run stopped while meshing.
    out = os.path.join(work, "meshing")
    code, text = signal_when(out + ".lock", start([softflow, "run", slow_case, "-o", out]),
                             "run during meshing")
    if code != INTERRUPTED:
        fail(f"SIGTERM during start-up: exit {code}, expected {INTERRUPTED}:\n{text}")
    if "stopped by SIGTERM during start-up" not in text:
        fail(f"no message naming the signal and the start-up:\n{text}")
    left = [n for n in os.listdir(work) if n.startswith("meshing")]
    if left:
        fail(f"a run stopped during start-up left {left}")

    # 2. A restart stopped during its set-up leaves the run as it was.
    interrupted = os.path.join(work, "interrupted")
    short_case = os.path.join(work, "short.toml")
    write(short_case, base.replace("end = 1.0", "end = 50.0"))
    result = subprocess.run([softflow, "run", short_case, "-o", interrupted, "-q",
                             "--wall-time-limit", "4"], capture_output=True, text=True)
    if result.returncode != INTERRUPTED:
        fail(f"the run to restart: exit {result.returncode}\n{result.stderr}")
    before = open(os.path.join(interrupted, "timeseries.csv")).read()
    code, text = signal_when(interrupted + ".lock",
                             start([softflow, "restart", interrupted]), "restart set-up")
    if code != INTERRUPTED or "SIGTERM" not in text:
        fail(f"SIGTERM during a restart's set-up: exit {code}:\n{text}")
    if open(os.path.join(interrupted, "timeseries.csv")).read() != before:
        fail("a restart stopped during its set-up changed timeseries.csv")
    support.run([softflow, "restart", interrupted, "-q", "--wall-time-limit", "4"],
                INTERRUPTED)

    # 3. A sweep stopped while its first case starts.
    sweep_text = slow.replace("capillary_number = 0.1", "capillary_number = [0.1, 0.2]")
    sweep_text = sweep_text.replace('name = "drop_short"', 'name = "early"')
    sweep_dir = os.path.join(work, "sweep")
    sweep_text += f'directory = "{sweep_dir}"\n'
    sweep_file = os.path.join(work, "sweep.toml")
    write(sweep_file, sweep_text)
    code, text = signal_when(os.path.join(sweep_dir, "capillary_number_0.1.lock"),
                             start([softflow, "sweep", sweep_file]), "sweep start-up")
    if code != INTERRUPTED:
        fail(f"a sweep stopped while its case started: exit {code}, expected {INTERRUPTED}:\n{text}")
    if "interrupted" not in text or "failed" in text:
        fail(f"the sweep does not report the case interrupted:\n{text}")
    print("early signals: exit 5 with a message, nothing half-written")


if __name__ == "__main__":
    main()
