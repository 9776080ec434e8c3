#!/usr/bin/python3
"""Validation of the Kelvin-Voigt particle in unbounded shear: runs the cases
below with the softflow binary (two at a time), then writes
docs/validation/kelvin_voigt_particle.{md,csv,png}.

A Kelvin-Voigt particle is the neo-Hookean solid with a viscosity mu_d beside
its modulus G: tau = 2 mu_d D + G (B - I). Unit sphere, no interfacial
tension, Newtonian matrix (eta_m = 1, shear rate 1), box 30 x 30 x 30,
Ca_e = eta_m gamma_dot / G, viscosity ratio lambda_s = mu_d / eta_m. The
small-deformation theory (docs/viscoelastic.md, `softflow theory --ca-e C
--solid-viscosity-ratio L`) predicts, to first order in Ca_e,

    D = 5/4 Ca_e (whatever lambda_s),   theta = pi/4 - (2 lambda_s + 3)/4 Ca_e,

so the solid's viscosity leaves D alone and turns the particle towards the
flow: the tilt pi/4 - theta grows by (2 lambda_s + 3)/3 over the neo-Hookean
particle's (lambda_s = 0, Roscoe's 3/4 Ca_e).

Study K: Ca_e = 0.025 and 0.05, lambda_s = 0 (model neo_hookean), 1 and 4,
         28 equator nodes, the interior filled (mesh.interior_growth = 0),
         dt = 0.02, to t = 10: steady D and theta against the theory, and the
         tilt ratio against the neo-Hookean twin on the same mesh.
Study M: Ca_e = 0.05, lambda_s = 1, the whole mesh refined by one factor
         (interface size, far size and growth together): 20/28/40 nodes.

Steady values are means over the last 2 pi time units. Finished cases (a
summary.json in their directory) are not rerun.
Usage: scripts/validation/kelvin_voigt_particle.py [build_dir] [work_dir] [--jobs N] [--report-only]"""
import csv
import math
import os

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

from case_runs import PARTICLE_FIGURES_CONFORMATION, meshed_size, read_run, richardson, validation_main  # noqa: E402

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
OUT = os.path.join(ROOT, "docs", "validation")
T_END = 10.0
DT = 0.02
WINDOW = 2.0 * math.pi

# (equator nodes, far size, growth): one refinement factor for all three,
# the meshes of docs/validation/elastic_particle.md.
MESHES = {20: (20, 4.5, 0.56), 28: (28, 3.2, 0.4), 40: (40, 2.25, 0.28)}
STUDY_K_CA = [0.025, 0.05]
STUDY_K_LAMBDA = [0.0, 1.0, 4.0]
STUDY_M = [20, 28, 40]
STUDY_M_POINT = (0.05, 1.0)


def case_name(ca_e, lam, n):
    return f"Cae{ca_e:g}_ls{lam:g}_N{n}"


def case_text(name, ca_e, lam, n):
    equator, far, growth = MESHES[n]
    model = 'model = "neo_hookean"' if lam == 0.0 else f'model = "kelvin_voigt"\nsolvent_viscosity = {lam}'
    return f"""[case]
name = "{name}"
[cell]
length = 30.0
height = 30.0
width = 30.0
[flow]
shear_rate = 1.0
[[objects]]
{model}
elastic_capillary_number = {ca_e}
[mesh]
equator_nodes = {equator}
far_size = {far}
growth = {growth}
interior_growth = 0
[time]
step = {DT}
end = {T_END}
[checkpoint]
interval_minutes = 0
[output]
fields = false
""" + PARTICLE_FIGURES_CONFORMATION


def all_cases():
    """Name -> (Ca_e, lambda_s, equator nodes), cheapest first so that the
    long 40-node run starts last."""
    cases = {case_name(c, lam, 28): (c, lam, 28) for c in STUDY_K_CA for lam in STUDY_K_LAMBDA}
    for n in STUDY_M:
        cases[case_name(*STUDY_M_POINT, n)] = (*STUDY_M_POINT, n)
    return cases


def theory_d(ca_e):
    return 1.25 * ca_e


def theory_tilt_deg(ca_e, lam):
    """pi/4 - theta, first order in Ca_e."""
    return math.degrees((2.0 * lam + 3.0) / 4.0 * ca_e)


def theory_theta(ca_e, lam):
    return 45.0 - theory_tilt_deg(ca_e, lam)


def small_strain_tilt_deg(ca_e, lam):
    """pi/4 - theta of the same small-strain model kept to all orders in
    x = (2 lambda_s + 3) Ca_e / 2, the shape's relaxation time over the
    flow's: tan 2 theta = 1 / x (docs/viscoelastic.md). Exact as Ca_e -> 0
    at fixed x (a very viscous solid, whose strain stays small)."""
    return math.degrees(0.5 * math.atan((2.0 * lam + 3.0) * ca_e / 2.0))


