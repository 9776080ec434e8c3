#!/usr/bin/python3
"""Checks of scripts/theory/roscoe_particle.py (Roscoe 1967). Plain python:
prints one line per check and exits non-zero if any fails.

Usage: scripts/theory/test_roscoe_particle.py   (about 10 s)"""
import math
import os
import sys

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from roscoe_particle import (TABLE_CA, eshelby_normal_rows, interior_stress, residuals,  # noqa: E402
                             roscoe_paper_form_residuals, roscoe_steady, small_ca_slopes)

FAILED = []


def check(name, ok, detail):
    print(f"{'ok  ' if ok else 'FAIL'} {name}: {detail}")
    if not ok:
        FAILED.append(name)


def test_small_ca_slopes():
    # Roscoe's linear limits (SPEC §3): D = 5/4 Ca_e, theta = pi/4 - 3/4 Ca_e; with a
    # particle viscosity theta = pi/4 - (3 + 2 lambda)/4 Ca_e (docs/viscoelastic.md), D unchanged.
    for lam in (0.0, 1.0, 2.0):
        sd, st = small_ca_slopes(1e-4, lam)
        want = -(3.0 + 2.0 * lam) / 4.0
        check(f"slopes at Ca_e = 1e-4, lambda = {lam:g}",
              abs(sd - 1.25) < 1e-3 and abs(st - want) < 1e-3,
              f"dD/dCa = {sd:.7f} (1.25), dtheta/dCa = {st:.7f} rad ({want:g})")


def test_consistency():
    for lam in (0.0, 1.0):
        prev = None
        for c in TABLE_CA + (1.0,):
            D, th, a1, a2, a3, w = roscoe_steady(c, lam)
            res = np.max(np.abs(residuals(a1, a2, math.radians(th), c, lam)))
            vol = abs(a1 * a2 * a3 - 1.0)
            paper = np.max(np.abs(roscoe_paper_form_residuals(a1, a2, math.radians(th), c, lam)))
            s, r = a1 * a1 + a2 * a2, a1 * a1 - a2 * a2
            w41 = s / (4.0 * a1 * a2) * (1.0 - r / s * math.cos(2.0 * math.radians(th)))
            ordered = a1 >= a2 > 0.0 and 0.0 < th < 45.0 and 0.0 < w <= 0.5
            monotone = prev is None or (D > prev[0] and th < prev[1])
            check(f"Ca_e = {c:g}, lambda = {lam:g}",
                  res < 1e-10 and vol < 1e-12 and paper < 1e-9 and abs(w - w41) < 1e-12 and ordered and monotone,
                  f"residual {res:.1e}, |a1 a2 a3 - 1| = {vol:.1e}, Roscoe's (78)-(80) {paper:.1e}, "
                  f"(41) {abs(w - w41):.1e}, D = {D:.5f}, theta = {th:.3f} deg")
            prev = (D, th)


def test_eshelby_rows():
    # sphere: normal-normal block of the incompressible Eshelby tensor, 3/5 on, 1/5 off the diagonal
    M = eshelby_normal_rows([1.0, 1.0, 1.0])
    want = np.full((3, 3), 0.2) + 0.4 * np.eye(3)
    check("Eshelby rows, sphere", np.max(np.abs(M - want)) < 1e-12, f"max error {np.max(np.abs(M - want)):.1e}")
    # elliptic cylinder (a3 -> infinity), semi-axes a, b: S1111 = (b^2 + 2ab)/(a+b)^2,
    # S1122 = b^2/(a+b)^2, S2211 = a^2/(a+b)^2, S2222 = (a^2 + 2ab)/(a+b)^2 (Poisson ratio 1/2)
    a, b = 2.0, 0.7
    M = eshelby_normal_rows([a, b, 1e8])
    cyl = np.array([[b * b + 2 * a * b, b * b], [a * a, a * a + 2 * a * b]]) / (a + b) ** 2
    err = np.max(np.abs(M[:2, :2] - cyl))
    check("Eshelby rows, elliptic cylinder limit", err < 1e-6, f"max error {err:.1e}")
    # incompressibility: a traceless t gives a traceless P (columns sum to 1)
    M = eshelby_normal_rows([1.7, 0.6, 1.0 / (1.7 * 0.6)])
    err = np.max(np.abs(M.sum(axis=0) - 1.0))
    check("Eshelby rows, column sums", err < 1e-12, f"max error {err:.1e}")


def test_limits():
    c0 = roscoe_steady(0.0)
    check("Ca_e = 0 is the rigidly rotating sphere", c0 == (0.0, 45.0, 1.0, 1.0, 1.0, 0.5), str(c0))
    # very viscous Kelvin-Voigt solid, Ca_e -> 0 at fixed x = (2 lambda + 3) Ca_e / 2:
    # tan 2 theta = 1/x and D = 5/4 Ca_e sin 2 theta (docs/viscoelastic.md)
    lam = 1e5
    for x in (0.5, 1.0, 2.0):
        c = 2.0 * x / (2.0 * lam + 3.0)
        D, th = roscoe_steady(c, lam)[:2]
        q = math.radians(th)
        check(f"very viscous solid, x = {x:g}",
              abs(q - 0.5 * math.atan(1.0 / x)) < 1e-4 and abs(D / (1.25 * c * math.sin(2 * q)) - 1) < 1e-6,
              f"theta = {th:.5f} deg vs {math.degrees(0.5 * math.atan(1.0 / x)):.5f}")
    # the stiff particle's stress: volume-averaged deviatoric stress of a rigid sphere, 5 eta_m E,
    # so G (B - I)_xy -> 5/2 eta_m gamma_dot (Batchelor 1970)
    el, _ = interior_stress(1e-3)
    check("stiff limit of the interior shear stress", abs(el[0, 1] - 2.5) < 1e-3, f"tau_xy = {el[0, 1]:.6f}")


def main():
    test_small_ca_slopes()
    test_consistency()
    test_eshelby_rows()
    test_limits()
    print("all passed" if not FAILED else f"{len(FAILED)} FAILED: {', '.join(FAILED)}")
    return 1 if FAILED else 0


if __name__ == "__main__":
    sys.exit(main())
