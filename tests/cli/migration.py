"""`softflow migration` from the command line (thesis ch. 3, issue 35), on two
run directories written here (case.toml and migration.csv, as a run writes
them), whose particles migrate at one constant speed, -0.01 y_p,max per unit
time, from y_p / y_p,max = 0.9 and 0.5 over t = 0 ... 10.

1. The master curves: migration.md names both runs and no neutral height.
2. --trajectory-from 0.85: along a constant curve the quasi-steady trajectory
   is a straight line, down to the lowest stretch's middle (0.41 with the
   transient 2 and stretches of 2) at t = (0.85 - 0.41) / 0.01 = 44; y_p,max
   comes from case.toml (H/2 - R = 1.5), so a wrong scale shows in t and y_p.
   migration.md, migration_trajectory.csv and the printed line agree; with
   plots on, migration.png is drawn with the trajectory.
3. A start outside the measured heights: exit 1, one message naming the
   option, the value and the heights allowed, and no output directory.
4. A later call without the option leaves no trajectory beside its curves.

usage: migration.py SOFTFLOW WORKDIR
"""
import csv
import os
import shutil
import sys

from cli_support import fail, run

softflow, work = sys.argv[1], sys.argv[2]
shutil.rmtree(work, ignore_errors=True)
os.makedirs(work)
Y_MAX, SPEED = 1.5, -0.01  # y_p,max = H/2 - R; d(y_p / y_p,max)/dt


def write_run(name, y_rel0):
    directory = os.path.join(work, name)
    os.makedirs(directory)
    with open(os.path.join(directory, "case.toml"), "w") as f:
        f.write("[cell]\nlength = 8.0\nheight = 5.0\nwidth = 8.0\n"
                f"[[objects]]\ncentre = [0.0, {y_rel0 * Y_MAX}, 0.0]\ncapillary_number = 0.2\n")
    with open(os.path.join(directory, "migration.csv"), "w") as f:
        f.write("step,t,object,y_p,y_p_rel,v_p,delta_s\n")
        for step in range(251):
            t = 0.04 * step
            y_rel = y_rel0 + SPEED * t
            f.write(f"{step},{t:.10g},1,{y_rel * Y_MAX:.12g},{y_rel:.12g},{SPEED * Y_MAX:.12g},-0.01\n")
    return directory


runs = [write_run("upper", 0.9), write_run("lower", 0.5)]
out = os.path.join(work, "curves")

# 1-2. Curves and the trajectory.
env_plots = os.environ.get("SOFTFLOW_PLOTS")
printed = run([softflow, "migration", *runs, "--transient", "2", "--trajectory-from", "0.85", "-o", out]).stdout
text = open(os.path.join(out, "migration.md")).read()
for expected in ("None: the stretches' v_p has one sign", "## Quasi-steady trajectory from y_p / y_p,max = 0.8500",
                 "at the lowest measured height, y_p / y_p,max = 0.4100", "after t = 44 "):
    if expected not in text:
        fail(f"migration.md lacks '{expected}':\n{text}")
path = list(csv.DictReader(open(os.path.join(out, "migration_trajectory.csv"))))
last = path[-1]
if abs(float(last["t"]) - 44.0) > 1e-6 or abs(float(last["y_p"]) - 0.41 * Y_MAX) > 1e-9:
    fail(f"the trajectory ends at t = {last['t']}, y_p = {last['y_p']}; expected 44 and {0.41 * Y_MAX}")
for row in path:  # a straight line at the constant speed
    if abs(float(row["y_p_rel"]) - (0.85 + SPEED * float(row["t"]))) > 1e-9:
        fail(f"trajectory row {row} is off the line y = 0.85 - 0.01 t")
if "quasi-steady trajectory from y_p / y_p,max = 0.85: ends at the lowest measured height" not in printed:
    fail(f"softflow migration did not say where the trajectory ends:\n{printed}")
if env_plots != "0" and not os.path.exists(os.path.join(out, "migration.png")):
    fail("plots are on but migration.png was not drawn")
print("the trajectory along a constant curve is the straight line to t = 44")

# 3. A start above the measured heights.
refused = os.path.join(work, "refused")
result = run([softflow, "migration", *runs, "--transient", "2", "--trajectory-from", "0.95", "-o", refused],
             expect=1)
message = result.stderr.strip()
for expected in ("--trajectory-from = 0.95", "0.4100 ... 0.8700"):
    if expected not in message:
        fail(f"the refusal lacks '{expected}': {message}")
if len(message.splitlines()) != 1:
    fail(f"the refusal is more than one line: {message}")
if os.path.exists(refused):
    fail(f"a refused call wrote {refused}")
print("a start outside the measured heights is refused with one message and nothing written")

# 4. Curves again without a trajectory: no stale trajectory beside them.
run([softflow, "migration", *runs, "--transient", "2", "-o", out])
if os.path.exists(os.path.join(out, "migration_trajectory.csv")):
    fail("an earlier call's migration_trajectory.csv stayed beside curves made without --trajectory-from")
if "Quasi-steady trajectory" in open(os.path.join(out, "migration.md")).read():
    fail("migration.md still has a trajectory section")
print("curves without --trajectory-from leave no trajectory")
