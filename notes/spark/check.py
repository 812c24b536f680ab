"""Checks of spark.py: coefficients, Jacobian, convergence orders, constraint residual,
symmetry, reversibility, long-run energy.  Usage:  python check.py [section ...]
sections: coeffs jac struct orders props lam variant holonomic energy (default: all, ~4 min)."""
import sys
import time
import numpy as np
from scipy.integrate import solve_ivp
from coeffs import Tableau
from spark import (spark_step, integrate, KnifeEdge, Sleigh, CVTPendulum, HolonomicPendulum,
                   constraint_weights)

np.set_printoptions(linewidth=150)
SECTIONS = sys.argv[1:] or ['coeffs', 'jac', 'struct', 'orders', 'props', 'lam', 'variant', 'holonomic', 'energy']


def out(*a):
    print(*a, flush=True)


# ------------------------------------------------------------------ coefficients
def check_coeffs():
    out('== coefficients: float64 tables vs odelab (odelab/scheme/rungekutta.py, HEAD ee3300c)')
    sf = np.sqrt(5)
    odelab_A = {2: [[0, 0], [.5, .5]],
                3: [[0, 0, 0], [5 / 24, 1 / 3, -1 / 24], [1 / 6, 2 / 3, 1 / 6]],
                4: [[0, 0, 0, 0],
                    [(11 + sf) / 120, (25 - sf) / 120, (25 - 13 * sf) / 120, (-1 + sf) / 120],
                    [(11 - sf) / 120, (25 + 13 * sf) / 120, (25 + sf) / 120, (-1 - sf) / 120],
                    [1 / 12, 5 / 12, 5 / 12, 1 / 12]]}
    odelab_B = {2: [[.5, 0], [.5, 0]],
                3: [[1 / 6, -1 / 6, 0], [1 / 6, 1 / 3, 0], [1 / 6, 5 / 6, 0]],
                4: [[1 / 12, (-1 - sf) / 24, (-1 + sf) / 24, 0],
                    [1 / 12, (25 + sf) / 120, (25 - 13 * sf) / 120, 0],
                    [1 / 12, (25 + 13 * sf) / 120, (25 - sf) / 120, 0],
                    [1 / 12, (11 - sf) / 24, (11 + sf) / 24, 0]]}
    for s in (2, 3, 4):
        T = Tableau(s)
        # odelab's compute_mean_stage_constraint, verbatim algorithm
        A1t = np.array(odelab_A[s])[1:, :]
        es = np.zeros(s); es[-1] = 1.
        Q = np.zeros([s, s + 1]); Q[:-1, :-1] = A1t; Q[-1, -1] = 1.
        Om = np.linalg.inv(np.vstack([A1t, es])) @ Q
        out(f's={s}: |A-odelab|={np.abs(T.A - odelab_A[s]).max():.1e} '
            f'|B-odelab|={np.abs(T.B - odelab_B[s]).max():.1e} |Omega-odelab|={np.abs(T.Omega - Om).max():.1e}')
    for s in range(2, 7):
        T = Tableau(s)
        out(f's={s}: c={np.array2string(T.c, precision=17)}')
        out(f'      w={np.array2string(T.w, precision=17)}')


