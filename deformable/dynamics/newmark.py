r"""Newmark's trapezoidal rule (beta = 1/4, gamma = 1/2) on the incremental potential: second order, no numerical
damping of linear modes:

    Phi(x) = 2 |x - x-hat|^2_M / dt^2 - (M a_n) . x + |x - x_n|^2_C / dt - (C v_n) . x + E(x) - F_{n+1} . x,
    a_{n+1} = 4 (x_{n+1} - x-hat) / dt^2 - a_n,   v_{n+1} = 2 (x_{n+1} - x_n) / dt - v_n,

x-hat = x_n + dt v_n; its stationarity is eq. (11) at t_{n+1}. It conserves energy better than implicit Euler and
gains energy at impacts (:mod:`.implicit` holds the Newton step).
"""

from __future__ import annotations

from ..solve.potential import flat
from .implicit import Implicit

__all__ = ["Newmark"]


class Newmark(Implicit):
    """Newmark's trapezoidal rule (module docstring)."""

    name = "newmark"
    rank = 2
    order = 2
    start = 0.5

    def coefficients(self, dt):
        return 4 / dt**2, 2 / dt

    def potential(self, state, M, C, F, xn, vn, xhat, dt):
        fl = self.flat
        self._an = an = self.acceleration(state) if state.A is None else flat(state.A)
        Man, Cvn = M @ an, C @ vn

        def phi(x):
            dx, dn = x - xhat, x - xn
            return (2 * dx @ (M @ dx) / dt**2 - Man @ x + dn @ (C @ dn) / dt - Cvn @ x
                    + fl.energy(x) - F @ x)

        def grad(x, contact=True):
            return 4 * M @ (x - xhat) / dt**2 - Man + 2 * C @ (x - xn) / dt - Cvn + fl.gradient(x, contact) - F

        return phi, grad

    def update(self, x, xn, vn, xhat, dt):
        return 2 * (x - xn) / dt - vn, 4 * (x - xhat) / dt**2 - self._an
