#!/usr/bin/python3
"""Validation of a viscoelastic (UCM) drop in a Newtonian matrix under unbounded
shear (thesis §2.5.2, Fig. 2.12): runs the cases below with the softflow binary
(two at a time), then writes docs/validation/ucm_drop.{md,csv,png}.

Unit drop, viscosity ratio lambda = eta_d / eta_m = 2 (UCM: eta_d = eta_p = G
lambda_d), drop elasticity p_d = Psi_1d Gamma / (2 R eta_d^2) = 0.5, so that
lambda_d = p_d R eta_d / Gamma = p_d lambda Ca / gamma_dot = Ca / gamma_dot,
Ca = eta_m gamma_dot R / Gamma = 0.05 ... 0.2. Each UCM run has a
Newtonian twin (same mesh, lambda = 2): theta's shift between them is compared
with Greco's (eq. 2.60) at the same Ca, where mesh errors largely cancel.
Box 30 x 30 x 30, 28 equator nodes; dt = lambda_d / 5 (the relaxation time
is the shortest time scale), to t = 6.

Finished cases (a summary.json in their directory) are not rerun.
Usage: scripts/validation/ucm_drop.py [build_dir] [work_dir] [--jobs N] [--report-only]"""
import csv
import math
import os

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

from case_runs import EULER_PREDICTION, read_run, richardson, validation_main  # noqa: E402
from oldroyd_b_matrix import greco_shift  # noqa: E402

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
OUT = os.path.join(ROOT, "docs", "validation")
LAMBDA = 2.0
P_D = 0.5
T_END = 6.0
CAS = [0.05, 0.1, 0.2]


def relaxation_time(ca, p_d=P_D):
    # p_d = Psi_1d Gamma / (2 R eta_d^2), Psi_1d = 2 eta_d lambda_d (UCM):
    # lambda_d = p_d R eta_d / Gamma = p_d Ca lambda / gamma_dot (eta_m = R = gamma_dot = 1).
    return p_d * ca * LAMBDA


def dt_for(ca, per_relaxation=5, p_d=P_D):
    return relaxation_time(ca, p_d) / per_relaxation


# Drop elasticity at Ca = 0.1: Greco's shift is linear in p_d.
P_D_STUDY = [0.25, 1.0]


# Fixed drop Deborah number lambda_d gamma_dot (= Ca p_d lambda): Greco's shift
# is proportional to Ca p_d, i.e. the same at every Ca on one of these lines;
# (Ca, p_d) pairs, the Ca -> 0 end is where the second-order theory holds.
FIXED_DEBORAH = {0.05: [(0.0125, 2.0), (0.025, 1.0), (0.05, 0.5), (0.1, 0.25)],
                 0.1: [(0.025, 2.0), (0.05, 1.0), (0.1, 0.5)]}


def pair_name(ca, p_d, ucm):
    tag = "" if p_d == P_D else f"_pd{p_d:g}"
    return f"{'ucm' if ucm else 'newtonian'}_Ca{ca:g}{tag}"


# Small drop Deborah numbers at Ca = 0.025: the slope of the shift in De_d,
# which Greco's theory gives exactly. (name, drop model lines, dt, end, twin).
# The twin is the Newtonian drop at the same dt.
SMALL_CA = 0.025


def ucm_lines(relaxation):
    return f'model = "ucm"\npolymer_viscosity = {LAMBDA}\nrelaxation_time = {relaxation:g}\n'


