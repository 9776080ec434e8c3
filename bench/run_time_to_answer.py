#!/usr/bin/python3
"""Time to a converged answer (issue 13): the Newtonian drop of the main
example (lambda = 1, Ca = 0.1, box 15 diameters) from rest until it is
steady, at constant and at adaptive steps, on the meshes of the whole-mesh
convergence study (examples/converge_drop.toml, docs/accuracy/converge_drop.md),
whose Richardson value of the steady D is the reference.

Every run stops at steady state (time.steady_tolerance 2e-5 over a window of
2, as the study). For each mesh and time-stepping it reports wall time,
accepted and rejected steps, unknowns, the steady D and its error against the
extrapolated D; runs go one at a time (timings), `--repeats` times, medians
reported. The machine is shared: compare ratios within one run of this script.
Writes docs/benchmarks/time_to_answer.{md,json}.

Usage: bench/run_time_to_answer.py [build_dir] [--repeats N] [--work DIR] [--levels 31,39]"""
import argparse
import json
import os
import re
import statistics
import subprocess

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
OUT = os.path.join(ROOT, "docs", "benchmarks")
STUDY = os.path.join(ROOT, "docs", "accuracy", "converge_drop.md")
BASE = os.path.join(ROOT, "examples", "converge_drop.toml")
# (equator nodes asked, far size, growth): levels 3-5 of the convergence study.
LEVELS = {31: (3.613, 0.3613), 39: (2.872, 0.2872), 49: (2.286, 0.2286)}
# (label, [time] lines): the example's constant step and adaptive steps from a small first step.
STEPPING = [("constant dt = 0.05", "step = 0.05\n"),
            ("adaptive, tolerance 1e-3", "step = 0.01\nadaptive_tolerance = 1e-3\n"),
            ("adaptive, tolerance 3e-3", "step = 0.01\nadaptive_tolerance = 3e-3\n")]


def reference_d():
    """The extrapolated steady D of the convergence study (its table)."""
    with open(STUDY) as f:
        for line in f:
            cells = [c.strip() for c in line.split("|")]
            if len(cells) > 5 and cells[2] == "D" and cells[4] in ("yes", "no"):
                return float(cells[5])
    raise SystemExit(f"no extrapolated D in {STUDY}")


def case_text(name, equator, far, growth, time_lines):
    with open(BASE) as f:
        text = f.read()
    text = re.sub(r'name = "[^"]*"', f'name = "{name}"', text, count=1)
    text = re.sub(r"equator_nodes = \d+", f"equator_nodes = {equator}", text)
    text = re.sub(r"far_size = [0-9.]+", f"far_size = {far}", text)
    text = re.sub(r"growth = [0-9.]+", f"growth = {growth}", text)
    text = re.sub(r"\nstep = [0-9.]+", "\n" + time_lines.rstrip("\n"), text)
    text = re.sub(r"interval_steps = \d+", "interval_steps = 0", text)
    text = re.sub(r'directory = "[^"]*".*\n', "", text)
    return text.replace("fields = true", "fields = false")


