#!/usr/bin/python3
"""Roscoe's (1967) exact steady state of an initially spherical, incompressible
neo-Hookean (optionally Kelvin-Voigt) particle in simple shear of a Newtonian
liquid, at any elastic capillary number.

    R. Roscoe, "On the rheology of a suspension of viscoelastic spheres in a
    viscous liquid", J. Fluid Mech. 28 (1967) 273-293.

Definitions (docs/roscoe.md has the derivation and the checks):
  eta_m      viscosity of the matrix liquid
  G          shear modulus of the particle: extra stress G (B - I), B = F F^T
  eta_p      viscosity of the particle (Kelvin-Voigt: + 2 eta_p D); 0 = purely elastic
  gamma_dot  shear rate of the far field u = gamma_dot y e_x
  R          radius of the undeformed sphere (lengths below are in units of R)
  Ca_e       = eta_m gamma_dot / G
  lambda     = eta_p / eta_m   (argument viscosity_ratio)

The steady particle is an ellipsoid with semi-axes a1 >= a2 in the shear plane
and a3 along the vorticity, a1 a2 a3 = 1, its a1 axis at angle theta from the
flow direction (towards the velocity gradient), and its material tank-treads:
x = B^(1/2) Q(t) X with Q(t) a rotation about z at rate -omega_tt gamma_dot
(clockwise, the sense of the shear's vorticity), so each material point
returns after 2 pi / (omega_tt gamma_dot).

Unknowns a1, a2, theta solve (time in 1/gamma_dot, b_i = a_i^2,
t_i = b_i - (b1 + b2 + b3)/3, J_i and J_ij the ellipsoid integrals below):

  (E1)  P_1 + P_2 = 0
  (E2)  P_1 - P_2 = 2 Ca_e sin 2 theta
  (E3)  cos 2 theta (1 - k r^2 J_12 / s) = (r / s) (1 - k s J_12),   k = (1 - lambda) / 2
  with  P_i = (3/2) b_i J_ii t_i + (1/2) sum_{k != i} b_k J_ik t_k,
        r = a1^2 - a2^2, s = a1^2 + a2^2,
and then the tank-treading rate follows explicitly:
  (E4)  omega_tt = a1 a2 / (s - k r^2 J_12).

Usage: scripts/theory/roscoe_particle.py   (prints the table and the slope check)
"""
import math
import sys

import numpy as np
from scipy.integrate import quad
from scipy.optimize import root
from scipy.special import elliprd

SMALL_CA_SLOPE_D = 1.25        # D = 5/4 Ca_e
SMALL_CA_SLOPE_THETA = -0.75   # theta = pi/4 - 3/4 Ca_e (rad), lambda = 0
TABLE_CA = (0.025, 0.05, 0.1, 0.2, 0.3, 0.35, 0.5)

# Below this relative separation of two b_i the difference formula for J_ij
# loses digits and the integral is evaluated by quadrature instead.
_CLOSE = 1e-4


def ellipsoid_integrals(a):
    """The integrals of the ellipsoid with semi-axes a = (a1, a2, a3), scaled
    by a1 a2 a3 so that they depend on the shape only:
      J[i]    = a1 a2 a3 int_0^inf du / ((b_i + u) Delta(u)),
      JJ[i,j] = a1 a2 a3 int_0^inf du / ((b_i + u)(b_j + u) Delta(u)),
    b_i = a_i^2, Delta(u) = sqrt((b1 + u)(b2 + u)(b3 + u)).
    J[0] + J[1] + J[2] = 2; a sphere of radius 1 has J = 2/3, JJ = 2/5."""
    a = np.asarray(a, dtype=float)
    b = a * a
    v = float(np.prod(a))
    J = np.array([2.0 / 3.0 * elliprd(b[(i + 1) % 3], b[(i + 2) % 3], b[i]) for i in range(3)]) * v
    JJ = np.zeros((3, 3))
    for i in range(3):
        for j in range(i + 1, 3):
            if abs(b[i] - b[j]) > _CLOSE * max(b[i], b[j]):
                JJ[i, j] = (J[j] - J[i]) / (b[i] - b[j])
            else:
                f = lambda u: 1.0 / ((b[i] + u) * (b[j] + u) * math.sqrt((b[0] + u) * (b[1] + u) * (b[2] + u)))
                JJ[i, j] = v * quad(f, 0.0, math.inf, epsabs=0.0, epsrel=1e-13, limit=200)[0]
            JJ[j, i] = JJ[i, j]
    for i in range(3):  # 3 JJ_ii + sum_{j != i} JJ_ij = 2 / b_i
        JJ[i, i] = (2.0 / b[i] - sum(JJ[i, j] for j in range(3) if j != i)) / 3.0
    return J, JJ