def small_deborah_runs():
    """(De_d, UCM run, twin run) at Ca = 0.025; runs as (name, drop lines, dt, end)."""
    twin = {dt: (f"newtonian_Ca0.025_dt{dt:g}", f"viscosity_ratio = {LAMBDA}\n", dt, 6.0 if dt > 0.005 else 3.0)
            for dt in (0.005, 0.01)}
    twin[0.02] = (pair_name(SMALL_CA, 2.0, False), f"viscosity_ratio = {LAMBDA}\n", 0.02, 6.0)
    out = [(0.005, ("ucm_Ca0.025_l0.005_dt0.005", ucm_lines(0.005), 0.005, 3.0), twin[0.005])]
    out += [(de, (f"ucm_Ca0.025_l{de:g}_dt0.01", ucm_lines(de), 0.01, 6.0), twin[0.01]) for de in (0.01, 0.02, 0.03)]
    # The fixed-Deborah runs above at Ca = 0.025 (dt = lambda_d / 5), one at dt = lambda_d / 10.
    out.append((0.05, (pair_name(SMALL_CA, 1.0, True), ucm_lines(0.05), 0.01, 6.0),
                (pair_name(SMALL_CA, 1.0, False), f"viscosity_ratio = {LAMBDA}\n", 0.01, 6.0)))
    out.append((0.1, ("ucm_Ca0.025_pd2_dt0.01", ucm_lines(0.1), 0.01, 6.0), twin[0.01]))
    out.append((0.2, ("ucm_Ca0.025_l0.2_dt0.02", ucm_lines(0.2), 0.02, 6.0), twin[0.02]))
    return out


def small_deborah_checks():
    """(label, De_d, run, twin, equator nodes, far size): resolution and an Oldroyd-B drop at Ca = 0.025."""
    twin28 = (pair_name(SMALL_CA, 2.0, False), f"viscosity_ratio = {LAMBDA}\n", 0.02, 6.0)
    ob = 'model = "oldroyd_b"\nsolvent_viscosity = 1.0\npolymer_viscosity = 1.0\nrelaxation_time = {:g}\n'
    return [
        ("UCM, 28 nodes, dt = 0.02", 0.1, (pair_name(SMALL_CA, 2.0, True), ucm_lines(0.1), 0.02, 6.0), twin28, 28, 4.0),
        ("UCM, 28 nodes, dt = 0.01", 0.1, ("ucm_Ca0.025_pd2_dt0.01", ucm_lines(0.1), 0.01, 6.0),
         ("newtonian_Ca0.025_dt0.01", f"viscosity_ratio = {LAMBDA}\n", 0.01, 6.0), 28, 4.0),
        ("UCM, 40 nodes, dt = 0.02", 0.1, ("ucm_Ca0.025_pd2_N40", ucm_lines(0.1), 0.02, 6.0),
         ("newtonian_Ca0.025_pd2_N40", f"viscosity_ratio = {LAMBDA}\n", 0.02, 6.0), 40, 2.8),
        # Oldroyd-B drop, eta_s = eta_p = 1 (eta_d = 2): Psi_1 = 2 eta_p lambda_d, Greco's shift
        # is that of the UCM drop with the same Psi_1, i.e. De_d(UCM) = lambda_d / 2.
        ("Oldroyd-B (eta_s = eta_p = 1), lambda_d = 0.1", 0.05, ("ob_Ca0.025_es1_ep1_l0.1", ob.format(0.1), 0.02, 6.0),
         twin28, 28, 4.0),
        ("Oldroyd-B (eta_s = eta_p = 1), lambda_d = 0.2", 0.1, ("ob_Ca0.025_es1_ep1_l0.2", ob.format(0.2), 0.02, 6.0),
         twin28, 28, 4.0),
    ]


def general_case_text(name, drop, dt, end, equator=28, far=4.0, growth=None, interior_growth=None):
    sizing = "".join(f"{key} = {value}\n" for key, value in (("growth", growth), ("interior_growth", interior_growth))
                     if value is not None)
    return f"""[case]
name = "{name}"
[[objects]]
{drop}capillary_number = {SMALL_CA}
[mesh]
equator_nodes = {equator}
far_size = {far}
{sizing}[time]
step = {dt}
end = {end}
[checkpoint]
interval_minutes = 0
[output]
fields = false
""" + EULER_PREDICTION


def completed_pair(work, run, twin):
    """A run and its twin, each (name, drop lines, dt, end, ...), read with steady values over the
    last 10 % of their time; (None, None) unless both completed."""
    u = read_run(os.path.join(work, run[0]), 0.1 * run[3])
    w = read_run(os.path.join(work, twin[0]), 0.1 * twin[3])
    return (u, w) if u and w and u["status"] == "completed" and w["status"] == "completed" else (None, None)


