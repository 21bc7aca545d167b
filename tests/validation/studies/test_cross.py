"""Study ``cross``: FD against FE on the hanging and flag scenes.

The whole study runs under ``slow`` (about 20 s at its smallest level count); the default run checks its
parts: the Richardson/GCI arithmetic on an exact power law, and that the FD-FE difference of the two
coarsest grids shrinks, at the study's own dt.
"""

import numpy as np
import pytest

from validation.studies import cross
from validation.studies.cross import STUDY

from ...conftest import checks_pass


def test_richardson_and_gci_are_exact_on_a_power_law():
    """f(h) = f* + C h^p on three grids with ratio 2: p and f* are recovered, the asymptotic ratio is 1."""
    f_star, C, p = 0.7, 0.3, 1.5
    f1, f2, f3 = (f_star + C * h**p for h in (0.125, 0.25, 0.5))
    g = cross.gci(f1, f2, f3, p_theory=p)
    assert g["p"] == pytest.approx(p, rel=1e-12) and g["extrapolated"] == pytest.approx(f_star, rel=1e-12)
    assert not g["oscillatory"]
    # GCI_23 / (r^p GCI_12) = |eps32 / eps21| r^-p f1 / f2: f1 / f2 in the asymptotic range (the GCI is relative)
    assert g["asymptotic"] == pytest.approx(f1 / f2, rel=1e-12)
    assert g["asymptotic_theory"] == pytest.approx(f1 / f2, rel=1e-12)
    assert g["gci_12"] == pytest.approx(cross.FS * abs((f2 - f1) / f1) / (2**p - 1), rel=1e-12)
    assert cross.gci(f1, f1, f3)["p"] != cross.gci(f1, f1, f3)["p"]  # no change between two grids: p is NaN


@pytest.mark.parametrize("scene", ["hanging", "flag"])
def test_fd_and_fe_positions_approach_each_other(scene):
    dt = cross.step(scene, 9)
    runs = {(b, n): cross.run_case(cross.Case(b, scene, n, dt)) for b in ("fd", "fe") for n in (5, 9)}
    assert all(r["status"] == "finished" for r in runs.values())
    d = [np.max(np.abs(runs[("fd", n)]["r"] - runs[("fe", n)]["r"])) for n in (5, 9)]
    assert d[1] < d[0], f"{scene}: FD-FE position differences {d}"
    assert runs[("fd", 5)]["r"].shape == (len(cross.SAMPLES), cross.COMMON**2, 3)


@pytest.mark.slow
def test_cross_difference_shrinks():
    """FD and FE approach each other at every refinement (issue 4: hanging over three levels). No order
    is asserted: the hanging cloth's two pinned corners are point supports of a membrane, singular in the
    continuum, which holds both backends below their smooth-solution orders (reported in the study)."""
    res = checks_pass(STUDY.run(STUDY.levels.minimum))
    for scene in ("hanging", "flag"):
        d = res.data[f"{scene}|r|fd-fe"]
        assert len(d) >= 3 and all(b < a for a, b in zip(d, d[1:])), f"{scene}: FD-FE position differences {d}"
