"""The strength matrix and the stepper of eq. (22)-(27) against exact discrete answers."""

import numpy as np
import pytest
import scipy.linalg as sla

import deformable as dm

from .conftest import flat_model


def lam(k, n_nodes, L):
    """Eigenvalue of -D11 (natural rule, pinned ends) for the sine mode k: 4/h^2 sin^2(k pi h / 2L)."""
    h = L / (n_nodes - 1)
    return 4 / h**2 * np.sin(k * np.pi * h / (2 * L)) ** 2


def test_frozen_eigenvalues_equal_the_exact_discrete_ones():
    """All edges pinned: sine modes are exact eigenvectors of the difference operators, so the
    eigenvalues of K against M are alpha (l1 + l2) + beta (l1^2 + l2^2) / mu exactly."""
    M, N, L1, L2 = 9, 7, 1.2, 0.9
    alpha, beta, mu = 3.0, 0.02, 2.5
    model = flat_model(nodes=(M, N), size=(L1, L2), force_model="frozen",
                       material=dm.Material(mu=mu, alpha=alpha, beta=beta),
                       constraints=[dm.Pin(["left", "right", "bottom", "top"])])
    free = np.setdiff1d(np.arange(model.ndof), model.fixed_dofs()[2])
    K = model.stiffness(model.initial_state()).toarray()[np.ix_(free, free)]
    Md = model.mass().toarray()[np.ix_(free, free)]
    computed = np.sort(sla.eigh(K, Md, eigvals_only=True))
    l1 = np.array([lam(j, M, L1) for j in range(1, M - 1)])
    l2 = np.array([lam(k, N, L2) for k in range(1, N - 1)])
    exact = np.sort((alpha * (l1[:, None] + l2[None, :]) + beta * (l1[:, None] ** 2 + l2[None, :] ** 2)).ravel() / mu)
    assert np.max(np.abs(computed - exact) / exact) < 1e-10


def single_mode(nodes=(11, 11), alpha=4.0, mu=1.5, dt=0.01, steps=60):
    """A frozen membrane released from its (1, 1) sine mode; returns the mode amplitude per step and w."""
    M, N = nodes
    model = flat_model(nodes=nodes, force_model="frozen", material=dm.Material(mu=mu, alpha=alpha),
                       constraints=[dm.Pin(["left", "right", "bottom", "top"])])
    mode = (np.sin(np.pi * model.a1) * np.sin(np.pi * model.a2)).ravel()
    X0 = model.initial_state()
    X0[:, 2] = 1e-2 * mode
    w = np.sqrt(alpha * (lam(1, M, 1.0) + lam(1, N, 1.0)) / mu)
    stepper = dm.TimeStepper(model, dt=dt)
    amp = [X0[:, 2] @ mode / (mode @ mode)] + [s.X[:, 2] @ mode / (mode @ mode) for s in stepper.iterate(X0, steps)]
    return np.array(amp), w, model


def test_stepper_amplification_and_phase_of_one_undamped_mode():
    """Eq. (22)-(27) on x'' = -w^2 x: x_{n+1} (1 + w^2 dt^2) = 2 x_n - x_{n-1}, so each step multiplies
    the complex amplitude by rho e^{i theta}, rho = (1 + w^2 dt^2)^(-1/2), theta = atan(w dt)."""
    dt = 0.01
    amp, w, _ = single_mode(dt=dt)
    rho, theta = (1 + (w * dt) ** 2) ** -0.5, np.arctan(w * dt)
    n = np.arange(amp.size)
    x0 = amp[0]  # V0 = 0 means x_{-1} = x_0
    b = (x0 * np.cos(theta) - rho * x0) / np.sin(theta)
    expected = rho**n * (x0 * np.cos(n * theta) + b * np.sin(n * theta))
    assert np.max(np.abs(amp - expected)) < 1e-10 * abs(x0)


