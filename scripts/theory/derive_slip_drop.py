#!/usr/bin/python3
"""Derives and checks the exact Stokes fields around a spherical drop with
Navier slip in a linear flow, as implemented in
src/softflow/analysis/theory/drop_in_linear_flow.{hpp,cpp}.

Usage: scripts/theory/derive_slip_drop.py   (sympy 1.11; about 10 minutes on one core)

The drop is the unit sphere r = 1 with outward normal n = x (pointing into
the matrix); matrix viscosity 1, drop viscosity lambda, dimensionless slip
coefficient alpha (= alpha_dim eta_m / R); far field u = E.x + W.x with E
symmetric and traceless, W antisymmetric; h = x.E.x. Both fields use the
ansatz

  outside u = E.x + A h x / r^5 + B grad(h / r^5) + W.x,   p = C h / r^5
  inside  u = K E.x + M (5 r^2 E.x - 2 h x) + W.x,          p = Q h + P0

(the four vector fields are the classical degree-2 Stokes solutions, h/r^5
is harmonic, so grad(h/r^5) carries no pressure). Stokes in each phase fixes
C and Q. The interface conditions on r = 1 are

  (1) n.u_m = n.u_d                                   (no mass crosses S)
  (2) (I - nn)(u_m - u_d) = alpha (I - nn)(sigma_m n)  (Navier slip, SPEC §9 sign)
  (3) (I - nn)(sigma_m - sigma_d) n = 0                (tangential traction)
  (4) instantaneous:  n.(sigma_m - sigma_d) n = 2 Gamma, uniform
      Taylor (quasi-steady): n.u_m = n.u_d = 0 instead

with sigma = -p I + viscosity (grad u + grad u^T). Every condition is
imposed as a polynomial identity (Stokes: cleared of 1/r and reduced modulo
r^2 - x^2 - y^2 - z^2; interface: at r = 1, reduced modulo
x^2 + y^2 + z^2 - 1; each coefficient set to zero), so the solution is
exact, not fitted. The solve uses one E with all five components (the
fields are linear in E); the script then checks Stokes and every condition
once more, identically, for a general E and W, the no-slip limits against
the fields of before, the form the C++ code evaluates, the closed forms of
the slip and interior dissipation, the first-order deformation D/Ca that
the Taylor field's normal-stress imbalance implies, and that the opposite
sign of the Navier law gives lambda + 1 - 5 alpha lambda instead of SPEC
§10's Lambda.

Results (d = 2 lambda + 3, e = 19 lambda + 16; always C = 2A, Q = 21 lambda M,
P0 = 2 Gamma; tangential traction T (I - nn) E n, slip velocity
S (I - nn) E n, S = alpha T):
  instantaneous, Den = d e + 10 alpha lambda (19 lambda + 24):
    A = 5 [(1 - lambda) e - 2 alpha lambda (19 lambda - 40)] / Den
    B = [(1 - lambda) e + 80 alpha lambda] / Den
    K = 5 (e + 128 alpha lambda) / Den,   M = -80 alpha lambda / Den
    T = 10 lambda e / Den
  taylor_quasi_steady, L = lambda + 1 + 5 alpha lambda:
    A = -(5 lambda + 2 + 10 alpha lambda) / (2L),  B = -lambda / (2L)
    K = -3 / (2L),  M = 1 / (2L),  T = 5 lambda / L
  slip dissipation (4 pi / 5) alpha T^2 E:E; interior viscous dissipation
  (8 pi / 15) lambda (5 K^2 + 42 K M + 111 M^2) E:E.
"""
import sympy as sp

x, y, z = sp.symbols("x y z", real=True)
X = sp.Matrix([x, y, z])
lam, alpha, gamma = sp.symbols("lambda alpha Gamma", positive=True)
e11, e22, e12, e13, e23 = sp.symbols("e11 e22 e12 e13 e23", real=True)
w1, w2, w3 = sp.symbols("w1 w2 w3", real=True)
E = sp.Matrix([[e11, e12, e13], [e12, e22, e23], [e13, e23, -e11 - e22]])
W = sp.Matrix([[0, -w3, w2], [w3, 0, -w1], [-w2, w1, 0]])
A, B, C, K, M, Q, P0 = sp.symbols("A B C K M Q P0")
UNKNOWNS = [A, B, C, K, M, Q, P0]

