"""Lobatto IIIA / IIIB / SPARK constraint coefficients, exact (sympy) and in
arbitrary precision (mpmath), plus float64 tables for spark.py.

Definitions (s >= 2 stages, nodes on [0, 1]):

  c_1 = 0, c_s = 1, c_2..c_{s-1} = (1 + x_k)/2, x_k the roots of P'_{s-1}(x)
  b_j   : sum_j b_j c_j^(k-1) = 1/k,            k = 1..s      (quadrature B(2s-2))
  A     : sum_j a_ij c_j^(k-1) = c_i^k / k,     k = 1..s      (Lobatto IIIA, C(s))
  Abar  : abar_ij = b_j (1 - a_ji / b_i)                      (Lobatto IIIB, D(s);
          the symplectic conjugate of IIIA: b_i abar_ij + b_j a_ji = b_i b_j)
  W     : (s-1) x s matrix of constraint weights = rows 2..s of A   (odelab, GI)
  Omega : s x (s+1) matrix = inv([A_{2:s,:}; e_s^T]) [[A_{2:s,:}, 0], [0, 1]]
          (odelab Spark.compute_mean_stage_constraint == GI lobatto_omega_matrix)
  w     : null vector of A_{2:s,:} normalised w_s = 1 (Omega = [I - w e_s^T | w])
"""
from fractions import Fraction
import numpy as np
import sympy as sp
import mpmath as mp


# ---------------------------------------------------------------- exact (sympy)
def lobatto_nodes_exact(s):
    """Exact nodes for s <= 5 (P'_{s-1} has degree s-2 <= 3, roots 0 and +-sqrt(r))."""
    x = sp.Symbol('x')
    if s == 2:
        xs = []
    else:
        dP = sp.Poly(sp.diff(sp.legendre(s - 1, x), x), x)
        xs = sorted(sp.roots(dP, x).keys(), key=lambda r: float(r))
    return [sp.Integer(0)] + [sp.radsimp((1 + r) / 2) for r in xs] + [sp.Integer(1)]


def tableaus_exact(s):
    """Exact tableaus in the number field Q(c_2, ..., c_{s-1}) (sympy DomainMatrix).

    Returns dict of sympy Matrices c, b, A (IIIA), B (IIIB), W, Omega, w.
    """
    from sympy.polys.matrices import DomainMatrix
    c = lobatto_nodes_exact(s)
    gens = [ci for ci in c if not ci.is_Rational]
    K = sp.QQ.algebraic_field(*gens) if gens else sp.QQ
    cK = [K.from_sympy(ci) for ci in c]
    one = K.one
    Vt = DomainMatrix([[cK[j] ** k for j in range(s)] for k in range(s)], (s, s), K)  # V[k,j]=c_j^k
    rhs_b = DomainMatrix([[K.from_sympy(sp.Rational(1, k + 1))] for k in range(s)], (s, 1), K)
    b = Vt.lu_solve(rhs_b)
    rhs_A = DomainMatrix([[cK[i] ** (k + 1) * K.from_sympy(sp.Rational(1, k + 1)) for i in range(s)]
                          for k in range(s)], (s, s), K)
    A = Vt.lu_solve(rhs_A).transpose()            # A[i, j]
    bl = [b[j, 0].element for j in range(s)]
    Al = [[A[i, j].element for j in range(s)] for i in range(s)]
    Bl = [[bl[j] * (one - Al[j][i] / bl[i]) for j in range(s)] for i in range(s)]
    L = DomainMatrix([Al[i] for i in range(1, s)] + [[K.zero] * (s - 1) + [one]], (s, s), K)
    Q0 = DomainMatrix([Al[i] + [K.zero] for i in range(1, s)] + [[K.zero] * s + [one]], (s, s + 1), K)
    Linv = L.inv()
    Om = Linv * Q0
    tosym = lambda e: sp.expand(sp.radsimp(sp.expand(K.to_sympy(e))))
    M = lambda rows: sp.Matrix([[tosym(e) for e in r] for r in rows])
    return dict(c=sp.Matrix(c), b=sp.Matrix([tosym(e) for e in bl]), A=M(Al), B=M(Bl),
                W=M(Al[1:]), Omega=M([[Om[i, j].element for j in range(s + 1)] for i in range(s)]),
                w=sp.Matrix([tosym(Linv[i, s - 1].element) for i in range(s)]))


