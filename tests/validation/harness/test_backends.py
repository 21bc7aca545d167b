"""The backend factory (validation.harness.backends)."""

import pytest

import deformable as dm
from fdmodel import FDModel
from femodel import FEModel
from validation.harness.backends import BACKENDS, make_model


def test_each_name_gives_its_model_and_options_reach_it():
    scene = dm.Scene(dm.Sheet(nodes=(4, 4)), dm.Material())
    assert BACKENDS == ("fd", "fe")
    assert isinstance(make_model(scene, "fe"), FEModel)
    fd = make_model(scene, "fd", weighting="control-area")
    assert isinstance(fd, FDModel) and fd.weighting == "control-area"
    with pytest.raises(ValueError, match="unknown backend 'fv'; choose one of fd, fe"):
        make_model(scene, "fv")
