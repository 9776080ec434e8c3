#!/usr/bin/python3
"""The shape of a migrating particle and its surface imbalance (thesis Fig. 3.7,
eq. 3.6): a neo-Hookean particle at beta = 0.4, Ca_e = 0.1 started at
y_p0 = 0.27 H (the thesis's snapshot: at y_p = 0.213 H on its way to the
centre plane), the case of scripts/validation/confined_migration.py with
the default conformation settings and the fields written every FIELDS_EVERY
steps. The particle's surface in the snapshot nearest Y_SNAPSHOT is drawn
red where the outward normal has n_y > 0 and blue where n_y < 0, as the
thesis draws it, and Delta S = (S(n_y > 0) - S(n_y < 0)) / (S / 2) is
measured twice: by the run on the curved P2 surface (migration.csv, every
step) and here from the written surface drawn flat between its nodes (every
snapshot), a check of eq. 3.6's integration. The thesis says the red area
exceeds the blue (Delta S > 0); docs/confinement.md finds the opposite sign
in softflow's beta = 0.4 runs.
Writes docs/validation/particle_surface_imbalance.{md,csv,png}.
Usage: scripts/validation/particle_surface_imbalance.py [build_dir] [work_dir] [--jobs N] [--report-only]"""
import glob
import os
import re

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
from mpl_toolkits.mplot3d.art3d import Poly3DCollection  # noqa: E402

import vtu_pieces  # noqa: E402
from case_runs import read_csv, validation_main, write_csv  # noqa: E402
from confined_migration import BETA, CA_E, HEIGHT, case_text  # noqa: E402

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
OUT = os.path.join(ROOT, "docs", "validation")
START = 0.27  # y_p0 / H
Y_SNAPSHOT = 0.213  # y_p / H of the thesis's snapshot
T_END = 8.0
FIELDS_EVERY = 10  # steps (0.4 time units)
NAME = "yp0_0.27_fields"


def text():
    base = case_text(NAME, START)
    # The default conformation settings (no [conformation] table), fields every FIELDS_EVERY steps.
    base = base[:base.index("[conformation]")]
    for old, new in (("end = 15.0\n", f"end = {T_END:g}\nfields_interval = {FIELDS_EVERY}\n"),):
        assert old in base
        base = base.replace(old, new)
    return base + "[output]\nfields = true\n"


def jobs():
    return [(NAME, text())]


def snapshots(directory):
    """{step: path of the particle's piece} of the written fields."""
    found = {}
    for path in glob.glob(os.path.join(directory, "fields", "object_1_*.vtu")):
        found[int(re.search(r"_(\d+)\.vtu$", path).group(1))] = path
    return dict(sorted(found.items()))


SUBDIVISIONS = [2, 8, 32]  # flat triangles per curved edge: 2 draws through the nodes, more follow the P2 map


def surface(path):
    piece = vtu_pieces.read_piece(path)
    return piece["points"], vtu_pieces.boundary_faces(piece["cells"], piece["points"])


def imbalance(area, normal):
    """eq. 3.6 on flat triangles: each counted by the sign of its normal's y."""
    up, down = area[normal[:, 1] > 0].sum(), area[normal[:, 1] < 0].sum()
    return (up - down) / (area.sum() / 2), up, down


def plot(points, faces, step_row, series, path):
    fig = plt.figure(figsize=(14, 5.2))
    ax = fig.add_subplot(1, 2, 1, projection="3d")
    corners = vtu_pieces.subdivided_triangles(points, faces, 4)
    _, normal = vtu_pieces.corner_geometry(corners)
    colours = np.where(normal[:, 1:2] > 0, [[0.85, 0.15, 0.1]], [[0.15, 0.3, 0.85]])
    # Drawn with y (the gradient direction) upwards, as the thesis draws it: plot axes (x, z, y).
    ax.add_collection3d(Poly3DCollection(corners[..., [0, 2, 1]], facecolors=colours, linewidths=0))
    c = (0.5 * (points.min(axis=0) + points.max(axis=0)))[[0, 2, 1]]
    for setter, k in ((ax.set_xlim, 0), (ax.set_ylim, 1), (ax.set_zlim, 2)):
        setter(c[k] - 1.3, c[k] + 1.3)
    ax.set_box_aspect((1, 1, 1))
    ax.view_init(elev=12, azim=-60)
    ax.set(xlabel="x", ylabel="z", zlabel="y",
           title=f"Fig. 3.7: t = {step_row['t']:g}, y_p = {step_row['y']:.4f} H (red: n_y > 0, blue: n_y < 0)")
    ax2 = fig.add_subplot(1, 2, 2)
    ax2.plot(series["t"], series["dS"], lw=0.8, label="run: curved P2 surface (migration.csv)")
    for n, values in series["snap_dS"].items():
        ax2.plot(series["snap_t"], values, "o", ms=3 if n > 2 else 5, mfc="none" if n == 2 else None,
                 label=f"written surface, {n}^2 flat triangles per curved one")
    ax2.axhline(0, color="k", lw=0.6)
    ax2.set(xlabel="gamma_dot t", ylabel="Delta S (eq. 3.6)", title="surface imbalance along the way")
    ax2.grid(alpha=0.3)
    ax2.legend(fontsize=8)
    fig.suptitle(f"neo-Hookean particle, beta = {BETA}, Ca_e = {CA_E}, from y_p0 = {START} H")
    fig.tight_layout()
    fig.savefig(path, dpi=120)


