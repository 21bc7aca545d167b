"""FDModel (fdmodel.model): what only the finite-difference backend promises.

The contract both backends share is tests/deformable/backends/test_contract.py.
"""

import contextlib

import numpy as np
import pytest
import scipy.linalg as sla

import deformable as dm
from validation.harness.backends import make_model
from validation.harness.orders import fit_order
from validation.harness.surfaces import get

from ..conftest import ALL_EDGES, FULL_ETA, FULL_XI, flat_model, free_dofs, sine_eigenvalue


def test_rest_state_force_and_energy_are_exactly_zero():
    """G0 and B0 are eq. (18)-(19) of the rest nodes themselves: the force vanishes to the last bit."""
    s = get("monge")
    sheet = dm.Sheet(size=s.size, nodes=(13, 11), rest=s)
    model = make_model(dm.Scene(sheet, dm.Material(eta=FULL_ETA, xi=FULL_XI)), "fd")
    X = model.initial_state()
    assert np.max(np.abs(model.internal_force(X))) == 0.0
    assert model.energy(X).total == 0.0


def test_unknown_weighting_names_the_valid_ones():
    with pytest.raises(ValueError, match=r"weighting must be one of \('pointwise', 'control-area'\)"):
        flat_model("fd", weighting="trapezoid")


def test_pins_hold_nodes_and_a_clamp_holds_its_edge_row():
    """The clamp's slope is the ghost row's (fdmodel.clamp), under the paper's force as under the energy."""
    model = flat_model("fd", nodes=(6, 5), constraints=[dm.Pin("bottom-left"), dm.Clamp("top")])
    idx = np.arange(30).reshape(6, 5)
    expected = {0} | set(idx[:, -1].ravel().tolist())
    for f in model.fixed_dofs():
        assert set(f.tolist()) == expected


def test_sample_is_exact_at_nodes_and_bilinear_between():
    s = get("monge")
    model = make_model(dm.Scene(dm.Sheet(size=s.size, nodes=(9, 9), rest=s), dm.Material(eta=1.0, xi=1.0)), "fd")
    X = model.initial_state()
    G, B = model.tensors(X)
    a = np.array([[model.a1[3, 2], model.a2[3, 2]], [model.a1[8, 8], model.a2[8, 8]]])
    smp = model.sample(X, a)
    assert np.array_equal(smp.r[0], model.grid(X)[3, 2]) and np.array_equal(smp.G[1], G[:, :, 8, 8])
    mid = model.sample(X, [[(model.a1[3, 2] + model.a1[4, 2]) / 2, model.a2[3, 2]]])
    assert np.allclose(mid.B[0], (B[:, :, 3, 2] + B[:, :, 4, 2]) / 2, rtol=0, atol=1e-14)


def test_frozen_eigenvalues_equal_the_exact_discrete_ones():
    """All edges pinned: sine modes are exact eigenvectors of the difference operators, so the
    eigenvalues of K against M are alpha (l1 + l2) + beta (l1^2 + l2^2) / mu exactly."""
    M, N, L1, L2 = 9, 7, 1.2, 0.9
    alpha, beta, mu = 3.0, 0.02, 2.5
    model = flat_model("fd", nodes=(M, N), size=(L1, L2), force_model="frozen",
                       material=dm.Material(mu=mu, alpha=alpha, beta=beta), constraints=[dm.Pin(ALL_EDGES)])
    free = free_dofs(model)
    K = model.stiffness(model.initial_state()).toarray()[np.ix_(free, free)]
    Md = model.mass().toarray()[np.ix_(free, free)]
    computed = np.sort(sla.eigh(K, Md, eigvals_only=True))
    l1 = np.array([sine_eigenvalue(j, M, L1) for j in range(1, M - 1)])
    l2 = np.array([sine_eigenvalue(k, N, L2) for k in range(1, N - 1)])
    exact = np.sort((alpha * (l1[:, None] + l2[None, :]) + beta * (l1[:, None] ** 2 + l2[None, :] ** 2)).ravel() / mu)
    assert np.max(np.abs(computed - exact) / exact) < 1e-10


