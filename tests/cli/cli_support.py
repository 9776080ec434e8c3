"""Helpers shared by the command-line tests: failing with a message, running
softflow with an expected exit code, reading a run's outputs."""
import csv
import json
import os
import subprocess
import sys
import time


def fail(message):
    print("FAIL: " + message)
    sys.exit(1)


def run(args, expect=0, launcher=()):
    """Runs `args` (after `launcher`), failing unless it exits with `expect`."""
    start = time.time()
    result = subprocess.run(list(launcher) + list(args), capture_output=True, text=True)
    if os.environ.get("SOFTFLOW_TEST_TIMES"):  # where a test's time goes
        print(f"[{time.time() - start:6.1f} s] {' '.join(list(launcher)[:3] + list(args)[:3])}", file=sys.stderr)
    if result.returncode != expect:
        fail(f"{' '.join(args)}: exit code {result.returncode}, expected {expect}\n"
             f"{result.stdout}\n{result.stderr}")
    return result


def rows(directory, name="timeseries.csv"):
    with open(os.path.join(directory, name)) as f:
        return list(csv.DictReader(f))


def read_json(directory, name="summary.json"):
    with open(os.path.join(directory, name)) as f:
        return json.load(f)


def stop_when_past(args, out, step, sig, launcher=()):
    """Starts `args` (a run writing into `out`) and sends `sig` once its
    progress.json reports `step`; returns the exit code and the output."""
    process = subprocess.Popen(list(launcher) + list(args), stdout=subprocess.PIPE,
                               stderr=subprocess.PIPE, text=True)
    progress = os.path.join(out, "progress.json")
    deadline = time.time() + 120
    while process.poll() is None and time.time() < deadline:
        try:
            with open(progress) as f:
                if json.load(f)["step"] >= step:
                    process.send_signal(sig)
                    break
        except (OSError, ValueError, KeyError):
            pass
        time.sleep(0.01)
    stdout, stderr = process.communicate(timeout=120)
    return process.returncode, stdout + stderr


def same_rows(reference, result, what, skip=("step_seconds",), tolerance=1e-12):
    """Every column but `skip` equal to `tolerance` (relative, at least
    absolute); nan equals nan. Fails naming the first difference; returns
    the largest difference."""
    if len(reference) != len(result):
        fail(f"{what}: {len(result)} rows, the reference run has {len(reference)}")
    worst = 0.0
    for a, b in zip(reference, result):
        for column in a:
            if column in skip:
                continue
            x, y = float(a[column]), float(b[column])
            if x != x or y != y:
                if (x != x) != (y != y):
                    fail(f"{what}: step {a['step']}, {column}: {y!r} vs {x!r} in the reference run")
                continue
            difference = abs(x - y)
            worst = max(worst, difference)
            if difference > tolerance * max(1.0, abs(x)):
                fail(f"{what}: step {a['step']}, {column}: {y!r} vs {x!r} in the reference run")
    return worst


def write(path, text):
    with open(path, "w") as f:
        f.write(text)


def start(args):
    """Starts `args` in the background, its output captured."""
    return subprocess.Popen(list(args), stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)


def wait_for(predicate, process, what, timeout=120):
    """Polls `predicate` until true; fails if `process` ends first or time runs out."""
    deadline = time.time() + timeout
    while not predicate():
        if process.poll() is not None:
            fail(f"{what}: the process ended first (exit {process.returncode}):\n"
                 f"{process.communicate()[1]}")
        if time.time() > deadline:
            fail(f"{what}: not within {timeout} s")
        time.sleep(0.002)
