r"""The bicubic Hermite element (femodel.hermite): its shape functions, exactness and interpolation orders.

Theory (interpolation by bicubics, smooth surface, max norm): the error of the k-th derivatives of r is
O(h^(4-k)), so G = r_i . r_j is O(h^3) and B = n . r_ij is O(h^2) anywhere in an element. At the 2 x 2
Gauss points the second derivatives of the tensor-product Hermite interpolant superconverge (the Gauss
points of degree 2 are the zeros of the leading error term of the 1-D second derivative, s^2 - s + 1/6),
so B is O(h^3) there. Windows: order 3 -> [2.6, 3.6], order 2 -> [1.7, 2.6].

The rectangle is 1 x 1.3 (h1 != h2) so a swap of h1 and h2 cannot hide. The surfaces are the harness's
generic Monge patch and its non-orthogonal skew sheet (G12 = 0.4 + z_1 z_2).
"""

from dataclasses import dataclass

import numpy as np
import pytest

import deformable as dm
from femodel.hermite import LOCAL, basis, cubic_hermite, evaluate
from validation.harness.backends import make_model
from validation.harness.orders import fit_order
from validation.harness.surfaces import get

from ..conftest import Polynomial

EPS = np.finfo(float).eps
SIZE = (1.0, 1.3)
LEVELS = (8, 16, 32, 64)
FINE = (8, 16, 32, 64, 128, 256)


def test_shape_functions_are_dual_to_the_scaled_nodal_dofs():
    """h1^p h2^q d^(p+q) phi_l at corner (a, b) is 1 for l = (a, b, p, q) and 0 otherwise."""
    h = (0.3, 0.7)
    for a in (0, 1):
        for b in (0, 1):
            for p in (0, 1):
                for q in (0, 1):
                    v = basis(np.array([float(a)]), np.array([float(b)]), h, (p, q))[:, 0] * h[0] ** p * h[1] ** q
                    expected = np.array([float(loc == (a, b, p, q)) for loc in LOCAL])
                    assert np.max(np.abs(v - expected)) < 10 * EPS, (a, b, p, q, v)


def test_one_dimensional_derivatives_are_those_of_the_values():
    s, e = np.linspace(0.05, 0.95, 7), 1e-6
    for order in (1, 2):
        numeric = (cubic_hermite(s + e, order - 1) - cubic_hermite(s - e, order - 1)) / (2 * e)
        assert np.max(np.abs(cubic_hermite(s, order) - numeric)) < 1e-8
    with pytest.raises(ValueError, match="order must be 0, 1 or 2"):
        cubic_hermite(s, 3)


def test_evaluate_is_the_basis_expansion_on_every_element(rng):
    ldofs = np.array([rng.choice(40, 16, replace=False) for _ in range(3)])
    X = rng.normal(size=(40, 3))
    s, t = rng.uniform(size=(2, 5))
    tables = [basis(s, t, (0.2, 0.5), d) for d in ((0, 0), (1, 1))]
    out = evaluate(X, ldofs, tables)
    assert out.shape == (3, 2, 3, 5)
    for e in range(3):
        for k, T in enumerate(tables):
            np.testing.assert_allclose(out[:, k, e], X[ldofs[e]].T @ T, rtol=1e-13)


def test_bicubic_surfaces_are_reproduced_exactly(rng):
    model = make_model(dm.Scene(dm.Sheet(size=SIZE, nodes=(6, 5)), dm.Material(eta=1.0)), "fe")
    c = rng.normal(size=(4, 4, 3)) * 0.3
    c[1, 0] += [1.0, 0.0, 0.0]
    c[0, 1] += [0.0, 1.0, 0.0]
    surface = Polynomial(c)
    a = rng.uniform([0, 0], SIZE, size=(200, 2))
    smp = model.sample(model.discretize(surface), a)
    r1, r2 = surface.r1(a[:, 0], a[:, 1]), surface.r2(a[:, 0], a[:, 1])
    G = np.stack([np.stack([(r1 * r1).sum(-1), (r1 * r2).sum(-1)], -1),
                  np.stack([(r1 * r2).sum(-1), (r2 * r2).sum(-1)], -1)], -2)
    assert np.max(np.abs(smp.r - surface.r(a[:, 0], a[:, 1]))) < 1e-13
    assert np.max(np.abs(smp.G - G)) < 1e-12


def gauss_points(model, k: int) -> np.ndarray:
    """The k x k Gauss points of every element, (E k^2, 2) parameter coordinates."""
    x, _ = np.polynomial.legendre.leggauss(k)
    x = (x + 1) / 2
    i, j = (v.ravel()[:, None] for v in np.meshgrid(np.arange(model.M - 1), np.arange(model.N - 1), indexing="ij"))
    return np.stack([((i + np.repeat(x, k)) * model.h1).ravel(), ((j + np.tile(x, k)) * model.h2).ravel()], axis=1)


@dataclass(frozen=True)
class Case:
    surface: str
    quantity: str  # "G" or "B"
    gauss: int  # k x k Gauss points per element
    window: tuple[float, float]
    bound: float  # on the error at 64 x 64 elements

    def __str__(self):
        return f"{self.surface}-{self.quantity}-gauss{self.gauss}"


CASES = [
    Case("monge", "G", 4, (2.6, 3.6), 3e-6),
    Case("monge", "B", 4, (1.7, 2.6), 1e-3),
    Case("monge", "B", 2, (2.6, 3.6), 6e-6),
    Case("skew", "G", 4, (2.6, 3.6), 1e-7),
    Case("skew", "B", 4, (1.7, 2.6), 1e-4),
    Case("skew", "B", 2, (2.6, 3.6), 4e-7),
]


def error(case: Case, n: int) -> float:
    """max |quantity_h - quantity| over the Gauss points and components, n x n elements."""
    s = get(case.surface)
    model = make_model(dm.Scene(dm.Sheet(size=SIZE, nodes=(n + 1, n + 1), rest=s), dm.Material(eta=1.0)), "fe")
    a = gauss_points(model, case.gauss)
    smp = model.sample(model.initial_state(), a)
    exact = np.moveaxis(getattr(s, case.quantity)(a[:, 0], a[:, 1]), -1, 0)
    return float(np.max(np.abs(getattr(smp, case.quantity) - exact)))


def check(case: Case, levels) -> list[float]:
    e = [error(case, n) for n in levels]
    p = fit_order([1.0 / n for n in levels], e)
    table = ", ".join(f"{n}: {v:.3e}" for n, v in zip(levels, e))
    lo, hi = case.window
    assert lo <= p <= hi, f"{case}: observed order p = {p:.3f} outside [{lo}, {hi}]; errors {table}"
    return e


@pytest.mark.parametrize("case", CASES, ids=str)
def test_observed_order(case):
    e = check(case, LEVELS)
    assert e[-1] < case.bound, f"{case}: error {e[-1]:.3e} at 64 x 64 above {case.bound:.1e}"


@pytest.mark.slow
@pytest.mark.parametrize("case", CASES, ids=str)
def test_clean_to_256(case):
    """Six levels to 256 x 256 elements: the order holds, and the last halving still gains its factor.

    Round-off growth (as in a global monomial basis) would flatten the last
    step; order 3 predicts a factor 8 per halving, order 2 a factor 4.
    """
    e = check(case, FINE)
    factor = 6.0 if case.window[0] > 2.5 else 3.0
    assert e[-1] < e[-2] / factor, (
        f"{case}: error at 256 x 256 {e[-1]:.3e} not below the 128 x 128 one {e[-2]:.3e} / {factor}"
    )
