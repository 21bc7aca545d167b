r"""Newton's method on a potential over the free degrees of freedom of a model.

The implicit time steps (:mod:`deformable.dynamics.implicit`) and static
equilibrium (:mod:`deformable.equilibrium`) both minimise a potential
``Phi(x) = (inertia, damping terms) + E(x) - F . x`` whose elastic part E is
the model's energy (the exact gradient of eq. (13) for the "variational"
model, the quadratic energy of the frozen one). This module holds what they
share: the model's energy over flat coordinate-blocked vectors
(:class:`FlatEnergy`), and :func:`minimise`, Newton with a backtracking line
search.

The Newton matrix is the exact Hessian; when it gives no descent direction (an
indefinite Hessian, e.g. under compression) the step falls back to
Gauss-Newton and then adds a Levenberg-Marquardt shift until it does. Each
Newton step moves no degree of freedom by more than ``max_step`` (the callers
use :data:`MAX_STEP` of the sheet's diagonal: a trust region of fixed radius;
without it a soft strip (eta = xi = 1) curling from flat jumped into twisted
states, and which ones depended on round-off).
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as spla

from .elasticity import require_energy_gradient

__all__ = ["ConvergenceError", "NewtonReport", "FlatEnergy", "minimise", "MAX_STEP", "flat", "unflat"]

#: largest move of any degree of freedom in one Newton step, as a fraction of the sheet's diagonal
MAX_STEP = 0.05


class ConvergenceError(RuntimeError):
    """Newton's method did not converge; ``history`` holds the residual norms per iteration."""

    def __init__(self, message: str, history=None, X=None):
        super().__init__(message)
        self.history, self.X = history or [], X


@dataclass
class NewtonReport:
    """Iterations and residual history of one Newton solve."""

    iterations: int = 0
    residuals: list = field(default_factory=list)
    converged: bool = False
    floor: float = 0.0  # round-off floor the tolerance was raised to, if any (N)


def flat(X) -> np.ndarray:
    """(ndof, 3) -> coordinate blocks (3 ndof,): index a * ndof + k."""
    return np.asarray(X, float).T.ravel()


def unflat(x, n: int) -> np.ndarray:
    """Coordinate blocks (3 n,) -> (n, 3)."""
    return x.reshape(3, n).T.copy()


class FlatEnergy:
    """A model's energy, gradient, Hessian, mass, damping and load over flat coordinate-blocked vectors.

    Parameters
    ----------
    model : Backend whose force model has an energy ("variational" or "frozen"; ValueError for tpbf87)

    Attributes
    ----------
    free : bool array (3 ndof,)
        The degrees of freedom that are not held.
    M, C : sparse (3 ndof, 3 ndof)
        diag(M, M, M) and diag(C, C, C).
    max_step : float
        :data:`MAX_STEP` times the sheet's diagonal.
    """

    def __init__(self, model):
        require_energy_gradient(model.scene)
        self.model, self.n = model, model.ndof
        I3 = sp.identity(3, format="csr")
        self.M = sp.kron(I3, model.mass(), format="csr")
        self.C = sp.kron(I3, model.damping(), format="csr")
        free = np.ones(3 * self.n, bool)
        free[np.concatenate([a * self.n + np.asarray(f, dtype=np.int64)
                             for a, f in enumerate(model.fixed_dofs())])] = False
        self.free = free
        self.max_step = MAX_STEP * float(np.hypot(*model.scene.sheet.size))

    def energy(self, x) -> float:
        return self.model.energy(unflat(x, self.n)).total

    def gradient(self, x) -> np.ndarray:
        return flat(self.model.energy_gradient(unflat(x, self.n)))

    def hessian(self, x, kind: str = "newton") -> sp.csr_matrix:
        return self.model.energy_hessian(unflat(x, self.n), kind)

    def load(self, X, t: float) -> np.ndarray:
        return flat(self.model.load(X, t))

    def hold(self, x, X0, t: float) -> np.ndarray:
        """A copy of flat x with the held degrees of freedom at their prescribed values at t (reference X0)."""
        x = np.array(x, dtype=float)
        held = ~self.free
        x[held] = flat(self.model.prescribed(X0, t))[held]
        return x


def minimise(phi, grad, hess, x, free, *, rtol, atol, max_iter, label, max_step=np.inf):
    """Minimise phi over x[free] (x[~free] held) from x by Newton's method; returns (x, NewtonReport).

    Parameters
    ----------
    phi, grad, hess : callables of the flat vector x
        The potential, its gradient (3 ndof,) and ``hess(x, kind)`` its Hessian ("newton" or "gauss-newton").
    free : bool array
    rtol, atol : float
        Stop when the max-norm of the free residual is below ``max(rtol * initial residual, atol)``
        (raised to a round-off floor of the internal forces, recorded in the report).
    max_iter : int
    label : str
        Named in the ConvergenceError of a failed line search.
    max_step : float
        No step moves a degree of freedom by more than this.
    """
    report = NewtonReport()
    g = grad(x)[free]
    r0 = np.max(np.abs(g)) if g.size else 0.0
    target = max(rtol * r0, atol)
    report.residuals.append(float(r0))
    for it in range(1, max_iter + 1):
        if report.residuals[-1] <= target:
            report.converged = True
            break
        f0 = phi(x)
        d = None
        for kind, shift in (("newton", 0.0), ("gauss-newton", 0.0), ("gauss-newton", 1e-8), ("gauss-newton", 1e-4),
                            ("gauss-newton", 1e-2)):
            H = hess(x, kind)[free][:, free].tocsc()
            if not report.floor:
                # round-off floor: internal forces are sums of terms of size |diag H| |x|
                report.floor = float(1e3 * np.finfo(float).eps * np.max(np.abs(H.diagonal()))
                                     * max(1.0, np.max(np.abs(x))))
                target = max(target, report.floor)
            if shift:
                H = H + shift * abs(H.diagonal()).mean() * sp.identity(H.shape[0], format="csc")
            try:
                cand = -spla.splu(H).solve(g)
            except RuntimeError:  # exactly singular
                continue
            if np.all(np.isfinite(cand)) and g @ cand < 0:
                d = cand
                break
        if d is None:
            d = -g
        longest = np.max(np.abs(d))
        if longest > max_step:
            d = d * (max_step / longest)
        slope = g @ d
        step = 1.0
        for _ in range(40):
            xt = x.copy()
            xt[free] += step * d
            ft = phi(xt)
            if np.isfinite(ft) and ft <= f0 + 1e-4 * step * slope:
                break
            step *= 0.5
        else:
            raise ConvergenceError(f"{label}: line search failed at iteration {it} (residual {report.residuals[-1]:.3e})",
                                   report.residuals, x)
        x = xt
        g = grad(x)[free]
        report.residuals.append(float(np.max(np.abs(g))))
        report.iterations = it
        # a step that no longer changes x is converged to round-off
        if step * np.max(np.abs(d)) <= 1e-15 * max(1.0, np.max(np.abs(x))):
            report.converged = report.residuals[-1] <= 1e3 * target
            break
    else:
        report.converged = report.residuals[-1] <= target
    return x, report
