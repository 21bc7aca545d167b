"""Observed orders (validation.harness.orders): the one order fit every convergence test uses."""

import numpy as np
import pytest

from validation.harness.orders import FS, fit_order, gci, pairwise_orders


def test_a_power_law_has_its_exponent_as_order():
    h = np.array([0.1, 0.05, 0.025, 0.0125])
    assert fit_order(h, 3.0 * h**2.5) == pytest.approx(2.5, abs=1e-12)
    np.testing.assert_allclose(pairwise_orders(h, 3.0 * h**2.5), 2.5, atol=1e-12)
    # a least-squares slope: the mean of a zig-zag of pairwise orders
    e = np.array([1.0, 0.25, 0.125, 0.03125])
    np.testing.assert_allclose(pairwise_orders(h, e), [2, 1, 2])
    assert 1.0 < fit_order(h, e) < 2.0


@pytest.mark.parametrize("h, e, message", [([0.1], [1.0], "at least two levels"),
                                           ([0.1, 0.05], [1.0], "matching arrays"),
                                           ([0.1, 0.05], [1.0, 0.0], "positive spacings and errors")])
def test_fit_order_refuses_what_has_no_order(h, e, message):
    with pytest.raises(ValueError, match=message):
        fit_order(h, e)


def test_richardson_and_gci_are_exact_on_a_power_law():
    """f(h) = f* + C h^p on three grids with ratio 2: p and f* are recovered, the asymptotic ratio is 1."""
    f_star, C, p = 0.7, 0.3, 1.5
    f1, f2, f3 = (f_star + C * h**p for h in (0.125, 0.25, 0.5))
    g = gci(f1, f2, f3, p_theory=p)
    assert g["p"] == pytest.approx(p, rel=1e-12) and g["extrapolated"] == pytest.approx(f_star, rel=1e-12)
    assert not g["oscillatory"]
    # GCI_23 / (r^p GCI_12) = |eps32 / eps21| r^-p f1 / f2: f1 / f2 in the asymptotic range (the GCI is relative)
    assert g["asymptotic"] == pytest.approx(f1 / f2, rel=1e-12)
    assert g["asymptotic_theory"] == pytest.approx(f1 / f2, rel=1e-12)
    assert g["gci_12"] == pytest.approx(FS * abs((f2 - f1) / f1) / (2**p - 1), rel=1e-12)
    assert gci(f1, f1, f3)["p"] != gci(f1, f1, f3)["p"]  # no change between two grids: p is NaN
