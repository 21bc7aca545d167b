"""The scenes of the paper's section 5 and scene files (deformable.scenes)."""

import numpy as np
import pytest

import deformable as dm
from deformable import scenes
from fdmodel import FDModel


@pytest.mark.parametrize("name", list(scenes.SCENES))
def test_each_scene_builds_and_its_default_dt_is_below_the_stretching_bound(name):
    """The default dt keeps a margin of 1.3 below the FD stretching bound on the default 32 x 32 grid."""
    spec = scenes.SCENES[name]
    scene = spec(nodes=(12, 10))
    assert isinstance(scene, dm.Scene) and scene.sheet.nodes == (12, 10) and scene.name == name
    cfg = spec.config()
    assert cfg.nodes == (32, 32)
    bound = FDModel(scenes.build(cfg)).stable_step()
    assert spec.dt == cfg.dt <= bound / 1.3, f"{name}: dt {cfg.dt} vs bound {bound:.3g}"


@pytest.mark.parametrize("name", list(scenes.SCENES))
def test_each_scene_takes_a_hundred_stable_steps(name):
    spec = scenes.SCENES[name]
    model = FDModel(spec(nodes=(16, 16)))
    result = dm.TimeStepper(model, spec.dt).run(model.initial_state(), steps=100)
    assert result.status == "finished", result.message
    assert np.all(np.isfinite(result.state.X))


def test_module_functions_match_the_registry():
    for name, fn in [("hanging", scenes.hanging), ("curtain", scenes.curtain), ("curtain-silky", scenes.curtain_silky),
                     ("paper", scenes.paper), ("flag", scenes.flag)]:
        assert fn(nodes=(8, 8)).name == name
    assert scenes.config("paper").xi == 3e-6
    silky, plain = scenes.config("curtain-silky"), scenes.config("curtain")
    assert silky.mu == 20 * plain.mu and silky.push == 20 * plain.push and silky.scale == 20


def test_curtain_top_row_slides_along_the_rail():
    model = FDModel(scenes.curtain(nodes=(10, 8)))
    fx, fy, fz = (set(map(int, f)) for f in model.fixed_dofs())
    top = {m * 8 + 7 for m in range(10)}
    assert top <= fy and top <= fz
    assert fx & top == {7}  # only the pinned end of the rail is held along x


def test_toml_overrides_a_named_scene_and_round_trips(tmp_path):
    path = tmp_path / "c.toml"
    path.write_text('scene = "curtain"\neta = 30.0\nnodes = [20, 24]\nrest_metric = [0.9, 1.0]\n')
    cfg = scenes.read_toml(path)
    assert cfg.scene == "curtain" and cfg.eta == 30.0 and cfg.nodes == (20, 24) and cfg.rest_metric == (0.9, 1.0)
    assert cfg.push == scenes.config("curtain").push
    again = tmp_path / "again.toml"
    again.write_text(scenes.to_toml(cfg))
    assert scenes.read_toml(again) == cfg
    assert scenes.build(cfg).sheet.nodes == (20, 24)


@pytest.mark.parametrize("text, message", [
    ('scene = "curtain"\netaa = 3.0\n', "unknown key 'etaa'"),
    ('scene = "flag"\npush = 3.0\n', "unknown key 'push'"),
    ('scene = "drape"\n', "unknown scene 'drape'"),
    ('eta = 3.0\n', "must name its scene"),
    ('scene = "flag"\neta = "stiff"\n', "eta must be a finite number"),
    ('scene = "flag"\nnodes = [2.5, 3]\n', "nodes must be two ints"),
    ('scene = "flag"\ndt = 0.0\n', "dt must be positive"),
    ('scene = "flag"\n[material]\neta = 1\n', "unknown key 'material'"),
    ('scene = \n', "not valid TOML"),
])
def test_bad_scene_files_are_value_errors_that_name_the_key(tmp_path, text, message):
    path = tmp_path / "bad.toml"
    path.write_text(text)
    with pytest.raises(ValueError, match=message):
        scenes.read_toml(path)


def test_unknown_override_is_named():
    with pytest.raises(ValueError, match="unknown key 'wind'"):
        scenes.config("curtain", wind=3.0)


@pytest.mark.slow
def test_curtain_gathers_into_folds_and_flag_waves_over_two_seconds():
    model = FDModel(scenes.curtain())
    cfg = scenes.config("curtain")
    res = dm.TimeStepper(model, cfg.dt).run(model.initial_state(), t_end=2.0)
    g = model.grid(res.state.X)
    assert res.status == "finished"
    assert g[:, -1, 0].max() < 0.7 * cfg.size[0], "the rail nodes are drawn together"
    assert np.ptp(g[..., 1]) > 0.2, "the sheet folds out of its plane"
    model = FDModel(scenes.flag())
    ys = []
    res = dm.TimeStepper(model, scenes.SCENES["flag"].dt).run(
        model.initial_state(), t_end=2.0, trackers=[dm.Callback(lambda s: ys.append(model.grid(s.X)[-1, :, 1].mean()), 50)])
    assert res.status == "finished"
    ys = np.array(ys[10:])
    assert np.sum(np.diff(np.sign(ys - ys.mean())) != 0) >= 2, "the free edge swings back and forth"
