#!/usr/bin/python3
"""A Newtonian drop in a weakly elastic Oldroyd-B matrix under shear, against
Greco's theta (eq. 2.60, its p term): issue 9's case (b). Writes
docs/validation/oldroyd_b_matrix.{md,csv,png}.

Unit drop, lambda = 1; matrix eta_m = mu + eta_p = 0.5 + 0.5 with relaxation
time lambda_m, so Wi = lambda_m gamma_dot and
p = Psi_1m Gamma / (2 R eta_m^2) = eta_p lambda_m / Ca. Greco's shift of theta
is proportional to Ca p = eta_p Wi: the same at every Ca on a line of fixed
Wi, where the Ca -> 0 end is the theory's range. Every elastic run has a
Newtonian twin (eta_m = 1) on the same mesh with the same step, and the shift
of theta between them is what is compared. Three studies:
  - Wi = 0.01, 0.02, 0.04, 0.08 at Ca = 0.1 (the shift should be linear in
    Wi, through zero);
  - Ca = 0.025, 0.05, 0.1 at Wi = 0.04 (the shift should not depend on Ca);
  - 28 and 40 equator nodes (far size and growth refined with them) at
    Ca = 0.1, Wi = 0.04.
Box 30, dt = lambda_m / 5, to t = 6; steady values are means over the last
10 %. Finished runs are not rerun.

Usage: scripts/validation/oldroyd_b_matrix.py [build_dir] [work_dir] [--jobs N] [--report-only]"""
import csv
import math
import os

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

from case_runs import EULER_PREDICTION, read_run, validation_main  # noqa: E402

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
OUT = os.path.join(ROOT, "docs", "validation")
LAMBDA, ETA_P, T_END = 1.0, 0.5, 6.0
# (Ca, Wi, equator nodes, far size): the elastic runs.
RUNS = [(0.1, 0.04, 28, 4.0), (0.1, 0.02, 28, 4.0), (0.1, 0.08, 28, 4.0),
        (0.05, 0.04, 28, 4.0), (0.025, 0.04, 28, 4.0), (0.1, 0.04, 40, 2.8), (0.1, 0.01, 28, 4.0)]


def dt_for(wi):
    return wi / 5


def name(ca, wi, equator, elastic):
    mesh = "" if equator == 28 else f"_N{equator}"
    return (f"oldroyd_b_Ca{ca:g}_Wi{wi:g}{mesh}" if elastic
            else f"newtonian_Ca{ca:g}_dt{dt_for(wi):g}{mesh}")


def case_text(run_name, ca, wi, equator, far, elastic, lam=LAMBDA):
    """The case: elastic matrix with relaxation time wi, or its Newtonian twin
    at the same step (dt_for(wi)); drop viscosity ratio lam."""
    matrix = (f'[matrix]\nmodel = "oldroyd_b"\nsolvent_viscosity = {1 - ETA_P}\npolymer_viscosity = {ETA_P}\n'
              f"relaxation_time = {wi:.10g}\n" if elastic else "")
    return f"""[case]
name = "{run_name}"
{matrix}[[objects]]
viscosity_ratio = {lam}
capillary_number = {ca}
[mesh]
equator_nodes = {equator}
far_size = {far}
[time]
step = {dt_for(wi):.10g}
end = {T_END}
[checkpoint]
interval_minutes = 0
[output]
fields = false
""" + EULER_PREDICTION


def greco_shift(lam, ca, p, p_d):
    """Greco's theta (eq. 2.60) minus Chaffey-Brenner's, in degrees."""
    return -math.degrees(ca * (p * (176 + 436 * lam + 323 * lam ** 2) / (30 * (1 + lam) * (16 + 19 * lam))
                               + p_d * (9 * lam ** 2 + 6 * lam ** 3) / (8 * (1 + lam) * (16 + 19 * lam))))


def derived_matrix_coefficient(lam):
    """The matrix's first-order angle per unit Deborah number of the matrix, in
    radians, as derived in scripts/theory/second_order_fluid_drop (docs/viscoelastic.md,
    "Eq. 2.60 re-derived"): -c_m, c_m = (19 lam^2 + 32 lam + 16) / (2 (1 + lam)(19 lam + 16))."""
    return (19 * lam ** 2 + 32 * lam + 16) / (2 * (1 + lam) * (19 * lam + 16))


def derived_drop_coefficient(lam):
    """The same for the drop phase: -c_d per unit Deborah number of the drop,
    c_d = 3 lam / (2 (1 + lam)(19 lam + 16))."""
    return 3 * lam / (2 * (1 + lam) * (19 * lam + 16))


def jobs():
    out = {}
    for ca, wi, equator, far in RUNS:
        for elastic in (True, False):
            n = name(ca, wi, equator, elastic)
            out[n] = case_text(n, ca, wi, equator, far, elastic)
    return out


