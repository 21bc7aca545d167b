"""``deformable run``: XDMF output read back, checkpoints and resume, divergence, bad input."""

import tomllib

import meshio
import numpy as np
import pytest

from deformable import scenes
from deformable.io import load_checkpoint
from validation.commands import build_parser, main
from validation.commands.run import prepare
from validation.harness.backends import make_model

from ...conftest import assert_same_series, series_frames

FIELDS = {"G11", "G12", "G22", "B11", "B12", "B22", "speed", "energy_density", "displacement"}


def _run(argv, capsys):
    code = main(["run", *map(str, argv)])
    out = capsys.readouterr()
    return code, out.out, out.err


def test_a_run_writes_a_series_that_meshio_reads_back(tmp_path, capsys):
    code, out, err = _run(["flag", "--grid", "12x10", "--steps", "30", "--every", "0.05", "--out", str(tmp_path)],
                          capsys)
    assert code == 0, err
    assert "flag: finished, 30 steps to t = 0.15 s" in out and "energy" in out
    with meshio.xdmf.TimeSeriesReader(str(tmp_path / "flag.xdmf")) as reader:
        points, cells = reader.read_points_cells()
        assert points.shape == (120, 3) and cells[0].type == "quad" and len(cells[0].data) == 11 * 9
        times = []
        for k in range(reader.num_steps):
            t, data, _ = reader.read_data(k)
            times.append(t)
            assert FIELDS <= set(data) and all(np.all(np.isfinite(v)) for k, v in data.items()
                                               if not k.startswith("compatibility_"))
            assert not any(np.any(np.isinf(v)) for v in data.values())  # the test's NaN where it is undefined
    assert times == pytest.approx([0.0, 0.05, 0.1, 0.15], abs=1e-12)
    assert np.abs(data["displacement"]).max() > 0 and data["speed"].max() > 0
    text = (tmp_path / "flag.toml").read_text()
    assert text.startswith("# resolved scene config") and "t_end = 0.15\n" in text and "steps = 30\n" in text


def test_a_scene_file_overrides_and_the_resolved_config_is_written(tmp_path, capsys):
    scene = tmp_path / "mine.toml"
    scene.write_text('scene = "curtain"\nfabric = ""\neta = 25.0\nnodes = [10, 12]\n')
    out_dir = tmp_path / "out"
    code, _, err = _run([str(scene), "--steps", "5", "--dt", "5e-4", "--out", str(out_dir)], capsys)
    assert code == 0, err
    text = (out_dir / "curtain.toml").read_text()
    resolved = tomllib.loads(text)
    assert resolved["eta"] == 25.0 and resolved["nodes"] == [10, 12] and resolved["dt"] == 0.0005


def test_render_writes_pngs_and_a_gif(tmp_path, capsys):
    """The frames themselves are checked in tests/deformable/io/test_render.py."""
    code, out, err = _run(["hanging", "--grid", "8x8", "--steps", "4", "--every", "0.01", "--render", "--field",
                           "energy_density", "--out", str(tmp_path)], capsys)
    assert code == 0, err
    pngs = sorted((tmp_path / "frames").glob("frame-*.png"))
    assert len(pngs) == 3 and (tmp_path / "frames" / "hanging.gif").stat().st_size > 0
    assert "rendered 3 frames" in out
    # what the rendering does, as it goes (issue 47): a line a frame here (each a tenth or more), then the GIF
    said = [line.split(" ", 2)[2] for line in err.splitlines() if " rendering hanging.xdmf: " in line]
    assert [line.split(",")[0] for line in said[:3]] == [f"rendering hanging.xdmf: {p} % ({k} of 3 frames)"
                                                          for p, k in ((33, 1), (67, 2), (100, 3))], err
    assert "left" not in said[0] and "left" in said[1]
    assert said[3] == "rendering hanging.xdmf: assembling hanging.gif from the 3 frames"


def test_a_resumed_run_is_bit_identical(tmp_path, capsys):
    full, part = tmp_path / "full", tmp_path / "part"
    base = ["curtain", "--grid", "10x12", "--steps", "40", "--checkpoint-every", "20"]
    assert _run(base + ["--out", str(full)], capsys)[0] == 0
    code, _, err = _run(base + ["--out", str(part), "--resume", str(full / "curtain-checkpoint-0000020.npz")], capsys)
    assert code == 0, err
    a = load_checkpoint(full / "curtain-checkpoint-0000040.npz")
    b = load_checkpoint(part / "curtain-checkpoint-0000040.npz")
    assert a["step"] == b["step"] == 40 and a["t"] == b["t"]
    np.testing.assert_array_equal(a["X"], b["X"])
    np.testing.assert_array_equal(a["V"], b["V"])


