#!/usr/bin/env python3
"""`softflow sweep`: a case file with lists runs every combination, each in its
own subdirectory, N at a time, and tabulates the final values beside theory;
re-running skips finished cases and resumes interrupted ones.

Usage: sweep.py SOFTFLOW CASE.toml WORK_DIR [--quick]   (CASE: the coarse drop_short case)
--quick leaves out part 3 (about two thirds of the run time): the default
test suite runs 1, 2 and 4, the slow one everything.

1. Two capillary numbers x two viscosity ratios, --jobs 2: four directories
   named after the values; every row of sweep.csv agrees with its case's
   summary.json (the varied values as the case resolved them, D, theta, the
   theory); sweep.md and sweep.png are written.
2. Re-running it changes nothing: every case is skipped.
3. A sweep stopped by SIGTERM (passed on to the running case, which
   checkpoints) exits 5; re-running it restarts that case from its
   checkpoint and runs the rest; the restarted case's time series equals the
   same case's in the uninterrupted sweep.
   With --wall-time-limit, the running case checkpoints in time and no
   further case starts.
4. `run` on a sweep file, an empty list and an invalid value are refused
   with messages naming the parameter.
"""
import csv
import json
import os
import re
import shutil
import signal
import subprocess
import sys
import time

INTERRUPTED = 5


def fail(message):
    print("FAIL: " + message)
    sys.exit(1)


def write(path, text):
    with open(path, "w") as f:
        f.write(text)


def sweep_case(base, directory, end="0.4"):
    text = base.replace("capillary_number = 0.1", "capillary_number = [0.1, 0.2]")
    text = text.replace("viscosity_ratio = 1.0", "viscosity_ratio = [1.0, 2.0]")
    text = text.replace("end = 1.0", f"end = {end}")
    return text.replace("fields = false", f'fields = false\ndirectory = "{directory}"')


def read_csv(path):
    with open(path) as f:
        return list(csv.DictReader(f))


def main(softflow, case_source, work, quick=False):
    shutil.rmtree(work, ignore_errors=True)
    os.makedirs(work)
    base = open(case_source).read()

    # 1. The sweep.
    first = os.path.join(work, "first")
    write(os.path.join(work, "first.toml"), sweep_case(base, first))
    result = subprocess.run([softflow, "sweep", os.path.join(work, "first.toml"), "--jobs", "2"],
                            capture_output=True, text=True)
    if result.returncode != 0:
        fail(f"sweep: exit code {result.returncode}\n{result.stdout}{result.stderr}")
    labels = [f"capillary_number_{ca}__viscosity_ratio_{lam}"
              for ca in ("0.1", "0.2") for lam in ("1", "2")]
    rows = read_csv(os.path.join(first, "sweep.csv"))
    if [r["case"] for r in rows] != labels:
        fail(f"sweep.csv lists {[r['case'] for r in rows]}, expected {labels}")
    for r in rows:
        with open(os.path.join(first, r["case"], "summary.json")) as f:
            summary = json.load(f)
        theory = summary["theory"][0]
        final = summary["final"][0]
        if summary["status"] != "completed" or r["status"] != "completed":
            fail(f"{r['case']}: status {summary['status']} / {r['status']}")
        if (float(r["capillary_number"]) != theory["capillary_number"]
                or float(r["viscosity_ratio"]) != theory["viscosity_ratio"]):
            fail(f"{r['case']}: the table's values are not the ones the case ran with")
        for column, value in (("D", final["D"]), ("theta_deg", final["theta_deg"]),
                              ("taylor_D", theory["taylor_D"]),
                              ("chaffey_brenner_theta_deg", theory["chaffey_brenner_theta_deg"])):
            if abs(float(r[column]) - value) > 1e-5 * abs(value):
                fail(f"{r['case']}: {column} {r[column]} in the table, {value} in summary.json")
    ds = sorted({r["D"] for r in rows})
    if len(ds) != 4:
        fail(f"the four cases did not give four different D: {ds}")
    for name in ("sweep.md", "sweep.png", "sweep_theory.csv"):
        if not os.path.exists(os.path.join(first, name)):
            fail(f"missing {name}")
    print(f"sweep of 4 cases: {result.stdout.strip().splitlines()[-1]}")

    # 2. Nothing to do the second time.
    stamps = {l: os.path.getmtime(os.path.join(first, l, "timeseries.csv")) for l in labels}
    result = subprocess.run([softflow, "sweep", os.path.join(work, "first.toml")],
                            capture_output=True, text=True)
    if result.returncode != 0 or result.stdout.count("completed earlier, skipped") != 4:
        fail(f"re-running a finished sweep did not skip every case:\n{result.stdout}{result.stderr}")
    if any(os.path.getmtime(os.path.join(first, l, "timeseries.csv")) != stamps[l] for l in labels):
        fail("re-running a finished sweep rewrote a case")

    if not quick:
        stop_and_resume(softflow, base, work, first, labels, rows)
    refusals(softflow, base, work)
    return 0