# The drop's interior filled at the interface size (mesh.interior_growth = 0):
# with the default growth the 28-node sphere has one vertex inside, so the
# drop's conformation (P1) is a star of elements around a hub.
# (name, drop lines, dt, end, equator, far, growth) per run.
def interior_runs():
    """(De_d, UCM run, twin run) at Ca = 0.025, 28 equator nodes, interior_growth = 0, dt = 0.01."""
    twin = ("newtonian_Ca0.025_dt0.01_ig0", f"viscosity_ratio = {LAMBDA}\n", 0.01, 6.0, 28, 4.0, None)
    return [(de, (f"ucm_Ca0.025_l{de:g}_dt0.01_ig0", ucm_lines(de), 0.01, 6.0, 28, 4.0, None), twin)
            for de in (0.01, 0.02, 0.05, 0.1)]


# The whole mesh refined by one ratio (equator nodes, far size and growth), the
# interior at the interface size: De_d = 0.1, Ca = 0.025, dt = 0.02.
INTERIOR_LEVELS = [(20, 5.6, 0.56), (28, 4.0, 0.4), (40, 2.8, 0.28)]


def interior_level_runs():
    out = []
    for n, far, growth in INTERIOR_LEVELS:
        out.append((n, (f"ucm_Ca0.025_l0.1_N{n}_ig0", ucm_lines(0.1), 0.02, 6.0, n, far, growth),
                    (f"newtonian_Ca0.025_N{n}_ig0", f"viscosity_ratio = {LAMBDA}\n", 0.02, 6.0, n, far, growth)))
    return out


def interior_case_text(run):
    name, drop, dt, end, equator, far, growth = run
    return general_case_text(name, drop, dt, end, equator, far, growth, interior_growth=0)


def interior_report(work, md):
    """Appends the interior-resolution tables to md."""
    def vertices_inside(run):
        return run["summary"]["mesh"].get("object_interior_vertices", "")

    md += ["", "## The drop's interior resolved (mesh.interior_growth = 0)", "",
           "With the default growth the 28-node drop has a single mesh vertex inside it: its P1 "
           "conformation is a star of elements around one hub. Filling the interior at the interface "
           "size (interior_growth = 0; the interface and the matrix mesh are unchanged) gives it 12. "
           "Ca = 0.025, 28 equator nodes, dt = 0.01, each UCM run beside its twin on the same mesh; "
           "the first column repeats the default mesh's shift (table above).", "",
           "| De_d | shift, default interior [deg] | D (UCM) | D (Newt.) | shift, interior filled [deg] | "
           "Greco shift [deg] | shift / Greco | vertices inside |", "|---|---|---|---|---|---|---|---|"]
    default = {de: (run, twin) for de, run, twin in small_deborah_runs()}
    points = []
    for de, run, twin in interior_runs():
        u, w = completed_pair(work, run, twin)
        g = greco_shift(LAMBDA, SMALL_CA, 0, de / (SMALL_CA * LAMBDA))
        old = ""
        if de in default:
            du, dw = completed_pair(work, *default[de])
            if du is not None:
                old = f"{du['theta_steady'] - dw['theta_steady']:+.4f}"
        if u is None:
            md.append(f"| {de:g} | {old} | | | | {g:+.4f} | not run | |")
            continue
        shift = u["theta_steady"] - w["theta_steady"]
        points.append((de, shift))
        md.append(f"| {de:g} | {old} | {u['D_steady']:.5f} | {w['D_steady']:.5f} | {shift:+.4f} | {g:+.4f} | "
                  f"{shift / g:.2f} | {vertices_inside(u)} |")
    if len(points) >= 2:
        slopes = [f"{(b[1] - a[1]) / (b[0] - a[0]):+.2f} ({a[0]:g}-{b[0]:g})" for a, b in zip(points, points[1:])]
        md += ["", "Slopes between successive De_d [deg per unit De_d]: " + ", ".join(slopes) + "; Greco "
               f"{greco_shift(LAMBDA, SMALL_CA, 0, 1.0 / (SMALL_CA * LAMBDA)):+.2f}."]
    md += ["", "The whole mesh refined by one ratio (equator nodes, far size, growth; interior at the "
           "interface size), De_d = 0.1, Ca = 0.025, dt = 0.02:", "",
           "| equator nodes (asked / meshed) | unknowns | vertices inside | D (UCM) | D (Newt.) | shift [deg] | "
           "Greco shift [deg] | shift / Greco | wall UCM / Newt. [s] |", "|---|---|---|---|---|---|---|---|---|"]
    levels = []
    g = greco_shift(LAMBDA, SMALL_CA, 0, 0.1 / (SMALL_CA * LAMBDA))
    for n, run, twin in interior_level_runs():
        u, w = completed_pair(work, run, twin)
        if u is None:
            md.append(f"| {n} | | | | | | {g:+.4f} | not run | |")
            continue
        shift = u["theta_steady"] - w["theta_steady"]
        meshed = u["summary"]["mesh"]["equator_nodes"]
        levels.append((meshed, shift, u["D_steady"], w["D_steady"]))
        md.append(f"| {n} / {meshed} | {u['unknowns']} | {vertices_inside(u)} | {u['D_steady']:.5f} | "
                  f"{w['D_steady']:.5f} | {shift:+.4f} | {g:+.4f} | {shift / g:.2f} | {u['wall']:.0f} / {w['wall']:.0f} |")
    if len(levels) == 3:
        (n0, s0, *_), (n1, s1, *_), (n2, s2, *_) = levels
        # h = 1 / (meshed equator nodes); the differences must shrink.
        fit = richardson([1.0 / n0, 1.0 / n1, 1.0 / n2], [s0, s1, s2], (0.1, 10.0))
        if fit and abs(s2 - s1) < abs(s1 - s0):
            p, limit = fit
            md += ["", f"Observed order of the shift {p:.2f}; Richardson-extrapolated shift {limit:+.4f} deg = "
                   f"{limit / g:.2f} of Greco's."]
        else:
            md += ["", "The shifts do not converge monotonically over these levels: no order or extrapolation."]
    return points


