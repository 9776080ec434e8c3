#!/usr/bin/python3
"""The UCM drop's orientation shift with the step-limited SUPG parameter: the
first check before that parameter can be the default in liquids (the
Oldroyd-B matrix drop's offset was the steady parameter's:
oldroyd_b_matrix_supg.py). scripts/validation/ucm_drop.py's De_d = 0.1,
Ca = 0.025 drop (lambda = 2, 28 equator nodes, far size 4, dt = 0.02, t = 6,
Euler prediction) with [conformation] supg_tau = "steady" and "transient",
each against its Newtonian twin on the same mesh and step. Why a drop:
the steady parameter grows as the convective velocity |u - u_m| falls, and
inside a drop that moves with its mesh that velocity may be small (the
reason for the check, not measured here). Then both parameters on ucm_drop.py's whole-mesh
study (20 / 28 / 40 equator nodes, far size and growth refined alike, the
interior at the interface size, dt = 0.02): do they approach one limit,
and which from closer? Writes docs/validation/ucm_drop_supg.{md,csv} and
ucm_drop_supg_levels.csv.
Usage: scripts/validation/ucm_drop_supg.py [build_dir] [work_dir] [--jobs N] [--report-only]"""
import math
import os

from case_runs import read_run, richardson, validation_main, write_csv  # noqa: E402
from oldroyd_b_matrix import derived_drop_coefficient  # noqa: E402
from ucm_drop import INTERIOR_LEVELS, LAMBDA, completed_pair, general_case_text, interior_case_text, \
    interior_level_runs, ucm_lines  # noqa: E402

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
OUT = os.path.join(ROOT, "docs", "validation")
DE_D, DT, T_END = 0.1, 0.02, 6.0
DERIVED_DEG = -math.degrees(DE_D * derived_drop_coefficient(LAMBDA))
TAUS = ["steady", "transient"]


def text(name, drop_lines, tau):
    return with_tau(general_case_text(name, drop_lines, DT, T_END), tau)


def with_tau(base, tau):
    assert base.count("[conformation]\n") == 1 and "supg_tau" not in base
    return base.replace("[conformation]\n", f'[conformation]\nsupg_tau = "{tau}"\n')


def level_runs():
    """(equator nodes, {tau: UCM run}, twin run) of ucm_drop.py's whole-mesh study, runs as
    (name, drop lines, dt, end, equator, far, growth); the UCM runs renamed by tau."""
    return [(n, {tau: (f"{ucm[0]}_{tau}",) + ucm[1:] for tau in TAUS}, twin) for n, ucm, twin in interior_level_runs()]


def jobs():
    runs = [(f"ucm_{tau}", text(f"ucm_{tau}", ucm_lines(DE_D), tau)) for tau in TAUS]
    runs += [("newtonian", text("newtonian", f"viscosity_ratio = {LAMBDA}\n", "steady"))]
    for _, ucm, twin in level_runs():
        runs += [(run[0], with_tau(interior_case_text(run), tau)) for tau, run in ucm.items()]
        runs += [(twin[0], interior_case_text(twin))]
    return runs


