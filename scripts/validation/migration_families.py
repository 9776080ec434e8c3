#!/usr/bin/python3
"""The blockage-ratio and capillary-number families of the Newtonian migration
(thesis Fig. 3.9): v_p against y_p / y_p,max for Ca_e = 0.1 and
beta = 0.1, 0.2, 0.3, 0.4 (Fig. 3.9a), and for beta = 0.2 and
Ca_e = 0.05, 0.1, 0.15, 0.2, 0.3 (Fig. 3.9b). The thesis names four betas
and five Ca_e without listing them in its text; these are Fig. 3.10's
values extended to 0.4 and 0.3. Writes docs/validation/migration_families.{md,csv,png}.

Every (beta, Ca_e) starts at y_p0 / y_p,max = 0.25, 0.5, 0.75 in the cell of
scripts/validation/confined_migration.py (10 particle diameters long and
wide, H = 2R / beta, 20 equator nodes, graded to the interface and the
walls), dt = 0.04 to t = T_END with remeshing below quality 0.2, and the
default conformation settings in the particle (the step-limited SUPG
parameter and the consistent predicted stress, which the figures of
chapter 3 before [conformation]'s keys could not use). v_p is the slope of
y_p(t) over t = TRANSIENT ... T_END, placed at the mean height over that
window: the master curve sampled at three heights per configuration (the
thesis ran each start for thousands of time units). Each configuration's
starts are also combined by `softflow migration` (its master curve and its
near-centre slope against eq. 3.8).

Checked against the thesis: v_p < 0 in the whole upper half (every start
migrates towards the centre plane), |v_p| grows towards the wall, and at a
fixed y_p / y_p,max |v_p| grows with beta and with Ca_e. Beside it, eq. 3.8
(v_p / (gamma_dot H) = -2 beta^3 Ca_e y_p / y_p,max, the near-centre law) at
each point, to show where the cubic-in-beta, linear-in-Ca_e scaling holds.
Usage: scripts/validation/migration_families.py [build_dir] [work_dir] [--jobs N] [--report-only]"""
import os

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

from case_runs import summary_of, validation_main, write_csv  # noqa: E402
from migration_near_centre import eq_3_8, height, y_max  # noqa: E402
from migration_runs import combine, mean_velocity, read_migration, read_starts  # noqa: E402

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
OUT = os.path.join(ROOT, "docs", "validation")
BASE_BETA, BASE_CA_E = 0.2, 0.1
BETAS = [0.1, 0.2, 0.3, 0.4]  # at BASE_CA_E (Fig. 3.9a)
CA_ES = [0.05, 0.1, 0.15, 0.2, 0.3]  # at BASE_BETA (Fig. 3.9b)
STARTS = [0.5, 0.75, 0.25]  # y_p0 / y_p,max, in the order they run
# One start on the next mesh level (28 equator nodes asked, far size, wall
# size and growth by 20/28: the whole mesh refined, as
# migration_resolution.py's N28): how much of v_p is the mesh.
# delta_s_resolution.py refines a start on each side of Delta S's sign
# change. (beta, Ca_e, start, nodes)
FINER = [(0.4, 0.1, 0.5, 28)]
DT = 0.04
T_END = 6.0
TRANSIENT = 2.0


def configurations():
    """(beta, Ca_e) of both families, the shared one once."""
    return [(b, BASE_CA_E) for b in BETAS] + [(BASE_BETA, ca) for ca in CA_ES if ca != BASE_CA_E]


def case_name(beta, ca, start, nodes=20):
    return f"beta{beta:.2f}_ca{ca:.2f}_y{start:.2f}" + ("" if nodes == 20 else f"_N{nodes}")


def case_text(beta, ca, start, nodes=20):
    y0 = start * y_max(beta) * height(beta)
    scale = 20 / nodes
    return f"""[case]
name = "{case_name(beta, ca, start, nodes)}"
[cell]
length = 20.0
width = 20.0
blockage_ratio = {beta}
[flow]
shear_rate = 1.0
[[objects]]
model = "neo_hookean"
radius = 1.0
elastic_capillary_number = {ca}
centre = [0.0, {y0:.6f}, 0.0]
[mesh]
equator_nodes = {nodes}
far_size = {round(2.0 * scale, 6)}
growth = {round(0.4 * scale, 6)}
wall_size = {round(0.5 * scale, 6)}
gap_elements = 2
[time]
step = {DT}
end = {T_END}
[remesh]
quality = 0.2
[checkpoint]
interval_minutes = 10.0
[output]
fields = false
"""


def jobs():
    # One start of every configuration before the next start: the family's
    # ordering at one height is readable after the first round.
    return ([(case_name(b, ca, s), case_text(b, ca, s)) for s in STARTS for b, ca in configurations()] +
            [(case_name(*x), case_text(*x)) for x in FINER])


