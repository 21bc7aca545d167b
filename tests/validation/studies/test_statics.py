"""Study ``statics``: at its smallest level count its checks pass; FD second order, FE fourth."""

import pytest

from validation.studies.statics import STUDY, navier_centre

from ...conftest import checks_pass


def test_statics_orders():
    res = checks_pass(STUDY.run(STUDY.levels.minimum))
    assert abs(res.data["fd"]["order"] - 2) <= 0.3 and abs(res.data["fe"]["order"] - 4) <= 0.3, res.data


def test_navier_series_has_converged_at_its_default_length():
    """Half the default length already gives the sum to round-off: the tail is below 1e-13 relative."""
    assert abs(navier_centre(terms=2000) / navier_centre() - 1) < 1e-13


@pytest.mark.slow
def test_full_levels():
    checks_pass(STUDY.run(STUDY.levels.full))
