#!/usr/bin/env python3
"""Node relocation of the moving mesh (time.relocation_quality), through the program.

Usage: node_relocation.py SOFTFLOW WORK_DIR [MPI launcher words...]

A drop at Ca = 0.3 (lambda = 1) on a coarse mesh (20 equator nodes): the
harmonic mesh motion alone folds the P2 map of an element at the drop's tip
(quality below time.min_quality at t ~ 0.64, D ~ 0.2).
1. With relocation_quality = 0 the run stops there: exit 2, the message
   names the degraded element.
2. With the default relocation it runs to t = 1 (D ~ 0.26): the smallest
   element quality never falls below 0.15, summary.json counts the
   relocations, the volume drift stays below 1e-3 and D agrees with the
   unrelocated run to 1e-3 wherever both ran (the relocation is part of the
   ALE motion: a relocation that moved nodes without telling the mesh
   velocity would shift the fields, and the interface, by it).
3. A run stopped by SIGTERM after relocations began and restarted equals
   the uninterrupted run in every column to round-off.
4. With an MPI launcher: two ranks equal one.
"""
import os
import shutil
import signal
import sys

from cli_support import fail, run, rows, read_json, same_rows, stop_when_past

CASE = """
[case]
name = "relocation"
[[objects]]
viscosity_ratio = 1.0
capillary_number = 0.3
[mesh]
equator_nodes = 20
far_size = 4.5
growth = 0.56
[time]
step = 0.02
end = 1.0
{extra}
[checkpoint]
interval_steps = 0
interval_minutes = 0
[output]
fields = false
"""
INTERRUPTED = 5
MESH_DEGRADED = 2


def write_case(work, name, extra=""):
    path = os.path.join(work, name + ".toml")
    with open(path, "w") as f:
        f.write(CASE.format(extra=extra))
    return path


def main():
    softflow, work = sys.argv[1], sys.argv[2]
    launcher = sys.argv[3:]
    shutil.rmtree(work, ignore_errors=True)
    os.makedirs(work)

    # 1. Without relocation the mesh folds.
    plain = os.path.join(work, "plain")
    result = run([softflow, "run", write_case(work, "plain", "relocation_quality = 0.0"),
                  "--output", plain], expect=MESH_DEGRADED)
    if "the moving mesh degraded" not in result.stderr:
        fail(f"relocation off: no degraded-mesh message:\n{result.stderr}")
    unrelocated = rows(plain)
    t_fold = float(unrelocated[-1]["t"])
    if not 0.3 < t_fold < 0.9:
        fail(f"relocation off: stopped at t = {t_fold}, expected near 0.64 (has the mesh changed?)")

    # 2. With it the run goes on.
    case = write_case(work, "relocated")
    relocated = os.path.join(work, "relocated")
    run([softflow, "run", case, "--output", relocated])
    series = rows(relocated)
    if abs(float(series[-1]["t"]) - 1.0) > 1e-9:
        fail(f"relocated run ended at t = {series[-1]['t']}")
    worst = min(float(r["min_quality"]) for r in series)
    if worst < 0.15:
        fail(f"relocated run: element quality fell to {worst}")
    summary = read_json(relocated)
    if summary["relocation_steps"] <= 0 or summary["relocated_nodes"] <= 0:
        fail(f"summary.json counts no relocation: {summary['relocation_steps']}, "
             f"{summary['relocated_nodes']}")
    v0 = float(series[0]["volume"])
    drift = max(abs(float(r["volume"]) / v0 - 1.0) for r in series)
    if drift > 1e-3:
        fail(f"relocated run: volume drift {drift:.2e}")
    largest = 0.0
    for a, b in zip(unrelocated, series):
        if a["t"] != b["t"]:
            fail(f"step {a['step']}: t = {b['t']} vs {a['t']}")
        largest = max(largest, abs(float(a["D"]) - float(b["D"])))
    if largest > 1e-3:
        fail(f"D with and without relocation differ by {largest:.2e} where both ran")
    print(f"relocation off: folds at t = {t_fold}; on: t = 1, D = {float(series[-1]['D']):.5f}, "
          f"quality >= {worst:.3f}, {summary['relocation_steps']} relocation steps, "
          f"volume drift {drift:.1e}, D differs by <= {largest:.1e} where both ran")

    # 3. Stop and restart after relocations began.
    stopped = os.path.join(work, "stopped")
    code, output = stop_when_past([softflow, "run", case, "--output", stopped], stopped, 40,
                                  signal.SIGTERM)
    if code != INTERRUPTED:
        fail(f"SIGTERM: exit code {code}, expected {INTERRUPTED}\n{output}")
    run([softflow, "restart", stopped])
    same_rows(series, rows(stopped), "restarted run")
    print("stopped at step 40 and restarted: every column equal")

    # 4. Two ranks.
    if launcher:
        parallel = os.path.join(work, "parallel")
        run([softflow, "run", case, "--output", parallel], launcher=launcher)
        same_rows(series, rows(parallel), "two ranks", tolerance=1e-9)
        print("two ranks: every column equal to 1e-9")
    print("PASS")


if __name__ == "__main__":
    main()
