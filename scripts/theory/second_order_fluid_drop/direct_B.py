"""
Independent direct check of case (B) (Newtonian drop in UCM/SOF matrix) at given lambda.
Outside particular solution built degree by degree (tau' split into homogeneous parts),
ansatz v = sum c x^a R^(k-|a|) (1, log R), fitted by least squares collocation (residual
checked); then Lamb homogeneous solutions inside/outside fitted to the interface conditions.
"""
import sys, itertools
import sympy as sp
import numpy as np
x, y, z = sp.symbols('x y z', real=True)
R, t = sp.symbols('R t', positive=True)
X = [x, y, z]; Xv = sp.Matrix(X); I3 = sp.eye(3)
lam = sp.Rational(sys.argv[1]) if len(sys.argv) > 1 else sp.Integer(2)
LMAX = 8

def d(f, i):
    return sp.diff(f, X[i]) + X[i] / R * sp.diff(f, R)
def grad_vec(u):
    return sp.Matrix(3, 3, lambda i, j: d(u[i], j))
def lap(f):
    return sum(d(d(f, i), i) for i in range(3))

Lmat = sp.Matrix([[0, 1, 0], [0, 0, 0], [0, 0, 0]]); E = (Lmat + Lmat.T) / 2; W = (Lmat - Lmat.T) / 2
Pb = -(5 * lam + 2) / (2 * (lam + 1)); Qb = -lam / (lam + 1)
al = -sp.Rational(3, 2) / (lam + 1); be = sp.Rational(1, 2) / (lam + 1)
Ex = E * Xv; xEx = (Xv.T * E * Xv)[0, 0]
u_st = Pb * Xv * xEx / R**5
u_q = Qb * (Ex / R**5 - sp.Rational(5, 2) * Xv * xEx / R**7)
u_tag = Lmat * Xv + t**3 * u_st + t**5 * u_q
# sanity: base flow BCs at r=1 for the untagged field
u_in0 = W * Xv + al * Ex + be * (5 * R**2 * Ex - 2 * Xv * xEx)
Lt = grad_vec(u_tag); A1 = Lt + Lt.T
A1up = sp.Matrix(3, 3, lambda i, j: sum(u_tag[k] * d(A1[i, j], k) for k in range(3))) - Lt * A1 - A1 * Lt.T
A1up = A1up.applyfunc(sp.expand)
parts = {}
for k in range(0, 11):
    Pk = A1up.applyfunc(lambda e: e.coeff(t, k))
    if Pk != sp.zeros(3, 3):
        parts[k] = -Pk            # tau' per unit De_m (matrix viscosity 1)
print('homogeneous parts of tau_out (t-power = minus degree):', sorted(parts))
tau_full = sum((parts[k] for k in parts), sp.zeros(3, 3))
assert sp.simplify(tau_full - (-(A1up.subs(t, 1)))) == sp.zeros(3, 3)

# ---- collocation points
def sphere_pts(n, seed):
    rng = np.random.default_rng(seed)
    v = rng.normal(size=(3, n)); return v / np.linalg.norm(v, axis=0)

def mono_list(N):
    return [a for a in itertools.product(range(N + 1), repeat=3) if sum(a) <= N]

def mono_eval(a, P):   # P: 3 x n
    return P[0]**a[0] * P[1]**a[1] * P[2]**a[2]
def mono_grad(a, P):
    g = []
    for i in range(3):
        if a[i] == 0:
            g.append(np.zeros(P.shape[1]))
        else:
            b = list(a); b[i] -= 1
            g.append(a[i] * mono_eval(b, P))
    return np.array(g)
def mono_lap(a, P):
    s = np.zeros(P.shape[1])
    for i in range(3):
        if a[i] >= 2:
            b = list(a); b[i] -= 2
            s += a[i] * (a[i] - 1) * mono_eval(b, P)
    return s

