#!/usr/bin/python3
"""Before/after time-to-solution benchmark of two softflow builds.

Runs the drop-in-shear case of bench/run_drop_bench.py (lambda = 1, Ca = 0.1,
from rest to t = 10, semi-implicit tension) on 28 and 40 equator nodes with
dt = 0.05, alternating the two binaries (before, after, before, after, ...)
so both see the same machine load, and reports per configuration and binary
the median wall time, the median seconds per step of each stage, Stokes
iterations per step, factorizations, the final D and theta, and the
after/before wall-time ratio. Writes docs/benchmarks/drop_shear_before_after.{md,json}.

Usage: bench/compare_drop_bench.py BEFORE_BUILD AFTER_BUILD [--repeats N] [--work DIR]"""
import argparse
import datetime
import hashlib
import json
import os
import statistics
import subprocess
import sys
import tempfile

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
sys.path.insert(0, os.path.join(ROOT, "bench"))
try:
    import run_drop_bench  # noqa: E402  (run_once: one run of the bench case; it imports drop_shear)
except ModuleNotFoundError as error:
    # drop_shear.py needs matplotlib, which the system python has; a python
    # without it (e.g. a pyenv shim) hands over to /usr/bin/python3.
    if error.name == "matplotlib" and os.path.realpath(sys.executable) != os.path.realpath("/usr/bin/python3"):
        os.execv("/usr/bin/python3", ["/usr/bin/python3", os.path.abspath(__file__)] + sys.argv[1:])
    raise

# (equator nodes, dt, semi-implicit tension); t_end = run_drop_bench.T_END (10).
CONFIGURATIONS = [(28, 0.05, True), (40, 0.05, True)]
STAGES = ["stokes_assembly", "stokes_solve", "ale", "correct_interface", "predict_and_translate", "analysis"]


def source_commit(build):
    """Short commit (and whether the tree has local changes) of the source a build directory was configured from."""
    source = None
    with open(os.path.join(build, "CMakeCache.txt")) as f:
        for line in f:
            if line.startswith("CMAKE_HOME_DIRECTORY:"):
                source = line.split("=", 1)[1].strip()
    if source is None:
        return None, None, False
    commit = subprocess.run(["git", "-C", source, "rev-parse", "--short", "HEAD"],
                            capture_output=True, text=True).stdout.strip()
    dirty = bool(subprocess.run(["git", "-C", source, "status", "--porcelain", "--untracked-files=no"],
                                capture_output=True, text=True).stdout.strip())
    return source, commit, dirty


def binary_id(build):
    path = os.path.join(build, "softflow")
    with open(path, "rb") as f:
        digest = hashlib.sha256(f.read()).hexdigest()[:12]
    mtime = datetime.datetime.fromtimestamp(os.path.getmtime(path), datetime.timezone.utc)
    return {"sha256_12": digest, "mtime_utc": mtime.strftime("%Y-%m-%d %H:%M:%S")}


def config_name(n, dt, semi):
    return f"bench_N{n}_dt{dt:g}_{'semi' if semi else 'explicit'}"


