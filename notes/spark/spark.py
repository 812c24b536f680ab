"""Lobatto IIIA-IIIB SPARK step for nonholonomic mechanical systems (numpy prototype).

System class:  q in R^N,  L = 1/2 qdot^T M qdot - V(q),  A(q) qdot = 0  (m rows)
    qdot = v,   M vdot = -grad V(q) + A(q)^T lambda,   A(q) v = 0.

One step (q0, v0) -> (q1, v1), s >= 2 Lobatto stages, a = IIIA, abar = IIIB, b weights,
W = constraint weights ((s-1) x s); default W = rows 2..s of IIIA (odelab Spark, GI SPARK):

    Q_i   = q0 + h sum_j a_ij V_j                                         i = 1..s
    M V_i = M v0 + h sum_j abar_ij ( -grad V(Q_j) + A(Q_j)^T Lambda_j )   i = 1..s
    0     = sum_j W_kj A(Q_j) V_j                                         k = 1..s-1
    q1    = q0 + h sum_j b_j V_j          (= Q_s)
    M v1  = M v0 + h sum_j b_j ( -grad V(Q_j) + A(Q_j)^T Lambda_j )
    0     = A(q1) v1

Unknowns: V_1..V_s (s N) and Lambda_1..Lambda_s (s m); s(N+m) equations.
Newton is run on X = (V, Z) with Z_j = h Lambda_j (scales the saddle-point blocks alike).
"""
import numpy as np
from coeffs import Tableau


class Mechanical:
    """Base class. Subclasses set N, m, M and define gradV, hessV, A, dA.

    dA(q)[r, n, l] = d A_{rn} / d q_l   (shape m x N x N)
    """
    def setup(self):
        self.Minv = np.linalg.inv(self.M)

    def J(self, q, u):      # d(A(q) u)/dq, m x N
        return np.einsum('rnl,n->rl', self.dA(q), u)

    def K(self, q, z):      # d(A(q)^T z)/dq, N x N
        return np.einsum('rnl,r->nl', self.dA(q), z)

    def energy(self, q, v):
        return 0.5 * v @ self.M @ v + self.V(q)

    def lam(self, q, v):
        """Continuous multiplier: (A M^-1 A^T) lam = A M^-1 grad V - J(q, v) v."""
        A = self.A(q)
        S = A @ self.Minv @ A.T
        return np.linalg.solve(S, A @ self.Minv @ self.gradV(q) - self.J(q, v) @ v)

    def rhs(self, t, y):
        """Index-1 ODE with lambda eliminated (for the reference solver)."""
        N = self.N
        q, v = y[:N], y[N:]
        lam = self.lam(q, v)
        return np.concatenate([v, self.Minv @ (-self.gradV(q) + self.A(q).T @ lam)])


def constraint_weights(T, variant='odelab'):
    s = T.s
    if variant == 'odelab':          # = Jay BIT 2003 / odelab Spark / GI lobatto_omega_matrix
        return T.A[1:, :].copy()
    if variant == 'pointwise':       # cardillo LobattoIIIAB: A(Q_i)V_i = 0, i = 2..s
        return np.eye(s)[1:, :]
    raise ValueError(variant)


