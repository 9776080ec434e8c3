#!/usr/bin/python3
"""Draws DIR/moduli.png from DIR/moduli.csv (written by `softflow moduli`): G' R / Gamma and
G'' / (eta_m omega) with their standard deviations over the configurations, against the first
varied parameter (omega* when none is varied but the seed), Oldroyd's emulsion beside them.
Usage: plot_moduli.py DIR"""
import csv
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

FIXED = ["omega_star", "configurations", "fitted", "phi", "G_storage_R_over_Gamma", "G_storage_std",
         "G_loss_over_eta_m_omega", "G_loss_std", "oldroyd_G_storage", "oldroyd_G_loss", "worst_fit_residual"]


def number(text):
    try:
        return float(text)
    except ValueError:
        return float("nan")


def main(directory):
    with open(os.path.join(directory, "moduli.csv")) as f:
        rows = [r for r in csv.DictReader(f) if r["fitted"] not in ("", "0")]
    if not rows:
        return
    varied = [k for k in rows[0] if k not in FIXED]
    axis = varied[0] if varied else "omega_star"
    # A parameter such as frequency varies the x axis; with a second one, one series per value.
    series = {}
    for r in rows:
        series.setdefault(tuple(r[k] for k in varied[1:]), []).append(r)
    fig, ax = plt.subplots(1, 2, figsize=(11, 4.4))
    for k, (group, members) in enumerate(series.items()):
        members.sort(key=lambda r: number(r[axis]))
        x = [number(r[axis]) for r in members]
        name = ", ".join(f"{n} = {v}" for n, v in zip(varied[1:], group))
        for a, mean, std, theory in ((ax[0], "G_storage_R_over_Gamma", "G_storage_std", "oldroyd_G_storage"),
                                     (ax[1], "G_loss_over_eta_m_omega", "G_loss_std", "oldroyd_G_loss")):
            a.errorbar(x, [number(r[mean]) for r in members], yerr=[number(r[std]) for r in members],
                       fmt="o", color=f"C{k}", capsize=3, label=f"softflow {name}".strip())
            a.plot(x, [number(r[theory]) for r in members], "s-", mfc="none", color=f"C{k}",
                   label=f"Oldroyd at the runs' phi {name}".strip())
    if axis in ("frequency", "omega_star"):
        for a in ax:
            a.set_xscale("log")
    ax[0].set(xlabel=axis, ylabel="G' R / Gamma", title="storage modulus")
    ax[1].set(xlabel=axis, ylabel="G'' / (eta_m omega)", title="loss modulus")
    for a in ax:
        a.grid(alpha=0.3)
        a.legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(os.path.join(directory, "moduli.png"), dpi=120)


if __name__ == "__main__":
    main(sys.argv[1])