def stop_and_resume(softflow, base, work, first, labels, rows):
    # 3. Stopped mid-case by SIGTERM, then resumed.
    second = os.path.join(work, "second")
    write(os.path.join(work, "second.toml"), sweep_case(base, second))
    process = subprocess.Popen([softflow, "sweep", os.path.join(work, "second.toml"), "-j", "1"],
                               stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    progress = os.path.join(second, labels[0], "progress.json")
    deadline = time.time() + 120
    while process.poll() is None and time.time() < deadline:
        try:
            with open(progress) as f:
                if json.load(f)["step"] >= 3:
                    process.send_signal(signal.SIGTERM)
                    break
        except (OSError, ValueError, KeyError):
            pass
        time.sleep(0.01)
    stdout, stderr = process.communicate(timeout=120)
    if process.returncode != INTERRUPTED:
        fail(f"the stopped sweep exited with {process.returncode}, expected {INTERRUPTED}\n"
             f"{stdout}{stderr}")
    with open(os.path.join(second, labels[0], "summary.json")) as f:
        stopped_at = json.load(f)["steps"]
    if os.path.exists(os.path.join(second, labels[1])):
        fail("the stopped sweep went on to start another case")
    result = subprocess.run([softflow, "sweep", os.path.join(work, "second.toml"), "-j", "2"],
                            capture_output=True, text=True)
    if result.returncode != 0 or "restarted from its checkpoint" not in result.stdout:
        fail(f"the resumed sweep: exit {result.returncode}\n{result.stdout}{result.stderr}")
    a = read_csv(os.path.join(first, labels[0], "timeseries.csv"))
    b = read_csv(os.path.join(second, labels[0], "timeseries.csv"))
    if len(a) != len(b) or any(x[c] != y[c] for x, y in zip(a, b) for c in x if c != "step_seconds"):
        fail("the resumed case's time series differs from the uninterrupted sweep's")
    if [r["D"] for r in read_csv(os.path.join(second, "sweep.csv"))] != [r["D"] for r in rows]:
        fail("the resumed sweep's table differs from the uninterrupted one's")
    print(f"sweep stopped by SIGTERM at step {stopped_at} of its first case, resumed: same table")

    # 3b. The wall-time limit: the running case checkpoints before it, no new one starts.
    limited = os.path.join(work, "limited")
    # A case far longer than the limit (600 steps), so that it is always cut short.
    write(os.path.join(work, "limited.toml"), sweep_case(base, limited, end="30.0"))
    start = time.time()
    result = subprocess.run([softflow, "sweep", os.path.join(work, "limited.toml"),
                             "--wall-time-limit", "12"], capture_output=True, text=True)
    elapsed = time.time() - start
    table = read_csv(os.path.join(limited, "sweep.csv"))
    if result.returncode != INTERRUPTED or elapsed > 13.0:  # 1 s for process start-up and load
        fail(f"sweep --wall-time-limit 12: exit {result.returncode} after {elapsed:.1f} s\n"
             f"{result.stdout}{result.stderr}")
    if (table[0]["status"] != "interrupted"
            or not os.path.exists(os.path.join(limited, labels[0], "checkpoint.h5"))
            or any(r["status"] != "not run" for r in table[1:])):
        fail(f"after the wall-time limit: {[r['status'] for r in table]}")
    print(f"--wall-time-limit 12: stopped after {elapsed:.1f} s, first case at step {table[0]['steps']}")


def refusals(softflow, base, work):
    # 4. Refusals.
    case = os.path.join(work, "first.toml")
    result = subprocess.run([softflow, "run", case], capture_output=True, text=True)
    if result.returncode != 1 or "softflow sweep" not in result.stderr:
        fail(f"run on a sweep file: exit {result.returncode}: {result.stderr}")
    write(os.path.join(work, "empty.toml"), base.replace("capillary_number = 0.1", "capillary_number = []"))
    result = subprocess.run([softflow, "sweep", os.path.join(work, "empty.toml")],
                            capture_output=True, text=True)
    if result.returncode != 1 or "objects[1].capillary_number = []" not in result.stderr:
        fail(f"an empty list: exit {result.returncode}: {result.stderr}")
    write(os.path.join(work, "bad.toml"), sweep_case(base, os.path.join(work, "bad"))
          .replace("[0.1, 0.2]", "[0.1, -0.2]"))
    result = subprocess.run([softflow, "sweep", os.path.join(work, "bad.toml")],
                            capture_output=True, text=True)
    if (result.returncode != 1 or not re.search(r"capillary_number_-0\.2", result.stderr)
            or "must be > 0" not in result.stderr or os.path.exists(os.path.join(work, "bad"))):
        fail(f"an invalid value: exit {result.returncode}: {result.stderr}")
    print("refused: " + result.stderr.strip()[:160])


if __name__ == "__main__":
    sys.exit(main(*sys.argv[1:4], quick="--quick" in sys.argv[4:]))
