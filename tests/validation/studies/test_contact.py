"""Study ``contact``: its experiments on small grids, each against what holds for it.

- every contact scene keeps a positive clearance at every step, on both backends (the 5 m/s drop, with
  every trial point of the line search, is in tests/deformable/contact/test_potential.py);
- a sheet on an inclined plane sticks 1 degree below the friction angle and slides 1 degree above it with
  g (sin a - mu cos a) (within 2%), on the analytic plane and on a triangle mesh of it;
- a frictionless undamped drop: implicit Euler's total energy never rises.
The drape's refinement runs with the study itself (``deformable validate contact``: minutes).
"""

import math

import pytest

from validation.studies import contact as ct
from validation.studies import get_study

SMALL = {"fd": 6, "fe": 4}


@pytest.mark.parametrize("backend", ["fd", "fe"])
@pytest.mark.parametrize("scene", [s for s, _, _ in ct.CLEARANCE_SCENES])
def test_every_contact_scene_stays_outside_at_every_step(scene, backend):
    r = ct.run_scene(ct.SceneCase(backend, scene, SMALL[backend], 0.15))
    assert r["steps"] >= 30 and r["clearance"] > 0, r


@pytest.mark.parametrize("floor,backend", [("plane", "fd"), ("plane", "fe"), ("mesh", "fd"),
                                           pytest.param("mesh", "fe", marks=pytest.mark.slow)])  # FE: 4 s, the study
@pytest.mark.parametrize("offset", [-1.0, 1.0])
def test_incline_sticks_below_and_slides_above_the_friction_angle(backend, offset, floor):
    """On the analytic plane and on a mesh of it (split away from the sheet: no edge under it). The mesh's barrier
    weights the sheet's vertices by the contact mesh's areas, not by the FD nodes' own, so the sheet settles for
    longer after its start at a tenth of the activation distance: on 3 x 3 nodes it still moved at 2 cm/s over
    the second tenth of a second; it is run as the study runs it (5 x 5 nodes, 0.4 s)."""
    angle = math.degrees(math.atan(ct.FRICTION)) + offset
    nodes, t_end = (3, 0.2) if floor == "plane" else (5, 0.4)
    r = ct.run_incline(ct.InclineCase(backend, nodes, angle, ct.FRICTION, t_end=t_end, floor=floor))
    assert r["clearance"] > 0
    if offset < 0:
        assert r["theory"] < 0 and r["speed"] < r["slip"], r  # stuck: no more than the smoothing's creep
    else:
        assert r["theory"] > 0 and abs(r["acceleration"] - r["theory"]) <= 0.02 * r["theory"], r


@pytest.mark.parametrize("backend", ["fd", "fe"])
def test_implicit_euler_never_gains_energy_on_impact(backend):
    r = ct.run_energy(ct.EnergyCase(backend, 3, "implicit-euler"))
    assert r["rise"] <= 1e-9 and r["fall"] > 0.5 and r["clearance"] > 0, r  # the landing dissipates


def test_the_study_is_registered_outside_the_default_run():
    study = get_study("contact")
    assert study is ct.STUDY and not study.in_default and study.levels.minimum >= 3  # two changes to compare