# ------------------------------------------------------------------ jacobian
def check_jac():
    out('== analytic Newton Jacobian vs central differences (sleigh, random point)')
    rng = np.random.default_rng(1)
    sy = Sleigh(mass=1.3, inertia=0.7, a=0.6, g=0.4)
    q0 = np.array([0.1, -0.2, 0.7])
    v0 = np.array([0.3, 0.0, 0.8]); v0[1] = (sy.a * v0[2] + np.sin(q0[2]) * v0[0]) / np.cos(q0[2])
    for s in (2, 3, 4, 5):
        _, _, _, info = spark_step(sy, q0, v0, 0.2, s, return_info=True)
        out(f's={s}: h=0.2 Newton iterations {info["iterations"]}, final residual {info["residual"]:.1e}, '
            f'update norms ' + ' '.join(f'{x:.0e}' for x in info['steps']))
    # direct FD of the residual (copy of the residual in spark.py, independent code path)
    from spark import Tableau as _T
    for s in (2, 3, 5):
        T = _T(s); a, ab, b = T.A, T.B, T.b; W = constraint_weights(T)
        h = 0.2; N = 3; m = 1
        def res(X):
            V = X[:s * N].reshape(s, N); Z = X[s * N:].reshape(s, m)
            Q = q0 + h * a @ V
            F = np.array([-sy.gradV(Qj) for Qj in Q]); G = np.array([sy.A(Q[j]).T @ Z[j] for j in range(s)])
            R1 = (V - v0) @ sy.M.T - h * ab @ F - ab @ G
            g = np.array([sy.A(Q[j]) @ V[j] for j in range(s)])
            q1 = q0 + h * b @ V; v1 = v0 + sy.Minv @ (h * b @ F + b @ G)
            return np.concatenate([R1.ravel(), (W @ g).ravel(), sy.A(q1) @ v1])
        X = np.concatenate([np.tile(v0, s) + 0.05 * rng.standard_normal(s * N), 0.1 * rng.standard_normal(s * m)])
        Jfd = np.zeros((len(X), len(X)))
        for k in range(len(X)):
            e = np.zeros(len(X)); e[k] = 1e-6
            Jfd[:, k] = (res(X + e) - res(X - e)) / 2e-6
        _, _, _, inf = spark_step(sy, q0, v0, h, s, return_info=True,
                                  guess=(X[:s * N].reshape(s, N), X[s * N:].reshape(s, m) / h), maxit=1)
        # inf['jac'] is the Jacobian at the guess (first iteration)
        out(f's={s}: max|J_analytic - J_fd| = {np.abs(inf["jac"] - Jfd).max():.1e}  (|J| ~ {np.abs(Jfd).max():.1f})')


# ------------------------------------------------------------------ problems
def knife_problem(g):
    sy = KnifeEdge(g=g)
    q0 = np.array([0.2, -0.1, 0.3])
    u0, om = 0.7, 1.3
    v0 = np.array([u0 * np.cos(q0[2]), u0 * np.sin(q0[2]), om])
    return sy, q0, v0


def sleigh_problem(g=0.1, mass=1.0, inertia=1.0, a=1.0):
    sy = Sleigh(mass=mass, inertia=inertia, a=a, g=g)
    th0 = 0.4
    q0 = np.array([0.0, 0.0, th0])
    xd, thd = 0.5, 1.0            # choose xdot, thetadot; ydot from the constraint
    yd = (a * thd + np.sin(th0) * xd) / np.cos(th0)
    v0 = np.array([xd, yd, thd])
    return sy, q0, v0


def cvt_problem():
    sy = CVTPendulum()
    q0 = np.array([1.0, 1.0, 0.0])
    v0 = np.array([0.0, 0.0, 1.8973666])
    # consistent: x1dot + sin(0) x2dot = 0 -> x1dot = 0; give the passenger speed too
    v0 = np.array([-np.sin(0.0) * 0.3, 0.3, 1.8973666])
    return sy, q0, v0


def reference(sy, q0, v0, Tend, rtol=1e-13, atol=1e-15, n_check=4):
    """DOP853 on the index-1 ODE; returns (q, v) at t = k T/n_check, k = 1..n_check (rows)."""
    ts = Tend * np.arange(1, n_check + 1) / n_check
    sol = solve_ivp(sy.rhs, (0, Tend), np.concatenate([q0, v0]), method='DOP853', rtol=rtol, atol=atol,
                    t_eval=ts)
    return sol.y[:sy.N].T, sol.y[sy.N:].T


def exact_checkpoints(sy, q0, v0, Tend, n_check=4):
    qs, vs = zip(*[sy.exact(Tend * k / n_check, q0, v0) for k in range(1, n_check + 1)])
    return np.array(qs), np.array(vs)


