#!/usr/bin/env python3
"""Checkpoint and restart of a run in time, through the command-line program.

Usage: restart.py SOFTFLOW CASE.toml WORK_DIR [LAUNCHER] [--iterative]

With --iterative the case runs the iterative Stokes solver, which keeps its
fieldsplit/AMG preconditioner across steps; -stokes_pc_reuse_growth 1.0
rebuilds it as soon as a solve needs more iterations than the fewest since
its build, and the walls stop at t = 0.3 (cessation) so that one does: the
restart must rebuild the very preconditioner kept at the stop.

With LAUNCHER (e.g. "mpiexec -n 2 --oversubscribe"), parts 1 and 2 run on
several ranks, the stop request is SIGUSR1 sent to the launcher (mpirun
forwards it to every rank; SIGTERM it does not), and "round-off" allows
1e-9 relative: parallel MUMPS factors are not bit-reproducible.

1. A reference run of 20 steps.
2. The same run stopped by a real SIGTERM once it passes step 10: exit code
   5, a checkpoint, status "interrupted"; `softflow restart` continues it to
   step 20. Every column of timeseries.csv except the wall time
   (step_seconds) must equal the reference to round-off, the Stokes
   iteration counts included: the solver must rebuild the very LU factors
   it was reusing when stopped. The test forces frequent refactorisations
   (-stokes_lu_reuse_max_its 2: the solves start from the previous
   step's solution and need few iterations) so that the factors in use at the stop are
   not the first ones.
3. A run killed with SIGKILL (no chance to checkpoint) continues from its
   last periodic checkpoint; its rows past that checkpoint are recomputed.
   A fresh `run` refuses to overwrite the unfinished directory and says it
   was killed (progress.json's "running" with a dead pid); the restart says
   so too and removes the killed writer's stale checkpoint temporary.
4. A run stopped by --wall-time-limit exits with 5 and continues too.
5. A restart refuses a case.toml changed after the checkpoint, and does
   nothing for a run that is complete.
6. A restart after timeseries.csv was deleted warns and records the lost
   rows in summary.json's warnings.
"""
import os
import shutil
import signal
import sys

import cli_support as support
from cli_support import fail, read_json, rows

PETSC = ["--", "-stokes_lu_reuse_max_its", "2"]
MIN_BUILDS = 3      # preconditioner builds the reference run must make
INTERRUPTED = 5
LAUNCHER = []       # set from the command line
TOLERANCE = 1e-12   # relative, per value


def run(args, expect):
    return support.run(args, expect, LAUNCHER)


def stop_when_past(softflow, case, out, step, sig):
    """Starts a run and sends `sig` once progress.json reports `step`."""
    return support.stop_when_past([softflow, "run", case, "-o", out, "-q"] + PETSC, out, step, sig,
                                  LAUNCHER)


def compare(reference, result, what):
    """Every column but the wall time, to round-off; returns the largest difference."""
    worst = support.same_rows(reference, result, what, tolerance=TOLERANCE)
    print(f"{what}: {len(result)} rows, every column but step_seconds within "
          f"{worst:.1e} of the uninterrupted run")
    return worst


