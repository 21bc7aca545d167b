"""Study ``time``: at its smallest level count its checks pass; the stepper is first order in time."""

from validation.studies.temporal import STUDY

from ...conftest import checks_pass


def test_time_order_is_one():
    assert STUDY.name == "time"
    res = checks_pass(STUDY.run(STUDY.levels.minimum))
    for b in ("fd", "fe"):
        assert abs(res.data[b]["order"] - 1) <= 0.3, f"{b}: temporal order {res.data[b]['order']:.2f}"