def test_prestressed_membrane_oscillates_at_the_discrete_laplacian_frequency():
    """tpbf87 with G0 = 0.81 I on a flat pinned sheet: alpha = 0.19 eta, and a small bump oscillates
    at w_d = sqrt(alpha (l1 + l2) / mu), seen through the stepper's phase atan(w_d dt) per step."""
    M = N = 17
    eta, mu, dt = 50.0, 1.0, 2e-3
    model = flat_model(nodes=(M, N), material=dm.Material(mu=mu, gamma=0.0, eta=eta),
                       rest_metric=0.81, constraints=[dm.Pin(["left", "right", "bottom", "top"])])
    X0 = model.initial_state()
    X0[:, 2] = 1e-4 * (np.sin(np.pi * model.a1) * np.sin(np.pi * model.a2)).ravel()
    w_d = np.sqrt(eta * 0.19 * (lam(1, M, 1.0) + lam(1, N, 1.0)) / mu)
    centre = (M // 2) * N + N // 2
    z = np.array([X0[centre, 2]] + [s.X[centre, 2] for s in dm.TimeStepper(model, dt).iterate(X0, 1500)])
    # zero crossings by linear interpolation; half a period between consecutive ones
    i = np.flatnonzero(np.sign(z[:-1]) != np.sign(z[1:]))
    crossings = i + z[i] / (z[i] - z[i + 1])
    theta = np.pi / np.mean(np.diff(crossings))  # measured phase advance per step
    w_measured = np.tan(theta) / dt  # undo the stepper's known phase shift atan(w dt)
    assert len(crossings) >= 6
    assert abs(w_measured / w_d - 1) < 5e-3, f"w measured {w_measured:.5f}, discrete Laplacian {w_d:.5f}"


@pytest.mark.parametrize("weighting, order", [("pointwise", 1), ("control-area", 2)])
def test_free_edge_order_depends_on_control_area_weighting(weighting, order):
    """A strip pinned at a1 = 0, free at a1 = L = 1, under the load q = sin(2 a1 + c): -alpha w'' = q,
    w(0) = 0, w'(L) = 0, so w = (sin(2 a1 + c) - sin c)/(4 alpha) - a1 cos(2 L + c)/(2 alpha).
    (A uniform load has a quadratic solution, which the control-area scheme reproduces exactly.)
    The natural-boundary rows are a flux balance over half a cell:
    pointwise loads give first order, control-area weights second (DESIGN.md). The strip has free
    edges a2 = 0, L2 too, so this also checks that the weighting is consistent along them."""
    alpha, c = 2.0, 0.5
    load = lambda a1, a2, t: np.stack([0 * a1, 0 * a1, np.sin(2 * a1 + c)], axis=-1)  # noqa: E731
    hs, errors = [], []
    for M in (9, 17, 33, 65):
        model = flat_model(nodes=(M, 4), force_model="frozen", weighting=weighting,
                           material=dm.Material(alpha=alpha), constraints=[dm.Pin("left")],
                           forces=[dm.BodyForce(f=load)])
        free = np.setdiff1d(np.arange(model.ndof), model.fixed_dofs()[2])
        K = model.stiffness(model.initial_state()).tocsr()[free][:, free]
        F = model.load(model.initial_state(), 0.0)[free, 2]
        w = np.zeros(model.ndof)
        w[free] = np.linalg.solve(K.toarray(), F)
        a1 = model.a1
        exact = ((np.sin(2 * a1 + c) - np.sin(c)) / (4 * alpha) - a1 * np.cos(2 + c) / (2 * alpha)).ravel()
        hs.append(model.h1)
        errors.append(np.max(np.abs(w - exact)))
    p = np.polyfit(np.log(hs), np.log(errors), 1)[0]
    assert order - 0.2 <= p <= order + 0.3, f"{weighting}: observed order {p:.2f}, theory {order}"
    assert errors[-1] < 0.5 * hs[-1] ** order


def test_stiffness_keeps_its_pattern_and_the_stepper_reuses_it(rng):
    model = flat_model(nodes=(8, 9), material=dm.Material(eta=10.0, xi=0.1), constraints=[dm.Pin("top")])
    X = model.initial_state()
    K1, K2 = model.stiffness(X), model.stiffness(X + 0.01 * rng.normal(size=X.shape))
    assert np.array_equal(K1.indptr, K2.indptr) and np.array_equal(K1.indices, K2.indices)
    assert not np.array_equal(K1.data, K2.data)


def test_slide_lets_nodes_move_along_their_axis_only():
    model = flat_model(nodes=(9, 9), material=dm.Material(mu=1.0, gamma=0.5, eta=20.0),
                       constraints=[dm.Slide("top", axis="x"), dm.Pin("top-left")],
                       forces=[dm.Gravity(direction=(0, -1, 0)), dm.EdgeLoad("top", f=(3.0, 0, 0))])
    X0 = model.initial_state()
    state = dm.TimeStepper(model, dt=2e-3).run(X0, steps=100).state
    top = model.grid(state.X)[:, -1]
    top0 = model.grid(X0)[:, -1]
    assert np.array_equal(top[:, 1:], top0[:, 1:])  # y and z held on the rail
    assert np.max(np.abs(top[1:, 0] - top0[1:, 0])) > 1e-4  # x moved
    assert np.array_equal(top[0], top0[0])  # the pinned corner holds


def test_pin_motion_prescribes_positions():
    model = flat_model(nodes=(7, 7), material=dm.Material(mu=1.0, gamma=1.0, eta=10.0),
                       constraints=[dm.Pin("left", motion=lambda t: (0.0, 0.0, 0.5 * t))])
    X0 = model.initial_state()
    states = list(dm.TimeStepper(model, dt=0.01).iterate(X0, 10))
    left = model.grid(states[-1].X)[0]
    assert np.allclose(left[:, 2], 0.5 * states[-1].t, rtol=0, atol=1e-15)
