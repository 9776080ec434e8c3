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
import json
import os

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

from case_runs import PARTICLE_FIGURES_CONFORMATION, validation_main  # noqa: E402
from giesekus_shear import relaxation_time_for_p  # noqa: E402
from migration_runs import combine, mean_velocity, plot_trajectories, read_starts, start_table, write_series  # noqa: E402

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
OUT = os.path.join(ROOT, "docs", "validation")
BETA = 0.2
CA_E = 0.1
P = 4.5
SOLVENT, POLYMER, MOBILITY = 0.1, 0.9, 0.2
HEIGHT = 2.0 / BETA
STARTS = [0.28, 0.20, 0.35, 0.10]  # y_p0 / H
T_END = 15.0
DT = 0.04
TRANSIENT = 5.0
Y_MAX = (1.0 - BETA) / 2.0


# Two readings of p (see the module's docstring): the zero-shear Psi_1 of
# chapter 2 and softflow's summary (lambda_m = p Ca_e / eta_p), and chapter 3's
# N / Ca_e^2 with N_1 at the shear rate (giesekus_shear; the run reports it as
# p_N1). Case names: yp0_Y and n1_yp0_Y. The second reading's lambda_m is the
# first's at p = 5.86, so its runs also give the zero-shear reading's
# neutral height at that p.
DEFINITIONS = {
    "zero_shear": ("", P * CA_E / POLYMER),
    "n1": ("n1_", relaxation_time_for_p(P, CA_E, SOLVENT, POLYMER, MOBILITY)),
}
# (definition, start) in the order they run: each reading's starts nearest a
# sign change of v_p first.
ORDER = [("zero_shear", 0.28), ("zero_shear", 0.20), ("n1", 0.28), ("zero_shear", 0.10),
         ("n1", 0.10), ("n1", 0.20), ("zero_shear", 0.35), ("n1", 0.35)]


def case_name(start, definition="zero_shear"):
    return f"{DEFINITIONS[definition][0]}yp0_{start:.2f}"


def case_text(start, definition="zero_shear"):
    return f"""[case]
name = "{case_name(start, definition)}"
[cell]
length = 20.0
width = 20.0
blockage_ratio = {BETA}
[matrix]
model = "giesekus"
solvent_viscosity = {SOLVENT}
polymer_viscosity = {POLYMER}
relaxation_time = {DEFINITIONS[definition][1]:.10g}
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
""" + PARTICLE_FIGURES_CONFORMATION


def jobs():
    return [(case_name(s, d), case_text(s, d)) for d, s in ORDER]


def p_reported(directory, symbol):
    """The run's own value of the dimensionless group `symbol` (summary.json)."""
    path = os.path.join(directory, "summary.json")
    if not os.path.exists(path):
        return None
    groups = json.load(open(path)).get("dimensionless_groups", [])
    return next((g["value"] for g in groups if g["symbol"] == symbol and g.get("object") == 1), None)


def direction_table(runs):
    lines = ["| y_p0 / H | mean y_p / H, t >= transient | mean v_p | direction | eq. 3.8 (Newtonian) | ratio | "
             "p (zero-shear Psi_1) | p_N1 (N_1 at the shear rate) |", "|---|---|---|---|---|---|---|---|"]
    for start, (directory, r) in runs.items():
        v = mean_velocity(r, TRANSIENT)
        late = [y for t, y in zip(r["t"], r["y"]) if t >= TRANSIENT]
        if v is None or not late:
            continue
        y_mean = sum(late) / len(late)
        law = -2.0 * BETA ** 3 * CA_E * y_mean / Y_MAX
        p0, p1 = p_reported(directory, "p"), p_reported(directory, "p_N1")
        lines.append(f"| {start:.2f} | {y_mean:.4f} | {v:.3e} | {'towards the wall' if v > 0 else 'towards the centre'} "
                     f"| {law:.3e} | {v / law:.2f} | {'' if p0 is None else f'{p0:.3f}'} | "
                     f"{'' if p1 is None else f'{p1:.3f}'} |")
    return lines


