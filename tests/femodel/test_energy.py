"""The FE energy (13) by the Gauss rule and its derivatives (femodel.energy), beyond the shared contract."""

import warnings

import numpy as np

import deformable as dm
from validation.harness.backends import make_model
from validation.harness.surfaces import get

from ..conftest import FULL_ETA, FULL_XI, gradient_error


def test_gradient_with_a_given_rest_curvature_matches_finite_differences(rng):
    """An arbitrary B0 override (incompatible with the rest metric, eq. 10) is fine for checking derivatives,
    so its warning is expected and silenced."""
    sheet = dm.Sheet(size=(1.0, 0.8), nodes=(4, 3), rest=get("monge"))
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", dm.IncompatibleRestState)
        scene = dm.Scene(sheet, dm.Material(eta=FULL_ETA, xi=FULL_XI), force_model="variational",
                         rest_curvature=np.array([[1.5, -0.3], [-0.3, 0.7]]))
    model = make_model(scene, "fe")
    err = gradient_error(model, model.initial_state() + 0.05 * rng.normal(size=(model.ndof, 3)))
    assert err < 1e-6, f"relative gradient error {err:.2e}"


def test_hessians_are_symmetric_by_construction_on_one_pattern(rng):
    """Assembled from upper triangles: exactly symmetric; both kinds on one fixed pattern."""
    model = make_model(dm.Scene(dm.Sheet(size=(1.0, 0.8), nodes=(4, 3), rest=get("monge")),
                                dm.Material(eta=FULL_ETA, xi=FULL_XI), force_model="variational"), "fe")
    X = model.initial_state() + 0.05 * rng.normal(size=(model.ndof, 3))
    H, GN = model.energy_hessian(X, "newton"), model.energy_hessian(X, "gauss-newton")
    assert abs(H - H.T).max() == 0.0 and abs(GN - GN.T).max() == 0.0
    assert GN.indptr is H.indptr and GN.indices is H.indices
