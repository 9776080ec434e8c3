# Is div(A1_upper) of the base Stokes flows a gradient?  (curl == 0 ?)
import sympy as sp, re
src = open('derive.py').read()
cut = src.index('print("=== 2a.')
exec(src[:cut])
def A1_upper(u):
    L = grad_vec(u); A1 = L + L.T
    conv = sp.Matrix(3, 3, lambda i, j: sum(u[k] * d(A1[i, j], k) for k in range(3)))
    return conv - L * A1 - A1 * L.T
for name, u in (('in', u_in), ('out', u_out)):
    U = A1_upper(u)
    f = div_tens(U)
    curl = [d(f[2],1)-d(f[1],2), d(f[0],2)-d(f[2],0), d(f[1],0)-d(f[0],1)]
    vals=[]
    for pt in PTS[:6]:
        for sc in (sp.Rational(1,2), 3):
            sub={x:sc*pt[0],y:sc*pt[1],z:sc*pt[2],R:sc}
            vals.append([sp.simplify(c.subs(sub).subs(lam,2)) for c in curl])
    print(name, 'curl(div A1_upper) sample values (lam=2):', vals[:3])
    print(name, 'all zero:', all(v==0 for vv in vals for v in vv))
