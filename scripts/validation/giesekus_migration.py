#!/usr/bin/python3
"""Migration of a confined neo-Hookean particle in a Giesekus matrix (thesis
§3.2.3, Figs. 3.12-3.13): beta = 0.2, Ca_e = 0.1, p = 4.5, alpha_m = 0.2,
started at y_p0 / H = 0.10, 0.20, 0.28, 0.35. In a Newtonian matrix the
particle always migrates to the centre plane; here the matrix's normal
stresses push it towards the wall above a neutral height y_N, where v_p
changes sign. Runs the cases with the softflow binary, combines them with
`softflow migration` (master curve v_p(y_p), neutral heights with their
error estimate) and writes docs/validation/giesekus_migration.{md,csv,png}.

Matrix as scripts/validation/giesekus_particle.py (solvent 0.1, polymer 0.9,
so eta_m = 1; mobility 0.2; lambda_m = p Ca_e / eta_p = 0.5). Cell 10
particle diameters long and wide, H = 2R / beta = 10, 20 equator nodes,
graded to the walls (wall_size 0.5, 2 elements across a wall gap), remeshed
below quality 0.2, dt = 0.04, T_END time units per start; v_p from
t = TRANSIENT on (the particle's deformation and the matrix's stresses
settle in a few lambda_m).

The thesis ran each trajectory to its end (2-3 weeks on 12 cores); here each
start gives a stretch of the master curve, and the neutral height comes from
where the stretches' v_p changes sign (`softflow migration`). A run
interrupted (a session's end) continues from its checkpoint when the script
is run again.
Usage: scripts/validation/giesekus_migration.py [build_dir] [work_dir] [--jobs N] [--report-only]"""
import csv
import os
import subprocess

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

from case_runs import read_csv, validation_main  # noqa: E402

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
OUT = os.path.join(ROOT, "docs", "validation")
BETA = 0.2
CA_E = 0.1
P = 4.5
SOLVENT, POLYMER, MOBILITY = 0.1, 0.9, 0.2
HEIGHT = 2.0 / BETA
STARTS = [0.35, 0.10, 0.28, 0.20]  # y_p0 / H; the two ends of the curve first
T_END = 15.0
DT = 0.04
TRANSIENT = 5.0
Y_MAX = (1.0 - BETA) / 2.0


def case_name(start):
    return f"yp0_{start:.2f}"


def case_text(start):
    return f"""[case]
name = "{case_name(start)}"
[cell]
length = 20.0
width = 20.0
blockage_ratio = {BETA}
[matrix]
model = "giesekus"
solvent_viscosity = {SOLVENT}
polymer_viscosity = {POLYMER}
relaxation_time = {P * CA_E / POLYMER:.10g}
mobility = {MOBILITY}
[flow]
shear_rate = 1.0
[[objects]]
model = "neo_hookean"
radius = 1.0
elastic_capillary_number = {CA_E}
centre = [0.0, {start * HEIGHT:.6f}, 0.0]
[mesh]
equator_nodes = 20
far_size = 2.0
growth = 0.4
wall_size = 0.5
gap_elements = 2
[time]
step = {DT}
end = {T_END}
[remesh]
quality = 0.2
[checkpoint]
interval_minutes = 10.0
[output]
fields = false
"""


def jobs():
    return [(case_name(s), case_text(s)) for s in STARTS]


def read_migration(directory):
    rows = [r for r in read_csv(os.path.join(directory, "migration.csv")) if r["object"] == "1"]
    return {"t": [float(r["t"]) for r in rows], "y": [float(r["y_p"]) / HEIGHT for r in rows],
            "v": [float(r["v_p"]) / HEIGHT for r in rows], "dS": [float(r["delta_s"]) for r in rows]}


