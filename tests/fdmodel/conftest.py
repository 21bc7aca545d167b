import numpy as np
import pytest

import deformable as dm
from fdmodel import FDModel


def flat_model(nodes=(9, 9), size=(1.0, 1.0), **scene):
    """An FD model of a flat sheet; keyword arguments go to Scene (material defaults below)."""
    material = scene.pop("material", dm.Material(mu=1.0, gamma=0.0, eta=10.0, xi=0.0))
    weighting = scene.pop("weighting", "pointwise")
    sheet = scene.pop("sheet", dm.Sheet(size=size, nodes=nodes))
    return FDModel(dm.Scene(sheet, material, **scene), weighting=weighting)


@pytest.fixture
def rng():
    return np.random.default_rng(12345)