def test_a_diverging_run_stops_keeps_its_frames_and_checkpoints_the_last_good_state(tmp_path, capsys):
    # the paper's force at a dt far beyond its stretching bound h sqrt(mu / (2 eta G)) (docs/design.md, "Findings")
    code, out, err = _run(["hanging", "--force-model", "tpbf87", "--grid", "12x12", "--dt", "0.02", "--steps", "200",
                           "--every", "0.02", "--out", str(tmp_path)], capsys)
    assert code == 1
    assert "diverged at step" in err and len(err.strip().splitlines()) == 1
    ck = load_checkpoint(tmp_path / "hanging-diverged.npz")
    assert np.all(np.isfinite(ck["X"])) and 0 < ck["step"] < 200
    with meshio.xdmf.TimeSeriesReader(str(tmp_path / "hanging.xdmf")) as reader:
        reader.read_points_cells()
        assert reader.num_steps == ck["step"] + 1  # every frame up to the last good state
        t, _, _ = reader.read_data(reader.num_steps - 1)
    assert t == pytest.approx(ck["t"])


def test_the_run_api_reports_divergence_with_the_last_good_state(tmp_path):
    args = build_parser().parse_args(["run", "hanging", "--force-model", "tpbf87", "--grid", "12x12", "--dt", "0.02",
                                      "--steps", "200", "--out", str(tmp_path)])
    sim = prepare(args)
    result = sim.run()
    assert result.status == "diverged" and np.all(np.isfinite(result.state.X))
    assert sim.checkpoints[-1].name == "hanging-diverged.npz" and sim.series.frames >= 1
    assert sim.energy.history[-1, 0] <= result.state.t


@pytest.fixture(scope="module")
def flag_checkpoint(tmp_path_factory):
    folder = tmp_path_factory.mktemp("ck")
    assert main(["run", "flag", "--grid", "10x10", "--steps", "2", "--checkpoint-every", "1",
                 "--out", str(folder)]) == 0
    return folder / "flag-checkpoint-0000001.npz"


def _bad_cases(tmp_path, ck):
    blocker = tmp_path / "a-file"
    blocker.write_text("x")
    toml = tmp_path / "bad.toml"
    toml.write_text('scene = "flag"\nwindd = 3.0\n')
    junk = tmp_path / "junk.npz"
    junk.write_bytes(b"not a checkpoint")
    inside = tmp_path / "inside.toml"
    inside.write_text('scene = "floor"\nnodes = [5, 5]\n\n[[obstacles]]\nkind = "sphere"\nradius = 0.2\n'
                      'center = [0.5, 0.5, 0.3]\n')
    bad_obstacle = tmp_path / "bad_obstacle.toml"
    bad_obstacle.write_text('scene = "floor"\n\n[[obstacles]]\nkind = "sphere"\ncentre = [0, 0, 0]\n')
    return {
        "unknown scene": (["tablecloth"], "unknown scene 'tablecloth'"),
        "unknown TOML key": ([str(toml)], "unknown key 'windd'"),
        "malformed grid": (["flag", "--grid", "32by32"], "malformed grid '32by32'"),
        "tiny grid": (["flag", "--grid", "2x8"], "at least 3 nodes"),
        "dt zero": (["flag", "--dt", "0"], "--dt must be positive"),
        "dt negative": (["flag", "--dt=-1e-3"], "--dt must be positive"),
        "dt text": (["flag", "--dt", "fast"], "--dt must be a positive number"),
        "unwritable output": (["flag", "--out", str(blocker / "sub")], "cannot write to output folder"),
        "unknown backend": (["flag", "--backend", "fv"], "unknown backend 'fv'"),
        "unknown field": (["flag", "--field", "colour"], "unknown field 'colour'"),
        "resume other scene": (["curtain", "--resume", str(ck)], "scene = 'curtain' vs 'flag'"),
        "resume other grid": (["flag", "--grid", "12x12", "--resume", str(ck)], "nodes = (12, 12) vs (10, 10)"),
        "resume other dt": (["flag", "--grid", "10x10", "--dt", "5e-4", "--resume", str(ck)], "dt = 0.0005 vs 0.005"),
        "resume not a checkpoint": (["flag", "--resume", str(junk)], "cannot read checkpoint"),
        "resume missing": (["flag", "--resume", str(tmp_path / "none.npz")], "cannot read checkpoint"),
        "resume past the end": (["--steps", "1", "--resume", str(ck)], "nothing to do"),
        "start inside an obstacle": ([str(inside)], "lies 0.2 m inside obstacle 1 (sphere)"),
        "unknown obstacle key": ([str(bad_obstacle)], "unknown key 'centre' in scene field obstacles[0]"),
        "papers scheme with the barrier": (["floor", "--force-model", "tpbf87"],
                                           "set the contact method to 'exponential'"),
    }