def small_deborah_report(work, md):
    """Appends the small-De_d tables to md; returns the points for the plot."""
    md += ["", "## Small drop Deborah numbers at Ca = 0.025: the slope of the shift", "",
           "UCM drops at Ca = 0.025 (28 equator nodes), De_d = lambda_d gamma_dot from 0.005 to 0.2, "
           "each beside a Newtonian twin at the same dt. Greco's shift (eq. 2.60 as printed) is "
           f"{greco_shift(LAMBDA, SMALL_CA, 0, 1.0 / (SMALL_CA * LAMBDA)):.3f} deg per unit De_d at lambda = 2.", "",
           "| De_d | dt | t_end | D (UCM) | D (Newt.) | shift [deg] | Greco shift [deg] | shift / Greco |",
           "|---|---|---|---|---|---|---|---|"]
    points = []
    for de, run, twin in small_deborah_runs():
        u, w = completed_pair(work, run, twin)
        g = greco_shift(LAMBDA, SMALL_CA, 0, de / (SMALL_CA * LAMBDA))
        if u is None:
            md.append(f"| {de:g} | {run[2]:g} | {run[3]:g} | | | | {g:+.4f} | not run |")
            continue
        shift = u["theta_steady"] - w["theta_steady"]
        points.append((de, shift, u["D_steady"] / w["D_steady"] - 1.0))
        md.append(f"| {de:g} | {run[2]:g} | {run[3]:g} | {u['D_steady']:.5f} | {w['D_steady']:.5f} | "
                  f"{shift:+.4f} | {g:+.4f} | {shift / g:.2f} |")
    fit = None
    small = [(de, sh) for de, sh, _ in points if de <= 0.05]
    if len(small) >= 3:
        n = len(small)
        mx, my = sum(d for d, _ in small) / n, sum(sh for _, sh in small) / n
        slope = sum((d - mx) * (sh - my) for d, sh in small) / sum((d - mx) ** 2 for d, _ in small)
        fit = (my - slope * mx, slope)
        greco_slope = greco_shift(LAMBDA, SMALL_CA, 0, 1.0 / (SMALL_CA * LAMBDA))
        md += ["", f"Least-squares line through De_d <= 0.05: shift = {fit[0]:+.4f} {fit[1]:+.3f} De_d [deg]: "
               f"the slope is {fit[1] / greco_slope:.2f} of Greco's ({greco_slope:.3f}); the intercept is the "
               "shift the discretisation leaves at De_d -> 0, where the UCM drop is a Newtonian drop "
               "whose viscous stress comes through the P1 conformation."]
    md += ["", "Resolution at De_d = 0.1 and an Oldroyd-B drop (Ca = 0.025, twin at the same dt and mesh):", "",
           "| run | De_d (Greco) | D (run) | D (Newt.) | shift [deg] | Greco shift [deg] | shift / Greco |",
           "|---|---|---|---|---|---|---|"]
    for label, de, run, twin, _, _ in small_deborah_checks():
        u, w = completed_pair(work, run, twin)
        g = greco_shift(LAMBDA, SMALL_CA, 0, de / (SMALL_CA * LAMBDA))
        if u is None:
            md.append(f"| {label} | {de:g} | | | | {g:+.4f} | not run |")
            continue
        shift = u["theta_steady"] - w["theta_steady"]
        md.append(f"| {label} | {de:g} | {u['D_steady']:.5f} | {w['D_steady']:.5f} | {shift:+.4f} | "
                  f"{g:+.4f} | {shift / g:.2f} |")
    return points, fit