def level_report(work):
    """Lines of the whole-mesh study for both parameters, and its csv."""
    rows = []
    for n, ucm, twin in level_runs():
        for tau, run in ucm.items():
            u, w = completed_pair(work, run, twin)
            if u:
                rows.append({"equator_nodes": n, "meshed_nodes": u["summary"]["mesh"]["equator_nodes"], "supg_tau": tau,
                             "unknowns": u["unknowns"], "D_ucm": u["D_steady"],
                             "D_newtonian": w["D_steady"], "shift_deg": u["theta_steady"] - w["theta_steady"],
                             "wall_ucm_s": u["wall"]})
    write_csv(os.path.join(OUT, "ucm_drop_supg_levels.csv"),
              ["equator_nodes", "meshed_nodes", "supg_tau", "unknowns", "D_ucm", "D_newtonian", "shift_deg", "wall_ucm_s"], rows)
    lines = ["", "## Both parameters on the whole-mesh study", "",
             "ucm_drop.py's levels: equator nodes, far size and growth refined by one ratio, the interior at the "
             f"interface size (interior_growth = 0), De_d = {DE_D:g}, Ca = 0.025, dt = {DT:g}; each UCM run beside "
             "its Newtonian twin on the same mesh.", "",
             "| equator nodes (asked / meshed) | supg_tau | unknowns | D (UCM) | D (twin) | shift [deg] | shift / derived | wall UCM [s] |",
             "|---|---|---|---|---|---|---|---|"]
    for x in rows:
        lines.append(f"| {x['equator_nodes']} / {x['meshed_nodes']} | {x['supg_tau']} | {x['unknowns']} | {x['D_ucm']:.5f} | "
                     f"{x['D_newtonian']:.5f} | {x['shift_deg']:.4f} | {x['shift_deg'] / DERIVED_DEG:.3f} | "
                     f"{x['wall_ucm_s']:.0f} |")
    lines.append("")
    for tau in TAUS:
        levels = [x for x in rows if x["supg_tau"] == tau]
        if len(levels) == len(INTERIOR_LEVELS):
            # h = 1 / (meshed equator nodes), as ucm_drop.py's own study.
            fit = richardson([1.0 / x["meshed_nodes"] for x in levels], [x["shift_deg"] for x in levels], (0.1, 10.0))
            lines.append(f"- {tau}: " + ("the changes do not shrink monotonically: no Richardson limit" if fit is None
                                        else f"observed order {fit[0]:.2f}, Richardson shift {fit[1]:.4f} deg "
                                             f"({fit[1] / DERIVED_DEG:.3f} of the derived)"))
    lines.append("")
    return lines


def report(work):
    twin = read_run(os.path.join(work, "newtonian"), 0.1 * T_END)
    rows = []
    for tau in TAUS:
        run = read_run(os.path.join(work, f"ucm_{tau}"), 0.1 * T_END)
        if run and twin:
            rows.append({"supg_tau": tau, "D_ucm": run["D_steady"], "D_newtonian": twin["D_steady"],
                         "theta_ucm_deg": run["theta_steady"], "theta_newtonian_deg": twin["theta_steady"],
                         "shift_deg": run["theta_steady"] - twin["theta_steady"], "derived_shift_deg": DERIVED_DEG})
    write_csv(os.path.join(OUT, "ucm_drop_supg.csv"), list(rows[0]) if rows else ["supg_tau"], rows)
    lines = ["# The UCM drop's shift with the steady and the step-limited SUPG parameter", "",
             "Generated by `scripts/validation/ucm_drop_supg.py`: ucm_drop.py's drop (lambda = 2, Ca = 0.025, "
             f"De_d = {DE_D:g}, 28 equator nodes, far size 4, dt = {DT:g}, t = {T_END:g}, Euler prediction; steady "
             "values over the last 10 %) beside its Newtonian twin (same mesh and step). Derived: the first-order "
             "second-order-fluid shift of docs/viscoelastic.md (eq. 2.60 as printed: -0.186 deg).", "",
             "| supg_tau | D (UCM) | D (twin) | theta (UCM) [deg] | theta (twin) [deg] | shift [deg] | derived [deg] | "
             "shift / derived |", "|---|---|---|---|---|---|---|---|"]
    for x in rows:
        lines.append(f"| {x['supg_tau']} | {x['D_ucm']:.5f} | {x['D_newtonian']:.5f} | {x['theta_ucm_deg']:.3f} | "
                     f"{x['theta_newtonian_deg']:.3f} | {x['shift_deg']:.4f} | {x['derived_shift_deg']:.4f} | "
                     f"{x['shift_deg'] / x['derived_shift_deg']:.3f} |")
    lines.append("")
    lines += level_report(work)
    with open(os.path.join(OUT, "ucm_drop_supg.md"), "w") as f:
        f.write("\n".join(lines))
    print("\n".join(lines))


if __name__ == "__main__":
    validation_main("validation_ucm_drop_supg", jobs, report)
