"""Study ``modes``: at its smallest level count its checks pass and the orders match theory."""

import pytest

from validation.harness.orders import fit_order
from validation.studies.modes import STUDY

from ...conftest import checks_pass


def test_modes_orders():
    res = checks_pass(STUDY.run(STUDY.levels.minimum))
    for key, theory in (("fd|both", 2), ("fe|both", 4), ("fe|tpbf87 bending", 4)):
        d = res.data[key]
        p = fit_order(d["h"], d["error"])
        assert abs(p - theory) <= 0.3, f"{key}: observed order {p:.2f}, theory {theory}"
    assert res.data["fd|tpbf87 xi only"]["max_K"] == 0.0


@pytest.mark.slow
def test_full_levels():
    checks_pass(STUDY.run(STUDY.levels.full))
