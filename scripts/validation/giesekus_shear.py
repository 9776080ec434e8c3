"""Steady simple shear of a Giesekus liquid in closed form, and the relaxation
time that gives a confined particle's matrix a stated p (thesis ch. 3).

The steady shear solution of eq. 2.7 (Giesekus 1982; Bird, Armstrong and
Hassager, Dynamics of Polymeric Liquids vol. 1, 2nd ed.), with Wi = lambda
gamma_dot:
    chi^2 = (sqrt(1 + 16 alpha (1 - alpha) Wi^2) - 1) / (8 alpha (1 - alpha) Wi^2),
    f = (1 - chi) / (1 + (1 - 2 alpha) chi),
    eta_polymer(gamma_dot) / eta_p = (1 - f)^2 / (1 + (1 - 2 alpha) f),
    Psi_1(gamma_dot) / (2 eta_p lambda) = f (1 - alpha f) / (alpha Wi^2 (1 - f)).
softflow's C++ side solves the same steady state by Newton's method
(physics/viscoelastic/steady_shear) and reports p from it; a run's summary
is checked against this file by the scripts that use it.

Chapter 3 defines p = N / Ca_e^2 with N = N_1 / (2 G_p) and Ca_e = eta_m
gamma_dot / G_p, so p = N_1 / (2 eta_m gamma_dot Ca_e) (eta_m the zero-shear
viscosity, the one in Ca_e). N_1 of a Giesekus matrix at fixed eta_p and
gamma_dot rises with lambda to a largest value and falls beyond it: only the
rising branch is searched, and a p beyond its top is refused."""
import math


def first_normal_stress_difference(lam, eta_p, alpha, shear_rate=1.0):
    """N_1 of the polymer in steady simple shear (alpha in (0, 1); alpha -> 0 is Oldroyd-B)."""
    wi = lam * shear_rate
    if wi == 0.0:
        return 0.0
    if alpha == 0.0:
        return 2.0 * eta_p * lam * shear_rate ** 2
    s = 8.0 * alpha * (1.0 - alpha) * wi * wi
    chi = math.sqrt((math.sqrt(1.0 + 2.0 * s) - 1.0) / s)
    f = (1.0 - chi) / (1.0 + (1.0 - 2.0 * alpha) * chi)
    return 2.0 * eta_p * lam * f * (1.0 - alpha * f) / (alpha * wi * wi * (1.0 - f)) * shear_rate ** 2


def p_from_first_normal_stress(lam, ca_e, eta_s, eta_p, alpha, shear_rate=1.0):
    """p = N_1(gamma_dot) / (2 eta_m gamma_dot Ca_e), eta_m = eta_s + eta_p (thesis ch. 3)."""
    return first_normal_stress_difference(lam, eta_p, alpha, shear_rate) / (
        2.0 * (eta_s + eta_p) * shear_rate * ca_e)


def relaxation_time_for_p(p, ca_e, eta_s, eta_p, alpha, shear_rate=1.0):
    """The lambda_m on N_1's rising branch with p_from_first_normal_stress = p."""
    def p_of(lam):
        return p_from_first_normal_stress(lam, ca_e, eta_s, eta_p, alpha, shear_rate)
    # The top of the rising branch, by golden-section search over Wi in (0, 100].
    lo, hi = 1e-6 / shear_rate, 100.0 / shear_rate
    g = (math.sqrt(5.0) - 1.0) / 2.0
    for _ in range(200):
        a, b = hi - g * (hi - lo), lo + g * (hi - lo)
        if p_of(a) < p_of(b):
            lo = a
        else:
            hi = b
    top = 0.5 * (lo + hi)
    if p > p_of(top):
        raise ValueError(f"p = {p} is beyond the largest p = {p_of(top):.4g} this matrix reaches at "
                         f"Ca_e = {ca_e} (N_1 at the shear rate peaks at lambda = {top:.4g})")
    lo, hi = 0.0, top
    for _ in range(200):
        mid = 0.5 * (lo + hi)
        if p_of(mid) < p:
            lo = mid
        else:
            hi = mid
    return 0.5 * (lo + hi)
