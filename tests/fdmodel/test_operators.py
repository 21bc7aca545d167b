"""Difference operators of the TPBF87 appendix: exact on the polynomials they must differentiate."""

import numpy as np
import pytest

from fdmodel.operators import node_derivatives, operators, valid_rows

M, N, L1, L2 = 9, 7, 1.3, 0.8
h1, h2 = L1 / (M - 1), L2 / (N - 1)
a1, a2 = np.meshgrid(np.linspace(0, L1, M), np.linspace(0, L2, N), indexing="ij")
OPS = operators(M, N, h1, h2)
VALID = valid_rows(M, N)
EXACT = 1e-11  # round-off of differences of O(1) values over h ~ 0.1


def apply(name, u):
    return (OPS[name] @ u.ravel()).reshape(M, N)


def test_forward_difference_exact_on_quadratics_at_midpoints():
    u = lambda x, y: 0.7 * x**2 - 1.1 * x * y + 0.4 * y**2 + 2 * x - y  # noqa: E731
    d1 = apply("D1", u(a1, a2))
    d2 = apply("D2", u(a1, a2))
    ex1 = 1.4 * (a1 + h1 / 2) - 1.1 * a2 + 2
    ex2 = -1.1 * a1 + 0.8 * (a2 + h2 / 2) - 1
    assert np.max(np.abs(d1 - ex1)[VALID["D1"]]) < EXACT
    assert np.max(np.abs(d2 - ex2)[VALID["D2"]]) < EXACT
    # natural boundary rule: a difference that leaves the grid is zero
    assert np.all(d1[~VALID["D1"]] == 0) and np.all(d2[~VALID["D2"]] == 0)


def test_central_second_difference_exact_on_cubics():
    u = 0.3 * a1**3 - 0.5 * a1**2 * a2 + 0.2 * a2**3 + a1 * a2
    d11, d22 = apply("D11", u), apply("D22", u)
    assert np.max(np.abs(d11 - (1.8 * a1 - a2))[VALID["D11"]]) < 10 * EXACT
    assert np.max(np.abs(d22 - 1.2 * a2)[VALID["D22"]]) < 10 * EXACT
    assert np.all(d11[~VALID["D11"]] == 0) and np.all(d22[~VALID["D22"]] == 0)


def test_mixed_difference_exact_on_biquadratics_at_cell_centres():
    u = (a1**2 + 0.5 * a1) * (a2**2 - a2)
    d12 = apply("D12", u)
    c1, c2 = a1 + h1 / 2, a2 + h2 / 2
    assert np.max(np.abs(d12 - (2 * c1 + 0.5) * (2 * c2 - 1))[VALID["D12"]]) < 10 * EXACT
    assert np.all(d12[~VALID["D12"]] == 0)


@pytest.mark.parametrize("name", ["D1", "D2", "D11", "D22", "D12"])
def test_node_derivatives_agree_with_sparse_operators_where_defined(name):
    rng = np.random.default_rng(1)
    R = rng.normal(size=(M, N, 3))
    dr, ddr = node_derivatives(R, h1, h2)
    arrays = {"D1": dr[:, 0], "D2": dr[:, 1], "D11": ddr[:, 0, 0], "D22": ddr[:, 1, 1], "D12": ddr[:, 0, 1]}
    for c in range(3):
        sparse = apply(name, R[..., c])
        assert np.allclose(arrays[name][c][VALID[name]], sparse[VALID[name]], rtol=0, atol=1e-10)


def test_outer_operators_are_adjoints_of_inner_ones():
    """-D1-(alpha D1+ r) with the zero rule equals (D1+)^T diag(alpha) D1+ r (eq. 16-17)."""
    rng = np.random.default_rng(2)
    r, alpha = rng.normal(size=(M, N)), rng.normal(size=(M, N))
    p = alpha * apply("D1", r)  # zero on the last row by the natural rule
    # backward difference with p = 0 outside the grid
    padded = np.concatenate([np.zeros((1, N)), p], axis=0)
    minus_D1m_p = -(padded[1:] - padded[:-1]) / h1
    assert np.allclose(minus_D1m_p.ravel(), OPS["D1"].T @ p.ravel(), rtol=0, atol=1e-10)
