"""
Independent derivation: O(De) shift of the steady orientation angle of a nearly
spherical drop in simple shear, when drop (A) or matrix (B) is a second-order /
UCM fluid at small De (tau = eta*A1 - eta*lam_r*A1_upper).

Method: Taylor base flow (spherical drop, u.n = 0), Lorentz reciprocal theorem
with auxiliary normal-traction-driven flows, shape equation
  b S = a E + M + W S - S W   ->   dtheta = -m (2 lam + 3)/5,  M = m diag(1,-1,0)+...
All fields are written with x,y,z and a separate symbol R (=|x|); derivatives use
the chain rule d/dx_i = d/dx_i|_R + (x_i/R) d/dR.
"""
import os

import sympy as sp
from functools import lru_cache

x, y, z = sp.symbols('x y z', real=True)
R = sp.symbols('R', positive=True)
nx, ny, nz = sp.symbols('n_x n_y n_z', real=True)
lam = sp.symbols('lambda', positive=True)
X = [x, y, z]
Xv = sp.Matrix(X)
I3 = sp.eye(3)


def d(f, i):
    return sp.diff(f, X[i]) + X[i] / R * sp.diff(f, R)


def grad_vec(u):
    """L_ij = d u_i / d x_j"""
    return sp.Matrix(3, 3, lambda i, j: d(u[i], j))


def div_vec(u):
    return sum(d(u[i], i) for i in range(3))


def lap(f):
    return sum(d(d(f, i), i) for i in range(3))


def div_tens(T):
    return sp.Matrix([sum(d(T[i, j], j) for j in range(3)) for i in range(3)])


def stress(u, p, eta):
    L = grad_vec(u)
    return -p * I3 + eta * (L + L.T)


def on_sphere(expr):
    """evaluate at R=1, x=n"""
    return sp.sympify(expr).subs({R: 1}).subs({x: nx, y: ny, z: nz}, simultaneous=True)


def is_zero_on_sphere(expr):
    e = sp.together(sp.expand(on_sphere(expr)))
    num, den = sp.fraction(e)
    num = sp.expand(num)
    if num == 0:
        return True
    G = [nx**2 + ny**2 + nz**2 - 1]
    _, rem = sp.reduced(num, G, nx, ny, nz)
    return sp.simplify(rem) == 0


@lru_cache(None)
def sph_mono(a, b, c):
    if a % 2 or b % 2 or c % 2:
        return sp.Integer(0)
    return 2 * sp.gamma(sp.Rational(a + 1, 2)) * sp.gamma(sp.Rational(b + 1, 2)) * \
        sp.gamma(sp.Rational(c + 1, 2)) / sp.gamma(sp.Rational(a + b + c + 3, 2))


def angular_integral(expr_n):
    """integral over unit sphere of expression polynomial in nx,ny,nz (coeffs may depend on R, lam)"""
    expr_n = sp.expand(expr_n)
    P = sp.Poly(expr_n, nx, ny, nz)
    tot = 0
    for (a, b, c), coef in P.terms():
        tot += coef * sph_mono(a, b, c)
    return sp.simplify(tot)


def to_radial(expr):
    """substitute x = R n"""
    return sp.sympify(expr).subs({x: R * nx, y: R * ny, z: R * nz}, simultaneous=True)


def volume_integral(expr, inside):
    f = angular_integral(to_radial(expr))
    f = sp.simplify(f)
    if inside:
        return sp.simplify(sp.integrate(f * R**2, (R, 0, 1)))
    return sp.simplify(sp.integrate(f * R**2, (R, 1, sp.oo)))


def surface_integral(expr):
    return angular_integral(on_sphere(expr))


# sample points on unit sphere (rational)
base_pts = [(1, 2, 2, 3), (2, 3, 6, 7), (1, 4, 8, 9), (2, 6, 9, 11), (3, 4, 12, 13), (2, 10, 11, 15)]
PTS = []
for (a, b, c, n) in base_pts:
    for sx in (1, -1):
        for sy in (1, -1):
            PTS.append((sp.Rational(sx * a, n), sp.Rational(sy * b, n), sp.Rational(c, n)))
            PTS.append((sp.Rational(sy * c, n), sp.Rational(a, n), sp.Rational(sx * b, n)))


