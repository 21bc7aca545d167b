r"""Static equilibrium of a model with an energy: ``grad E(X) = F(t)`` at the free degrees of freedom.

E is the model's energy (the exact discrete eq. (13) for the "variational"
model, the quadratic energy of the frozen model) plus the energy of the
scene's springs at time t; the equilibrium minimises
``E(x) - F . x`` by Newton's method (:func:`deformable.solve.newton.minimise`),
optionally under load continuation.
"""

from __future__ import annotations

import dataclasses

import numpy as np

from ..errors import ConvergenceError, InputError
from .newton import Newton
from .potential import FlatEnergy, flat, unflat

__all__ = ["equilibrium"]


def equilibrium(model, X0, tol: float = 1e-10, t: float = 0.0, max_iter: int = 200, load_steps: int = 1,
                newton: dict | None = None):
    """Static equilibrium grad E(X) = F(t) by Newton's method with line search.

    Parameters
    ----------
    model : Backend with an energy (force_model "variational" or "frozen")
    X0 : array (ndof, 3)
        Starting positions; held degrees of freedom keep their prescribed values at t.
    tol : float
        Relative tolerance on the max-norm of the free residual (relative to
        the larger of the load and the starting residual), never below the
        round-off floor of the internal forces.
    max_iter : int
        Newton iterations per load step.
    load_steps : int
        Apply the load in this many equal increments (continuation), each
        solved to the tolerance.
    newton : dict, optional
        Further :class:`deformable.solve.newton.NewtonSettings` (hessian, solver, reuse).

    Returns
    -------
    X : array (ndof, 3)
    history : list of float
        Residual max-norm per iteration (N).

    Raises
    ------
    ConvergenceError
        If the residual does not fall below the tolerance within ``max_iter`` iterations.
    """
    if int(load_steps) != load_steps or load_steps < 1:
        raise InputError(f"load_steps must be a positive integer, got {load_steps!r}")
    fl = FlatEnergy(model)
    if not fl.loads.conservative:
        raise InputError("equilibrium: the scene's Wind is not conservative (it depends on velocities); "
                         "find a steady state by running the dynamics instead")
    fl.t = t
    solver = Newton(fl, dict(newton or {}, max_iter=max_iter, rtol=0.0))
    X0 = np.asarray(X0, float)
    F_full = fl.load(t)
    x = fl.hold(flat(X0), X0, t)
    history: list[float] = []
    for k in range(1, int(load_steps) + 1):
        F = F_full * (k / load_steps)

        def phi(x, F=F):
            return fl.energy(x) - F @ x

        def grad(x, F=F):
            return fl.gradient(x) - F

        scale = max(np.max(np.abs(F[fl.free])) if F.size else 0.0, np.max(np.abs(grad(x)[fl.free])))
        solver.settings = dataclasses.replace(solver.settings, atol=tol * scale)
        x, report = solver.minimise(phi, grad, x, label="equilibrium")
        history += report.residuals
        if not report.converged:
            raise ConvergenceError(
                f"equilibrium did not converge in {report.iterations} Newton iterations (load step {k} of "
                f"{load_steps}): residual {report.residuals[-1]:.3e} N, tolerance "
                f"{max(tol * scale, report.floor):.3e} N", history, unflat(x, fl.n))
    return unflat(x, fl.n), history
