"""The matched-accuracy rows of ``deformable bench``: the level matching, the verdicts computed from the numbers, and
a tiny run of ours whose error falls as its tolerance tightens."""

import csv
import math

import pytest

from validation.benches import accuracy, peers
from validation.benches.accuracy import AccuracyRow, Setting, front, match_level, matched_levels, verdicts

#: (CPU s per sim s, error, setting): a work-precision curve with one dominated point (50, 1e-2)
POINTS = [(1.0, 1e-1, "a"), (10.0, 1e-3, "b"), (100.0, 1e-5, "c"), (50.0, 1e-2, "dominated")]


def test_the_front_keeps_the_points_nothing_beats_by_cost():
    assert [p[2] for p in front(POINTS + [(math.nan, 1e-9, "failed"), (2.0, math.nan, "no error")])] == ["a", "b", "c"]


def test_a_level_is_interpolated_in_log_log_between_its_bracketing_points():
    cost, best, cheapest, cheapest_cost, how = match_level(POINTS, 1e-2)
    assert cost == pytest.approx(10**0.5) and best == 1e-5  # half way in log error between (1, 1e-1) and (10, 1e-3)
    assert (cheapest, cheapest_cost) == ("b", 10.0) and how == "interpolated between a and b"
    assert match_level(POINTS, 1e-4)[0] == pytest.approx(10**1.5)
    assert match_level(POINTS, 1e-5)[0] == pytest.approx(100.0)


def test_a_level_the_cheapest_point_meets_costs_that_point_and_one_never_reached_gives_the_best_error():
    assert match_level(POINTS, 0.5)[::4] == (1.0, "cheapest point")  # no extrapolation below the cheapest point
    cost, best, cheapest, _, how = match_level(POINTS, 1e-6)
    assert math.isnan(cost) and best == 1e-5 and cheapest == "" and how == "never: best 1e-05"
    assert match_level([], 1e-3)[-1] == "no points"


def _rows(solver, dt, points, check=1e-9):
    """Synthetic rows of a solver: its reference, a check of error ``check`` at a high cost, and the points."""
    def row(setting, role, cost, error, status="ok"):
        return AccuracyRow(solver, setting, role, "64x64", dt, 0.1, 6, 1.0, 0.1 * cost, cost, error, status)

    return ([row("ref", "reference", 1e4, 0.0), row("check", "check", 1e3, check)]
            + [row(name, "sweep", cost, error) for cost, error, name in points])


def test_the_verdicts_are_computed_from_the_numbers():
    dt = 1 / 600
    rows = (_rows("ours", dt, [(5.0, 1e-3, "o1"), (50.0, 1e-6, "o2")]) + _rows("vbd", dt, [(20.0, 1e-3, "v")])
            + _rows("style3d", dt, [(2.0, 1e-2, "s1"), (4.0, 1e-4, "s2")]))
    vbd, style3d = verdicts(rows)
    assert vbd.startswith("dt = 1/600 s: ours at 0.001: 5 CPU s per sim s; newton VBD: 20 (met: ours <= VBD")
    assert "VBD / ours = 4x" in vbd and "the cheapest setting of ours (o1) is already at 0.001" in vbd
    assert "newton Style3D: 2.83 (NOT met: ours <= Style3D" in style3d  # 2 * (4 / 2)^(1/2), interpolated
    levels = {(m.solver, m.level): m for m in matched_levels(rows)}
    assert levels["vbd", 1e-4].how == "interpolated between v and check"  # a reference's check is a point too
    assert levels["ours", 1e-2].cpu_per_sim_s == 5.0 and levels["style3d", 1e-3].cheapest == "s2"


def test_a_peer_short_of_the_level_is_compared_at_its_best_and_a_loose_reference_is_flagged():
    dt = 1 / 60
    rows = _rows("ours", dt, [(1.0, 1e-2, "o1"), (10.0, 1e-4, "o2")]) + _rows("vbd", dt, [(3.0, 1e-2, "v")],
                                                                                  check=5e-3)
    (line,) = verdicts(rows)
    assert line.startswith("dt = 1/60 s: ours at 0.005: ") and "(met: ours <= VBD" in line
    assert "VBD never reaches 0.001 (best 0.005): compared at VBD's best level" in line
    assert "caution: VBD's reference differs from its check (check) by 0.005" in line


