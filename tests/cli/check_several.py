#!/usr/bin/env python3
"""`softflow check A.toml B.toml ...`: several case files in one process.

Usage: check_several.py SOFTFLOW WORK_DIR

Five files: a valid case, one with an unknown key, one with valid PETSc
options, one with an unknown KSP type, and a sweep. Each gets one verdict:
"FILE: valid" (a sweep: "FILE: valid, a sweep of N cases") on stdout, or
its message on stderr naming the file; the exit code is 1 as one was
refused. "-- -stokes_pc_type nonsense" after three of them refuses all three (the
options after "--" go with every case), and the valid ones alone exit 0.
A valid case with a constant step above the tangential redistribution's
stability bound gets one warning on stderr and exits 0.
"""
import os
import shutil
import sys

from cli_support import fail, run

FILES = {
    "valid": "[mesh]\nequator_nodes = 20\n",
    "unknown_key": "[mesh]\nequator_node = 20\n",
    "petsc_ok": "[solver]\npetsc_options = \"-stokes_ksp_type gmres\"\n",
    "petsc_bad": "[solver]\npetsc_options = \"-stokes_ksp_type nonsense\"\n",
    "sweep": "[[objects]]\ncapillary_number = [0.1, 0.2, 0.3]\n[time]\nend = 1.0\n",
}


def main(softflow, work):
    shutil.rmtree(work, ignore_errors=True)
    os.makedirs(work)
    paths = {}
    for name, text in FILES.items():
        paths[name] = os.path.join(work, name + ".toml")
        with open(paths[name], "w") as f:
            f.write(text)

    result = run([softflow, "check"] + list(paths.values()), expect=1)
    out, err = result.stdout.splitlines(), result.stderr
    for name in ("valid", "petsc_ok"):
        if f"{paths[name]}: valid" not in out:
            fail(f"no 'valid' line for {name}:\n{result.stdout}")
    if f"{paths['sweep']}: valid, a sweep of 3 cases" not in out:
        fail(f"no sweep line:\n{result.stdout}")
    if f"{paths['unknown_key']}: unknown key 'mesh.equator_node'" not in err:
        fail(f"unknown key not reported with its file:\n{err}")
    if f"{paths['petsc_bad']}: PETSc options" not in err or "nonsense" not in err:
        fail(f"bad PETSc option not reported with its file:\n{err}")
    if len(out) != 3 or err.count("softflow: ") != 2:
        fail(f"one verdict per file expected:\n{result.stdout}\n{err}")

    result = run([softflow, "check", paths["valid"], paths["petsc_ok"], paths["petsc_bad"], "--",
                  "-stokes_pc_type", "nonsense"], expect=1)
    refused = result.stderr.count("Unable to find requested PC type nonsense")
    if refused != 3 or result.stdout:
        fail(f"the options after -- go with every case, and refuse all three ({refused}):\n"
             f"{result.stdout}\n{result.stderr}")

    run([softflow, "check", paths["valid"], paths["petsc_ok"], paths["sweep"]], expect=0)

    # A valid case whose constant step is above the tangential redistribution's
    # bound 4 / (3 k): valid (exit 0), with one warning naming both keys and
    # the largest stable values; none at half the factor, none with adaptive steps.
    steps = "[[objects]]\ncapillary_number = 0.1\n[time]\nstep = 0.16\nend = 1.0\n"
    cases = {"above_bound": steps, "half_factor": steps + "[interface]\nredistribution_factor = 5.0\n",
             "adaptive": steps.replace("end = 1.0", "end = 1.0\nadaptive_tolerance = 1e-3")}
    for name, text in cases.items():
        paths[name] = os.path.join(work, name + ".toml")
        with open(paths[name], "w") as f:
            f.write(text)
    result = run([softflow, "check"] + [paths[name] for name in cases], expect=0)
    warnings = [line for line in result.stderr.splitlines() if ": warning: " in line]
    if len(result.stdout.splitlines()) != 3 or len(warnings) != 1 or paths["above_bound"] not in warnings[0]:
        fail(f"one warning, for the step above the bound, expected:\n{result.stdout}\n{result.stderr}")
    for expected in ("time.step = 0.16", "0.1333", "interface.redistribution_factor", "at most 8.333"):
        if expected not in warnings[0]:
            fail(f"the warning does not say {expected!r}: {warnings[0]}")
    print("PASS")


if __name__ == "__main__":
    main(*sys.argv[1:3])
