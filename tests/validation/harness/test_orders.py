"""Observed orders (validation.harness.orders): the one order fit every convergence test uses."""

import numpy as np
import pytest

from validation.harness.orders import fit_order, pairwise_orders


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
