#!/usr/bin/python3
"""One drop in small-amplitude oscillatory shear against the dilute limit of
Oldroyd's emulsion (thesis ch. 4, appendix A; issue 32 item 3): runs the cases
below with the softflow binary and writes docs/validation/dilute_drop_moduli.{md,csv,png}.

A drop (R = 1, Gamma = 1, eta_m = 1, so tau_em = 1 and omega* = omega) in a cell
24 x 16 x 24 (blockage 1/8) between walls oscillating with strain amplitude
gamma0 = 0.05; [bulk_stress] box_side = 4. summary.json's moduli fit the last
two periods (bulk_stress.fit_periods = 2) of the stresslet S_xy = V (<sigma>_xy -
eta_m <2 D_xy>) against the walls' shear rate: S_xy = Re(c eta_m V_d gamma_dot_w),
c the drop's complex intrinsic viscosity, which the dilute limit of Oldroyd's
eta*/eta_m = 1 + c phi predicts (analysis::theory::oldroyd_dilute_coefficient):
Re c = [G'' / (eta_m omega) - 1] / phi and -omega* Im c = [G' R / Gamma] / phi.

Each run lasts 8 of the drop's relaxation times tau (Oldroyd's, at phi = 0) plus
the two fitted periods, rounded up to whole periods (at least 3), with 64 steps
per period. Two meshes (20 and 28 equator nodes) and their order-2 extrapolation.
Linearity (eq. 4.3): lambda = 1, omega* = 1 again with gamma0 = 0.1.
Usage: scripts/validation/dilute_drop_moduli.py [build_dir] [work_dir] [--jobs N] [--report-only]"""
import csv
import json
import math
import os

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

from case_runs import validation_main  # noqa: E402

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
OUT = os.path.join(ROOT, "docs", "validation")
POINTS = [(0.1, w) for w in (0.1, 0.4, 1.0, 4.0)] + [(1.0, w) for w in (0.1, 0.4, 1.0, 4.0)] + \
         [(5.0, w) for w in (0.4, 1.0)]
NODES = [20, 28]
STRAIN = 0.05
STEPS_PER_PERIOD = 64
FIT_PERIODS = 2


def oldroyd_dilute(lam, w, alpha=0.0):
    """Oldroyd's dilute coefficient c (complex) with slip alpha (appendix B as SPEC §9 corrects it;
    alpha = 0: appendix A), written out here independently of softflow
    (analysis::theory::oldroyd_dilute_coefficient)."""
    steady = 5.0 * (5.0 * lam + 2.0) + 50.0 * alpha * lam
    elastic = 5.0 * (lam - 1.0) * (19.0 * lam + 16.0) + 10.0 * alpha * lam * (19.0 * lam - 40.0)
    d0 = 10.0 * (lam + 1.0) + 50.0 * alpha * lam
    t0 = (19.0 * lam + 16.0) * (2.0 * lam + 3.0) + 10.0 * alpha * lam * (19.0 * lam + 24.0)
    return complex(steady, w * elastic / 4.0) / complex(d0, w * t0 / 4.0)


def relaxation_time(lam):
    """Oldroyd's tau / tau_em at phi = 0 (eq. A.4): the drop's shape relaxation time."""
    return (19.0 * lam + 16.0) * (2.0 * lam + 3.0) / (40.0 * (lam + 1.0))


def periods(lam, w):
    period = 2.0 * math.pi / w
    return max(3, math.ceil(8.0 * relaxation_time(lam) / period) + FIT_PERIODS)


def case_name(lam, w, n, strain=STRAIN):
    extra = "" if strain == STRAIN else f"_strain{strain:g}"
    return f"lambda{lam:g}_omega{w:g}_N{n}{extra}"