def spark_step(sys, q0, v0, h, s, lam0=None, variant='odelab', maxit=40, return_info=False,
               guess=None, newton='full'):
    """newton='full': Jacobian every iteration; 'simplified': Jacobian (and its LU) from the
    initial guess only, reused for all iterations."""
    T = Tableau(s)
    a, abar, b = T.A, T.B, T.b
    W = constraint_weights(T, variant)
    N, m = sys.N, sys.m
    M, Minv = sys.M, sys.Minv
    nV, nZ = s * N, s * m

    # initial guess: V_i = v0, Lambda_j = lam0 (or the continuous multiplier)
    if guess is not None:
        V, Z = guess[0].copy(), h * guess[1].copy()
    else:
        if lam0 is None:
            lam0 = sys.lam(q0, v0)
        V = np.tile(v0, (s, 1))
        Z = np.tile(h * lam0, (s, 1))

    def unpack(X):
        return X[:nV].reshape(s, N), X[nV:].reshape(s, m)

    def residual_and_jacobian(V, Z, need_jac=True):
        Q = q0 + h * a @ V                                   # s x N
        Aj = [sys.A(Q[j]) for j in range(s)]
        F = np.array([-sys.gradV(Q[j]) for j in range(s)])   # s x N
        G = np.array([Aj[j].T @ Z[j] for j in range(s)])     # s x N  (= h A^T Lambda)
        R1 = (V - v0) @ M.T - h * abar @ F - abar @ G        # s x N
        g = np.array([Aj[j] @ V[j] for j in range(s)])       # s x m
        R2 = W @ g                                           # (s-1) x m
        q1 = q0 + h * b @ V
        v1 = v0 + Minv @ (h * b @ F + b @ G)
        A1 = sys.A(q1)
        R3 = A1 @ v1
        R = np.concatenate([R1.ravel(), R2.ravel(), R3])
        if not need_jac:
            return R, (Q, q1, v1)
        Jac = np.zeros((nV + nZ, nV + nZ))
        # per-stage derivative of (h f(Q_j) + G_j) w.r.t. Q_j
        D = [-h * sys.hessV(Q[j]) + sys.K(Q[j], Z[j]) for j in range(s)]   # N x N
        Jg = [sys.J(Q[j], V[j]) for j in range(s)]                          # m x N
        for i in range(s):
            ri = slice(i * N, (i + 1) * N)
            for k in range(s):
                ck = slice(k * N, (k + 1) * N)
                blk = -sum(abar[i, j] * D[j] * h * a[j, k] for j in range(s))
                if i == k:
                    blk = blk + M
                Jac[ri, ck] = blk
                Jac[ri, nV + k * m: nV + (k + 1) * m] = -abar[i, k] * Aj[k].T
        for r in range(s - 1):
            rr = slice(nV + r * m, nV + (r + 1) * m)
            for k in range(s):
                ck = slice(k * N, (k + 1) * N)
                Jac[rr, ck] = W[r, k] * Aj[k] + sum(W[r, j] * Jg[j] * h * a[j, k] for j in range(s))
        rr = slice(nV + (s - 1) * m, nV + s * m)
        J1 = sys.J(q1, v1)
        for k in range(s):
            ck = slice(k * N, (k + 1) * N)
            dv1 = Minv @ sum(b[j] * D[j] * h * a[j, k] for j in range(s))
            Jac[rr, ck] = J1 * h * b[k] + A1 @ dv1
            Jac[rr, nV + k * m: nV + (k + 1) * m] = b[k] * A1 @ Minv @ Aj[k].T
        return R, Jac

    X = np.concatenate([V.ravel(), Z.ravel()])
    hist = []
    it = 0
    small = 0
    for it in range(1, maxit + 1):
        V, Z = unpack(X)
        if newton == 'full' or it == 1:
            R, Jac = residual_and_jacobian(V, Z)
        else:
            R, _ = residual_and_jacobian(V, Z, need_jac=False)
        dX = np.linalg.solve(Jac, -R)
        X = X + dX
        nd = np.max(np.abs(dX)) / (1.0 + np.max(np.abs(X)))
        hist.append(nd)
        # stop once the update is at round-off twice in a row (or stops decreasing there)
        if nd < 1e-15:
            small += 1
            if small >= 2:
                break
        elif len(hist) > 3 and nd > 0.5 * hist[-2] and hist[-2] < 1e-13:
            break
    if maxit > 2 and hist and hist[-1] > 1e-12:
        raise RuntimeError(f'Newton did not converge: last update {hist[-1]:.1e} after {it} iterations')
    V, Z = unpack(X)
    R, (Q, q1, v1) = residual_and_jacobian(V, Z, need_jac=False)
    Lam = Z / h
    if return_info:
        return q1, v1, Lam[-1], dict(iterations=it, residual=np.max(np.abs(R)), steps=hist,
                                     V=V, Lam=Lam, Q=Q, jac=Jac)
    return q1, v1, Lam[-1]


def integrate(sys, q0, v0, h, n, s, variant='odelab', callback=None):
    q, v = q0.copy(), v0.copy()
    lam = sys.lam(q, v)
    guess = None
    for k in range(n):
        q1, v1, lam, info = spark_step(sys, q, v, h, s, lam0=lam, variant=variant, return_info=True,
                                       guess=guess)
        q, v = q1, v1
        if callback is not None:
            callback(k + 1, q, v, lam, info)
    return q, v, lam