# Resolution study at Ca = 0.1: (equator nodes, far size, steps per relaxation time).
RESOLUTION = [(28, 4.0, 10), (40, 2.8, 5)]


def case_text(name, ca, ucm, equator=28, far=4.0, per_relaxation=5, p_d=P_D):
    drop = (f'model = "ucm"\npolymer_viscosity = {LAMBDA}\nrelaxation_time = {relaxation_time(ca, p_d):.10g}\n'
            if ucm else f"viscosity_ratio = {LAMBDA}\n")
    return f"""[case]
name = "{name}"
[[objects]]
{drop}capillary_number = {ca}
[mesh]
equator_nodes = {equator}
far_size = {far}
[time]
step = {dt_for(ca, per_relaxation, p_d):.10g}
end = {T_END}
[checkpoint]
interval_minutes = 0
[output]
fields = false
""" + EULER_PREDICTION


def name_of(ca, ucm, equator=28, per_relaxation=5):
    suffix = "" if (equator, per_relaxation) == (28, 5) else f"_N{equator}_dtl{per_relaxation}"
    return f"{'ucm' if ucm else 'newtonian'}_Ca{ca:g}{suffix}"


def load(directory):
    # Steady values: means over the last 10 % of the run.
    return read_run(directory, 0.1 * T_END)


def taylor(lam, ca):
    return (19 * lam + 16) / (16 * lam + 16) * ca


def chaffey_brenner(lam, ca):
    return math.degrees(math.pi / 4 - (19 * lam + 16) * (2 * lam + 3) / (80 * (1 + lam)) * ca)


