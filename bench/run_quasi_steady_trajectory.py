#!/usr/bin/python3
"""Wall time per quasi-steady Giesekus migration trajectory (issue 35's
benchmark: one trajectory from y_p0 = 0.35 H in at most 4 hours on this 2-core
machine, on the mesh the convergence study asks for).

A trajectory is `softflow migration --trajectory-from` along the master curve
of short runs from several heights (scripts/validation/
giesekus_quasi_steady_trajectory.py: 20 equator nodes; giesekus_quasi_steady_resolved.py:
28, the convergence study's level). Its cost is the curve's runs, two at a
time on the two cores (each run one rank), plus the command.

By default the level's starts are run here, in the validation script's order,
`--jobs` at a time, and the wall clock of the whole is measured. With
--from-runs DIR the finished runs of a validation script's work directory are
read instead: their own wall times (each measured beside the other run of its
pair), and the wall clock of the whole is reconstructed by handing the runs, in
the script's order, to `--jobs` workers as each frees, as the script does.

--mirror-averaged measures the 28-node curve on gmsh's meshes only instead
(giesekus_quasi_steady_resolved.py's GMSH_CURVE): each start averaged with its
mirror start where one runs, four more runs, none carried from the
point-symmetric mesh (whose error near the centre plane the mirror pairs found).

Writes docs/benchmarks/quasi_steady_trajectory.{md,json} (one row per level
and curve; a level measured again replaces its row).
Usage: bench/run_quasi_steady_trajectory.py [build_dir] [--nodes 20|28] [--mirror-averaged] [--work DIR] [--jobs N]
                                            [--from-runs DIR]"""
import argparse
import concurrent.futures
import json
import os
import sys
import time

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
sys.path.insert(0, os.path.join(ROOT, "scripts", "validation"))
import giesekus_quasi_steady_resolved as resolved  # noqa: E402
import giesekus_quasi_steady_trajectory as coarse  # noqa: E402
from case_runs import run_softflow, summary_of  # noqa: E402
from migration_runs import quasi_steady_path, read_csv, read_migration  # noqa: E402

OUT = os.path.join(ROOT, "docs", "benchmarks")
LEVELS = {coarse.COARSE.nodes: coarse.COARSE, resolved.LEVEL.nodes: resolved.LEVEL}
TARGET_HOURS = 4.0
TARGET_NODES = resolved.NODES  # the level the convergence study asks for


CARRIED, MIRRORED = "carried below 0.20 H", "gmsh only, mirror-averaged"  # the 28-node curves


def run_here(build, work, level_jobs, jobs):
    """Runs the (name, case text) list `jobs` at a time; returns the whole's wall clock."""
    os.makedirs(work, exist_ok=True)

    def one(job):
        name, text = job
        path = os.path.join(work, name + ".toml")
        with open(path, "w") as f:
            f.write(text)
        # As the validation scripts launch it: a rebuild during the bench waits rather than failing the run.
        run_softflow([os.path.join(build, "softflow"), "run", path, "-o", os.path.join(work, name), "-q",
                      "--overwrite"]).check_returncode()

    began = time.monotonic()
    with concurrent.futures.ThreadPoolExecutor(jobs) as pool:
        list(pool.map(one, level_jobs))
    return time.monotonic() - began, "measured"


def reconstructed_wall(seconds, jobs):
    """The wall clock of runs taking `seconds` (in order) handed to `jobs` workers as each frees."""
    free = [0.0] * jobs
    for s in seconds:
        i = free.index(min(free))
        free[i] += s
    return max(free)


def curve_of(level, mirrored):
    return MIRRORED if mirrored else (CARRIED if level.symmetric_below > 0.0 else "gmsh's meshes")