def read_point(work, beta, ca, s, nodes=20):
    """One start past the window's end, else None: the mean height, v_p and
    Delta S after the transient (the late rows' Delta S kept as `late_delta_s`)."""
    directory = os.path.join(work, case_name(beta, ca, s, nodes))
    if not os.path.exists(os.path.join(directory, "migration.csv")):
        return None
    r = read_migration(directory, height(beta))
    v = mean_velocity(r, TRANSIENT)
    if v is None or r["t"][-1] < T_END - 1e-9:
        return None  # not yet past the window
    late = [i for i, t in enumerate(r["t"]) if t >= TRANSIENT - 1e-9]
    y_rel = sum(r["y"][i] for i in late) / len(late) / y_max(beta)
    summary = summary_of(directory)
    gap = (height(beta) / 2 - y_rel * y_max(beta) * height(beta) - 1.0)  # to the near wall, in R
    late_delta_s = [r["dS"][i] for i in late]
    return {"beta": beta, "ca_e": ca, "y_p0_rel": s, "equator_nodes": nodes, "y_p_rel": y_rel,
            "wall_gap_over_R": gap, "v_p": v,
            "eq_3_8": eq_3_8(beta, ca, y_rel), "ratio": v / eq_3_8(beta, ca, y_rel),
            "delta_s": sum(late_delta_s) / len(late_delta_s), "late_delta_s": late_delta_s,
            "unknowns": summary.get("unknowns"), "wall_seconds": summary.get("wall_seconds"),
            "summary": summary, "series": r}


def read_points(work):
    """One row per start past the window's end (read_point)."""
    runs = [(b, ca, s, 20) for b, ca in configurations() for s in sorted(STARTS)] + FINER
    return [x for x in (read_point(work, *run) for run in runs) if x is not None]


def family_rows(rows, family):
    """The figure's rows (20 equator nodes) of the beta or the Ca_e family."""
    key = (lambda x: x["ca_e"] == BASE_CA_E) if family == "beta" else (lambda x: x["beta"] == BASE_BETA)
    return [x for x in rows if key(x) and x["equator_nodes"] == 20]


def ordering_lines(rows):
    """At each start height: is |v_p| increasing along each family (the thesis's claim)?"""
    lines = []
    for family, label, values in (("beta", "beta", BETAS), ("ca_e", "Ca_e", CA_ES)):
        for s in sorted(STARTS):
            at = {x[family]: x for x in family_rows(rows, family) if x["y_p0_rel"] == s}
            present = [v for v in values if v in at]
            if len(present) < 2:
                continue
            speeds = [-at[v]["v_p"] for v in present]
            grows = all(b > a for a, b in zip(speeds, speeds[1:]))
            lines.append(f"- y_p0 / y_p,max = {s:.2f}, {label} = " + ", ".join(f"{v:g}" for v in present) +
                         ": -v_p = " + ", ".join(f"{x:.3e}" for x in speeds) +
                         (f" (grows with {label})" if grows else f" (**not** monotonic in {label})"))
    return lines


def plot(rows, path):
    fig, axes = plt.subplots(2, 2, figsize=(13, 9.5))
    ax = axes.ravel()
    for panel, family, values, label in ((0, "beta", BETAS, "beta"), (1, "ca_e", CA_ES, "Ca_e")):
        for v in values:
            pts = sorted((x for x in family_rows(rows, family) if x[family] == v), key=lambda x: x["y_p_rel"])
            if not pts:
                continue
            beta, ca = pts[0]["beta"], pts[0]["ca_e"]
            line, = ax[panel].plot([x["y_p_rel"] for x in pts], [x["v_p"] for x in pts], "o-", label=f"{label} = {v:g}")
            for x in pts:
                r = x["series"]
                late = [i for i, t in enumerate(r["t"]) if t >= TRANSIENT]
                ax[panel].plot([r["y"][i] / y_max(beta) for i in late], [r["v"][i] for i in late], ".", ms=1,
                               color=line.get_color(), alpha=0.3)
            ax[panel].plot([0, 1], [0, eq_3_8(beta, ca, 1.0)], "--", lw=0.8, color=line.get_color())
            ax[2].plot([x["y_p_rel"] for x in pts], [x["v_p"] / (2 * beta ** 3 * ca) for x in pts],
                       "o-" if family == "beta" else "s:", color=line.get_color(),
                       label=f"beta = {beta:g}, Ca_e = {ca:g}")
        ax[panel].set(xlabel="y_p / y_p,max", ylabel="v_p / (gamma_dot H)", xlim=(0, 1))
    ax[0].set(title=f"Fig. 3.9a: Ca_e = {BASE_CA_E:g} (dashed: eq. 3.8)")
    ax[1].set(title=f"Fig. 3.9b: beta = {BASE_BETA:g} (dashed: eq. 3.8)")
    ax[2].plot([0, 1], [0, -1], "k--", lw=0.8, label="eq. 3.8")
    ax[2].set(xlabel="y_p / y_p,max", ylabel="v_p / (2 beta^3 Ca_e gamma_dot H)", xlim=(0, 1),
              title="scaled by eq. 3.8's factor")
    for x in rows:
        ax[3].plot(x["wall_gap_over_R"], x["delta_s"], "o" if x["equator_nodes"] == 20 else "k*",
                   color=plt.cm.viridis(x["beta"] / 0.45), ms=6 if x["equator_nodes"] == 20 else 10)
    for beta in BETAS:
        ax[3].plot([], [], "o", color=plt.cm.viridis(beta / 0.45), label=f"beta = {beta:g}")
    ax[3].plot([], [], "k*", label="28 equator nodes")
    ax[3].axhline(0, color="k", lw=0.6)
    ax[3].set(xlabel="wall gap (H/2 - y_p - R) / R", ylabel=f"Delta S, mean over t = {TRANSIENT:g}-{T_END:g}",
              title="surface imbalance against the gap to the wall (all starts)")
    for a in ax:
        a.grid(alpha=0.3)
        a.legend(fontsize=7)
    fig.suptitle(f"Newtonian migration of a neo-Hookean particle: v_p over t = {TRANSIENT:g}-{T_END:g} "
                 "(points at the window's mean height; dots: per step)")
    fig.tight_layout()
    fig.savefig(path, dpi=120)


