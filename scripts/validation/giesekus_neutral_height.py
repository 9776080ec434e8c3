#!/usr/bin/python3
"""Fig. 3.14 on the resolved setting: where does a neo-Hookean particle in the
Giesekus matrix of Figs. 3.12-3.13 stop migrating, as the particle stiffens?
p grows as 1 / Ca_e at the fixed matrix (lambda_m = 0.5, alpha_m = 0.2,
eta_s = 0.1, eta_p = 0.9, Wi = 0.5; beta = 0.2) as in
scripts/validation/giesekus_migration_stiff.py: Ca_e = 0.1, 0.05, 0.02
(zero-shear p = 4.5, 9, 22.5), each started at y_p0 = 0.10, 0.20, 0.28,
0.35 H, and Ca_e = 0.03 (p = 15, between the last p without a neutral
height and the first with one) from 0.10, 0.20, 0.28 H. Every run uses the setting that the mesh study of
scripts/validation/giesekus_migration_supg.py found resolved (20 equator
nodes with the step-limited SUPG parameter: within 5 % of the 28-node mesh
at p = 4.5, within 7e-5 gamma_dot H at p = 22.5, both at 0.20 H; at 0.10 H
the symmetric starts below find it unresolved), the consistent predicted
stress, dt = 0.04 to t = 6; v_p is the slope of y_p over t = 2-6. A
neutral height y_N lies between two adjacent starts whose v_p change sign;
its estimate is the linear interpolation of v_p between them, its error the
half-width of that bracket. The 0.20 H starts at p = 4.5 and 22.5 are the
runs of giesekus_migration_supg.py and giesekus_migration_stiff.py (the
same case), read from their csv tables.
Writes docs/validation/giesekus_neutral_height.{md,csv,png}.
Usage: scripts/validation/giesekus_neutral_height.py [build_dir] [work_dir] [--jobs N] [--report-only]"""
import os

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

from case_runs import read_csv, summary_of, validation_main, write_csv  # noqa: E402
from giesekus_migration import BETA, HEIGHT, Y_MAX  # noqa: E402
from giesekus_migration_stiff import p_of, run_name as stiff_run_name, text as stiff_text  # noqa: E402
from migration_runs import read_migration, window_velocities  # noqa: E402

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
OUT = os.path.join(ROOT, "docs", "validation")
CA_E = [0.1, 0.05, 0.03, 0.02]
STARTS = [0.10, 0.20, 0.28, 0.35]  # y_p0 / H
# p = 15 brackets where the neutral heights appear; every p has its 0.35 H
# start migrating down, so it is not repeated there.
STARTS_OF = {0.03: [0.10, 0.20, 0.28]}
SYMMETRIC_ONLY = [(0.03, 0.10)]  # p = 15 at 0.10 H: from the symmetric start only
WINDOW = (2.0, 6.0)
NODES, TAU = 20, "transient"
# The runs already made elsewhere with this exact case: (Ca_e, y_p0) -> (csv, its row's keys).
ELSEWHERE = {
    (0.1, 0.20): ("giesekus_migration_supg.csv", {"equator_nodes": "20", "supg_tau": TAU}),
    (0.02, 0.20): ("giesekus_migration_stiff.csv",
                   {"ca_e": "0.02", "matrix": "giesekus", "equator_nodes": "20", "supg_tau": TAU}),
}
# The order they run, two at a time: the stiffest particle's bracket first,
# then the thesis's p = 4.5 on both sides of its 0.20 H start.
ORDER = [(0.02, 0.10), (0.02, 0.28), (0.1, 0.10), (0.1, 0.28), (0.05, 0.20), (0.02, 0.35), (0.05, 0.10),
         (0.05, 0.28), (0.1, 0.35), (0.05, 0.35)]


# The p = 22.5 bracket on the next mesh level (28 equator nodes, the whole
# mesh refined by 20/28, the steady parameter, which agrees with the
# step-limited one there: giesekus_migration_supg.py); its 0.20 H start is
# giesekus_migration_stiff.py's N28 run (FINER_ELSEWHERE).
FINER = [(0.02, 0.10), (0.02, 0.28)]
FINER_NODES, FINER_TAU = 28, "steady"
# The 0.10 H starts again from the point-symmetric start (mesh.point_symmetric_start:
# gmsh's mesh drifts a centred particle by up to ~1e-4 gamma_dot H at these
# resolutions, docs/confinement.md, as large as v_p near the centre plane;
# from the symmetric start that drift vanishes with the offset). A carry to
# 0.20 H inverts an element on this mesh, so only the 0.10 H start has one.
# Queued after the finer runs, before p = 15 (Ca_e = 0.03) at 0.20 and 0.28 H.
SYMMETRIC = [(0.02, 0.10), (0.1, 0.10), (0.03, 0.10), (0.05, 0.10)]
# The symmetric 0.10 H starts at p = 22.5 and 4.5 on the next mesh level
# (FINER's mesh and parameter), queued after the first two 20-node ones.
SYMMETRIC_FINER = [(0.02, 0.10), (0.1, 0.10)]
LATER = [(0.03, 0.20), (0.03, 0.28)]
# The runs on that level made elsewhere with the same case, as ELSEWHERE.
FINER_ELSEWHERE = {
    (0.02, 0.20): ("giesekus_migration_stiff.csv",
                   {"ca_e": "0.02", "matrix": "giesekus", "equator_nodes": "28", "supg_tau": FINER_TAU}),
    (0.1, 0.20): ("giesekus_migration_supg.csv", {"equator_nodes": "28", "supg_tau": FINER_TAU}),
}


