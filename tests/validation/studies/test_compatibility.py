"""Study ``compatibility``: at its smallest level count its checks pass, residual orders and the flags."""

import pytest

from validation.harness.orders import fit_order
from validation.studies.compatibility import STUDY

from ...conftest import checks_pass


def test_compatibility_orders_and_flags():
    res = checks_pass(STUDY.run(STUDY.levels.minimum, surfaces=["monge", "sphere"]))
    assert res.data["incompatible_rest_state"]["gauss"] == pytest.approx(0.25, abs=1e-12)
    for src, theory in (("exact", 2), ("fe", 2), ("fd", 1)):
        rows = res.data[f"{src}|monge"]
        p = fit_order([r["h"] for r in rows], [r["codazzi"] for r in rows])
        assert abs(p - theory) <= 0.3, f"{src}: Codazzi residual order {p:.2f}, theory {theory}"


@pytest.mark.slow
def test_full_levels_on_every_surface():
    checks_pass(STUDY.run(STUDY.levels.full))
