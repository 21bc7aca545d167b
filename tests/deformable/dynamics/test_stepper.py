"""The run controller (deformable.dynamics.stepper): schemes, arguments, divergence and resumption."""

import math

import numpy as np
import pytest

import deformable as dm

from ...conftest import flat_model


def hanging(dt, nodes=25):
    """docs/design.md's measured case: 24 x 24 cells, eta = 50, mu = 0.1, h = 1/24, the top edge pinned; the
    lagged alpha makes the step conditionally stable, dt below the model's stable_step() (1.3e-3)."""
    model = flat_model("fd", nodes=(nodes, nodes), material=dm.Material(mu=0.1, gamma=0.0, eta=50.0),
                       forces=[dm.Gravity(direction=(0, -1, 0))], constraints=[dm.Pin("top")])
    return model, dm.TimeStepper(model, dt=dt)


@pytest.mark.parametrize("dt", [0.0, -1e-3, math.nan, math.inf, "fast"])
def test_stepper_rejects_non_positive_dt(dt):
    with pytest.raises(ValueError, match=r"dt must be a?\s?positive"):
        dm.TimeStepper(flat_model("fd", nodes=(5, 5)), dt=dt)


def test_each_force_model_gets_its_scheme_and_refuses_the_others():
    frozen = flat_model("fd", nodes=(5, 5), force_model="frozen", material=dm.Material(alpha=1.0))
    variational = flat_model("fd", nodes=(5, 5), force_model="variational")
    tpbf87 = flat_model("fd", nodes=(5, 5))
    assert dm.TimeStepper(tpbf87, 1e-3).scheme == dm.TimeStepper(frozen, 1e-3).scheme == "semi-implicit"
    assert dm.TimeStepper(variational, 1e-3).scheme == "implicit-euler"
    assert dm.TimeStepper(frozen, 1e-3, scheme="newmark").scheme == "newmark"
    with pytest.raises(ValueError, match="needs an energy"):
        dm.TimeStepper(tpbf87, dt=1e-3, scheme="newmark")
    with pytest.raises(ValueError, match="no strength matrix|does not have"):
        dm.TimeStepper(variational, dt=1e-3, scheme="semi-implicit")
    with pytest.raises(ValueError, match=r"scheme must be one of.*'leapfrog'"):
        dm.TimeStepper(tpbf87, dt=1e-3, scheme="leapfrog")
    assert dm.SCHEMES == ("semi-implicit", "implicit-euler", "newmark")


def test_the_old_scheme_name_warns_and_is_the_semi_implicit_scheme_bit_for_bit():
    model, new = hanging(1e-3, nodes=9)
    with pytest.warns(DeprecationWarning, match="'tpbf87' is now called 'semi-implicit'"):
        old = dm.TimeStepper(model, dt=1e-3, scheme="tpbf87")
    assert old.scheme == "semi-implicit"
    a = old.run(model.initial_state(), steps=50).state
    b = new.run(model.initial_state(), steps=50).state
    np.testing.assert_array_equal(a.X, b.X)
    np.testing.assert_array_equal(a.V, b.V)


def test_diverging_run_stops_and_returns_the_last_good_state():
    model, stepper = hanging(dt=3e-3)
    result = stepper.run(model.initial_state(), steps=400)
    assert result.status == "diverged" and "diverged at step" in result.message
    assert result.steps < 400
    assert np.all(np.isfinite(result.state.X))
    assert result.state.step == result.steps


def test_stable_step_below_the_stretching_bound_runs_to_the_end():
    model, stepper = hanging(dt=1e-3)
    result = stepper.run(model.initial_state(), steps=150, trackers=[dm.EnergyMonitor(every=50)])
    assert result.status == "finished" and result.steps == 150
    assert result.message == f"150 steps to t = {result.state.t:.6g} s"
    history = result.trackers[1].history
    assert history.shape == (4, 4) and np.all(np.isfinite(history))
    assert set(stepper.timings) == {"assembly", "factorisation", "solve"} and stepper.newton_reports == []


def test_a_resumed_run_is_bit_identical():
    model, stepper = hanging(dt=1e-3, nodes=9)
    X0 = model.initial_state()
    whole = stepper.run(X0, steps=20).state
    half = dm.TimeStepper(model, dt=1e-3).run(X0, steps=10).state
    rest = dm.TimeStepper(model, dt=1e-3).run(X0, steps=10, resume=half).state
    assert rest.step == 20 and rest.t == whole.t
    np.testing.assert_array_equal(rest.X, whole.X)
    np.testing.assert_array_equal(rest.V, whole.V)
    by_time = dm.TimeStepper(model, dt=1e-3).run(X0, t_end=0.02)
    assert by_time.steps == 20


def test_run_arguments_are_checked():
    model, stepper = hanging(dt=1e-3, nodes=5)
    X0 = model.initial_state()
    with pytest.raises(ValueError, match="exactly one of t_end and steps"):
        stepper.run(X0, steps=3, t_end=1.0)
    with pytest.raises(ValueError, match="exactly one of t_end and steps"):
        stepper.run(X0)
    with pytest.raises(ValueError, match="steps must be a non-negative integer"):
        stepper.run(X0, steps=2.5)
    with pytest.raises(ValueError, match="t_end must be later than the start time"):
        stepper.run(X0, t_end=0.0)
    with pytest.raises(ValueError, match=r"X0 has shape \(3, 3\), expected \(25, 3\)"):
        stepper.run(X0[:3], steps=1)
    with pytest.raises(ValueError, match=r"V0 has shape"):
        stepper.run(X0, V0=np.zeros(3), steps=1)