def eshelby_normal_rows(a):
    """P-matrix M with P_i = sum_k M[i, k] t_k: the normal-normal block of the
    Eshelby tensor of an incompressible matrix (Poisson ratio 1/2) for the
    ellipsoid a, M[i, i] = 3/2 b_i JJ_ii, M[i, k] = 1/2 b_k JJ_ik."""
    b = np.asarray(a, dtype=float) ** 2
    _, JJ = ellipsoid_integrals(a)
    M = 0.5 * JJ * b[np.newaxis, :]
    for i in range(3):
        M[i, i] = 1.5 * b[i] * JJ[i, i]
    return M


def _shape(x):
    a1, a2 = math.exp(x[0]), math.exp(x[1])
    return np.array([a1, a2, 1.0 / (a1 * a2)])


def residuals(a1, a2, theta, ca_e, viscosity_ratio=0.0):
    """Residuals of (E1)-(E3) at semi-axes a1, a2 (a3 = 1/(a1 a2)) and angle
    theta [rad]. (E1) and (E2) are divided by Ca_e (their terms are O(Ca_e)),
    so all three are O(1)-scaled; all vanish at the solution."""
    a = np.array([a1, a2, 1.0 / (a1 * a2)])
    b = a * a
    t = b - b.mean()
    P = eshelby_normal_rows(a) @ t
    _, JJ = ellipsoid_integrals(a)
    r, s = b[0] - b[1], b[0] + b[1]
    k = 0.5 * (1.0 - viscosity_ratio)
    e1 = (P[0] + P[1]) / ca_e
    e2 = (P[0] - P[1]) / (2.0 * ca_e) - math.sin(2.0 * theta)
    e3 = math.cos(2.0 * theta) * (1.0 - k * r * r * JJ[0, 1] / s) - (r / s) * (1.0 - k * s * JJ[0, 1])
    return np.array([e1, e2, e3])


def tank_treading_rate(a1, a2, viscosity_ratio=0.0):
    """(E4): omega_tt in units of gamma_dot (1/2 for a sphere, the rigid rotation)."""
    a = np.array([a1, a2, 1.0 / (a1 * a2)])
    _, JJ = ellipsoid_integrals(a)
    r, s = a1 * a1 - a2 * a2, a1 * a1 + a2 * a2
    return a1 * a2 / (s - 0.5 * (1.0 - viscosity_ratio) * r * r * JJ[0, 1])


def _linear_guess(ca_e, lam):
    """The small-Ca_e solution (ln a1 = -ln a2 = 5/4 Ca_e, theta = pi/4 - (3 + 2 lambda)/4 Ca_e)
    to first order, written so that it stays a valid shape and angle at any Ca_e."""
    d = SMALL_CA_SLOPE_D * ca_e / (1.0 + ca_e)
    return np.array([d, -d, (math.pi / 4) / (1.0 + (3.0 + 2.0 * lam) * ca_e / math.pi)])


def _solve_at(ca_e, lam, x0):
    sol = root(lambda x: residuals(math.exp(x[0]), math.exp(x[1]), x[2], ca_e, lam), x0,
               method="hybr", options={"xtol": 1e-15, "maxfev": 2000})
    x = sol.x
    res = residuals(math.exp(x[0]), math.exp(x[1]), x[2], ca_e, lam)
    ok = np.max(np.abs(res)) < 1e-9 and x[0] >= x[1] - 1e-14 and 0.0 <= x[2] <= math.pi / 4 + 1e-12
    return x, ok


