r"""Implicit time steps and static equilibrium for models with an energy (the "variational" model).

For a model whose internal force is the gradient of an energy E (the exact
gradient of eq. (13), or the quadratic energy of the frozen model), each step
minimises an incremental potential over the free degrees of freedom by
Newton's method with a backtracking line search. With M, C, F integrated
(``measure`` times the backend's rows) and x-hat = x_n + dt v_n:

- ``"implicit-euler"`` (first order, dissipative: with gamma = 0 and no load the
  total energy does not grow)::

      Phi(x) = |x - x-hat|^2_M / (2 dt^2) + |x - x_n|^2_C / (2 dt) + E(x) - F_{n+1} . x
      v_{n+1} = (x_{n+1} - x_n) / dt

- ``"newmark"`` (beta = 1/4, gamma = 1/2, the trapezoidal rule: second order,
  no numerical damping of linear modes)::

      Phi(x) = 2 |x - x-hat|^2_M / dt^2 - (M a_n) . x + |x - x_n|^2_C / dt - (C v_n) . x + E(x) - F_{n+1} . x
      a_{n+1} = 4 (x_{n+1} - x-hat) / dt^2 - a_n,   v_{n+1} = 2 (x_{n+1} - x_n) / dt - v_n

The stationarity of Phi is the equation of motion (11) at t_{n+1} in each
scheme. :func:`equilibrium` minimises ``E(x) - F . x`` by the same machinery.

The Newton matrix is the exact Hessian; when it gives no descent direction (an
indefinite Hessian, e.g. under compression) the step falls back to
Gauss-Newton and then adds a Levenberg-Marquardt shift until it does. Each
Newton step moves no node by more than :data:`MAX_STEP` of the sheet's
diagonal (a trust region of fixed radius): without that cap a soft strip
(eta = xi = 1) curling from flat jumped into twisted states, and which ones
depended on round-off.
"""

from __future__ import annotations

import logging
from dataclasses import dataclass, field

import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as spla

__all__ = ["ConvergenceError", "NewtonReport", "ImplicitIntegrator", "equilibrium", "MAX_STEP"]

#: largest move of any degree of freedom in one Newton step, as a fraction of the sheet's diagonal
MAX_STEP = 0.05

log = logging.getLogger(__name__)


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


def _flat(X):
    return np.asarray(X, float).T.ravel()  # coordinate blocks: index a * ndof + k


def _unflat(x, n):
    return x.reshape(3, n).T.copy()


def _fixed_flat(model) -> np.ndarray:
    n = model.ndof
    return np.concatenate([a * n + np.asarray(f, dtype=np.int64) for a, f in enumerate(model.fixed_dofs())])