def case_text(name, lam, w, n, strain=STRAIN):
    period = 2.0 * math.pi / w
    return f"""[case]
name = "{name}"
[cell]
length = 24.0
height = 16.0
width = 24.0
[flow]
type = "oscillatory"
strain_amplitude = {strain}
frequency = {w}
periods = {periods(lam, w)}
[[objects]]
radius = 1.0
viscosity_ratio = {lam}
interfacial_tension = 1.0
[mesh]
equator_nodes = {n}
[time]
step = {period / STEPS_PER_PERIOD:.12g}
[bulk_stress]
box_side = 4.0
fit_periods = {FIT_PERIODS}
[output]
fields = false
"""


def jobs():
    runs = [(case_name(lam, w, n), case_text(case_name(lam, w, n), lam, w, n)) for n in NODES
            for lam, w in POINTS]
    runs.append((case_name(1.0, 1.0, 20, 0.1), case_text(case_name(1.0, 1.0, 20, 0.1), 1.0, 1.0, 20, 0.1)))
    return runs


def read(work, name):
    path = os.path.join(work, name, "summary.json")
    if not os.path.exists(path):
        return None
    s = json.load(open(path))
    m = s.get("moduli", {})
    if "stresslet_coefficient" not in m:
        return None
    re, im = m["stresslet_coefficient"]
    return {"c": complex(re, im), "residual": m["fit_residual_stresslet"], "size": 1.0 / s["mesh"]["equator_nodes"],
            "wall": s["wall_seconds"], "steps": s["steps"], "status": s["status"],
            "G_storage": m.get("G_storage_R_over_Gamma"), "G_loss": m.get("G_loss_over_eta_m_omega"),
            "phi": m["volume_fraction"], "oldroyd": m.get("oldroyd", {})}


