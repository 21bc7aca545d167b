"""Force models (deformable.physics.force_models): the registry, what each answers, the elastic law of eq. (13)-(15).

The stretching bound (:func:`stretching_step`) is checked where it is measured: a backend's
``stable_step()`` against its own matrices and against runs (tests/deformable/backends/test_contract.py).
"""

import math

import numpy as np
import pytest
import scipy.sparse as sp

from deformable.physics.force_models import QuadraticEnergy, alpha, beta, energy_density, stretching_step

from ...conftest import flat_scene


def test_weights_and_density_vanish_at_rest_and_only_there(rng):
    eta, xi = rng.uniform(0.5, 2.0, size=(2, 2, 2, 5))
    G0, B0 = rng.normal(size=(2, 2, 2, 5))
    assert not alpha(eta, G0, G0).any() and not beta(xi, B0, B0).any()
    s, b = energy_density(eta, xi, G0, G0, B0, B0)
    assert not s.any() and not b.any()
    G, B = G0 + 0.1 * rng.normal(size=G0.shape), B0 + 0.1 * rng.normal(size=B0.shape)
    s, b = energy_density(eta, xi, G, G0, B, B0)
    assert np.all(s > 0) and np.all(b > 0)
    # the density is the weights' own quadratic form: sum alpha_ij (G_ij - G0_ij) (and beta likewise)
    np.testing.assert_allclose(s, np.sum(alpha(eta, G, G0) * (G - G0), axis=(0, 1)), rtol=1e-14)
    np.testing.assert_allclose(b, np.sum(beta(xi, B, B0) * (B - B0), axis=(0, 1)), rtol=1e-14)
    # without bending weights no curvature is needed (degenerate tangents allowed)
    s2, b2 = energy_density(eta, 0 * xi, G, G0, None, B0)
    np.testing.assert_array_equal(s2, s)
    assert not b2.any()


def test_stretching_step_is_infinite_without_stretching_weight_and_falls_with_stiffness():
    assert stretching_step(0.1, 0.0, 4.0) == math.inf
    assert stretching_step(0.1, 50.0, 4.0 * 24**2) > stretching_step(0.1, 50.0, 4.0 * 24**2, G=1.5)
    assert stretching_step(0.1, 50.0, 1.0) > stretching_step(0.1, 100.0, 1.0)


def test_quadratic_energy_is_half_RKR_split_into_its_parts(rng):
    A = sp.random(8, 8, density=0.5, random_state=1)
    Ka, Kb = (A @ A.T).tocsr(), sp.identity(8, format="csr") * 0.3
    q = QuadraticEnergy((Ka + Kb).tocsr(), Ka, Kb)
    X = rng.normal(size=(8, 3))
    e = q.energy(X)
    assert e.stretching == pytest.approx(0.5 * np.sum(X * (Ka @ X)), rel=1e-14)
    assert e.bending == pytest.approx(0.15 * np.sum(X * X), rel=1e-14)
    np.testing.assert_allclose(q.gradient(X), (Ka + Kb) @ X, rtol=1e-14)
    np.testing.assert_allclose(q.hessian(X) @ X.T.ravel(), q.gradient(X).T.ravel(), rtol=1e-13)


def test_force_models_are_told_what_they_lack():
    with pytest.raises(ValueError, match="tpbf87.*no energy gradient.*variational"):
        flat_scene(nodes=(3, 3)).force_model.require_energy()
    with pytest.raises(ValueError, match="no strength matrix.*implicit-euler"):
        flat_scene(nodes=(3, 3), force_model="variational").force_model.require_strength_matrix()
    flat_scene(nodes=(3, 3), force_model="variational").force_model.require_energy()
    flat_scene(nodes=(3, 3)).force_model.require_strength_matrix()