# r is carried as the symbol R with dR/dx_i = x_i / R, so that every field is
# a polynomial in x, y, z, 1/R and identities can be checked exactly.
R = sp.Symbol("R", positive=True)
r2 = x**2 + y**2 + z**2
h = (X.T * E * X)[0]
EX = E * X


def d(f, v):
    return sp.diff(f, v) + sp.diff(f, R) * v / R


def grad_scalar(f):
    return sp.Matrix([d(f, v) for v in (x, y, z)])


def grad_vector(u):
    """G[i, j] = du_i / dx_j."""
    return sp.Matrix(3, 3, lambda i, j: d(u[i], [x, y, z][j]))


def laplacian(u):
    return sp.Matrix([sum(d(d(u[i], v), v) for v in (x, y, z)) for i in range(3)])


def stress(u, p, viscosity):
    g = grad_vector(u)
    return -p * sp.eye(3) + viscosity * (g + g.T)


# ---- the ansatz ----
u_out = EX + A * h * X / R**5 + B * grad_scalar(h / R**5) + W * X
p_out = C * h / R**5
u_in = K * EX + M * (5 * r2 * EX - 2 * h * X) + W * X
p_in = Q * h + P0

VARS = (x, y, z, e11, e22, e12, e13, e23, w1, w2, w3)


def reduce_polynomial(num, relation, gens):
    _, rem = sp.reduced(sp.expand(num), [relation], *gens, order="lex")
    return sp.expand(rem)


def identically(expr):
    """expr (polynomial in x, y, z, 1/R) with R = |x|, as a polynomial that is
    zero exactly when expr vanishes everywhere: cleared of 1/R and reduced
    modulo R^2 - r^2 (R first in lex order: at most linear in R)."""
    num, _ = sp.fraction(sp.together(sp.expand(expr)))
    return reduce_polynomial(num, R**2 - r2, (R,) + VARS)


def on_sphere(expr):
    """expr at r = 1 as a polynomial reduced modulo x^2 + y^2 + z^2 - 1: zero
    exactly when expr vanishes on the whole unit sphere."""
    expr = sp.expand(sp.expand(expr).subs(R, 1))
    num, den = sp.fraction(sp.together(expr))
    return sp.expand(reduce_polynomial(num, r2 - 1, VARS) / den)


def coefficient_equations(expr):
    """The coefficients of a polynomial in x, y, z, E, W (and R): all must vanish."""
    poly = sp.Poly(sp.expand(expr), R, *VARS)
    return [c for c in poly.coeffs() if c != 0]


def stokes_equations(u, p, viscosity):
    """-viscosity lap u + grad p = 0 and div u = 0, as coefficient equations."""
    res = list(-viscosity * laplacian(u) + grad_scalar(p)) + [grad_vector(u).trace()]
    eqs = []
    for comp in res:
        eqs += coefficient_equations(identically(comp))
    return eqs


n = X  # on r = 1
P = sp.eye(3) - n * n.T  # tangential projector


def interface_conditions(kind, sign=1):
    s_m = stress(u_out, p_out, 1)
    s_d = stress(u_in, p_in, lam)
    t_m = s_m * n
    t_d = s_d * n
    eqs = []
    eqs += coefficient_equations(on_sphere((n.T * (u_out - u_in))[0]))
    navier = P * (u_out - u_in) - sign * alpha * P * t_m
    for i in range(3):
        eqs += coefficient_equations(on_sphere(navier[i]))
    tangential = P * (t_m - t_d)
    for i in range(3):
        eqs += coefficient_equations(on_sphere(tangential[i]))
    if kind == "instantaneous":
        eqs += coefficient_equations(on_sphere((n.T * (t_m - t_d))[0] - 2 * gamma))
    else:
        eqs += coefficient_equations(on_sphere((n.T * u_out)[0] - (n.T * W * n)[0]))
        eqs += coefficient_equations(on_sphere((n.T * u_in)[0] - (n.T * W * n)[0]))
        eqs += [P0 - 2 * gamma]  # the pressure level, as in the no-slip field
    return eqs