def fit_order(hs, errs, floor, npts=3):
    hs, errs = np.asarray(hs), np.asarray(errs)
    ok = errs > floor
    if ok.sum() < 2:
        return np.nan, 0
    x, y = np.log(hs[ok]), np.log(errs[ok])
    idx = np.argsort(x)[:npts]          # the smallest-h points above the round-off floor
    p = np.polyfit(x[idx], y[idx], 1)
    return p[0], len(idx)


def run_checkpoints(sy, q0, v0, h, n, s, n_check=4, variant='odelab'):
    every = n // n_check
    qs, vs = [], []
    def cb(k, q, v, lam, info):
        if k % every == 0:
            qs.append(q.copy()); vs.append(v.copy())
    integrate(sy, q0, v0, h, n, s, variant=variant, callback=cb)
    return np.array(qs), np.array(vs)


def convergence(name, sy, q0, v0, Tend, qref, vref, s_list=(2, 3, 4, 5), variant='odelab', floor=1e-12):
    out(f'-- {name}: T={Tend}, |q_ref|={np.abs(qref).max():.3g}, |v_ref|={np.abs(vref).max():.3g}, '
        f'variant={variant}; error = max over t = T/4, T/2, 3T/4, T and components')
    Ns = [4, 8, 12, 16, 24, 32, 48, 64, 96, 128, 192, 256, 384, 512, 768, 1024]
    res = {}
    for s in s_list:
        rows = []
        for n in Ns:
            h = Tend / n
            qs, vs = run_checkpoints(sy, q0, v0, h, n, s, variant=variant)
            eq, ev = np.abs(qs - qref).max(), np.abs(vs - vref).max()
            rows.append((h, n, eq, ev))
            if max(eq, ev) < 1e-13 and n >= 16:
                break
        hs = [r[0] for r in rows]
        pq, nq = fit_order(hs, [r[2] for r in rows], floor)
        pv, nv = fit_order(hs, [r[3] for r in rows], floor)
        res[s] = (pq, pv)
        out(f'   s={s} (expected {2*s-2}): fitted order q {pq:.2f}, v {pv:.2f}')
        out('      n         ' + ' '.join(f'{r[1]:>8d}' for r in rows))
        out('      err q     ' + ' '.join(f'{r[2]:8.1e}' for r in rows))
        out('      err v     ' + ' '.join(f'{r[3]:8.1e}' for r in rows))
        with np.errstate(divide='ignore', invalid='ignore'):
            lq = np.diff(np.log([r[2] for r in rows])) / np.diff(np.log(hs))
            lv = np.diff(np.log([r[3] for r in rows])) / np.diff(np.log(hs))
        out('      slope q       ' + '     '.join(f'{x:4.1f}' for x in lq))
        out('      slope v       ' + '     '.join(f'{x:4.1f}' for x in lv))
    return res


