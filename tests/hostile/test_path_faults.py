"""Issue 48: equilibrium_path with nothing to follow, or a tangent matrix with a free mode, says so in one line
instead of SuperLU's "Factor is exactly singular"."""

import warnings

import numpy as np
import pytest

import deformable as dm
from validation.harness.backends import make_model

MATERIAL = dm.Material(mu=0.1, eta=np.full((2, 2), 50.0), xi=np.full((2, 2), 1e-3))


def _model(forces, constraints=("left",)):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # a free sheet is ill-posed on purpose below
        scene = dm.Scene(dm.Sheet(size=(1.0, 1.0), nodes=(6, 6)), MATERIAL, forces=forces,
                         constraints=[dm.Clamp(list(constraints))] if constraints else [], force_model="variational")
    return make_model(scene, "fd")


@pytest.mark.parametrize("forces", [[], [dm.Gravity(time=lambda t: t)]], ids=["no load", "time load at t = 0"])
def test_a_path_with_no_load_to_follow_is_an_input_error_naming_t(forces):
    model = _model(forces)
    with pytest.raises(dm.InputError, match="no load to follow at t = 0 s") as err:
        dm.equilibrium_path(model, model.initial_state(), 0.01, steps=2)
    assert err.value.field == "t" and "\n" not in str(err.value)
    assert len(dm.equilibrium_path(model, model.initial_state(), 0.01, steps=1, t=1.0)) == 2 if forces else True


def test_a_singular_tangent_is_a_convergence_error_naming_the_load_factor(monkeypatch):
    """SuperLU's RuntimeError on an exactly singular matrix (a free mode) becomes the path's own error."""
    import deformable.solve.continuation as continuation

    def singular(A, **options):
        raise RuntimeError("Factor is exactly singular")

    monkeypatch.setattr(continuation.spla, "splu", singular)
    model = _model([dm.Gravity()])
    with pytest.raises(dm.ConvergenceError, match="tangent matrix is singular at load factor 0 "):
        dm.equilibrium_path(model, model.initial_state(), 0.01, steps=2)
