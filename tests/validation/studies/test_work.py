"""Study ``work``: at its smallest level count its checks pass; the FE error falls with work."""

import numpy as np

from validation.studies.work import STUDY

from ...conftest import checks_pass


def test_work_errors_fall():
    res = checks_pass(STUDY.run(STUDY.levels.minimum))
    for b in ("fd", "fe"):
        assert np.all(np.diff(res.data[b]["error"]) < 0) and np.all(np.array(res.data[b]["cpu"]) > 0)