def report(work, build):
    rows = read_points(work)
    if not rows:
        print("no runs to report")
        return
    os.makedirs(OUT, exist_ok=True)
    fields = ["beta", "ca_e", "y_p0_rel", "equator_nodes", "y_p_rel", "wall_gap_over_R", "v_p", "eq_3_8", "ratio",
              "delta_s",
              "unknowns", "wall_seconds"]
    write_csv(os.path.join(OUT, "migration_families.csv"), fields, [{k: x[k] for k in fields} for x in rows])
    plot(rows, os.path.join(OUT, "migration_families.png"))
    lines = ["# Migration families in a Newtonian matrix (thesis Fig. 3.9)", "",
             "Generated by `scripts/validation/migration_families.py`: a neo-Hookean particle (R = 1) between "
             "walls at y = +-H/2, H = 2R / beta, cell 20 x H x 20, 20 equator nodes, dt = 0.04, t = 0 ... "
             f"{T_END:g} with remeshing below quality 0.2, default conformation settings. v_p: slope of y_p(t) "
             f"over t = {TRANSIENT:g}-{T_END:g} in gamma_dot H (negative: towards the centre plane), at the "
             "window's mean height y_p / y_p,max (y_p,max = H/2 - R). eq. 3.8: -2 beta^3 Ca_e y_p / y_p,max.", "",
             "Delta S (eq. 3.6): its mean over the same window. Wall gap: from the particle's undeformed "
             "surface to the nearer wall at the mean height, H/2 - y_p - R, in R.", "",
             "| beta | Ca_e | y_p0 / y_p,max | equator nodes | y_p / y_p,max | wall gap / R | v_p | eq. 3.8 | "
             "v_p / eq. 3.8 | Delta S | unknowns | wall s |",
             "|---|---|---|---|---|---|---|---|---|---|---|---|"]
    for x in rows:
        lines.append(f"| {x['beta']:g} | {x['ca_e']:g} | {x['y_p0_rel']:.2f} | {x['equator_nodes']} | "
                     f"{x['y_p_rel']:.4f} | {x['wall_gap_over_R']:.2f} | {x['v_p']:.3e} | {x['eq_3_8']:.3e} | "
                     f"{x['ratio']:.3f} | "
                     f"{x['delta_s']:+.4f} | {x['unknowns'] or ''} | {x['wall_seconds'] or 0:.0f} |")
    lines += ["", "## The thesis's claims", "",
              f"- v_p < 0 at every start: {'yes' if all(x['v_p'] < 0 for x in rows) else '**no**'} "
              f"({len(rows)} starts).",
              f"- Delta S > 0 at every start (Fig. 3.8's sign): "
              f"{'yes' if all(x['delta_s'] > 0 for x in rows) else '**no**'}: "
              f"{sum(x['delta_s'] > 0 for x in rows)} of {len(rows)} positive; by the wall gap:"]
    for x in sorted(rows, key=lambda x: x["wall_gap_over_R"]):
        lines.append(f"  - gap {x['wall_gap_over_R']:.2f} R (beta = {x['beta']:g}, Ca_e = {x['ca_e']:g}, "
                     f"{x['equator_nodes']} nodes): Delta S {x['delta_s']:+.4f}")
    lines += ordering_lines(rows)
    lines += ["", "## Each configuration's starts combined by `softflow migration`", ""]
    for beta, ca in configurations():
        runs = read_starts(work, STARTS, lambda s, b=beta, c=ca: case_name(b, c, s), height(beta))
        finished = {s: run for s, run in runs.items() if run[1]["t"] and run[1]["t"][-1] >= T_END - 1e-9}
        if len(finished) < 2:
            continue
        lines += [f"### beta = {beta:g}, Ca_e = {ca:g}", ""]
        lines += combine(build, work, finished, TRANSIENT, name=f"combined_beta{beta:.2f}_ca{ca:.2f}")
        lines.append("")
    with open(os.path.join(OUT, "migration_families.md"), "w") as f:
        f.write("\n".join(lines) + "\n")
    print("\n".join(lines))


if __name__ == "__main__":
    validation_main("validation_migration_families", jobs, report)