def tilt(r):
    return 45.0 - r["theta_steady"]


def study_k(results):
    md = ["## Steady D and theta against the theory (28 equator nodes, interior filled, dt = 0.02)", "",
          "`tilt` is 45 deg - theta. `extra tilt` is the tilt minus that of the neo-Hookean twin "
          "(lambda_s = 0, same Ca_e, same mesh); its theory value is lambda_s Ca_e / 2 rad. The "
          "mesh's error in the tilt is nearly the same for the twins (the neo-Hookean tilt's error "
          "is shown in its own row) and cancels in the difference. The first-order theory is an "
          "expansion in x = (2 lambda_s + 3) Ca_e / 2 (the shape's relaxation time over the flow's); "
          "`small-strain` keeps every order in x (tilt = atan(x) / 2, same model, docs/viscoelastic.md).", "",
          "| Ca_e | lambda_s = mu_d / eta_m | unknowns | D | D ampl. | theory D | D / theory - 1 | theta [deg] | "
          "theory theta [deg] | tilt [deg] | theory tilt [deg] | extra tilt [deg] | theory extra tilt [deg] | "
          "extra tilt / theory - 1 | x | small-strain extra tilt [deg] | extra tilt / small-strain - 1 | "
          "ellipsoid dev. | wall time [s] | status |",
          "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|"]
    for c in STUDY_K_CA:
        twin = results[case_name(c, 0.0, 28)]
        for lam in STUDY_K_LAMBDA:
            r = results[case_name(c, lam, 28)]
            extra_theory = theory_tilt_deg(c, lam) - theory_tilt_deg(c, 0.0)
            extra_small = small_strain_tilt_deg(c, lam) - small_strain_tilt_deg(c, 0.0)
            x = (2 * lam + 3) * c / 2
            theory_columns = (f"{extra_theory:.3f}", f"{extra_small:.3f}") if lam > 0 else ("-", "-")
            if r is None:
                md.append(f"| {c:g} | {lam:g} | | | | {theory_d(c):.5f} | | | {theory_theta(c, lam):.3f} | | "
                          f"{theory_tilt_deg(c, lam):.3f} | | {theory_columns[0]} | | {x:.4g} | "
                          f"{theory_columns[1]} | | | | not run |")
                continue
            extra, extra_error, small_error = "-", "-", "-"
            if twin and lam > 0:
                measured = tilt(r) - tilt(twin)
                extra = f"{measured:.3f}"
                extra_error = f"{measured / extra_theory - 1:+.1%}"
                small_error = f"{measured / extra_small - 1:+.1%}"
            md.append(f"| {c:g} | {lam:g} | {r['unknowns']} | {r['D_steady']:.5f} | {r['D_amplitude']:.1e} | "
                      f"{theory_d(c):.5f} | {r['D_steady'] / theory_d(c) - 1:+.1%} | {r['theta_steady']:.3f} | "
                      f"{theory_theta(c, lam):.3f} | {tilt(r):.3f} | {theory_tilt_deg(c, lam):.3f} | {extra} | "
                      f"{theory_columns[0]} | {extra_error} | {x:.4g} | {theory_columns[1]} | {small_error} | "
                      f"{r['deviation']:.1e} | {r['wall']:.0f} | "
                      f"{r['status']} (t = {r['end']:g}) |")
    return md


def study_m(results):
    c, lam = STUDY_M_POINT
    md = ["", f"## Mesh study at Ca_e = {c:g}, lambda_s = {lam:g} (interior filled, dt = 0.02; "
          "equator nodes, far size and growth refined together)", "",
          "| equator nodes / far size / growth | meshed equator nodes | unknowns | vertices inside | D | D ampl. | "
          "theta [deg] | wall time [s] | status |",
          "|---|---|---|---|---|---|---|---|---|"]
    levels = []
    for n in STUDY_M:
        r = results[case_name(c, lam, n)]
        label = f"{n} / {MESHES[n][1]:g} / {MESHES[n][2]:g}"
        if r is None:
            md.append(f"| {label} | | | | | | | | not run |")
            continue
        levels.append((meshed_size(r), r["D_steady"], r["theta_steady"]))
        md.append(f"| {label} | {r['summary']['mesh']['equator_nodes']} | {r['unknowns']} | "
                  f"{r['summary']['mesh'].get('object_interior_vertices', '?')} | {r['D_steady']:.5f} | "
                  f"{r['D_amplitude']:.1e} | {r['theta_steady']:.3f} | {r['wall']:.0f} | {r['status']} |")
    if len(levels) == 3:
        hs, ds, ths = zip(*levels)
        md += ["", "h = 1 / meshed equator nodes:", ""]
        for name, values, unit in (("D", ds, ""), ("theta", ths, " deg")):
            fit = richardson(hs, values)
            diffs = f"differences {values[0] - values[1]:+.2e}, {values[1] - values[2]:+.2e}"
            if fit is None:
                md.append(f"- {name}: {diffs}: no order (not monotone)")
            else:
                md.append(f"- {name}: {diffs}: observed order {fit[0]:.2f}, Richardson {name} = "
                          f"{fit[1]:.5f}{unit}, the finest run {values[2] - fit[1]:+.2e}{unit} from it")
    return md


