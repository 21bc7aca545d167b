"""Study ``shells``: at its smallest level count every check passes (the problems' own tests are beside their code:
tests/fdmodel/test_varying_weights.py, tests/deformable/physics/test_moments.py, tests/fdmodel/test_clamp.py,
tests/deformable/solve/test_continuation.py, tests/femodel/test_symmetry.py)."""

import pytest

from validation.studies.shells import STUDY

from ...conftest import checks_pass


@pytest.mark.slow  # each part is tested beside its code; this reruns them together (about 10 s)
def test_shells_checks_pass_at_the_quick_levels():
    res = checks_pass(STUDY.run(STUDY.levels.minimum))
    assert res.data["frozen"]["nodes"][-1] == 65 and res.data["roll_fe"]["gap"][-1] <= 1e-3