def check_orders():
    out('== convergence orders (global error at T, max norm)')
    table = {}
    # (a1) knife edge, V = 0, exact solution
    sy, q0, v0 = knife_problem(0.0)
    T = 3.0
    qe, ve = exact_checkpoints(sy, q0, v0, T)
    table['knife V=0 (exact)'] = convergence('knife edge, V = 0, vs exact', sy, q0, v0, T, qe, ve)
    # (a2) knife edge on incline g = 1, exact
    sy, q0, v0 = knife_problem(1.0)
    qe, ve = exact_checkpoints(sy, q0, v0, T)
    qr, vr = reference(sy, q0, v0, T)
    out(f'   [DOP853 reference vs exact on knife g=1: q {np.abs(qr-qe).max():.1e}, v {np.abs(vr-ve).max():.1e}]')
    table['knife g=1 (exact)'] = convergence('knife edge on incline g = 1, vs exact', sy, q0, v0, T, qe, ve)
    # (b) Chaplygin sleigh, unit masses (Jay/odelab), g = 0.1, a = 1
    sy, q0, v0 = sleigh_problem(g=0.1)
    T = 3.0
    qr, vr = reference(sy, q0, v0, T)
    qr2, vr2 = reference(sy, q0, v0, T, rtol=1e-12, atol=1e-14)
    out(f'   [sleigh reference: |rtol1e-13 - rtol1e-12| q {np.abs(qr-qr2).max():.1e}, v {np.abs(vr-vr2).max():.1e}]')
    table['sleigh unit, g=0.1'] = convergence('Chaplygin sleigh m=I=a=1, g=0.1, vs DOP853', sy, q0, v0, T, qr, vr)
    # (b') sleigh with non-identity M
    sy, q0, v0 = sleigh_problem(g=0.5, mass=2.0, inertia=0.5, a=0.6)
    qr, vr = reference(sy, q0, v0, T)
    table['sleigh m=2,I=.5,a=.6,g=.5'] = convergence('Chaplygin sleigh m=2, I=0.5, a=0.6, g=0.5, vs DOP853',
                                                     sy, q0, v0, T, qr, vr)
    # (c) nhlab's cvt_pendulum (paper class, nonlinear potential)
    sy, q0, v0 = cvt_problem()
    qr, vr = reference(sy, q0, v0, T)
    table['cvt_pendulum'] = convergence('cvt_pendulum (eps=0), vs DOP853', sy, q0, v0, T, qr, vr)
    out('== summary: fitted orders (q, v)')
    for k, r in table.items():
        out(f'   {k:28s} ' + '  '.join(f's={s}: {r[s][0]:5.2f} {r[s][1]:5.2f}' for s in r))
    return table


# ------------------------------------------------------------------ properties
def check_props(variant='odelab'):
    out(f'== constraint residual, symmetry, reversibility (variant {variant})')
    probs = {'knife g=1': knife_problem(1.0), 'sleigh g=0.1': sleigh_problem(0.1),
             'sleigh M!=I': sleigh_problem(0.5, 2.0, 0.5, 0.6), 'cvt_pendulum': cvt_problem()}
    for name, (sy, q0, v0) in probs.items():
        for s in (2, 3, 4, 5):
            worst = dict(con=0, sym=0, rev=0, its=0)
            q, v = q0.copy(), v0.copy()
            for h in (0.05, 0.2, 0.5):
                q1, v1, l1, inf = spark_step(sy, q, v, h, s, variant=variant, return_info=True)
                worst['its'] = max(worst['its'], inf['iterations'])
                worst['con'] = max(worst['con'], np.abs(sy.A(q1) @ v1).max())
                qb, vb, _ = spark_step(sy, q1, v1, -h, s, lam0=l1, variant=variant)
                worst['sym'] = max(worst['sym'], np.abs(np.concatenate([qb - q, vb - v])).max())
                qr, vr, _ = spark_step(sy, q1, -v1, h, s, lam0=l1, variant=variant)
                worst['rev'] = max(worst['rev'], np.abs(np.concatenate([qr - q, -vr - v])).max())
            out(f'   {name:14s} s={s}: max|A(q1)v1|={worst["con"]:.1e}  '
                f'|Phi_-h Phi_h y - y|={worst["sym"]:.1e}  |rho Phi_h rho Phi_h y - y|={worst["rev"]:.1e}  '
                f'(Newton its <= {worst["its"]})')


# ------------------------------------------------------------------ energy
def check_energy(nsteps=10000):
    out(f'== energy over {nsteps} steps (max |H - H0| per decile of the run)')
    probs = {'knife g=1, h=0.1': (knife_problem(1.0), 0.1),
             'sleigh free g=0, h=0.1': (sleigh_problem(0.0), 0.1),
             'sleigh g=0.1, h=0.1': (sleigh_problem(0.1), 0.1),
             'cvt_pendulum, h=0.1': (cvt_problem(), 0.1)}
    for name, ((sy, q0, v0), h) in probs.items():
        for s in (2, 3):
            H0 = sy.energy(q0, v0)
            errs = np.zeros(nsteps)
            cons = np.zeros(nsteps)
            def cb(k, q, v, lam, info):
                errs[k - 1] = sy.energy(q, v) - H0
                cons[k - 1] = abs(sy.A(q) @ v).max()
            t0 = time.time()
            q, v, _ = integrate(sy, q0, v0, h, nsteps, s, callback=cb)
            dec = np.abs(errs).reshape(10, -1).max(axis=1)
            out(f'   {name:24s} s={s}: H0={H0:.4f}  deciles ' + ' '.join(f'{d:.1e}' for d in dec)
                + f'   mean(H-H0) first/last decile {errs[:nsteps//10].mean():+.1e}/{errs[-nsteps//10:].mean():+.1e}'
                + f'   max|Av|={cons.max():.0e}  ({time.time()-t0:.0f}s)  final q={np.array2string(q, precision=3)}')


