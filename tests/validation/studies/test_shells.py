"""Study ``shells``: at its smallest level count every check passes (the problems' own tests are beside their code:
tests/fdmodel/test_varying_weights.py, tests/deformable/physics/test_moments.py, tests/fdmodel/test_clamp.py,
tests/deformable/solve/test_continuation.py, tests/femodel/test_symmetry.py)."""

import pytest

from validation.studies.shells import STUDY


@pytest.mark.slow  # each part is tested beside its code; this reruns them together (about 10 s)
def test_shells_checks_pass_at_the_quick_levels_but_the_published_roof():
    """Every check passes but one, which fails as measured: the hinged roof is 3.2 % from Sze, Liu and Lo's path
    at its worst tabulated level (issue 28 keeps it open); the test holds the study to reporting it."""
    res = STUDY.run(STUDY.levels.minimum)
    failed = [c for c in res.checks if not c.passed]
    assert [c.name for c in failed] == ["hinged roof within 2 % of the published path at every tabulated level (FE 9 "
                                        "nodes)"], [(c.name, c.observed) for c in failed]
    assert len(res.data["roof"]["error_relative"]) == 36  # every tabulated level reached and compared
    assert res.data["frozen"]["nodes"][-1] == 65 and res.data["roll_fe"]["gap"][-1] <= 1e-3
