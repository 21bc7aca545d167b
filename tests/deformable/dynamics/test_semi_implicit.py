"""The paper's semi-implicit step, eq. (22)-(27) (deformable.dynamics.semi_implicit), against exact answers."""

import numpy as np

import deformable as dm
from validation.harness.backends import make_model

from ...conftest import ALL_EDGES, flat_model, sine_eigenvalue, vertical_hanging


def single_mode(nodes=(11, 11), alpha=4.0, mu=1.5, dt=0.01, steps=60):
    """A frozen FD membrane released from its (1, 1) sine mode; returns the mode amplitude per step and w."""
    M, N = nodes
    model = flat_model("fd", nodes=nodes, force_model="frozen", material=dm.Material(mu=mu, alpha=alpha),
                       constraints=[dm.Pin(ALL_EDGES)])
    mode = (np.sin(np.pi * model.a1) * np.sin(np.pi * model.a2)).ravel()
    X0 = model.initial_state()
    X0[:, 2] = 1e-2 * mode
    w = np.sqrt(alpha * (sine_eigenvalue(1, M, 1.0) + sine_eigenvalue(1, N, 1.0)) / mu)
    stepper = dm.TimeStepper(model, dt=dt)
    amp = [X0[:, 2] @ mode / (mode @ mode)] + [s.X[:, 2] @ mode / (mode @ mode) for s in stepper.iterate(X0, steps)]
    return np.array(amp), w, stepper


def test_amplification_and_phase_of_one_undamped_mode():
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


def test_a_linear_model_is_factorised_once_for_the_run():
    _, _, stepper = single_mode(steps=3)
    once = stepper.timings["factorisation"]
    list(stepper.iterate(stepper.start(stepper.model.initial_state()), 5))
    assert once > 0 and stepper.timings["factorisation"] == once and stepper.timings["solve"] > 0


def test_prestressed_membrane_oscillates_at_the_discrete_laplacian_frequency():
    """tpbf87 with G0 = 0.81 I on a flat pinned sheet: alpha = 0.19 eta, and a small bump oscillates
    at w_d = sqrt(alpha (l1 + l2) / mu), seen through the stepper's phase atan(w_d dt) per step."""
    M = N = 17
    eta, mu, dt = 50.0, 1.0, 2e-3
    model = flat_model("fd", nodes=(M, N), material=dm.Material(mu=mu, gamma=0.0, eta=eta),
                       rest_metric=0.81, constraints=[dm.Pin(ALL_EDGES)])
    X0 = model.initial_state()
    X0[:, 2] = 1e-4 * (np.sin(np.pi * model.a1) * np.sin(np.pi * model.a2)).ravel()
    w_d = np.sqrt(eta * 0.19 * (sine_eigenvalue(1, M, 1.0) + sine_eigenvalue(1, N, 1.0)) / mu)
    centre = (M // 2) * N + N // 2
    z = np.array([X0[centre, 2]] + [s.X[centre, 2] for s in dm.TimeStepper(model, dt).iterate(X0, 1500)])
    # zero crossings by linear interpolation; half a period between consecutive ones
    i = np.flatnonzero(np.sign(z[:-1]) != np.sign(z[1:]))
    crossings = i + z[i] / (z[i] - z[i + 1])
    theta = np.pi / np.mean(np.diff(crossings))  # measured phase advance per step
    w_measured = np.tan(theta) / dt  # undo the stepper's known phase shift atan(w dt)
    assert len(crossings) >= 6
    assert abs(w_measured / w_d - 1) < 5e-3, f"w measured {w_measured:.5f}, discrete Laplacian {w_d:.5f}"


def test_hanging_fe_sheet_runs_on_the_stepper():
    """A sheet hanging from its top edge (tpbf87) on FE's own stable step: gravity can release at most
    mu g L1 L2 * L2 (the whole sheet falling its own length)."""
    model = make_model(vertical_hanging(9), "fe")
    stepper = dm.TimeStepper(model, dt=0.3 * model.stable_step())
    monitor = dm.EnergyMonitor()
    result = stepper.run(model.initial_state(), steps=200, trackers=[monitor])
    assert result.status == "finished", result.message
    h = monitor.history  # rows (t, stretching, bending, kinetic)
    bound = 0.1 * 9.81 * 1.0
    assert np.all(h[:, 1:].sum(axis=1) < 0.1 * bound), f"energy up to {h[:, 1:].sum(axis=1).max():.3g} J"
    z = model.grid(result.state.X)[..., 2] - model.grid(model.initial_state())[..., 2]
    assert np.all(z[:, -1] == 0) and z[:, 0].mean() < -1e-3  # top held, bottom sagged
    assert stepper.timings["assembly"] > 0 and stepper.timings["solve"] > 0