def report(work, build):
    runs = {}
    for s in sorted(STARTS):
        directory = os.path.join(work, case_name(s))
        if os.path.exists(os.path.join(directory, "migration.csv")):
            runs[s] = (directory, read_migration(directory))
    if not runs:
        print("no runs to report")
        return
    combined = os.path.join(work, "combined")
    subprocess.run([os.path.join(build, "softflow"), "migration", *[d for d, _ in runs.values()],
                    "--transient", str(TRANSIENT), "-o", combined], check=True)

    os.makedirs(OUT, exist_ok=True)
    with open(os.path.join(OUT, "giesekus_migration.csv"), "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(["y_p0_over_H", "t", "y_p_over_H", "v_p_over_gamma_dot_H", "delta_S"])
        for s, (_, r) in runs.items():
            for row in zip(r["t"], r["y"], r["v"], r["dS"]):
                w.writerow([f"{s:.2f}", *(f"{x:.6g}" for x in row)])

    fig, ax = plt.subplots(1, 2, figsize=(11, 4.4))
    for s, (_, r) in runs.items():
        ax[0].plot(r["t"], r["y"], label=f"y_p0 = {s:.2f} H")
        late = [i for i, t in enumerate(r["t"]) if t >= TRANSIENT]
        ax[1].plot([r["y"][i] for i in late], [r["v"][i] for i in late], ".", ms=2, label=f"y_p0 = {s:.2f} H")
    ax[0].axhspan(Y_MAX, 0.5, color="0.85")
    ax[0].set(xlabel="gamma_dot t", ylabel="y_p / H", ylim=(0, 0.5), title="trajectories (Fig. 3.12)")
    ax[1].axhline(0.0, color="k", lw=0.6)
    ax[1].set(xlabel="y_p / H", ylabel="v_p / (gamma_dot H)", xlim=(0, 0.5),
              title=f"migration velocity, t >= {TRANSIENT:g} (Fig. 3.13)")
    for a in ax:
        a.grid(alpha=0.3)
        a.legend(fontsize=7)
    fig.suptitle(f"neo-Hookean particle in a Giesekus matrix: beta = {BETA}, Ca_e = {CA_E}, p = {P}, "
                 f"alpha_m = {MOBILITY}; {T_END:g} time units per start")
    fig.tight_layout()
    fig.savefig(os.path.join(OUT, "giesekus_migration.png"), dpi=120)

    import json
    lines = ["# Migration in a Giesekus matrix (thesis Figs. 3.12-3.13)", "",
             f"Generated by `scripts/validation/giesekus_migration.py`: beta = {BETA}, Ca_e = {CA_E}, p = {P} "
             f"(alpha_m = {MOBILITY}, eta_s = {SOLVENT}, eta_p = {POLYMER}, lambda_m = {P * CA_E / POLYMER:g}), "
             f"cell 20 x {HEIGHT:g} x 20 (R = 1), 20 equator nodes, dt = {DT}, t = 0 ... {T_END:g} per start, "
             "[remesh] quality = 0.2. v_p in units of gamma_dot H, y_p in units of H.", "",
             "| y_p0 / H | y_p / H at t = 5 | y_p / H at end | mean v_p, t >= 5 | remeshes | unknowns | wall s | status |",
             "|---|---|---|---|---|---|---|---|"]
    for s, (directory, r) in runs.items():
        path = os.path.join(directory, "summary.json")
        summary = json.load(open(path)) if os.path.exists(path) else {}
        late = [i for i, t in enumerate(r["t"]) if t >= TRANSIENT]
        at5 = r["y"][late[0]] if late else float("nan")
        mean_v = (r["y"][-1] - at5) / (r["t"][-1] - r["t"][late[0]]) if len(late) > 1 else float("nan")
        remesh_csv = os.path.join(directory, "remesh.csv")
        remeshes = len(read_csv(remesh_csv)) if os.path.exists(remesh_csv) else 0
        lines.append(f"| {s:.2f} | {at5:.4f} | {r['y'][-1]:.4f} | {mean_v:.3e} | {remeshes} | "
                     f"{summary.get('unknowns', '')} | {summary.get('wall_seconds', 0):.0f} | "
                     f"{summary.get('status', 'running')} (t = {r['t'][-1]:g}) |")
    lines += ["", "## softflow migration (master curve, neutral heights)", ""]
    md = os.path.join(combined, "migration.md")
    if os.path.exists(md):
        lines += [line.rstrip("\n") for line in open(md)][1:]
    with open(os.path.join(OUT, "giesekus_migration.md"), "w") as f:
        f.write("\n".join(lines) + "\n")
    print("\n".join(lines))


if __name__ == "__main__":
    validation_main("validation_giesekus_migration", jobs, report)
