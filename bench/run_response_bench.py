#!/usr/bin/python3
"""Cost of a frequency sweep in the frequency domain (`softflow response`,
issue 32 item 5; target: 20 frequencies in at most 10 minutes), each case
solved at the same 20 frequencies (0.02 ... 10, evenly in log) with the
solver it names:
  drop_N40_direct     one drop, lambda = 1, cell 24 x 16 x 24, 40 equator
                      nodes (scripts/validation/dilute_drop_response.py's finest)
  drop_N40_iterative  the same with FGMRES + PRESB
  emulsion_moduli_seed1  examples/emulsion_moduli.toml's seed 1: 10 drops,
                      16 equator nodes, direct (auto)
  emulsion_phi0.2     24 drops at phi = 0.2 in a core cube of side 8 of a
                      12^3 cell, gaps >= 0.1 R, 14 equator nodes: iterative
                      (auto: too large to factor); with --quick only its
                      first FEW frequencies, the sweep's time estimated from them
  phi0.2_point_seedS  issue 32's benchmark point (phi = 0.2, lambda = 1,
                      omega = 0.4; target: all its configurations in at most
                      1 hour): the emulsion above for seeds 1 ... 5 at omega = 0.4
Wall time includes meshing. Writes docs/benchmarks/response.{md,json}.

Usage: bench/run_response_bench.py [build_dir] [--work DIR] [--quick] [--only NAME...]"""
import argparse
import json
import os
import re
import statistics
import subprocess

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
FREQUENCIES = [round(0.02 * (10 / 0.02) ** (k / 19), 6) for k in range(20)]
FEW = 3

DROP = """[case]
name = "drop"
[cell]
length = 24.0
height = 16.0
width = 24.0
[flow]
type = "oscillatory"
strain_amplitude = 0.05
frequency = 1.0
[[objects]]
radius = 1.0
viscosity_ratio = 1.0
interfacial_tension = 1.0
[mesh]
equator_nodes = 40
"""

DENSE = """[case]
name = "dense"
[cell]
length = 12.0
height = 12.0
width = 12.0
[flow]
type = "oscillatory"
strain_amplitude = 0.05
frequency = 0.4
[[objects]]
radius = 1.0
viscosity_ratio = 1.0
interfacial_tension = 1.0
[emulsion]
volume_fraction = 0.2
seed = 1
core_side = 8.0
min_gap = 0.1
[bulk_stress]
box_side = 8.0
[mesh]
equator_nodes = 14
far_size = 1.5
"""


def emulsion_moduli_seed1():
    text = open(os.path.join(ROOT, "examples", "emulsion_moduli.toml")).read()
    text = re.sub(r"seed = \[[^\]]*\]", "seed = 1", text)
    return re.sub(r"frequency = \[[^\]]*\]", "frequency = 1.0", text)