def solve_conditions(conds, unknowns):
    eqs = []
    for cexpr in conds:
        for pt in PTS:
            e = sp.sympify(cexpr).subs({R: 1}).subs({x: pt[0], y: pt[1], z: pt[2]}, simultaneous=True)
            e = sp.simplify(e)
            if e != 0:
                eqs.append(e)
    sol = sp.solve(eqs, unknowns, dict=True)
    assert len(sol) == 1, sol
    return sol[0]


# ---------------------------------------------------------------------------
# Shear flow
Lmat = sp.Matrix([[0, 1, 0], [0, 0, 0], [0, 0, 0]])
E = (Lmat + Lmat.T) / 2
W = (Lmat - Lmat.T) / 2


def l2_fields(Kmat, A, B, P, Q, eta_in):
    """generic l=2 interior/exterior Stokes fields for a symmetric traceless tensor Kmat"""
    Kx = Kmat * Xv
    xKx = (Xv.T * Kmat * Xv)[0, 0]
    u_in = A * Kx + B * (5 * R**2 * Kx - 2 * Xv * xKx)
    p_in = eta_in * 21 * B * xKx
    u_out = P * Xv * xKx / R**5 + Q * (Kx / R**5 - sp.Rational(5, 2) * Xv * xKx / R**7)
    p_out = 2 * P * xKx / R**5
    return u_in, p_in, u_out, p_out


def check_stokes(u, p, eta, label):
    """exact evaluation of residuals at many points with rational |x| (scaled Pythagorean quadruples)"""
    res = [eta * lap(ui) - d(p, i) for i, ui in enumerate(u)] + [div_vec(u)]
    ok = True
    for scale in (sp.Rational(1, 3), sp.Rational(1, 2), 2, 5):
        for pt in PTS[:12]:
            sub = {x: scale * pt[0], y: scale * pt[1], z: scale * pt[2], R: scale}
            for e in res:
                if sp.simplify(e.subs(sub)) != 0:
                    ok = False
    print(f"  Stokes+continuity check [{label}] (48 exact points):", ok)
    assert ok


report = {}

print("=== 1. Taylor base flow (spherical drop, u.n = 0) ===")
al, be, Pb, Qb = sp.symbols('alpha beta P_b Q_b')
ui_E, pi_E, uo_E, po_E = l2_fields(E, al, be, Pb, Qb, lam)
u_in = W * Xv + ui_E
p_in = pi_E
u_out = Lmat * Xv + uo_E
p_out = po_E
nvec = Xv / R
sig_in = stress(u_in, p_in, lam)
sig_out = stress(u_out, p_out, 1)
jump_t = (sig_out - sig_in) * nvec
tang = (I3 - nvec * nvec.T) * jump_t
conds = list(u_in - u_out) + [(u_in.T * nvec)[0, 0]] + list(tang)
solB = solve_conditions(conds, [al, be, Pb, Qb])
print("  base coefficients:", {k: sp.factor(v) for k, v in solB.items()})
u_in = sp.simplify(u_in.subs(solB)); p_in = sp.simplify(p_in.subs(solB))
u_out = sp.simplify(u_out.subs(solB)); p_out = sp.simplify(p_out.subs(solB))
check_stokes(u_in, p_in, lam, 'base in')
check_stokes(u_out, p_out, 1, 'base out')
sig_in = stress(u_in, p_in, lam)
sig_out = stress(u_out, p_out, 1)
ok = all(is_zero_on_sphere(c) for c in list(u_in - u_out) + [(u_in.T * nvec)[0, 0]] +
         list((I3 - nvec * nvec.T) * (sig_out - sig_in) * nvec))
print("  interface conditions hold for all n:", ok)
assert ok