# --------------------------------------------------------- arbitrary precision
def lobatto_nodes_mp(s, dps=50):
    """Nodes on [0,1]: roots of P'_{s-1} by Newton from Chebyshev-Gauss-Lobatto guesses."""
    with mp.workdps(dps + 10):
        xs = []
        n = s - 1
        for k in range(1, s - 1):
            x = -mp.cos(mp.pi * k / n)                  # CGL guess
            for _ in range(100):
                # P'_n and P''_n from the Legendre ODE: (1-x^2)P'' = 2xP' - n(n+1)P
                P = mp.legendre(n, x)
                dP = mp.diff(lambda t: mp.legendre(n, t), x)
                d2P = (2 * x * dP - n * (n + 1) * P) / (1 - x * x)
                dx = dP / d2P
                x -= dx
                if abs(dx) < mp.mpf(10) ** (-(dps + 5)):
                    break
            xs.append(x)
        c = [mp.mpf(0)] + [(1 + x) / 2 for x in xs] + [mp.mpf(1)]
        return c


def tableaus_mp(s, dps=50):
    with mp.workdps(dps + 10):
        c = lobatto_nodes_mp(s, dps)
        V = mp.matrix(s, s)
        for k in range(s):
            for j in range(s):
                V[k, j] = c[j] ** k
        b = mp.lu_solve(V, mp.matrix([mp.mpf(1) / (k + 1) for k in range(s)]))
        A = mp.matrix(s, s)
        for i in range(s):
            row = mp.lu_solve(V, mp.matrix([c[i] ** (k + 1) / (k + 1) for k in range(s)]))
            for j in range(s):
                A[i, j] = row[j]
        B = mp.matrix(s, s)
        for i in range(s):
            for j in range(s):
                B[i, j] = b[j] * (1 - A[j, i] / b[i])
        L = mp.matrix(s, s)
        for i in range(s - 1):
            for j in range(s):
                L[i, j] = A[i + 1, j]
        L[s - 1, s - 1] = 1
        Linv = L ** -1
        Q0 = mp.matrix(s, s + 1)
        for i in range(s - 1):
            for j in range(s):
                Q0[i, j] = A[i + 1, j]
        Q0[s - 1, s] = 1
        Om = Linv * Q0
        w = [Linv[i, s - 1] for i in range(s)]
        return dict(c=c, b=[b[i] for i in range(s)], A=A, B=B, Omega=Om, w=w)


def mp2np(x, shape=None):
    if isinstance(x, mp.matrix):
        return np.array([[float(x[i, j]) for j in range(x.cols)] for i in range(x.rows)])
    return np.array([float(v) for v in x])


class Tableau:
    """float64 coefficients for spark.py (rounded once from 50-digit values)."""
    _cache = {}

    def __new__(cls, s):
        if s in cls._cache:
            return cls._cache[s]
        t = super().__new__(cls)
        T = tableaus_mp(s, 50)
        t.s = s
        t.c = mp2np(T['c'])
        t.b = mp2np(T['b'])
        t.A = mp2np(T['A'])
        t.B = mp2np(T['B'])
        t.Omega = mp2np(T['Omega'])
        t.w = mp2np(T['w'])
        t.W = t.A[1:, :].copy()            # constraint weights, odelab/GI ("IIIA rows 2..s")
        cls._cache[s] = t
        return t


# ------------------------------------------------------- plain float64 (what a Rust port would do)
def legendre_f64(n, x):
    """P_n(x), P_n'(x) by the three-term recurrence (n >= 1)."""
    p0, p1 = 1.0, x
    for k in range(2, n + 1):
        p0, p1 = p1, ((2 * k - 1) * x * p1 - (k - 1) * p0) / k
    dp = n * (x * p1 - p0) / (x * x - 1.0)           # valid for |x| < 1
    return p1, dp


def tableaus_f64(s):
    """Nodes by Newton on P'_{s-1} (P'' from the Legendre ODE), weights by the closed formula
    b_j = 1 / (s (s-1) P_{s-1}(2c_j-1)^2), A by the C(s) Vandermonde solve, Abar = b_j(1 - a_ji/b_i)."""
    n = s - 1
    xs = []
    for k in range(1, s - 1):
        x = -np.cos(np.pi * k / n)
        for _ in range(50):
            P, dP = legendre_f64(n, x)
            d2P = (2 * x * dP - n * (n + 1) * P) / (1 - x * x)
            dx = dP / d2P
            x -= dx
            if abs(dx) < 1e-17:
                break
        xs.append(x)
    c = np.array([0.0] + [(1 + x) / 2 for x in xs] + [1.0])
    b = np.array([1.0 / (s * (s - 1) * legendre_f64(n, 2 * cj - 1)[0] ** 2) if 0 < cj < 1
                  else 1.0 / (s * (s - 1)) for cj in c])
    V = np.vander(c, s, increasing=True).T                 # V[k, j] = c_j^k
    A = np.array([np.linalg.solve(V, c[i] ** np.arange(1, s + 1) / np.arange(1, s + 1)) for i in range(s)])
    B = b[None, :] * (1 - A.T / b[:, None])
    return c, b, A, B