# E of one solve: any E with all five components gives every coefficient
# equation (the fields are linear in E); check_identically then verifies the
# solution for a general E and W.
E_SOLVE = {e11: 1, e22: sp.Rational(-1, 3), e12: sp.Rational(1, 2), e13: sp.Rational(2, 7),
           e23: sp.Rational(-3, 4), w1: 0, w2: 0, w3: 0}


def solve(kind, sign=1):
    """The coefficients; sign = -1 solves with the Navier law's sign flipped."""
    global u_out, p_out, u_in, p_in
    general = (u_out, p_out, u_in, p_in)
    u_out, p_out, u_in, p_in = (f.subs(E_SOLVE) for f in general)
    try:
        eqs = stokes_equations(u_out, p_out, 1) + stokes_equations(u_in, p_in, lam)
        eqs += interface_conditions(kind, sign)
    finally:
        u_out, p_out, u_in, p_in = general
    eqs = list({sp.expand(e) for e in eqs} - {0})
    sol = sp.solve(eqs, UNKNOWNS, dict=True)
    assert len(sol) == 1, sol
    sol = {k: sp.factor(v) for k, v in sol[0].items()}
    # every equation holds with it (the system is overdetermined)
    for e in eqs:
        assert sp.simplify(e.subs(sol)) == 0, e
    return sol


def check_identically(sol, kind):
    """All conditions once more, with the solved coefficients substituted."""
    uo, po = u_out.subs(sol), p_out.subs(sol)
    ui, pi = u_in.subs(sol), p_in.subs(sol)
    for u, p, visc in ((uo, po, 1), (ui, pi, lam)):
        res = -visc * laplacian(u) + grad_scalar(p)
        assert all(identically(c) == 0 for c in res), "Stokes"
        assert identically(grad_vector(u).trace()) == 0, "div u"
    t_m = stress(uo, po, 1) * n
    t_d = stress(ui, pi, lam) * n
    assert on_sphere((n.T * (uo - ui))[0]) == 0, "n.u continuous"
    assert all(on_sphere(c) == 0 for c in P * (uo - ui) - alpha * P * t_m), "Navier"
    assert all(on_sphere(c) == 0 for c in P * (t_m - t_d)), "tangential traction"
    if kind == "instantaneous":
        assert on_sphere((n.T * (t_m - t_d))[0] - 2 * gamma) == 0, "normal traction"
    else:
        assert on_sphere((n.T * (uo - W * n))[0]) == 0, "u.n = 0"
    return uo, po, ui, pi, t_m, t_d


# Integrals over the unit sphere and ball of monomials x^a y^b z^c.
def sphere_monomial(a, b, c):
    if a % 2 or b % 2 or c % 2:
        return sp.Integer(0)
    return 2 * sp.gamma(sp.Rational(a + 1, 2)) * sp.gamma(sp.Rational(b + 1, 2)) * \
        sp.gamma(sp.Rational(c + 1, 2)) / sp.gamma(sp.Rational(a + b + c + 3, 2))


def integrate_sphere(poly_expr):
    poly = sp.Poly(sp.expand(poly_expr), x, y, z)
    return sp.simplify(sum(coef * sphere_monomial(*m) for m, coef in poly.terms()))


def integrate_ball(poly_expr):
    # int_ball x^a y^b z^c = int_sphere(...) / (a + b + c + 3)
    poly = sp.Poly(sp.expand(poly_expr), x, y, z)
    return sp.simplify(sum(coef * sphere_monomial(*m) / (sum(m) + 3) for m, coef in poly.terms()))


EE = sp.expand(sum(E[i, j] ** 2 for i in range(3) for j in range(3)))  # E:E