print("=== 2a. free-interface drop in strain E (no tension): normal velocity a n.E.n ===")
a1, b1, P1, Q1 = sp.symbols('a1 b1 P1 Q1')
ui_f, pi_f, uo_f, po_f = l2_fields(E, a1, b1, P1, Q1, lam)
uo_f = E * Xv + uo_f   # pure strain far field
sig_if = stress(ui_f, pi_f, lam)
sig_of = stress(uo_f, po_f, 1)
conds = list(ui_f - uo_f) + list((sig_of - sig_if) * nvec)
solF = solve_conditions(conds, [a1, b1, P1, Q1])
ui_f = sp.simplify(ui_f.subs(solF)); pi_f = sp.simplify(pi_f.subs(solF))
uo_f = sp.simplify(uo_f.subs(solF)); po_f = sp.simplify(po_f.subs(solF))
un_f = sp.simplify(on_sphere((ui_f.T * nvec)[0, 0]))
a_coef = sp.simplify(un_f / on_sphere((Xv.T * E * Xv)[0, 0]))
print("  a =", sp.factor(a_coef), " expected 5/(2 lam+3):", sp.simplify(a_coef - 5 / (2 * lam + 3)) == 0)
assert sp.simplify(a_coef - 5 / (2 * lam + 3)) == 0
ok = all(is_zero_on_sphere(c) for c in list(ui_f - uo_f) + list((stress(uo_f, po_f, 1) - stress(ui_f, pi_f, lam)) * nvec))
print("  free-drop interface conditions hold for all n:", ok)

print("=== 2b. auxiliary problem: normal traction jump (n.K.n) n ===")
ks = sp.symbols('k1:6')
Kgen = sp.Matrix([[ks[0], ks[1], ks[2]], [ks[1], ks[3], ks[4]], [ks[2], ks[4], -ks[0] - ks[3]]])
Ak, Bk, Pk, Qk = sp.symbols('A_K B_K P_K Q_K')


def aux_solution(Kmat):
    ui, pi, uo, po = l2_fields(Kmat, Ak, Bk, Pk, Qk, lam)
    nKn = (nvec.T * Kmat * nvec)[0, 0]
    conds = list(ui - uo) + list((stress(uo, po, 1) - stress(ui, pi, lam)) * nvec - nKn * nvec)
    s = solve_conditions(conds, [Ak, Bk, Pk, Qk])
    return s


solK = aux_solution(Kgen)
print("  aux coefficients:", {k: sp.factor(v) for k, v in solK.items()})
# verify for generic K
uiK, piK, uoK, poK = [sp.simplify(f.subs(solK)) if hasattr(f, 'subs') else f for f in l2_fields(Kgen, Ak, Bk, Pk, Qk, lam)]
nKn = (nvec.T * Kgen * nvec)[0, 0]
ok = all(is_zero_on_sphere(c) for c in list(uiK - uoK) + list((stress(uoK, poK, 1) - stress(uiK, piK, lam)) * nvec - nKn * nvec))
print("  aux interface conditions hold for all n and generic K:", ok)
assert ok
mu_mob = sp.factor(sp.simplify(sp.factor(sp.simplify(-on_sphere((uiK.T * nvec)[0, 0]) / on_sphere(nKn))).subs(nz**2, 1 - nx**2 - ny**2)))
print("  normal velocity = -mu n.K.n, mu =", sp.factor(mu_mob))
Ca = sp.symbols('Ca', positive=True)
b_coef = sp.factor(4 * mu_mob / Ca)  # capillary jump (1/Ca)*div n = (1/Ca)(2 + 4 n.S.n)
print("  b = 4 mu/Ca =", b_coef, " expected 40(l+1)/((2l+3)(19l+16)Ca):",
      sp.simplify(b_coef - 40 * (lam + 1) / ((2 * lam + 3) * (19 * lam + 16) * Ca)) == 0)
