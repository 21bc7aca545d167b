"""Material parameters (deformable.physics.material): validation and the shapes a weight may take."""

import math

import numpy as np
import pytest

import deformable as dm


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


def test_per_node_arrays_of_the_wrong_shape_are_named():
    with pytest.raises(ValueError, match=r"Material\.eta has shape \(4, 4\).*\(5, 6\)"):
        dm.Scene(dm.Sheet(nodes=(5, 6)), dm.Material(eta=np.ones((4, 4))))
    with pytest.raises(ValueError, match=r"Material\.mu has shape \(3,\)"):
        dm.Scene(dm.Sheet(nodes=(5, 6)), dm.Material(mu=np.ones(3)))


def test_every_form_of_a_weight_is_the_same_tensor_field():
    nodes = (4, 3)
    field = np.array([[2.0, 0.5], [0.5, 1.0]])[:, :, None, None] * np.ones(nodes)
    for value in ([[2.0, 0.5], [0.5, 1.0]], field):
        np.testing.assert_array_equal(dm.Material(eta=value).tensor("eta", nodes), field)
    diagonal = dm.Material(xi=np.full(nodes, 3.0)).tensor("xi", nodes)
    np.testing.assert_array_equal(diagonal, dm.Material(xi=3.0).tensor("xi", nodes))
    assert np.all(diagonal[0, 1] == 0) and np.all(diagonal[1, 1] == 3.0)
    assert not dm.Material().tensor("alpha", nodes).any()  # not given: zero
    np.testing.assert_array_equal(dm.Material(mu=2.0).field("mu", nodes), np.full(nodes, 2.0))
    assert dm.Material(mu=1.0).replace(mu=2.0).mu == 2.0
    with pytest.raises(ValueError, match=r"Material\.mu must be positive"):
        dm.Material(mu=1.0).replace(mu=0.0)