def as_multiple_of_EE(value):
    ratio = sp.factor(sp.simplify(value / EE))
    assert not ratio.free_symbols & {e11, e22, e12, e13, e23, w1, w2, w3}, ratio
    return ratio


def report(kind, sol):
    print(f"== {kind} ==")
    for k in UNKNOWNS:
        print(f"  {k} = {sol[k]}")
    uo, po, ui, pi, t_m, t_d = check_identically(sol, kind)
    print("  Stokes in both phases and every interface condition hold identically")

    # The slip velocity and the tangential traction are multiples of (I - nn) E n.
    Pn = P * E * n
    jump = P * (uo - ui)
    s = sp.Symbol("s")
    s_val = sp.solve(on_sphere((jump - s * Pn)[0]).subs({e12: 0, e13: 1, e23: 0, e11: 0, e22: 0})
                     .subs({x: sp.Rational(3, 5), y: 0, z: sp.Rational(4, 5)}), s)[0]
    assert all(on_sphere(c) == 0 for c in jump - s_val * Pn)
    t_val = sp.factor(s_val / alpha) if s_val != 0 else sp.factor(
        sp.solve(on_sphere((P * t_m - s * Pn)[0]).subs({e12: 0, e13: 1, e23: 0, e11: 0, e22: 0})
                 .subs({x: sp.Rational(3, 5), y: 0, z: sp.Rational(4, 5)}), s)[0])
    assert all(on_sphere(c) == 0 for c in P * t_m - t_val * Pn)
    print(f"  (I - nn)(u_m - u_d) = {sp.factor(s_val)} (I - nn) E n")
    print(f"  (I - nn) sigma_m n  = {t_val} (I - nn) E n")

    # Slip dissipation: int (u_m - u_d).(sigma_m n) dS = alpha int |(I - nn) sigma_m n|^2.
    # W drops out (the jump and the traction above are multiples of (I - nn) E n
    # for a general W), so it is set to 0 here to keep the integrands small.
    no_w = {w1: 0, w2: 0, w3: 0}
    uo, ui, t_m = uo.subs(no_w), ui.subs(no_w), t_m.subs(no_w)
    # (At R = 1 the integrands are polynomials in x, y, z: no reduction needed.)
    work = ((uo - ui).T * t_m)[0].subs(R, 1)
    slip_diss = as_multiple_of_EE(integrate_sphere(work))
    slip_diss2 = as_multiple_of_EE(integrate_sphere((alpha * (P * t_m).T * (P * t_m))[0].subs(R, 1)))
    assert sp.simplify(slip_diss - slip_diss2) == 0
    print(f"  slip dissipation  int (u_m - u_d).(sigma_m n) dS = ({slip_diss}) E:E")
    assert sp.simplify(slip_diss - alpha * t_val**2 * sp.Rational(4, 5) * sp.pi) == 0

    # Viscous dissipation inside: int 2 lambda D:D dV (W.x has D = 0), and the
    # form the code uses, (8 pi / 15) lambda (5 K^2 + 42 K M + 111 M^2) E:E.
    g = grad_vector(ui)
    d = (g + g.T) / 2
    dd = sp.expand(sum(d[i, j] ** 2 for i in range(3) for j in range(3)))
    inner = as_multiple_of_EE(integrate_ball(2 * lam * dd))
    print(f"  interior viscous dissipation int 2 lambda D:D dV = ({inner}) E:E")
    kk, mm = sol[K], sol[M]
    assert sp.simplify(inner - 8 * sp.pi / 15 * lam * (5 * kk**2 + 42 * kk * mm + 111 * mm**2)) == 0
    return s_val, t_val, slip_diss, inner, t_m, t_d