assert sp.simplify(b_coef - 40 * (lam + 1) / ((2 * lam + 3) * (19 * lam + 16) * Ca)) == 0
# check the capillary l=2 curvature: div n for r = 1 + eps n.S.n  -> 2 + 4 eps nSn at O(eps)
eps = sp.symbols('epsilon')
S_t = sp.Matrix([[1, 2, 0], [2, -3, 1], [0, 1, 2]]) / 7
rr = sp.sqrt(x**2 + y**2 + z**2)
Fsurf = rr - 1 - eps * (Xv.T * S_t * Xv)[0, 0] / rr**2
gF = sp.Matrix([sp.diff(Fsurf, v) for v in X])
nF = gF / sp.sqrt((gF.T * gF)[0, 0])
divn = sum(sp.diff(nF[i], X[i]) for i in range(3))
pt = (sp.Rational(2, 7), sp.Rational(3, 7), sp.Rational(6, 7))
nSn_pt0 = (sp.Matrix(pt).T * S_t * sp.Matrix(pt))[0, 0]
# evaluate div n ON the perturbed surface r = 1 + eps nSn, then take d/d eps at 0
divn_s = divn.subs({x: (1 + eps * nSn_pt0) * pt[0], y: (1 + eps * nSn_pt0) * pt[1], z: (1 + eps * nSn_pt0) * pt[2]}, simultaneous=True)
val = sp.simplify(sp.diff(divn_s, eps).subs(eps, 0))
nSn_pt = (sp.Matrix(pt).T * S_t * sp.Matrix(pt))[0, 0]
print("  curvature check d(div n)/d eps = 4 nSn at sample pt:", sp.simplify(val - 4 * nSn_pt) == 0,
      " (div n at r=1:", sp.simplify(divn.subs(eps, 0).subs({x: pt[0], y: pt[1], z: pt[2]})), ")")

print("=== 2c. shape dynamics: steady b S = a E + M + W S - S W, angle ===")
mm, bb = sp.symbols('m b', positive=True)
aa = 5 / (2 * lam + 3)
# solve steady 2x2 (shear-plane) system with M = m diag(1,-1,0) exactly, then expand
s11, s12, s22 = sp.symbols('s11 s12 s22')
Sm = sp.Matrix([[s11, s12, 0], [s12, s22, 0], [0, 0, -s11 - s22]])
Mm = mm * sp.diag(1, -1, 0)
eqS = bb * Sm - (aa * E + Mm + W * Sm - Sm * W)
solS = sp.solve([eqS[0, 0], eqS[0, 1], eqS[1, 1]], [s11, s12, s22], dict=True)[0]
Ss = Sm.subs(solS)
tan2th = sp.simplify(2 * Ss[0, 1] / (Ss[0, 0] - Ss[1, 1]))
theta = sp.atan(tan2th) / 2  # tan2th > 0 -> theta in (0, pi/4)
# expansion for small 1/b and small m: theta = pi/4 - 1/(2b) - m/a + ...
t_ = sp.symbols('t')
th_ser = sp.series(sp.pi / 4 - sp.atan(1 / tan2th.subs({bb: 1 / t_, mm: t_ * 0 + mm})) / 2, t_, 0, 2)
print("  tan(2 theta) =", tan2th)
th1 = sp.simplify(sp.diff(sp.pi / 4 - sp.atan(1 / tan2th) / 2, bb).subs(mm, 0))
# angle = pi/4 - (1/2) arctan(1/tan2th);  1/tan2th = 1/b + 2m/a exactly
print("  1/tan(2theta) - (1/b + 2m/a) =", sp.simplify(1 / tan2th - (1 / bb + 2 * mm / aa)))
dth_dm = sp.simplify(sp.diff(-sp.atan(1 / tan2th) / 2, mm).subs({mm: 0}))
dth_dm_lead = sp.limit(dth_dm, bb, sp.oo)
print("  d theta/dm (b->inf) =", sp.factor(dth_dm_lead), "  expected -(2lam+3)/5")
assert sp.simplify(dth_dm_lead + (2 * lam + 3) / 5) == 0
newt = sp.factor((1 / (2 * b_coef)))
print("  Newtonian: theta = pi/4 - 1/(2b) = pi/4 -", newt, " matches Chaffey-Brenner:",
      sp.simplify(newt - Ca * (16 + 19 * lam) * (3 + 2 * lam) / (80 * (1 + lam))) == 0)