def run_name(ca, start, nodes=NODES, symmetric=False):
    return f"ca{ca:g}_yp0_{start:.2f}" + ("" if nodes == NODES else f"_N{nodes}") + ("_sym" if symmetric else "")


def text(ca, start, nodes=NODES, tau=TAU, symmetric=False):
    base = stiff_text(ca, "giesekus", nodes, tau)
    old_name = f'name = "{stiff_run_name(ca, "giesekus", nodes, tau)}"'
    old_centre = f"centre = [0.0, {0.20 * HEIGHT:.6f}, 0.0]"
    old_mesh_end = "gap_elements = 2\n"
    assert old_name in base and old_centre in base and base.count(old_mesh_end) == 1
    base = base.replace(old_name, f'name = "{run_name(ca, start, nodes, symmetric)}"').replace(
        old_centre, f"centre = [0.0, {start * HEIGHT:.6f}, 0.0]")
    if not symmetric:
        return base
    # Without remeshing, as Fig. 3.10's symmetric starts: a remesh gives the
    # symmetry up, and the carried mesh starts at quality 0.209, just above the
    # base case's remesh threshold (0.2), which it passed at t = 0.2-0.3.
    old_remesh = "[remesh]\nquality = 0.2\n"
    assert base.count(old_remesh) == 1
    return base.replace(old_mesh_end, old_mesh_end + "point_symmetric_start = true\n").replace(old_remesh, "")


def jobs():
    assert sorted(ORDER + LATER) == sorted((ca, s) for ca in CA_E for s in starts_of(ca)
                                           if (ca, s) not in ELSEWHERE and (ca, s) not in SYMMETRIC_ONLY)
    # (starts, nodes, SUPG parameter, symmetric start), in the order they run.
    groups = [(ORDER, NODES, TAU, False), (FINER, FINER_NODES, FINER_TAU, False), (SYMMETRIC[:2], NODES, TAU, True),
              (SYMMETRIC_FINER, FINER_NODES, FINER_TAU, True), (SYMMETRIC[2:], NODES, TAU, True),
              (LATER, NODES, TAU, False)]
    return [(run_name(ca, s, nodes, symmetric), text(ca, s, nodes, tau, symmetric))
            for starts, nodes, tau, symmetric in groups for ca, s in starts]


def starts_of(ca):
    return STARTS_OF.get(ca, STARTS)


def point_here(work, ca, start, nodes=NODES, symmetric=False):
    directory = os.path.join(work, run_name(ca, start, nodes, symmetric))
    if not os.path.exists(os.path.join(directory, "migration.csv")):
        return None
    r = read_migration(directory, HEIGHT)
    v, = window_velocities(r, [WINDOW])
    inside = [y for t, y in zip(r["t"], r["y"]) if WINDOW[0] <= t <= WINDOW[1]]
    s = summary_of(directory)
    return {"v_p": v, "y_mean": sum(inside) / len(inside) if v is not None else None, "t_last": r["t"][-1],
            "unknowns": s.get("unknowns"), "wall_seconds": s.get("wall_seconds"),
            "source": f"output/validation_giesekus_neutral_height/{run_name(ca, start, nodes, symmetric)}"}


def point_elsewhere(ca, start, elsewhere=ELSEWHERE):
    name, keys = elsewhere[(ca, start)]
    path = os.path.join(OUT, name)
    if not os.path.exists(path):
        return None
    column = f"mean_v_p_t{WINDOW[0]:g}_{WINDOW[1]:g}"
    row = next((r for r in read_csv(path) if all(r[k] == v for k, v in keys.items())), None)
    if row is None or not row.get(column):
        return None
    v = float(row[column])
    # The tables keep v_p, not the mean height: y_p moves linearly over the window.
    return {"v_p": v, "y_mean": start + v * sum(WINDOW) / 2.0, "t_last": float(row["t_last"]),
            "unknowns": row.get("unknowns"), "wall_seconds": float(row["wall_seconds"] or 0),
            "source": f"docs/validation/{name}"}


