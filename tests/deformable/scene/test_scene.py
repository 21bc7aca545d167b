"""The scene (deformable.scene): validation and the rest tensors G0, B0."""

import warnings

import numpy as np
import pytest

import deformable as dm

from ...conftest import flat_model


def test_scene_rejects_unknown_force_models_and_foreign_objects():
    sheet, mat = dm.Sheet(nodes=(5, 5)), dm.Material(eta=1.0)
    with pytest.raises(ValueError, match=r"force_model.*'tpbf88'"):
        dm.Scene(sheet, mat, force_model="tpbf88")
    with pytest.raises(ValueError, match="'frozen' needs Material.alpha"):
        dm.Scene(sheet, mat, force_model="frozen")
    with pytest.raises(ValueError, match="is not a Gravity"):
        dm.Scene(sheet, mat, forces=[(0, 0, 1)])
    with pytest.raises(ValueError, match="is not a Pin, Slide, Clamp or Symmetry"):
        dm.Scene(sheet, mat, constraints=["top"])
    with pytest.raises(ValueError, match="Scene.rest_metric must be"):
        dm.Scene(sheet, mat, rest_metric=[[1.0, 0.2], [0.0, 1.0]])


@pytest.mark.parametrize("backend", ["fd", "fe"])
def test_rest_tensor_overrides_replace_those_of_the_rest_shape(backend):
    G0 = np.array([[0.81, 0.1], [0.1, 0.9]])
    model = flat_model(backend, nodes=(4, 4), rest_metric=G0)
    np.testing.assert_array_equal(model.G0, np.broadcast_to(G0[:, :, None, None], model.G0.shape))
    with pytest.raises(ValueError, match=r"Scene.rest_metric callable returned shape"):
        flat_model(backend, nodes=(4, 4), rest_metric=lambda a1, a2: np.ones(a1.shape + (3,)))


def test_with_nodes_keeps_everything_but_the_grid():
    scene = dm.Scene(dm.Sheet(size=(2.0, 1.0), nodes=(5, 5)), dm.Material(eta=3.0), forces=[dm.Gravity()],
                     constraints=[dm.Pin("top")], name="mine")
    finer = scene.with_nodes((9, 7))
    assert finer.sheet.nodes == (9, 7) and finer.sheet.size == (2.0, 1.0)
    assert (finer.material, finer.forces, finer.constraints, finer.name) == (scene.material, scene.forces,
                                                                             scene.constraints, "mine")


@pytest.mark.parametrize("eta, xi, free", [
    (1.0, 0.0, ["shear"]), (1.0, 0.1, ["shear", "twist"]), ([[1.0, 1.0], [1.0, 1.0]], 0.1, ["twist"]),
])
def test_the_variational_model_without_off_diagonal_weights_warns_what_is_free(eta, xi, free):
    with pytest.warns(dm.IllPosedScene) as caught:
        dm.Scene(dm.Sheet(nodes=(4, 4)), dm.Material(eta=eta, xi=xi), force_model="variational")
    message = str(caught[0].message)
    assert all(f in message for f in free) and "full weight tensors" in message


def test_full_tensors_and_the_papers_force_do_not_warn():
    with warnings.catch_warnings():
        warnings.simplefilter("error", dm.IllPosedScene)
        dm.Scene(dm.Sheet(nodes=(4, 4)), dm.Material(eta=[[1.0, 1.0], [1.0, 1.0]], xi=[[0.1, 0.1], [0.1, 0.1]]),
                 force_model="variational")
        dm.Scene(dm.Sheet(nodes=(4, 4)), dm.Material(eta=1.0, xi=0.1), force_model="tpbf87")