def _solve(ca_e, lam):
    """Newton-type solve of (E1)-(E3) in (ln a1, ln a2, theta); from the
    small-Ca_e solution for small Ca_e, else by continuation in Ca_e."""
    x, ok = _solve_at(ca_e, lam, _linear_guess(ca_e, lam))
    if ok:
        return x
    steps = max(8, int(math.ceil(ca_e / 0.01)))
    x = _linear_guess(ca_e / steps, lam)
    for n in range(1, steps + 1):
        x, ok = _solve_at(ca_e * n / steps, lam, x)
        if not ok:
            raise RuntimeError(f"Roscoe: no converged solution at Ca_e = {ca_e * n / steps:g}, lambda = {lam:g}")
    return x


def roscoe_steady(ca_e, viscosity_ratio=0.0):
    """Steady state of Roscoe's theory at elastic capillary number
    ca_e = eta_m gamma_dot / G and viscosity ratio eta_p / eta_m.
    Returns (D, theta_deg, a1, a2, a3, omega_tt):
      D         Taylor deformation (a1 - a2) / (a1 + a2), shear-plane semi-axes
      theta_deg angle of the a1 axis from the flow direction, degrees (45 at Ca_e -> 0)
      a1, a2, a3 semi-axes over R (a3 along the vorticity), a1 a2 a3 = 1
      omega_tt  tank-treading angular frequency over gamma_dot (clockwise; 1/2 at Ca_e -> 0)."""
    ca_e = float(ca_e)
    lam = float(viscosity_ratio)
    if ca_e < 0.0 or lam < 0.0:
        raise ValueError("Ca_e and the viscosity ratio must be >= 0")
    if ca_e == 0.0:
        return 0.0, 45.0, 1.0, 1.0, 1.0, 0.5
    x = _solve(ca_e, lam)
    a1, a2 = math.exp(x[0]), math.exp(x[1])
    a3 = 1.0 / (a1 * a2)
    return (a1 - a2) / (a1 + a2), math.degrees(x[2]), a1, a2, a3, tank_treading_rate(a1, a2, lam)


def interior_stress(ca_e, viscosity_ratio=0.0):
    """The uniform stress inside the steady particle in the lab frame (x flow,
    y gradient, z vorticity), in units of eta_m gamma_dot:
    returns (elastic, viscous), each a 3x3 array; elastic = G (B - I) / (eta_m gamma_dot),
    viscous = 2 eta_p D_in / (eta_m gamma_dot) (zero when viscosity_ratio = 0)."""
    _, th, a1, a2, a3, w = roscoe_steady(ca_e, viscosity_ratio)
    q = math.radians(th)
    Q = np.array([[math.cos(q), -math.sin(q), 0.0], [math.sin(q), math.cos(q), 0.0], [0.0, 0.0, 1.0]])
    b = np.array([a1, a2, a3]) ** 2
    elastic = Q @ np.diag((b - 1.0) / ca_e) @ Q.T
    d12 = w * (a1 * a1 - a2 * a2) / (2.0 * a1 * a2)   # interior rate of strain, particle axes
    Din = np.zeros((3, 3))
    Din[0, 1] = Din[1, 0] = d12
    viscous = 2.0 * viscosity_ratio * (Q @ Din @ Q.T)
    return elastic, viscous