def neutral_heights(points):
    """(estimate, half-width, direction) for each adjacent pair of heights whose
    v_p change sign; direction "stable" when v_p goes from + below to - above."""
    found = []
    for a, b in zip(points, points[1:]):
        if a["v_p"] * b["v_p"] < 0.0:
            y = a["y_mean"] - a["v_p"] * (b["y_mean"] - a["y_mean"]) / (b["v_p"] - a["v_p"])
            found.append((y, (b["y_mean"] - a["y_mean"]) / 2.0, "stable" if a["v_p"] > 0.0 else "unstable"))
    return found


def height_rows(points):
    """(y_N, +-, kind) cells for each neutral height of `points` (sorted by
    height), or one "none" row naming where every start goes; nothing from a
    single start, which brackets nothing."""
    if len(points) < 2:
        return []
    found = neutral_heights(points)
    if found:
        return [(f"{y:.3f}", f"{half:.3f}", kind) for y, half, kind in found]
    return [("none", "", "towards the centre" if all(x["v_p"] < 0 for x in points) else "towards the wall")]


def finer_points(work, ca):
    """The 28-node gmsh points of p (Ca_e = ca), made here or elsewhere, by height: (start, point)."""
    found = [(s, point_elsewhere(c, s, FINER_ELSEWHERE) if (c, s) in FINER_ELSEWHERE
              else point_here(work, c, s, FINER_NODES)) for c, s in sorted(FINER + list(FINER_ELSEWHERE)) if c == ca]
    return [(s, x) for s, x in found if x is not None and x["v_p"] is not None]


def symmetric_lines(work, by_p):
    """The 0.10 H starts from the point-symmetric start beside gmsh's mesh on
    both mesh levels, and the neutral heights with them in place of gmsh's
    0.10 H points."""
    levels = {nodes: {ca: point_here(work, ca, s, nodes, symmetric=True) for ca, s in starts}
              for nodes, starts in ((NODES, SYMMETRIC), (FINER_NODES, SYMMETRIC_FINER))}
    levels = {nodes: {ca: x for ca, x in found.items() if x is not None and x["v_p"] is not None}
              for nodes, found in levels.items()}
    if not levels[NODES] and not levels[FINER_NODES]:
        return []
    def cell(x):
        return "" if x is None else f"{x['v_p']:.3e}"
    lines = ["", "The 0.10 H starts from the point-symmetric start (`mesh.point_symmetric_start`, no remeshing: the "
             "mesh's own drift across streamlines vanishes with the offset; otherwise the same case on each level; "
             f"{FINER_NODES} nodes with the {FINER_TAU} SUPG parameter, as above), v_p over t = "
             f"{WINDOW[0]:g}-{WINDOW[1]:g}:", "",
             f"| Ca_e | p | gmsh's mesh, {NODES} nodes | symmetric start, {NODES} nodes | gmsh's mesh, {FINER_NODES} "
             f"nodes | symmetric start, {FINER_NODES} nodes |", "|---|---|---|---|---|---|"]
    for ca in sorted(set(levels[NODES]) | set(levels[FINER_NODES]), reverse=True):
        plain = next((y for y in by_p.get(ca, []) if y["y_p0"] == 0.10), None)
        plain_finer = dict(finer_points(work, ca)).get(0.10)
        lines.append(f"| {ca:g} | {p_of(ca):g} | {cell(plain)} | {cell(levels[NODES].get(ca))} | "
                     f"{cell(plain_finer)} | {cell(levels[FINER_NODES].get(ca))} |")
    lines += ["", "Neutral heights with the symmetric 0.10 H start in place of gmsh's (the other starts on gmsh's "
              "mesh of the same level):", "", "| Ca_e | p | nodes | y_N / H | +- | kind |", "|---|---|---|---|---|---|"]
    others_of = {NODES: lambda ca: by_p.get(ca, []),
                 FINER_NODES: lambda ca: [{**x, "y_p0": s} for s, x in finer_points(work, ca)]}
    for nodes in (NODES, FINER_NODES):
        for ca, x in sorted(levels[nodes].items(), reverse=True):
            points = sorted([y for y in others_of[nodes](ca) if y["y_p0"] != 0.10] + [{**x, "y_p0": 0.10}],
                            key=lambda y: y["y_p0"])
            starts = ", ".join(f"{y['y_p0']:.2f}" for y in points)
            for y, half, kind in height_rows(points):
                kind = f"every start ({starts} H) {kind}" if y == "none" else kind
                lines.append(f"| {ca:g} | {p_of(ca):g} | {nodes} | {y} | {half} | {kind} |")
    return lines