def report(work):
    rows = []
    for lam, w in POINTS:
        runs = [read(work, case_name(lam, w, n)) for n in NODES]
        runs = [r for r in runs if r]
        if not runs:
            continue
        c = [r["c"] for r in runs]
        extrapolated = float("nan") * 1j
        if len(runs) == 2:
            ratio = (runs[1]["size"] / runs[0]["size"]) ** 2
            extrapolated = c[1] + (c[1] - c[0]) * ratio / (1.0 - ratio)
        rows.append((lam, w, oldroyd_dilute(lam, w), c, extrapolated, runs))

    os.makedirs(OUT, exist_ok=True)
    with open(os.path.join(OUT, "dilute_drop_moduli.csv"), "w", newline="") as f:
        out = csv.writer(f)
        out.writerow(["lambda", "omega_star", "oldroyd_re_c", "oldroyd_im_c",
                      *(f"N{n}_{part}" for n in NODES for part in ("re_c", "im_c")),
                      "extrapolated_re_c", "extrapolated_im_c", "fit_residual_finest", "wall_s_finest", "steps"])
        for lam, w, theory, c, ex, runs in rows:
            padded = c + [complex(float("nan"), float("nan"))] * (len(NODES) - len(c))
            out.writerow([lam, w, f"{theory.real:.6g}", f"{theory.imag:.6g}",
                          *(f"{v:.6g}" for z in padded for v in (z.real, z.imag)),
                          f"{ex.real:.6g}", f"{ex.imag:.6g}", f"{runs[-1]['residual']:.2e}",
                          f"{runs[-1]['wall']:.0f}", runs[-1]["steps"]])

    def rel(z, exact):
        return f"{100 * abs(z - exact) / abs(exact):.2f} %"

    lines = [
        "# One drop in oscillatory shear against the dilute limit of Oldroyd's emulsion",
        "",
        "Generated by `scripts/validation/dilute_drop_moduli.py`: R = 1, Gamma = 1, eta_m = 1 (omega* = omega), "
        f"cell 24 x 16 x 24, strain amplitude {STRAIN}, {STEPS_PER_PERIOD} steps per period, the last "
        f"{FIT_PERIODS} periods fitted after 8 relaxation times of the drop. c is the drop's complex intrinsic "
        "viscosity, S_xy = Re(c eta_m V_d gamma_dot_w e^{i omega t}) (summary.json's "
        "moduli.stresslet_coefficient); Oldroyd's dilute eta*/eta_m = 1 + c phi gives "
        "G'' / (eta_m omega) = 1 + phi Re c and G' R / Gamma = -phi omega* Im c. "
        "Extrapolated: the two meshes at order 2. Error: |c - c_Oldroyd| / |c_Oldroyd|.",
        "",
        "| lambda | omega* | Oldroyd c | " + " | ".join(f"{n} nodes" for n in NODES)
        + " | extrapolated | error (finest) | error (extrapolated) | fit residual | wall s (finest) |",
        "|---|---|---|" + "---|" * len(NODES) + "---|---|---|---|---|",
    ]

    def show(z):
        return f"{z.real:.4f} {z.imag:+.4f} i"
    for lam, w, theory, c, ex, runs in rows:
        cells = [show(z) for z in c] + [""] * (len(NODES) - len(c))
        lines.append(f"| {lam:g} | {w:g} | {show(theory)} | " + " | ".join(cells)
                     + f" | {show(ex) if len(c) == 2 else ''} | {rel(c[-1], theory)} | "
                     + (f"{rel(ex, theory)}" if len(c) == 2 else "") + f" | {runs[-1]['residual']:.1e} | "
                     f"{runs[-1]['wall']:.0f} |")
    base = read(work, case_name(1.0, 1.0, 20))
    doubled = read(work, case_name(1.0, 1.0, 20, 0.1))
    if base and doubled:
        lines += ["", f"Linearity (eq. 4.3), lambda = 1, omega* = 1, 20 nodes: c at strain 0.1 differs from c at "
                  f"{STRAIN} by {100 * abs(doubled['c'] - base['c']) / abs(base['c']):.3f} % "
                  f"({show(doubled['c'])} against {show(base['c'])})."]
    with open(os.path.join(OUT, "dilute_drop_moduli.md"), "w") as f:
        f.write("\n".join(lines) + "\n")
    print("\n".join(lines))

    fig, ax = plt.subplots(1, 2, figsize=(11, 4.4))
    line = [10 ** (-2 + 0.02 * i) for i in range(176)]
    for k, lam in enumerate(sorted({r[0] for r in rows})):
        colour = f"C{k}"
        ax[0].plot(line, [oldroyd_dilute(lam, w).real for w in line], colour, label=f"Oldroyd, lambda = {lam:g}")
        ax[1].plot(line, [-w * oldroyd_dilute(lam, w).imag for w in line], colour)
        mine = [r for r in rows if r[0] == lam]
        ax[0].plot([r[1] for r in mine], [r[3][-1].real for r in mine], colour + "o", mfc="none",
                   label=f"softflow {NODES[len(mine[0][3]) - 1]} nodes")
        ax[1].plot([r[1] for r in mine], [-r[1] * r[3][-1].imag for r in mine], colour + "o", mfc="none")
        done = [r for r in mine if len(r[3]) == 2]
        ax[0].plot([r[1] for r in done], [r[4].real for r in done], colour + "x")
        ax[1].plot([r[1] for r in done], [-r[1] * r[4].imag for r in done], colour + "x")
    ax[0].set(xscale="log", xlabel="omega* = omega eta_m R / Gamma", ylabel="Re c = [G''/(eta_m omega) - 1] / phi",
              title="loss: one drop against Oldroyd's dilute limit")
    ax[1].set(xscale="log", xlabel="omega*", ylabel="-omega* Im c = [G' R / Gamma] / phi",
              title="storage (x: extrapolated)")
    for a in ax:
        a.grid(alpha=0.3)
    ax[0].legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(os.path.join(OUT, "dilute_drop_moduli.png"), dpi=120)


if __name__ == "__main__":
    validation_main("validation_dilute_drop_moduli", jobs, report)
