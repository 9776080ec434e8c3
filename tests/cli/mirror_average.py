"""A migration start averaged with its mirror start (scripts/validation/
migration_runs.mirror_averaged_run, issue 35), read by `softflow migration`.

The shear flow between walls is symmetric under the half turn about the
vorticity axis, which takes y_p, v_p and Delta S to minus themselves; a
mesh's own drift need not be. Written here: two heights (y_p / y_p,max = 0.9
and 0.5), each a start and its mirror start (-0.9, -0.5) whose particles
migrate towards the centre plane at 0.01 y_p,max per unit time while their
meshes add the same +0.004 y_p,max per unit time to both (the even part
that a mirror start exposes).

1. The averaged migration.csv is the migration alone: y_p / y_p,max =
   y0 - 0.01 t row by row, v_p and Delta S likewise.
2. `softflow migration` along the two averaged runs: the quasi-steady
   trajectory from 0.85 is the straight line at 0.01 to the lowest
   stretch's middle (0.41) at t = 44; along the +y starts alone, whose speed
   is 0.006, to their lowest stretch's middle (0.446) at t = 67.3 (so the
   check tells the two apart).
3. A start and a run at other times are refused (ValueError naming both).
4. `softflow migration --mirror` on the raw starts and mirror starts gives
   the averaged runs' trajectory and curves and lists each pair's meshes'
   part (+0.004 y_p,max per unit time); a start given without its mirror
   start enters alone, listed so; a centred start, two starts at one height
   and a pair at other times are refused with exit code 1, the run named,
   nothing written.

usage: mirror_average.py SOFTFLOW WORKDIR SCRIPTS_DIR
"""
import csv
import os
import re
import shutil
import sys

from cli_support import fail, run

softflow, work, scripts = sys.argv[1:4]
sys.dont_write_bytecode = True
sys.path.insert(0, scripts)
from migration_runs import mirror_averaged_run  # noqa: E402

shutil.rmtree(work, ignore_errors=True)
os.makedirs(work)
Y_MAX, SPEED, MESHES = 1.5, -0.01, 0.004  # y_p,max = H/2 - R; d(y_p / y_p,max)/dt: the migration, the meshes' part
DELTA_S, DELTA_S_MESHES = -0.01, 0.003


def write_run(name, y_rel0, steps=251):
    """A run from y_p / y_p,max = y_rel0: the migration (odd in y_p) plus the meshes' drift (even)."""
    directory = os.path.join(work, name)
    os.makedirs(directory)
    sign = 1.0 if y_rel0 > 0 else -1.0
    with open(os.path.join(directory, "case.toml"), "w") as f:
        f.write("[cell]\nlength = 8.0\nheight = 5.0\nwidth = 8.0\n"
                f"[[objects]]\ncentre = [0.0, {y_rel0 * Y_MAX}, 0.0]\ncapillary_number = 0.2\n")
    with open(os.path.join(directory, "migration.csv"), "w") as f:
        f.write("step,t,object,y_p,y_p_rel,v_p,delta_s\n")
        for step in range(steps):
            t = 0.04 * step
            speed = sign * SPEED + MESHES
            y_rel = y_rel0 + speed * t
            f.write(f"{step},{t:.10g},1,{y_rel * Y_MAX:.12g},{y_rel:.12g},{speed * Y_MAX:.12g},"
                    f"{sign * DELTA_S + DELTA_S_MESHES:.12g}\n")
    return directory


averaged = []
for y0 in (0.9, 0.5):
    start, mirror = write_run(f"start_{y0}", y0), write_run(f"mirror_{y0}", -y0)
    averaged.append(mirror_averaged_run(start, mirror, os.path.join(work, "averaged", f"start_{y0}")))

# 1. The averaged rows.
for directory, y0 in zip(averaged, (0.9, 0.5)):
    rows = list(csv.DictReader(open(os.path.join(directory, "migration.csv"))))
    if len(rows) != 251:
        fail(f"{directory}: {len(rows)} averaged rows, expected 251")
    for r in rows:
        t = float(r["t"])
        expected = {"y_p_rel": y0 + SPEED * t, "y_p": (y0 + SPEED * t) * Y_MAX, "v_p": SPEED * Y_MAX,
                    "delta_s": DELTA_S}
        for key, value in expected.items():
            if abs(float(r[key]) - value) > 1e-9:
                fail(f"{directory} at t = {t:g}: {key} = {r[key]}, expected {value} (the migration alone)")
print("the averaged runs hold the migration alone (the meshes' part dropped)")


# 2. softflow migration along the averaged runs, and along the +y starts alone.
def trajectory_end(runs, out, *options):
    run([softflow, "migration", *runs, *options, "--transient", "2", "--trajectory-from", "0.85", "-o", out])
    text = open(os.path.join(out, "migration.md")).read()
    found = re.search(r"after t = ([0-9.]+)", text)
    if not found:
        fail(f"{out}/migration.md names no trajectory end:\n{text}")
    return float(found.group(1))


os.environ["SOFTFLOW_PLOTS"] = "0"
end = trajectory_end(averaged, os.path.join(work, "curves_averaged"))
if abs(end - 44.0) > 0.05:
    fail(f"along the averaged runs the trajectory ends at t = {end}, expected 44 (0.44 at 0.01)")
