"""Study ``cross``: FD against FE on well-posed problems, work-precision, and the paper's force as a finding.

The whole study at its coarsest levels runs under ``slow`` (a few minutes); the default run checks its
parts: the references, the probe, the FD-FE convergence on one problem at two levels, the plate elements
of the work-precision, and that the paper's force is a finding without checks.
"""

import numpy as np
import pytest

import deformable as dm
from validation.harness.backends import make_model
from validation.studies.cross import STUDY, paper_force, problems
from validation.studies.cross.cases import Case, probe, run_case
from validation.studies.cross.convergence import differences
from validation.studies.cross.measure import Probe, difference
from validation.studies.cross.work import WorkCase, cpu_to_reach, error_at, run_work

from ...conftest import checks_pass


def test_the_extensible_elastica_is_the_continuum_limit_of_the_cantilever():
    """FE on 41 x 3 nodes (its error ~1e-8 m here) meets the collocation reference to 1e-6 m."""
    x, z = problems.elastica_tip(2.0)
    model = make_model(problems.cantilever((41, 3), 2.0), "fe")
    X, _ = dm.equilibrium(model, model.initial_state(), tol=1e-12, newton=problems.NEWTON)
    tip = model.grid(X)[-1, 1]
    assert abs(tip[0] - x) < 1e-6 and abs(tip[2] - z) < 1e-6
    assert (10 - x) / 10 == pytest.approx(0.1606, abs=1e-3)  # Sze, Liu and Lo's -u/L at P L^2 / EI = 2


def test_probe_points_stay_at_thirds_of_every_finer_cell():
    pr = Probe.on_cells((2.0, 1.0), (4, 2))
    assert pr.weights.sum() == pytest.approx(2.0, rel=1e-14) and pr.points.shape == (8 * 4, 2)
    for k in range(5):  # relative position inside the cells of the grid refined k times
        frac = np.mod(pr.points[:, 0] / (0.5 / 2**k), 1.0)
        assert np.all(np.isclose(frac, 1 / 3) | np.isclose(frac, 2 / 3))
    inner = Probe.on_cells((1.0, 1.0), (4, 4)).interior  # points at least 1/8 from the edges: 6 of 8 a side
    assert inner.sum() == 6 * 6
    assert difference(np.ones((64, 3)), np.zeros((64, 3)), Probe.on_cells((2.0, 1.0), (4, 4))) == pytest.approx(
        (np.sqrt(3 * 2.0), np.sqrt(3)))


def test_fd_and_fe_approach_each_other_on_the_hanging_sheet():
    """Two levels (9, 17 nodes): the FD-FE differences of r, G and B fall at about FD's order 2."""
    runs = {(b, k): run_case(Case("hanging", b, k)) for b in ("fd", "fe") for k in (0, 1)}
    d = differences(runs, 2, probe("hanging"))
    for q in ("r", "G", "B"):
        for norm in ("L2", "interior max"):
            v = d.cross[(q, norm)]
            assert 1.6 <= np.log2(v[0] / v[1]) <= 2.6, f"{q} {norm}: FD-FE differences {v}"


def test_the_plate_elements_of_the_work_precision_converge():
    """scikit-fem's Morley (O(h^2)) and Argyris (O(h^6), limited by the corners) on the clamped square."""
    morley = [run_work(WorkCase("plate", "morley", n))["error"] for n in (9, 17)]
    argyris = [run_work(WorkCase("plate", "argyris", n))["error"] for n in (5, 9)]
    assert 1.7 <= np.log2(morley[0] / morley[1]) <= 2.3, morley
    assert argyris[1] < 1e-5 and np.log2(argyris[0] / argyris[1]) > 5, argyris


def test_cpu_to_reach_and_error_at_interpolate_in_log_log():
    cpu, err = np.array([0.1, 1.0, 10.0]), np.array([1e-2, 1e-4, 1e-6])
    assert cpu_to_reach(cpu, err, 1e-5) == pytest.approx(np.sqrt(10.0), rel=1e-12)
    assert np.isnan(cpu_to_reach(cpu, err, 1e-7)) and cpu_to_reach(cpu, err, 1.0) == 0.1
    assert error_at(cpu, err, 3.0) == pytest.approx(1e-4 * 3.0**-2, rel=1e-12) and np.isnan(error_at(cpu, err, 20.0))


def test_the_paper_force_is_reported_as_a_finding_never_a_check():
    """Differences that grow under refinement (as G and B do under the paper's force) make a finding and a
    table, never a check (synthetic runs: the report's logic only)."""
    from validation.harness.study import StudyResult

    pr = paper_force.probe("cloth")
    P = pr.points.shape[0]

    def run(backend, level):  # FD and FE drift apart in G and B, come together in r
        s = {"r": np.full((P, 3), (backend == "fd") * 0.1 / 2**level),
             "G": np.full((P, 4), (backend == "fd") * 0.1 * 2**level),
             "B": np.full((P, 4), (backend == "fd") * 1.0 * 2**level)}
        return {"h": 0.25 / 2**level, "samples": [s] * 4, "status": "finished"}

    raw = {paper_force.ForceCase("cloth", b, k, 1e-3): run(b, k) for b in ("fd", "fe") for k in range(3)}
    res = StudyResult("x", "y")
    paper_force.report(res, 3, raw)
    assert not res.checks and res.tables[0].name == "paper_force"
    finding = next(f for f in res.findings if "need not converge under the paper's force with xi = 0" in f)
    assert "G: 0.2, 0.4, 0.8 (order -1.00)" in finding  # |G| over its four components: 2 x 0.1
    assert "G (L2), G (interior max), B (L2), B (interior max) do not shrink at every refinement" in finding
    assert "r (L2), r (interior max) shrink" in finding


@pytest.mark.slow
def test_the_study_at_its_coarsest_levels():
    """Every check of the study holds at its smallest level count (the quick report's levels)."""
    res = checks_pass(STUDY.run(STUDY.levels.minimum))
    assert len(res.checks) >= 40