print("=== 3. reciprocal theorem: (8 pi/15) K:M = int tau':grad u_K dV [- int_S n.tau_inf.u_K dS] ===")
basis = {}
basis['xx-yy'] = sp.diag(1, -1, 0)
basis['xy'] = sp.Matrix([[0, 1, 0], [1, 0, 0], [0, 0, 0]])
basis['xx+yy-2zz'] = sp.diag(1, 1, -2)
basis['xz'] = sp.Matrix([[0, 0, 1], [0, 0, 0], [1, 0, 0]])
basis['yz'] = sp.Matrix([[0, 0, 0], [0, 0, 1], [0, 1, 0]])


def aux_fields(Kmat):
    sub = {ks[0]: Kmat[0, 0], ks[1]: Kmat[0, 1], ks[2]: Kmat[0, 2], ks[3]: Kmat[1, 1], ks[4]: Kmat[1, 2]}
    return [f.subs(sub) for f in (uiK, piK, uoK, poK)]


def M_from_reciprocal(tau_in=None, tau_out=None, tau_inf=None):
    """returns symmetric traceless M (l=2 part of normal velocity on r=1)"""
    vals = {}
    for name, Kmat in basis.items():
        ui, pi, uo, po = aux_fields(Kmat)
        tot = 0
        if tau_in is not None:
            Gi = grad_vec(ui)
            integrand = sum(tau_in[i, j] * Gi[i, j] for i in range(3) for j in range(3))
            tot += volume_integral(integrand, inside=True)
        if tau_out is not None:
            Go = grad_vec(uo)
            tt = tau_out - (tau_inf if tau_inf is not None else sp.zeros(3, 3))
            integrand = sum(tt[i, j] * Go[i, j] for i in range(3) for j in range(3))
            tot += volume_integral(integrand, inside=False)
            if tau_inf is not None:
                tot -= surface_integral((nvec.T * tau_inf * uo)[0, 0])
        vals[name] = sp.simplify(sp.Rational(15, 8) / sp.pi * tot)  # = K:M
    # reconstruct M from K:M values
    Ms = sp.symbols('M11 M12 M13 M22 M23')
    Mg = sp.Matrix([[Ms[0], Ms[1], Ms[2]], [Ms[1], Ms[3], Ms[4]], [Ms[2], Ms[4], -Ms[0] - Ms[3]]])
    eqs = [sum(Mg[i, j] * basis[nm][i, j] for i in range(3) for j in range(3)) - vals[nm] for nm in basis]
    s = sp.solve(eqs, Ms, dict=True)[0]
    return sp.simplify(Mg.subs(s))


def dev(T):
    return T - T.trace() / 3 * I3


print("  check 3a (Eshelby): uniform extra stress T inside drop")
Tu = sp.Matrix([[1, 2, 0], [2, -1, 3], [0, 3, 5]])
M_rec = M_from_reciprocal(tau_in=Tu)
print("   M(reciprocal) + dev(T)/(2lam+3) == 0 :", sp.simplify(M_rec + dev(Tu) / (2 * lam + 3)) == sp.zeros(3, 3))
# direct solution of the uniform-T problem
At, Bt, Pt, Qt = sp.symbols('A_T B_T P_T Q_T')
ui, pi, uo, po = l2_fields(dev(Tu), At, Bt, Pt, Qt, lam)
c0 = sp.symbols('c0')
pi = pi + c0
conds = list(ui - uo) + list(stress(uo, po, 1) * nvec - (stress(ui, pi, lam) + Tu) * nvec)
sT = solve_conditions(conds, [At, Bt, Pt, Qt, c0])
un_direct = sp.simplify(on_sphere((ui.T * nvec)[0, 0]).subs(sT))
un_expect = -on_sphere((nvec.T * dev(Tu) * nvec)[0, 0]) / (2 * lam + 3)
print("   direct solve: n.v = -n.dev(T).n/(2lam+3):", is_zero_on_sphere(un_direct - un_expect))

