"""Weights that vary over the sheet: each FD term weighed at its own centre (fdmodel.operators.centred_tensor),
second order on a manufactured problem (validation.harness.manufactured); FE recovers the same solution."""

import numpy as np
import pytest

import deformable as dm
from fdmodel.operators import centred_tensor
from validation.harness import manufactured
from validation.harness.backends import make_model
from validation.harness.orders import pairwise_orders

LEVELS = (9, 17, 33)


def errors(backend, weights, levels=LEVELS):
    out = []
    for n in levels:
        model = make_model(manufactured.scene(n, weights), backend)
        X, _ = dm.equilibrium(model, model.initial_state(), tol=1e-9)
        out.append(manufactured.node_error(model, X))
    return np.array(out)


@pytest.mark.parametrize("weights", ["callable", "nodes"])
def test_fd_is_second_order_under_varying_weights(weights):
    """Theory: second order (every term a midpoint rule). A node's weight half a cell from its term, as
    before, gives order 1 (measured 1.49, 1.31, 1.18 on 9..65 nodes, 6.4e-4 at 33); the bound on the finest
    error is twice the centred error measured at 33 nodes (1.50e-4)."""
    e = errors("fd", weights)
    orders = pairwise_orders(1.0 / (np.array(LEVELS) - 1), e)
    assert np.all((orders > 1.8) & (orders < 2.3)), (e, orders)
    assert e[-1] < 3e-4, e


def test_fe_recovers_the_manufactured_solution_at_its_order():
    """Bicubic Hermite elements: order 4 in the nodal values (a check of the manufactured load itself;
    measured 3.83, 1.19e-6 at 17 nodes)."""
    e = errors("fe", "callable", levels=(9, 17))
    order = np.log2(e[0] / e[1])
    assert 3.5 < order < 4.7 and e[-1] < 2e-6, (e, order)


def test_a_callable_weight_stands_at_each_terms_centre():
    sheet = dm.Sheet(size=(2.0, 1.0), nodes=(5, 4))
    h1, h2 = sheet.h
    a1, a2 = sheet.coordinates()

    def w(x, y):  # a full tensor whose components tell where they were evaluated
        return np.stack([np.stack([x, x + y], -1), np.stack([x + y, y], -1)], -2)

    eta = centred_tensor(dm.Material(eta=w), "eta", sheet)
    inner1, inner2 = (slice(None, -1), slice(None)), (slice(None), slice(None, -1))
    np.testing.assert_allclose(eta[0, 0][inner1], (a1 + h1 / 2)[inner1])  # at (m + 1/2, n)
    np.testing.assert_allclose(eta[1, 1][inner2], (a2 + h2 / 2)[inner2])  # at (m, n + 1/2)
    np.testing.assert_allclose(eta[0, 1][:-1, :-1], (a1 + a2 + (h1 + h2) / 2)[:-1, :-1])  # at the cell centre
    np.testing.assert_allclose(eta[0, 0][-1], a1[-1])  # no term past the last row: the node
    xi = centred_tensor(dm.Material(xi=w), "xi", sheet)
    np.testing.assert_allclose(xi[0, 0], a1)  # D11 is central: at the node
    np.testing.assert_allclose(xi[1, 1], a2)
    np.testing.assert_allclose(xi[0, 1][:-1, :-1], (a1 + a2 + (h1 + h2) / 2)[:-1, :-1])


def test_a_uniform_weight_is_the_same_in_every_form():
    """A constant callable, a (2, 2) array and a node array give the same FD and FE models (to round-off)."""
    sheet = dm.Sheet(size=(1.0, 1.0), nodes=(6, 5), initial=manufactured.shape)
    T = np.array([[3.0, 1.0], [1.0, 2.0]])
    forms = [T, T[:, :, None, None] * np.ones(sheet.nodes), lambda a1, a2: np.broadcast_to(T, a1.shape + (2, 2))]
    for backend in ("fd", "fe"):
        values = []
        for eta, mu in zip(forms, [1.0, 1.0, lambda a1, a2: 1.0 + 0 * a1]):
            model = make_model(dm.Scene(sheet, dm.Material(mu=mu, eta=eta, xi=0.5),
                                        force_model="variational"), backend)
            X = model.initial_state()
            values.append((model.energy(X).total, model.energy_gradient(X), model.mass().diagonal()))
        e0, g0, m0 = values[0]
        for e, g, m in values[1:]:
            assert abs(e - e0) <= 1e-12 * abs(e0)
            np.testing.assert_allclose(g, g0, rtol=0, atol=1e-12 * np.abs(g0).max())
            np.testing.assert_allclose(m, m0, rtol=1e-14)


@pytest.mark.parametrize("eta, message", [
    (lambda a1, a2: -1.0 + 0 * a1, r"Material\.eta must be non-negative"),
    (lambda a1, a2: np.nan * a1, r"Material\.eta must be finite"),
    (lambda a1, a2: np.ones(3), r"Material\.eta: the callable returned shape \(3,\)"),
    (lambda a1, a2: 1 / 0, r"Material\.eta: the callable failed.*ZeroDivisionError"),
    (lambda a1, a2: np.stack([np.stack([a1, a1], -1), np.stack([0 * a1, a1], -1)], -2),
     r"Material\.eta must be symmetric"),
])
def test_a_bad_callable_weight_is_named_when_the_scene_is_built(eta, message):
    with pytest.raises(dm.InputError, match=message):
        dm.Scene(dm.Sheet(nodes=(4, 4)), dm.Material(eta=eta))


def test_a_callable_material_keeps_its_meaning_on_every_grid():
    """Unlike a node array, a callable refines with the grid (Scene.with_nodes), and node consumers read its
    node values (Scene.nodal_material)."""
    scene = dm.Scene(dm.Sheet(nodes=(5, 5)), dm.Material(mu=lambda a1, a2: 1.0 + a1, eta=10.0))
    fine = scene.with_nodes((9, 9))
    np.testing.assert_allclose(fine.nodal_material().mu, 1.0 + fine.sheet.coordinates()[0])
    assert make_model(fine, "fd").mu.shape == (9, 9)


@pytest.mark.parametrize("backend", ["fd", "fe"])
def test_a_callable_material_runs_through_a_time_step_and_the_series_fields(backend):
    """The node consumers (the stable-step estimate of dt = "auto", the series' fields) read its node values."""
    from deformable.io.series import node_fields

    full = lambda a1, a2: np.stack([np.stack([10 + a2, 1 + 0 * a1], -1), np.stack([1 + 0 * a1, 10 + a1], -1)], -2)  # noqa: E731
    mat = dm.Material(mu=lambda a1, a2: 0.1 + 0.05 * a1, gamma=0.01, eta=full, xi=np.full((2, 2), 1e-3))
    scene = dm.Scene(dm.Sheet(size=(1.0, 1.0), nodes=(7, 7)), mat, forces=[dm.Gravity()], constraints=[dm.Pin("top")],
                     force_model="variational")
    model = make_model(scene, backend)
    result = dm.TimeStepper(model, "auto").run(model.initial_state(), steps=2)
    assert np.all(np.isfinite(result.state.X)) and result.state.step == 2
    assert "G11" in node_fields(model, result.state.X, result.state.V)