def test_a_missing_peer_says_so():
    rows = _rows("ours", 1 / 60, [(1.0, 1e-4, "o")]) + [
        AccuracyRow("vbd", "300 iterations", "reference", "64x64", 1 / 60, math.nan, 0, math.nan, math.nan, math.nan,
                    math.nan, peers.MISSING)]
    assert verdicts(rows) == [f"dt = 1/60 s: newton VBD not measured: {peers.MISSING}"]
    (m,) = [m for m in matched_levels(rows) if m.solver == "vbd" and m.level == 1e-3]
    assert not m.met and m.how == peers.MISSING


def test_the_peers_substep_divides_their_frame():
    assert accuracy.substeps_of(1 / 60) == 1 and accuracy.substeps_of(1 / 600) == 10
    with pytest.raises(ValueError, match="does not divide"):
        accuracy.substeps_of(0.007)


def test_the_default_sweeps_have_one_reference_and_its_check_at_each_dt():
    for settings in accuracy.SWEEPS.values():
        for dt in accuracy.DTS:
            roles = [s.role for s in accuracy._at(settings, dt)]
            assert roles[:2] == ["reference", "check"] and roles.count("check") == 1 and len(roles) > 6
    with pytest.raises(ValueError, match="needs one reference"):
        accuracy._at(accuracy.SWEEPS["vbd"], 1 / 120)  # the peers' references are given per dt


def test_ours_error_falls_as_the_force_tolerance_tightens():
    ref = accuracy.run_ours(8, 1 / 600, 0.02, dict(test="force", rtol=1e-10, max_iter=500))
    assert ref.status == "ok" and ref.steps == 12 and ref.t_end == pytest.approx(0.02) and ref.cpu > 0
    errors = [accuracy._rms(accuracy.run_ours(8, 1 / 600, 0.02, dict(test="force", rtol=rtol)).X, ref.X, 1.0)
              for rtol in (1e-2, 1e-3, 1e-4)]
    assert errors[0] > errors[1] > errors[2] > 0


def test_the_bench_writes_its_tables_plot_and_verdicts_and_ours_runs_without_the_peers(tmp_path, monkeypatch):
    """Without newton (made missing here) every peer row says so and ours still runs, each in its own process."""
    monkeypatch.setattr(peers, "_missing", lambda: True)
    sweeps = {"ours": (Setting("tight", "reference", dict(test="force", rtol=1e-10, max_iter=500)),
                       Setting("check", "check", dict(test="force", rtol=1e-4)),
                       Setting("loose", "sweep", dict(test="force", rtol=1e-2))),
              "vbd": tuple(Setting(f"{k} iterations", role, {"iterations": k})
                           for k, role in ((300, "reference"), (200, "check"), (10, "sweep")))}
    lines = accuracy.bench_accuracy(tmp_path, t_end=0.02, dts=(1 / 600,), progress=None, nodes=8,
                                    solvers=("ours", "vbd"), sweeps=sweeps)
    assert lines == [f"dt = 1/600 s: newton VBD not measured: {peers.MISSING}"]
    with (tmp_path / "bench_accuracy.csv").open() as fh:
        rows = list(csv.DictReader(fh))
    assert [(r["solver"], r["role"]) for r in rows] == [("ours", "reference"), ("ours", "check"), ("ours", "sweep"),
                                                        ("vbd", "reference"), ("vbd", "check"), ("vbd", "sweep")]
    ours = rows[:3]
    assert all(r["status"] == "ok" and float(r["cpu_per_sim_s"]) > 0 for r in ours)
    assert float(ours[0]["error"]) == 0 and float(ours[2]["error"]) > float(ours[1]["error"]) > 0
    assert all(r["status"] == peers.MISSING for r in rows[3:])
    with (tmp_path / "bench_accuracy_levels.csv").open() as fh:
        assert len(list(csv.DictReader(fh))) == 6  # two solvers at three levels
    md = (tmp_path / "bench_accuracy.md").read_text()
    assert lines[0] in md and "## Matched levels" in md
    assert (tmp_path / "bench_accuracy.png").stat().st_size > 10_000


@pytest.mark.slow
def test_a_peer_runs_through_the_shared_runner():
    """A tiny VBD and Style3D run at one substep a frame (VBD's graph then replays two frames) and the fixed-budget
    row, which runs the same code (compiles Warp's kernels on a cold cache: slow)."""
    pytest.importorskip("newton")
    for solver, knobs in (("vbd", dict(iterations=5)), ("style3d", dict(iterations=2, linear_iterations=5))):
        run = accuracy.run_newton_peer(solver, 8, 1 / 60, 0.05, knobs)
        assert run.status == "ok" and run.steps == 3 and run.X.shape == (64, 3) and run.cpu > 0
    row = peers.bench_peer("vbd", 8, 0.1)
    assert row.status == "ok" and row.steps == 60