def report(work):
    os.makedirs(OUT, exist_ok=True)
    results = {name: read_run(os.path.join(work, name), WINDOW) for name in all_cases()}
    md = ["# Kelvin-Voigt particle in unbounded shear", "",
          "Unit sphere of a Kelvin-Voigt solid, tau = 2 mu_d D + G (B - I), no interfacial tension, "
          "in a Newtonian matrix (eta_m = 1, shear rate 1), box 30 x 30 x 30 (15 diameters), periodic "
          "in x and z; Ca_e = eta_m gamma_dot / G, lambda_s = mu_d / eta_m (lambda_s = 0: the neo-Hookean "
          "particle, model neo_hookean). Theory (docs/viscoelastic.md), first order in Ca_e: "
          "D = 5/4 Ca_e whatever lambda_s, theta = 45 deg - (2 lambda_s + 3)/4 Ca_e rad. Steady values: "
          "means over the last 2 pi time units of each run; `D ampl.` is the half-amplitude of D over "
          "that window; `ellipsoid dev.` the largest node distance from the fitted ellipsoid over R at the "
          "end. Generated by `scripts/validation/kelvin_voigt_particle.py`.", ""]
    md += study_k(results) + study_m(results)
    with open(os.path.join(OUT, "kelvin_voigt_particle.csv"), "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(["Ca_e", "lambda_s", "equator_nodes", "unknowns", "D", "D_amplitude", "theta_deg",
                    "theory_D", "theory_theta_deg", "wall_seconds", "status"])
        for name, (c, lam, n) in all_cases().items():
            r = results[name]
            if r:
                w.writerow([c, lam, n, r["unknowns"], f"{r['D_steady']:.6g}", f"{r['D_amplitude']:.3g}",
                            f"{r['theta_steady']:.6g}", theory_d(c), f"{theory_theta(c, lam):.6g}",
                            f"{r['wall']:.0f}", r["status"]])

    fig, axes = plt.subplots(1, 3, figsize=(15, 4.2))
    for k, c in enumerate(STUDY_K_CA):
        for j, lam in enumerate(STUDY_K_LAMBDA):
            r = results[case_name(c, lam, 28)]
            if r is None:
                continue
            style = "-" if k == len(STUDY_K_CA) - 1 else ":"
            axes[0].plot(r["t"], r["D"], style, color=f"C{j}", label=f"Ca_e {c:g}, lambda_s {lam:g}")
            axes[1].plot(r["t"][1:], r["theta"][1:], style, color=f"C{j}", label=f"Ca_e {c:g}, lambda_s {lam:g}")
            axes[1].axhline(theory_theta(c, lam), color=f"C{j}", lw=0.6, ls="--")
            axes[2].plot([lam], [tilt(r) / c], "o" if k == 0 else "s", color=f"C{k}",
                         label=f"Ca_e = {c:g}" if j == 0 else None)
    for c in STUDY_K_CA:
        axes[0].axhline(theory_d(c), color="gray", lw=0.6, ls="--")
    grid = [i * 0.1 for i in range(46)]
    axes[2].plot(grid, [math.degrees((2 * x + 3) / 4) for x in grid], "--", color="gray",
                 label="theory (2 lambda_s + 3)/4 rad")
    axes[0].set(xlabel="t gamma_dot", ylabel="D", title="D(t); dashed: 5/4 Ca_e")
    axes[1].set(xlabel="t gamma_dot", ylabel="theta [deg]", title="theta(t); dashed: theory")
    axes[2].set(xlabel="lambda_s = mu_d / eta_m", ylabel="(45 deg - theta) / Ca_e [deg]",
                title="tilt per unit Ca_e (28 nodes)")
    for a in axes:
        a.legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(os.path.join(OUT, "kelvin_voigt_particle.png"), dpi=110)
    with open(os.path.join(OUT, "kelvin_voigt_particle.md"), "w") as f:
        f.write("\n".join(md) + "\n\n![Kelvin-Voigt particle](kelvin_voigt_particle.png)\n")


def main():
    validation_main("validation_kelvin_voigt_particle",
                    lambda: [(name, case_text(name, *spec)) for name, spec in all_cases().items()], report)


if __name__ == "__main__":
    main()