def report(work, build):
    series = {}
    for d, (prefix, lam) in DEFINITIONS.items():
        runs = read_starts(work, STARTS, lambda s, d=d: case_name(s, d), HEIGHT)
        if runs:
            series[d] = (lam, runs)
    if not series:
        print("no runs to report")
        return
    os.makedirs(OUT, exist_ok=True)
    fig, ax = plt.subplots(1, 2, figsize=(11, 4.6))
    styles = {"zero_shear": ("-", "."), "n1": ("--", "x")}
    names = {"zero_shear": "p = 4.5 from the zero-shear Psi_1 (lambda_m = 0.5)",
             "n1": f"p = 4.5 from N_1 at the shear rate (lambda_m = {DEFINITIONS['n1'][1]:.4f}; zero-shear p = "
                   f"{POLYMER * DEFINITIONS['n1'][1] / CA_E:.2f})"}
    lines = ["# Migration in a Giesekus matrix (thesis Figs. 3.12-3.13)", "",
             f"Generated by `scripts/validation/giesekus_migration.py`: beta = {BETA}, Ca_e = {CA_E}, p = {P}, "
             f"alpha_m = {MOBILITY}, eta_s = {SOLVENT}, eta_p = {POLYMER}, cell 20 x {HEIGHT:g} x 20 (R = 1), "
             f"20 equator nodes, dt = {DT}, t = 0 ... {T_END:g} per start, [remesh] quality = 0.2. v_p in units "
             "of gamma_dot H, y_p in units of H. Two readings of the thesis's p (see "
             "scripts/validation/giesekus_shear.py and docs/confinement.md): each a series of starts.", "",
             "The thesis (§3.2.3, Figs. 3.12-3.13): the starts 0.10 and 0.20 migrate upwards (towards the "
             "wall), 0.28 and 0.35 downwards, to the neutral height y_N = 0.26 H; v_p is largest at "
             "y_p = 0.16 H. Beside each start, the sign of its mean v_p, the Newtonian matrix's law "
             "(eq. 3.8, -2 beta^3 Ca_e y_p / y_p,max) at its mean height, and the p the run reports."]
    for d, (lam, runs) in series.items():
        suffix = "" if d == "zero_shear" else "_" + d
        write_series(os.path.join(OUT, f"giesekus_migration{suffix}.csv"), runs)
        linestyle, marker = styles[d]
        plot_trajectories(ax, runs, Y_MAX, TRANSIENT, prefix="N_1 p: " if d == "n1" else "", linestyle=linestyle,
                          marker=marker)
        combined_lines = combine(build, work, runs, TRANSIENT, name="combined" + suffix)
        lines += ["", f"## {names[d]}", ""] + start_table(runs, TRANSIENT) + [""] + direction_table(runs)
        lines += ["", f"### softflow migration (master curve, neutral heights): {names[d]}", ""] + combined_lines
    ax[0].set(title="trajectories (Fig. 3.12); dashed: p from N_1 at the shear rate")
    ax[1].axhline(0.0, color="k", lw=0.6)
    ax[1].set(xlim=(0, 0.5), title=f"migration velocity, t >= {TRANSIENT:g} (Fig. 3.13)")
    for a in ax:
        a.grid(alpha=0.3)
        a.legend(fontsize=6)
    fig.suptitle(f"neo-Hookean particle in a Giesekus matrix: beta = {BETA}, Ca_e = {CA_E}, p = {P}, "
                 f"alpha_m = {MOBILITY}; {T_END:g} time units per start")
    fig.tight_layout()
    fig.savefig(os.path.join(OUT, "giesekus_migration.png"), dpi=120)
    with open(os.path.join(OUT, "giesekus_migration.md"), "w") as f:
        f.write("\n".join(lines) + "\n")
    print("\n".join(lines))


if __name__ == "__main__":
    validation_main("validation_giesekus_migration", jobs, report)
