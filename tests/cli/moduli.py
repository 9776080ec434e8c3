#!/usr/bin/env python3
"""`softflow moduli` through the program.

Usage: moduli.py SOFTFLOW WORK_DIR

A tiny emulsion (2 drops of R = 1 in an 8 x 6 x 8 cell, lambda = 1, Gamma = 1,
oscillatory strain 0.05 at omega = 1, two periods, the last fitted) with two
random configurations (emulsion.seed = [1, 2]):
1. moduli.csv has one point of 2 configurations whose mean and sample standard
   deviation of G' R / Gamma and G'' / (eta_m omega) are those of the two runs'
   summary.json (recomputed here), and Oldroyd's moduli at their mean volume
   fraction computed here from eqs. A.1-A.5 independently of softflow.
2. Running it again skips the finished runs and writes the same table; one
   configuration stopped by SIGTERM inside the fitted period and restarted from its checkpoint
   has the moduli of the uninterrupted run to round-off (the fitted history is
   in the checkpoint).
3. Cases that cannot give moduli are refused with exit code 1 naming the key:
   steady flow, no bulk_stress.box_side, no list.
4. Linearity (eq. 4.3): with strain_amplitude = [0.05, 0.1] (one seed), moduli.md
   compares the doubled amplitude's G', G'' with the smaller's, as the two runs give them.
"""
import csv
import json
import math
import os
import shutil
import sys

import signal

from cli_support import fail, run, stop_when_past

CASE = """[case]
name = "tiny_moduli"
[cell]
length = 8.0
height = 6.0
width = 8.0
[flow]
type = "oscillatory"
strain_amplitude = 0.05
frequency = 1.0
periods = 2
[[objects]]
radius = 1.0
viscosity_ratio = 1.0
interfacial_tension = 1.0
[emulsion]
volume_fraction = 0.02
seed = [1, 2]
[bulk_stress]
box_side = 5.0
fit_periods = 1
[mesh]
equator_nodes = 14
far_size = 1.5
[time]
step = 0.4
[output]
fields = false
directory = "{out}"
"""


def oldroyd(lam, phi, w):
    den = 10 * (lam + 1) - 2 * (5 * lam + 2) * phi
    eta = (10 * (lam + 1) + 3 * (5 * lam + 2) * phi) / den
    tau = (19 * lam + 16) * (2 * lam + 3 - 2 * (lam - 1) * phi) / (4 * den)
    xi = (19 * lam + 16) * (2 * lam + 3 + 3 * (lam - 1) * phi) / (4 * den)
    return (eta * tau - xi) * w * w / (1 + tau * tau * w * w), (eta * w + xi * tau * w ** 3) / (1 + tau * tau * w * w) / w


def write(path, text):
    with open(path, "w") as f:
        f.write(text)


