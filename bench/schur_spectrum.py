#!/usr/bin/env python3
"""Spectrum of the viscosity-weighted pressure mass as a Schur complement
approximation: the generalized eigenvalues mu of  S v = mu (M/eta) v,
S = G^T A^-1 G, for one drop at 34k unknowns and several viscosity ratios,
with where the extreme modes live (drop or matrix pressure unknowns) and
what scaling the drop's block of M/eta by f does to the spread.

Why: the iterative solver's iteration count spreads 1.63x over lambda =
0.01 ... 100 (docs/stokes_engine.md), and with an exact velocity solve
already 1.86x; this shows which pressure modes -M/eta gets wrong.

Usage: bench/schur_spectrum.py [build] [work]  (needs python3-scipy).
The matrices come from softflow runs with PETSc's -ksp_view_mat dumps:
the whole operator from the direct path, -M/eta from the iterative one.
"""
import os
import subprocess
import sys

import numpy as np
import scipy.linalg as la
import scipy.sparse as sp
import scipy.sparse.linalg as spl

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import run_scaling_bench as scaling  # noqa: E402

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
LAMBDAS = [0.01, 1.0, 100.0]
SCALINGS = {0.01: [1.0, 0.5, 0.3], 1.0: [1.0], 100.0: [1.0, 1.5, 2.0, 3.0]}


def read_aij(path):
    """The first matrix of a PETSc binary file (big-endian AIJ)."""
    with open(path, "rb") as f:
        head = np.frombuffer(f.read(16), ">i4")
        assert head[0] == 1211216, "not a PETSc matrix file"
        m, n, nz = (int(v) for v in head[1:])
        lengths = np.frombuffer(f.read(4 * m), ">i4").astype(np.int64)
        columns = np.frombuffer(f.read(4 * nz), ">i4")
        values = np.frombuffer(f.read(8 * nz), ">f8")
    return sp.csr_matrix((values, columns, np.concatenate([[0], np.cumsum(lengths)])), shape=(m, n))


def dump(build, work, lam):
    """K (direct path, whole operator) and -M/eta (iterative path) for lambda."""
    k, m = os.path.join(work, f"K_{lam:g}.bin"), os.path.join(work, f"M_{lam:g}.bin")
    if os.path.exists(k) and os.path.exists(m):
        return k, m
    text = scaling.case_text("1drop_40k", "solve", lam)
    for kind, option, out in (("direct", "-stokes_ksp_view_mat", k),
                              ("iterative", "-stokes_fieldsplit_pressure_ksp_view_pmat", m)):
        case = os.path.join(work, f"{kind}_{lam:g}.toml")
        open(case, "w").write(text.replace('type = "iterative"', f'type = "{kind}"'))
        env = dict(os.environ, PETSC_OPTIONS=f"{option} binary:{out}")
        subprocess.run([os.path.join(build, "softflow"), "run", case, "-o",
                        os.path.join(work, f"out_{kind}_{lam:g}"), "-q", "--overwrite"],
                       check=True, env=env)
    return k, m


def pressure_split(K):
    """Pressure rows of the direct operator (zero diagonal) and its pinned
    gauge: an identity row; Dirichlet velocity rows come as identity
    triples, so the gauge is the 4th of the one run of 4 ([u v w p] of a
    wall vertex)."""
    d = K.diagonal()
    identity = np.array([d[i] == 1.0 and np.count_nonzero(K.data[K.indptr[i]:K.indptr[i + 1]]) == 1
                         for i in range(K.shape[0])])
    runs, i = [], 0
    while i < len(identity):
        if identity[i]:
            j = i
            while j + 1 < len(identity) and identity[j + 1]:
                j += 1
            runs.append((i, j - i + 1))
            i = j + 1
        else:
            i += 1
    odd = [r for r in runs if r[1] % 3]
    assert len(odd) == 1 and odd[0][1] == 4, f"cannot find the pinned gauge: {odd}"
    gauge = odd[0][0] + 3
    pressure = np.where(d == 0.0)[0]
    every = np.sort(np.concatenate([pressure, [gauge]]))
    return pressure, every, int(np.searchsorted(every, gauge))


def main():
    build = sys.argv[1] if len(sys.argv) > 1 else os.path.join(ROOT, "build")
    work = sys.argv[2] if len(sys.argv) > 2 else os.path.join(ROOT, "output", "schur_spectrum")
    os.makedirs(work, exist_ok=True)
    mass_at_1 = None
    for lam in sorted(LAMBDAS, key=lambda v: v != 1.0):  # lambda = 1 first: it marks the drop's dofs
        k_path, m_path = dump(build, work, lam)
        K = read_aij(k_path)
        pressure, every, pinned = pressure_split(K)
        velocity = np.setdiff1d(np.arange(K.shape[0]), every)
        A = K[velocity][:, velocity].tocsc()
        G = K[velocity][:, pressure].toarray()
        S = G.T @ spl.splu(A).solve(G)
        S = 0.5 * (S + S.T)
        keep = [i for i in range(len(every)) if i != pinned]
        M = -read_aij(m_path).toarray()
        M = 0.5 * (M + M.T)[np.ix_(keep, keep)]
        if mass_at_1 is None:
            mass_at_1 = np.diag(M).copy()
        drop = np.abs(np.diag(M) - mass_at_1) > 1e-12 * np.abs(mass_at_1)
        mu, V = la.eigh(S, M)
        # mu[0] ~ 4e-5: the constant pressure, only pinned at one node.
        share = lambda v: ((v * (M @ v))[drop].sum() / (v * (M @ v)).sum())  # noqa: E731
        n = len(mu)
        top = np.mean([share(V[:, i]) for i in range(int(0.95 * n), n)])
        low = np.mean([share(V[:, i]) for i in range(1, 4)])
        print(f"lambda {lam:g}: {K.shape[0]} unknowns, {n} pressure unknowns ({int(drop.sum())} in the drop)")
        print(f"  mu without the gauge mode: {mu[1]:.3g} ... {mu[-1]:.3g}; quantiles 1/5/50/95/99 %: "
              + " ".join(f"{q:.3g}" for q in np.quantile(mu[1:], [0.01, 0.05, 0.5, 0.95, 0.99])))
        print(f"  share on drop dofs: lowest 3 modes {low:.2f}, top 5 % {top:.2f}")
        for f in SCALINGS[lam]:
            s = np.where(drop, np.sqrt(f), 1.0)
            m2 = np.sort(la.eigh(S, M * np.outer(s, s), eigvals_only=True))[1:]
            print(f"  drop block of M/eta x {f:g}: mu {m2[0]:.3g} ... {m2[-1]:.3g}, ratio {m2[-1] / m2[0]:.1f}")


if __name__ == "__main__":
    main()
