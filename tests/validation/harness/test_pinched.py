"""The pinched cylinder over rigid diaphragms (validation/harness/shells.py) against Sze, Liu and Lo's table before
its snap: the octant's constraints and load as the source models them. The whole path is the shells study's, at
its full level."""

import numpy as np
import pytest

import deformable as dm
from validation.harness import shells
from validation.harness.backends import make_model
from validation.studies.shells import _at_levels


@pytest.mark.slow  # about 25 s
def test_the_pinched_cylinder_follows_the_published_path_before_its_snap():
    model = make_model(shells.pinched_cylinder(17), "fe")
    arc, half = shells.PINCHED["R"] * np.pi / 2, shells.PINCHED["L"] / 2
    path = dm.equilibrium_path(model, model.initial_state(), length=2.0, steps=40, max_load=0.1)
    table = shells.PINCHED_TABLE[1:4]  # P / P_max = 0.05, 0.075, 0.1
    ours = _at_levels(np.asarray(path.loads), [-path.displacement(model, (arc, half), 2)], table[:, 0])
    assert all(o is not None for o in ours)
    err = [abs(o[0] - w) / w for o, w in zip(ours, table[:, 1])]
    assert max(err) <= 0.02, err