def _newton(phi, grad, hess, x, free, *, rtol, atol, max_iter, label, max_step=np.inf):
    """Minimise phi over x[free] (x[~free] held) from x; returns (x, NewtonReport).

    No step moves a degree of freedom by more than ``max_step``.
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


class ImplicitIntegrator:
    """Newton-based steps of the implicit-Euler or Newmark scheme (module docstring).

    Parameters
    ----------
    model : Backend with ``energy_gradient``, ``energy_hessian`` and ``measure``
    dt : float
    scheme : "implicit-euler" | "newmark"
    rtol, atol : float
        Newton stops when the max-norm of the free residual is below
        ``max(rtol * initial residual, atol)`` (atol in N).
    max_iter : int
    """

    def __init__(self, model, dt, scheme, rtol=1e-9, atol=1e-12, max_iter=30):
        for name in ("energy_gradient", "energy_hessian", "measure"):
            if not hasattr(model, name):
                raise ValueError(f"scheme {scheme!r} needs a model with an energy ({name} is missing)")
        self.model, self.dt, self.scheme = model, dt, scheme
        self.rtol, self.atol, self.max_iter = rtol, atol, max_iter
        n = model.ndof
        I3 = sp.identity(3, format="csr")
        self.Mb = sp.kron(I3, model.measure * model.mass(), format="csr")
        self.Cb = sp.kron(I3, model.measure * model.damping(), format="csr")
        free = np.ones(3 * n, bool)
        free[_fixed_flat(model)] = False
        self.free = free
        self.reports: list[NewtonReport] = []
        self.max_step = MAX_STEP * float(np.hypot(*model.scene.sheet.size))
        self._acc = None  # (step, t, a_n) for Newmark

    def _energy(self, x):
        return self.model.energy(_unflat(x, self.model.ndof)).total

    def _grad(self, x):
        return _flat(self.model.energy_gradient(_unflat(x, self.model.ndof)))

    def _hess(self, x, kind):
        return self.model.energy_hessian(_unflat(x, self.model.ndof), kind)

    def acceleration(self, state) -> np.ndarray:
        """a = M^-1 (F - C v - grad E) at a state (flat), for starting Newmark."""
        n = self.model.ndof
        F = _flat(self.model.measure * self.model.load(state.X, state.t))
        rhs = F - self.Cb @ _flat(state.V) - self._grad(_flat(state.X))
        a = np.zeros(3 * n)
        f = self.free
        a[f] = spla.spsolve(self.Mb[f][:, f].tocsc(), rhs[f])
        return a

    def step(self, state, X0):
        from .stepper import DivergenceError, State

        model, dt, n = self.model, self.dt, self.model.ndof
        t1 = state.t + dt
        xn, vn = _flat(state.X), _flat(state.V)
        xhat = xn + dt * vn
        F = _flat(model.measure * model.load(state.X, t1))
        Mb, Cb = self.Mb, self.Cb
        if self.scheme == "implicit-euler":
            def phi(x):
                dx, dn = x - xhat, x - xn
                return 0.5 * dx @ (Mb @ dx) / dt**2 + 0.5 * dn @ (Cb @ dn) / dt + self._energy(x) - F @ x

            def grad(x):
                return Mb @ (x - xhat) / dt**2 + Cb @ (x - xn) / dt + self._grad(x) - F

            def hess(x, kind):
                return Mb / dt**2 + Cb / dt + self._hess(x, kind)
        else:
            if self._acc is None or self._acc[0] != state.step or self._acc[1] != state.t:
                self._acc = (state.step, state.t, self.acceleration(state))
            an = self._acc[2]
            Man, Cvn = Mb @ an, Cb @ vn

            def phi(x):
                dx, dn = x - xhat, x - xn
                return (2 * dx @ (Mb @ dx) / dt**2 - Man @ x + dn @ (Cb @ dn) / dt - Cvn @ x
                        + self._energy(x) - F @ x)

            def grad(x):
                return 4 * Mb @ (x - xhat) / dt**2 - Man + 2 * Cb @ (x - xn) / dt - Cvn + self._grad(x) - F

            def hess(x, kind):
                return 4 * Mb / dt**2 + 2 * Cb / dt + self._hess(x, kind)

        x = xhat.copy()
        held = ~self.free
        x[held] = _flat(model.prescribed(X0, t1))[held]
        try:
            x, report = _newton(phi, grad, hess, x, self.free, rtol=self.rtol, atol=self.atol,
                                max_iter=self.max_iter, label=f"{self.scheme} step {state.step + 1}",
                                max_step=self.max_step)
        except ConvergenceError as err:
            raise DivergenceError(f"diverged at step {state.step + 1} (t = {t1:.6g} s): {err}", state) from err
        self.reports.append(report)
        if not report.converged:
            log.warning("%s step %d: Newton stopped after %d iterations at residual %.3e",
                        self.scheme, state.step + 1, report.iterations, report.residuals[-1])
        if not np.all(np.isfinite(x)):
            raise DivergenceError(f"diverged at step {state.step + 1} (t = {t1:.6g} s): non-finite positions", state)
        if self.scheme == "implicit-euler":
            v = (x - xn) / dt
        else:
            a = 4 * (x - xhat) / dt**2 - an
            v = 2 * (x - xn) / dt - vn
            self._acc = (state.step + 1, t1, a)
        return State(t=t1, X=_unflat(x, n), V=_unflat(v, n), step=state.step + 1)


def equilibrium(model, X0, tol: float = 1e-10, t: float = 0.0, max_iter: int = 200, load_steps: int = 1):
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
        solved to the tolerance: large rotations under a large load converge
        in far fewer iterations this way.

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
        raise ValueError(f"load_steps must be a positive integer, got {load_steps!r}")
    integ = ImplicitIntegrator(model, 1.0, "implicit-euler")
    n = model.ndof
    F_full = _flat(model.measure * model.load(np.asarray(X0, float), t))
    x = _flat(X0)
    held = ~integ.free
    x[held] = _flat(model.prescribed(X0, t))[held]
    history: list[float] = []
    for k in range(1, int(load_steps) + 1):
        F = F_full * (k / load_steps)

        def phi(x, F=F):
            return integ._energy(x) - F @ x

        def grad(x, F=F):
            return integ._grad(x) - F

        scale = max(np.max(np.abs(F[integ.free])) if F.size else 0.0, np.max(np.abs(grad(x)[integ.free])))
        x, report = _newton(phi, grad, integ._hess, x, integ.free, rtol=0.0, atol=tol * scale,
                            max_iter=max_iter, label="equilibrium", max_step=integ.max_step)
        history += report.residuals
        if not report.converged:
            raise ConvergenceError(
                f"equilibrium did not converge in {report.iterations} Newton iterations (load step {k} of "
                f"{load_steps}): residual {report.residuals[-1]:.3e} N, tolerance "
                f"{max(tol * scale, report.floor):.3e} N", history, _unflat(x, n))
    return _unflat(x, n), history

