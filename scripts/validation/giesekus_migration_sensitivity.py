#!/usr/bin/python3
"""The two remaining candidates for the Giesekus migration's disagreement with
the thesis (issue 35; docs/confinement.md): the time step and the solvent
fraction. The y_p0 = 0.20 H start of scripts/validation/giesekus_migration.py
(beta = 0.2, Ca_e = 0.1, p = 4.5 read with the zero-shear Psi_1, alpha_m =
0.2, 20 equator nodes), to t = 6, with
  - the time step halved: dt = 0.04 (the figures'), 0.02, 0.01, 0.005 (to t = 2; the
    thesis, §3.1, took steps of 1-2e-3 on meshes of
    2-4 * 10^4 tetrahedra, the size of this 20-node mesh),
  - the solvent fraction mu_m / eta_m = 0.01, 0.1 (the figures'), 0.5 at the
    same p (p fixes eta_p lambda_m: lambda_m = p Ca_e / eta_p) and the same
    zero-shear viscosity eta_m = 1. The thesis does not state mu_m.
Writes the mean v_p (slope of y_p(t), gamma_dot H) over t = 2-6 and its two
halves, the time-step study's observed order and extrapolated v_p (three
levels), to docs/validation/giesekus_migration_sensitivity.{md,csv}.
Usage: scripts/validation/giesekus_migration_sensitivity.py [build_dir] [work_dir] [--jobs N] [--report-only]"""
import csv
import json
import os

from case_runs import richardson, validation_main  # noqa: E402
from giesekus_migration import CA_E, HEIGHT, P, SOLVENT, case_name, case_text  # noqa: E402
from migration_runs import mean_velocity, read_migration  # noqa: E402

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
OUT = os.path.join(ROOT, "docs", "validation")
START = 0.20
END = 6.0
WINDOWS = [(0.2, 0.4), (1.0, 2.0), (2.0, 4.0), (4.0, 6.0), (2.0, 6.0)]
BASE_DT = 0.04
# (name, time step, solvent viscosity, end); eta_m = 1 throughout. The
# longest first; the smallest step only through the first window (t = 1-2,
# after two relaxation times of the matrix) for the time-step study.
# The last element: [conformation] supg_tau (docs/viscoelastic.md): the
# studies above with the thesis's steady parameter everywhere (the only one
# when they ran), then the figures' step with the default (auto: transient in
# the particle) and with the transient parameter in the matrix as well.
RUNS = [("dt0.01", 0.01, SOLVENT, END, "steady"), ("base", BASE_DT, SOLVENT, END, "steady"),
        ("dt0.02", 0.02, SOLVENT, END, "steady"), ("solvent0.5", BASE_DT, 0.5, END, "steady"),
        ("solvent0.01", BASE_DT, 0.01, END, "steady"), ("dt0.005", 0.005, SOLVENT, 2.0, "steady"),
        ("supg_auto", BASE_DT, SOLVENT, END, "auto"), ("supg_transient", BASE_DT, SOLVENT, END, "transient")]


def text(name, dt, solvent, end, supg):
    polymer = 1.0 - solvent
    base = case_text(START).replace(f'name = "{case_name(START)}"', f'name = "{name}"')
    old_matrix = base[base.index("solvent_viscosity"):base.index("mobility")]
    new_matrix = (f"solvent_viscosity = {solvent}\npolymer_viscosity = {polymer:.10g}\n"
                  f"relaxation_time = {P * CA_E / polymer:.10g}\n")
    base = base.replace(old_matrix, new_matrix)
    base = base.replace(f"step = {BASE_DT}", f"step = {dt}")
    base = base.replace("end = 15.0", f"end = {end}")
    return base.replace('supg_tau = "steady"', f'supg_tau = "{supg}"')


def jobs():
    return [(name, text(name, dt, solvent, end, supg)) for name, dt, solvent, end, supg in RUNS]


def summary_of(directory):
    path = os.path.join(directory, "summary.json")
    return json.load(open(path)) if os.path.exists(path) else {}