def check_variant():
    out('== variant "pointwise" (cardillo: A(Q_i)V_i = 0 for i = 2..s, plus end) for comparison')
    sy, q0, v0 = sleigh_problem(0.1)
    T = 3.0
    qr, vr = reference(sy, q0, v0, T)
    convergence('Chaplygin sleigh, variant pointwise', sy, q0, v0, T, qr, vr, variant='pointwise')
    check_props('pointwise')


def check_holonomic():
    out('== holonomic constraints given in velocity form A(q) = G(q) = dg/dq: drift of g(q) over t <= 20')
    class Circ(HolonomicPendulum):          # g = |q|^2 - 1, nonlinear potential
        def V(self, q): return q[0] ** 4 + 0.5 * q[1] ** 3 + q[0] * q[1]
        def gradV(self, q): return np.array([4 * q[0] ** 3 + q[1], 1.5 * q[1] ** 2 + q[0]])
        def hessV(self, q): return np.array([[12 * q[0] ** 2, 1.0], [1.0, 3 * q[1]]])
    class Cubic(HolonomicPendulum):         # g = x^2 + y^2 + 0.3 x^3 - 1.3, V = y
        def A(self, q): return np.array([[2 * q[0] + 0.9 * q[0] ** 2, 2 * q[1]]])
        def dA(self, q):
            d = np.zeros((1, 2, 2)); d[0, 0, 0] = 2 + 1.8 * q[0]; d[0, 1, 1] = 2; return d
    q0, v0 = np.array([1.0, 0.0]), np.array([0.0, 0.8])
    cases = [('circle |q|^2=1, V=y', HolonomicPendulum(1.0), lambda q: q @ q - 1),
             ('circle, V=x^4+y^3/2+xy', Circ(), lambda q: q @ q - 1),
             ('cubic g, V=y', Cubic(), lambda q: q[0] ** 2 + q[1] ** 2 + 0.3 * q[0] ** 3 - 1.3)]
    for name, sy, g in cases:
        for s in (2, 3, 4):
            row = []
            for h in (0.1, 0.05, 0.025):
                d = []
                integrate(sy, q0, v0, h, int(round(20 / h)), s, callback=lambda k, q, v, l, i: d.append(g(q)))
                row.append(np.abs(d).max())
            out(f'   {name:24s} s={s}: max|g(q)| for h = 0.1, 0.05, 0.025: ' + ' '.join(f'{x:.1e}' for x in row))


