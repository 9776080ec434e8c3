#!/usr/bin/python3
"""Where LU reuse beats the iterative Stokes path, as a function of the run's
length (issue 34, item 1): the main drop (examples/drop_shear.toml's physics:
lambda = 1, Ca = 0.1, cell 30^3, far_size 3) at several mesh sizes, STEPS constant steps
of dt = 0.1 on one rank, once with solver.type = "direct" and once with
"iterative". From each run's step_seconds (timeseries.csv): the first step
(the direct path factors there; the iterative one builds BoomerAMG) and the
median of the later ones (the direct path reuses its factors as a
preconditioner, the iterative one its hierarchy). A run of S steps then costs
about first + (S - 1) later, and the direct path is the faster one from

    S* = 1 + (first_direct - first_iterative) / (later_iterative - later_direct)

steps on (never, if its later steps are not cheaper). Writes
docs/benchmarks/solver_crossover.{md,json}. Timings on a shared machine are
noisy: the runs of one size are made back to back and only their ratios and
S* are used.
With --physics stress: the same measurement for systems whose matrix carries
the stress terms of a phase with a conformation (the D'Avino-Hulsen and
DEVSS-G terms, which change every step): a neo-Hookean particle (Ca_e = 0.1)
in a Newtonian matrix and in a Giesekus one (alpha = 0.2, mu = 0.1,
eta_p = 0.9, lambda = 0.5: p = 4.5), and an Oldroyd-B drop (lambda = 1,
Ca = 0.1, mu_d = eta_pd = 0.5, lambda_d = 1), cell 20^3, far_size 2.5,
dt = 0.04; written to docs/benchmarks/solver_crossover_stress.{md,json}.
Usage: bench/run_solver_crossover.py [build_dir] [equator_nodes,...] [--steps N] [--add] [--physics stress]"""
import argparse
import csv
import json
import os
import statistics
import subprocess
import tempfile

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


# --physics stress: (name, [matrix] and [[objects]] tables).
STRESS_CASES = [
    ("neo_hookean_particle", """[[objects]]
model = "neo_hookean"
elastic_capillary_number = 0.1
"""),
    ("particle_in_giesekus", """[matrix]
model = "giesekus"
solvent_viscosity = 0.1
polymer_viscosity = 0.9
relaxation_time = 0.5
mobility = 0.2
[[objects]]
model = "neo_hookean"
elastic_capillary_number = 0.1
"""),
    ("oldroyd_b_drop", """[[objects]]
capillary_number = 0.1
model = "oldroyd_b"
solvent_viscosity = 0.5
polymer_viscosity = 0.5
relaxation_time = 1.0
"""),
]


def stress_case_text(physics, nodes, solver, steps, directory):
    return f"""[case]
name = "crossover"
[cell]
length = 20.0
height = 20.0
width = 20.0
{physics}[mesh]
equator_nodes = {nodes}
far_size = 2.5
[solver]
type = "{solver}"
[time]
step = 0.04
end = {0.04 * steps:.6g}
min_quality = 0.001         # a solver benchmark of 8 steps: gmsh's 70-node mesh here has an element at 0.0075
[output]
fields = false
directory = "{directory}"
"""


def case_text(nodes, solver, steps, directory):
    return f"""[case]
name = "crossover"
[[objects]]
viscosity_ratio = 1.0
capillary_number = 0.1
[mesh]
equator_nodes = {nodes}
[solver]
type = "{solver}"
[time]
step = 0.1
end = {0.1 * steps:.6g}
min_quality = 0.005         # a solver benchmark: gmsh's 70-node mesh has one element at 0.008
[output]
fields = false
directory = "{directory}"
"""


