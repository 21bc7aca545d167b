r"""Implicit time steps for models with an energy (the "variational" and "frozen" force models).

For a model whose internal force is the gradient of an energy E (the exact
gradient of eq. (13), or the quadratic energy of the frozen model), each step
minimises an incremental potential over the free degrees of freedom by
Newton's method (:func:`deformable.newton.minimise`). With M, C, F the
backend's integrated matrices and load and x-hat = x_n + dt v_n:

- ``"implicit-euler"`` (first order, dissipative: with gamma = 0 and no load the
  total energy does not grow)::

      Phi(x) = |x - x-hat|^2_M / (2 dt^2) + |x - x_n|^2_C / (2 dt) + E(x) - F_{n+1} . x
      v_{n+1} = (x_{n+1} - x_n) / dt

- ``"newmark"`` (beta = 1/4, gamma = 1/2, the trapezoidal rule: second order,
  no numerical damping of linear modes)::

      Phi(x) = 2 |x - x-hat|^2_M / dt^2 - (M a_n) . x + |x - x_n|^2_C / dt - (C v_n) . x + E(x) - F_{n+1} . x
      a_{n+1} = 4 (x_{n+1} - x-hat) / dt^2 - a_n,   v_{n+1} = 2 (x_{n+1} - x_n) / dt - v_n

The stationarity of Phi is the equation of motion (11) at t_{n+1} in each scheme.
"""

from __future__ import annotations

import logging
import time

import numpy as np
import scipy.sparse.linalg as spla

from ..newton import ConvergenceError, FlatEnergy, flat, minimise, unflat
from .state import DivergenceError, State

__all__ = ["Implicit", "IMPLICIT_SCHEMES"]

log = logging.getLogger(__name__)

IMPLICIT_SCHEMES = ("implicit-euler", "newmark")


class Implicit:
    """Newton-based steps of the implicit-Euler or Newmark scheme (module docstring).

    Parameters
    ----------
    model : Backend with an energy (force model "variational" or "frozen")
    dt : float
    scheme : "implicit-euler" | "newmark"
    rtol, atol : float
        Newton stops when the max-norm of the free residual is below
        ``max(rtol * initial residual, atol)`` (atol in N).
    max_iter : int

    Attributes
    ----------
    reports : list of NewtonReport, one per step
    timings : dict
        Seconds spent in "solve" (the whole Newton solve of each step).
    """

    def __init__(self, model, dt, scheme, rtol=1e-9, atol=1e-12, max_iter=30):
        self.model, self.dt, self.name = model, dt, scheme
        self.rtol, self.atol, self.max_iter = rtol, atol, max_iter
        self.flat = FlatEnergy(model)
        self.reports: list = []
        self.timings = {"solve": 0.0}
        self._acc = None  # (step, t, a_n) for Newmark

    def acceleration(self, state) -> np.ndarray:
        """a = M^-1 (F - C v - grad E) at a state (flat), for starting Newmark."""
        fl = self.flat
        rhs = fl.load(state.X, state.t) - fl.C @ flat(state.V) - fl.gradient(flat(state.X))
        a = np.zeros(3 * fl.n)
        f = fl.free
        a[f] = spla.spsolve(fl.M[f][:, f].tocsc(), rhs[f])
        return a

    def step(self, state: State, X0: np.ndarray) -> State:
        """The state at t + dt; ``X0`` is the run's constraint reference."""
        t_start = time.perf_counter()
        fl, dt = self.flat, self.dt
        t1 = state.t + dt
        xn, vn = flat(state.X), flat(state.V)
        xhat = xn + dt * vn
        F = fl.load(state.X, t1)
        M, C = fl.M, fl.C
        if self.name == "implicit-euler":
            def phi(x):
                dx, dn = x - xhat, x - xn
                return 0.5 * dx @ (M @ dx) / dt**2 + 0.5 * dn @ (C @ dn) / dt + fl.energy(x) - F @ x

            def grad(x):
                return M @ (x - xhat) / dt**2 + C @ (x - xn) / dt + fl.gradient(x) - F

            def hess(x, kind):
                return M / dt**2 + C / dt + fl.hessian(x, kind)
        else:
            if self._acc is None or self._acc[0] != state.step or self._acc[1] != state.t:
                self._acc = (state.step, state.t, self.acceleration(state))
            an = self._acc[2]
            Man, Cvn = M @ an, C @ vn

            def phi(x):
                dx, dn = x - xhat, x - xn
                return (2 * dx @ (M @ dx) / dt**2 - Man @ x + dn @ (C @ dn) / dt - Cvn @ x
                        + fl.energy(x) - F @ x)

            def grad(x):
                return 4 * M @ (x - xhat) / dt**2 - Man + 2 * C @ (x - xn) / dt - Cvn + fl.gradient(x) - F

            def hess(x, kind):
                return 4 * M / dt**2 + 2 * C / dt + fl.hessian(x, kind)

        x = fl.hold(xhat, X0, t1)
        try:
            x, report = minimise(phi, grad, hess, x, fl.free, rtol=self.rtol, atol=self.atol,
                                 max_iter=self.max_iter, label=f"{self.name} step {state.step + 1}",
                                 max_step=fl.max_step)
        except ConvergenceError as err:
            raise DivergenceError(f"diverged at step {state.step + 1} (t = {t1:.6g} s): {err}", state) from err
        finally:
            self.timings["solve"] += time.perf_counter() - t_start
        self.reports.append(report)
        if not report.converged:
            log.warning("%s step %d: Newton stopped after %d iterations at residual %.3e",
                        self.name, state.step + 1, report.iterations, report.residuals[-1])
        if not np.all(np.isfinite(x)):
            raise DivergenceError(f"diverged at step {state.step + 1} (t = {t1:.6g} s): non-finite positions", state)
        if self.name == "implicit-euler":
            v = (x - xn) / dt
        else:
            a = 4 * (x - xhat) / dt**2 - an
            v = 2 * (x - xn) / dt - vn
            self._acc = (state.step + 1, t1, a)
        n = fl.n
        return State(t=t1, X=unflat(x, n), V=unflat(v, n), step=state.step + 1)
