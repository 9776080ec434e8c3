#!/usr/bin/env python3
"""`softflow response` (the frequency-domain linear response) through the program.

Usage: response.py SOFTFLOW WORK_DIR [MPI launcher words...]

A drop (R = 1, lambda = 1, Gamma = 1) in a 24 x 16 x 24 cell on 20 equator nodes:
1. --log-range 0.4 10 3 solves omega = 0.4, 2, 10; response.csv has those rows,
   c within 5 % of Oldroyd's dilute limit computed here from appendix A (the
   mesh's error: measured 2.7, 0.8, 0.4 %), Re c falling from near Taylor's steady value
   towards the tension-free sphere's as omega grows; the cell's moduli are the
   dilute law 1 + phi c written as G', G'' (recomputed here from c and phi);
   response.md and summary.json are there, and no staging directory is left.
2. The same on two ranks (with a launcher): c equal to 1e-8; the iterative path
   (solver.type = "iterative": FGMRES with PRESB) on two ranks at omega = 2: c
   equal to 1e-6, in at most 12 FGMRES iterations; with slip (alpha = 1) the
   iterative path on two ranks against the LU on one (14 equator nodes), the
   same to 1e-6; at omega = 0.02 (14 equator nodes) the iterative path on two
   ranks with its exact interface block (on there: Gamma / (omega eta R) = 50)
   and without it (-oscillatory_interface_block never), both the LU's c to
   1e-6, the block in fewer inner iterations.
3. --cube-sides 4,6,16 with bulk_stress.box_side = 4: cubes.csv's side-4 row
   is response.csv's cube, and phi side^3 is the drop's volume in every cube.
4. A sweep stopped by SIGTERM after its first frequency exits with 5 and
   keeps the solved frequencies in <dir>.frequencies-done.json; run again,
   it takes them and solves the rest: response.csv equal to 1. to the bit,
   the record removed.
5. Bad input: exit 1, one message naming the key or option, no output:
   an elastic particle, steady flow without --frequency, --frequency 0, a bad
   --log-range, a cube that does not fit in the cell.
"""
import json
import math
import os
import shutil
import signal
import subprocess
import sys
import time

from cli_support import fail, read_json, rows, run

CASE = """[case]
name = "drop_response"
[cell]
length = 24.0
height = 16.0
width = 24.0
[flow]
type = "oscillatory"
strain_amplitude = 0.05
frequency = 1.0
[[objects]]
radius = 1.0
viscosity_ratio = 1.0
interfacial_tension = 1.0
[mesh]
equator_nodes = 20
"""


def oldroyd_dilute(lam, w):
    """Oldroyd's dilute c (appendix A, alpha = 0), written out independently of softflow."""
    return complex(5.0 * (5.0 * lam + 2.0), w * 5.0 * (lam - 1.0) * (19.0 * lam + 16.0) / 4.0) / \
        complex(10.0 * (lam + 1.0), w * (19.0 * lam + 16.0) * (2.0 * lam + 3.0) / 4.0)


def refused(softflow, work, name, text, extra, expected):
    path = os.path.join(work, name + ".toml")
    with open(path, "w") as f:
        f.write(text)
    out = os.path.join(work, "out_" + name)
    result = run([softflow, "response", path, "-o", out] + extra, expect=1)
    if expected not in result.stderr:
        fail(f"{name}: the message lacks '{expected}':\n{result.stderr}")
    if len(result.stderr) > 400:
        fail(f"{name}: a message of {len(result.stderr)} characters:\n{result.stderr}")
    leftovers = [e for e in os.listdir(work) if e.startswith("out_" + name)]
    if leftovers:
        fail(f"{name}: output left behind: {leftovers}")


