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
import argparse
import concurrent.futures
import csv
import math
import os

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

from case_runs import read_run, richardson, run_case  # noqa: E402

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
"""


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


def report(work):
    raise NotImplementedError  # written once the runs are in


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("build", nargs="?", default=os.path.join(ROOT, "build"))
    parser.add_argument("work", nargs="?", default=os.path.join(ROOT, "output", "validation_kelvin_voigt_particle"))
    parser.add_argument("--jobs", type=int, default=2)
    parser.add_argument("--report-only", action="store_true")
    args = parser.parse_args()
    if not args.report_only:
        jobs = [(name, case_text(name, *spec)) for name, spec in all_cases().items()]
        with concurrent.futures.ThreadPoolExecutor(args.jobs) as pool:
            list(pool.map(lambda j: run_case(args.build, args.work, *j), jobs))
    report(args.work)


if __name__ == "__main__":
    main()