def report(work):
    rows, by_p = [], {}
    for ca in CA_E:
        for s in starts_of(ca):
            x = point_elsewhere(ca, s) if (ca, s) in ELSEWHERE else point_here(work, ca, s)
            if x is None or x["v_p"] is None:
                continue
            law = -2.0 * BETA ** 3 * ca * x["y_mean"] / Y_MAX  # eq. 3.8 (Newtonian matrix)
            rows.append({"ca_e": ca, "p": p_of(ca), "y_p0": s, **x, "eq_3_8": law})
            by_p.setdefault(ca, []).append(rows[-1])
    write_csv(os.path.join(OUT, "giesekus_neutral_height.csv"),
              ["ca_e", "p", "y_p0", "y_mean", "v_p", "eq_3_8", "t_last", "unknowns", "wall_seconds", "source"], rows)
    a, b = WINDOW
    lines = ["# Neutral heights against p on the resolved setting (thesis Fig. 3.14)", "",
             "Generated by `scripts/validation/giesekus_neutral_height.py`: beta = 0.2, the Giesekus matrix of "
             "Figs. 3.12-3.13 (lambda_m = 0.5, alpha_m = 0.2, eta_s = 0.1, eta_p = 0.9, Wi = 0.5); Ca_e sets the "
             "particle's modulus, p = 4.5 x 0.1 / Ca_e (zero-shear Psi_1). 20 equator nodes, step-limited SUPG "
             "parameter, consistent predicted stress, dt = 0.04, t = 0-6. "
             f"v_p: slope of y_p over t = {a:g}-{b:g}, in gamma_dot H (negative: towards the centre plane); "
             "y_p: its mean over the same window, in H. eq. 3.8: the Newtonian near-centre law at that height.",
             "", "| Ca_e | p | y_p0 / H | mean y_p / H | v_p | eq. 3.8 | t reached | unknowns | wall s | run |",
             "|---|---|---|---|---|---|---|---|---|---|"]
    for x in rows:
        lines.append(f"| {x['ca_e']:g} | {x['p']:g} | {x['y_p0']:.2f} | {x['y_mean']:.4f} | {x['v_p']:.3e} | "
                     f"{x['eq_3_8']:.3e} | {x['t_last']:g} | {x['unknowns'] or ''} | {x['wall_seconds'] or 0:.0f} | "
                     f"`{x['source']}` |")
    lines += ["", "Neutral heights (sign changes of v_p between adjacent starts; estimate by linear interpolation, "
              "error the half-width of the bracket). The thesis's Fig. 3.14 at Ca_e = 0.1: y_N = 0.26 H at "
              "p = 4.5, rising with p until the walls attract every start beyond p ~ 10.", "",
              "| Ca_e | p | starts measured | y_N / H | +- | kind |", "|---|---|---|---|---|---|"]
    for ca in CA_E:
        points = by_p.get(ca, [])
        starts = ", ".join(f"{x['y_p0']:.2f}" for x in points)
        for y, half, kind in height_rows(points):
            kind = f"every start {kind}" if y == "none" else kind
            lines.append(f"| {ca:g} | {p_of(ca):g} | {starts} | {y} | {half} | {kind} |")
    finer = finer_points(work, FINER[0][0])
    if finer:
        lines += ["", f"p = 22.5 on the next mesh level ({FINER_NODES} equator nodes asked, the whole mesh refined by "
                  f"20/{FINER_NODES}, {FINER_TAU} SUPG parameter):", "",
                  "| y_p0 / H | mean y_p / H | v_p | t reached | run |", "|---|---|---|---|---|"]
        lines += [f"| {s:.2f} | {x['y_mean']:.4f} | {x['v_p']:.3e} | {x['t_last']:g} | `{x['source']}` |"
                  for s, x in finer]
        for y, half, kind in neutral_heights([x for _, x in finer]):
            lines.append(f"\n- {kind} neutral height {y:.3f} +- {half:.3f} H")
    lines += symmetric_lines(work, by_p)
    lines.append("")
    with open(os.path.join(OUT, "giesekus_neutral_height.md"), "w") as f:
        f.write("\n".join(lines))
    print("\n".join(lines))
    fig, ax = plt.subplots(figsize=(6.4, 4.4))
    for ca in CA_E:
        points = by_p.get(ca, [])
        if points:
            ax.plot([x["y_mean"] for x in points], [x["v_p"] for x in points], "o-", label=f"p = {p_of(ca):g}")
    ax.axhline(0.0, color="k", lw=0.6)
    ax.axvspan(Y_MAX, 0.5, color="0.85")
    ax.set(xlim=(0, 0.5), xlabel="y_p / H", ylabel="v_p / (gamma_dot H)",
           title="Giesekus matrix, beta = 0.2 (20 nodes, step-limited SUPG)")
    ax.grid(alpha=0.3)
    ax.legend()
    fig.tight_layout()
    fig.savefig(os.path.join(OUT, "giesekus_neutral_height.png"), dpi=120)


if __name__ == "__main__":
    validation_main("validation_giesekus_neutral_height", jobs, report)
