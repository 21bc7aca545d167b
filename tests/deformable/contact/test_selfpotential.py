"""The self-contact barrier (deformable.contact.selfpotential): zero on a flat sheet, positive on a sheet folded
closer than dhat, its gradient the derivative of its energy, its Hessian symmetric and positive semi-definite,
and its step bound keeping a fold from passing through the sheet, on both backends."""

import math

import numpy as np
import pytest

import deformable as dm
from deformable.contact.selfpotential import SelfContactPotential
from fdmodel import FDModel
from femodel import FEModel
from validation.harness.folds import u_fold

DHAT = 0.05


def _model(cls):
    nodes = (16, 16) if cls is FDModel else (9, 9)  # FE: 9 x 9 nodes, a 17 x 17 contact mesh (its h/2 sub-grid)
    full = np.full((2, 2), 1.0)
    scene = dm.Scene(dm.Sheet(size=(1.0, 1.0), nodes=nodes), dm.Material(mu=0.1, gamma=0.0, eta=10.0 * full,
                     xi=1e-4 * full), forces=[dm.Gravity()], force_model="variational")
    return cls(scene)


def flat(X):
    return np.asarray(X, float).T.ravel()


@pytest.mark.parametrize("cls", [FDModel, FEModel])
def test_the_barrier_is_zero_on_a_flat_sheet_and_positive_on_a_fold_closer_than_dhat(cls):
    model = _model(cls)
    S = SelfContactPotential(model, DHAT)
    x0 = flat(model.initial_state())
    assert S.energy(x0) == 0.0 and not np.any(S.gradient(x0)) and S.hessian(x0).nnz == 0
    near, far = flat(model.discretize(u_fold(0.6 * DHAT))), flat(model.discretize(u_fold(3 * DHAT)))
    assert 0 < S.energy(near) < math.inf
    assert S.energy(near) > S.energy(flat(model.discretize(u_fold(0.9 * DHAT)))) > S.energy(far)  # closer costs more


@pytest.mark.parametrize("cls", [FDModel, FEModel])
def test_the_gradient_is_the_derivative_of_the_energy_and_the_hessian_is_symmetric_psd(cls):
    model = _model(cls)
    S = SelfContactPotential(model, DHAT)
    x = flat(model.discretize(u_fold(0.6 * DHAT)))
    g = S.gradient(x)
    assert np.linalg.norm(g) > 0
    rng = np.random.default_rng(1)
    for _ in range(3):
        v = rng.standard_normal(x.size)
        v *= 1e-6 / np.max(np.abs(S.Wv @ v))  # vertices move at most 1 um
        fd = (S.energy(x + v) - S.energy(x - v)) / 2
        assert fd == pytest.approx(g @ v, rel=1e-5)
    H = S.hessian(x).toarray()
    assert np.allclose(H, H.T, rtol=0, atol=1e-9 * np.max(np.abs(H)))
    assert np.linalg.eigvalsh(H).min() >= -1e-8 * np.max(np.abs(H))


@pytest.mark.parametrize("cls", [FDModel, FEModel])
def test_a_step_through_the_sheet_is_cut_short_of_it_and_a_step_apart_is_taken_whole(cls):
    model = _model(cls)
    S = SelfContactPotential(model, DHAT)
    gap = 0.6 * DHAT
    x = flat(model.discretize(u_fold(gap)))
    X = x.reshape(3, -1)
    values = np.asarray(model.value_dofs)  # the degrees of freedom that are node positions
    y, z = X[1, values], X[2, values]
    patch = values[(z > 0.9 * gap) & (0.2 < y) & (y < 0.35)]  # inside the upper leg, away from the bend
    step = np.zeros_like(X)
    step[2, patch] = -3 * gap  # would carry that patch through the lower leg, the bend's side held
    down = step.ravel()
    assert S.mesh.intersects((x + down).reshape(3, -1).T) and not S.mesh.intersects(X.T)
    alpha = S.max_step(x, down)
    assert 0 < alpha < 1 / 3  # the legs meet a third of the way
    assert not S.mesh.intersects((x + alpha * down).reshape(3, -1).T)
    assert S.energy(x + alpha * down) < math.inf and S.energy(x + down) == math.inf
    assert S.max_step(x, -down) == 1.0