def report(work):
    rows = []
    for ca, wi, equator, far in RUNS:
        ob = read_run(os.path.join(work, name(ca, wi, equator, True)), 0.1 * T_END)
        nt = read_run(os.path.join(work, name(ca, wi, equator, False)), 0.1 * T_END)
        p = ETA_P * wi / ca
        row = {"Ca": ca, "Wi": wi, "p": p, "equator_nodes": equator, "dt": dt_for(wi),
               "greco_shift_deg": greco_shift(LAMBDA, ca, p, 0.0)}
        if ob and nt:
            row.update({"D_oldroyd_b": ob["D_steady"], "D_newtonian": nt["D_steady"],
                        "theta_oldroyd_b_deg": ob["theta_steady"], "theta_newtonian_deg": nt["theta_steady"],
                        "shift_deg": ob["theta_steady"] - nt["theta_steady"],
                        "D_change": ob["D_steady"] / nt["D_steady"] - 1.0, "unknowns": ob["unknowns"],
                        "wall_oldroyd_b_s": ob["wall"], "wall_newtonian_s": nt["wall"],
                        "status": f"{ob['status']} / {nt['status']}"})
        rows.append(row)
    os.makedirs(OUT, exist_ok=True)
    keys = ["Ca", "Wi", "p", "equator_nodes", "dt", "D_oldroyd_b", "D_newtonian", "D_change",
            "theta_oldroyd_b_deg", "theta_newtonian_deg", "shift_deg", "greco_shift_deg", "unknowns",
            "wall_oldroyd_b_s", "wall_newtonian_s", "status"]
    with open(os.path.join(OUT, "oldroyd_b_matrix.csv"), "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=keys)
        w.writeheader()
        for r in rows:
            w.writerow({k: r.get(k, "") for k in keys})
    md = ["# Newtonian drop in a weakly elastic Oldroyd-B matrix (issue 9 case b)", "",
          f"lambda = {LAMBDA:g}; matrix solvent and polymer viscosities {1 - ETA_P:g} + {ETA_P:g}, relaxation "
          "time lambda_m = Wi (gamma_dot = 1), p = eta_p Wi / Ca. Each elastic run has a Newtonian twin "
          "(same mesh, same step). Box 30, far size 4 at 28 equator nodes and 2.8 at 40, dt = lambda_m / 5, "
          "to t = 6; steady values are means over the last 10 %. Greco's shift (eq. 2.60, p term) is "
          "-Ca p (176 + 436 lambda + 323 lambda^2) / (30 (1 + lambda)(16 + 19 lambda)) rad = "
          "-eta_p Wi x 0.445 rad here, independent of Ca. "
          "Generated by `scripts/validation/oldroyd_b_matrix.py`.", "",
          "| Ca | Wi | p | equator nodes | D (Oldroyd-B) | D change vs twin | theta (O-B) [deg] | "
          "theta twin [deg] | shift [deg] | Greco shift [deg] | shift / Greco | unknowns | wall O-B / twin [s] |",
          "|---|---|---|---|---|---|---|---|---|---|---|---|---|"]
    for r in rows:
        if "shift_deg" not in r:
            md.append(f"| {r['Ca']:g} | {r['Wi']:g} | {r['p']:g} | {r['equator_nodes']} | not run |"
                      " | | | | | | | |")
            continue
        md.append(f"| {r['Ca']:g} | {r['Wi']:g} | {r['p']:g} | {r['equator_nodes']} | {r['D_oldroyd_b']:.5f} | "
                  f"{r['D_change']:+.2%} | {r['theta_oldroyd_b_deg']:.3f} | {r['theta_newtonian_deg']:.3f} | "
                  f"{r['shift_deg']:+.3f} | {r['greco_shift_deg']:+.3f} | "
                  f"{r['shift_deg'] / r['greco_shift_deg']:.2f} | {r['unknowns']} | "
                  f"{r['wall_oldroyd_b_s']:.0f} / {r['wall_newtonian_s']:.0f} |")
    with open(os.path.join(OUT, "oldroyd_b_matrix.md"), "w") as f:
        f.write("\n".join(md) + "\n")
    print("\n".join(md))

    done = [r for r in rows if "shift_deg" in r and r["equator_nodes"] == 28]
    fig, (a, b) = plt.subplots(1, 2, figsize=(10, 4))
    for ax, key, fixed, label in ((a, "Wi", ("Ca", 0.1), "Wi"), (b, "Ca", ("Wi", 0.04), "Ca")):
        sel = sorted((r for r in done if r[fixed[0]] == fixed[1]), key=lambda r: r[key])
        xs = [r[key] for r in sel]
        ax.plot(xs, [r["shift_deg"] for r in sel], "o", label="softflow (Oldroyd-B − twin)")
        ax.plot(xs, [r["greco_shift_deg"] for r in sel], "--", label="Greco (eq. 2.60)")
        fine = [r for r in rows if "shift_deg" in r and r["equator_nodes"] != 28 and r[fixed[0]] == fixed[1]]
        if fine:
            ax.plot([r[key] for r in fine], [r["shift_deg"] for r in fine], "s", label="40 equator nodes")
        ax.set_xlabel(label)
        ax.set_ylabel("theta shift [deg]")
        ax.set_title(f"{fixed[0]} = {fixed[1]:g}")
        ax.axhline(0, color="grey", lw=0.5)
        ax.legend()
    fig.tight_layout()
    fig.savefig(os.path.join(OUT, "oldroyd_b_matrix.png"), dpi=120)


def main():
    validation_main("validation_oldroyd_b_matrix", lambda: list(jobs().items()), report)


if __name__ == "__main__":
    main()