# ------------------------------------------------------------------ test systems
class KnifeEdge(Mechanical):
    """q = (x, y, phi), M = I, V = -g x (incline, gravity along x), sin(phi) xdot - cos(phi) ydot = 0.
    phi does not appear in V and A has no phi column, so phi = phi0 + omega t exactly."""
    def __init__(self, g=0.0):
        self.N, self.m, self.g = 3, 1, g
        self.M = np.eye(3)
        self.setup()

    def V(self, q):
        return -self.g * q[0]

    def gradV(self, q):
        return np.array([-self.g, 0.0, 0.0])

    def hessV(self, q):
        return np.zeros((3, 3))

    def A(self, q):
        return np.array([[np.sin(q[2]), -np.cos(q[2]), 0.0]])

    def dA(self, q):
        d = np.zeros((1, 3, 3))
        d[0, 0, 2] = np.cos(q[2])
        d[0, 1, 2] = np.sin(q[2])
        return d

    def exact(self, t, q0, v0):
        """Closed form. u = blade speed cos(phi) xdot + sin(phi) ydot, udot = g cos(phi)."""
        x0, y0, p0 = q0
        om = v0[2]
        u0 = np.cos(p0) * v0[0] + np.sin(p0) * v0[1]
        g = self.g
        p = p0 + om * t
        u = u0 + g / om * (np.sin(p) - np.sin(p0))
        # x = x0 + int u cos(phi) dt = x0 + (1/om) [u0 sin + (g/om)(sin^2/2 - sin(p0) sin)]_p0^p
        Fx = lambda P: u0 * np.sin(P) + g / om * (0.5 * np.sin(P) ** 2 - np.sin(p0) * np.sin(P))
        Fy = lambda P: -u0 * np.cos(P) + g / om * (0.5 * P - 0.25 * np.sin(2 * P) + np.sin(p0) * np.cos(P))
        x = x0 + (Fx(p) - Fx(p0)) / om
        y = y0 + (Fy(p) - Fy(p0)) / om
        q = np.array([x, y, p])
        v = np.array([u * np.cos(p), u * np.sin(p), om])
        return q, v


class Sleigh(Mechanical):
    """Chaplygin sleigh: q = (x, y, theta), M = diag(m, m, I), V = m g y,
    -sin(theta) xdot + cos(theta) ydot - a thetadot = 0 (model.md's chaplygin_sleigh)."""
    def __init__(self, mass=1.0, inertia=1.0, a=1.0, g=0.1):
        self.N, self.m = 3, 1          # m = number of constraint rows (mass is self.mass)
        self.mass, self.I, self.a, self.g = mass, inertia, a, g
        self.M = np.diag([mass, mass, inertia])
        self.setup()

    def V(self, q):
        return self.mass * self.g * q[1]

    def gradV(self, q):
        return np.array([0.0, self.mass * self.g, 0.0])

    def hessV(self, q):
        return np.zeros((3, 3))

    def A(self, q):
        th = q[2]
        return np.array([[-np.sin(th), np.cos(th), -self.a]])

    def dA(self, q):
        th = q[2]
        d = np.zeros((1, 3, 3))
        d[0, 0, 2] = -np.cos(th)
        d[0, 1, 2] = -np.sin(th)
        return d


class CVTPendulum(Mechanical):
    """nhlab's cvt_pendulum (eps = 0): q = (x1, x2, zeta), M = I,
    V = (x1^2 + x2^2)/2 + 1 - cos(zeta), constraint x1dot + sin(zeta) x2dot = 0."""
    def __init__(self):
        self.N, self.m = 3, 1
        self.M = np.eye(3)
        self.setup()

    def V(self, q):
        return 0.5 * (q[0] ** 2 + q[1] ** 2) + 1 - np.cos(q[2])

    def gradV(self, q):
        return np.array([q[0], q[1], np.sin(q[2])])

    def hessV(self, q):
        return np.diag([1.0, 1.0, np.cos(q[2])])

    def A(self, q):
        return np.array([[1.0, np.sin(q[2]), 0.0]])

    def dA(self, q):
        d = np.zeros((1, 3, 3))
        d[0, 1, 2] = np.cos(q[2])
        return d


class HolonomicPendulum(Mechanical):
    """Planar pendulum written with the velocity form of |q|^2 = 1: A(q) = q^T (integrable).
    M = I, V = g q_2.  Used to see what the nonholonomic SPARK does on a holonomic constraint."""
    def __init__(self, g=1.0):
        self.N, self.m, self.g = 2, 1, g
        self.M = np.eye(2)
        self.setup()

    def V(self, q):
        return self.g * q[1]

    def gradV(self, q):
        return np.array([0.0, self.g])

    def hessV(self, q):
        return np.zeros((2, 2))

    def A(self, q):
        return q.reshape(1, 2).copy()

    def dA(self, q):
        d = np.zeros((1, 2, 2))
        d[0, 0, 0] = 1.0
        d[0, 1, 1] = 1.0
        return d
