#!/usr/bin/python3
"""Cross-stream migration of a neo-Hookean particle in confined shear (thesis
§3.2.2, Figs. 3.5, 3.6, 3.8, eq. 3.6): runs the cases below with the softflow
binary, combines them with `softflow migration`, and writes
docs/validation/confined_migration.{md,csv,png}.

beta = 0.4, Ca_e = 0.1: a particle of radius R = 1 between walls at
y = +-H/2, H = 2R / beta = 5, in a periodic cell 10 particle diameters long and
wide (as the thesis), started at y_p0 / H = 0.05, 0.10, 0.15, 0.20, 0.27
(Fig. 3.5's starts; 0.27 leaves a gap of 0.03 H to the wall). The mesh is
graded towards the interface and the walls with 2 elements across the
particle-wall gap; [remesh] quality = 0.2 meshes the cell again around the
deformed, migrating particle whenever an element degrades (issue 31), so the
mesh follows the particle across the channel. dt = 0.04 to t = T_END.

The thesis ran each trajectory for thousands of time units (2-3 weeks on 12
cores); here each start runs T_END time units, so the figures are the
trajectories' beginnings and the master curves sampled where those
beginnings lie (after the first TRANSIENT time units, the particle's
deformation from a sphere, which the thesis drops as "the very early
stages").
Usage: scripts/validation/confined_migration.py [build_dir] [work_dir] [--jobs N] [--report-only]"""
import os

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

from case_runs import PARTICLE_FIGURES_CONFORMATION, validation_main  # noqa: E402
from migration_runs import (combine, plot_trajectories, read_migration, read_starts, start_table,  # noqa: E402
                            write_series)

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
OUT = os.path.join(ROOT, "docs", "validation")
BETA = 0.4
CA_E = 0.1
HEIGHT = 2.0 / BETA
STARTS = [0.05, 0.10, 0.15, 0.20, 0.27]  # y_p0 / H
# The mirror image of a start: the rotation by 180 deg about z maps the case
# onto its start, so v_p and Delta S must come out opposite; their sum is the
# mesh's part (the two meshes are not mirror images).
MIRRORS = [-0.15]
T_END = 15.0
DT = 0.04
TRANSIENT = 5.0
Y_MAX = (1.0 - BETA) / 2.0  # y_p / H of a sphere touching a wall (eq. 3.7's y_p,max is H/2 - R)


def case_name(start):
    return f"yp0_{start:.2f}"


def case_text(name, start):
    # gmsh's mesh of the y_p0 = 0.05 cell has an element of quality 0.018,
    # below the default time.min_quality (0.02) the run checks before its
    # first step; the remesh at step 0 (quality < 0.2) replaces it.
    min_quality = "min_quality = 0.01\n" if start == 0.05 else ""
    return f"""[case]
name = "{name}"
[cell]
length = 20.0
width = 20.0
blockage_ratio = {BETA}
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
{min_quality}[remesh]
quality = 0.2
[checkpoint]
interval_minutes = 10.0
""" + PARTICLE_FIGURES_CONFORMATION


def jobs():
    # The near-wall start (the finest mesh) last.
    return [(case_name(s), case_text(case_name(s), s)) for s in STARTS + MIRRORS]


