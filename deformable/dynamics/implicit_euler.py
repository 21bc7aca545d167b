r"""Implicit Euler on the incremental potential (first order, dissipative):

    Phi(x) = |x - x-hat|^2_M / (2 dt^2) + |x - x_n|^2_C / (2 dt) + E(x) - F_{n+1} . x,
    v_{n+1} = (x_{n+1} - x_n) / dt,   a_{n+1} = (v_{n+1} - v_n) / dt,

x-hat = x_n + dt v_n; its stationarity is eq. (11) at t_{n+1}. With gamma = 0 and no load the total energy does not
grow: the right choice with contact (:mod:`.implicit` holds the Newton step).
"""

from __future__ import annotations

from .implicit import Implicit

__all__ = ["ImplicitEuler"]


class ImplicitEuler(Implicit):
    """Implicit Euler (module docstring); the default scheme of force models with an energy density."""

    name = "implicit-euler"
    rank = 1

    def coefficients(self, dt):
        return 1 / dt**2, 1 / dt

    def potential(self, state, M, C, F, xn, vn, xhat, dt):
        fl = self.flat

        def phi(x):
            dx, dn = x - xhat, x - xn
            return 0.5 * dx @ (M @ dx) / dt**2 + 0.5 * dn @ (C @ dn) / dt + fl.energy(x) - F @ x

        def grad(x, contact=True):
            return M @ (x - xhat) / dt**2 + C @ (x - xn) / dt + fl.gradient(x, contact) - F

        return phi, grad

    def update(self, x, xn, vn, xhat, dt):
        v = (x - xn) / dt
        return v, (v - vn) / dt