def main(softflow, case_source, work):
    shutil.rmtree(work, ignore_errors=True)
    os.makedirs(work)
    with open(case_source) as f:
        text = f.read()
    text = text.replace("fields = false", "fields = true")
    if ITERATIVE:
        # The walls stop at t = 0.3: the previous step's flow is no guess
        # for the next, the kept preconditioner needs more iterations and is
        # rebuilt (in steady shear they only fall, and it never is).
        text += '\n[solver]\ntype = "iterative"\n[flow]\ntype = "cessation"\nstop_time = 0.3\n'
    # ale_rebuild_quality near 1 rebuilds the mesh-motion operator on the
    # moved mesh after the first step: a restart must rebuild it there too.
    text = text.replace("end = 1.0", "end = 1.0\nfields_interval = 5\nale_rebuild_quality = 0.99")
    text += "\n[checkpoint]\ninterval_steps = 4\n"
    case = os.path.join(work, "case.toml")
    with open(case, "w") as f:
        f.write(text)

    # 1. Uninterrupted.
    full = os.path.join(work, "full")
    run([softflow, "run", case, "-o", full, "-q"] + PETSC, 0)
    reference = rows(full)
    factorizations = read_json(full, "summary.json")["stokes_factorizations"]
    if len(reference) != 21:
        fail(f"the reference run has {len(reference)} rows, expected 21")
    if factorizations < MIN_BUILDS:
        fail(f"only {factorizations} factorisations: the test would not exercise reused factors")
    if read_json(full, "summary.json")["ale_rebuilds"] < 1:
        fail("the mesh-motion operator was never rebuilt: the test would not exercise its restart")

    # 2. SIGTERM past step 10, then restart.
    stopped = os.path.join(work, "sigterm")
    stop = signal.SIGUSR1 if LAUNCHER else signal.SIGTERM
    code, output = stop_when_past(softflow, case, stopped, 10, stop)
    if code != INTERRUPTED:
        fail(f"{stop.name}: exit code {code}, expected {INTERRUPTED}\n{output}")
    if "softflow restart" not in output:
        fail(f"the interrupted run does not say how to continue:\n{output}")
    summary = read_json(stopped, "summary.json")
    at = summary["steps"]
    if summary["status"] != "interrupted" or summary["last_checkpoint"]["step"] != at or at >= 20:
        fail(f"after SIGTERM: status {summary['status']}, steps {at}, "
             f"checkpoint {summary['last_checkpoint']}")
    if read_json(stopped, "progress.json")["status"] != "interrupted":
        fail("progress.json does not say the run was interrupted")
    if len(rows(stopped)) != at + 1:
        fail(f"the interrupted run's time series has {len(rows(stopped))} rows for {at} steps")
    print(f"{stop.name} stopped the run at step {at} (exit code {code})")
    run([softflow, "restart", stopped, "-q"] + PETSC, 0)
    compare(reference, rows(stopped), f"{stop.name} + restart")
    summary = read_json(stopped, "summary.json")
    if summary["status"] != "completed" or summary["sessions"] != 2:
        fail(f"after the restart: status {summary['status']}, sessions {summary['sessions']}")
    if summary["stokes_factorizations"] != factorizations:
        fail(f"{summary['stokes_factorizations']} factorisations, uninterrupted {factorizations}")
    with open(os.path.join(stopped, "fields.pvd")) as f:
        pvd = f.read()
    for step in (5, 10, 15, 20):
        if f"matrix_{step:06d}.vtu" not in pvd:
            fail(f"fields.pvd lacks step {step} after the restart")
    if LAUNCHER:
        return 0  # the rest does not depend on the number of ranks

    # 3. SIGKILL: no checkpoint at the stop; the last periodic one (every 4 steps) is used.
    killed = os.path.join(work, "sigkill")
    code, output = stop_when_past(softflow, case, killed, 10, signal.SIGKILL)
    if code != -signal.SIGKILL:
        fail(f"SIGKILL: exit code {code}")
    progress = read_json(killed, "progress.json")
    if progress["status"] != "running" or progress["last_checkpoint"] is None:
        fail(f"after SIGKILL progress.json says {progress}")
    # Nothing can be written on SIGKILL: the recorded pid, now dead, tells.
    if "pid" not in progress or "host" not in progress:
        fail(f"progress.json records no pid and host: {progress}")
    # A stale temporary of a writer killed mid-checkpoint goes at the next write.
    stale = os.path.join(killed, f"checkpoint.h5.tmp-{progress['pid']}")
    with open(stale, "w") as f:
        f.write("partial")
    result = run([softflow, "run", case, "-o", killed, "-q"], 1)
    if "softflow restart" not in result.stderr or "killed" not in result.stderr:
        fail(f"a fresh run over a killed one does not say so and point to restart: {result.stderr}")
    print(f"SIGKILL at step {progress['step']}, checkpoint at {progress['last_checkpoint']['step']}")
    result = run([softflow, "restart", killed] + PETSC, 0)
    if "killed" not in result.stdout:
        fail(f"the restart does not report the killed session:\n{result.stdout[:500]}")
    if os.path.exists(stale):
        fail("the killed writer's checkpoint.h5.tmp-<pid> is still there")
    compare(reference, rows(killed), "SIGKILL + restart")

    # 4. The wall-time limit: a limit shorter than the run.
    limited = os.path.join(work, "limited")
    seconds = max(1.0, 0.5 * read_json(full, "summary.json")["wall_seconds"])
    result = run([softflow, "run", case, "-o", limited, "-q", "--wall-time-limit", f"{seconds:.2f}"]
                 + PETSC, INTERRUPTED)
    steps = read_json(limited, "summary.json")["steps"]
    print(f"--wall-time-limit {seconds:.2f} stopped the run at step {steps}")
    lost = os.path.join(work, "lost_series")  # for part 6: an unfinished run
    shutil.copytree(limited, lost)
    run([softflow, "restart", limited, "-q"] + PETSC, 0)
    compare(reference, rows(limited), "wall-time limit + restart")

    # 5. Incompatible case; a complete run.
    changed = os.path.join(work, "changed")
    shutil.copytree(killed, changed)
    case_text = open(os.path.join(changed, "case.toml")).read()
    with open(os.path.join(changed, "case.toml"), "w") as f:
        f.write(case_text.replace("capillary_number = 0.1", "capillary_number = 0.2"))
    result = run([softflow, "restart", changed, "-q"], 1)
    if "capillary_number" not in result.stderr or "not the case" not in result.stderr:
        fail(f"a changed case is not refused clearly: {result.stderr}")
    print("changed case refused: " + result.stderr.strip().splitlines()[0][:160])
    # 6. A time series deleted before the restart: continued from the
    # checkpoint with a warning, and summary.json says what is missing.
    os.remove(os.path.join(lost, "timeseries.csv"))
    result = run([softflow, "restart", lost, "-q"] + PETSC, 0)
    warnings = read_json(lost, "summary.json").get("warnings", [])
    if "timeseries.csv has no rows" not in result.stderr or not any(
            "timeseries.csv has no rows" in w for w in warnings):
        fail(f"a restart without its time series does not say so:\n{result.stderr}\n{warnings}")
    print("lost time series reported: " + warnings[0][:120])
    before = open(os.path.join(full, "timeseries.csv")).read()
    result = run([softflow, "restart", full], 0)
    if "nothing to do" not in result.stdout or open(os.path.join(full, "timeseries.csv")).read() != before:
        fail("restarting a complete run changed it")
    return 0


ITERATIVE = False


if __name__ == "__main__":
    args = [a for a in sys.argv[1:] if a != "--iterative"]
    if "--iterative" in sys.argv[1:]:
        ITERATIVE = True
        PETSC = ["--", "-stokes_pc_reuse_growth", "1.0"]
        MIN_BUILDS = 2
    if len(args) > 3 and args[3].strip():
        LAUNCHER = args[3].split()
        TOLERANCE = 1e-9
    sys.exit(main(*args[0:3]))
