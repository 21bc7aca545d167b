"""G (eq. 18) and B (eq. 19) on the node grid: closed forms and observed orders."""

from dataclasses import dataclass

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import deformable as dm
from fdmodel import FDModel
from validation.orders import fit_order
from validation.surfaces import get

from .conftest import flat_model


def fd_tensors(surface, n):
    sheet = dm.Sheet(size=surface.size, nodes=(n, n), rest=surface)
    model = FDModel(dm.Scene(sheet, dm.Material(eta=1.0, xi=1.0)))
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
        inner = (slice(1, -1), slice(1, -1))
        Gx = np.moveaxis(s.G_exact(model.a1, model.a2), (-2, -1), (0, 1))
        Bx = np.moveaxis(s.B_exact(model.a1, model.a2), (-2, -1), (0, 1))
        hs.append(1 / (n - 1))
        eG.append(np.max(np.abs(G - Gx)[(slice(None), slice(None)) + inner]))
        eB.append(np.max(np.abs(B - Bx)[(slice(None), slice(None)) + inner]))
    pG, pB = fit_order(hs, eG), fit_order(hs, eB)
    assert 0.8 <= pG <= 1.3, f"sphere G at nodes: observed order {pG:.2f}, theory 1"
    assert 0.8 <= pB <= 1.3, f"sphere B at nodes: observed order {pB:.2f}, theory 1"
    assert eG[-1] < 2 * hs[-1] and eB[-1] < 2 * hs[-1]


@dataclass(frozen=True)
class OrderCase:
    """An FD quantity on the generic Monge patch, where it is compared, and the order theory gives."""

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


def monge_error(case: OrderCase, n: int) -> float:
    s = get("monge")
    model, G, B = fd_tensors(s, n)
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
def test_observed_orders_on_generic_monge_patch(case):
    hs = [1 / (n - 1) for n in LEVELS]
    errors = [monge_error(case, n) for n in LEVELS]
    p = fit_order(hs, errors)
    lo, hi = case.window
    assert lo <= p <= hi, f"{case.name}: observed order {p:.3f}, theory {case.order}, errors {errors}"
    # the derivatives of the patch are O(3^k): the leading error constant is O(10) at most
    assert errors[-1] < 10 * hs[-1] ** case.order, f"{case.name}: finest error {errors[-1]:.3e}"


def rotation(q):
    q = np.asarray(q, float)
    q = q / np.linalg.norm(q)
    w, x, y, z = q
    return np.array([
        [1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
        [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
        [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)],
    ])


unit = st.floats(-1, 1, allow_nan=False)


@settings(max_examples=40, deadline=None)
@given(q=st.tuples(unit, unit, unit, unit).filter(lambda q: np.linalg.norm(q) > 0.1),
       shift=st.tuples(*[st.floats(-100, 100, allow_nan=False)] * 3))
def test_G_and_B_are_invariant_under_rigid_motions(q, shift):
    model, G, B = fd_tensors(get("monge"), 11)
    X = model.initial_state() @ rotation(q).T + np.asarray(shift)
    G2, B2 = model.tensors(X)
    # round-off: positions up to 1e2 differenced over h = 0.1
    tol = 1e-13 * (1 + np.max(np.abs(shift))) / model.h1**2
    assert np.max(np.abs(G2 - G)) < tol and np.max(np.abs(B2 - B)) < tol


def test_rest_state_has_zero_internal_force():
    s = get("monge")
    sheet = dm.Sheet(size=s.size, nodes=(13, 11), rest=s)
    material = dm.Material(eta=np.array([[5.0, 1.0], [1.0, 3.0]]), xi=np.array([[0.5, 0.2], [0.2, 0.1]]))
    model = FDModel(dm.Scene(sheet, material))
    X = model.initial_state()
    assert np.max(np.abs(model.internal_force(X))) == 0.0
    assert model.energy(X).total == 0.0


def test_stiffness_is_symmetric_for_full_tensors(rng):
    s = get("monge")
    material = dm.Material(eta=np.array([[5.0, 1.5], [1.5, 3.0]]), xi=np.array([[0.5, 0.2], [0.2, 0.1]]))
    model = FDModel(dm.Scene(dm.Sheet(nodes=(12, 10), rest=s), material))
    X = model.initial_state() + 0.05 * rng.normal(size=(model.ndof, 3))
    K = model.stiffness(X)
    asym = abs(K - K.T).max() / abs(K).max()
    assert asym < 1e-12, f"relative asymmetry {asym:.2e}"


def test_frozen_stiffness_is_symmetric():
    alpha = np.array([[2.0, 0.7], [0.7, 1.0]])
    model = flat_model(nodes=(8, 11), force_model="frozen", material=dm.Material(alpha=alpha, beta=0.3))
    K = model.stiffness(model.initial_state())
    assert abs(K - K.T).max() / abs(K).max() < 1e-12


def test_sample_is_exact_at_nodes_and_bilinear_between():
    model, G, B = fd_tensors(get("monge"), 9)
    X = model.initial_state()
    a = np.array([[model.a1[3, 2], model.a2[3, 2]], [model.a1[8, 8], model.a2[8, 8]]])
    s = model.sample(X, a)
    assert np.array_equal(s.r[0], model.grid(X)[3, 2]) and np.array_equal(s.G[1], G[:, :, 8, 8])
    mid = model.sample(X, [[(model.a1[3, 2] + model.a1[4, 2]) / 2, model.a2[3, 2]]])
    assert np.allclose(mid.B[0], (B[:, :, 3, 2] + B[:, :, 4, 2]) / 2, rtol=0, atol=1e-14)
    with pytest.raises(ValueError, match="sample points"):
        model.sample(X, [[2.0, 0.5]])
