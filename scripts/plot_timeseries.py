#!/usr/bin/python3
"""Draws OUTDIR/deformation.png from OUTDIR/timeseries.csv: D(t) and theta(t)
of every object, with the Taylor (eq. 1.1) and Chaffey-Brenner (eq. 2.59)
values from OUTDIR/summary.json drawn beside. Usage: plot_timeseries.py OUTDIR"""
import csv
import json
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def main(directory):
    with open(os.path.join(directory, "timeseries.csv")) as f:
        rows = list(csv.DictReader(f))
    summary = {}
    path = os.path.join(directory, "summary.json")
    if os.path.exists(path):
        with open(path) as f:
            summary = json.load(f)
    fig, (ax_d, ax_t) = plt.subplots(1, 2, figsize=(11, 4.2))
    colour = {}  # each object's theory lines in its own colour
    for obj in sorted({int(r["object"]) for r in rows}):
        sub = [r for r in rows if int(r["object"]) == obj]
        t = [float(r["t"]) for r in sub]
        colour[obj] = ax_d.plot(t, [float(r["D"]) for r in sub], label=f"object {obj}")[0].get_color()
        # theta is undefined while the object is still a sphere (D ~ 0).
        ax_t.plot([x for x, r in zip(t, sub) if float(r["D"]) > 1e-3],
                  [float(r["theta_deg"]) for r in sub if float(r["D"]) > 1e-3], label=f"object {obj}",
                  color=colour[obj])
    for th in summary.get("theory", []):
        label = f"(object {th['object']}, Ca = {th['capillary_number']:g}, lambda = {th['viscosity_ratio']:g})"
        c = colour.get(th["object"], "gray")
        ax_d.axhline(th["taylor_D"], ls="--", color=c, alpha=0.7, label="Taylor " + label)
        ax_t.axhline(th["chaffey_brenner_theta_deg"], ls="--", color=c, alpha=0.7,
                     label="Chaffey-Brenner " + label)
    ax_d.set_xlabel("t")
    ax_d.set_ylabel("D = (L - B) / (L + B)")
    ax_t.set_xlabel("t")
    ax_t.set_ylabel("theta [deg]")
    for ax in (ax_d, ax_t):
        ax.grid(True, alpha=0.3)
        ax.legend(fontsize=8)
    fig.suptitle(summary.get("case", ""))
    fig.tight_layout()
    fig.savefig(os.path.join(directory, "deformation.png"), dpi=120)


if __name__ == "__main__":
    main(sys.argv[1])
