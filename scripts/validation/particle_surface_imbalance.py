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


def surface(path):
    piece = vtu_pieces.read_piece(path)
    faces = vtu_pieces.boundary_faces(piece["cells"], piece["points"])
    flat = vtu_pieces.flat_triangles(faces)
    area, normal = vtu_pieces.triangle_geometry(piece["points"], flat)
    return piece["points"], flat, area, normal


def imbalance(area, normal):
    """eq. 3.6 on flat triangles: each counted by the sign of its normal's y."""
    up, down = area[normal[:, 1] > 0].sum(), area[normal[:, 1] < 0].sum()
    return (up - down) / (area.sum() / 2), up, down


def plot(points, flat, normal, step_row, series, path):
    fig = plt.figure(figsize=(14, 5.2))
    ax = fig.add_subplot(1, 2, 1, projection="3d")
    colours = np.where(normal[:, 1:2] > 0, [[0.85, 0.15, 0.1]], [[0.15, 0.3, 0.85]])
    ax.add_collection3d(Poly3DCollection(points[flat], facecolors=colours, linewidths=0))
    c = points.mean(axis=0)
    for setter, k in ((ax.set_xlim, 0), (ax.set_ylim, 1), (ax.set_zlim, 2)):
        setter(c[k] - 1.3, c[k] + 1.3)
    ax.set_box_aspect((1, 1, 1))
    ax.view_init(elev=15, azim=-70)
    ax.set(xlabel="x", ylabel="y", zlabel="z",
           title=f"Fig. 3.7: t = {step_row['t']:g}, y_p = {step_row['y']:.4f} H (red: n_y > 0, blue: n_y < 0)")
    ax2 = fig.add_subplot(1, 2, 2)
    ax2.plot(series["t"], series["dS"], lw=0.8, label="run: curved P2 surface (migration.csv)")
    ax2.plot(series["snap_t"], series["snap_dS"], "o", ms=4, label="written surface, drawn flat")
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
        points, flat, area, normal = surface(path)
        flat_ds, up, down = imbalance(area, normal)
        r = by_step[step]
        table.append({"step": step, "t": float(r["t"]), "y_p_over_H": float(r["y_p"]) / HEIGHT,
                      "delta_s_run": float(r["delta_s"]), "delta_s_flat": flat_ds,
                      "area_up": up, "area_down": down})
    if not table:
        print("no snapshot yet")
        return
    os.makedirs(OUT, exist_ok=True)
    write_csv(os.path.join(OUT, "particle_surface_imbalance.csv"), list(table[0]), table)
    nearest = min(table, key=lambda x: abs(x["y_p_over_H"] - Y_SNAPSHOT))
    points, flat, area, normal = surface(snapshots(directory)[nearest["step"]])
    series = {"t": [float(r["t"]) for r in rows], "dS": [float(r["delta_s"]) for r in rows],
              "snap_t": [x["t"] for x in table], "snap_dS": [x["delta_s_flat"] for x in table]}
    plot(points, flat, normal, {"t": nearest["t"], "y": nearest["y_p_over_H"]}, series,
         os.path.join(OUT, "particle_surface_imbalance.png"))
    lines = ["# The shape of a migrating particle and its surface imbalance (thesis Fig. 3.7, eq. 3.6)", "",
             "Generated by `scripts/validation/particle_surface_imbalance.py`: beta = 0.4, Ca_e = 0.1, from "
             f"y_p0 = {START} H (the case of `confined_migration.py`, default conformation settings), fields "
             f"every {FIELDS_EVERY} steps. Delta S by the run (curved P2 surface) and from the written surface "
             "drawn flat between its nodes (four flat triangles per curved one); the snapshot drawn is the "
             f"one nearest the thesis's y_p = {Y_SNAPSHOT} H.", "",
             "![Fig. 3.7](particle_surface_imbalance.png)", "",
             "| step | t | y_p / H | Delta S (run) | Delta S (flat) | S(n_y > 0) | S(n_y < 0) |",
             "|---|---|---|---|---|---|---|"]
    for x in table:
        mark = " (drawn)" if x is nearest else ""
        lines.append(f"| {x['step']}{mark} | {x['t']:g} | {x['y_p_over_H']:.4f} | {x['delta_s_run']:+.4f} | "
                     f"{x['delta_s_flat']:+.4f} | {x['area_up']:.4f} | {x['area_down']:.4f} |")
    late = [x for x in table if x["t"] >= 2.0]
    if late:
        diffs = [abs(x["delta_s_run"] - x["delta_s_flat"]) for x in late]
        lines += ["", f"Over t >= 2 ({len(late)} snapshots): Delta S (run) from {min(x['delta_s_run'] for x in late):+.4f} "
                  f"to {max(x['delta_s_run'] for x in late):+.4f}; the flat drawing differs from the run's curved "
                  f"integration by at most {max(diffs):.4f}."]
    lines.append("")
    with open(os.path.join(OUT, "particle_surface_imbalance.md"), "w") as f:
        f.write("\n".join(lines))
    print("\n".join(lines))


if __name__ == "__main__":
    validation_main("validation_particle_surface_imbalance", jobs, report)