plain = trajectory_end([os.path.join(work, "start_0.9"), os.path.join(work, "start_0.5")],
                       os.path.join(work, "curves_plain"))
drift = SPEED + MESHES  # the +y start's own speed; its lowest stretch's middle at t = 9
expected_plain = (0.85 - (0.5 + 9 * drift)) / -drift
if abs(plain - expected_plain) > 0.05:
    fail(f"along the +y starts alone the trajectory ends at t = {plain}, expected {expected_plain:.1f}")
print(f"softflow migration along the averaged runs: t = {end:g} (the +y starts alone: {plain:g})")

# 3. Runs at other times are no pair.
short = write_run("mirror_short", -0.9, steps=200)
try:
    mirror_averaged_run(os.path.join(work, "start_0.9"), short, os.path.join(work, "averaged", "refused"))
    fail("a mirror start with other times was averaged")
except ValueError as e:
    if "start_0.9" not in str(e) or "mirror_short" not in str(e):
        fail(f"the refusal does not name both runs: {e}")
if os.path.exists(os.path.join(work, "averaged", "refused")):
    fail("the refused pair left a directory behind")
print("a pair at other times is refused")

# 4. The same pairing inside softflow migration.
pairs = [os.path.join(work, n) for n in ("start_0.9", "mirror_0.5", "start_0.5", "mirror_0.9")]  # any order
paired_out = os.path.join(work, "curves_paired")
paired = trajectory_end(pairs, paired_out, "--mirror")
if abs(paired - end) > 1e-9 * end:
    fail(f"--mirror: the trajectory ends at t = {paired}, the averaged runs' at {end}")
for name in ("migration_curves.csv", "migration_trajectory.csv"):
    a = list(csv.DictReader(open(os.path.join(paired_out, name))))
    b = list(csv.DictReader(open(os.path.join(work, "curves_averaged", name))))
    if len(a) != len(b) or any(abs(float(x[k]) - float(y[k])) > 1e-9 for x, y in zip(a, b) for k in x
                               if k != "run"):
        fail(f"--mirror: {name} differs from the averaged runs' one")
md = open(os.path.join(paired_out, "migration.md")).read()
listed = re.findall(r"^\| \d \| \S*start_(0\.\d) \| \S*mirror_(0\.\d) \| ([-0-9.]+) \| \d+ \|"
                    r" ([-0-9.e]+) \| ([-0-9.e]+) \| ([-0-9.e]+) \| ([-0-9.e]+) \|$", md, re.M)
if sorted(x[:2] for x in listed) != [("0.5", "0.5"), ("0.9", "0.9")]:
    fail(f"--mirror: migration.md does not list the two pairs:\n{md}")
for start, _, y0, v_start, v_mirror, v_mean, v_meshes in listed:
    expected = {"y_p0 / y_p,max": (float(y0), float(start)), "start": (float(v_start), (SPEED + MESHES) * Y_MAX),
                "mirror": (float(v_mirror), (-SPEED + MESHES) * Y_MAX), "mean": (float(v_mean), SPEED * Y_MAX),
                "meshes' part": (float(v_meshes), MESHES * Y_MAX)}
    for key, (value, want) in expected.items():
        if abs(value - want) > 1e-3 * abs(want):
            fail(f"--mirror: pair {start}: {key} {value}, expected {want}")
print(f"softflow migration --mirror on the raw pairs: t = {paired:g}, the meshes' part listed")

mixed_out = os.path.join(work, "curves_mixed")  # 0.9 without its mirror start: alone
run([softflow, "migration", pairs[0], pairs[1], pairs[2], "--mirror", "--transient", "2", "-o", mixed_out])
md = open(os.path.join(mixed_out, "migration.md")).read()
alone = re.search(r"^\| \d \| \S*start_0\.9 \| none given[^|]*\| 0\.9000 \| \d+ \| ([-0-9.e]+) \|", md, re.M)
if not alone or abs(float(alone.group(1)) - (SPEED + MESHES) * Y_MAX) > 1e-6:
    fail(f"--mirror: the 0.9 start given alone is not listed alone with its own v_p:\n{md}")
if not re.search(r"^\| \d \| \S*start_0\.5 \| \S*mirror_0\.5 \|", md, re.M):
    fail(f"--mirror: the 0.5 pair is not listed beside the start alone:\n{md}")
print("a start given without its mirror start enters alone, listed so")

refused_out = os.path.join(work, "curves_refused")
centred = write_run("centred", 0.0)
again = write_run("again_0.9", 0.9)
for runs, named in (([pairs[0], pairs[3], centred], "centred"),
                    ([pairs[0], again, pairs[3]], "again_0.9"),
                    ([pairs[0], short], "mirror_short")):
    result = run([softflow, "migration", *runs, "--mirror", "--transient", "2", "-o", refused_out], expect=1)
    if named not in result.stderr or "--mirror" not in result.stderr:
        fail(f"--mirror refusal does not name {named} and the option: {result.stderr}")
    if os.path.exists(refused_out):
        fail("a refused --mirror left output behind")
print("--mirror refuses a centred start, two starts at one height and a pair at other times")