def main(softflow, work):
    shutil.rmtree(work, ignore_errors=True)
    os.makedirs(work)
    out = os.path.join(work, "study")
    case = os.path.join(work, "moduli.toml")
    write(case, CASE.format(out=out))
    run([softflow, "moduli", case, "-j", "2", "-q"])

    # 1. The point against the runs' own moduli and Oldroyd's.
    with open(os.path.join(out, "moduli.csv")) as f:
        points = list(csv.DictReader(f))
    if len(points) != 1:
        fail(f"{len(points)} points in moduli.csv, expected 1 (the seed is averaged over)")
    p = points[0]
    if p["configurations"] != "2" or p["fitted"] != "2":
        fail(f"configurations {p['configurations']}, fitted {p['fitted']}: expected 2 and 2")
    runs = []
    for name in sorted(os.listdir(out)):
        path = os.path.join(out, name, "summary.json")
        if os.path.exists(path):
            runs.append(json.load(open(path))["moduli"])
    if len(runs) != 2:
        fail(f"{len(runs)} runs with a summary, expected 2")
    for key, column, std_column in (("G_storage_R_over_Gamma", "G_storage_R_over_Gamma", "G_storage_std"),
                                    ("G_loss_over_eta_m_omega", "G_loss_over_eta_m_omega", "G_loss_std")):
        values = [r[key] for r in runs]
        mean = sum(values) / 2
        std = abs(values[0] - values[1]) / math.sqrt(2)
        if not math.isclose(float(p[column]), mean, rel_tol=1e-6):
            fail(f"{column} = {p[column]}, the runs' mean is {mean}")
        if not math.isclose(float(p[std_column]), std, rel_tol=1e-5, abs_tol=1e-12):
            fail(f"{std_column} = {p[std_column]}, the runs' sample deviation is {std}")
    phi = sum(r["volume_fraction"] for r in runs) / 2
    storage, loss = oldroyd(1.0, phi, 1.0)
    if not (math.isclose(float(p["oldroyd_G_storage"]), storage, rel_tol=1e-6)
            and math.isclose(float(p["oldroyd_G_loss"]), loss, rel_tol=1e-6)):
        fail(f"Oldroyd at phi = {phi}: {storage}, {loss}; moduli.csv has {p['oldroyd_G_storage']}, "
             f"{p['oldroyd_G_loss']}")
    # The fit explains the signal (two periods from rest leave some transient in the last).
    if not float(p["worst_fit_residual"]) < 0.05:
        fail(f"fit residual {p['worst_fit_residual']}")
    md = open(os.path.join(out, "moduli.md")).read()
    if "| 1 | 2/2 |" not in md:
        fail("moduli.md has no row for the point:\n" + md)

    # 2. Again: nothing runs, the same table.
    before = open(os.path.join(out, "moduli.csv")).read()
    run([softflow, "moduli", case, "-q"])
    if open(os.path.join(out, "moduli.csv")).read() != before:
        fail("a second run changed moduli.csv")

    restarted = os.path.join(work, "restarted")
    code, output = stop_when_past([softflow, "run", os.path.join(out, "cases", "seed_1.toml"), "-o", restarted,
                                   "-q"], restarted, 24, signal.SIGTERM)
    if code != 5:
        fail(f"the stopped run exited with {code}, expected 5:\n{output}")
    run([softflow, "restart", restarted, "-q"])
    again = json.load(open(os.path.join(restarted, "summary.json")))["moduli"]
    whole = json.load(open(os.path.join(out, "seed_1", "summary.json")))["moduli"]
    for key in ("G_storage", "G_loss", "volume_fraction", "samples"):
        if not math.isclose(again[key], whole[key], rel_tol=1e-9, abs_tol=1e-14):
            fail(f"moduli.{key} after a restart {again[key]}, uninterrupted {whole[key]}")

    # 3. Refusals before anything runs.
    for change, expected in (
            (('type = "oscillatory"\nstrain_amplitude = 0.05\nfrequency = 1.0\nperiods = 2\n',
              'type = "steady"\n'), 'flow.type must be "oscillatory"'),
            (("box_side = 5.0", "box_side = 0.0"), "bulk_stress.box_side = 0"),
            (("seed = [1, 2]", "seed = 1"), "no parameter is a list")):
        bad = os.path.join(work, "bad.toml")
        write(bad, CASE.format(out=os.path.join(work, "bad")).replace(*change))
        result = run([softflow, "moduli", bad], expect=1)
        if expected not in result.stderr:
            fail(f"the refusal does not say {expected!r}:\n{result.stderr}")
        if os.path.exists(os.path.join(work, "bad")):
            fail("a refused study wrote its output directory")
    # 4. The linearity section.
    linear = os.path.join(work, "linear")
    case = os.path.join(work, "linear.toml")
    write(case, CASE.format(out=linear).replace("strain_amplitude = 0.05", "strain_amplitude = [0.05, 0.1]")
          .replace("seed = [1, 2]", "seed = 1"))
    run([softflow, "moduli", case, "-j", "2", "-q"])
    small = json.load(open(os.path.join(linear, "strain_amplitude_0.05", "summary.json")))["moduli"]
    large = json.load(open(os.path.join(linear, "strain_amplitude_0.1", "summary.json")))["moduli"]
    md = open(os.path.join(linear, "moduli.md")).read()
    change = 100 * (large["G_storage_R_over_Gamma"] / small["G_storage_R_over_Gamma"] - 1)
    row = [line for line in md.splitlines() if "0.1 vs 0.05" in line]
    if "## Linearity (eq. 4.3)" not in md or len(row) != 1:
        fail("moduli.md has no linearity row for 0.1 vs 0.05:\n" + md)
    shown = float(row[0].split("|")[3].strip().rstrip("%").strip())
    if not math.isclose(shown, change, rel_tol=1e-2, abs_tol=1e-3):
        fail(f"G' change {shown} % in moduli.md, the runs give {change} %")
    print("moduli: ok")


if __name__ == "__main__":
    main(*sys.argv[1:])
