#!/usr/bin/env python3
"""Adaptive time steps (time.adaptive_tolerance), through the program.

Usage: adaptive_steps.py SOFTFLOW CASE.toml WORK_DIR [MPI launcher words...]

The coarse drop of the regression case (drop_short.toml, to t = 1):
1. Adaptive from a first step of 0.01 with tolerance 1e-3 against the same
   case at a constant dt = 0.0125 (80 steps, the time error of D ~1e-5):
   D within the tolerance at every time of that series (linear
   interpolation between adaptive steps), in fewer steps; the stored
   dt = 0.05 series is further away (its first, BDF1, step costs ~4e-3 in D).
   The run ends exactly at t = 1, every accepted step's estimate is within
   the tolerance, the dt column is the difference of successive times, no
   step exceeds 1 / (k gamma_dot) = 0.1 (the redistribution's stability
   bound), and summary.json's adaptive block counts the steps.
2. From a first step of 0.05, too large for the start: steps are rejected
   and taken again (the run says so), the time series has no rows of
   rejected steps (consecutive step numbers, increasing times).
3. A run stopped by SIGTERM and restarted takes the same steps: every column
   equal to round-off.
4. With an MPI launcher (e.g. mpiexec -n 2): the accuracy run of 1 on two
   ranks takes the same steps as the serial one (every column to round-off).
5. Bad input: max_step below step, adaptive steps without objects or with
   oscillatory flow, max_growth without adaptive steps: exit 1, one message
   naming the key.
"""
import bisect
import os
import shutil
import signal
import sys

from cli_support import fail, run, rows, read_json, same_rows, stop_when_past

TOL = 1e-3
INTERRUPTED = 5


def series(directory):
    r = rows(directory)
    return [float(x["t"]) for x in r], [float(x["D"]) for x in r], r


def at(times, values, t):
    i = bisect.bisect_left(times, t - 1e-12)
    if abs(times[i] - t) <= 1e-12:
        return values[i]
    f = (t - times[i - 1]) / (times[i] - times[i - 1])
    return values[i - 1] + f * (values[i] - values[i - 1])


def write(work, name, text):
    path = os.path.join(work, name + ".toml")
    with open(path, "w") as f:
        f.write(text)
    return path