def check_struct():
    out('== structure: W Abar[:, :s-1] (multiplier block of the h->0 Jacobian) and the end projection')
    for s in range(2, 7):
        T = Tableau(s)
        Wb = T.A[1:, :] @ T.B[:, :s - 1]
        out(f'   s={s}: det(W Abar[:, :s-1]) = {np.linalg.det(Wb):+.3e}, cond = {np.linalg.cond(Wb):.2e}, '
            f'max|Abar[:, s]| = {np.abs(T.B[:, -1]).max():.0e}')
    sy, q0, v0 = sleigh_problem(0.5, 2.0, 0.5, 0.6)
    for s in (2, 3, 4, 5):
        h = 0.3
        q1, v1, l1, info = spark_step(sy, q0, v0, h, s, return_info=True)
        T = Tableau(s); Q = info['Q']; Lam = info['Lam']
        F = np.array([-sy.gradV(Qj) for Qj in Q])
        vhat = v0 + sy.Minv @ (h * T.b @ F + h * sum(T.b[j] * sy.A(Q[j]).T @ Lam[j] for j in range(s - 1)))
        A1 = sy.A(q1)
        P = np.eye(3) - sy.Minv @ A1.T @ np.linalg.solve(A1 @ sy.Minv @ A1.T, A1)
        g = np.array([sy.A(Q[j]) @ info['V'][j] for j in range(s)]).ravel()
        out(f'   s={s}: |q1 - Q_s| = {np.abs(q1 - Q[-1]).max():.0e}, |v1 - P_M(q1) vhat| = {np.abs(v1 - P @ vhat).max():.1e}, '
            f'g_j/g_s = {np.array2string(g / g[-1], precision=6)}, w = {np.array2string(T.w, precision=6)}')
    out('   Newton iterations to round-off (update < 1e-15 twice), full vs simplified (Jacobian frozen at the guess V_i = v0, Lambda_j = lam(q0, v0)):')
    for name, (sy2, qq, vv) in {'sleigh M!=I': (sy, q0, v0), 'cvt_pendulum': cvt_problem()}.items():
        for s in (2, 3, 5):
            row = []
            for h in (0.05, 0.1, 0.2, 0.4):
                its = []
                for nt in ('full', 'simplified'):
                    _, _, _, inf = spark_step(sy2, qq, vv, h, s, return_info=True, newton=nt)
                    its.append(inf['iterations'])
                row.append(f'h={h}: {its[0]}/{its[1]}')
            out(f'      {name:12s} s={s}: ' + '   '.join(row))
    out('   size of the stage constraint values mu = A(Q_s)V_s after one step from a consistent point:')
    for s in (2, 3, 4, 5):
        r = []
        hs = (0.4, 0.2, 0.1, 0.05)
        for h in hs:
            _, _, _, inf = spark_step(sy, q0, v0, h, s, return_info=True)
            r.append(abs(sy.A(inf['Q'][-1]) @ inf['V'][-1]).max())
        sl = np.diff(np.log(r)) / np.diff(np.log(hs))
        out(f'   s={s}: |mu| at h = 0.4..0.05: ' + ' '.join(f'{x:.1e}' for x in r) + '  slopes ' + ' '.join(f'{x:.2f}' for x in sl))


def check_lam():
    out('== multiplier: error of Lambda_s (odelab output) and of sum b_j Lambda_j (GI output) at T')
    sy, q0, v0 = sleigh_problem(0.1)
    T = 3.0
    qr, vr = reference(sy, q0, v0, T)
    qr, vr = qr[-1], vr[-1]
    lr = sy.lam(qr, vr)
    for s in (2, 3, 4, 5):
        row = []
        for n in (8, 16, 32, 64, 128):
            h = T / n
            q, v = q0.copy(), v0.copy()
            lam = sy.lam(q, v)
            for k in range(n):
                q, v, lam, inf = spark_step(sy, q, v, h, s, lam0=lam, return_info=True)
            Tb = Tableau(s)
            e_last = abs(inf['Lam'][-1] - lr).max()
            e_avg = abs(Tb.b @ inf['Lam'] - lr).max()
            e_cont = abs(sy.lam(q, v) - lr).max()
            row.append((n, e_last, e_avg, e_cont))
        out(f'   s={s}: n=' + ' '.join(f'{r[0]:>7d}' for r in row))
        out('        Lambda_s      ' + ' '.join(f'{r[1]:7.1e}' for r in row))
        out('        sum b Lambda  ' + ' '.join(f'{r[2]:7.1e}' for r in row))
        out('        lam(q1,v1)    ' + ' '.join(f'{r[3]:7.1e}' for r in row))


if __name__ == '__main__':
    for sec in SECTIONS:
        t0 = time.time()
        {'coeffs': check_coeffs, 'jac': check_jac, 'orders': check_orders, 'props': check_props,
         'energy': check_energy, 'variant': check_variant, 'holonomic': check_holonomic,
         'lam': check_lam, 'struct': check_struct}[sec]()
        out(f'   [{sec}: {time.time()-t0:.1f}s]')