def summarise(runs):
    """Medians over the repeats of one configuration and binary."""
    s = runs[-1]["summary"]
    med = lambda values: statistics.median(values)  # noqa: E731
    return {
        "runs": len(runs), "unknowns": s["unknowns"], "steps": s["steps"],
        "wall_seconds": med(r["wall"] for r in runs),
        "wall_seconds_all": [r["wall"] for r in runs],
        "seconds_per_step": {k: med(r["summary"]["seconds_per_step"].get(k, float("nan")) for r in runs)
                             for k in sorted(set().union(*(r["summary"]["seconds_per_step"] for r in runs)))},
        "stokes_iterations_per_step": med(r["summary"]["stokes_iterations_per_step"] for r in runs),
        "stokes_iterations_per_step_all": [r["summary"]["stokes_iterations_per_step"] for r in runs],
        "stokes_factorizations": med(r["summary"]["stokes_factorizations"] for r in runs),
        "stokes_factorizations_all": [r["summary"]["stokes_factorizations"] for r in runs],
        "D_final": runs[-1]["D_final"], "theta_final_deg": runs[-1]["theta_final"],
        "D_final_all": [r["D_final"] for r in runs],
        "D_steady": runs[-1]["D_steady"], "theta_steady_deg": runs[-1]["theta_steady"],
        "binaries": sorted({r["binary"]["sha256_12"] for r in runs}),
    }


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("before", help="build directory of the earlier commit (holds softflow)")
    parser.add_argument("after", help="build directory of the later commit (holds softflow)")
    parser.add_argument("--repeats", type=int, default=3)
    parser.add_argument("--work", default=os.path.join(tempfile.gettempdir(), "softflow_compare_drop_bench"))
    parser.add_argument("--out", default=os.path.join(ROOT, "docs", "benchmarks"))
    parser.add_argument("--t-end", type=float, default=run_drop_bench.T_END, help="end time (a quick check)")
    args = parser.parse_args()
    run_drop_bench.T_END = args.t_end  # run_once reads it
    builds = {"before": os.path.abspath(args.before), "after": os.path.abspath(args.after)}
    started = datetime.datetime.now(datetime.timezone.utc).strftime("%Y-%m-%d %H:%M UTC")
    info = {}
    for label, build in builds.items():
        source, commit, dirty = source_commit(build)
        info[label] = {"build": build, "source": source, "commit": commit, "source_has_local_changes": dirty,
                       "binary_at_start": binary_id(build)}
    # The after binary belongs to the main checkout: its HEAD at the start is the commit compared.
    head = subprocess.run(["git", "-C", ROOT, "rev-parse", "--short", "HEAD"],
                          capture_output=True, text=True, check=True).stdout.strip()
    print(json.dumps(info, indent=1), flush=True)

    runs = {(label, c): [] for label in builds for c in CONFIGURATIONS}
    log = os.path.join(args.work, "runs.jsonl")
    os.makedirs(args.work, exist_ok=True)
    for repeat in range(args.repeats):
        for c in CONFIGURATIONS:
            for label, build in builds.items():  # before, after, before, after, ...
                binary = binary_id(build)
                r = run_drop_bench.run_once(build, os.path.join(args.work, label), config_name(*c), *c)
                if r is None or r["status"] != "completed":
                    sys.exit(f"{label} {config_name(*c)}: run did not complete")
                final = r["summary"]["final"][0]
                r["D_final"], r["theta_final"] = final["D"], final["theta_deg"]
                r["binary"] = binary
                runs[(label, c)].append(r)
                record = {"repeat": repeat, "binary": label, "configuration": config_name(*c), "wall": r["wall"],
                          "D_final": r["D_final"], "theta_final_deg": r["theta_final"],
                          "stokes_iterations_per_step": r["summary"]["stokes_iterations_per_step"],
                          "seconds_per_step": r["summary"]["seconds_per_step"], "softflow": binary}
                with open(log, "a") as f:
                    f.write(json.dumps(record) + "\n")
                print(json.dumps(record), flush=True)
    for label, build in builds.items():
        info[label]["binary_at_end"] = binary_id(build)

    rows = []
    for c in CONFIGURATIONS:
        n, dt, semi = c
        row = {"equator_nodes": n, "dt": dt, "tension": "semi-implicit" if semi else "explicit",
               "t_end": run_drop_bench.T_END}
        for label in builds:
            row[label] = summarise(runs[(label, c)])
        b, a = row["before"], row["after"]
        row["wall_ratio_after_before"] = a["wall_seconds"] / b["wall_seconds"]
        row["stage_ratio_after_before"] = {k: a["seconds_per_step"][k] / b["seconds_per_step"][k]
                                           for k in b["seconds_per_step"] if k in a["seconds_per_step"]
                                           and b["seconds_per_step"][k] > 0}
        row["D_final_after_minus_before"] = a["D_final"] - b["D_final"]
        row["theta_final_after_minus_before_deg"] = a["theta_final_deg"] - b["theta_final_deg"]
        rows.append(row)

    before_commit = info["before"]["commit"] or "?"
    os.makedirs(args.out, exist_ok=True)
    with open(os.path.join(args.out, "drop_shear_before_after.json"), "w") as f:
        json.dump({"started": started, "before_commit": before_commit, "after_commit": head,
                   "builds": info, "repeats": args.repeats, "t_end": run_drop_bench.T_END,
                   "order": "per repeat and configuration: before, then after", "rows": rows}, f, indent=2)

    changed = [label for label in builds
               if info[label]["binary_at_start"]["sha256_12"] != info[label]["binary_at_end"]["sha256_12"]]
    dirty = [f"{label} ({info[label]['source']})" for label in builds if info[label]["source_has_local_changes"]]
    lines = [
        f"# Drop in shear to t = {run_drop_bench.T_END:g}: before/after a refactoring",
        "",
        f"Commits compared: before = `{before_commit}`, after = `{head}` (HEAD of the main checkout when the "
        f"run started, {started}). Case of `bench/run_drop_bench.py`: lambda = 1, Ca = 0.1, box 15 diameters, "
        f"from rest to t = {run_drop_bench.T_END:g}, semi-implicit tension, direct solver, 1 MPI rank. "
        f"{args.repeats} run(s) per configuration and binary, the binaries alternated (before, after, before, "
        "after, ...) so both see the same load; medians over the runs. The machine is shared (2 cores): "
        "absolute times vary between runs of this script, the after/before ratios within one run are what "
        "counts. Regenerate with `bench/compare_drop_bench.py BEFORE_BUILD AFTER_BUILD`.",
        "",
        f"Stage columns are seconds per step (median over the runs); interface = correct_interface + "
        f"predict_and_translate. D and theta are the values at t = {run_drop_bench.T_END:g} (summary.json `final`).",
        "",
        "| equator nodes | dt | binary | commit | unknowns | steps | wall [s] | after/before | assembly | Stokes solve | ALE | interface | analysis | Stokes its/step | factorizations | D (t_end) | theta (t_end) [deg] |",
        "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|",
    ]
    for row in rows:
        for label in builds:
            r = row[label]
            sp = r["seconds_per_step"]
            ratio = f"{row['wall_ratio_after_before']:.3f}" if label == "after" else ""
            lines.append(
                f"| {row['equator_nodes']} | {row['dt']:g} | {label} | `{before_commit if label == 'before' else head}` | "
                f"{r['unknowns']} | {r['steps']} | {r['wall_seconds']:.1f} | {ratio} | "
                f"{sp['stokes_assembly']:.4f} | {sp['stokes_solve']:.4f} | {sp['ale']:.4f} | "
                f"{sp['correct_interface'] + sp['predict_and_translate']:.4f} | {sp['analysis']:.5f} | "
                f"{r['stokes_iterations_per_step']:.3f} | {r['stokes_factorizations']:g} | "
                f"{r['D_final']:.9f} | {r['theta_final_deg']:.6f} |")
    lines += ["", "| equator nodes | wall runs before [s] | wall runs after [s] | after/before: wall | assembly | Stokes solve | ALE | interface (correct) | D after - before | theta after - before [deg] |",
              "|---|---|---|---|---|---|---|---|---|---|"]
    for row in rows:
        sr = row["stage_ratio_after_before"]
        lines.append(
            f"| {row['equator_nodes']} | {', '.join(f'{w:.1f}' for w in row['before']['wall_seconds_all'])} | "
            f"{', '.join(f'{w:.1f}' for w in row['after']['wall_seconds_all'])} | {row['wall_ratio_after_before']:.3f} | "
            f"{sr.get('stokes_assembly', float('nan')):.3f} | {sr.get('stokes_solve', float('nan')):.3f} | "
            f"{sr.get('ale', float('nan')):.3f} | {sr.get('correct_interface', float('nan')):.3f} | "
            f"{row['D_final_after_minus_before']:+.2e} | {row['theta_final_after_minus_before_deg']:+.2e} |")
    if changed:
        lines += ["", f"Note: the softflow binary of {', '.join(changed)} changed during the run "
                  "(see the json's binary_at_start / binary_at_end and the per-run binaries)."]
    if dirty:
        lines += ["", f"Note: tracked files of {', '.join(dirty)} had local changes when the run started."]
    with open(os.path.join(args.out, "drop_shear_before_after.md"), "w") as f:
        f.write("\n".join(lines) + "\n")
    print("\n".join(lines))


if __name__ == "__main__":
    main()