def main(softflow, case_source, work, *launcher):
    shutil.rmtree(work, ignore_errors=True)
    os.makedirs(work)
    with open(case_source) as f:
        base = f.read()
    reference_csv = os.path.join(os.path.dirname(os.path.abspath(case_source)), "drop_short.ref.csv")

    def adaptive(first_step):
        return base.replace("step = 0.05", f"step = {first_step}").replace(
            "end = 1.0", f"end = 1.0\nadaptive_tolerance = {TOL}")

    # 1. Accuracy against a fine constant step.
    fine_dir, ad_dir = os.path.join(work, "fine"), os.path.join(work, "adaptive")
    run([softflow, "run", write(work, "fine", base.replace("step = 0.05", "step = 0.0125")), "-o", fine_dir, "-q"])
    run([softflow, "run", write(work, "adaptive", adaptive(0.01)), "-o", ad_dir, "-q"])
    t_f, d_f, _ = series(fine_dir)
    t_a, d_a, r_a = series(ad_dir)
    s = read_json(ad_dir)
    if abs(t_a[-1] - 1.0) > 1e-12 or s["status"] != "completed":
        fail(f"the adaptive run ended at t = {t_a[-1]!r}, status {s['status']}")
    error = max(abs(at(t_a, d_a, t) - d) for t, d in zip(t_f[1:], d_f[1:]))
    if not error <= TOL:
        fail(f"adaptive D differs from the dt = 0.0125 run by {error:.3g} > {TOL}")
    ref = [(float(x["t"]), float(x["D"])) for x in rows(os.path.dirname(reference_csv), "drop_short.ref.csv")]
    stored_error = max(abs(at(t_f, d_f, t) - d) for t, d in ref[1:])
    if not error < stored_error:
        fail(f"adaptive error {error:.3g} not below the stored dt = 0.05 series' {stored_error:.3g}")
    if not len(t_a) - 1 < len(t_f) - 1:
        fail(f"{len(t_a) - 1} adaptive steps, no fewer than the {len(t_f) - 1} constant ones")
    a = s["adaptive"]
    if a["accepted"] != len(t_a) - 1 or a["tolerance"] != TOL:
        fail(f"summary.json adaptive block {a} for {len(t_a) - 1} steps")
    # The redistribution's stability bound 1 / (k gamma_dot), k = 10 (the default), gamma_dot = 1.
    if abs(a["step_bound"] - 0.1) > 1e-12 or max(float(r["dt"]) for r in r_a[1:]) > 0.1 + 1e-12:
        fail(f"steps above the bound 0.1: step_bound {a['step_bound']}, largest {a['largest_step']}")
    for prev, row in zip(r_a, r_a[1:]):
        dt = float(row["dt"])
        if abs(float(row["t"]) - float(prev["t"]) - dt) > 1e-9:
            fail(f"step {row['step']}: dt {dt} is not the time difference")
        change = float(row["interface_change"])
        if change == change and change > TOL:  # nan at the first (BDF1) step
            fail(f"step {row['step']} was accepted with estimate {change} > {TOL}")
    print(f"adaptive: {len(t_a) - 1} steps (dt {a['smallest_step']:.3g}..{a['largest_step']:.3g}), "
          f"max |D - D_fine| = {error:.2e}; stored dt = 0.05 series {stored_error:.2e}; "
          f"constant dt = 0.0125: {len(t_f) - 1} steps")

    # 2. Rejections.
    rej_dir = os.path.join(work, "rejecting")
    result = run([softflow, "run", write(work, "rejecting", adaptive(0.05)), "-o", rej_dir])
    s = read_json(rej_dir)
    if s["adaptive"]["rejected"] < 1 or "taken again" not in result.stdout:
        fail(f"no step was rejected from a first step of 0.05: {s['adaptive']}\n{result.stdout}")
    t_r, _, r_r = series(rej_dir)
    if [int(x["step"]) for x in r_r] != list(range(len(r_r))) or any(b <= a for a, b in zip(t_r, t_r[1:])):
        fail("the time series of a run with rejected steps is not one row per accepted step")
    print(f"first step 0.05: {s['adaptive']['rejected']} steps taken again, {len(r_r) - 1} accepted")

    # 3. SIGTERM and restart.
    stopped = os.path.join(work, "interrupted")
    code, _ = stop_when_past([softflow, "run", os.path.join(work, "rejecting.toml"), "-o", stopped, "-q"],
                             stopped, 8, signal.SIGTERM)
    if code != INTERRUPTED:
        fail(f"SIGTERM: exit code {code}, expected {INTERRUPTED}")
    run([softflow, "restart", stopped, "-q"])
    again = rows(stopped)
    same_rows(r_r, again, "restarted run")
    print(f"interrupted past step 8, restarted: the same {len(again)} rows")

    # 4. Two ranks.
    if launcher:
        par_dir = os.path.join(work, "adaptive_mpi")
        run([softflow, "run", os.path.join(work, "adaptive.toml"), "-o", par_dir, "-q"], launcher=launcher)
        par = rows(par_dir)
        same_rows(r_a, par, "two ranks", skip=("step_seconds", "stokes_iterations"), tolerance=1e-9)
        print(f"two ranks: the same {len(par)} rows as serially")

    # 5. Bad input.
    no_objects = base[:base.index("[[objects]]")] + base[base.index("[mesh]"):]
    for name, text, key in [
            ("max_step", adaptive(0.05).replace("adaptive_tolerance", "max_step = 0.01\nadaptive_tolerance"), "time.max_step"),
            ("no_objects", no_objects.replace("end = 1.0", "end = 1.0\nadaptive_tolerance = 1e-3"), "time.adaptive_tolerance"),
            ("growth", base.replace("end = 1.0", "end = 1.0\nmax_growth = 1.5"), "time.max_growth"),
            ("oscillatory", adaptive(0.05).replace("[mesh]", "[flow]\ntype = \"oscillatory\"\nstrain_amplitude = 0.1\nfrequency = 1.0\n[mesh]"),
             "time.adaptive_tolerance")]:
        result = run([softflow, "check", write(work, "bad_" + name, text)], expect=1)
        message = result.stderr.strip()
        if key not in message or "Traceback" in message:
            fail(f"{name}: the message does not name {key}:\n{message}")
    print("bad input refused, naming the key")
    print("PASS")


if __name__ == "__main__":
    main(*sys.argv[1:])