def roscoe_paper_form_residuals(a1, a2, theta, ca_e, viscosity_ratio=0.0):
    """Cross-check: the same steady state written the way Roscoe (1967) writes it
    (as restated with his equation numbers by Gerum et al. 2022, eLife,
    in fabrylab/shear_flow_deformation_cytometer), evaluated with independent
    quadratures in Roscoe's integrals
      g_i'' = int_0^inf u du / ((b_j + u)(b_k + u) Delta),  g_3' = int_0^inf du / ((b_1 + u)(b_2 + u) Delta),
      I = 2/5 (g_1'' + g_2'') / (g_2'' g_3'' + g_3'' g_1'' + g_1'' g_2''),
      J = 2/5 (g_1'' - g_2'') / (same),  K = (b_1 + b_2) / (5 g_3' b_1 b_2),
    and Roscoe's sigma = 5 eta_m / (2 G), tau = (3 eta_m + 2 eta_p) / (2 G):
      (78) (b_1 + b_2 - 2 b_3) / (b_1 - b_2) = J / I        (shape, flow-independent)
      (79) gamma_dot sigma sin 2 theta = (b_1 - b_2) / (2 I)
      (80) cos 2 theta = (r/s) [1 + (tau - sigma)/(K sigma) (s/(2 a1 a2))^2] / [1 + (tau - sigma)/(K sigma) (r/(2 a1 a2))^2]
    Returns the three residuals (the first two relative)."""
    a = np.array([a1, a2, 1.0 / (a1 * a2)])
    b = a * a
    delta = lambda u: math.sqrt((b[0] + u) * (b[1] + u) * (b[2] + u))
    g2 = []
    for i in range(3):
        j, k = (i + 1) % 3, (i + 2) % 3
        g2.append(quad(lambda u: u / ((b[j] + u) * (b[k] + u) * delta(u)), 0.0, math.inf,
                       epsabs=0.0, epsrel=1e-13, limit=400)[0])
    g3p = quad(lambda u: 1.0 / ((b[0] + u) * (b[1] + u) * delta(u)), 0.0, math.inf,
               epsabs=0.0, epsrel=1e-13, limit=400)[0]
    den = g2[1] * g2[2] + g2[2] * g2[0] + g2[0] * g2[1]
    I = 0.4 * (g2[0] + g2[1]) / den
    Jr = 0.4 * (g2[0] - g2[1]) / den
    K = (b[0] + b[1]) / (5.0 * g3p * b[0] * b[1])
    r, s, p = b[0] - b[1], b[0] + b[1], a1 * a2
    sigma = 2.5 * ca_e                      # gamma_dot = 1, eta_m = 1, G = 1/Ca_e
    tau = (3.0 + 2.0 * viscosity_ratio) / 2.0 * ca_e
    c = (tau - sigma) / (K * sigma)
    e78 = ((s - 2.0 * b[2]) * I - Jr * r) / (abs(s - 2.0 * b[2]) * I + abs(Jr * r))
    e79 = (sigma * math.sin(2.0 * theta) * 2.0 * I - r) / r
    e80 = math.cos(2.0 * theta) - (r / s) * (1.0 + c * (s / (2.0 * p)) ** 2) / (1.0 + c * (r / (2.0 * p)) ** 2)
    return np.array([e78, e79, e80])


def small_ca_slopes(h=1e-4, viscosity_ratio=0.0):
    """Finite-difference slopes at Ca_e = 0: D(h)/h and (theta(h) - pi/4)/h [rad]."""
    D, th = roscoe_steady(h, viscosity_ratio)[:2]
    return D / h, (math.radians(th) - math.pi / 4) / h


def main():
    print("Roscoe (1967), neo-Hookean sphere in simple shear, lambda = eta_p/eta_m = 0")
    print(f"{'Ca_e':>6} {'D':>8} {'theta[deg]':>10} {'a1':>8} {'a2':>8} {'a3':>8} {'omega_tt':>9} {'5/4Ca':>7} {'45-3/4Ca[deg]':>13} {'max|res|':>9}")
    worst = 0.0
    for c in TABLE_CA:
        D, th, a1, a2, a3, w = roscoe_steady(c)
        res = np.max(np.abs(residuals(a1, a2, math.radians(th), c)))
        worst = max(worst, res)
        print(f"{c:6.3f} {D:8.5f} {th:10.4f} {a1:8.5f} {a2:8.5f} {a3:8.5f} {w:9.5f} "
              f"{1.25 * c:7.4f} {45 - math.degrees(0.75 * c):13.4f} {res:9.1e}")
    sd, st = small_ca_slopes()
    ok = abs(sd - SMALL_CA_SLOPE_D) < 1e-3 and abs(st - SMALL_CA_SLOPE_THETA) < 1e-3 and worst < 1e-10
    print(f"small-Ca_e slopes at Ca_e = 1e-4: dD/dCa = {sd:.6f} (5/4), dtheta/dCa = {st:.6f} rad (-3/4)")
    print("slope check:", "passed" if ok else "FAILED")
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main())
