"""Two methods written in Python (docs/own-methods.md): the paper's leap-frog, equal to the
built-in `leapfrog` to round-off (its increments summed with compensation, as the built-in
sums them), and Störmer–Verlet with the velocity projected onto the
constraints, a method nhlab does not have. Importable, so that Dask workers find them."""

import numpy as np

from ._own import Method


def add(x, c, *parts):
    """x + Σ parts with Kahan's compensation c carried between steps, as nhlab's own steps
    sum their increments; returns the new x and c."""
    for d in parts:
        y = d - c
        t = x + y
        c = (t - x) - y
        x = t
    return x, c


class Leapfrog(Method):
    """The nonholonomic leap-frog (McLachlan & Perlmutter 2006; Modin & Verdier §2) in
    velocity-Verlet form, λ and the sums' compensations carried in `memory`."""

    name = "my LF"
    order = 2
    symmetric = True

    def step(self, system, q, v, h, memory):
        Minv = system.M_inv()
        lam = memory.get("lambda")
        if lam is None:  # a run's first step: the continuous multiplier
            lam = system.multiplier(q, v)
        dv_half = 0.5 * h * Minv @ (system.A(q).T @ lam - system.grad_V(q))
        q1, cq = add(q, memory.get("cq", 0.0), h * v, h * dv_half)
        A1 = system.A(q1)
        kick = -0.5 * h * Minv @ system.grad_V(q1)
        # q̇₁ = w + (h/2) M⁻¹A₁ᵀλ₁ with A₁ q̇₁ = 0, w = q̇₀ + Δq̇_½ − (h/2) M⁻¹∇V(q₁)
        lam1 = np.linalg.solve(A1 @ Minv @ A1.T, A1 @ (v + dv_half + kick)) * (-2.0 / h)
        v1, cv = add(v, memory.get("cv", 0.0), kick + 0.5 * h * Minv @ A1.T @ lam1, dv_half)
        memory.update({"lambda": lam1, "cq": cq, "cv": cv})
        return q1, v1


class ProjectedVerlet(Method):
    """Störmer–Verlet whose half kicks end with the M-orthogonal projection of the velocity
    onto the constraints at the current configuration (a projection method: Hairer, Lubich &
    Wanner, Geometric Numerical Integration, §IV.4). Explicit and on the constraint at every
    step's end, but neither symmetric nor reversible. `damping` scales the projection's
    correction (1: the projection; the sweeps' example parameter)."""

    name = "projected Verlet"
    order = 2
    parameters = ("damping",)

    def __init__(self, damping=1.0):
        self.damping = damping

    def step(self, system, q, v, h, memory):
        Minv = system.M_inv()
        v_half = v - 0.5 * h * Minv @ system.grad_V(q)
        v_half += self.damping * (system.project(q, v_half) - v_half)
        q1 = q + h * v_half
        v1 = v_half - 0.5 * h * Minv @ system.grad_V(q1)
        return q1, v1 + self.damping * (system.project(q1, v1) - v1)
