"""``deformable bench``: the table and CSV of step time against one direct factor+solve, on both backends."""

import csv

import numpy as np
import pytest

import deformable as dm
from validation.commands import main
from validation.benches import SEMI_IMPLICIT_DT, hanging_model


def test_bench_writes_both_tables_and_csvs_for_both_backends(tmp_path, capsys):
    assert main(["bench", "--backend", "all", "--sizes", "8,12", "--steps", "2", "--implicit-fd", "8",
                 "--implicit-fe", "4", "--contact-fd", "6", "--contact-fe", "3", "--contact-steps", "3",
                 "--out", str(tmp_path)]) == 0
    out = capsys.readouterr().out
    assert "step / (factor+solve)" in out and "| fd | 12x12 |" in out and "| fe | 12x12 |" in out
    with (tmp_path / "bench.csv").open() as fh:
        rows = list(csv.DictReader(fh))
    assert [(r["backend"], r["nodes"]) for r in rows] == [("fd", "8x8"), ("fd", "12x12"), ("fe", "8x8"),
                                                           ("fe", "12x12")]
    for r in rows:
        parts = float(r["assembly"]) + float(r["factorisation"]) + float(r["solve"])
        assert 0 < parts <= float(r["step"]) * 1.01
        ref = float(r["direct_factor"]) + float(r["direct_solve"])
        assert float(r["ratio"]) == pytest.approx(float(r["step"]) / ref, rel=1e-3)
        assert float(r["peak_mb"]) > 10  # the row's own process, interpreter included
    with (tmp_path / "bench_implicit.csv").open() as fh:
        implicit = list(csv.DictReader(fh))
    assert [(r["backend"], r["grid"]) for r in implicit] == [("fd", "8x8"), ("fe", "4x4")]
    for r in implicit:
        assert float(r["newton_per_step"]) >= 1 and float(r["factorisations_per_step"]) >= 1
        iteration = float(r["step"]) / float(r["newton_per_step"])
        assert float(r["iteration_ratio"]) == pytest.approx(iteration / (float(r["factor"]) + float(r["solve"])),
                                                           rel=1e-3)
        assert float(r["step_ratio"]) == pytest.approx(float(r["step"]) / float(r["semi_implicit_step"]), rel=1e-3)
    assert "Newton iterations / step" in out and "iteration / (factor+solve)" in out
    with (tmp_path / "bench_contact.csv").open() as fh:
        contact = list(csv.DictReader(fh))
    assert [(r["backend"], r["grid"]) for r in contact] == [("fd", "6x6"), ("fe", "3x3")]
    for r in contact:
        assert float(r["newton_free"]) >= 1 and float(r["newton_contact"]) >= 1 and int(r["contact_points"]) >= 36
        assert int(r["steps"]) == 3  # the contact rows' own window
        assert float(r["step_ratio"]) == pytest.approx(float(r["step_contact"]) / float(r["step_free"]), rel=1e-3)
    assert "step ms, ball" in out


def test_row_lists_given_run_whatever_the_backend_and_unset_ones_follow_it(tmp_path, capsys):
    """--implicit-fe given runs its FE rows under --backend fd; unset, FE's contact and scene rows stay off."""
    assert main(["bench", "--sizes", "8", "--steps", "1", "--implicit-fd", "", "--implicit-fe", "3",
                 "--contact-fd", "", "--out", str(tmp_path)]) == 0
    with (tmp_path / "bench_implicit.csv").open() as fh:
        assert [(r["backend"], r["grid"]) for r in csv.DictReader(fh)] == [("fe", "3x3")]
    assert not (tmp_path / "bench_contact.csv").exists() and not (tmp_path / "bench_scenes.csv").exists()
    assert "scene 1 of" not in capsys.readouterr().out


def test_scene_rows_run_shipped_scenes_for_their_time(tmp_path, capsys):
    """Opt-in scene rows: each shipped scene as it ships, on each backend, with Newton's counts per step."""
    assert main(["bench", "--sizes", "8", "--steps", "1", "--implicit-fd", "", "--implicit-fe", "", "--contact-fd", "",
                 "--backend", "all", "--scenes", "curtain,hanging", "--scene-fd", "6", "--scene-fe", "3",
                 "--scene-time", "0.02", "--out", str(tmp_path)]) == 0
    out = capsys.readouterr().out
    assert "scene 1 of 4: curtain fd 6x6" in out and "definite fallbacks / step" in out
    with (tmp_path / "bench_scenes.csv").open() as fh:
        rows = list(csv.DictReader(fh))
    assert [(r["scene"], r["backend"], r["grid"]) for r in rows] == [
        ("curtain", "fd", "6x6"), ("curtain", "fe", "3x3"), ("hanging", "fd", "6x6"), ("hanging", "fe", "3x3")]
    for r in rows:
        assert r["status"] == "finished" and float(r["t_reached"]) == pytest.approx(0.02)
        assert int(r["steps"]) >= 1 and float(r["wall"]) > 0
        newton, fallbacks = float(r["newton_per_step"]), float(r["fallbacks_per_step"])
        assert newton >= 1 and float(r["factorisations_per_step"]) >= 1 and 0 <= fallbacks <= newton


@pytest.mark.parametrize("backend", ["fd", "fe"])
def test_the_bench_steps_each_backend_within_its_own_stable_step(backend):
    """The bench's hanging scene at its dt runs 200 guarded steps without divergence. FE's bound is about a
    fifth of FD's: on 12 x 12 nodes already below the scene's dt, so FE gets its own step."""
    model, dt = hanging_model(backend, 12)
    assert dt <= 0.5 * model.stable_step()
    assert (SEMI_IMPLICIT_DT > model.stable_step()) == (backend == "fe")
    result = dm.TimeStepper(model, dt).run(model.initial_state(), steps=200)
    assert result.status == "finished", result.message
    assert np.all(np.isfinite(result.state.X))


@pytest.mark.parametrize("argv, message", [
    (["--sizes", "8,x"], "--sizes must be comma-separated integers"),
    (["--sizes", "2"], "grid sizes of at least 3"),
    (["--backend", "fv"], "unknown backend 'fv'"),
    (["--steps", "0"], "--steps must be a positive integer"),
    (["--contact-steps", "1.5"], "--contact-steps must be a positive integer, got '1.5'"),
    (["--implicit-fd", "4,y"], "--implicit-fd must be comma-separated integers"),
    (["--implicit-fe", "2"], "--implicit-fe needs grid sizes of at least 3"),
    (["--scenes", "curtain", "--scene-fd", ""], "--scenes 'curtain' needs a grid"),
    (["--contact-fd", "z"], "--contact-fd must be comma-separated integers"),
    (["--solver", "mumps"], "solver must be one of"),
    (["--scenes", "curtain,drapes"], "--scenes: unknown scene 'drapes'"),
    (["--scenes", "flag", "--scene-time", "-2"], "--scene-time must be a positive number of seconds"),
    (["--scenes", "flag", "--scene-fe", "2"], "--scene-fe needs grid sizes of at least 3"),
])
def test_bench_bad_input(argv, message, tmp_path, capsys):
    assert main(["bench", *argv, "--out", str(tmp_path / "o")]) == 2
    err = capsys.readouterr().err
    assert len(err.strip().splitlines()) == 1 and message in err
    assert not (tmp_path / "o").exists()
