"""``deformable bench``: the table and CSV of step time against one direct factor+solve, on both backends."""

import csv

import numpy as np
import pytest

import deformable as dm
from deformable.contact.selfpotential import PARTS
from validation.benches import SEMI_IMPLICIT_DT, hanging_model
from validation.commands import main


def test_bench_writes_both_tables_and_csvs_for_both_backends(tmp_path, capsys):
    assert main(["bench", "--backend", "all", "--sizes", "8,12", "--steps", "2", "--self-fd", "", "--implicit-fd", "8",
                 "--implicit-fe", "4", "--implicit-time", "0.02", "--contact-fd", "6", "--contact-fe", "3",
                 "--contact-steps", "3",
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
        its = float(r["newton_per_step"])
        # 0.02 s at 5 ms, the first step untimed
        assert its >= 1 and float(r["factorisations_per_step"]) > 0 and int(r["steps"]) == 3
        kernels = {k: float(r[k]) for k in ("energy", "gradient", "hessian", "factor", "solve")}
        assert all(v > 0 for v in kernels.values())
        floor = kernels["hessian"] + kernels["factor"] + its * (kernels["solve"] + kernels["gradient"])
        assert float(r["floor_step"]) == pytest.approx(floor, rel=1e-3)
        assert float(r["step_ratio"]) == pytest.approx(float(r["step"]) / floor, rel=1e-3)
        assert float(r["iteration_ratio"]) == pytest.approx(float(r["step"]) / its / sum(kernels.values()), rel=1e-3)
        assert float(r["semi_ratio"]) == pytest.approx(float(r["step"]) / float(r["semi_implicit_step"]), rel=1e-3)
    assert "Newton / step" in out and "step / floor" in out
    with (tmp_path / "bench_contact.csv").open() as fh:
        contact = list(csv.DictReader(fh))
    assert [(r["backend"], r["grid"]) for r in contact] == [("fd", "6x6"), ("fe", "3x3")]
    for r in contact:
        assert float(r["newton_free"]) >= 1 and float(r["newton_contact"]) >= 1 and int(r["contact_points"]) >= 36
        assert int(r["steps"]) == 3  # the contact rows' own window
        assert float(r["step_ratio"]) == pytest.approx(float(r["step_contact"]) / float(r["step_free"]), rel=1e-3)
        assert float(r["self_ratio"]) == pytest.approx(float(r["step_self"]) / float(r["step_contact"]), rel=1e-3)
        parts = sum(float(r[f"self_{k}"]) for k in PARTS)
        assert 0 < parts and float(r["self_share"]) == pytest.approx(parts / (3 * float(r["step_self"])), rel=1e-3)
    assert "step ms, ball" in out and "self ratio" in out


def test_row_lists_given_run_whatever_the_backend_and_unset_ones_follow_it(tmp_path, capsys):
    """--implicit-fe given runs its FE rows under --backend fd; unset, FE's contact and scene rows stay off."""
    assert main(["bench", "--sizes", "8", "--steps", "1", "--self-fd", "", "--implicit-fd", "", "--implicit-fe", "3",
                 "--implicit-time", "0.01", "--contact-fd", "", "--out", str(tmp_path)]) == 0
    with (tmp_path / "bench_implicit.csv").open() as fh:
        assert [(r["backend"], r["grid"]) for r in csv.DictReader(fh)] == [("fe", "3x3")]
    assert not (tmp_path / "bench_contact.csv").exists() and not (tmp_path / "bench_scenes.csv").exists()
    assert "scene 1 of" not in capsys.readouterr().out


def test_scene_rows_run_shipped_scenes_for_their_time(tmp_path, capsys):
    """Opt-in scene rows: each shipped scene as it ships, on each backend, with Newton's counts per step."""
    assert main(["bench", "--sizes", "8", "--steps", "1", "--self-fd", "", "--implicit-fd", "", "--implicit-fe", "",
                 "--contact-fd", "", "--backend", "all", "--scenes", "curtain,hanging", "--scene-fd", "6", "--scene-fe", "3",
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
        # a factorisation may outlive its step (NewtonSettings.lag): fewer than one a step, never none at all
        assert newton >= 1 and float(r["factorisations_per_step"]) > 0 and 0 <= fallbacks <= newton


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
    (["--implicit-time", "0"], "--implicit-time must be a positive number of seconds"),
    (["--self-fd", "2"], "--self-fd needs grid sizes of at least 3"),
    (["--self-time", "-1"], "--self-time must be a positive number of seconds"),
    (["--bar", "--bar-grid", "x"], "--bar-grid must be a positive integer"),
    (["--bar", "--bar-grid", "2"], "--bar-grid needs at least 3 nodes a side"),
    (["--rates-settings", "fast"], "--rates-settings: unknown settings 'fast'"),
    (["--scenes", "curtain", "--scene-fd", ""], "--scenes 'curtain' needs a grid"),
    (["--contact-fd", "z"], "--contact-fd must be comma-separated integers"),
    (["--solver", "mumps"], "solver must be one of"),
    (["--scenes", "curtain,drapes"], "--scenes: unknown scene 'drapes'"),
    (["--scenes", "flag", "--scene-time", "-2"], "--scene-time must be a positive number of seconds"),
    (["--scenes", "flag", "--scene-fe", "2"], "--scene-fe needs grid sizes of at least 3"),
    (["--rates", "--rates-time", "0"], "--rates-time must be a positive number of seconds"),
    (["--rates", "--rates-scenes", "curtian"], "--rates-scenes: unknown scene 'curtian'"),
    (["--rates", "--rates-fd", "", "--rates-fe", "", "--rates-curtain-fd", ""], "--rates needs a scene and a grid"),
    (["--rates", "--rates-fe", "2"], "--rates-fe needs grid sizes of at least 3"),
])
def test_bench_bad_input(argv, message, tmp_path, capsys):
    assert main(["bench", *argv, "--out", str(tmp_path / "o")]) == 2
    err = capsys.readouterr().err
    assert len(err.strip().splitlines()) == 1 and message in err
    assert not (tmp_path / "o").exists()


def test_rate_rows_time_both_settings_against_their_references(tmp_path, capsys):
    """``--rates``: the curtain on FD 6 x 6 nodes under the defaults and before-step-test's, each with its Newton
    error against the tight run and the dt vs dt/2 difference; the verdicts name what this run did not measure."""
    assert main(["bench", "--sizes", "8", "--steps", "1", "--self-fd", "", "--implicit-fd", "", "--contact-fd", "",
                 "--rates", "--rates-scenes", "curtain", "--rates-fd", "6", "--rates-fe", "", "--rates-curtain-fd", "",
                 "--rates-time", "0.03", "--out", str(tmp_path)]) == 0
    with (tmp_path / "bench_rates.csv").open() as fh:
        rows = list(csv.DictReader(fh))
    assert [(r["scene"], r["grid"], r["settings"]) for r in rows] == [("curtain", "6x6", "defaults"),
                                                                       ("curtain", "6x6", "before-step-test")]
    for r in rows:
        assert r["status"] == "finished" and float(r["t_reached"]) == pytest.approx(0.03)
        assert float(r["rate"]) == pytest.approx(float(r["t_reached"]) / float(r["cpu"]), rel=1e-9)
        error, time_error = float(r["newton_error"]), float(r["time_error"])
        assert 0 <= error < time_error and float(r["error_ratio"]) == pytest.approx(error / time_error)
    verdicts = (tmp_path / "bench_rates.md").read_text()
    assert "curtain FD 64x64 nodes: not measured in this run" in verdicts


def test_self_contact_rows_and_the_curtain_bar(tmp_path, capsys):
    """The self-contact rows: the curtain with its self-contact against without, their ratio and counts; the curtain
    bar: CPU per simulated second in units of a fixed matrix's SuperLU factor+solve, with its Newton error against
    dt vs dt/2; the rate rows under one setting without references (errors not measured)."""
    assert main(["bench", "--sizes", "8", "--steps", "1", "--implicit-fd", "", "--contact-fd", "", "--self-fd", "8",
                 "--self-time", "0.03", "--bar", "--bar-grid", "8", "--bar-time", "0.03", "--rates", "--rates-scenes",
                 "curtain", "--rates-fd", "6", "--rates-fe", "", "--rates-curtain-fd", "", "--rates-time", "0.02",
                 "--rates-settings", "defaults", "--no-rates-references", "--out", str(tmp_path)]) == 0
    out = capsys.readouterr().out
    assert "self-contact row: curtain fd 8x8" in out and "factor+solves / simulated s" in out
    with (tmp_path / "bench_self.csv").open() as fh:
        (row,) = list(csv.DictReader(fh))
    assert row["grid"] == "8x8" and float(row["step_self"]) > 0 and float(row["step_free"]) > 0
    assert float(row["ratio"]) == pytest.approx(float(row["step_self"]) / float(row["step_free"]), rel=1e-3)
    assert int(row["rejected_self"]) >= 0 and 1 <= float(row["broad_phases"]) and 0 <= float(row["bounded"]) <= 1
    with (tmp_path / "bench_bar.csv").open() as fh:
        (bar,) = list(csv.DictReader(fh))
    assert bar["status"] == "finished" and float(bar["t_end"]) == pytest.approx(0.03) and float(bar["unit"]) > 0
    assert float(bar["bar"]) == pytest.approx(float(bar["cpu"]) / 0.03 / float(bar["unit"]), rel=1e-3)
    assert 0 <= float(bar["newton_error"]) < float(bar["time_error"])
    with (tmp_path / "bench_rates.csv").open() as fh:
        (rate,) = list(csv.DictReader(fh))
    assert rate["settings"] == "defaults" and rate["newton_error"] == "nan" and float(rate["peak_mb"]) > 10


def _rate(scene, grid, settings, rate, **kw):
    from validation.benches.rates import RateRow

    fields = dict(backend="fd", unknowns=0, dt=0.005, t_end=2.0, status="finished", t_reached=2.0, steps=400,
                  wall=2.0 / rate, cpu=2.0 / rate, peak_mb=100.0, newton_per_step=2.0, factorisations_per_step=1.0, fallbacks_per_step=0.0,
                  newton_error=1e-3, time_error=1e-2, error_ratio=0.1)
    fields.update(kw)
    return RateRow(scene=scene, grid=grid, settings=settings, rate=rate, **fields)


def test_the_rate_verdicts_follow_the_numbers():
    from validation.benches.rates import verdicts

    rows = [_rate("curtain", "64x64", "defaults", 0.05), _rate("curtain", "64x64", "before-step-test", 0.02),
            _rate("flag", "64x64", "defaults", 0.01, newton_per_step=2.6, error_ratio=0.05),
            _rate("flag", "64x64", "before-step-test", 0.01)]
    lines = verdicts(rows)
    assert "2.50x (target >= 2x): met" in lines[0] and "256x256 nodes: not measured" in lines[1]
    assert any(line.startswith("flag FD 64x64") and "5.00 %" in line and line.endswith(": met") for line in lines)
    assert any("Newton iterations a step: 2.60 (target <= 2.5): NOT met" in line for line in lines)
    assert "sphere FD 64x64 Newton error: not measured in this run" in lines
    slower = verdicts([_rate("curtain", "64x64", "defaults", 0.03),
                       _rate("curtain", "64x64", "before-step-test", 0.02)])
    assert slower[0].endswith("1.50x (target >= 2x): NOT met")
    # the fine grid: CPU minutes per simulated second against 10, with its peak memory
    fine = [line for line in verdicts([_rate("curtain", "256x256", "defaults", 1 / 996, t_end=1.0, t_reached=1.0,
                                             cpu=996.0, peak_mb=5246.0)]) if "FD 256x256 nodes, 1 of 1 s" in line]
    assert fine == ["curtain FD 256x256 nodes, 1 of 1 s under defaults, CPU per simulated second (peak memory 5246 MB):"
                    " 16.6 min (target <= 10 min): NOT met"]
    met = verdicts([_rate("curtain", "256x256", "defaults", 1 / 250, t_end=0.5, t_reached=0.5, cpu=250.0)])
    assert any("0.5 of 0.5 s" in line and line.endswith("8.3 min (target <= 10 min): met") for line in met)


@pytest.mark.slow  # a slow fault or a whole pipeline, run by pytest -m slow
def test_realtime_rows_run_the_view_offscreen_and_append_a_row_a_run(tmp_path, capsys):
    """``--realtime``: the scene stepped and drawn as ``deformable view --offscreen`` does, in CPU seconds; each run
    appends its row (one scene, then another: two rows), and the default tables do not run."""
    for scene in ("hanging", "flag"):
        assert main(["bench", "--realtime", scene, "--grid", "6x6", "--t-end", "0.1", "--out", str(tmp_path)]) == 0
    out = capsys.readouterr().out
    with (tmp_path / "bench_realtime.csv").open() as fh:
        reader = csv.DictReader(fh)
        rows = list(reader)
    assert reader.fieldnames == ["scene", "backend", "grid", "sim_seconds", "cpu_steps", "cpu_render",
                                 "realtime_factor"]
    assert [(r["scene"], r["backend"], r["grid"]) for r in rows] == [("hanging", "fd", "6x6"), ("flag", "fd", "6x6")]
    for r in rows:
        sim, steps, render = float(r["sim_seconds"]), float(r["cpu_steps"]), float(r["cpu_render"])
        assert sim == pytest.approx(0.1)  # 3 frames at 30 a simulated second, whole 5 ms steps
        assert steps > 0 and render > 0
        assert float(r["realtime_factor"]) == pytest.approx(sim / (steps + render), rel=1e-5)
        assert f"| {r['scene']} | fd | 6x6 | {r['sim_seconds']} | {r['cpu_steps']} | {r['cpu_render']} | " \
               f"{r['realtime_factor']} |" in out  # the same row printed
    assert "wrote" in out and "appended to" in out
    assert not (tmp_path / "bench.csv").exists() and not (tmp_path / "bench_implicit.csv").exists()


def test_a_realtime_table_of_other_columns_is_written_anew(tmp_path):
    from validation.benches.realtime import COLUMNS, RealtimeRow, write_row

    path = tmp_path / "bench_realtime.csv"
    path.write_text("scene,wall\ncurtain,3.5\n")
    row = RealtimeRow("curtain", "fd", "20x20", 2.0, 3.0, 1.0, 0.5)
    assert not write_row(path, row) and write_row(path, row)
    assert path.read_text().splitlines() == [",".join(COLUMNS)] + ["curtain,fd,20x20,2,3,1,0.5"] * 2


@pytest.mark.parametrize("argv, message", [
    (["--realtime", "drapes"], "--realtime: unknown scene 'drapes'"),
    (["--realtime", "curtain", "--grid", "20"], "--grid: malformed grid '20'"),
    (["--realtime", "curtain", "--grid", "2x20"], "--grid: grid '2x20' needs at least 3 nodes a side"),
    (["--realtime", "flag", "--t-end", "-2"], "--t-end must be a positive number of seconds, got '-2'"),
    (["--realtime", "flag", "--t-end", "x"], "--t-end must be a positive number of seconds"),
    (["--realtime", "flag", "--backend", "fv"], "unknown backend 'fv'"),
])
def test_realtime_bad_input(argv, message, tmp_path, capsys):
    assert main(["bench", *argv, "--out", str(tmp_path / "o")]) == 2
    err = capsys.readouterr().err
    assert len(err.strip().splitlines()) == 1 and message in err
    assert not (tmp_path / "o").exists()
