"""Newton's method on a potential (deformable.newton), shared by the implicit steps and equilibrium."""

import numpy as np
import pytest
import scipy.sparse as sp

import deformable as dm
from deformable.newton import MAX_STEP, ConvergenceError, FlatEnergy, flat, minimise, unflat

from ..conftest import flat_model


def test_flat_vectors_are_coordinate_blocked(rng):
    X = rng.normal(size=(4, 3))
    x = flat(X)
    assert x[2 * 4 + 1] == X[1, 2]
    np.testing.assert_array_equal(unflat(x, 4), X)


def quartic(c):
    """phi = sum cosh(x - c): convex, minimum at c; its Hessian diag(cosh(x - c))."""
    return (lambda x: np.sum(np.cosh(x - c)), lambda x: np.sinh(x - c),
            lambda x, kind: sp.diags(np.cosh(x - c), format="csr"))


def test_minimise_converges_quadratically_and_keeps_held_entries():
    c = np.array([0.5, -1.0, 2.0, 0.3])
    free = np.array([True, True, False, True])
    x0 = np.zeros(4)
    x, report = minimise(*quartic(c), x0, free, rtol=0.0, atol=1e-13, max_iter=30, label="test")
    assert report.converged and x[2] == 0.0
    np.testing.assert_allclose(x[free], c[free], rtol=0, atol=1e-12)
    r = np.array(report.residuals)
    assert report.iterations == len(r) - 1 <= 8
    # quadratic convergence: each residual about the square of the one before, near the end
    assert r[-2] < 1e-6 and r[-1] <= 10 * r[-2] ** 2


def test_every_step_moves_no_entry_farther_than_max_step():
    c = np.array([1.0, -0.4])
    phi, grad, hess = quartic(c)
    path = [np.zeros(2)]

    def recording(x):
        path.append(x.copy())
        return phi(x)

    x, report = minimise(recording, grad, hess, np.zeros(2), np.ones(2, bool), rtol=0.0, atol=1e-12, max_iter=50,
                         label="test", max_step=0.1)
    assert report.converged and report.iterations >= 10  # 1.0 to go, 0.1 at a time
    accepted = [x for x in path]
    assert max(np.max(np.abs(b - a)) for a, b in zip(accepted, accepted[1:])) <= 0.1 + 1e-15


def test_an_indefinite_hessian_falls_back_to_a_descent_direction():
    """phi = x^4/4 - x^2/2 from x = 0.1, where the exact Hessian is negative: the minimum at x = 1 is reached."""
    phi = lambda x: float(np.sum(x**4 / 4 - x**2 / 2))  # noqa: E731
    grad = lambda x: x**3 - x  # noqa: E731

    def hess(x, kind):
        return sp.diags(3 * x**2 - 1 if kind == "newton" else 3 * x**2, format="csr")

    x, report = minimise(phi, grad, hess, np.array([0.1]), np.ones(1, bool), rtol=0.0, atol=1e-12, max_iter=50,
                         label="test")
    assert report.converged and abs(x[0] - 1.0) < 1e-10


def test_a_failed_line_search_is_a_convergence_error():
    phi = lambda x: 0.0 if np.all(x == 0) else np.nan  # noqa: E731
    with pytest.raises(ConvergenceError, match="thing: line search failed at iteration 1"):
        minimise(phi, lambda x: np.ones_like(x), lambda x, kind: sp.identity(2, format="csr"), np.zeros(2),
                 np.ones(2, bool), rtol=0.0, atol=1e-12, max_iter=5, label="thing")


def test_flat_energy_holds_the_constrained_coordinates():
    model = flat_model("fd", nodes=(4, 4), force_model="variational",
                       constraints=[dm.Pin("left", motion=lambda t: (0.0, 0.0, t))])
    fl = FlatEnergy(model)
    held = np.concatenate([a * model.ndof + f for a, f in enumerate(model.fixed_dofs())])
    assert not fl.free[held].any() and fl.free.sum() == 3 * model.ndof - held.size
    assert fl.max_step == pytest.approx(MAX_STEP * np.sqrt(2.0))
    X0 = model.initial_state()
    x = fl.hold(np.zeros(3 * model.ndof), X0, 2.0)
    np.testing.assert_array_equal(x[held], flat(model.prescribed(X0, 2.0))[held])
    assert not x[fl.free].any()
    with pytest.raises(ValueError, match="no energy gradient"):
        FlatEnergy(flat_model("fd", nodes=(4, 4)))
