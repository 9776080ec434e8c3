#!/usr/bin/python3
"""Time-to-solution benchmark: the Newtonian drop of issue 3 (lambda = 1,
Ca = 0.1, box 15 diameters) from rest to t = 10, run by the softflow binary.

For each configuration (equator nodes, dt, tension scheme) it reports wall
time, unknowns, steps, Stokes iterations and factorizations per run, the
seconds per step of each stage, and the error of the steady D against the
finest resolution available: the 50-equator-node run of the validation study
(scripts/validation/drop_shear.py), which this script runs itself if it is
missing. Each configuration runs `--repeats` times; medians are reported.
Writes docs/benchmarks/drop_shear.{md,json}.

Usage: bench/run_drop_bench.py [build_dir] [--repeats N] [--work DIR] [--rerun]"""
import argparse
import json
import os
import statistics
import subprocess
import sys

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
sys.path.insert(0, os.path.join(ROOT, "scripts", "validation"))
import drop_shear  # noqa: E402  (case text, steady-value extraction, the reference runs)

# (equator nodes, dt, semi-implicit tension, repeats or None for --repeats); t_end = 10.
# The last is the thesis's explicit tension at a step it is stable with, once:
# the baseline the semi-implicit runs are compared with.
CONFIGURATIONS = [(40, 0.05, True, None), (28, 0.1, True, None), (28, 0.05, True, None),
                  (40, 0.01, False, 1)]
T_END = 10.0


def run_once(build, work, name, n, dt, semi):
    directory = os.path.join(work, name)
    subprocess.run(["rm", "-rf", directory], check=True)
    os.makedirs(work, exist_ok=True)
    path = os.path.join(work, name + ".toml")
    with open(path, "w") as f:
        f.write(drop_shear.case_text(name, 1.0, 0.1, n, dt, T_END, semi))
    subprocess.run([os.path.join(build, "softflow"), "run", path, "-o", directory, "-q"], check=True)
    return drop_shear.load(directory)


def reference(build, validation_work):
    n, dt, t_end, semi = drop_shear.STUDY_A[-1]
    name = drop_shear.resolution_name("A", n, dt, semi)
    directory = drop_shear.run(build, validation_work, name,
                               drop_shear.case_text(name, 1.0, 0.1, n, dt, t_end, semi))
    r = drop_shear.load(directory)
    return name, r["D_steady"], r["theta_steady"]


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("build", nargs="?", default=os.path.join(ROOT, "build"))
    parser.add_argument("--repeats", type=int, default=1)
    parser.add_argument("--rerun", action="store_true", help="rerun configurations measured before")
    parser.add_argument("--work", default=os.path.join(ROOT, "output", "bench_drop_shear"))
    parser.add_argument("--validation-work", default=os.path.join(ROOT, "output", "validation_drop_shear"))
    args = parser.parse_args()
    ref_name, d_ref, theta_ref = reference(args.build, args.validation_work)
    rows = []
    for n, dt, semi, repeats in CONFIGURATIONS:
        name = f"bench_N{n}_dt{dt:g}_{'semi' if semi else 'explicit'}"
        # A configuration measured before (its row kept in the work directory)
        # is not rerun unless --rerun: the explicit baseline alone takes minutes.
        cached = os.path.join(args.work, name + ".row.json")
        if os.path.exists(cached) and not args.rerun:
            with open(cached) as f:
                row = json.load(f)
            row["D_error_vs_finest"] = row["D"] / d_ref - 1.0
            row["theta_error_vs_finest_deg"] = row["theta_deg"] - theta_ref
            rows.append(row)
            print(json.dumps(row), flush=True)
            continue
        runs = [run_once(args.build, args.work, name, n, dt, semi)
                for _ in range(repeats or args.repeats)]
        s = runs[-1]["summary"]
        row = {
            "equator_nodes": n, "dt": dt, "tension": "semi-implicit" if semi else "explicit",
            "unknowns": s["unknowns"], "steps": s["steps"],
            "wall_seconds": statistics.median(r["wall"] for r in runs),
            "wall_seconds_all": [r["wall"] for r in runs],
            "stokes_iterations_per_step": s["stokes_iterations_per_step"],
            "stokes_factorizations": s["stokes_factorizations"],
            "seconds_per_step": s["seconds_per_step"],
            "D": runs[-1]["D_steady"], "theta_deg": runs[-1]["theta_steady"],
        }
        row["D_error_vs_finest"] = row["D"] / d_ref - 1.0
        row["theta_error_vs_finest_deg"] = row["theta_deg"] - theta_ref
        row["repeats"] = len(runs)
        rows.append(row)
        with open(cached, "w") as f:
            json.dump(row, f)
        print(json.dumps(row), flush=True)
    out = os.path.join(ROOT, "docs", "benchmarks")
    os.makedirs(out, exist_ok=True)
    with open(os.path.join(out, "drop_shear.json"), "w") as f:
        json.dump({"reference": {"run": ref_name, "D": d_ref, "theta_deg": theta_ref},
                   "t_end": T_END, "repeats": args.repeats, "rows": rows}, f, indent=2)
    lines = [
        "# Drop in shear to t = 10: time to solution",
        "",
        f"lambda = 1, Ca = 0.1, box 30^3 (15 diameters), unit drop, direct solver, 1 MPI rank, "
        f"from rest to t = {T_END:g}; median wall time of the runs counted in the table. The error is "
        f"against the steady D = {d_ref:.5f}, theta = {theta_ref:.3f} deg of the finest run "
        f"(`{ref_name}` of `scripts/validation/drop_shear.py`). Regenerate with "
        "`bench/run_drop_bench.py`.",
        "",
        "| equator nodes | dt | tension | unknowns | steps | runs | wall [s] | Stokes its/step | LU factorizations | assembly [s/step] | Stokes solve [s/step] | ALE [s/step] | interface [s/step] | D | D error vs finest | theta - finest [deg] |",
        "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|",
    ]
    for r in rows:
        sp = r["seconds_per_step"]
        lines.append(
            f"| {r['equator_nodes']} | {r['dt']:g} | {r['tension']} | {r['unknowns']} | {r['steps']} | "
            f"{r.get('repeats', 1)} | "
            f"{r['wall_seconds']:.0f} | {r['stokes_iterations_per_step']:.1f} | {r['stokes_factorizations']} | "
            f"{sp['stokes_assembly']:.3f} | {sp['stokes_solve']:.3f} | {sp['ale']:.3f} | "
            f"{sp['correct_interface'] + sp['predict_and_translate']:.3f} | {r['D']:.5f} | "
            f"{r['D_error_vs_finest']:+.2%} | {r['theta_error_vs_finest_deg']:+.3f} |")
    with open(os.path.join(out, "drop_shear.md"), "w") as f:
        f.write("\n".join(lines) + "\n")
    print("\n".join(lines))


if __name__ == "__main__":
    main()