@pytest.mark.parametrize("case", ["unknown scene", "unknown TOML key", "malformed grid", "tiny grid", "dt zero",
                                  "dt negative", "dt text", "unwritable output", "unknown backend", "unknown field",
                                  "resume other scene", "resume other grid", "resume other dt",
                                  "resume not a checkpoint", "resume missing", "resume past the end",
                                  "start inside an obstacle", "unknown obstacle key", "papers scheme with the barrier"])
def test_bad_input_is_one_line_exit_2_and_writes_nothing(case, tmp_path, capsys, flag_checkpoint):
    argv, message = _bad_cases(tmp_path, flag_checkpoint)[case]
    out_dir = tmp_path / "out"
    if "--out" not in argv:
        argv = argv + ["--out", str(out_dir)]
    code, _, err = _run(argv, capsys)
    assert code == 2
    assert len(err.strip().splitlines()) == 1 and message in err, err
    assert "Traceback" not in err
    assert not out_dir.exists() or not any(out_dir.iterdir())


def test_force_model_option_runs_the_papers_force(tmp_path, capsys):
    code, out, err = _run(["flag", "--force-model", "tpbf87", "--grid", "6x6", "--steps", "3",
                           "--out", str(tmp_path)], capsys)
    assert code == 0, err
    assert 'force_model = "tpbf87"' in next(tmp_path.glob("*.toml")).read_text()


def test_unknown_force_model_is_one_line(tmp_path, capsys):
    code, out, err = _run(["flag", "--force-model", "tpbf88", "--out", str(tmp_path)], capsys)
    assert code == 2 and len(err.strip().splitlines()) == 1 and "unknown force model 'tpbf88'" in err
    assert not any(tmp_path.iterdir())


@pytest.mark.parametrize("scene", list(scenes.SCENES))
def test_every_scene_runs_on_the_fe_backend_at_its_own_stable_step(scene, tmp_path, capsys):
    """The scenes' default dt is FD's; the FE backend runs at no more than half its own stretching bound."""
    code, out, err = _run([scene, "--backend", "fe", "--grid", "6x6", "--steps", "20", "--out", str(tmp_path)],
                          capsys)
    assert code == 0, err
    assert f"{scene}: finished, 20 steps" in out and "6x6 fe" in out
    assert list(tmp_path.glob("*.xdmf"))
    cfg = scenes.read_toml(tmp_path / f"{scene}.toml")
    assert cfg.dt <= 0.5 * make_model(scenes.build(cfg), "fe").stable_step()


def test_under_the_papers_force_a_backend_picks_its_own_step_where_the_scenes_is_too_long(tmp_path, capsys):
    code, out, err = _run(["hanging", "--force-model", "tpbf87", "--backend", "fe", "--grid", "16x16", "--steps", "5",
                           "--out", str(tmp_path)], capsys)
    assert code == 0, err
    cfg = scenes.read_toml(tmp_path / "hanging.toml")
    bound = make_model(scenes.build(cfg), "fe").stable_step()
    assert bound < scenes.config("hanging").dt and cfg.dt <= 0.5 * bound


# -- reproducible runs (issue 16, point 2) -------------------------------------------------------------
@pytest.mark.parametrize("backend", ["fd", "fe"])
def test_rerunning_the_resolved_config_reproduces_the_run_bit_for_bit(backend, tmp_path, capsys):
    first, again = tmp_path / "first", tmp_path / "again"
    code, _, err = _run(["hanging", "eta=25", "xi=2e-5", "--grid", "6x6", "--backend", backend, "--scheme", "newmark",
                         "--t-end", "0.03", "--every", "0.01", "--out", first], capsys)
    assert code == 0, err
    text = (first / "hanging.toml").read_text()
    resolved = tomllib.loads(text)
    assert (resolved["eta"], resolved["xi"], resolved["nodes"], resolved["t_end"]) == (25.0, 2e-5, [6, 6], 0.03)
    assert {k: resolved["run"][k] for k in ("backend", "scheme", "every")} == \
        {"backend": backend, "scheme": "newmark", "every": 0.01} and resolved["run"]["version"]
    code, out, err = _run([first / "hanging.toml", "--out", again], capsys)
    assert code == 0, err
    assert f"{backend}, newmark" in out
    assert_same_series(first / "hanging.xdmf", again / "hanging.xdmf")
    assert (again / "hanging.toml").read_text() == text