def report(work):
    os.makedirs(OUT, exist_ok=True)
    md = ["# UCM drop in a Newtonian matrix under shear (thesis §2.5.2, Fig. 2.12)", "",
          f"lambda = eta_d / eta_m = {LAMBDA:g}, p_d = {P_D:g} (relaxation time lambda_d = Ca here), "
          "box 30 x 30 x 30, 28 equator nodes, dt = lambda_d / 5, to t = 6. Steady values: means "
          "over the last 10 % of each run. The Newtonian twin has the same mesh and viscosity ratio. "
          "Generated by `scripts/validation/ucm_drop.py`.", "",
          "| Ca | dt | D (UCM) | D (Newtonian) | Taylor D | theta UCM [deg] | theta Newt. [deg] | "
          "shift [deg] | Greco shift [deg] | Greco theta [deg] | unknowns | wall time UCM / Newt. [s] | status |",
          "|---|---|---|---|---|---|---|---|---|---|---|---|---|"]
    rows, shifts = [], []
    for ca in CAS:
        u = load(os.path.join(work, name_of(ca, True)))
        n = load(os.path.join(work, name_of(ca, False)))
        g = greco_shift(LAMBDA, ca, 0.0, P_D)
        if u is None or n is None:
            md.append(f"| {ca:g} | {dt_for(ca):g} | | | {taylor(LAMBDA, ca):.4f} | | | | {g:+.3f} | "
                      f"{chaffey_brenner(LAMBDA, ca) + g:.2f} | | | not run |")
            continue
        shift = u["theta_steady"] - n["theta_steady"]
        shifts.append((ca, shift, g, u, n))
        md.append(f"| {ca:g} | {dt_for(ca):g} | {u['D_steady']:.4f} | {n['D_steady']:.4f} | "
                  f"{taylor(LAMBDA, ca):.4f} | {u['theta_steady']:.3f} | {n['theta_steady']:.3f} | "
                  f"{shift:+.3f} | {g:+.3f} | {chaffey_brenner(LAMBDA, ca) + g:.2f} | {u['unknowns']} | "
                  f"{u['wall']:.0f} / {n['wall']:.0f} | {u['status']} / {n['status']} |")
        rows.append([ca, dt_for(ca), u["D_steady"], n["D_steady"], taylor(LAMBDA, ca), u["theta_steady"],
                     n["theta_steady"], shift, g, u["wall"], n["wall"]])
    md += ["", "## Resolution at Ca = 0.1 (UCM and Newtonian twin on each mesh and step)", "",
           "| equator nodes | far size | dt | D (UCM) | D (Newt.) | theta UCM [deg] | theta Newt. [deg] | shift [deg] | "
           "Greco shift [deg] | unknowns | wall time UCM / Newt. [s] |", "|---|---|---|---|---|---|---|---|---|---|---|"]
    for n, far, k in [(28, 4.0, 5)] + RESOLUTION:
        u = load(os.path.join(work, name_of(0.1, True, n, k)))
        w = load(os.path.join(work, name_of(0.1, False, n, k)))
        if u is None or w is None:
            md.append(f"| {n} | {far:g} | {dt_for(0.1, k):g} | | | | | | {greco_shift(LAMBDA, 0.1, 0, P_D):+.3f} | | not run |")
            continue
        md.append(f"| {n} | {far:g} | {dt_for(0.1, k):g} | {u['D_steady']:.5f} | {w['D_steady']:.5f} | "
                  f"{u['theta_steady']:.3f} | {w['theta_steady']:.3f} | {u['theta_steady'] - w['theta_steady']:+.3f} | "
                  f"{greco_shift(LAMBDA, 0.1, 0, P_D):+.3f} | {u['unknowns']} | {u['wall']:.0f} / {w['wall']:.0f} |")
    md += ["", "## Drop elasticity at Ca = 0.1 (28 equator nodes, dt = lambda_d / 5; Greco's shift is linear in p_d)", "",
           "| p_d | lambda_d | D (UCM) | D (Newt.) | theta UCM [deg] | theta Newt. [deg] | shift [deg] | Greco shift [deg] |",
           "|---|---|---|---|---|---|---|---|"]
    for p_d in sorted(P_D_STUDY + [P_D]):
        tag = "" if p_d == P_D else f"_pd{p_d:g}"
        u = load(os.path.join(work, f"ucm_Ca0.1{tag}"))
        w = load(os.path.join(work, f"newtonian_Ca0.1{tag}"))
        g = greco_shift(LAMBDA, 0.1, 0, p_d)
        if u is None or w is None:
            md.append(f"| {p_d:g} | {relaxation_time(0.1, p_d):g} | | | | | | {g:+.3f} |")
            continue
        md.append(f"| {p_d:g} | {relaxation_time(0.1, p_d):g} | {u['D_steady']:.5f} | {w['D_steady']:.5f} | "
                  f"{u['theta_steady']:.3f} | {w['theta_steady']:.3f} | {u['theta_steady'] - w['theta_steady']:+.3f} | {g:+.3f} |")
    md += ["", "## Fixed drop Deborah number: the Ca -> 0 limit of the shift (28 equator nodes, dt = lambda_d / 5)", "",
           "Greco's shift depends on Ca and p_d only through the drop's Deborah number "
           "De_d = lambda_d gamma_dot = Ca p_d lambda, so along each line below it is constant; the "
           "theory is the first term of an expansion in Ca, so the runs should approach it as Ca -> 0. "
           "The last column extrapolates the shift linearly in Ca to Ca = 0 from the two smallest Ca.", "",
           "| De_d | Ca | p_d | D (UCM) | D (Newt.) | shift [deg] | Greco shift [deg] | extrapolated to Ca = 0 [deg] |",
           "|---|---|---|---|---|---|---|---|"]
    deborah_lines = {}
    for de, pairs in FIXED_DEBORAH.items():
        points = []
        for ca, p_d in pairs:
            u = load(os.path.join(work, pair_name(ca, p_d, True)))
            w = load(os.path.join(work, pair_name(ca, p_d, False)))
            g = greco_shift(LAMBDA, ca, 0, p_d)
            if u is None or w is None:
                md.append(f"| {de:g} | {ca:g} | {p_d:g} | | | | {g:+.3f} | |")
                continue
            points.append((ca, u["theta_steady"] - w["theta_steady"], g, u, w))
        deborah_lines[de] = points
        for i, (ca, shift, g, u, w) in enumerate(points):
            extrapolated = ""
            if i == 0 and len(points) >= 2:
                (c0, s0), (c1, s1) = (points[0][0], points[0][1]), (points[1][0], points[1][1])
                extrapolated = f"{s0 - c0 * (s1 - s0) / (c1 - c0):+.3f}"
            md.append(f"| {de:g} | {ca:g} | {pairs[[c for c, _ in pairs].index(ca)][1]:g} | {u['D_steady']:.5f} | "
                      f"{w['D_steady']:.5f} | {shift:+.3f} | {g:+.3f} | {extrapolated} |")
    small_points, small_fit = small_deborah_report(work, md)
    interior_points = interior_report(work, md)
    with open(os.path.join(OUT, "ucm_drop.csv"), "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(["Ca", "dt", "D_ucm", "D_newtonian", "D_taylor", "theta_ucm_deg", "theta_newtonian_deg",
                    "shift_deg", "greco_shift_deg", "wall_ucm_s", "wall_newtonian_s"])
        w.writerows(rows)
    fig, axes = plt.subplots(1, 6, figsize=(27, 4.2))
    for ca, shift, g, u, n in shifts:
        axes[0].plot(u["t"], u["D"], label=f"UCM Ca = {ca:g}")
        axes[0].plot(n["t"], n["D"], ":", color=axes[0].lines[-1].get_color())
        axes[1].plot(u["t"][1:], u["theta"][1:], label=f"UCM Ca = {ca:g}")
        axes[1].plot(n["t"][1:], n["theta"][1:], ":", color=axes[1].lines[-1].get_color())
    axes[0].set(xlabel="t", ylabel="D", title="D(t): UCM (solid), Newtonian (dotted)")
    axes[1].set(xlabel="t", ylabel="theta [deg]", title="theta(t)")
    grid = [0.25 * i / 50 for i in range(1, 51)]
    axes[2].plot([s[0] for s in shifts], [s[3]["D_steady"] for s in shifts], "o", label="UCM drop")
    axes[2].plot([s[0] for s in shifts], [s[4]["D_steady"] for s in shifts], "s", mfc="none", label="Newtonian drop")
    axes[2].plot(grid, [taylor(LAMBDA, c) for c in grid], "--", color="gray", label="Taylor")
    axes[2].set(xlabel="Ca", ylabel="steady D", title="D vs Ca (Fig. 2.12a)")
    axes[3].plot([s[0] for s in shifts], [s[3]["theta_steady"] for s in shifts], "o", label="UCM drop")
    axes[3].plot([s[0] for s in shifts], [s[4]["theta_steady"] for s in shifts], "s", mfc="none", label="Newtonian drop")
    axes[3].plot(grid, [chaffey_brenner(LAMBDA, c) for c in grid], "--", color="gray", label="Chaffey-Brenner")
    axes[3].plot(grid, [chaffey_brenner(LAMBDA, c) + greco_shift(LAMBDA, c, 0, P_D) for c in grid], "-.",
                 color="k", label="Greco, p_d = 0.5")
    axes[3].set(xlabel="Ca", ylabel="steady theta [deg]", title="theta vs Ca (Fig. 2.12b)")
    for de, points in deborah_lines.items():
        if not points:
            continue
        line, = axes[4].plot([p[0] for p in points], [p[1] for p in points], "o-", label=f"softflow, De_d = {de:g}")
        axes[4].axhline(points[0][2], ls="--", color=line.get_color(), label=f"Greco, De_d = {de:g}")
    axes[4].axhline(0.0, color="gray", lw=0.5)
    axes[4].set(xlabel="Ca", ylabel="theta shift UCM - Newtonian [deg]", xlim=(0, None),
                title="shift at fixed drop Deborah number")
    if small_points:
        de = [p[0] for p in small_points]
        axes[5].plot(de, [p[1] for p in small_points], "o", label="softflow, Ca = 0.025")
        top = max(de) * 1.05
        slope = greco_shift(LAMBDA, SMALL_CA, 0, 1.0 / (SMALL_CA * LAMBDA))
        axes[5].plot([0, top], [0, slope * top], "--", color="k", label="Greco (eq. 2.60)")
        if interior_points:
            axes[5].plot([p[0] for p in interior_points], [p[1] for p in interior_points], "^",
                         label="interior filled (interior_growth = 0)")
        if small_fit:
            axes[5].plot([0, top], [small_fit[0], small_fit[0] + small_fit[1] * top], ":",
                         label=f"line through De_d <= 0.05 (slope {small_fit[1]:.2f})")
        axes[5].set(xlabel="De_d = lambda_d gamma_dot", ylabel="theta shift [deg]",
                    title="shift vs drop Deborah number, Ca = 0.025")
    for a in axes:
        a.legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(os.path.join(OUT, "ucm_drop.png"), dpi=110)
    with open(os.path.join(OUT, "ucm_drop.md"), "w") as f:
        f.write("\n".join(md) + "\n\n![UCM drop](ucm_drop.png)\n")


