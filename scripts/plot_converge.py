#!/usr/bin/python3
"""Draws DIR/converge.png from DIR/converge.csv and converge.json (written by
`softflow converge`): object 1's D and theta against the equator-node count
N, with the Richardson-extrapolated value of the finest three levels as a
dashed line when there is one. Usage: plot_converge.py DIR"""
import csv
import json
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def main(directory):
    with open(os.path.join(directory, "converge.csv")) as f:
        rows = [r for r in csv.DictReader(f) if r["object"] == "1" and r["D"]]
    with open(os.path.join(directory, "converge.json")) as f:
        extrapolated = {e["quantity"]: e for e in json.load(f)["extrapolation"] if e["object"] == 1}
    n = [int(r["meshed_equator_nodes"]) for r in rows]
    fig, axes = plt.subplots(1, 2, figsize=(10, 4))
    for ax, key, label in zip(axes, ("D", "theta_deg"), ("D", "theta [deg]")):
        ax.plot(n, [float(r[key]) for r in rows], "o-", label="softflow")
        e = extrapolated.get(key)
        if e and e["extrapolated"] is not None:
            orders = ", ".join("—" if p is None else f"{p:.2f}" for p in e["orders"])
            ax.axhline(e["extrapolated"], ls="--", color="grey",
                       label=f"extrapolated {e['extrapolated']:.6g} (orders {orders})")
        ax.set_xlabel("meshed equator nodes N (whole mesh refined)")
        ax.set_ylabel(label)
        ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(os.path.join(directory, "converge.png"), dpi=110)


if __name__ == "__main__":
    main(sys.argv[1])
