"""Implicit Euler and Newmark on an incremental potential (deformable.dynamics.implicit)."""

import numpy as np
import pytest

import deformable as dm
from validation.harness.orders import fit_order

from ...conftest import ALL_EDGES, flat_model


class Bump:
    """Flat sheet with a transverse bump 0.05 sin(pi a1) sin(pi a2), closed-form derivatives."""

    A = 0.05

    def _vec(self, x, y, z):
        x, y, z = np.broadcast_arrays(x, y, z)
        return np.stack([x, y, z], axis=-1).astype(float)

    def r(self, a1, a2):
        return self._vec(a1, a2, self.A * np.sin(np.pi * a1) * np.sin(np.pi * a2))

    def r1(self, a1, a2):
        return self._vec(1.0, 0.0, self.A * np.pi * np.cos(np.pi * a1) * np.sin(np.pi * a2))

    def r2(self, a1, a2):
        return self._vec(0.0, 1.0, self.A * np.pi * np.sin(np.pi * a1) * np.cos(np.pi * a2))

    def r12(self, a1, a2):
        return self._vec(0.0, 0.0, self.A * np.pi**2 * np.cos(np.pi * a1) * np.cos(np.pi * a2))


@pytest.mark.parametrize("backend, steps", [("fd", 60), ("fe", 40)])
def test_implicit_euler_never_lets_the_energy_grow(backend, steps):
    """gamma = 0, no load: the variational model's total energy does not grow, and it does dissipate."""
    model = flat_model(backend, sheet=dm.Sheet(nodes=(9, 9), initial=Bump()), force_model="variational",
                       material=dm.Material(mu=1.0, gamma=0.0, eta=20.0, xi=0.05),
                       constraints=[dm.Pin(["left", "right"])], rest_metric=0.9)
    X0 = model.initial_state()
    stepper = dm.TimeStepper(model, dt=5e-3)
    assert stepper.scheme == "implicit-euler"
    energies = [model.energy(X0).total]
    energies += [model.energy(s.X).total + model.kinetic_energy(s.V) for s in stepper.iterate(X0, steps)]
    growth = np.max(np.diff(energies))
    assert growth <= 1e-10 * energies[0], f"energy grew by {growth:.3e}"
    assert energies[-1] < 0.999 * energies[0]  # and it does dissipate (first-order scheme)
    assert len(stepper.newton_reports) == steps and all(r.converged for r in stepper.newton_reports)
    assert set(stepper.timings) == {"hessian", "factor", "solve", "search"} and stepper.timings["factor"] > 0


def frozen_membrane():
    """A linear (frozen) FD membrane released from its (1, 1) mode, all edges pinned."""
    model = flat_model("fd", nodes=(7, 7), force_model="frozen", material=dm.Material(mu=1.0, alpha=2.0),
                       constraints=[dm.Pin(ALL_EDGES)])
    X0 = model.initial_state()
    X0[:, 2] = 0.1 * (np.sin(np.pi * model.a1) * np.sin(np.pi * model.a2)).ravel()
    return model, X0


@pytest.mark.parametrize("scheme, order", [("implicit-euler", 1), ("newmark", 2)])
def test_temporal_order_of_the_implicit_schemes(scheme, order):
    """The mode at T = 0.6 s against a 16x finer reference of the same scheme."""
    model, X0 = frozen_membrane()

    def final(dt):
        return dm.TimeStepper(model, dt=dt, scheme=scheme).run(X0, t_end=0.6).state.X[:, 2]

    dts = [0.04, 0.02, 0.01]
    ref = final(dts[-1] / 16)
    errors = [np.max(np.abs(final(dt) - ref)) for dt in dts]
    p = fit_order(dts, errors)
    assert order - 0.25 <= p <= order + 0.35, f"{scheme}: observed order {p:.2f}, theory {order}"


def test_newmark_keeps_the_energy_of_a_linear_undamped_mode():
    """The trapezoidal rule conserves the quadratic energy of a linear system: no numerical damping."""
    model, X0 = frozen_membrane()
    stepper = dm.TimeStepper(model, dt=0.05, scheme="newmark")
    energies = [model.energy(s.X).total + model.kinetic_energy(s.V) for s in stepper.iterate(X0, 100)]
    e0 = model.energy(X0).total
    assert np.max(np.abs(np.array(energies) - e0)) < 1e-8 * e0
