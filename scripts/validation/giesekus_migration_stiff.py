#!/usr/bin/python3
"""The Giesekus migration towards the rigid limit: the thesis's p grows as
1 / Ca_e at a fixed matrix (p = Psi_1m G / (2 eta_m^2), G = eta_m gamma_dot /
Ca_e), and §3.2.4 says that beyond p ~ 10 the walls attract the particle from
every start, the p -> infinity limit being the rigid sphere, which migrates
towards the closest wall in a Giesekus fluid for any elasticity (D'Avino et
al., the thesis's ref. [25]). This script checks that limit, where the
particle's deformation (the inward push) fades and only the matrix's
elasticity is left: the y_p0 = 0.20 H start of
scripts/validation/giesekus_migration.py (beta = 0.2, the same Giesekus
matrix: lambda_m = 0.5, alpha_m = 0.2, eta_s = 0.1, eta_p = 0.9, Wi = 0.5)
at Ca_e = 0.1, 0.05, 0.02 (zero-shear p = 4.5, 9, 22.5), each beside its
Newtonian twin (the same particle in a Newtonian matrix of the same
zero-shear viscosity), dt = 0.04 to t = 6, the consistent predicted stress,
the steady SUPG parameter, 20 equator nodes. The difference of the two v_p
is the part of the migration the matrix's elasticity makes.
Writes docs/validation/giesekus_migration_stiff.{md,csv}.
Usage: scripts/validation/giesekus_migration_stiff.py [build_dir] [work_dir] [--jobs N] [--report-only]"""
import csv
import json
import os

from case_runs import validation_main  # noqa: E402
from giesekus_migration import BETA, HEIGHT, P, POLYMER, SOLVENT, Y_MAX  # noqa: E402
from giesekus_migration_supg import text as supg_text  # noqa: E402
from giesekus_migration_sensitivity import WINDOWS  # noqa: E402
from migration_runs import mean_velocity, read_migration  # noqa: E402

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
OUT = os.path.join(ROOT, "docs", "validation")
CA_E = [0.02, 0.1, 0.05]  # in the order they run: the rigid end first
BASE_CA_E = 0.1
MATRICES = ["giesekus", "newtonian"]
# The rigid end on the next mesh level (28 equator nodes asked, the whole mesh
# refined by 20/28, as giesekus_migration_resolution.py's N28), where the
# p = 4.5 start's v_p moved by -3.6e-4 gamma_dot H from the 20-node mesh, and
# on the 20-node mesh with the step-limited SUPG parameter, which gave the
# finer mesh's v_p at p = 4.5 (giesekus_migration_supg.py).
# (Ca_e, matrix, equator nodes, supg_tau)
EXTRA = [(0.02, "giesekus", 28, "steady"), (0.02, "giesekus", 20, "transient")]


def run_name(ca, matrix, nodes=20, tau="steady"):
    return f"{matrix}_ca{ca:g}" + ("" if nodes == 20 else f"_N{nodes}") + ("" if tau == "steady" else f"_{tau}")


def text(ca, matrix, nodes=20, tau="steady"):
    base = supg_text(nodes, tau).replace(f'name = "N{nodes}_{tau}"', f'name = "{run_name(ca, matrix, nodes, tau)}"')
    old_ca = f"elastic_capillary_number = {BASE_CA_E}\n"
    assert old_ca in base
    base = base.replace(old_ca, f"elastic_capillary_number = {ca}\n")
    if matrix == "newtonian":
        matrix_table = base[base.index("[matrix]"):base.index("[flow]")]
        base = base.replace(matrix_table, f'[matrix]\nmodel = "newtonian"\nviscosity = {SOLVENT + POLYMER:g}\n')
    return base


def jobs():
    runs = [(run_name(ca, m), text(ca, m)) for ca in CA_E for m in MATRICES]
    return runs[:2] + [(run_name(*x), text(*x)) for x in EXTRA] + runs[2:]


def p_of(ca):
    """The zero-shear p of the Giesekus matrix (lambda_m fixed at P Ca_e / eta_p for Ca_e = 0.1)."""
    return P * BASE_CA_E / ca