def cases(quick):
    return [("drop_N40_direct", DROP + '[solver]\ntype = "direct"\n', FREQUENCIES),
            ("drop_N40_iterative", DROP + '[solver]\ntype = "iterative"\n', FREQUENCIES),
            ("emulsion_moduli_seed1", emulsion_moduli_seed1(), FREQUENCIES)] + \
           [(f"phi0.2_point_seed{k}", DENSE.replace("seed = 1", f"seed = {k}"), [0.4]) for k in range(1, 6)] + \
           [("emulsion_phi0.2", DENSE, FREQUENCIES[:FEW] if quick else FREQUENCIES)]


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("build", nargs="?", default=os.path.join(ROOT, "build"))
    parser.add_argument("--work", default=os.path.join(ROOT, "output", "bench_response"))
    parser.add_argument("--quick", action="store_true", help=f"the phi = 0.2 emulsion at its first {FEW} frequencies")
    parser.add_argument("--rerun", action="store_true", help="run cases whose results are in the work directory again")
    parser.add_argument("--only", nargs="*", help="run only these cases (the table keeps the others' last results)")
    args = parser.parse_args()
    os.makedirs(args.work, exist_ok=True)
    json_path = os.path.join(ROOT, "docs", "benchmarks", "response.json")
    previous = {r["case"]: r for r in json.load(open(json_path))} if os.path.exists(json_path) else {}
    results = []
    for name, text, frequencies in cases(args.quick):
        if args.only and name not in args.only:
            if name in previous:
                results.append(previous[name])
            continue
        path = os.path.join(args.work, name + ".toml")
        with open(path, "w") as f:
            f.write(text)
        out = os.path.join(args.work, name)
        summary_path = os.path.join(out, "summary.json")
        done = os.path.exists(summary_path) and \
            [round(w, 6) for w in json.load(open(summary_path))["frequencies"]] == [round(w, 6) for w in frequencies]
        if not done or args.rerun:
            subprocess.run([os.path.join(args.build, "softflow"), "response", path, "-q", "-o", out,
                            "-f", ",".join(f"{w:g}" for w in frequencies)], check=True)
        summary = json.load(open(summary_path))
        wall = summary["wall_seconds"]  # the command's own, meshing included
        seconds = [p["seconds"] for p in summary["points"]]
        result = {"case": name, "unknowns": summary["unknowns"], "drops": summary["drops"],
                  "solver": summary["solver"]["method"], "frequencies": len(frequencies), "wall_seconds": wall,
                  "mesh_seconds": summary["mesh"]["seconds"], "median_seconds_per_frequency": statistics.median(seconds),
                  "first_frequency_seconds": seconds[0],
                  "iterations": [p["iterations"] for p in summary["points"]],
                  "inner_solves": [p["inner_solves"] for p in summary["points"]],
                  "peak_memory_mb": summary.get("peak_memory_mb")}
        result["sweep_of_20_seconds"] = wall if len(frequencies) == 20 else \
            summary["mesh"]["seconds"] + 20 * statistics.median(seconds)
        results.append(result)
        print(json.dumps(result))
    lines = ["# A frequency sweep in the frequency domain (softflow response)", "",
             "Generated by `bench/run_response_bench.py`: 20 frequencies from 0.02 to 10 per case (target: at most 10 "
             "minutes), wall time of the whole command (meshing included), this machine (2 cores, other work "
             "possibly running: see the date of the commit). Iterative: FGMRES iterations per frequency (PRESB, two "
             "inner Stokes solves each).", "",
             "| case | drops | real unknowns | solver | frequencies run | wall s | s per frequency (median) | first "
             "frequency s | FGMRES iterations | 20 frequencies, s |", "|---|---|---|---|---|---|---|---|---|---|"]
    for r in results:
        its = r["iterations"]
        lines.append(f"| {r['case']} | {r['drops']} | {r['unknowns']} | {r['solver']} | {r['frequencies']} | {r['wall_seconds']:.0f} | "
                     f"{r['median_seconds_per_frequency']:.1f} | {r['first_frequency_seconds']:.1f} | "
                     f"{min(its)}-{max(its)} | {r['sweep_of_20_seconds']:.0f}"
                     f"{'' if r['frequencies'] == 20 else ' (estimated: meshing + 20 x median)'} |")
    point = [r for r in results if r["case"].startswith("phi0.2_point")]
    if point:
        lines += ["", f"Issue 32's point (phi = 0.2, lambda = 1, omega = 0.4): {len(point)} configurations in "
                  f"{sum(r['wall_seconds'] for r in point) / 60:.1f} min, one after another (target: at most 60)."]
    out_dir = os.path.join(ROOT, "docs", "benchmarks")
    with open(os.path.join(out_dir, "response.md"), "w") as f:
        f.write("\n".join(lines) + "\n")
    with open(os.path.join(out_dir, "response.json"), "w") as f:
        json.dump(results, f, indent=2)
    print("\n".join(lines))


if __name__ == "__main__":
    main()