def run(build, work, name, text, reuse):
    out = os.path.join(work, name)
    if reuse and os.path.exists(os.path.join(out, "summary.json")):
        with open(os.path.join(out, "summary.json")) as f:
            return json.load(f)
    path = os.path.join(work, name + ".toml")
    with open(path, "w") as f:
        f.write(text)
    subprocess.run([os.path.join(build, "softflow"), "run", path, "-o", out, "-q", "--overwrite"], check=True)
    with open(os.path.join(out, "summary.json")) as f:
        return json.load(f)


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("build", nargs="?", default=os.path.join(ROOT, "build"))
    parser.add_argument("--repeats", type=int, default=1)
    parser.add_argument("--work", default=os.path.join(ROOT, "output", "bench_time_to_answer"))
    parser.add_argument("--levels", default="31,39,49")
    parser.add_argument("--reuse", action="store_true", help="report finished runs instead of running them again")
    args = parser.parse_args()
    os.makedirs(args.work, exist_ok=True)
    d_ref = reference_d()
    results = []
    for equator in [int(n) for n in args.levels.split(",")]:
        far, growth = LEVELS[equator]
        for label, lines in STEPPING:
            name = f"N{equator}_" + re.sub(r"[^a-z0-9]+", "_", label.lower()).strip("_")
            summaries = [run(args.build, args.work, name, case_text(name, equator, far, growth, lines), args.reuse)
                         for _ in range(args.repeats)]
            s = summaries[-1]
            d = s["final"][0]["D"]
            adaptive = s.get("adaptive", {})
            results.append({
                "equator_nodes": equator, "stepping": label, "unknowns": s["unknowns"],
                "wall_seconds_median": statistics.median(x["wall_seconds"] for x in summaries),
                "wall_seconds": [x["wall_seconds"] for x in summaries],
                "accepted_steps": s["steps"], "rejected_steps": adaptive.get("rejected", 0) + adaptive.get("failed", 0),
                "largest_step": adaptive.get("largest_step"), "t_steady": s["steady"]["time"],
                "steady": s["steady"]["reached"], "D": d, "D_error": d / d_ref - 1.0})
            r = results[-1]
            print(f"N{equator} {label:26s} {r['wall_seconds_median']:7.1f} s  steps {r['accepted_steps']:4d} "
                  f"(+{r['rejected_steps']} rejected)  t_steady {r['t_steady']}  D {d:.6f}  error {100 * r['D_error']:+.3f} %",
                  flush=True)
    os.makedirs(OUT, exist_ok=True)
    with open(os.path.join(OUT, "time_to_answer.json"), "w") as f:
        json.dump({"reference_D": d_ref, "repeats": args.repeats, "results": results}, f, indent=2)
    md = ["# Time to a converged answer: the main drop from rest to steady state", "",
          "lambda = 1, Ca = 0.1, box 30 (15 diameters); meshes of the whole-mesh study "
          "(docs/accuracy/converge_drop.md); every run stops at steady state (steady_tolerance 2e-5, "
          f"window 2). Error: steady D against the study's extrapolated D = {d_ref:.7f}. "
          f"Median wall time of {args.repeats} run(s) each, one run at a time. "
          "Generated by `bench/run_time_to_answer.py`.", "",
          "| equator nodes | stepping | unknowns | wall time [s] | steps accepted (rejected) | largest dt | "
          "steady at t | D | error of D |", "|---|---|---|---|---|---|---|---|---|"]
    for r in results:
        largest = f"{r['largest_step']:.3g}" if r["largest_step"] else "0.05"
        steady = "not steady by t = 12" if r["t_steady"] is None else f"{r['t_steady']:.2f}"
        md.append(f"| {r['equator_nodes']} | {r['stepping']} | {r['unknowns']} | {r['wall_seconds_median']:.1f} | "
                  f"{r['accepted_steps']} ({r['rejected_steps']}) | {largest} | {steady} | "
                  f"{r['D']:.6f} | {100 * r['D_error']:+.3f} % |")
    md += ["", "![D and dt against t](time_to_answer.png)"]
    with open(os.path.join(OUT, "time_to_answer.md"), "w") as f:
        f.write("\n".join(md) + "\n")
    plot(args.work, results, d_ref)


def plot(work, results, d_ref):
    """D(t) and the step size against t for each run of the coarsest mesh."""
    import csv
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    coarsest = min(r["equator_nodes"] for r in results)
    fig, (ax_d, ax_dt) = plt.subplots(1, 2, figsize=(11, 4))
    for r in results:
        if r["equator_nodes"] != coarsest:
            continue
        name = f"N{coarsest}_" + re.sub(r"[^a-z0-9]+", "_", r["stepping"].lower()).strip("_")
        with open(os.path.join(work, name, "timeseries.csv")) as f:
            rows = list(csv.DictReader(f))[1:]
        t = [float(x["t"]) for x in rows]
        ax_d.plot(t, [float(x["D"]) for x in rows], ".-", ms=3, label=r["stepping"])
        ax_dt.plot(t, [float(x["dt"]) for x in rows], ".-", ms=3, label=r["stepping"])
    ax_d.axhline(d_ref, color="gray", ls="--", label="converged D (extrapolated)")
    ax_d.set(xlabel="t", ylabel="D", title=f"D(t), {coarsest} equator nodes, to steady state")
    ax_dt.set(xlabel="t", ylabel="dt", yscale="log", title="step size")
    for a in (ax_d, ax_dt):
        a.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(os.path.join(OUT, "time_to_answer.png"), dpi=110)


if __name__ == "__main__":
    main()
