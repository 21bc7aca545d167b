"""The FD strength matrix K(r) of eq. (16)-(20) (fdmodel.strength)."""

import numpy as np
import pytest
import scipy.sparse as sp

import deformable as dm
from fdmodel.operators import operators
from fdmodel.strength import StrengthMatrix
from validation.harness.backends import make_model
from validation.harness.surfaces import get

from ..conftest import FULL_ETA, FULL_XI, flat_model


def paper_K(ops, alpha, beta):
    """Eq. (20) from the operators: sum_ij D_i+^T diag(alpha_ij) D_j+ + D_ij^T diag(beta_ij) D_ij."""
    D = {1: ops["D1"], 2: ops["D2"]}
    DD = {(1, 1): ops["D11"], (1, 2): ops["D12"], (2, 1): ops["D12"], (2, 2): ops["D22"]}
    K = sp.csr_matrix(ops["D1"].shape)
    for i in (1, 2):
        for j in (1, 2):
            K = K + D[i].T @ sp.diags(alpha[i - 1, j - 1].ravel()) @ D[j]
            K = K + DD[i, j].T @ sp.diags(beta[i - 1, j - 1].ravel()) @ DD[i, j]
    return K


def symmetric_field(rng, shape):
    T = rng.normal(size=(2, 2) + shape)
    return T + np.swapaxes(T, 0, 1)


def centred(w, stretching):
    """Node fields (2, 2, M, N) at the centres of the terms they weigh: 11 (22) the mean of nodes m, m + 1 (n,
    n + 1) for stretching, the node for bending; 12 the mean of the cell's four nodes; the last row kept."""
    out = np.array(w)
    mid1 = lambda u: np.concatenate([0.5 * (u[:-1] + u[1:]), u[-1:]], axis=0)  # noqa: E731
    mid2 = lambda u: mid1(u.T).T  # noqa: E731
    if stretching:
        out[0, 0], out[1, 1] = mid1(w[0, 0]), mid2(w[1, 1])
    out[0, 1], out[1, 0] = mid2(mid1(w[0, 1])), mid2(mid1(w[1, 0]))
    return out


def test_the_stiffness_is_the_cell_area_times_the_papers_K(rng):
    """Frozen fields (node arrays, carried to the centres of their terms) and the tpbf87 alpha, beta of a
    deformed curved sheet alike (pointwise rows)."""
    M, N = 7, 6
    alpha, beta = symmetric_field(rng, (M, N)), symmetric_field(rng, (M, N))
    frozen = flat_model("fd", nodes=(M, N), size=(1.2, 0.9), force_model="frozen",
                        material=dm.Material(alpha=alpha, beta=beta))
    h1, h2 = frozen.spacing
    K = frozen.stiffness(frozen.initial_state())
    ops = operators(M, N, h1, h2)
    expected = paper_K(ops, centred(alpha, True), centred(beta, False))
    assert abs(K / (h1 * h2) - expected).max() < 1e-12 * abs(K).max() / (h1 * h2)
    curved = make_model(dm.Scene(dm.Sheet(size=(1.2, 0.9), nodes=(M, N), rest=get("monge")),
                                 dm.Material(eta=FULL_ETA, xi=FULL_XI)), "fd")
    X = curved.initial_state() + 0.05 * rng.normal(size=(curved.ndof, 3))
    K = curved.stiffness(X)
    assert abs(K / (h1 * h2) - paper_K(ops, *curved.alpha_beta(X))).max() < 1e-12 * abs(K).max() / (h1 * h2)


def test_parts_sum_to_the_matrix_and_a_membrane_keeps_the_small_stencil(rng):
    M, N = 7, 6
    ops = operators(M, N, 0.2, 0.3)
    ones = {k: np.ones((M, N)) for k in ops}
    alpha, beta = symmetric_field(rng, (M, N)), symmetric_field(rng, (M, N))
    full = StrengthMatrix(ops, ones, 0.06, bending=True)
    Ka, Kb = full.parts(alpha, beta)
    assert abs(Ka + Kb - full.matrix(alpha, beta)).max() < 1e-12 * abs(Ka).max()
    membrane = StrengthMatrix(ops, ones, 0.06, bending=False)
    union = abs(ops["D1"].T @ ops["D1"]) + abs(ops["D2"].T @ ops["D2"]) + abs(ops["D1"].T @ ops["D2"]) \
        + abs(ops["D2"].T @ ops["D1"])
    assert membrane.pattern.nnz == union.nnz < full.pattern.nnz
    assert abs(membrane.matrix(alpha, 0 * beta) - Ka).max() < 1e-12 * abs(Ka).max()


@pytest.mark.parametrize("weighting", ["pointwise", "control-area"])
def test_the_rows_integrate_the_membrane_energy_of_a_flat_sheet(weighting):
    """Frozen alpha = I on the flat sheet at rest: E = R^T K R / 2 = (1/2) integral (r_1 . r_1 + r_2 . r_2)
    = L1 L2 exactly with the trapezoidal (control-area) rows; the pointwise difference rows cover
    L1 (L2 + h2) and (L1 + h1) L2."""
    L1, L2 = 1.0, 1.2
    model = flat_model("fd", nodes=(6, 7), size=(L1, L2), weighting=weighting, force_model="frozen",
                       material=dm.Material(alpha=1.0))
    h1, h2 = model.spacing
    expected = L1 * L2 if weighting == "control-area" else 0.5 * (L1 * (L2 + h2) + (L1 + h1) * L2)
    assert abs(model.energy(model.initial_state()).stretching / expected - 1) < 1e-13