def measure(build, level, work, jobs, from_runs, mirrored=False):
    level_jobs = resolved.gmsh_curve_jobs() if mirrored else level.jobs()  # in the order they run
    if from_runs:
        work = from_runs
    else:
        wall, how = run_here(build, work, level_jobs, jobs)
    starts = []
    for name, _ in level_jobs:
        directory = os.path.join(work, name)
        summary = summary_of(directory)
        if summary.get("status") != "completed":
            sys.exit(f"{directory}: not a completed run (status {summary.get('status')!r}); run "
                     f"scripts/validation/{level.stem}.py first, or leave out --from-runs")
        rows = [r for r in read_csv(os.path.join(directory, "timeseries.csv")) if r["object"] == "1"]
        starts.append({"run": name, "directory": directory, "unknowns": summary["unknowns"],
                       "wall_seconds": summary["wall_seconds"],
                       "stokes_iterations_per_step": summary["stokes_iterations_per_step"],
                       "steps": len(rows)})
    if from_runs:
        wall, how = reconstructed_wall([x["wall_seconds"] for x in starts], jobs), "reconstructed"
    began = time.monotonic()
    if mirrored:
        q = resolved.mirror_averaged_curve(work, build)
    else:
        top = read_migration(os.path.join(work, level.name(max(level.starts))), coarse.HEIGHT)
        q = quasi_steady_path(build, sorted((x["directory"] for x in starts)),
                              os.path.join(work, "bench_curves"), (top["t"], top["y"]), coarse.TRANSIENT,
                              coarse.STRETCH, coarse.Y_MAX_OVER_H)
    command_seconds = time.monotonic() - began
    return {"equator_nodes": level.nodes, "curve": curve_of(level, mirrored), "starts": starts, "jobs": jobs,
            "runs_wall_clock_seconds": wall,
            "wall_clock_is": how, "core_seconds": sum(x["wall_seconds"] for x in starts),
            "command_seconds": command_seconds, "trajectory_time_units": q["t"][-1] - q["t"][0],
            "trajectory_from": q["y0"], "trajectory_to": q["y"][-1], "ends": q["ends"],
            "hours": (wall + command_seconds) / 3600.0}


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("build", nargs="?", default=os.path.join(ROOT, "build"))
    parser.add_argument("--nodes", type=int, default=resolved.LEVEL.nodes, choices=sorted(LEVELS))
    parser.add_argument("--work", default=None, help="where the runs go (default output/bench_quasi_steady_NODES)")
    parser.add_argument("--jobs", type=int, default=2)
    parser.add_argument("--from-runs", default=None, help="a validation script's work directory of finished runs")
    parser.add_argument("--mirror-averaged", action="store_true",
                        help=f"the {resolved.NODES}-node curve on gmsh's meshes only, mirror starts averaged in")
    args = parser.parse_args()
    level = LEVELS[args.nodes]
    if args.mirror_averaged and level is not resolved.LEVEL:
        sys.exit(f"--mirror-averaged: the mirror starts exist for the {resolved.NODES}-node curve only, "
                 f"not for --nodes {args.nodes}")
    work = args.work or os.path.join(ROOT, "output", f"bench_quasi_steady_{args.nodes}"
                                                       + ("_mirror" if args.mirror_averaged else ""))
    result = measure(os.path.abspath(args.build), level, work, args.jobs, args.from_runs, args.mirror_averaged)
    print(json.dumps(result, indent=1))

    json_path = os.path.join(OUT, "quasi_steady_trajectory.json")
    results = json.load(open(json_path)) if os.path.exists(json_path) else []
    for r in results:  # rows written before the gmsh-only curve: the level's own
        r.setdefault("curve", curve_of(LEVELS[r["equator_nodes"]], False))

    def key(r):
        return r["equator_nodes"], r["curve"]
    results = sorted([r for r in results if key(r) != key(result)] + [result], key=key)
    with open(json_path, "w") as f:
        json.dump(results, f, indent=1)
    md = ["# Wall time per quasi-steady Giesekus migration trajectory (issue 35)", "",
          "Generated by `bench/run_quasi_steady_trajectory.py`: beta = 0.2, Ca_e = 0.1 (p = 4.5), Wi = 0.5, "
          "alpha_m = 0.2, dt = 0.04, step-limited SUPG parameter; the master curve of starts at seven heights "
          "(0.10-0.35 H; on 28 nodes either carried from the point-symmetric mesh below 0.20 H, or all on gmsh's "
          "meshes with mirror starts at -0.10, -0.15, -0.20 and -0.28 H averaged in) each run to t = 6 on one rank, `jobs` at a time on the 2-core machine, then `softflow "
          "migration --trajectory-from` from the 0.35 H start's first stretch (docs/validation/"
          "giesekus_quasi_steady_trajectory.md, giesekus_quasi_steady_resolved.md). Wall clock: measured around "
          "the runs, or reconstructed from each run's own wall time (measured beside whatever else ran then: on "
          "20 nodes the 0.10 and 0.28 H starts are giesekus_trajectory_time_step.py's, run in other pairs) by "
          "handing the runs in order to `jobs` workers, as the validation scripts do. Target: "
          f"{TARGET_HOURS:g} hours on this machine, on the mesh the convergence study asks for ({TARGET_NODES} nodes: "
          "docs/validation/delta_s_resolution.md).", "",
          "| equator nodes | curve | runs | jobs | unknowns | Stokes iterations per step | core hours | wall clock [h] | "
          "wall clock is | trajectory [time units] | from -> to [H] | ends | within 4 h |",
          "|---|---|---|---|---|---|---|---|---|---|---|---|---|"]
    for r in results:
        unknowns = [x["unknowns"] for x in r["starts"]]
        its = [x["stokes_iterations_per_step"] for x in r["starts"]]
        within = ("yes" if r["hours"] <= TARGET_HOURS else "no") if r["equator_nodes"] == TARGET_NODES else \
            "n/a (not the target's mesh)"
        md.append(f"| {r['equator_nodes']} | {r['curve']} | {len(r['starts'])} | {r['jobs']} | "
                  f"{min(unknowns)}-{max(unknowns)} | "
                  f"{min(its):.1f}-{max(its):.1f} | "
                  f"{r['core_seconds'] / 3600:.2f} | {r['hours']:.2f} | {r['wall_clock_is']} | "
                  f"{r['trajectory_time_units']:.1f} | {r['trajectory_from']:.4f} -> {r['trajectory_to']:.4f} | "
                  f"{r['ends']} | {within} |")
    with open(os.path.join(OUT, "quasi_steady_trajectory.md"), "w") as f:
        f.write("\n".join(md) + "\n")
    print("\n".join(md))


if __name__ == "__main__":
    main()
