"""Bad input gets a ValueError that names the field and the value; diverging runs stop cleanly."""

import math

import numpy as np
import pytest

import deformable as dm
from fdmodel import FDModel


@pytest.mark.parametrize(
    "kwargs, field, value",
    [
        (dict(mu=0.0), "mu", "0.0"),
        (dict(mu=-2.0), "mu", "-2.0"),
        (dict(mu=math.nan), "mu", "nan"),
        (dict(gamma=-0.1), "gamma", "-0.1"),
        (dict(eta=math.nan), "eta", "nan"),
        (dict(xi=math.nan), "xi", "nan"),
        (dict(xi=-1.0), "xi", "-1.0"),
        (dict(eta=[[1.0, 2.0], [0.0, 1.0]]), "eta", "symmetric"),
        (dict(mu="heavy"), "mu", "heavy"),
    ],
)
def test_material_rejects_bad_values(kwargs, field, value):
    with pytest.raises(ValueError, match=rf"Material\.{field}.*{value}"):
        dm.Material(**kwargs)


@pytest.mark.parametrize(
    "kwargs, text",
    [
        (dict(nodes=(2, 5)), r"at least 3 nodes.*\(2, 5\)"),
        (dict(nodes=(5.5, 5)), r"two integers.*5\.5"),
        (dict(size=(1.0, -1.0)), r"Sheet\.size.*-1\.0"),
        (dict(size=(1.0, math.nan)), r"Sheet\.size.*nan"),
    ],
)
def test_sheet_rejects_bad_grids(kwargs, text):
    with pytest.raises(ValueError, match=text):
        dm.Sheet(**kwargs)


def test_per_node_arrays_of_the_wrong_shape_are_named():
    with pytest.raises(ValueError, match=r"Material\.eta has shape \(4, 4\).*\(5, 6\)"):
        dm.Scene(dm.Sheet(nodes=(5, 6)), dm.Material(eta=np.ones((4, 4))))
    with pytest.raises(ValueError, match=r"Material\.mu has shape \(3,\)"):
        dm.Scene(dm.Sheet(nodes=(5, 6)), dm.Material(mu=np.ones(3)))


def test_scene_rejects_unknown_force_model_and_empty_pins():
    sheet, mat = dm.Sheet(nodes=(5, 5)), dm.Material(eta=1.0)
    with pytest.raises(ValueError, match=r"force_model.*'tpbf88'"):
        dm.Scene(sheet, mat, force_model="tpbf88")
    scene = dm.Scene(sheet, mat, constraints=[dm.Pin(lambda a1, a2: a1 > 2.0)])
    with pytest.raises(ValueError, match="selects no node"):
        FDModel(scene)
    with pytest.raises(ValueError, match=r"unknown edge or corner 'middle'"):
        FDModel(dm.Scene(sheet, mat, constraints=[dm.Pin("middle")]))


@pytest.mark.parametrize("dt", [0.0, -1e-3, math.nan, math.inf])
def test_stepper_rejects_non_positive_dt(dt):
    model = FDModel(dm.Scene(dm.Sheet(nodes=(5, 5)), dm.Material(eta=1.0)))
    with pytest.raises(ValueError, match=r"dt must be positive"):
        dm.TimeStepper(model, dt=dt)


def test_schemes_must_fit_the_force_model():
    sheet, mat = dm.Sheet(nodes=(5, 5)), dm.Material(eta=1.0)
    with pytest.raises(ValueError, match="needs an energy"):
        dm.TimeStepper(FDModel(dm.Scene(sheet, mat)), dt=1e-3, scheme="newmark")
    with pytest.raises(ValueError, match="no strength matrix|does not have"):
        dm.TimeStepper(FDModel(dm.Scene(sheet, mat, force_model="variational")), dt=1e-3, scheme="tpbf87")
    with pytest.raises(ValueError, match=r"scheme must be one of.*'leapfrog'"):
        dm.TimeStepper(FDModel(dm.Scene(sheet, mat)), dt=1e-3, scheme="leapfrog")


def hanging(dt):
    """DESIGN.md's measured case: 24 x 24 nodes, eta = 50, mu = 0.1, h = 1/24; the lagged alpha makes
    the step conditionally stable, dt below about h sqrt(mu / (2 eta G)) = 1.3e-3."""
    scene = dm.Scene(dm.Sheet(nodes=(25, 25)), dm.Material(mu=0.1, gamma=0.0, eta=50.0),
                     forces=[dm.Gravity(direction=(0, -1, 0))], constraints=[dm.Pin("top")])
    model = FDModel(scene)
    return model, dm.TimeStepper(model, dt=dt)


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
    history = result.trackers[1].history
    assert history.shape == (4, 4) and np.all(np.isfinite(history))


def test_energy_bound_of_the_guard_stops_the_run():
    model, stepper = hanging(dt=1e-3)
    guard = dm.DivergenceGuard(max_energy=1e-6)
    result = stepper.run(model.initial_state(), steps=100, trackers=[guard])
    assert result.status == "diverged" and "energy" in result.message
    assert model.energy(result.state.X).total <= 1e-6
