"""TimeStepper.retune: a running simulation takes other material values (a slider of deformable view) and keeps its
solver: the Newton matrix's pattern and the factorisation's analysis stay, the motion is the new material's."""

import numpy as np
import pytest

import deformable as dm
from deformable import scenes
from deformable.algebra.solvers import available
from deformable.errors import InputError
from validation.harness.backends import make_model


def _model(**fields):
    return make_model(scenes.build(scenes.config("curtain", nodes=(10, 10), **fields)), "fd")


@pytest.mark.parametrize("solver", available())
def test_a_retuned_stepper_moves_as_a_new_one_with_the_new_material_and_keeps_its_solver(solver):
    model = _model()
    stepper = dm.TimeStepper(model, 5e-3, newton=dict(solver=solver))
    state = stepper.start(model.initial_state())
    for _ in range(20):
        state = stepper.step(state)
    block = stepper.newton.directions._system
    version, analysis = block.version, getattr(stepper.newton.solver, "_pattern", None)
    stiffer = _model(fabric="", eta=4 * scenes.config("curtain").eta, gamma=0.5)
    stepper.retune(stiffer)
    fresh = dm.TimeStepper(stiffer, 5e-3, newton=dict(solver=solver))
    fresh.start(model.initial_state())  # the same constraint reference
    a = b = state
    for _ in range(20):
        a, b = stepper.step(a), fresh.step(b)
    assert stepper.newton.directions._system is block and block.version == version  # the same pattern ...
    assert getattr(stepper.newton.solver, "_pattern", None) == analysis  # ... and the same analysis (PARDISO)
    # the same motion as a stepper built for the new material, to the Newton tolerance (vtol dt a step, 20 steps)
    assert np.max(np.abs(a.X - b.X)) <= 20 * 1e-2 * 5e-3
    assert np.max(np.abs(a.X - state.X)) > 1e-3  # it did move


def test_retune_refuses_another_grid_or_other_held_degrees_of_freedom():
    model = _model()
    stepper = dm.TimeStepper(model, 5e-3)
    with pytest.raises(InputError, match="same backend and grid"):
        stepper.retune(make_model(scenes.build(scenes.config("curtain", nodes=(12, 12))), "fd"))
    with pytest.raises(InputError, match="held degrees of freedom"):
        stepper.retune(_model(rings=1))