def report(work):
    rows = []
    for name, dt, solvent, _, supg in RUNS:
        directory = os.path.join(work, name)
        if not os.path.exists(os.path.join(directory, "migration.csv")):
            continue
        r = read_migration(directory, HEIGHT)
        t_last = r["t"][-1] if r["t"] else 0.0
        s = summary_of(directory)
        groups = {g["symbol"]: g["value"] for g in s.get("dimensionless_groups", []) if g.get("object") == 1}
        vs = [mean_velocity(r, a, b) if t_last >= b - 1e-9 else None for a, b in WINDOWS]
        rows.append(dict(name=name, dt=dt, solvent=solvent, supg=supg, lam=P * CA_E / (1.0 - solvent), p=groups.get("p"),
                         p_n1=groups.get("p_N1"), vs=vs, t_last=t_last, wall=s.get("wall_seconds"),
                         unknowns=s.get("unknowns")))
    os.makedirs(OUT, exist_ok=True)
    with open(os.path.join(OUT, "giesekus_migration_sensitivity.csv"), "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(["run", "supg_tau", "dt", "solvent_viscosity", "relaxation_time", "p", "p_N1"] +
                   [f"mean_v_p_t{a:g}_{b:g}" for a, b in WINDOWS] + ["t_last", "wall_time_s"])
        for x in rows:
            w.writerow([x["name"], x["supg"], x["dt"], x["solvent"], f"{x['lam']:.6g}", x["p"], x["p_n1"]] +
                       ["" if v is None else f"{v:.6g}" for v in x["vs"]] + [x["t_last"], x["wall"]])

    def cell(v, fmt):
        return "" if v is None else format(v, fmt)
    lines = ["# Giesekus migration: time step and solvent fraction (beta = 0.2, Ca_e = 0.1, p = 4.5, "
             "y_p0 = 0.20 H)", "",
             "Generated by `scripts/validation/giesekus_migration_sensitivity.py`: the 0.20 H start of "
             "giesekus_migration.py (20 equator nodes, 28,260 tetrahedra, zero-shear p, eta_m = 1) to t = 6 with "
             "the time step halved (dt = 0.005 only to t = 2; a run stopped early shows the t it reached, its "
             "windows past that empty) and with the solvent fraction changed at the same p. v_p is the slope of y_p(t) in "
             "gamma_dot H; negative is towards the centre plane. The thesis (Fig. 3.12, y_N = 0.26 H) has this "
             "start migrating towards the wall (v_p > 0). `supg_tau`: the conformation transport's SUPG "
             "parameter (docs/viscoelastic.md); the time-step study below uses the steady runs.", "",
             "| run | supg_tau | dt | mu_m / eta_m | lambda_m | p | p_N1 | " +
             " | ".join(f"v_p, t = {a:g}-{b:g}" for a, b in WINDOWS) + " | t reached | wall time (s) |",
             "|---|---|---|---|---|---|---|" + "---|" * len(WINDOWS) + "---|---|"]
    for x in rows:
        lines.append(f"| {x['name']} | {x['supg']} | {x['dt']:g} | {x['solvent']:g} | {x['lam']:.4f} | {cell(x['p'], '.3f')} | "
                     f"{cell(x['p_n1'], '.3f')} | " + " | ".join(cell(v, ".3e") for v in x["vs"]) +
                     f" | {x['t_last']:g} | {cell(x['wall'], '.0f')} |")
    # The time-step study: per window, v_p against dt, and v = v* + c dt^p
    # through each three successive halvings.
    for k, (a, b) in enumerate(WINDOWS):
        steps = {x["dt"]: x["vs"][k] for x in rows
                 if x["solvent"] == SOLVENT and x["supg"] == "steady" and x["vs"][k] is not None}
        levels = sorted(steps, reverse=True)
        if len(levels) < 2:
            continue
        lines += ["", f"Time steps, v_p over t = {a:g}-{b:g}: " +
                  ", ".join(f"dt = {dt:g}: {steps[dt]:.3e}" for dt in levels) + "; v_p(dt) - v_p(dt / 2) " +
                  ", ".join(f"{steps[levels[i]] - steps[levels[i + 1]]:+.2e}" for i in range(len(levels) - 1))]
        for i in range(len(levels) - 2):
            hs = tuple(levels[i:i + 3])
            fit = richardson(hs, tuple(steps[h] for h in hs))
            lines.append(f"- dt = {hs[0]:g}, {hs[1]:g}, {hs[2]:g}: " +
                         ("the differences change sign or fit no order in (0.05, 12): no extrapolation" if fit is None
                          else f"observed order {fit[0]:.2f}, extrapolated v_p = {fit[1]:.3e}"))
    with open(os.path.join(OUT, "giesekus_migration_sensitivity.md"), "w") as f:
        f.write("\n".join(lines) + "\n")
    print("\n".join(lines))


if __name__ == "__main__":
    validation_main("validation_giesekus_migration_sensitivity", jobs, report)
