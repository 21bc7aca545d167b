"""Study ``work``: at its smallest level count its checks pass; the errors fall with work; the timings are the run's."""

import numpy as np

from validation.studies.work import STUDY

from ...conftest import checks_pass


def test_work_errors_fall_and_the_timings_stay_out_of_the_committed_report():
    res = checks_pass(STUDY.run(STUDY.levels.minimum))
    for b in ("fd", "fe"):
        assert np.all(np.diff(res.data[b]["error"]) < 0) and "cpu" not in res.data[b]
    work = {t.name: t for t in res.tables}["work"]
    assert work.volatile and all(row[3] > 0 for row in work.rows)  # CPU time (s), run.md only
    assert all(f.volatile for f in res.figures) and len(res.run_findings) == 3 and not res.findings
