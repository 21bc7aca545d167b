"""Difference operators of the TPBF87 appendix (fdmodel.operators), and G (eq. 18) and B (eq. 19) from them."""

from dataclasses import dataclass

import numpy as np
import pytest

import deformable as dm
from fdmodel.operators import node_derivatives, operators, tangent_1d, valid_rows
from validation.harness.backends import make_model
from validation.harness.orders import fit_order
from validation.harness.surfaces import get

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


# -- G (eq. 18) and B (eq. 19) at the nodes ---------------------------------------------------
def fd_tensors(surface, n):
    sheet = dm.Sheet(size=surface.size, nodes=(n, n), rest=surface)
    model = make_model(dm.Scene(sheet, dm.Material(eta=1.0, xi=1.0)), "fd")
    G, B = model.tensors(model.initial_state())
    return model, G, B


def test_plane_is_exact():
    model, G, B = fd_tensors(get("plane"), 9)
    assert np.array_equal(G, np.broadcast_to(np.eye(2)[:, :, None, None], G.shape))
    assert np.all(B == 0)


def test_cylinder_matches_the_closed_form_of_the_discrete_tensors():
    """On r = (R cos(a1/R), R sin(a1/R), a2) the differences have closed forms:
    |D1+ r| = 2 R sin(h/2R)/h, n at a node is the chord's outward normal, D11 r = 2 R (cos(h/R) - 1)/h^2 (cos, sin, 0)."""
    R, n = 0.6, 17
    model, G, B = fd_tensors(get("cylinder"), n)
    h = 1.0 / (n - 1)
    chord = (2 * R * np.sin(h / (2 * R)) / h) ** 2
    inner = (slice(1, -1), slice(1, -1))
    tol = 1e-12
    assert np.max(np.abs(G[0, 0][inner] - chord)) < tol
    assert np.max(np.abs(G[1, 1][inner] - 1)) < tol and np.max(np.abs(G[0, 1][inner])) < tol
    b11 = 2 * R * (np.cos(h / R) - 1) / h**2 * np.cos(h / (2 * R))
    assert np.max(np.abs(B[0, 0][inner] - b11)) < 1e-10
    assert np.max(np.abs(B[1, 1][inner])) < tol and np.max(np.abs(B[0, 1][inner])) < tol
    # ... and those tend to the continuum values G = I, B = diag(-1/R, 0) at O(h^2)
    assert abs(chord - 1) < h**2 / (12 * R**2) * 1.01 and abs(b11 + 1 / R) < h**2 / R**3


def test_sphere_interior_nodes_converge_to_closed_form_at_first_order():
    s = get("sphere")
    hs, eG, eB = [], [], []
    for n in (17, 33, 65):
        model, G, B = fd_tensors(s, n)
        inner = (slice(None), slice(None), slice(1, -1), slice(1, -1))
        Gx = np.moveaxis(s.G_exact(model.a1, model.a2), (-2, -1), (0, 1))
        Bx = np.moveaxis(s.B_exact(model.a1, model.a2), (-2, -1), (0, 1))
        hs.append(1 / (n - 1))
        eG.append(np.max(np.abs(G - Gx)[inner]))
        eB.append(np.max(np.abs(B - Bx)[inner]))
    pG, pB = fit_order(hs, eG), fit_order(hs, eB)
    assert 0.8 <= pG <= 1.3, f"sphere G at nodes: observed order {pG:.2f}, theory 1"
    assert 0.8 <= pB <= 1.3, f"sphere B at nodes: observed order {pB:.2f}, theory 1"
    assert eG[-1] < 2 * hs[-1] and eB[-1] < 2 * hs[-1]


@dataclass(frozen=True)
class OrderCase:
    """An FD quantity on the generic Monge patch, where it is compared, and the order theory gives:
    first at the nodes (forward differences are centred at half-nodes), second at the stencil centres."""

    name: str
    order: float
    window: tuple[float, float]


LEVELS = (17, 33, 65, 129)
MONGE_CASES = [
    OrderCase("G11 at nodes", 1, (0.85, 1.25)),
    OrderCase("G22 at nodes", 1, (0.85, 1.25)),
    OrderCase("G11 at edge midpoints", 2, (1.8, 2.25)),
    OrderCase("G22 at edge midpoints", 2, (1.8, 2.25)),
    OrderCase("G12 at nodes", 1, (0.85, 1.25)),
    OrderCase("B11 at nodes", 1, (0.85, 1.25)),
    OrderCase("B12 at nodes", 1, (0.85, 1.25)),
    OrderCase("B22 at nodes", 1, (0.85, 1.25)),
]


@pytest.fixture(scope="module")
def monge_levels():
    return {n: fd_tensors(get("monge"), n) for n in LEVELS}


def monge_error(case: OrderCase, model, G, B) -> float:
    s = get("monge")
    a1, a2, h = model.a1, model.a2, model.h1
    valid = model.valid
    comp = {"11": (0, 0), "12": (0, 1), "22": (1, 1)}[case.name[1:3]]
    if case.name.startswith("G"):
        where = {"G11": (h / 2, 0), "G22": (0, h / 2)}.get(case.name[:3], (0, 0)) if "midpoints" in case.name else (0, 0)
        exact = s.G(a1 + where[0], a2 + where[1])[comp]
        mask = valid["D1"] if comp[0] == 0 else valid["D2"]
        mask = mask & (valid["D1"] if comp[1] == 0 else valid["D2"])
        return float(np.max(np.abs(G[comp] - exact)[mask]))
    exact = s.B(a1, a2)[comp]
    mask = valid["D11"] & valid["D22"]  # nodes where all of eq. (19) is defined
    return float(np.max(np.abs(B[comp] - exact)[mask]))


@pytest.mark.parametrize("case", MONGE_CASES, ids=lambda c: c.name)
def test_observed_orders_on_generic_monge_patch(case, monge_levels):
    hs = [1 / (n - 1) for n in LEVELS]
    errors = [monge_error(case, *monge_levels[n]) for n in LEVELS]
    p = fit_order(hs, errors)
    lo, hi = case.window
    assert lo <= p <= hi, f"{case.name}: observed order {p:.3f}, theory {case.order}, errors {errors}"
    # the derivatives of the patch are O(3^k): the leading error constant is O(10) at most
    assert errors[-1] < 10 * hs[-1] ** case.order, f"{case.name}: finest error {errors[-1]:.3e}"


def test_backward_tangents_mirror_the_forward_ones():
    """The backward tangent operator (forward on the first row) is the forward one (backward on the last row)
    read from the other end of the row, with the sign of the reversed direction."""
    F, B = tangent_1d(6, 0.3).toarray(), tangent_1d(6, 0.3, backward=True).toarray()
    assert np.array_equal(B, -F[::-1, ::-1])
    u = np.arange(6.0) ** 2 * 0.09  # (0.3 k)^2: backward differences (2 a - h) inside, forward on the first row
    a = 0.3 * np.arange(6)
    assert np.allclose((B @ u)[1:], 2 * a[1:] - 0.3) and np.isclose((B @ u)[0], 0.3)
