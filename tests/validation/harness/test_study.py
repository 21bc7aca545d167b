"""The study framework (validation.harness.study): checks, order checks, level sets and Study.run."""

import numpy as np
import pytest

from validation.harness.runner import Runner
from validation.harness.study import Levels, Study, StudyResult, Table, nodes_at, order_check


def test_check_all_holds_only_when_every_item_holds():
    res = StudyResult("s", "d")
    assert res.check_all("all good", "every case", {"a": True, "b": True})
    assert not res.check_all("one bad", "every case", {"a": True, "b": False, "c": False})
    assert res.checks[1].observed == "1 of 3 hold; not: b, c"
    assert (res.passed, res.failed) == (1, 1)


def test_check_all_over_an_empty_set_fails():
    """Nothing was shown: an empty set of cases is not a pass."""
    res = StudyResult("s", "d")
    assert res.check_all("vacuous", "every case", {}) is False
    assert res.checks[0].observed == "no case to check" and res.failed == 1


@pytest.mark.parametrize("p, finest, passed", [(2.0, None, True), (2.29, None, True), (2.31, None, False),
                                               (1.69, None, False), (np.nan, None, False), (2.0, 0.5, False),
                                               (2.0, 0.05, True)])
def test_order_check_window_and_finest_error(p, finest, passed):
    res = StudyResult("s", "d")
    bound = 0.1 if finest is not None else None
    assert order_check(res, "order", p, 2.0, finest=finest, bound=bound) is passed
    assert "order 2 (window [1.70, 2.30])" in res.checks[0].expectation


def test_levels_resolve_and_refinement_halves_h():
    levels = Levels(quick=4, full=6, minimum=3, maximum=7)
    assert levels.resolve("x") == 4 and levels.resolve("x", "full") == 6 and levels.resolve("x", count=5) == 5
    with pytest.raises(ValueError, match="study 'x' runs 3 to 7 levels, got 9"):
        levels.resolve("x", count=9)
    with pytest.raises(ValueError, match="unknown level set 'slow'"):
        levels.resolve("x", "slow")
    assert [nodes_at(k, 9) for k in range(3)] == [9, 17, 33]


def test_table_rows_must_fit_the_columns():
    with pytest.raises(ValueError, match="has 2 cells, expected 3"):
        Table("t", "t", ("a", "b", "c"), [(1, 2)])


def test_study_run_resolves_its_levels_and_passes_surfaces_only_to_studies_that_take_them():
    seen = []

    def fill(res, levels, runner, **kw):
        seen.append((levels, type(runner), kw))
        res.check("ran", "yes", "yes", True)

    plain = Study("plain", "d", Levels(quick=3, full=5), fill)
    res = plain.run(surfaces=["monge"])
    assert res.config == {"levels": 3} and res.passed == 1
    Study("surf", "d", Levels(quick=3, full=5), fill, surfaces=True).run(4, surfaces=["monge"], mode="full")
    assert seen == [(3, Runner, {}), (4, Runner, {"surfaces": ["monge"]})]
    with pytest.raises(ValueError, match="runs 3 to 8 levels"):
        plain.run(2)
