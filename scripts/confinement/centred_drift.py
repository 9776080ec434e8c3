#!/usr/bin/env python3
"""The noise floor of a migration measurement (issue 35, item 6): how fast a
drop or particle centred at y = 0 drifts across streamlines, on gmsh's mesh of
the whole cell ("plain") and on the point-symmetric mesh (mesh.point_symmetric
= true, "symmetric"), on the migration figures' confined boxes.

usage: centred_drift.py SOFTFLOW [--objects drop,particle] [--betas 0.4,0.2]
                        [--nodes 16,24] [--meshes plain,symmetric]
                        [--step 0.05] [--end 0.5] [--work DIR] [--out FILE.md]

By symmetry (the rotation by pi about z maps simple shear and a centred object
onto themselves and v_p onto -v_p) v_p = 0: every v_p measured is numerical.
Cells as the thesis's chapter 3: 10 particle diameters long and wide (L = W =
20 R), H = 2R / beta; mesh as examples/confined_particle.toml (far_size 2,
growth 0.4, wall_size 0.5). The drop: lambda = 1, Ca = 0.1; the particle:
neo-Hookean, Ca_e = 0.1 (the thesis's Figs. 3.5-3.10). Runs are one at a time
(`nice -n 5`), resumable: a run whose summary.json says completed is not
run again. Prints a Markdown table and writes it to --out.

Columns (lengths in R = 1, times in 1/gamma_dot, so velocities in gamma_dot R):
v_p(end) the migration velocity at the last step; max |v_p| over the steps
after the first (the first has no BDF velocity yet); mean drift (y_p(end) -
y_p(0)) / t_end; |x_p| drift likewise in x relative to the shear (an object on
y = 0 has zero velocity in x); Delta S at the end (eq. 3.6, zero by the same
symmetry); the volume change over the run.
"""
import argparse
import csv
import json
import os
import subprocess
import sys

parser = argparse.ArgumentParser()
parser.add_argument("softflow")
parser.add_argument("--objects", default="drop,particle")
parser.add_argument("--betas", default="0.4,0.2")
parser.add_argument("--nodes", default="16,24")
parser.add_argument("--meshes", default="plain,symmetric")
parser.add_argument("--step", type=float, default=0.05)
parser.add_argument("--end", type=float, default=0.5)
parser.add_argument("--work", default="/tmp/softflow_centred_drift")
parser.add_argument("--out", default=None)
args = parser.parse_args()
os.makedirs(args.work, exist_ok=True)

# The particle's conformation numerics as the drift table was computed
# (before the keys of [conformation]: scripts/validation/case_runs.py).
CONFORMATION = {"particle": '[conformation]\nsupg_tau = "steady"\nstress_prediction = "euler"\n'}
OBJECTS = {
    "drop": "viscosity_ratio = 1.0\ncapillary_number = 0.1\n",
    "particle": "model = \"neo_hookean\"\nelastic_capillary_number = 0.1\n",
}


def case_text(obj, beta, n, mesh, directory):
    return f"""[case]
name = "{os.path.basename(directory)}"
[cell]
length = 20.0
width = 20.0
blockage_ratio = {beta}
[[objects]]
radius = 1.0
centre = [0.0, 0.0, 0.0]
{OBJECTS[obj]}[mesh]
equator_nodes = {n}
far_size = 2.0
growth = 0.4
wall_size = 0.5
{"point_symmetric = true" + chr(10) if mesh == "symmetric" else ""}[time]
step = {args.step}
end = {args.end}
[output]
fields = false
directory = "{directory}"
{CONFORMATION.get(obj, "")}"""


def completed(directory):
    try:
        with open(os.path.join(directory, "summary.json")) as f:
            return json.load(f).get("status") == "completed"
    except (OSError, ValueError):
        return False


def run(obj, beta, n, mesh):
    name = f"{obj}_beta{beta}_n{n}_{mesh}"
    directory = os.path.join(args.work, name)
    if not completed(directory):
        path = os.path.join(args.work, name + ".toml")
        with open(path, "w") as f:
            f.write(case_text(obj, beta, n, mesh, directory))
        r = subprocess.run(["nice", "-n", "5", args.softflow, "run", path, "--quiet", "--overwrite"],
                           capture_output=True, text=True)
        if r.returncode != 0:
            return None, r.stderr.strip().splitlines()[-1:] or ["failed"]
    return directory, None


def measures(directory):
    with open(os.path.join(directory, "migration.csv")) as f:
        rows = [r for r in csv.DictReader(f) if r["object"] == "1"]
    with open(os.path.join(directory, "timeseries.csv")) as f:
        series = [r for r in csv.DictReader(f) if r["object"] == "1"]
    with open(os.path.join(directory, "summary.json")) as f:
        summary = json.load(f)
    t_end = float(rows[-1]["t"])
    v = [float(r["v_p"]) for r in rows[2:]]
    volume0, volume1 = float(series[0]["volume"]), float(series[-1]["volume"])
    return {
        "nodes": summary["mesh"]["nodes"],
        "v_end": float(rows[-1]["v_p"]),
        "v_max": max(abs(x) for x in v) if v else float("nan"),
        "drift": (float(rows[-1]["y_p"]) - float(rows[0]["y_p"])) / t_end,
        "x_drift": (float(series[-1]["xc"]) - float(series[0]["xc"])) / t_end,
        "delta_s": float(rows[-1]["delta_s"]),
        "volume": (volume1 - volume0) / volume0,
        "seconds": summary.get("wall_seconds", float("nan")),
    }


lines = ["| object | beta | N | mesh | nodes | v_p(end) | max abs v_p | mean drift dy_p/dt | "
         "mean dx_p/dt | Delta S(end) | volume change | wall s |",
         "|---|---|---|---|---|---|---|---|---|---|---|---|"]
print("\n".join(lines))
for obj in args.objects.split(","):
    for beta in (float(b) for b in args.betas.split(",")):
        for n in (int(x) for x in args.nodes.split(",")):
            for mesh in args.meshes.split(","):
                directory, error = run(obj, beta, n, mesh)
                if directory is None:
                    line = f"| {obj} | {beta:g} | {n} | {mesh} | failed: {' '.join(error)} ||||||||"
                else:
                    m = measures(directory)
                    line = (f"| {obj} | {beta:g} | {n} | {mesh} | {m['nodes']} | {m['v_end']:.2e} | "
                            f"{m['v_max']:.2e} | {m['drift']:.2e} | {m['x_drift']:.2e} | "
                            f"{m['delta_s']:.2e} | {m['volume']:.2e} | {m['seconds']:.0f} |")
                lines.append(line)
                print(line)
                sys.stdout.flush()
if args.out:
    with open(args.out, "w") as f:
        f.write("\n".join(lines) + "\n")