def basis_ops(a, s, ell, P):
    """f = x^a R^s (log R)^ell : value, grad (3xn), laplacian"""
    D = sum(a); Rn = np.linalg.norm(P, axis=0); lg = np.log(Rn)
    m = mono_eval(a, P); gm = mono_grad(a, P); lm = mono_lap(a, P)
    Lg = lg**ell
    val = m * Rn**s * Lg
    grad = (gm * Rn**s + s * m * Rn**(s - 2) * P) * Lg + (ell * m * Rn**(s - 2) * P if ell else 0)
    lapv = (lm * Rn**s + s * (2 * D + s + 1) * m * Rn**(s - 2)) * Lg + (ell * (2 * D + 2 * s + 1) * m * Rn**(s - 2) if ell else 0)
    return val, grad, lapv

def grad_second(a, s, ell, P, h=None):
    pass

NV = 9
particular = []   # list of (k, coef vector, basis description)
for k, tau_k in sorted(parts.items()):
    if k == 0:
        continue    # uniform far-field stress: no body force
    g = sp.Matrix([sum(d(tau_k[i, j], j) for j in range(3)) for i in range(3)])
    g_f = sp.lambdify((x, y, z, R), list(g), 'numpy')
    kv = -(k - 1)     # velocity degree
    kp = -k           # pressure degree
    vb = [(a, kv - sum(a), ell) for a in mono_list(NV) for ell in (0, 1)]
    pb = [(a, kp - sum(a), ell) for a in mono_list(NV + 1) for ell in (0, 1)]
    Ppts = np.hstack([sphere_pts(500, k), 2.0 * sphere_pts(500, k + 100)])
    npt = Ppts.shape[1]
    Rn = np.linalg.norm(Ppts, axis=0)
    G = np.array([np.broadcast_to(np.asarray(c, float), (npt,)) for c in g_f(Ppts[0], Ppts[1], Ppts[2], Rn)])
    # unknown ordering: [v_x basis, v_y basis, v_z basis, p basis]
    nvb = len(vb); npb = len(pb)
    A = np.zeros((4 * npt, 3 * nvb + npb)); rhs = np.zeros(4 * npt)
    for jb, (a, s, ell) in enumerate(vb):
        val, grad, lapv = basis_ops(a, s, ell, Ppts)
        for i in range(3):
            A[i * npt:(i + 1) * npt, i * nvb + jb] = lapv          # momentum i
            A[3 * npt:, i * nvb + jb] = grad[i]                    # div v
    for jb, (a, s, ell) in enumerate(pb):
        val, grad, lapv = basis_ops(a, s, ell, Ppts)
        for i in range(3):
            A[i * npt:(i + 1) * npt, 3 * nvb + jb] = -grad[i]
    for i in range(3):
        rhs[i * npt:(i + 1) * npt] = -G[i]
    # scale rows by R^(something) to balance radii
    colsc = np.linalg.norm(A, axis=0); colsc[colsc == 0] = 1
    c, *_ = np.linalg.lstsq(A / colsc, rhs, rcond=1e-13)
    c = c / colsc
    res = A @ c - rhs
    print(f'  degree part k={k}: particular-solution residual max {np.abs(res).max():.2e} (rhs max {np.abs(rhs).max():.2e}), log-coef max {max(abs(c[i*nvb+j]) for i in range(3) for j,(a,s,ell) in enumerate(vb) if ell):.2e}')
    # verify on fresh points
    Pv = np.hstack([sphere_pts(200, 7 * k + 1), 3.7 * sphere_pts(200, 7 * k + 2)])
    particular.append((k, c, vb, pb, nvb))

def particular_fields(P):
    """velocity (3xn), and gradient L_ij (3x3xn) and pressure of the summed particular solution"""
    n = P.shape[1]
    U = np.zeros((3, n)); Lg = np.zeros((3, 3, n)); Pr = np.zeros(n)
    for (k, c, vb, pb, nvb) in particular:
        for jb, (a, s, ell) in enumerate(vb):
            val, grad, _ = basis_ops(a, s, ell, P)
            for i in range(3):
                cc = c[i * nvb + jb]
                if cc != 0:
                    U[i] += cc * val; Lg[i] += cc * grad
        for jb, (a, s, ell) in enumerate(pb):
            val, _, _ = basis_ops(a, s, ell, P)
            Pr += c[3 * nvb + jb] * val
    return U, Lg, Pr

