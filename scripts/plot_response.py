#!/usr/bin/python3
"""Draws DIR/response.png from DIR/response.csv (written by `softflow response`): the drops'
complex intrinsic viscosity c against omega* beside Oldroyd's dilute limit, and the cell's
G' R / Gamma and G'' / (eta_m omega) beside Oldroyd's at the cell's volume fraction (and the
centred cube's, when the case has one).
Usage: plot_response.py DIR"""
import csv
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def number(text):
    try:
        return float(text)
    except ValueError:
        return float("nan")


def main(directory):
    with open(os.path.join(directory, "response.csv")) as f:
        rows = sorted(csv.DictReader(f), key=lambda r: number(r["omega_star"]))
    if not rows:
        return
    w = [number(r["omega_star"]) for r in rows]
    column = {k: [number(r[k]) for r in rows] for k in rows[0]}
    fig, ax = plt.subplots(1, 3, figsize=(15, 4.4))
    ax[0].plot(w, column["c_real"], "o", color="C0", label="Re c (softflow)")
    ax[0].plot(w, column["oldroyd_c_real"], "-", color="C0", label="Re c (Oldroyd, dilute)")
    ax[0].plot(w, [-x for x in column["c_imag"]], "s", color="C1", label="-Im c (softflow)")
    ax[0].plot(w, [-x for x in column["oldroyd_c_imag"]], "-", color="C1", label="-Im c (Oldroyd, dilute)")
    ax[0].set(ylabel="c = S_xy / (eta_m gamma_dot V_d)", title="intrinsic viscosity")
    for a, name, theory, label in ((ax[1], "cell_G_storage_R_over_Gamma", "oldroyd_cell_G_storage", "G' R / Gamma"),
                                   (ax[2], "cell_G_loss_over_eta_m_omega", "oldroyd_cell_G_loss",
                                    "G'' / (eta_m omega)")):
        a.plot(w, column[name], "o", color="C0", label="cell (walls)")
        a.plot(w, column[theory], "-", color="C0", label="Oldroyd at the cell's phi")
        box = name.replace("cell_", "box_")
        if any(x == x for x in column.get(box, [])):
            a.plot(w, column[box], "s", color="C2", label="centred cube")
            a.plot(w, column[theory.replace("cell", "box")], "--", color="C2", label="Oldroyd at the cube's phi")
        a.set(ylabel=label, title=label)
    for a in ax:
        a.set_xscale("log")
        a.set_xlabel("omega* = omega eta_m R / Gamma")
        a.grid(alpha=0.3)
        a.legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(os.path.join(directory, "response.png"), dpi=120)


if __name__ == "__main__":
    main(sys.argv[1])