def verify(s, dps=50):
    """Residuals of the defining conditions at `dps` digits (all should be ~10^-dps)."""
    with mp.workdps(dps + 10):
        T = tableaus_mp(s, dps)
        c, b, A, B = T['c'], T['b'], T['A'], T['B']
        r = {}
        r['B(2s-2)'] = max(abs(sum(b[j] * c[j] ** (k - 1) for j in range(s)) - mp.mpf(1) / k) for k in range(1, 2 * s - 1))
        r['C(s) IIIA'] = max(abs(sum(A[i, j] * c[j] ** (k - 1) for j in range(s)) - c[i] ** k / k) for i in range(s) for k in range(1, s + 1))
        r['D(s) IIIB'] = max(abs(sum(b[i] * c[i] ** (k - 1) * B[i, j] for i in range(s)) - b[j] * (1 - c[j] ** k) / k) for j in range(s) for k in range(1, s + 1))
        r['C(s-2) IIIB'] = max(abs(sum(B[i, j] * c[j] ** (k - 1) for j in range(s)) - c[i] ** k / k) for i in range(s) for k in range(1, s - 1)) if s > 2 else mp.mpf(0)
        r['IIIB last col'] = max(abs(B[i, s - 1]) for i in range(s))
        r['sym A'] = max(abs(A[i, j] + A[s - 1 - i, s - 1 - j] - b[j]) for i in range(s) for j in range(s))
        r['sym B'] = max(abs(B[i, j] + B[s - 1 - i, s - 1 - j] - b[j]) for i in range(s) for j in range(s))
        r['W w = 0'] = max(abs(sum(A[i, j] * T['w'][j] for j in range(s))) for i in range(1, s))
        # Omega == [I - w e_s^T | w]
        Om = T['Omega']
        ref = lambda i, j: ((1 if i == j else 0) - (T['w'][i] if j == s - 1 else 0)) if j < s else T['w'][i]
        r['Omega form'] = max(abs(Om[i, j] - ref(i, j)) for i in range(s) for j in range(s + 1))
        # reversal symmetry of w: w_{s+1-j} = (-1)^(s+1) w_j
        r['w reversal'] = max(abs(T['w'][s - 1 - j] - (-1) ** (s + 1) * T['w'][j]) for j in range(s))
        # closed-form weights b_j = 1/(s(s-1) P_{s-1}(2c_j-1)^2)
        r['b closed form'] = max(abs(b[j] - 1 / (s * (s - 1) * mp.legendre(s - 1, 2 * c[j] - 1) ** 2)) for j in range(s))
        # plain float64 construction (Newton + recurrence + Vandermonde), error vs 50 digits
        cf, bf, Af, Bf = tableaus_f64(s)
        r['f64 build: c'] = max(abs(cf[j] - c[j]) for j in range(s))
        r['f64 build: b'] = max(abs(bf[j] - b[j]) for j in range(s))
        r['f64 build: A'] = max(abs(Af[i, j] - A[i, j]) for i in range(s) for j in range(s))
        r['f64 build: Abar'] = max(abs(Bf[i, j] - B[i, j]) for i in range(s) for j in range(s))
        return {k: float(v) for k, v in r.items()}


ODELAB = {  # odelab/scheme/rungekutta.py LobattoIIIA / LobattoIIIB stage blocks (rows 0..s-1, cols 1..)
}


if __name__ == '__main__':
    import sys
    smax = int(sys.argv[1]) if len(sys.argv) > 1 else 5
    for s in range(2, smax + 1):
        print(f"===== s = {s}")
        if s <= 5:
            T = tableaus_exact(s)
            Tm = tableaus_mp(s, 50)
            diff = max(abs(float(T[k][i, j]) - float(Tm[k][i, j])) for k in ('A', 'B', 'Omega') for i in range(T[k].rows) for j in range(T[k].cols))
            print('max |exact - mp50| (A, B, Omega):', diff)
            for k in ('c', 'b', 'A', 'B', 'Omega', 'w'):
                print(k, '=', T[k].tolist())
        else:
            T = tableaus_mp(s, 50)
            r = sp.sqrt(sp.Integer(21)) if s == 5 else None
            def ident(x):
                return sp.nsimplify(sp.Float(mp.nstr(x, 45), 45), [r] if r is not None else [], tolerance=1e-40) if r is not None else mp.nstr(x, 20)
            print('c =', [ident(x) for x in T['c']])
            print('b =', [ident(x) for x in T['b']])
            for k in ('A', 'B', 'Omega'):
                M = T[k]
                print(k, '=', [[ident(M[i, j]) for j in range(M.cols)] for i in range(M.rows)])
            print('w =', [ident(x) for x in T['w']])
        print('residuals (50 digits):', verify(s))
