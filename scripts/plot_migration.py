#!/usr/bin/env python3
"""Plots the migration master curves of `softflow migration`: v_p and Delta S against
y_p / y_p,max, one colour per run, and eq. 3.8's near-centre line; with a
quasi-steady trajectory (--trajectory-from), y_p / y_p,max against t beside them.

Usage: plot_migration.py DIR  (reads DIR/migration_curves.csv, DIR/migration.md,
DIR/migration_trajectory.csv if there; writes DIR/migration.png)
"""
import csv
import os
import re
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt


def main(directory):
    rows = list(csv.DictReader(open(f"{directory}/migration_curves.csv")))
    runs = sorted({int(r["run"]) for r in rows})
    text = open(f"{directory}/migration.md").read()
    m = re.search(r"eq\. 3\.8 gives -2 beta\^3 Ca_e = ([-0-9.e+]+)", text)
    theory = float(m.group(1)) if m else None
    path_file = f"{directory}/migration_trajectory.csv"
    path = list(csv.DictReader(open(path_file))) if os.path.exists(path_file) else []
    fig, axes = plt.subplots(1, 3 if path else 2, figsize=(15 if path else 10, 4))
    ax_v, ax_s = axes[0], axes[1]
    for run in runs:
        pts = [r for r in rows if int(r["run"]) == run]
        y = [float(r["y_p_rel"]) for r in pts]
        ax_v.plot(y, [float(r["v_p"]) for r in pts], ".", ms=3, label=f"run {run}")
        ax_s.plot(y, [float(r["delta_s"]) for r in pts], ".", ms=3)
    if theory is not None:
        ax_v.plot([-0.1, 0.1], [-0.1 * theory, 0.1 * theory], "k--", label="eq. 3.8")
    ax_v.axhline(0.0, color="gray", lw=0.5)
    ax_v.set_xlabel("y_p / y_p,max")
    ax_v.set_ylabel("v_p")
    ax_v.legend(fontsize=7)
    ax_s.set_xlabel("y_p / y_p,max")
    ax_s.set_ylabel("Delta S (eq. 3.6)")
    if path:
        ax_t = axes[2]
        ax_t.plot([float(r["t"]) for r in path], [float(r["y_p_rel"]) for r in path], "k-")
        ax_t.set_xlabel("t (quasi-steady, along the master curve)")
        ax_t.set_ylabel("y_p / y_p,max")
    fig.tight_layout()
    fig.savefig(f"{directory}/migration.png", dpi=120)


if __name__ == "__main__":
    main(sys.argv[1])