# independent residual check of the summed particular solution by finite differences
Pchk = 1.7 * sphere_pts(5, 99)
h = 1e-3
def Ufun(P):
    return particular_fields(P)[0]
gtot = sp.Matrix([sum(d(tau_full[i, j], j) for j in range(3)) for i in range(3)])
gtot_f = sp.lambdify((x, y, z, R), list(gtot), 'numpy')
U0, L0, P0 = particular_fields(Pchk)
lapU = np.zeros_like(U0); gradP = np.zeros_like(U0)
for i in range(3):
    e = np.zeros((3, 1)); e[i] = h
    Up_, _, Pp_ = particular_fields(Pchk + e); Um_, _, Pm_ = particular_fields(Pchk - e)
    lapU += (Up_ - 2 * U0 + Um_) / h**2
    gradP[i] = (Pp_ - Pm_) / (2 * h)
Gchk = np.array([np.broadcast_to(np.asarray(c, float), (5,)) for c in gtot_f(*Pchk, np.linalg.norm(Pchk, axis=0))])
print('  FD check of summed particular solution: max |lap v - grad p + div tau| =', np.abs(lapU - gradP + Gchk).max(), ' scale', np.abs(Gchk).max())

# ---- Lamb homogeneous solutions (same as direct_A)
def harmonic_basis(l):
    mons = [x**a * y**b * z**(l - a - b) for a in range(l + 1) for b in range(l + 1 - a)]
    if l < 2:
        return mons
    cs = sp.symbols(f'h0:{len(mons)}')
    poly = sum(c * m for c, m in zip(cs, mons))
    lp = sp.expand(sum(sp.diff(poly, v_, 2) for v_ in X))
    tmons = [x**a * y**b * z**(l - 2 - a - b) for a in range(l - 1) for b in range(l - 1 - a)]
    P = sp.Poly(lp, x, y, z)
    rows = [[sp.diff(P.coeff_monomial(tm), c) for c in cs] for tm in tmons]
    ns = sp.Matrix(rows).nullspace()
    assert len(ns) == 2 * l + 1
    return [sp.expand(sum(n_[kk] * mons[kk] for kk in range(len(mons)))) for n_ in ns]

def curl_x(hh):
    return sp.Matrix([d(hh * z, 1) - d(hh * y, 2), d(hh * x, 2) - d(hh * z, 0), d(hh * y, 0) - d(hh * x, 1)])
fields_in, fields_out = [], []
for l in range(0, LMAX + 1):
    for hh in harmonic_basis(l):
        if l >= 1:
            fields_in.append((curl_x(hh), 0))
            fields_in.append((sp.Matrix([d(hh, i) for i in range(3)]), 0))
        ui = (sp.Rational(l + 3, 2 * (l + 1) * (2 * l + 3)) * R**2 * sp.Matrix([d(hh, i) for i in range(3)])
              - sp.Rational(l, (l + 1) * (2 * l + 3)) * Xv * hh)
        fields_in.append((ui, lam * hh))
        hd = hh / R**(2 * l + 1)
        if l >= 1:
            fields_out.append((curl_x(hd), 0))
        fields_out.append((sp.Matrix([d(hd, i) for i in range(3)]), 0))
        if l >= 1:
            uo = (-sp.Rational(l - 2, 2 * l * (2 * l - 1)) * R**2 * sp.Matrix([d(hd, i) for i in range(3)])
                  + sp.Rational(l + 1, l * (2 * l - 1)) * Xv * hd)
            fields_out.append((uo, hd))
print('Lamb basis sizes', len(fields_in), len(fields_out))