def main():
    inst = solve("instantaneous")
    s_i, t_i, diss_i, inner_i, _, _ = report("instantaneous", inst)
    # alpha = 0: the no-slip field of the existing code.
    d0 = 2 * lam + 3
    no_slip = {A: 5 * (1 - lam) / d0, B: (1 - lam) / d0, C: 10 * (1 - lam) / d0, K: 5 / d0,
               M: 0, Q: 0, P0: 2 * gamma}
    for k, v in no_slip.items():
        assert sp.simplify(inst[k].subs(alpha, 0) - v) == 0, (k, inst[k])
    print("  alpha = 0 gives the existing no-slip instantaneous field")
    # The form the code evaluates: X = X0 + S X1, S = alpha T0 / (1 - alpha T1).
    e = 19 * lam + 16
    per_unit_slip = {A: 3 * lam / d0, B: lam * (19 * lam + 21) / (d0 * e),
                     K: 3 * (11 * lam + 24) / (d0 * e), M: -8 / e}
    t0, t1 = 10 * lam / d0, -10 * lam * (19 * lam + 24) / (d0 * e)
    s_code = alpha * t0 / (1 - alpha * t1)
    assert sp.simplify(s_code - s_i) == 0 and sp.simplify(t0 + s_code * t1 - t_i) == 0
    for k, v in per_unit_slip.items():
        assert sp.simplify(no_slip[k] + s_code * v - inst[k]) == 0, k
    print("  = the no-slip field + S x (the field of a unit slip velocity):", per_unit_slip,
          f"T0 = {t0}, T1 = {sp.factor(t1)}")
    # alpha -> infinity (free slip): a finite limit.
    print("  alpha -> infinity:", {k: sp.limit(v, alpha, sp.oo) for k, v in inst.items()})

    taylor = solve("taylor")
    s_t, t_t, diss_t, inner_t, t_m, t_d = report("taylor_quasi_steady", taylor)
    big_l = lam + 1 + 5 * alpha * lam
    spec = {A: -(5 * lam + 2 + 10 * alpha * lam) / big_l, B: -lam / (2 * big_l),
            C: -(5 * lam + 2 + 10 * alpha * lam) / big_l, K: -3 / (2 * big_l),
            M: 1 / (2 * big_l), Q: 21 * lam / (2 * big_l)}
    for k, v in spec.items():
        same = sp.simplify(taylor[k] - v) == 0
        print(f"  SPEC §10 {k} = {v}: {'agrees' if same else 'DIFFERS, derived ' + str(taylor[k])}")
    # The first-order deformation its normal-stress imbalance carries: the
    # h-part of n.(sigma_m - sigma_d) n, c h, balances Gamma (div n - 2) =
    # 4 Gamma f on r = 1 + f (f a degree-2 harmonic), so in simple shear
    # (E = (e_x e_y + e_y e_x)/2, h = xy) D = c / 8 Ca.
    jump_n = on_sphere((n.T * (t_m - t_d))[0] - 2 * gamma)
    c = sp.Symbol("c")
    c_val = sp.solve((jump_n - c * h).subs({e11: 0, e22: 0, e13: 0, e23: 0})
                     .subs({x: sp.Rational(3, 5), y: sp.Rational(4, 5), z: 0}), c)[0]
    assert on_sphere(jump_n - c_val * h) == 0
    d_over_ca = sp.factor(sp.simplify(c_val / 8))
    expected = (19 * lam + 16 + 80 * alpha * lam) / (16 * (1 + lam + 5 * alpha * lam))
    print(f"  normal-stress imbalance h-coefficient c = {sp.factor(c_val)};  D/Ca = c/8 = {d_over_ca}")
    assert sp.simplify(d_over_ca - expected) == 0
    print("  D/Ca = (19 lambda + 16 + 80 alpha lambda) / (16 (1 + lambda + 5 alpha lambda)) (SPEC §10)")

    # The sign of SPEC §9: with the law's sign flipped (thesis eq. 2.18 as
    # printed) the slip would feed energy in, and Lambda = lambda + 1 - 5 alpha lambda.
    flipped = solve("taylor", sign=-1)
    print("  with the Navier sign flipped: M =", flipped[M], "(Lambda = lambda + 1 - 5 alpha lambda)")
    assert sp.simplify(flipped[M] - 1 / (2 * (lam + 1 - 5 * alpha * lam))) == 0


if __name__ == "__main__":
    main()
