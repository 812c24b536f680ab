#!/usr/bin/env python3
"""What a user would pick instead of nhlab: SciPy's solve_ivp(method="DOP853") on the same
reduced ODE (docs/model.md §1, multiplier eliminated), on the two work–precision scenes of
docs/performance.md and the inclined Chaplygin sleigh (docs/high-order.md). Prints CSV: scene,method,rtol,elapsed_ms,final_error, the error taken against
SciPy's own reference: DOP853 at its tightest tolerance (rtol = 100 ε, atol = 1e-15), restarted
every time unit with the angle ζ brought back near 0 by whole turns, as nhlab's reference is (a
plain solve at 1e-13 is only good to ~1e-7 on the rotating CVT at t = 3000: ζ reaches 7000). Its
final state goes to stderr, to compare with nhlab's. Tolerances in half decades, 1e-3 … 3.2e-14 (as
fine as nhlab's √2 step ladder; SciPy allows rtol down to 100 ε). Time is the minimum of 3 runs.

    pip install scipy && python3 bench/scipy_dop853.py [SCENE ...] > target/wp_scipy.csv
"""
import math
import sys
import time

import numpy as np
from scipy.integrate import solve_ivp


def knife_edge(eps):
    def rhs(t, y):
        x1, x2, z, v1, v2, vz = y
        s, c = math.sin(z), math.cos(z)
        a = np.array([-s, c - eps, 0.0])
        da = np.array([-c, -s, 0.0]) * vz
        grad = np.array([-1.0, 0.0, 0.0])
        v = np.array([v1, v2, vz])
        lam = (a @ grad - da @ v) / (a @ a)
        acc = a * lam - grad
        return [v1, v2, vz, acc[0], acc[1], acc[2]]

    return rhs


def sleigh(m, inertia, a, g):
    """The Chaplygin sleigh, q = (x, y, θ): M = diag(m, m, I), V = m g y, constraint
    −sin θ ẋ + cos θ ẏ − a θ̇ = 0; M q̈ = −∇V + Aᵀλ with λ from A q̈ + Ȧ q̇ = 0."""
    m_inv = np.array([1 / m, 1 / m, 1 / inertia])
    grad = np.array([0.0, m * g, 0.0])

    def rhs(t, y):
        th, v = y[2], y[3:]
        s, c = math.sin(th), math.cos(th)
        A = np.array([-s, c, -a])
        a_dot_v = -v[2] * (c * v[0] + s * v[1])
        lam = (A @ (m_inv * grad) - a_dot_v) / (A @ (m_inv * A))
        return np.concatenate([v, m_inv * (-grad + A * lam)])
    return rhs


def cvt_pendulum(eps):
    def rhs(t, y):
        x1, x2, z, v1, v2, vz = y
        s, c = math.sin(z), math.cos(z)
        a = np.array([1.0, s, 0.0])
        da = np.array([0.0, c, 0.0]) * vz
        grad = np.array([x1, x2, s - eps * math.cos(2 * z)])
        v = np.array([v1, v2, vz])
        lam = (a @ grad - da @ v) / (a @ a)
        acc = a * lam - grad
        return [v1, v2, vz, acc[0], acc[1], acc[2]]

    return rhs


SCENES = [
    ("knife_edge/paper", knife_edge(0.0), [0, 0, math.pi / 2, 0, 0, 1.0], 100.0),
    ("chaplygin_sleigh/inclined", sleigh(1.0, 1.0, 1.0, 0.1), [0, 0, 0, 0, 1.0, 1.0], 100.0),
    ("cvt_pendulum/rotating-perturbed", cvt_pendulum(0.5), [1, 1, 0, 0, 0, 2.82842712], 3000.0),
]


def solve(rhs, y0, t_end, rtol):
    return solve_ivp(rhs, (0.0, t_end), y0, method="DOP853", rtol=rtol, atol=rtol).y[:, -1]


def reference(rhs, y0, t_end):
    """The reference: unit segments, ζ (index 2) kept near 0 by whole turns."""
    y, t, turns = np.array(y0, dtype=float), 0.0, 0.0
    while t < t_end:
        t1 = min(t + 1.0, t_end)
        y = solve_ivp(rhs, (t, t1), y, method="DOP853", rtol=100 * np.finfo(float).eps,
                      atol=1e-15).y[:, -1]
        k = round(y[2] / (2 * math.pi))
        y[2] -= k * 2 * math.pi
        turns += k
        t = t1
    y[2] += turns * 2 * math.pi
    return y


def main():
    print("scene,method,rtol,elapsed_ms,final_error")
    only = sys.argv[1:]  # scene names (or parts of them) to run; all when none
    for name, rhs, y0, t_end in SCENES:
        if only and not any(o in name for o in only):
            continue
        t = time.perf_counter()
        ref = reference(rhs, y0, t_end)
        print(f"{name}: reference {(time.perf_counter() - t):.1f} s, y = {list(ref)!r}",
              file=sys.stderr)
        for k in range(6, 28):
            rtol = 10.0 ** (-k / 2)
            best = math.inf
            for _ in range(3):
                t = time.perf_counter()
                y = solve(rhs, y0, t_end, rtol)
                best = min(best, (time.perf_counter() - t) * 1e3)
            err = float(np.max(np.abs(y - ref)))
            print(f"{name},scipy DOP853,{rtol:.1e},{best:.3f},{err:.3e}")


if __name__ == "__main__":
    main()