def test_key_value_sets_any_scene_field(tmp_path, capsys):
    code, _, err = _run(["flag", "wind=5", "coil=12.5", "nodes=[6,5]", "force_model=variational", "shear=0.5",
                         "--steps", "2", "--out", tmp_path], capsys)
    assert code == 0, err
    cfg = scenes.read_toml(tmp_path / "flag.toml")
    assert (cfg.wind, cfg.coil, cfg.nodes, cfg.shear) == (5.0, 12.5, (6, 5), 0.5)


@pytest.mark.parametrize("model, end", [("variational", ["--steps", "8"]),
                                        ("tpbf87", ["--t-end", "0.037"])])  # 7 steps of 5 ms and one of 2 ms
def test_a_resumed_run_continues_the_same_series_frame_by_frame(model, end, tmp_path, capsys):
    """Killed after step 5 with a checkpoint at step 3: the resumed series (in place, and copied into another
    folder) equals the uninterrupted one, displacement measured from the original start."""
    full, part, other = tmp_path / "full", tmp_path / "part", tmp_path / "other"
    base = ["curtain", "--force-model", model, "--grid", "8x8", "--every", "0.01", "--checkpoint-every", "3"]
    assert _run(base + [*end, "--out", full], capsys)[0] == 0
    assert _run(base + ["--steps", "5", "--out", part], capsys)[0] == 0
    code, _, err = _run([*end, "--resume", part / "curtain-checkpoint-0000003.npz", "--out", other], capsys)
    assert code == 0, err
    code, _, err = _run(base + [*end, "--resume", part / "curtain-checkpoint-0000003.npz"], capsys)
    assert code == 0, err
    assert sorted(p.name for p in part.glob("*.xdmf")) == ["curtain.xdmf"]
    assert_same_series(full / "curtain.xdmf", part / "curtain.xdmf")
    assert_same_series(full / "curtain.xdmf", other / "curtain.xdmf")


# -- output (issue 16, point 3) ------------------------------------------------------------------------
def test_frames_every_so_many_simulated_seconds_at_exact_times(tmp_path, capsys):
    """The same frames on both backends although FE steps at its own, shorter dt; times without round-off."""
    times = {}
    for backend in ("fd", "fe"):
        out = tmp_path / backend
        code, _, err = _run(["hanging", "--backend", backend, "--grid", "6x6", "--t-end", "0.1", "--every", "0.025",
                             "--out", out], capsys)
        assert code == 0, err
        dt = scenes.read_toml(out / "hanging.toml").dt
        times[backend] = [t for t, _, _ in series_frames(out / "hanging.xdmf")]
        targets = [0.0, 0.025, 0.05, 0.075, 0.1]
        assert len(times[backend]) == len(targets)
        assert all(0 <= t - g < dt for t, g in zip(times[backend], targets))
        assert times[backend][-1] == 0.1
    assert times["fd"] == [0.0, 0.025, 0.05, 0.075, 0.1]


def test_the_output_api_is_public_and_creates_its_folders(tmp_path):
    import deformable as dm

    model = make_model(scenes.hanging(nodes=(5, 5)), "fd")
    series = tmp_path / "a" / "b" / "run.xdmf"
    dm.TimeStepper(model, 5e-3).run(model.initial_state(), t_end=0.02, trackers=[dm.XDMFWriter(series, interval=0.01)])
    cells, frames = dm.read_series(series)
    assert [t for t, _, _ in frames] == [0.0, 0.01, 0.02] and cells.shape == (16, 4)


# -- command-line polish (issue 16, point 6) -----------------------------------------------------------
def test_every_option_of_every_command_states_its_default():
    from validation.commands import HelpFormatter

    parser = build_parser()
    subs = next(a for a in parser._actions if a.dest == "command").choices
    missing = []
    for name, sub in {"deformable": parser, **subs}.items():
        for action in sub._actions:
            if action.option_strings and action.nargs != 0:
                if "default" not in HelpFormatter(name)._get_help_string(action):
                    missing.append(f"{name} {action.option_strings[-1]}")
    assert set(subs) == {"scenes", "run", "view", "params", "check", "validate", "bench", "sweep",
                         "fabrics"} and missing == [], missing


def test_quiet_prints_nothing_but_errors(tmp_path, capsys):
    code, out, err = _run(["flag", "--grid", "6x6", "--steps", "2", "--out", tmp_path, "--quiet"], capsys)
    assert code == 0 and out == "" and err == ""