def run(build, nodes, solver, steps, work, physics=None):
    directory = os.path.join(work, f"n{nodes}_{solver}")
    path = directory + ".toml"
    with open(path, "w") as f:
        f.write(case_text(nodes, solver, steps, directory) if physics is None
                else stress_case_text(physics, nodes, solver, steps, directory))
    subprocess.run([os.path.join(build, "softflow"), "run", path, "-q", "--overwrite"], check=True)
    summary = json.load(open(os.path.join(directory, "summary.json")))
    with open(os.path.join(directory, "timeseries.csv")) as f:
        # Row 0 is the initial state (no step).
        seconds = [float(r["step_seconds"]) for r in csv.DictReader(f) if r["object"] == "1"][1:]
    with open(os.path.join(directory, "timeseries.csv")) as f:
        iterations = [int(r["stokes_iterations"]) for r in csv.DictReader(f) if r["object"] == "1"][2:]
    return {"unknowns": summary["unknowns"], "first": seconds[0], "later": statistics.median(seconds[1:]),
            "later_iterations": statistics.median(iterations),
            "wall": summary["wall_seconds"], "peak_mb": summary["peak_memory_mb"]["largest_rank"]
            if isinstance(summary.get("peak_memory_mb"), dict) else summary.get("peak_memory_mb")}


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("build", nargs="?", default=os.path.join(ROOT, "build"))
    parser.add_argument("nodes", nargs="?", default="40,70,100")
    parser.add_argument("--steps", type=int, default=8)
    parser.add_argument("--add", action="store_true",
                        help="keep the sizes already in solver_crossover.json that this run does not measure")
    parser.add_argument("--physics", choices=["newtonian", "stress"], default="newtonian")
    args = parser.parse_args()
    if args.physics == "stress":
        return stress_main(args)
    out = os.path.join(ROOT, "docs", "benchmarks")
    rows = []
    with tempfile.TemporaryDirectory() as work:
        for nodes in [int(n) for n in args.nodes.split(",")]:
            direct = run(args.build, nodes, "direct", args.steps, work)
            iterative = run(args.build, nodes, "iterative", args.steps, work)
            gain = iterative["later"] - direct["later"]
            crossover = 1 + (direct["first"] - iterative["first"]) / gain if gain > 0 else None
            rows.append({"equator_nodes": nodes, "unknowns": direct["unknowns"], "direct": direct,
                         "iterative": iterative, "crossover_steps": crossover})
            print(json.dumps(rows[-1]), flush=True)
    if args.add and os.path.exists(os.path.join(out, "solver_crossover.json")):
        measured = {r["equator_nodes"] for r in rows}
        kept = [r for r in json.load(open(os.path.join(out, "solver_crossover.json")))
                if r["equator_nodes"] not in measured]
        rows = sorted(kept + rows, key=lambda r: r["unknowns"])
    with open(os.path.join(out, "solver_crossover.json"), "w") as f:
        json.dump(rows, f, indent=1)
    lines = ["# Direct against iterative Stokes solves over a run's length", "",
             "Generated by `bench/run_solver_crossover.py`: the main drop (lambda = 1, Ca = 0.1, cell 30^3, "
             f"far_size 3), {args.steps} steps of dt = 0.1, one rank. First: the first step's wall time (the "
             "direct path factors, the iterative one builds its preconditioner); later: the median of the "
             "other steps' (both reuse what they built). S*: the run length from which the direct path "
             "is faster, 1 + (first_direct - first_iterative) / (later_iterative - later_direct).", "",
             "| equator nodes | unknowns | direct first [s] | direct later [s] | iterative first [s] | "
             "iterative later [s] | S* [steps] | direct peak MB | iterative peak MB |",
             "|---|---|---|---|---|---|---|---|---|"]
    for r in rows:
        d, i = r["direct"], r["iterative"]
        s = "never" if r["crossover_steps"] is None else f"{r['crossover_steps']:.1f}"
        lines.append(f"| {r['equator_nodes']} | {r['unknowns']} | {d['first']:.2f} | {d['later']:.3f} | "
                     f"{i['first']:.2f} | {i['later']:.3f} | {s} | {d['peak_mb']:.0f} | {i['peak_mb']:.0f} |")
    with open(os.path.join(out, "solver_crossover.md"), "w") as f:
        f.write("\n".join(lines) + "\n")
    print("\n".join(lines))


def stress_main(args):
    out = os.path.join(ROOT, "docs", "benchmarks")
    rows = []
    with tempfile.TemporaryDirectory() as work:
        for nodes in [int(n) for n in args.nodes.split(",")]:
            for name, physics in STRESS_CASES:
                direct = run(args.build, nodes, "direct", args.steps, work, physics)
                iterative = run(args.build, nodes, "iterative", args.steps, work, physics)
                gain = iterative["later"] - direct["later"]
                crossover = 1 + (direct["first"] - iterative["first"]) / gain if gain > 0 else None
                rows.append({"case": name, "equator_nodes": nodes, "unknowns": direct["unknowns"],
                             "direct": direct, "iterative": iterative, "crossover_steps": crossover})
                print(json.dumps(rows[-1]), flush=True)
    path = os.path.join(out, "solver_crossover_stress.json")
    if args.add and os.path.exists(path):
        measured = {(r["case"], r["equator_nodes"]) for r in rows}
        rows = [r for r in json.load(open(path)) if (r["case"], r["equator_nodes"]) not in measured] + rows
    rows.sort(key=lambda r: (r["unknowns"], [c for c, _ in STRESS_CASES].index(r["case"])))
    with open(path, "w") as f:
        json.dump(rows, f, indent=1)
    write_stress_report(rows, args.steps)


def write_stress_report(rows, steps):
    out = os.path.join(ROOT, "docs", "benchmarks")
    lines = ["# Direct against iterative Stokes solves with stress terms in the matrix", "",
             "Generated by `bench/run_solver_crossover.py --physics stress`: cell 20^3, far_size 2.5, "
             f"{steps} steps of dt = 0.04, one rank; columns as in solver_crossover.md, with the median "
             "GMRES iterations of the later steps (the direct path's, preconditioned by its first step's "
             "factors; the iterative path's, by its kept fieldsplit).", "",
             "| case | equator nodes | unknowns | direct first [s] | direct later [s] | direct its | "
             "iterative first [s] | iterative later [s] | iterative its | S* [steps] | direct peak MB | "
             "iterative peak MB |", "|---|---|---|---|---|---|---|---|---|---|---|---|"]
    for r in rows:
        d, i = r["direct"], r["iterative"]
        s = "never" if r["crossover_steps"] is None else f"{r['crossover_steps']:.1f}"
        lines.append(f"| {r['case']} | {r['equator_nodes']} | {r['unknowns']} | {d['first']:.2f} | "
                     f"{d['later']:.3f} | {d['later_iterations']:g} | {i['first']:.2f} | {i['later']:.3f} | "
                     f"{i['later_iterations']:g} | {s} | {d['peak_mb']:.0f} | {i['peak_mb']:.0f} |")
    with open(os.path.join(out, "solver_crossover_stress.md"), "w") as f:
        f.write("\n".join(lines) + "\n")
    print("\n".join(lines))


if __name__ == "__main__":
    main()