ng, nphi = 20, 42
mu, wmu = np.polynomial.legendre.leggauss(ng)
phis = np.arange(nphi) * 2 * np.pi / nphi
MU, PH = np.meshgrid(mu, phis, indexing='ij')
WT = (wmu[:, None] * np.ones(nphi)[None, :] * 2 * np.pi / nphi).ravel()
N = np.vstack([(np.sqrt(1 - MU**2) * np.cos(PH)).ravel(), (np.sqrt(1 - MU**2) * np.sin(PH)).ravel(), MU.ravel()])
npts = N.shape[1]

def eval_vel_trac(u, pr, eta):
    Lg = grad_vec(u)
    sig = -pr * I3 + eta * (Lg + Lg.T)
    f_u = sp.lambdify((x, y, z, R), list(u), 'numpy')
    f_s = sp.lambdify((x, y, z, R), list(sig), 'numpy')
    U = np.array([np.broadcast_to(np.asarray(c, dtype=float), (npts,)) for c in f_u(N[0], N[1], N[2], 1.0)])
    S = np.array([np.broadcast_to(np.asarray(c, dtype=float), (npts,)) for c in f_s(N[0], N[1], N[2], 1.0)]).reshape(3, 3, npts)
    return U, np.einsum('ijn,jn->in', S, N)

cols = []
for (u, pr) in fields_in:
    U, T = eval_vel_trac(u, pr, float(lam)); cols.append(np.concatenate([U.ravel(), -T.ravel()]))
for (u, pr) in fields_out:
    U, T = eval_vel_trac(u, pr, 1.0); cols.append(np.concatenate([-U.ravel(), T.ravel()]))
A = np.array(cols).T
# particular part (outside) + full extra stress traction at r=1
Up, Lp, Pp = particular_fields(N)
Sp = -Pp[None, None, :] * np.eye(3)[:, :, None] + (Lp + Lp.transpose(1, 0, 2))
tau_f = sp.lambdify((x, y, z, R), list(tau_full), 'numpy')
TAU = np.array([np.broadcast_to(np.asarray(c, float), (npts,)) for c in tau_f(N[0], N[1], N[2], 1.0)]).reshape(3, 3, npts)
Tp = np.einsum('ijn,jn->in', Sp + TAU, N)
# conditions: v_in - v_out_hom - v_p = 0 ; (sig_out_hom + sig_p + tau) n - sig_in n = 0
rhs = np.concatenate([Up.ravel(), -Tp.ravel()])
sqw = np.sqrt(np.tile(WT, 6))
coef, *_ = np.linalg.lstsq(A * sqw[:, None], rhs * sqw, rcond=None)
print('interface collocation residual max:', np.abs(A @ coef - rhs).max(), ' rhs max', np.abs(rhs).max())
nin = len(fields_in)
Uin = np.zeros((3, npts))
for kk in range(nin):
    Uin += coef[kk] * A[:3 * npts, kk].reshape(3, npts)
vn = np.einsum('in,in->n', Uin, N)
Kb = {'xx-yy': np.diag([1., -1, 0]), 'xy': np.array([[0, 1., 0], [1, 0, 0], [0, 0, 0]]), 'xx+yy-2zz': np.diag([1., 1, -2])}
KM = {kn: 15 / (8 * np.pi) * np.sum(WT * np.einsum('in,ij,jn->n', N, K, N) * vn) for kn, K in Kb.items()}
m = KM['xx-yy'] / 2
print('direct: K:M =', KM)
print(f'direct: c_m = -m(2lam+3)/5 = {-m*(2*float(lam)+3)/5:.10f}')
cm = -(19 * lam**2 + 32 * lam + 16) / (2 * (lam + 1) * (19 * lam + 16))
print('reciprocal formula c_m =', cm, '=', float(cm))
MB_zz = -(475 * lam**3 + 1920 * lam**2 + 2088 * lam + 832) / (42 * (lam + 1)**2 * (2 * lam + 3) * (19 * lam + 16))
print('reciprocal K:M for diag(1,1,-2) = -3 M_zz =', float(-3 * MB_zz))
print('Greco-transcribed c_m =', float(-(176 + 436 * lam + 323 * lam**2) / (30 * (1 + lam) * (16 + 19 * lam))))