print("  check 3b: drop viscosity lam -> lam+delta in free-interface strain flow; expect M = da/dlam * E")
Ai = grad_vec(ui_f)
M_b = M_from_reciprocal(tau_in=(Ai + Ai.T))
expect = sp.diff(5 / (2 * lam + 3), lam) * E
print("   M == da/dlam E :", sp.simplify(M_b - expect) == sp.zeros(3, 3))
print("  check 3c: matrix viscosity 1 -> 1+delta (a = 5/(2lam/mu+3)); uses tau_inf subtraction")
Ao = grad_vec(uo_f)
M_c = M_from_reciprocal(tau_out=(Ao + Ao.T), tau_inf=2 * E)
mu_ = sp.symbols('mu', positive=True)
expect = sp.diff(5 / (2 * lam / mu_ + 3), mu_).subs(mu_, 1) * E
print("   M == da/dmu E :", sp.simplify(M_c - expect) == sp.zeros(3, 3))
M_c_wrong = M_from_reciprocal(tau_out=(Ao + Ao.T), tau_inf=None)
print("   (for info: without tau_inf treatment, M_xy would be", sp.factor(M_c_wrong[0, 1]), "instead of", sp.factor(expect[0, 1]), ")")


print("=== 4. viscoelastic extra stresses tau' = -eta lam_r A1_upper(base) ===")


def A1_upper(u):
    L = grad_vec(u)
    A1 = L + L.T
    conv = sp.Matrix(3, 3, lambda i, j: sum(u[k] * d(A1[i, j], k) for k in range(3)))
    return sp.simplify(conv - L * A1 - A1 * L.T)


Up_in = A1_upper(u_in)
Up_out = A1_upper(u_out)
Up_inf = A1_upper(Lmat * Xv)
print("  far-field A1_upper =", Up_inf, " -> N1 = 2 eta lam_r (Psi1 = 2 eta lam_r)")
# (A) UCM drop: tau_in = -lam * De_d * Up_in
M_A = M_from_reciprocal(tau_in=-lam * Up_in)
print("  (A) M per De_d =", sp.simplify(M_A))
mA = sp.simplify((M_A[0, 0] - M_A[1, 1]) / 2)
c_d = sp.factor(-mA * (2 * lam + 3) / 5)
print("  (A) c_d(lam) =", c_d)
# (B) UCM matrix: tau_out = -De_m * Up_out, tau_inf = -De_m*Up_inf
M_B = M_from_reciprocal(tau_out=-Up_out, tau_inf=-Up_inf)
print("  (B) M per De_m =", sp.simplify(M_B))
mB = sp.simplify((M_B[0, 0] - M_B[1, 1]) / 2)
c_m = sp.factor(-mB * (2 * lam + 3) / 5)
print("  (B) c_m(lam) =", c_m)

print("=== 5. comparison with Greco (2002) as transcribed ===")
greco_m = -(176 + 436 * lam + 323 * lam**2) / (30 * (1 + lam) * (16 + 19 * lam))      # times De_m
greco_d = -(9 * lam**2 + 6 * lam**3) / (8 * (1 + lam) * (16 + 19 * lam)) / lam        # times De_d (Ca p_d = De_d/lam)
print("  Greco c_m =", sp.factor(greco_m), "   ratio mine/Greco =", sp.factor(c_m / greco_m))
print("  Greco c_d =", sp.factor(greco_d), "   ratio mine/Greco =", sp.factor(c_d / greco_d))
for lv in (sp.Rational(1, 10), 1, 2, 5):
    print(f"  lam={lv}: c_d={sp.nsimplify(c_d.subs(lam, lv))}={float(c_d.subs(lam, lv)):.6f} rad "
          f"({float(c_d.subs(lam, lv) * 180 / sp.pi):.4f} deg); Greco c_d={float(greco_d.subs(lam, lv)):.6f}; "
          f"c_m={sp.nsimplify(c_m.subs(lam, lv))}={float(c_m.subs(lam, lv)):.6f} rad "
          f"({float(c_m.subs(lam, lv) * 180 / sp.pi):.4f} deg); Greco c_m={float(greco_m.subs(lam, lv)):.6f}")
import pickle
with open(os.path.join(os.path.dirname(os.path.abspath(__file__)), 'results.pkl'), 'wb') as fh:
    pickle.dump({'c_d': c_d, 'c_m': c_m, 'M_A': M_A, 'M_B': M_B}, fh)
