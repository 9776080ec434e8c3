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
One stepping also stops sooner (steady_window 1 instead of 2). A second
table answers the same question by extrapolation: `softflow converge` on
three coarse meshes of the same family (coarsest `--richardson` equator
nodes, factor 1.25), or on the coarsest two with the study's order given
(`--order 3`), timed as a whole; its Richardson value is compared with the
reference. The reference comes from the study's finest
three levels, so the two share at most one mesh (stated in the table).

Writes docs/benchmarks/time_to_answer.{md,json}.

Usage: bench/run_time_to_answer.py [build_dir] [--repeats N] [--work DIR] [--levels 31,33,39]
                                   [--richardson 25] [--jobs 1]"""
import argparse
import csv
import json
import os
import re
import shutil
import statistics
import subprocess
import time

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
OUT = os.path.join(ROOT, "docs", "benchmarks")
STUDY = os.path.join(ROOT, "docs", "accuracy", "converge_drop.md")
BASE = os.path.join(ROOT, "examples", "converge_drop.toml")


def level_mesh(equator):
    """(far size, growth) of the study's mesh family at `equator` nodes: the
    coarsest level's (20 nodes: 5.6, 0.56) scaled by 20 / equator, as
    `softflow converge` scales them."""
    return 5.6 * 20 / equator, 0.56 * 20 / equator

# (label, [time] lines, start from Taylor's ellipsoid): the example's constant
# step, adaptive steps from a small first step, and the same from the steady
# ellipsoid of small-deformation theory on the sphere's mesh
# ([[objects]] initial_deformation = "taylor").
STEPPING = [("constant dt = 0.05", "step = 0.05\n", False),
            ("adaptive, tolerance 1e-3", "step = 0.01\nadaptive_tolerance = 1e-3\n", False),
            ("adaptive, tolerance 3e-3", "step = 0.01\nadaptive_tolerance = 3e-3\n", False),
            ("Taylor start, adaptive 1e-3", "step = 0.01\nadaptive_tolerance = 1e-3\n", True),
            ("Taylor start, adaptive 3e-3", "step = 0.01\nadaptive_tolerance = 3e-3\n", True),
            ("Taylor start, adaptive 3e-3, window 1", "step = 0.01\nadaptive_tolerance = 3e-3\nsteady_window = 1.0\n",
             True)]
# The extrapolation's levels: as the study (constant 0.05 from the sphere),
# and the fastest stepping above; (label, [time] lines, Taylor start, levels,
# order given to `converge --order` or None: observed from three levels).
# The study's order is 3 (docs/accuracy.md: 2.9-3.0 from its finest levels).
EXTRAPOLATIONS = [("constant dt = 0.05, sphere", "step = 0.05\n", False, 3, None),
                  ("Taylor start, adaptive 3e-3", "step = 0.01\nadaptive_tolerance = 3e-3\n", True, 3, None),
                  ("Taylor start, adaptive 3e-3, window 1",
                   "step = 0.01\nadaptive_tolerance = 3e-3\nsteady_window = 1.0\n", True, 2, 3.0)]


def reference_d():
    """The extrapolated steady D of the convergence study and the meshed
    equator nodes of its finest three levels (its tables)."""
    d_ref, meshed = None, []
    with open(STUDY) as f:
        for line in f:
            cells = [c.strip() for c in line.split("|")]
            if len(cells) > 5 and cells[2] == "D" and cells[4] in ("yes", "no"):
                d_ref = float(cells[5])
            match = re.match(r"\d+ / (\d+)$", cells[2]) if len(cells) > 3 else None
            if match:
                meshed.append(int(match.group(1)))
    if d_ref is None:
        raise SystemExit(f"no extrapolated D in {STUDY}")
    return d_ref, meshed[-3:]


def case_text(name, equator, far, growth, time_lines, taylor=False):
    with open(BASE) as f:
        text = f.read()
    if taylor:
        text = re.sub(r"\ncapillary_number = ([0-9.e-]+)", r'\ncapillary_number = \1\ninitial_deformation = "taylor"',
                      text, count=1)
    text = re.sub(r'name = "[^"]*"', f'name = "{name}"', text, count=1)
    text = re.sub(r"equator_nodes = \d+", f"equator_nodes = {equator}", text)
    text = re.sub(r"far_size = [0-9.]+", f"far_size = {far}", text)
    text = re.sub(r"growth = [0-9.]+", f"growth = {growth}", text)
    # The base's own line of every [time] key the stepping sets (its step is replaced below).
    for key in re.findall(r"^(\w+) =", time_lines, flags=re.M):
        if key != "step":
            text = re.sub(rf"\n{key} = [^\n]*", "", text, count=1)
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


def richardson_answer(build, work, coarsest, jobs, reuse, time_lines, taylor, tag, levels=3, order=None, repeat=0):
    """`softflow converge` on `levels` levels from `coarsest` equator nodes
    (with `--order order` if given): (total wall seconds, converge.json's D
    entry, the levels' rows)."""
    name = f"converge_N{coarsest}{tag}_r{repeat}"
    out = os.path.join(work, name)
    text = case_text(name, coarsest, *level_mesh(coarsest), time_lines, taylor)
    text = text.replace("\n[output]\n", f'\n[output]\ndirectory = "{out}"\n')
    timing = os.path.join(work, name + "_wall_seconds.txt")
    if not (reuse and os.path.exists(timing)):
        path = os.path.join(work, name + ".toml")
        with open(path, "w") as f:
            f.write(text)
        if os.path.exists(out):
            shutil.rmtree(out)
        start = time.monotonic()
        subprocess.run([os.path.join(build, "softflow"), "converge", path, "--levels", str(levels),
                        "--factor", "1.25", "-j", str(jobs), "-q"] + ([] if order is None else ["--order", f"{order:g}"]),
                       check=True)
        with open(timing, "w") as f:
            f.write(f"{time.monotonic() - start}\n")
    with open(timing) as f:
        wall = float(f.read())
    with open(os.path.join(out, "converge.json")) as f:
        entry = next(e for e in json.load(f)["extrapolation"] if e["quantity"] == "D")
    with open(os.path.join(out, "converge.csv")) as f:
        levels = list(csv.DictReader(f))
    return wall, entry, levels


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("build", nargs="?", default=os.path.join(ROOT, "build"))
    parser.add_argument("--repeats", type=int, default=1)
    parser.add_argument("--work", default=os.path.join(ROOT, "output", "bench_time_to_answer"))
    parser.add_argument("--levels", default="31,33,39")
    parser.add_argument("--richardson", type=int, default=25,
                        help="coarsest equator nodes of the three-level extrapolation")
    parser.add_argument("--jobs", type=int, default=1, help="levels of the extrapolation run at once")
    parser.add_argument("--reuse", action="store_true", help="report finished runs instead of running them again")
    args = parser.parse_args()
    os.makedirs(args.work, exist_ok=True)
    d_ref, reference_levels = reference_d()
    results = []
    for equator in [int(n) for n in args.levels.split(",")]:
        far, growth = level_mesh(equator)
        for label, lines, taylor in STEPPING:
            name = f"N{equator}_" + re.sub(r"[^a-z0-9]+", "_", label.lower()).strip("_")
            summaries = [run(args.build, args.work, name, case_text(name, equator, far, growth, lines, taylor),
                             args.reuse)
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
    extrapolations = []
    for label, lines, taylor, n_levels, order in EXTRAPOLATIONS:
        tag = re.sub(r"[^a-z0-9]+", "_", label.lower()).strip("_")
        answers = [richardson_answer(args.build, args.work, args.richardson, args.jobs, args.reuse, lines, taylor,
                                     tag, n_levels, order, k) for k in range(args.repeats)]
        wall = statistics.median(a[0] for a in answers)
        _, entry, levels = answers[-1]
        meshed = [int(l["meshed_equator_nodes"]) for l in levels]
        e = {"stepping": label, "equator_nodes": [int(l["equator_nodes"]) for l in levels],
             "meshed_equator_nodes": meshed,
             "unknowns": [int(l["unknowns"]) for l in levels], "jobs": args.jobs,
             "level_wall_seconds": [float(l["wall_seconds"]) for l in levels],
             "wall_seconds": wall, "wall_seconds_all": [a[0] for a in answers],
             "order": order if order is not None else entry["orders"][-1],
             "order_given": order is not None, "D": entry["extrapolated"],
             "D_error": (entry["extrapolated"] / d_ref - 1.0) if entry["extrapolated"] else None,
             "shared_with_reference": sorted(set(meshed) & set(reference_levels))}
        extrapolations.append(e)
        print(f"Richardson ({label}) from {meshed}: {wall:.1f} s  order {e['order']}  D {entry['extrapolated']}  "
              f"error {100 * e['D_error']:+.3f} %", flush=True)
    os.makedirs(OUT, exist_ok=True)
    with open(os.path.join(OUT, "time_to_answer.json"), "w") as f:
        json.dump({"reference_D": d_ref, "reference_meshed_equator_nodes": reference_levels,
                   "repeats": args.repeats, "results": results, "extrapolations": extrapolations}, f, indent=2)
    md = ["# Time to a converged answer: the main drop from rest to steady state", "",
          "lambda = 1, Ca = 0.1, box 30 (15 diameters); meshes of the whole-mesh study "
          "(docs/accuracy/converge_drop.md); every run stops at steady state (steady_tolerance 2e-5, "
          f"window 2). Error: steady D against the study's extrapolated D = {d_ref:.7f} (from its meshes "
          f"with {', '.join(map(str, reference_levels))} equator nodes). "
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
    e0 = extrapolations[0]
    shared = ", ".join(map(str, e0["shared_with_reference"])) or "none"
    md += ["", "## The answer by extrapolation from coarse meshes", "",
           f"`softflow converge` (the same steady stop unless the row says otherwise) on the family's meshes with "
           f"{' / '.join(map(str, e0['equator_nodes']))} equator nodes asked "
           f"({' / '.join(map(str, e0['meshed_equator_nodes']))} meshed), {e0['jobs']} level(s) at a time; "
           f"the Richardson value of D against the reference: from three levels with their observed order, or "
           f"from the coarsest two with the order the study observed, 3 (`--order 3`, marked \"given\"). "
           f"Total wall time: the whole command, median of {args.repeats}. Meshes shared with the "
           f"reference's three: {shared}.", "",
           "| stepping | levels (meshed equator nodes) | unknowns | wall time of each level [s] | "
           "total wall time [s] | order | extrapolated D | error of D |",
           "|---|---|---|---|---|---|---|---|"]
    for e in extrapolations:
        md.append(f"| {e['stepping']} | {' / '.join(map(str, e['meshed_equator_nodes']))} | "
                  f"{' / '.join(map(str, e['unknowns']))} | "
                  f"{' / '.join(f'{w:.1f}' for w in e['level_wall_seconds'])} | {e['wall_seconds']:.1f} | "
                  f"{e['order']:.2f}{' (given)' if e['order_given'] else ''} | {e['D']:.6f} | "
                  f"{100 * e['D_error']:+.3f} % |")
    md += ["", "![D and dt against t](time_to_answer.png)"]
    with open(os.path.join(OUT, "time_to_answer.md"), "w") as f:
        f.write("\n".join(md) + "\n")
    plot(args.work, results, d_ref)


def plot(work, results, d_ref):
    """D(t) and the step size against t for each run of the coarsest mesh."""
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
