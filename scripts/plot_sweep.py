#!/usr/bin/python3
"""Draws SWEEPDIR/sweep.png from SWEEPDIR/sweep.csv (written by `softflow sweep`):
the final D and theta of every case against the first swept parameter, one
line per combination of the others, beside small-deformation theory: the
curves of SWEEPDIR/sweep_theory.csv when the parameter is a capillary number
or viscosity ratio, else each case's Taylor D and Chaffey-Brenner theta as
open markers. Usage: plot_sweep.py SWEEPDIR"""
import csv
import json
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def number(text):
    try:
        return float(text)
    except ValueError:
        return None


def main(directory):
    with open(os.path.join(directory, "sweep.json")) as f:
        names = [p["name"] for p in json.load(f)["parameters"]]
    with open(os.path.join(directory, "sweep.csv")) as f:
        rows = [r for r in csv.DictReader(f) if r["D"] and r["object"] == "1"]
    x_name, others = names[0], names[1:]
    numeric = all(number(r[x_name]) is not None for r in rows)
    groups = {}
    for r in rows:
        key = " ".join(f"{n}={r[n]}" for n in others)
        groups.setdefault(key, []).append(r)

    fig, (ax_d, ax_t) = plt.subplots(1, 2, figsize=(11, 4.2))
    theory_path = os.path.join(directory, "sweep_theory.csv")
    curves = {}
    if os.path.exists(theory_path):
        with open(theory_path) as f:
            for r in csv.DictReader(f):
                curves.setdefault(r["group"], []).append(r)
    for i, (key, sub) in enumerate(sorted(groups.items())):
        colour = f"C{i}"
        label = key or "softflow"
        positions = [number(r[x_name]) if numeric else k for k, r in enumerate(sub)]
        order = sorted(range(len(sub)), key=lambda k: positions[k])
        xs = [positions[k] for k in order]
        sub = [sub[k] for k in order]
        ax_d.plot(xs, [float(r["D"]) for r in sub], "o-", color=colour, label=label)
        ax_t.plot(xs, [float(r["theta_deg"]) for r in sub], "o-", color=colour, label=label)
        if key in curves:
            c = curves[key]
            cx = [float(r[x_name]) for r in c]
            ax_d.plot(cx, [float(r["taylor_D"]) for r in c], "--", color=colour,
                      label="Taylor" + (f" ({key})" if key else ""))
            ax_t.plot(cx, [float(r["chaffey_brenner_theta_deg"]) for r in c], "--", color=colour,
                      label="Chaffey-Brenner" + (f" ({key})" if key else ""))
        else:
            theory = [r for r in sub if r["taylor_D"]]
            ax_d.plot([xs[k] for k, r in enumerate(sub) if r["taylor_D"]],
                      [float(r["taylor_D"]) for r in theory], "s", mfc="none", color=colour,
                      label="Taylor" + (f" ({key})" if key else ""))
            ax_t.plot([xs[k] for k, r in enumerate(sub) if r["taylor_D"]],
                      [float(r["chaffey_brenner_theta_deg"]) for r in theory], "s", mfc="none",
                      color=colour, label="Chaffey-Brenner" + (f" ({key})" if key else ""))
        if not numeric:
            ax_d.set_xticks(xs, [r[x_name] for r in sub])
            ax_t.set_xticks(xs, [r[x_name] for r in sub])
    for ax, ylabel in ((ax_d, "D (final)"), (ax_t, "theta (deg, final)")):
        ax.set_xlabel(x_name)
        ax.set_ylabel(ylabel)
        ax.grid(alpha=0.3)
        ax.legend(fontsize=8)
    fig.suptitle(f"sweep {os.path.basename(os.path.normpath(directory))}")
    fig.tight_layout()
    fig.savefig(os.path.join(directory, "sweep.png"), dpi=120)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1]))
