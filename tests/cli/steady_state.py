#!/usr/bin/env python3
"""Runs that stop at steady state (time.steady_tolerance), through the program.

Usage: steady_state.py SOFTFLOW CASE.toml WORK_DIR

The coarse drop of the regression case (dt = 0.1) with end = 20 as the
latest time, tolerance 2e-3 over a window of 1:
1. The run stops before end, exit 0, status "completed", summary.json's
   steady.reached and steady.time = the last step's time. The stopping step
   is checked against the time series independently: over the rows from the
   last one at or before t - 1 to t, D, D cos 2 theta, D sin 2 theta and each
   component of the centre velocity relative to the shear flow at the centre,
   (u_c - y_c, v_c, w_c) (drop radius 1, shear rate 1), spread by at most
   the tolerance, and at the step before they do not.
2. The answer is the steady one: D at the stop is within the tolerance of D
   at t = 20 of the same case run without stopping.
3. A run stopped by SIGTERM before it got there and restarted stops at the
   same step, its rows equal to round-off; `restart` of a run that reached
   steady state does nothing and says so.
4. A sweep's table reports it (steady = yes, steady_t).
"""
import csv
import math
import os
import shutil
import signal
import sys

from cli_support import fail, run, rows, read_json, same_rows, stop_when_past

TOL, WINDOW = 2e-3, 1.0
INTERRUPTED = 5




def summary(directory):
    return read_json(directory)


def quantities(row):
    d, theta = float(row["D"]), math.radians(float(row["theta_deg"]))
    return [d, d * math.cos(2 * theta), d * math.sin(2 * theta),
            float(row["uc"]) - float(row["yc"]), float(row["vc"]), float(row["wc"])]


def steady_at(series, i):
    """The criterion at row i, computed here from the time series."""
    t = float(series[i]["t"])
    start = max(j for j in range(i + 1) if float(series[j]["t"]) <= t - WINDOW + 1e-9 * WINDOW) \
        if float(series[0]["t"]) <= t - WINDOW + 1e-9 else None
    if start is None:
        return False
    window = [quantities(r) for r in series[start:i + 1]]
    return all(max(q) - min(q) <= TOL for q in zip(*window))


def main(softflow, case_source, work):
    shutil.rmtree(work, ignore_errors=True)
    os.makedirs(work)
    with open(case_source) as f:
        base = f.read().replace("step = 0.05", "step = 0.1").replace("end = 1.0", "end = 20.0")
    steady_text = base.replace("end = 20.0", f"end = 20.0\nsteady_tolerance = {TOL}\nsteady_window = {WINDOW}")
    case = os.path.join(work, "steady.toml")
    with open(case, "w") as f:
        f.write(steady_text)

    # 1. Stops at the first step where the criterion holds.
    out = os.path.join(work, "steady")
    result = run([softflow, "run", case, "-o", out])
    s = summary(out)
    series = rows(out)
    if s["status"] != "completed" or not s["steady"]["reached"]:
        fail(f"status {s['status']}, steady {s['steady']}")
    if not s["time"] < 20.0 - 1e-9:
        fail(f"the run went on to t = {s['time']}")
    if abs(s["steady"]["time"] - s["time"]) > 1e-12:
        fail(f"steady.time {s['steady']['time']} is not the last step's time {s['time']}")
    if "steady state at t =" not in result.stdout:
        fail("the run does not say it stopped at steady state:\n" + result.stdout)
    last = len(series) - 1
    if not steady_at(series, last):
        fail(f"at t = {series[last]['t']} the time series does not meet the criterion")
    if steady_at(series, last - 1):
        fail(f"the criterion held already at t = {series[last - 1]['t']}: the run stopped late")
    print(f"stopped at t = {s['time']:.2f} (step {s['steps']} of 200); changes {s['steady']['changes_over_window']}")

    # 2. Against the same case run to the end.
    full = os.path.join(work, "to_end")
    with open(os.path.join(work, "to_end.toml"), "w") as f:
        f.write(base)
    run([softflow, "run", os.path.join(work, "to_end.toml"), "-o", full, "-q"])
    d_stop, d_end = s["final"][0]["D"], summary(full)["final"][0]["D"]
    if not abs(d_stop - d_end) <= TOL:
        fail(f"D at the stop {d_stop} vs {d_end} at t = 20: more than the tolerance apart")
    print(f"D at the stop {d_stop:.6f}, at t = 20 {d_end:.6f}")

    # 3. Interrupted before steady state, restarted: the same stop.
    stopped = os.path.join(work, "interrupted")
    code, _ = stop_when_past([softflow, "run", case, "-o", stopped, "-q"], stopped, 8, signal.SIGTERM)
    if code != INTERRUPTED:
        fail(f"SIGTERM: exit code {code}, expected {INTERRUPTED}")
    if summary(stopped)["steps"] >= s["steps"]:
        fail("the run reached steady state before the stop: the test would not exercise a restart")
    run([softflow, "restart", stopped, "-q"])
    again = rows(stopped)
    same_rows(series, again, "restarted run")
    if summary(stopped)["steady"]["time"] != s["steady"]["time"]:
        fail("the restarted run reports another steady time")
    result = run([softflow, "restart", out])
    if "steady state" not in result.stdout or "nothing to do" not in result.stdout:
        fail("restarting a run at steady state does not say it is complete:\n" + result.stdout)
    print(f"interrupted past step 8, restarted: the same {len(again)} rows")

    # 4. The sweep table.
    sweep = os.path.join(work, "sweep.toml")
    with open(sweep, "w") as f:
        f.write(steady_text.replace("capillary_number = 0.1", "capillary_number = [0.1]").replace(
            "[output]", f"[output]\ndirectory = \"{os.path.join(work, 'sweep_out')}\""))
    run([softflow, "sweep", sweep, "-q"])
    with open(os.path.join(work, "sweep_out", "sweep.csv")) as f:
        table = list(csv.DictReader(f))
    if table[0]["steady"] != "yes" or abs(float(table[0]["steady_t"]) - s["steady"]["time"]) > 1e-6:
        fail(f"sweep.csv: steady {table[0].get('steady')!r}, steady_t {table[0].get('steady_t')!r}")
    print("sweep.csv: steady = yes, steady_t =", table[0]["steady_t"])
    print("PASS")


if __name__ == "__main__":
    main(*sys.argv[1:4])
