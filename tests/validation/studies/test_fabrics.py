"""Study ``fabrics``: the Peirce cantilever test (ASTM D1388) measures each preset's bending length on FD and FE.

First the rule itself, against the exact inextensible heavy elastica solved here by shooting (independent of
the study's collocation): at l = 2c its chord falls 41.487 degrees, so ASTM's c = l / 2 at 41.5 degrees is
exact to 2e-4, while Peirce's closed form inverted at 41.5 degrees is 1.9 % high. Then the test on coarse grids:
within 5 % of the source's c, and a doubled D is caught."""

import dataclasses
import math

import numpy as np
import pytest
from scipy.integrate import solve_ivp
from scipy.optimize import brentq

from deformable.physics.fabric import Fabric
from validation.studies import STUDIES
from validation.studies import fabrics as st

from ...conftest import checks_pass


def shooting_chord_angle(ratio: float) -> float:
    """The heavy elastica's chord angle (deg) at l / c = ``ratio``: theta'' = -(L - s) cos(theta), theta(0) = 0,
    theta'(L) = 0 by shooting on theta'(0) (between 0 and the linear beam's L^2 / 2)."""
    L = ratio

    def rhs(s, y):
        return [y[1], -(L - s) * math.cos(y[0]), math.cos(y[0]), math.sin(y[0])]

    def end(k0):
        return solve_ivp(rhs, (0.0, L), [0.0, k0, 0.0, 0.0], rtol=1e-12, atol=1e-14).y[:, -1]

    k0 = brentq(lambda k: end(k)[1], 1e-9, L**2 / 2, xtol=1e-14)
    _, _, x, z = end(k0)
    return math.degrees(math.atan2(z, x))


def test_astm_rule_against_the_exact_elastica():
    at_two = shooting_chord_angle(2.0)
    assert at_two == pytest.approx(41.4873, abs=1e-3)
    assert st.elastica_chord_angle(2.0) == pytest.approx(at_two, abs=1e-6)  # the study's collocation agrees
    assert st.elastica_chord_angle(1.5) == pytest.approx(shooting_chord_angle(1.5), abs=1e-6)
    root = brentq(lambda L: shooting_chord_angle(L) - st.PEIRCE_ANGLE, 1.9, 2.1, xtol=1e-9)
    assert abs(root / 2 - 1) < 3e-4  # c = l / 2 at 41.5 degrees: the exact elastica's c to 0.03 %
    assert 2 * st.peirce_formula(st.PEIRCE_ANGLE) - 1 == pytest.approx(0.0186, abs=5e-4)  # the formula: 1.9 % high


@pytest.mark.parametrize("backend, nodes", [("fd", 11), ("fe", 5)])
@pytest.mark.parametrize("name, direction", [("denim", "warp"), ("tshirt-knit", "weft")])
def test_peirce_reproduces_the_sources_bending_length(name, direction, backend, nodes):
    fabric = Fabric.preset(name)
    r = st.peirce(fabric, direction, backend, nodes)
    c = fabric.bending_length[0 if direction == "warp" else 1]
    assert r["angle"] == pytest.approx(st.PEIRCE_ANGLE, abs=1e-3)
    assert abs(r["c"] / c - 1) <= st.TOLERANCE, (r, c)
    assert abs(r["c"] / c - 1) <= 0.015  # measured: 1.2 % (FD 11 nodes, its clamp O(h^2)), 0.5 % (FE 5)


def test_warp_and_weft_bend_about_different_weights():
    """Denim's weft is 13 % shorter than its warp (c 2.72 against 3.12 cm): each direction sees its own D."""
    fabric = Fabric.preset("denim")
    warp, weft = (st.peirce(fabric, d, "fe", 5)["c"] for d in ("warp", "weft"))
    assert warp / weft == pytest.approx(fabric.bending_length[0] / fabric.bending_length[1], rel=0.01)


def test_a_wrong_bending_rigidity_fails_the_test():
    """Twice the preset's D: the measured c is 2^(1/3) = 1.26 times the source's, far outside 5 %."""
    fabric = Fabric.preset("denim")
    doubled = dataclasses.replace(fabric, bending=tuple(2 * d for d in fabric.bending))
    r = st.peirce(doubled, "warp", "fe", 5)
    assert r["c"] / fabric.bending_length[0] == pytest.approx(2 ** (1 / 3), rel=0.01)


def test_the_study_is_registered_and_its_checks_fail_on_no_case(monkeypatch):
    assert STUDIES["fabrics"] is st.STUDY and st.STUDY.in_default
    assert st.directions("paper") == ("warp",) and st.directions("denim") == ("warp", "weft")
    monkeypatch.setattr(Fabric, "presets", classmethod(lambda cls: ()))
    monkeypatch.setattr(st, "_elastica", lambda res: None)
    res = st.STUDY.run(1)
    assert res.failed == 2 and res.passed == 0 and all(c.observed == "no case to check" for c in res.checks)


def test_the_strip_hangs_from_the_clamped_edge():
    fabric = Fabric.preset("denim")
    for direction, shape in (("warp", (11, 3)), ("weft", (3, 11))):
        scene = st.strip(fabric, 0.06, direction, 11)
        assert scene.sheet.nodes == shape and np.isclose(max(scene.sheet.size), 0.06)


@pytest.mark.slow
def test_quick_level():
    res = checks_pass(st.STUDY.run(1))
    assert len(res.tables[0].rows) == 2 * (2 * len(Fabric.presets()) - 1)