def mirror_lines(work, runs):
    """Each mirror start against its start at the same times: v_p and Delta S split into
    the antisymmetric part (the physics) and the common part (the meshes' asymmetry)."""
    lines = []
    for m in MIRRORS:
        directory = os.path.join(work, case_name(m))
        if -m not in runs or not os.path.exists(os.path.join(directory, "migration.csv")):
            continue
        mirror, start = read_migration(directory, HEIGHT), runs[-m][1]
        by_time = {round(t, 6): i for i, t in enumerate(start["t"])}
        pairs = [(by_time[round(t, 6)], j) for j, t in enumerate(mirror["t"])
                 if round(t, 6) in by_time and t >= TRANSIENT]
        if not pairs:
            continue
        lines += ["", f"## The mirror pair y_p0 = +-{-m:.2f} H (t >= {TRANSIENT:g}, {len(pairs)} common times)", "",
                  "| t | y_p (+) | y_p (-) | v_p (+) | v_p (-) | Delta S (+) | Delta S (-) | "
                  "Delta S antisymmetric | Delta S common |", "|---|---|---|---|---|---|---|---|---|"]
        for i, j in pairs[::max(1, len(pairs) // 8)] + [pairs[-1]]:
            a, b = start["dS"][i], mirror["dS"][j]
            lines.append(f"| {start['t'][i]:.2f} | {start['y'][i]:.4f} | {mirror['y'][j]:.4f} | {start['v'][i]:.3e} | "
                         f"{mirror['v'][j]:.3e} | {a:+.4f} | {b:+.4f} | {(a - b) / 2:+.4f} | {(a + b) / 2:+.4f} |")
        anti = [(start["dS"][i] - mirror["dS"][j]) / 2 for i, j in pairs]
        common = [(start["dS"][i] + mirror["dS"][j]) / 2 for i, j in pairs]
        dv = [abs(start["v"][i] + mirror["v"][j]) / abs(start["v"][i]) for i, j in pairs if start["v"][i] != 0]
        lines += ["", f"Mean over the common times: Delta S antisymmetric {sum(anti) / len(anti):+.4f}, common "
                  f"{sum(common) / len(common):+.4f}; |v_p(+) + v_p(-)| / |v_p(+)| median "
                  f"{sorted(dv)[len(dv) // 2]:.3f}."]
    return lines


def report(work, build):
    runs = read_starts(work, STARTS, case_name, HEIGHT)
    if not runs:
        print("no runs to report")
        return
    combined_lines = combine(build, work, runs, TRANSIENT)
    os.makedirs(OUT, exist_ok=True)
    write_series(os.path.join(OUT, "confined_migration.csv"), runs)

    fig, ax = plt.subplots(1, 3, figsize=(15, 4.4))
    plot_trajectories(ax, runs, Y_MAX, TRANSIENT)
    for s, (_, r) in runs.items():
        late = [i for i, t in enumerate(r["t"]) if t >= TRANSIENT]
        ax[2].plot([r["y"][i] for i in late], [r["dS"][i] for i in late], ".", ms=2, label=f"y_p0 = {s:.2f} H")
    ax[0].set(title="trajectories (Fig. 3.5)")
    slope = -2 * BETA ** 3 * CA_E  # eq. 3.8, v_p / (gamma_dot H) against y_p / y_p,max
    ys = [0, Y_MAX]
    ax[1].plot(ys, [slope * y / Y_MAX for y in ys], "k--", lw=0.8, label="eq. 3.8 (near the centre)")
    ax[1].set(xlim=(0, 0.3), title=f"migration velocity, t >= {TRANSIENT:g} (Fig. 3.6)")
    ax[2].set(xlabel="y_p / H", ylabel="Delta S (eq. 3.6)", xlim=(0, 0.3),
              title=f"surface imbalance, t >= {TRANSIENT:g} (Fig. 3.8)")
    for a in ax:
        a.grid(alpha=0.3)
        a.legend(fontsize=7)
    fig.suptitle(f"neo-Hookean particle, beta = {BETA}, Ca_e = {CA_E}: softflow, {T_END:g} time units per start")
    fig.tight_layout()
    fig.savefig(os.path.join(OUT, "confined_migration.png"), dpi=120)

    lines = [
        "# Cross-stream migration of a confined neo-Hookean particle (thesis Figs. 3.5, 3.6, 3.8)",
        "",
        f"Generated by `scripts/validation/confined_migration.py`: beta = {BETA}, Ca_e = {CA_E}, "
        f"cell 20 x {HEIGHT:g} x 20 (R = 1), dt = {DT}, t = 0 ... {T_END:g} per start, "
        "[remesh] quality = 0.2. v_p in units of gamma_dot H, y_p in units of H.",
        "",
    ] + start_table(runs, TRANSIENT)
    lines += mirror_lines(work, runs)
    lines += ["", f"eq. 3.8 near the centre: v_p = {slope:.4f} y_p / y_p,max (gamma_dot H).", "",
              "## softflow migration (master curves, neutral heights, near-centre slope)", ""]
    lines += combined_lines
    with open(os.path.join(OUT, "confined_migration.md"), "w") as f:
        f.write("\n".join(lines) + "\n")
    print("\n".join(lines))


if __name__ == "__main__":
    validation_main("validation_confined_migration", jobs, report)