def report(work):
    directory = os.path.join(work, NAME)
    if not os.path.exists(os.path.join(directory, "migration.csv")):
        print("no run to report")
        return
    rows = [r for r in read_csv(os.path.join(directory, "migration.csv")) if r["object"] == "1"]
    by_step = {int(r["step"]): r for r in rows}
    table = []
    for step, path in snapshots(directory).items():
        if step not in by_step:
            continue
        points, faces = surface(path)
        r = by_step[step]
        row = {"step": step, "t": float(r["t"]), "y_p_over_H": float(r["y_p"]) / HEIGHT,
               "delta_s_run": float(r["delta_s"])}
        for n in SUBDIVISIONS:
            row[f"delta_s_n{n}"], row[f"area_up_n{n}"], row[f"area_down_n{n}"] = imbalance(
                *vtu_pieces.corner_geometry(vtu_pieces.subdivided_triangles(points, faces, n)))
        table.append(row)
    if not table:
        print("no snapshot yet")
        return
    os.makedirs(OUT, exist_ok=True)
    write_csv(os.path.join(OUT, "particle_surface_imbalance.csv"), list(table[0]), table)
    nearest = min(table, key=lambda x: abs(x["y_p_over_H"] - Y_SNAPSHOT))
    points, faces = surface(snapshots(directory)[nearest["step"]])
    series = {"t": [float(r["t"]) for r in rows], "dS": [float(r["delta_s"]) for r in rows],
              "snap_t": [x["t"] for x in table],
              "snap_dS": {n: [x[f"delta_s_n{n}"] for x in table] for n in SUBDIVISIONS}}
    plot(points, faces, {"t": nearest["t"], "y": nearest["y_p_over_H"]}, series,
         os.path.join(OUT, "particle_surface_imbalance.png"))
    lines = ["# The shape of a migrating particle and its surface imbalance (thesis Fig. 3.7, eq. 3.6)", "",
             "Generated by `scripts/validation/particle_surface_imbalance.py`: beta = 0.4, Ca_e = 0.1, from "
             f"y_p0 = {START} H (the case of `confined_migration.py`, default conformation settings), fields "
             f"every {FIELDS_EVERY} steps. Delta S by the run (on the curved P2 surface, each quadrature point "
             "counted by the sign of its normal) and from the written surface, each 6-node triangle cut into "
             "n^2 flat ones through points of its quadratic map (n = 2: through its nodes) and each flat one "
             "counted by the sign of its normal; the snapshot drawn is the one nearest the thesis's "
             f"y_p = {Y_SNAPSHOT} H (n = 4).", "",
             "![Fig. 3.7](particle_surface_imbalance.png)", "",
             "| step | t | y_p / H | Delta S (run) | " + " | ".join(f"Delta S, n = {n}" for n in SUBDIVISIONS) +
             f" | S(n_y > 0), n = {SUBDIVISIONS[-1]} | S(n_y < 0), n = {SUBDIVISIONS[-1]} |",
             "|---|---|---|---|" + "---|" * len(SUBDIVISIONS) + "---|---|"]
    last = SUBDIVISIONS[-1]
    for x in table:
        mark = " (drawn)" if x is nearest else ""
        lines.append(f"| {x['step']}{mark} | {x['t']:g} | {x['y_p_over_H']:.4f} | {x['delta_s_run']:+.4f} | " +
                     " | ".join(f"{x[f'delta_s_n{n}']:+.4f}" for n in SUBDIVISIONS) +
                     f" | {x[f'area_up_n{last}']:.4f} | {x[f'area_down_n{last}']:.4f} |")
    late = [x for x in table if x["t"] >= 2.0]
    if late:
        gaps = {n: max(abs(x["delta_s_run"] - x[f"delta_s_n{n}"]) for x in late) for n in SUBDIVISIONS}
        lines += ["", f"Over t >= 2 ({len(late)} snapshots): Delta S (run) from "
                  f"{min(x['delta_s_run'] for x in late):+.4f} to {max(x['delta_s_run'] for x in late):+.4f}; "
                  "largest difference from the run's: " +
                  ", ".join(f"{gaps[n]:.4f} at n = {n}" for n in SUBDIVISIONS) + "."]
    lines.append("")
    with open(os.path.join(OUT, "particle_surface_imbalance.md"), "w") as f:
        f.write("\n".join(lines))
    print("\n".join(lines))


if __name__ == "__main__":
    validation_main("validation_particle_surface_imbalance", jobs, report)
