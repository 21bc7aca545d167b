"""Nodal bicubic Hermite interpolation: observed orders of G (eq. 4) and B (eq. 8), clean to 256 x 256.

Theory (interpolation by bicubics, smooth surface, max norm): the error of the
k-th derivatives of r is O(h^(4-k)), so G = r_i . r_j is O(h^3) and
B = n . r_ij is O(h^2) anywhere in an element. At the 2 x 2 Gauss points the
second derivatives of the tensor-product Hermite interpolant superconverge
(the Gauss points of degree 2 are the zeros of the leading error term of the
1-D second derivative, s^2 - s + 1/6), so B is O(h^3) there. Windows:
order 3 -> [2.6, 3.6], order 2 -> [1.7, 2.6].

The rectangle is 1 x 1.3 (h1 != h2) so a swap of h1 and h2 cannot hide.
"""

from dataclasses import dataclass

import numpy as np
import pytest

import deformable as dm
from femodel import FEModel

from .conftest import gauss_points, observed_order
from .surfaces import MongePatch, SkewSheet

SIZE = (1.0, 1.3)
LEVELS = (8, 16, 32, 64)
FINE = (8, 16, 32, 64, 128, 256)


@dataclass(frozen=True)
class Case:
    surface: object
    quantity: str  # "G" or "B"
    gauss: int  # k x k Gauss points per element
    window: tuple[float, float]
    bound: float  # on the error at 64 x 64 elements

    def __str__(self):
        return f"{type(self.surface).__name__}-{self.quantity}-gauss{self.gauss}"


CASES = [
    Case(MongePatch(), "G", 4, (2.6, 3.6), 3e-6),
    Case(MongePatch(), "B", 4, (1.7, 2.6), 1e-3),
    Case(MongePatch(), "B", 2, (2.6, 3.6), 6e-6),
    Case(SkewSheet(), "G", 4, (2.6, 3.6), 1e-7),
    Case(SkewSheet(), "B", 4, (1.7, 2.6), 1e-4),
    Case(SkewSheet(), "B", 2, (2.6, 3.6), 4e-7),
]


def error(case: Case, n: int) -> float:
    """max |quantity_h - quantity| over the Gauss points and components, n x n elements."""
    sheet = dm.Sheet(size=SIZE, nodes=(n + 1, n + 1), rest=case.surface)
    model = FEModel(dm.Scene(sheet, dm.Material(eta=1.0)))
    a = gauss_points(model, case.gauss)
    s = model.sample(model.discretize(case.surface), a)
    exact = getattr(case.surface, case.quantity)(a[:, 0], a[:, 1])
    return float(np.max(np.abs(getattr(s, case.quantity) - exact)))


def check(case: Case, levels) -> list[float]:
    e = [error(case, n) for n in levels]
    h = [1.0 / n for n in levels]
    p = observed_order(h, e)
    table = ", ".join(f"{n}: {v:.3e}" for n, v in zip(levels, e))
    lo, hi = case.window
    assert lo <= p <= hi, f"{case}: observed order p = {p:.3f} outside [{lo}, {hi}]; errors {table}"
    return e


@pytest.mark.parametrize("case", CASES, ids=str)
def test_observed_order(case):
    e = check(case, LEVELS)
    assert e[-1] < case.bound, f"{case}: error {e[-1]:.3e} at 64 x 64 above {case.bound:.1e}"


def test_nonorthogonal_surface_is_nonorthogonal():
    a = np.array([[0.3, 0.4], [0.9, 1.2]])
    assert np.all(np.abs(SkewSheet().G(a[:, 0], a[:, 1])[:, 0, 1]) > 0.5)


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