def main(softflow, work, *launcher):
    shutil.rmtree(work, ignore_errors=True)
    os.makedirs(work)
    case = os.path.join(work, "drop.toml")
    with open(case, "w") as f:
        f.write(CASE)

    out = os.path.join(work, "serial")
    run([softflow, "response", case, "-o", out, "-q", "--log-range", "0.4", "10", "3"])
    table = rows(out, "response.csv")
    omegas = [float(r["omega"]) for r in table]
    if [round(w, 9) for w in omegas] != [0.4, 2.0, 10.0]:
        fail(f"--log-range 0.4 10 3 solved {omegas}")
    c = [complex(float(r["c_real"]), float(r["c_imag"])) for r in table]
    for w, z in zip(omegas, c):
        theory = oldroyd_dilute(1.0, w)
        error = abs(z - theory) / abs(theory)
        print(f"omega {w:g}: c = {z:.5f}, Oldroyd {theory:.5f}, error {100 * error:.2f} %")
        if not error < 0.05:
            fail(f"omega {w:g}: c = {z} is {100 * error:.2f} % from Oldroyd's {theory}")
    if not c[0].real > c[1].real > c[2].real:
        fail(f"Re c does not fall with the frequency: {c}")
    for r, z in zip(table, c):
        phi, w = float(r["cell_phi"]), float(r["omega_star"])
        storage, loss = -w * phi * z.imag, 1.0 + phi * z.real
        if abs(float(r["cell_G_storage_R_over_Gamma"]) - storage) > 1e-6 * max(abs(storage), 1e-12) or \
                abs(float(r["cell_G_loss_over_eta_m_omega"]) - loss) > 1e-9:
            fail(f"omega {w:g}: the cell's moduli are not 1 + phi c: {r}")
    summary = read_json(out)
    if summary["command"] != "response" or len(summary["points"]) != 3:
        fail(f"summary.json: {summary}")
    for name in ("response.md", "case.toml"):
        if not os.path.exists(os.path.join(out, name)):
            fail(f"{name} missing")
    if [e for e in os.listdir(work) if ".partial-" in e]:
        fail(f"a staging directory was left: {os.listdir(work)}")

    # A sweep stopped part-way keeps its solved frequencies beside the output
    # directory; the next run takes them and solves the rest, to the bit.
    resumed = os.path.join(work, "resumed")
    record = resumed + ".frequencies-done.json"
    process = subprocess.Popen([softflow, "response", case, "-o", resumed, "--log-range", "0.4", "10", "3"],
                               stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    while process.poll() is None and not os.path.exists(record):
        time.sleep(0.02)
    process.send_signal(signal.SIGTERM)
    out_text, err_text = process.communicate()
    if process.returncode != 5 or os.path.exists(resumed) or not os.path.exists(record):
        fail(f"a sweep stopped after its first frequency: exit {process.returncode} (expected 5), output directory "
             f"{'left' if os.path.exists(resumed) else 'absent'}, record {'kept' if os.path.exists(record) else 'gone'}"
             f"\n{out_text}\n{err_text}")
    if "frequencies-done.json" not in err_text:
        fail(f"the stop message does not say where the solved frequencies are kept: {err_text}")
    kept = len(json.load(open(record))["points"])
    again = run([softflow, "response", case, "-o", resumed, "--log-range", "0.4", "10", "3"]).stdout
    if again.count("kept from an interrupted run") != kept or not 1 <= kept < 3:
        fail(f"the rerun kept {again.count('kept from an interrupted run')} frequencies, the record held {kept}:\n{again}")
    if os.path.exists(record):
        fail("the record of solved frequencies outlived the committed results")
    for a, b in zip(table, rows(resumed, "response.csv")):
        if (a["c_real"], a["c_imag"], a["cell_phi"]) != (b["c_real"], b["c_imag"], b["cell_phi"]):
            fail(f"the resumed sweep differs from the uninterrupted one: {b} against {a}")
    print(f"a sweep stopped after {kept} of 3 frequencies resumes with them kept, the same to the bit")

    # A cube-side study (--cube-sides): the cube of bulk_stress.box_side gives
    # response.csv's cube columns again; every cube holding the drop has
    # the same drop volume, phi side^3.
    cubes_case = os.path.join(work, "cubes.toml")
    with open(cubes_case, "w") as f:
        f.write(CASE.replace("equator_nodes = 20", "equator_nodes = 14") + "[bulk_stress]\nbox_side = 4.0\n")
    cubes_out = os.path.join(work, "cubes")
    run([softflow, "response", cubes_case, "-o", cubes_out, "-q", "-f", "0.4", "--cube-sides", "4,6,16"])
    box, cubes = rows(cubes_out, "response.csv")[0], rows(cubes_out, "cubes.csv")
    if [float(c["side"]) for c in cubes] != [4.0, 6.0, 16.0]:
        fail(f"cubes.csv sides: {[c['side'] for c in cubes]}")
    for key in ("phi", "G_storage_R_over_Gamma", "G_loss_over_eta_m_omega", "oldroyd_G_storage"):
        column = "box_" + key if key in ("phi", "G_storage_R_over_Gamma", "G_loss_over_eta_m_omega") else \
            "oldroyd_box_G_storage"
        if cubes[0][key] != box[column]:
            fail(f"the cube of side 4: {key} {cubes[0][key]} against response.csv's {box[column]}")
    volumes = [float(c["phi"]) * float(c["side"]) ** 3 for c in cubes]
    if max(volumes) - min(volumes) > 1e-9 * volumes[0] or int(cubes[2]["drops"]) != 1:
        fail(f"the drop's volume in the cubes: {volumes}")
    print(f"cube sides 4, 6, 16: G' R/Gamma {[c['G_storage_R_over_Gamma'] for c in cubes]}")

    if launcher:
        parallel = os.path.join(work, "parallel")
        run([softflow, "response", case, "-o", parallel, "-q", "--log-range", "0.4", "10", "3"], launcher=launcher)
        for a, b in zip(table, rows(parallel, "response.csv")):
            for key in ("c_real", "c_imag"):
                if abs(float(a[key]) - float(b[key])) > 1e-8 * max(1.0, abs(float(a[key]))):
                    fail(f"two ranks: {key} {b[key]} against {a[key]} serial")
        print("two ranks: the same c")
        # The iterative path (FGMRES with PRESB) on two ranks: the same c to its tolerance.
        iterative_case = os.path.join(work, "iterative.toml")
        with open(iterative_case, "w") as f:
            f.write(CASE + '[solver]\ntype = "iterative"\n')
        iterative = os.path.join(work, "iterative")
        run([softflow, "response", iterative_case, "-o", iterative, "-q", "-f", "2"], launcher=launcher)
        for a, b in zip(table[1:2], rows(iterative, "response.csv")):  # omega = 2
            if abs(complex(float(a["c_real"]), float(a["c_imag"])) - complex(float(b["c_real"]), float(b["c_imag"]))) > \
                    1e-6 * abs(complex(float(a["c_real"]), float(a["c_imag"]))):
                fail(f"iterative, two ranks: c = {b['c_real']} {b['c_imag']} against {a['c_real']} {a['c_imag']}")
            if not 1 <= int(b["iterations"]) <= 12:
                fail(f"iterative: {b['iterations']} FGMRES iterations at omega {b['omega']}")
        print("iterative path on two ranks: the same c")
        # At low frequency the tension's stiffness (Gamma / (omega eta R) = 50)
        # switches on the inner solves' exact interface block: the same c as
        # the LU on one rank, in fewer inner iterations than without it.
        coarse = CASE.replace("equator_nodes = 20", "equator_nodes = 14")
        low = {}
        for name, text, words in (
                ("direct", coarse + '[solver]\ntype = "direct"\n', ()),
                ("block", coarse + '[solver]\ntype = "iterative"\n', launcher),
                ("no_block", coarse + '[solver]\ntype = "iterative"\n'
                 'petsc_options = "-oscillatory_interface_block never"\n', launcher)):
            low_case = os.path.join(work, f"low_{name}.toml")
            with open(low_case, "w") as f:
                f.write(text)
            low_out = os.path.join(work, f"low_{name}")
            run([softflow, "response", low_case, "-o", low_out, "-q", "-f", "0.02"], launcher=words)
            low[name] = rows(low_out, "response.csv")[0]
        c_low = {k: complex(float(r["c_real"]), float(r["c_imag"])) for k, r in low.items()}
        for name in ("block", "no_block"):
            if abs(c_low[name] - c_low["direct"]) > 1e-6 * abs(c_low["direct"]):
                fail(f"omega 0.02, iterative ({name}), two ranks: c = {c_low[name]} against the LU's {c_low['direct']}")
        inner = {k: int(low[k]["inner_iterations"]) for k in ("block", "no_block")}
        if not inner["block"] < inner["no_block"]:
            fail(f"omega 0.02: {inner['block']} inner iterations with the interface block, {inner['no_block']} without")
        print(f"omega 0.02, two ranks: the same c; inner iterations {inner['block']} with the interface block, "
              f"{inner['no_block']} without")
        # With slip: the iterative path on two ranks (the multipliers in its
        # inner Schur complement, the gauge pinned) against the LU on one.
        slip = CASE.replace("interfacial_tension = 1.0\n", "interfacial_tension = 1.0\nslip = 1.0\n").replace(
            "equator_nodes = 20", "equator_nodes = 14")  # coarser: two more solves, with twice the unknowns
        c_slip = {}
        for solver, words in (("direct", ()), ("iterative", launcher)):
            slip_case = os.path.join(work, f"slip_{solver}.toml")
            with open(slip_case, "w") as f:
                f.write(slip + f'[solver]\ntype = "{solver}"\n')
            slip_out = os.path.join(work, f"slip_{solver}")
            run([softflow, "response", slip_case, "-o", slip_out, "-q", "-f", "2"], launcher=words)
            r = rows(slip_out, "response.csv")[0]
            c_slip[solver] = complex(float(r["c_real"]), float(r["c_imag"]))
            if solver == "iterative" and not 1 <= int(r["iterations"]) <= 12:
                fail(f"iterative with slip: {r['iterations']} FGMRES iterations")
        if abs(c_slip["iterative"] - c_slip["direct"]) > 1e-6 * abs(c_slip["direct"]):
            fail(f"slip: iterative on two ranks c = {c_slip['iterative']} against the LU's {c_slip['direct']}")
        if abs(c_slip["direct"] - c[1]) < 0.1 * abs(c[1]):
            fail(f"slip = 1 gives the no-slip c {c[1]}: the slip did not reach the solver")
        print(f"slip on both paths: c = {c_slip['direct']:.5f} (LU) and {c_slip['iterative']:.5f} (PRESB, two ranks)")

    particle = CASE.replace("viscosity_ratio = 1.0\ninterfacial_tension = 1.0\n",
                            "model = \"neo_hookean\"\nmodulus = 1.0\n")
    refused(softflow, work, "particle", particle, [], "objects[1].model")
    steady = CASE.replace('type = "oscillatory"\nstrain_amplitude = 0.05\nfrequency = 1.0\n', "shear_rate = 1.0\n")
    refused(softflow, work, "steady", steady, [], "flow.frequency")
    refused(softflow, work, "zero_frequency", CASE, ["--frequency", "0"], "--frequency 0")
    refused(softflow, work, "bad_range", CASE, ["--log-range", "1", "0.5", "3"], "--log-range 1 0.5 3")
    refused(softflow, work, "big_cube", CASE, ["--cube-sides", "4,17"], "--cube-sides 17")
    print("response: all checks passed")


if __name__ == "__main__":
    if len(sys.argv) < 3:
        fail(__doc__)
    main(*sys.argv[1:])
