#!/usr/bin/python3
"""Stokes-solve benchmark: direct (MUMPS) and iterative (Schur fieldsplit +
BoomerAMG) solvers on 1 and 2 MPI ranks, on the 'unbounded' cell (box 15
drop diameters, unit drop, lambda = 1, Ca = 0.1).

Every configuration runs `repeats` times in one process (the first solve
includes setup); medians are reported. Writes docs/benchmarks/stokes_solve.md
and .json. Usage: bench/run_stokes_bench.py [build_dir] [equator_nodes] [repeats]
"""
import json
import os
import statistics
import subprocess
import sys

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


def run(build, method, ranks, equator_nodes, repeats):
    exe = os.path.join(build, "bench", "stokes_solve")
    cmd = [exe, method, str(equator_nodes), str(repeats)]
    if ranks > 1:
        cmd = ["mpirun", "-n", str(ranks), "--oversubscribe", "--allow-run-as-root"] + cmd
    out = subprocess.run(cmd, check=True, capture_output=True, text=True).stdout
    return [json.loads(line) for line in out.splitlines() if line.startswith("{")]


def main():
    build = sys.argv[1] if len(sys.argv) > 1 else os.path.join(ROOT, "build")
    equator_nodes = int(sys.argv[2]) if len(sys.argv) > 2 else 40
    repeats = int(sys.argv[3]) if len(sys.argv) > 3 else 3
    rows = []
    reference = None
    for method in ("direct", "iterative"):
        for ranks in (1, 2):
            records = run(build, method, ranks, equator_nodes, repeats)
            for phase in ("cold", "warm"):
                rs = [r for r in records if r["phase"] == phase]
                row = {
                    "method": method,
                    "phase": phase,
                    "ranks": ranks,
                    "unknowns": rs[0]["unknowns"],
                    "tets": rs[0]["tets"],
                    "assembly_s": statistics.median(r["assembly_seconds"] for r in rs),
                    "solve_s": statistics.median(r["solve_seconds"] for r in rs),
                    "iterations": statistics.median(r["iterations"] for r in rs),
                    "pressure_jump": rs[-1]["pressure_jump"],
                }
                if reference is None:
                    reference = row["pressure_jump"]
                row["jump_difference_vs_direct_1"] = abs(row["pressure_jump"] - reference)
                rows.append(row)
                print(row, flush=True)
    os.makedirs(os.path.join(ROOT, "docs", "benchmarks"), exist_ok=True)
    with open(os.path.join(ROOT, "docs", "benchmarks", "stokes_solve.json"), "w") as f:
        json.dump({"equator_nodes": equator_nodes, "repeats": repeats, "rows": rows}, f, indent=2)
    lines = [
        "# Stokes solve benchmark",
        "",
        f"Cell 30 x 30 x 30 (15 drop diameters), unit drop, lambda = 1, Ca = 0.1, "
        f"equator_nodes = {equator_nodes}; medians of {repeats} repeats in one process. "
        "A repeat builds a fresh system and solves twice: *cold* (pattern, LU "
        "factorisation or AMG setup, solve) and *warm* (the same problem again: the "
        "direct method's GMRES reuses the factorisation, as the time loop does while the "
        "mesh moves slowly; the iterative method rebuilds its preconditioner). "
        "Regenerate with `bench/run_stokes_bench.py`.",
        "",
        "| solver | phase | ranks | unknowns | tets | assembly [s] | solve [s] | iterations | pressure jump | diff. vs direct/1 |",
        "|---|---|---|---|---|---|---|---|---|---|",
    ]
    for r in rows:
        lines.append(
            f"| {r['method']} | {r['phase']} | {r['ranks']} | {r['unknowns']} | {r['tets']} | {r['assembly_s']:.3f} | "
            f"{r['solve_s']:.3f} | {r['iterations']:.0f} | {r['pressure_jump']:.8f} | "
            f"{r['jump_difference_vs_direct_1']:.1e} |")
    with open(os.path.join(ROOT, "docs", "benchmarks", "stokes_solve.md"), "w") as f:
        f.write("\n".join(lines) + "\n")


if __name__ == "__main__":
    main()
