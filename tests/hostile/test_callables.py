"""Issue 48: a user's callable that raises or returns NaN or inf is named where it enters: the field it was given
for, the point and the time; not a SingularMatrix from deep in Newton's direction, nor its bare exception."""

import math

import numpy as np
import pytest

import deformable as dm
from validation.harness.backends import make_model

MATERIAL = dm.Material(mu=0.1, eta=np.full((2, 2), 50.0), xi=np.full((2, 2), 1e-3))


def _step(force, backend="fd"):
    scene = dm.Scene(dm.Sheet(size=(1.0, 1.0), nodes=(6, 6)), MATERIAL, forces=[force],
                     constraints=[dm.Clamp(["left"])], force_model="variational")
    model = make_model(scene, backend)
    return dm.TimeStepper(model, 0.01).run(model.initial_state(), steps=2)


def _nan_at_the_far_edge(a1, a2, t):
    return np.where(a1[..., None] > 0.9, math.nan, 1.0) * np.ones(a1.shape + (3,))


def _fails(*args):
    raise ZeroDivisionError("the user's own bug")


@pytest.mark.parametrize("backend", ["fd", "fe"])
@pytest.mark.parametrize("force, field, where", [
    (dm.Gravity(time=lambda t: math.inf), "Gravity.time", "at t = "),
    (dm.BodyForce(f=_nan_at_the_far_edge), "BodyForce.f", "at a1 = "),  # the first point beyond 0.9 m
    (dm.EdgeLoad("right", f=_fails), "EdgeLoad.f", "the callable raised ZeroDivisionError: the user's own bug"),
    (dm.EdgeMoment("right", m=lambda a1, a2, t: math.nan * a1), "EdgeMoment.m", "at a1 = 1 m"),
    (dm.PointLoad(at=(1.0, 0.5), f=(0.0, 0.0, -1.0), time=_fails), "PointLoad.time", "raised ZeroDivisionError"),
])
def test_a_callable_s_fault_is_named_where_it_enters(force, field, where, backend):
    with pytest.raises(dm.InputError) as err:
        _step(force, backend)
    assert err.value.field == field and where in str(err.value) and "\n" not in str(err.value)
