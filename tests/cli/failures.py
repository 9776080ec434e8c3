#!/usr/bin/env python3
"""A run in time never dies silently: each way of failing stops it with the
documented exit code and a message saying what happened, at which step, where,
and what to try; the output so far and the last checkpoint stay readable.

Usage: failures.py SOFTFLOW CASE.toml WORK_DIR   (CASE: the coarse drop_short case)
"""
import csv
import json
import os
import re
import shutil
import subprocess
import sys


def fail(message):
    print("FAIL: " + message)
    sys.exit(1)


def run(args):
    return subprocess.run(args, capture_output=True, text=True)


def expect_stop(softflow, work, name, text, code, patterns, extra=()):
    """Runs `text` as a case; checks exit code, message and the kept output."""
    case = os.path.join(work, name + ".toml")
    out = os.path.join(work, name)
    with open(case, "w") as f:
        f.write(text)
    result = run([softflow, "run", case, "-o", out, "-q"] + list(extra))
    if result.returncode != code:
        fail(f"{name}: exit code {result.returncode}, expected {code}\n{result.stdout}{result.stderr}")
    for pattern in patterns:
        if not re.search(pattern, result.stderr):
            fail(f"{name}: the message lacks /{pattern}/:\n{result.stderr}")
    with open(os.path.join(out, "summary.json")) as f:
        summary = json.load(f)
    with open(os.path.join(out, "progress.json")) as f:
        progress = json.load(f)
    if summary["status"] != "stopped" or progress["status"] != "stopped":
        fail(f"{name}: status {summary['status']} / {progress['status']}, expected stopped")
    if summary["stop_reason"].split(".")[0] not in result.stderr:
        fail(f"{name}: summary.json's stop_reason differs from the message")
    with open(os.path.join(out, "timeseries.csv")) as f:
        rows = list(csv.DictReader(f))
    if len(rows) != summary["steps"] + 1:
        fail(f"{name}: {len(rows)} rows for {summary['steps']} completed steps")
    print(f"{name}: exit {code}: {result.stderr.strip()[:200]}")
    return out, summary, result.stderr


def main(softflow, case_source, work):
    shutil.rmtree(work, ignore_errors=True)
    os.makedirs(work)
    base = open(case_source).read()

    # A collapsing element: large Ca and dt tangle the never-remeshed mesh at step 9.
    text = base.replace("capillary_number = 0.1", "capillary_number = 0.3")
    text = text.replace("step = 0.05", "step = 0.15")
    text = text.replace("end = 1.0", "end = 3.0\nmax_volume_drift = 0.5")
    text += "\n[checkpoint]\ninterval_steps = 2\n"
    out, summary, message = expect_stop(softflow, work, "collapse", text, 2,
                                        [r"step \d+ \(t = ", r"element \d+", "quality", "try",
                                         r"last checkpoint \(step \d+"])
    failed_at = re.search(r"step (\d+) \(t = ", message).group(1)
    checkpoint = summary["last_checkpoint"]["step"]
    if not 0 < checkpoint < int(failed_at):
        fail(f"collapse: last checkpoint at {checkpoint}, failure at step {failed_at}")
    # The checkpoint is readable: a restart continues from it and meets the same failure.
    result = run([softflow, "restart", out, "-q"])
    if result.returncode != 2 or f"step {failed_at} (t = " not in result.stderr:
        fail(f"restart after the collapse: exit {result.returncode}: {result.stderr}")
    print(f"collapse: restart from step {checkpoint} fails again at step {failed_at}")

    # Volume drift past a tight limit (the coarse drop loses ~0.1 % at step 1).
    text = base.replace("end = 1.0", "end = 1.0\nmax_volume_drift = 0.0005")
    expect_stop(softflow, work, "volume_drift", text, 6,
                [r"step 1 \(t = ", "object 1", "volume", "time.max_volume_drift", "[Tt]ry"])

    # The same failure with checkpoints every 5 steps: the message says the
    # run failed before the first one, not that interval_steps should be set.
    text += "\n[checkpoint]\ninterval_steps = 5\n"
    _, _, message = expect_stop(softflow, work, "volume_drift_checkpointed", text, 6,
                                ["failed before step 5, the first checkpoint"])
    if "sets how often" in message:
        fail(f"volume_drift_checkpointed: advises a key that is already set: {message}")

    # A solver that does not converge.
    text = base + '\n[solver]\ntype = "iterative"\nmax_iterations = 2\n'
    expect_stop(softflow, work, "no_convergence", text, 3,
                [r"step 1 \(t = ", "did not converge", "DIVERGED_ITS", "try"])

    # NaN/Inf in the solution from a solver that does not notice: Richardson
    # overflowing, with no residual test (PETSc options after "--").
    expect_stop(softflow, work, "not_finite", base, 3,
                [r"step 1 \(t = ", "not finite", "nan", r"node \d+", "in the matrix", "try"],
                ["--", "-stokes_ksp_type", "richardson", "-stokes_ksp_richardson_scale", "1e300",
                 "-stokes_ksp_max_it", "5", "-stokes_ksp_norm_type", "none",
                 "-stokes_ksp_convergence_test", "skip", "-stokes_pc_type", "none"])

    # The direct solver's factorisation failing (PETSc's own LU, which does
    # not pivot, on the saddle point): the advice must not be to switch to
    # the direct solver.
    out, summary, message = expect_stop(
        softflow, work, "lu_failed", base, 3,
        [r"step 1 \(t = ", "DIVERGED_PC_FAILED", "LU factorisation failed", "time.step"],
        ["--", "-stokes_pc_factor_mat_solver_type", "petsc"])
    if 'type = "direct"' in message:
        fail(f"lu_failed: advises the direct solver to a direct run: {message}")

    # An absurd interfacial tension (Ca = 1e-300) blows the interface up in one
    # step. Which check stops it first (a non-finite position, or a volume
    # change of ~1e11 %) depends on round-off in sums of ~1e300 terms, e.g.
    # the element order of the assembly; either message names the object
    # and gives advice.
    text = base.replace("capillary_number = 0.1", "capillary_number = 1e-300")
    expect_stop(softflow, work, "blow_up", text, 6, [r"step 1 \(t = ", "object 1", "[Tt]ry"])

    # An initial mesh below time.min_quality: refused before the run, naming
    # the mesh keys, exit 2, and nothing written (it used to stop at step 1
    # advising a smaller time step).
    text = base.replace("end = 1.0", "end = 1.0\nmin_quality = 0.5")
    out = os.path.join(work, "poor_initial_mesh")
    case = out + ".toml"
    with open(case, "w") as f:
        f.write(text)
    result = run([softflow, "run", case, "-o", out, "-q"])
    if result.returncode != 2:
        fail(f"poor_initial_mesh: exit {result.returncode}, expected 2\n{result.stderr}")
    for pattern in ["initial mesh", "time.min_quality = 0.5", "mesh.equator_nodes", "mesh.far_size"]:
        if pattern not in result.stderr:
            fail(f"poor_initial_mesh: the message lacks '{pattern}':\n{result.stderr}")
    if os.path.exists(out):
        fail("poor_initial_mesh: an output directory was written")
    print(f"poor_initial_mesh: exit 2: {result.stderr.strip()[:200]}")
    return 0


if __name__ == "__main__":
    sys.exit(main(*sys.argv[1:4]))