def report(work):
    columns = [f"mean_v_p_t{a:g}_{b:g}" for a, b in WINDOWS]
    rows = []
    for ca, m, nodes, tau in [(ca, m, 20, "steady") for ca in sorted(CA_E, reverse=True) for m in MATRICES] + EXTRA:
        directory = os.path.join(work, run_name(ca, m, nodes, tau))
        if not os.path.exists(os.path.join(directory, "migration.csv")):
            continue
        r = read_migration(directory, HEIGHT)
        t_last = r["t"][-1] if r["t"] else 0.0
        path = os.path.join(directory, "summary.json")
        s = json.load(open(path)) if os.path.exists(path) else {}
        groups = {g["symbol"]: g["value"] for g in s.get("dimensionless_groups", []) if g.get("object") == 1}
        final = {f["object"]: f for f in s.get("final", [])}.get(1, {})
        rows.append({"ca_e": ca, "matrix": m, "equator_nodes": nodes, "supg_tau": tau, "p": groups.get("p"),
                     "D_end": final.get("D"),
                     "t_last": t_last, "wall_seconds": s.get("wall_seconds"),
                     **{c: (mean_velocity(r, a, b) if t_last >= b - 1e-9 else None)
                        for c, (a, b) in zip(columns, WINDOWS)}})
    os.makedirs(OUT, exist_ok=True)
    with open(os.path.join(OUT, "giesekus_migration_stiff.csv"), "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=["ca_e", "matrix", "equator_nodes", "supg_tau", "p", "D_end", "t_last",
                                          "wall_seconds"] + columns)
        w.writeheader()
        for x in rows:
            w.writerow({k: ("" if v is None else (f"{v:.6g}" if isinstance(v, float) else v)) for k, v in x.items()})
    last = columns[-1]
    a, b = WINDOWS[-1]
    law = -2.0 * BETA ** 3 * 0.20 / Y_MAX  # eq. 3.8 per unit Ca_e at y_p0 = 0.20 H
    lines = ["# Giesekus migration towards the rigid limit (p = 4.5, 9, 22.5 at Wi = 0.5)", "",
             "Generated by `scripts/validation/giesekus_migration_stiff.py`: beta = 0.2, y_p0 = 0.20 H, the Giesekus "
             f"matrix of Figs. 3.12-3.13 (lambda_m = {P * BASE_CA_E / POLYMER:g}, alpha_m = 0.2, eta_s = {SOLVENT:g}, "
             f"eta_p = {POLYMER:g}) or a Newtonian one of the same zero-shear viscosity; Ca_e sets the particle's "
             "modulus, so p = Psi_1m G / (2 eta_m^2) grows as 1 / Ca_e. dt = 0.04, consistent predicted stress, "
             "steady SUPG parameter, 20 equator nodes. v_p: slope of y_p(t), in gamma_dot H (negative: towards the "
             "centre plane). The thesis (§3.2.4, Fig. 3.14): beyond p ~ 10 every start migrates towards the wall; "
             "a rigid sphere in a Giesekus fluid does for any elasticity (its ref. [25]).", "",
             "| Ca_e | matrix | equator nodes | supg_tau | p | D at end | " +
             " | ".join(f"v_p, t = {a:g}-{b:g}" for a, b in WINDOWS) + " | t reached | wall s |",
             "|---|---|---|---|---|---|" + "---|" * len(WINDOWS) + "---|---|"]
    for x in rows:
        p = "" if x["p"] is None else format(x["p"], ".3g")
        lines.append(f"| {x['ca_e']:g} | {x['matrix']} | {x['equator_nodes']} | {x['supg_tau']} | {p} | "
                     f"{'' if x['D_end'] is None else format(x['D_end'], '.4f')} | " +
                     " | ".join("" if x[c] is None else f"{x[c]:.3e}" for c in columns) +
                     f" | {x['t_last']:g} | {x['wall_seconds'] or 0:.0f} |")
    lines += ["", f"The matrix's elastic part, v_p(Giesekus) - v_p(Newtonian) over t = {a:g}-{b:g}, beside eq. 3.8's "
              "Newtonian law at 0.20 H:", "", "| Ca_e | p | v_p Giesekus | v_p Newtonian | elastic part | eq. 3.8 |",
              "|---|---|---|---|---|---|"]
    by = {(x["ca_e"], x["matrix"]): x for x in rows if x["equator_nodes"] == 20 and x["supg_tau"] == "steady"}
    for ca in sorted(CA_E, reverse=True):
        g, n = by.get((ca, "giesekus")), by.get((ca, "newtonian"))
        if g is None or n is None or g[last] is None or n[last] is None:
            continue
        lines.append(f"| {ca:g} | {p_of(ca):g} | {g[last]:.3e} | {n[last]:.3e} | {g[last] - n[last]:+.3e} | "
                     f"{law * ca:.3e} |")
    lines.append("")
    with open(os.path.join(OUT, "giesekus_migration_stiff.md"), "w") as f:
        f.write("\n".join(lines))
    print("\n".join(lines))


if __name__ == "__main__":
    validation_main("validation_giesekus_migration_stiff", jobs, report)