def all_jobs():
    """Every (name, case text) of the studies above."""
    jobs = [(name_of(ca, ucm), case_text(name_of(ca, ucm), ca, ucm)) for ca in CAS for ucm in (True, False)]
    jobs += [(name_of(0.1, ucm, n, k), case_text(name_of(0.1, ucm, n, k), 0.1, ucm, n, far, k))
             for n, far, k in RESOLUTION for ucm in (True, False)]
    jobs += [(f"{'ucm' if ucm else 'newtonian'}_Ca0.1_pd{p_d:g}",
              case_text(f"{'ucm' if ucm else 'newtonian'}_Ca0.1_pd{p_d:g}", 0.1, ucm, p_d=p_d))
             for p_d in P_D_STUDY for ucm in (True, False)]
    jobs += [(pair_name(ca, p_d, ucm), case_text(pair_name(ca, p_d, ucm), ca, ucm, p_d=p_d))
             for pairs in FIXED_DEBORAH.values() for ca, p_d in pairs for ucm in (True, False)]
    small = {r[0]: general_case_text(r[0], r[1], r[2], r[3])
             for _, run, twin in small_deborah_runs() for r in (run, twin)}
    for _, _, run, twin, equator, far in small_deborah_checks():
        for r in (run, twin):
            small.setdefault(r[0], general_case_text(r[0], r[1], r[2], r[3], equator, far))
    jobs += list(small.items())
    interior = {}
    for _, run, twin in interior_runs() + interior_level_runs():
        for r in (run, twin):
            interior.setdefault(r[0], interior_case_text(r))
    return jobs + list(interior.items())


def main():
    validation_main("validation_ucm_drop", all_jobs, report)


if __name__ == "__main__":
    main()
