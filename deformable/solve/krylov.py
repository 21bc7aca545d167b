"""Preconditioned conjugate gradients for Newton's inexact directions.

Newton's loop (:mod:`deformable.solve.newton`) keeps a factorisation of a recent Newton matrix. When a chord
direction from it stops contracting, the exact Newton matrix A at the current iterate is assembled and A d = -g is
solved by conjugate gradients preconditioned by that factorisation (Hestenes and Stiefel 1952; Saad 2003, "Iterative
Methods for Sparse Linear Systems", algorithm 9.1), to the relative residual of an Eisenstat-Walker forcing term
(Eisenstat and Walker 1996, SIAM J. Sci. Comput. 17, choice 2), within the iterations that cost as much as a new
factorisation. CG stops at the first direction of non-positive curvature: the exact matrix is then not positive
definite and Newton factorises instead (its definite fallback). Each iteration is one product with A and one solve
with the factorisation, both compiled; the loop itself is Python.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

__all__ = ["CGResult", "pcg", "forcing"]


@dataclass(frozen=True)
class CGResult:
    """x: the approximate solution (n,); iterations: products with A; status: "converged", "indefinite" (a direction
    of non-positive curvature met) or "budget" (the iteration budget spent)."""

    x: np.ndarray
    iterations: int
    status: str


def pcg(A, b: np.ndarray, precondition, x0: np.ndarray | None = None, rtol: float = 1e-2,
        maxiter: int = 20) -> CGResult:
    """Solve A x = b (A symmetric, (n, n) sparse; b (n,)) by CG preconditioned by ``precondition(r) ~ A^-1 r``.

    Stops when ``||b - A x||_2 <= rtol ||b||_2``, at a direction p with ``p . A p <= 0`` ("indefinite": x is the
    last iterate, whose residual may not meet rtol), or after ``maxiter`` products with A ("budget").
    """
    b = np.asarray(b, float)
    bnorm = float(np.linalg.norm(b))
    x = np.zeros_like(b) if x0 is None else np.array(x0, float)
    r = b - A @ x if x0 is not None else b.copy()
    its = 0 if x0 is None else 1
    if bnorm == 0.0 or np.linalg.norm(r) <= rtol * bnorm:
        return CGResult(x, its, "converged")
    z = precondition(r)
    p = z.copy()
    rz = float(r @ z)
    while its < maxiter:
        Ap = A @ p
        its += 1
        curvature = float(p @ Ap)
        if not curvature > 0.0:
            return CGResult(x, its, "indefinite")
        alpha = rz / curvature
        x += alpha * p
        r -= alpha * Ap
        if np.linalg.norm(r) <= rtol * bnorm:
            return CGResult(x, its, "converged")
        z = precondition(r)
        rz, rz_old = float(r @ z), rz
        p = z + (rz / rz_old) * p
    return CGResult(x, its, "budget")


def forcing(residual: float, previous: float | None, last: float | None, high: float = 0.1,
            gamma: float = 0.9) -> float:
    """Eisenstat and Walker's choice 2 forcing term for the next linear solve: ``gamma (r_k / r_{k-1})^2``,
    safeguarded by ``gamma last^2`` when that is above 0.1, and at most ``high`` (``high`` for the first solve).

    ``residual``, ``previous``: the nonlinear residual norms now and at the previous iterate (None: the first
    iterate); ``last``: the forcing term used there (None if none).
    """
    if previous is None or not previous > 0:
        return high
    eta = gamma * (residual / previous) ** 2
    if last is not None and gamma * last**2 > 0.1:
        eta = max(eta, gamma * last**2)
    return float(min(high, eta))