ETA, XI = 3.0, 0.02
#: transverse operator about a flat sheet (docs/design.md, "Three readings of the model"):
#: e_z = -a (w11 + w22) + b (w1111 + w2222); (force model, g0, b0, a, b)
LINEAR_CASES = [
    ("tpbf87", 0.81, 0.0, ETA * (1 - 0.81), 0.0),
    ("tpbf87", 0.81, -0.5, ETA * (1 - 0.81), -XI * -0.5),
    ("variational", 0.81, 0.0, 4 * ETA * (1 - 0.81), 2 * XI),
]


@pytest.mark.parametrize("force_model, g0, b0, a, b", LINEAR_CASES, ids=["tpbf87", "tpbf87-b0", "variational"])
def test_linear_transverse_operator_about_a_flat_sheet(force_model, g0, b0, a, b):
    """With all edges pinned the sine modes are exact eigenvectors: the eigenvalues of the z-block of K
    (tpbf87) or of the energy Hessian (variational) against M are (a (l1 + l2) + b (l1^2 + l2^2)) / mu."""
    M, N, mu = 9, 8, 1.7
    # B0 = b0 I on a flat sheet is incompatible on purpose (the tpbf87 reading's bending stiffness)
    with pytest.warns(dm.IncompatibleRestState) if b0 else contextlib.nullcontext():
        model = flat_model("fd", nodes=(M, N), force_model=force_model, material=dm.Material(mu=mu, eta=ETA, xi=XI),
                           rest_metric=g0, rest_curvature=b0, constraints=[dm.Pin(ALL_EDGES)])
    X, n = model.initial_state(), model.ndof
    free = free_dofs(model)
    Kz = (model.energy_hessian(X).toarray()[2 * n:, 2 * n:] if force_model == "variational"
          else model.stiffness(X).toarray())[np.ix_(free, free)]
    computed = np.sort(sla.eigh(Kz, model.mass().toarray()[np.ix_(free, free)], eigvals_only=True))
    l1 = np.array([sine_eigenvalue(j, M, 1.0) for j in range(1, M - 1)])[:, None]
    l2 = np.array([sine_eigenvalue(k, N, 1.0) for k in range(1, N - 1)])[None, :]
    exact = np.sort((a * (l1 + l2) + b * (l1**2 + l2**2)).ravel() / mu)
    assert np.max(np.abs(computed - exact) / exact) < 1e-9


@pytest.mark.parametrize("weighting, order", [("pointwise", 1), ("control-area", 2)])
def test_free_edge_order_depends_on_control_area_weighting(weighting, order):
    """A strip pinned at a1 = 0, free at a1 = L = 1, under the load q = sin(2 a1 + c): -alpha w'' = q,
    w(0) = 0, w'(L) = 0, so w = (sin(2 a1 + c) - sin c)/(4 alpha) - a1 cos(2 L + c)/(2 alpha).
    (A uniform load has a quadratic solution, which the control-area scheme reproduces exactly.)
    The natural-boundary rows are a flux balance over half a cell:
    pointwise loads give first order, control-area weights second (docs/design.md). The strip has free
    edges a2 = 0, L2 too, so this also checks that the weighting is consistent along them."""
    alpha, c = 2.0, 0.5
    load = lambda a1, a2, t: np.stack([0 * a1, 0 * a1, np.sin(2 * a1 + c)], axis=-1)  # noqa: E731
    hs, errors = [], []
    for M in (9, 17, 33, 65):
        model = flat_model("fd", nodes=(M, 4), force_model="frozen", weighting=weighting,
                           material=dm.Material(alpha=alpha), constraints=[dm.Pin("left")],
                           forces=[dm.BodyForce(f=load)])
        free = free_dofs(model)
        K = model.stiffness(model.initial_state()).tocsr()[free][:, free]
        F = model.load(model.initial_state(), 0.0)[free, 2]
        w = np.zeros(model.ndof)
        w[free] = np.linalg.solve(K.toarray(), F)
        a1 = model.a1
        exact = ((np.sin(2 * a1 + c) - np.sin(c)) / (4 * alpha) - a1 * np.cos(2 + c) / (2 * alpha)).ravel()
        hs.append(model.h1)
        errors.append(np.max(np.abs(w - exact)))
    p = fit_order(hs, errors)
    assert order - 0.2 <= p <= order + 0.3, f"{weighting}: observed order {p:.2f}, theory {order}"
    assert errors[-1] < 0.5 * hs[-1] ** order
