"""The scenes of the paper's section 5 and scene files (deformable.scenes)."""

import numpy as np
import pytest

import deformable as dm
from deformable import scenes
from fdmodel import FDModel


@pytest.mark.parametrize("name", list(scenes.SCENES))
def test_each_scene_builds_with_the_energy_consistent_model_and_full_tensors(name):
    spec = scenes.SCENES[name]
    scene = spec(nodes=(12, 10))
    assert isinstance(scene, dm.Scene) and scene.sheet.nodes == (12, 10) and scene.name == name
    assert scene.force_model == "variational"
    cfg = spec.config()
    eta = scene.material.eta
    if cfg.fabric:  # the curtains: a named fabric's full tensors, warp and weft, its warp's in the fields
        f_eta, f_xi = cfg.named_fabric().weights("variational")
        np.testing.assert_array_equal(eta, f_eta)
        np.testing.assert_array_equal(scene.material.xi, f_xi)
        assert eta[0, 0] == cfg.eta and scene.material.xi[0, 0] == cfg.xi > 0 and eta[0, 1] > 0
    else:
        assert eta[0, 1] == eta[1, 0] == cfg.shear * cfg.eta == eta[0, 0] and scene.material.xi[0, 1] == cfg.xi > 0


def test_the_curtains_are_named_fabrics_on_the_grids_that_resolve_them():
    """curtain in denim, curtain-silky in the lightest measured fabric, paper in paper, stiffer in stretching and
    bending than every fabric preset; each ships on the grid its fabric's folds ask for (CurtainConfig.shipped_nodes),
    and is resolved there by params' rule."""
    from deformable.scenes.params import parameters

    fabrics = {n: dm.Fabric.preset(n) for n in dm.Fabric.presets()}
    cloth = {n: f for n, f in fabrics.items() if n != "paper"}
    expect = {"curtain": "denim", "curtain-silky": min(cloth, key=lambda n: cloth[n].density), "paper": "paper"}
    for name, fabric in expect.items():
        cfg = scenes.config(name)
        assert cfg.fabric == fabric and cfg.scale == 1 and cfg.nodes == cfg.shipped_nodes()
        assert parameters(cfg, FDModel(scenes.build(cfg)), "fd").resolved
    paper = fabrics["paper"]
    for f in cloth.values():
        assert np.all(np.asarray(paper.bending) > np.max(f.bending)) and np.all(
            np.asarray(paper.tensile) > np.max(f.tensile))


@pytest.mark.parametrize("name", list(scenes.SCENES))
@pytest.mark.parametrize("force_model", ["variational", "tpbf87"])
def test_each_scene_takes_steps_under_both_force_models(name, force_model):
    """The default (variational, implicit Euler at the scene's dt) and the paper's force at half its stable step."""
    cfg = scenes.config(name, nodes=(10, 10), force_model=force_model)
    if force_model == "tpbf87" and cfg.contact is not None:  # the paper's scheme takes the paper's obstacle force
        with pytest.raises(ValueError, match="exponential"):
            dm.TimeStepper(FDModel(scenes.build(cfg)), 0.5 * FDModel(scenes.build(cfg)).stable_step())
        cfg = cfg.replace(contact={"method": "exponential"})
    model = FDModel(scenes.build(cfg))
    dt = min(cfg.dt, 0.5 * model.stable_step())
    result = dm.TimeStepper(model, dt).run(model.initial_state(), steps=10)
    assert result.status == "finished", result.message
    assert np.all(np.isfinite(result.state.X))


def test_module_functions_match_the_registry():
    for name, fn in [("hanging", scenes.hanging), ("curtain", scenes.curtain), ("curtain-silky", scenes.curtain_silky),
                     ("paper", scenes.paper), ("flag", scenes.flag), ("floor", scenes.floor), ("sphere", scenes.sphere),
                     ("drape", scenes.drape)]:
        assert fn(nodes=(8, 8)).name == name
    for name, fn in [("curtain", scenes.curtain), ("curtain-silky", scenes.curtain_silky), ("paper", scenes.paper)]:
        cfg = scenes.config(name)
        assert fn(nodes=(8, 8)).material.mu == cfg.scale * cfg.mu and fn().sheet.nodes == cfg.nodes


@pytest.mark.parametrize("name", ["curtain", "curtain-silky", "paper"])
def test_the_curtains_ship_on_grids_that_resolve_their_bending_length(name):
    """The fold scale (D H / (mu g))^(1/4) spans at least 3 grid spacings on the grid a curtain ships on (the
    folds themselves, 5-6 times it, are wider still; a limp cloth's folds on a coarse grid follow the grid)."""
    cfg = scenes.config(name)
    h = cfg.size[0] / (cfg.nodes[0] - 1)
    assert scenes.fold_wavelength(cfg.xi, cfg.mu, cfg.g, cfg.size[1], cfg.scale) >= 3 * h


def test_scale_multiplies_mu_gamma_and_the_forces_and_the_motion_is_the_softer_sheets():
    """Section 3.1: (s mu, s gamma, s f) with (eta, xi) moves like (mu, gamma, f) with (eta / s, xi / s)."""
    s = 20.0
    flag = scenes.flag(nodes=(8, 6), scale=s)
    plain = scenes.flag(nodes=(8, 6))
    coil, coil0 = (next(f for f in sc.forces if isinstance(f, dm.Spring)) for sc in (flag, plain))
    wind, wind0 = (next(f for f in sc.forces if isinstance(f, dm.Wind)) for sc in (flag, plain))
    assert coil.stiffness == s * coil0.stiffness and wind.coefficient == s * wind0.coefficient
    assert flag.material.gamma == s * plain.material.gamma
    assert "eta = 1 N/m" in scenes.config("flag", scale=s).scaling()
    runs = []
    for cfg in (scenes.config("hanging", nodes=(7, 7), scale=s),
                scenes.config("hanging", nodes=(7, 7), eta=50.0 / s, xi=1e-5 / s)):
        model = FDModel(scenes.build(cfg))
        runs.append(dm.TimeStepper(model, 5e-3, newton={"rtol": 1e-12}).run(model.initial_state(), steps=20).state.X)
    np.testing.assert_allclose(runs[0], runs[1], rtol=0, atol=1e-9)


def test_curtain_top_keeps_its_height_and_its_drawn_end_travels_the_gathered_width():
    cfg = scenes.config("curtain", nodes=(10, 8))
    model = FDModel(scenes.build(cfg))
    fx, fy, fz = (set(map(int, f)) for f in model.fixed_dofs())
    top = {m * 8 + 7 for m in range(10)}
    ends = {7, 9 * 8 + 7}
    assert top <= fz and fx & top == fy & top == ends  # the rod holds the height; rings slide and swing out
    X0 = model.initial_state()
    for t, travel in ((0.0, 0.0), (cfg.draw_time / 2, 0.5), (cfg.draw_time, 1.0), (2 * cfg.draw_time, 1.0)):
        x = model.prescribed(X0, t)[9 * 8 + 7, 0]
        assert x == pytest.approx(cfg.size[0] * (1 - cfg.gather * travel), abs=1e-12)


def test_the_curtains_rings_carry_the_top_together_uniformly_and_let_it_swing_along_y():
    cfg = scenes.config("curtain", nodes=(10, 8), rings=1)
    model = FDModel(scenes.build(cfg))
    fx, fy, fz = (set(map(int, f)) for f in model.fixed_dofs())
    top = [m * 8 + 7 for m in range(10)]
    assert set(top) <= fx & fz and not set(top) & fy
    X0 = model.initial_state()
    X = model.prescribed(X0, cfg.draw_time)
    np.testing.assert_allclose(X[top, 0], X0[top, 0] * (1 - cfg.gather), atol=1e-12)
    hooks = scenes.hook_nodes(cfg.replace(hooks=0.25))  # h = 1/9 m: every second node, and the last
    assert hooks.tolist() == [0, 2, 4, 6, 8, 9]
    fx, fy, fz = (set(map(int, f)) for f in FDModel(scenes.build(cfg.replace(hooks=0.25))).fixed_dofs())
    assert fx & set(top) == {m * 8 + 7 for m in hooks} and set(top) <= fz and not fy & set(top)
    with pytest.raises(ValueError, match="rings must be 0"):
        scenes.config("curtain", rings=2)


def test_the_curtains_ripple_is_the_same_function_on_both_backends_and_has_its_rms():
    from femodel import FEModel

    cfg = scenes.config("curtain", nodes=(40, 9), noise=2e-3, seed=7)
    fd, fe = FDModel(scenes.build(cfg)), FEModel(scenes.build(cfg))
    np.testing.assert_array_equal(fd.initial_state(), fe.grid(fe.initial_state()).reshape(-1, 3))
    y = fd.grid(fd.initial_state())[:, 0, 1]
    assert 1e-3 < np.sqrt(np.mean(y**2)) < 4e-3
    again = scenes.config("curtain", nodes=(40, 9), noise=2e-3, seed=8)
    assert not np.allclose(FDModel(scenes.build(again)).initial_state(), fd.initial_state())
    noise = scenes.FoldNoise(1.0, 1e-3, 3)
    a1, a2, e = np.linspace(0.0, 1.0, 7), np.full(7, 0.4), 1e-6
    np.testing.assert_allclose(noise.r1(a1, a2), (noise.r(a1 + e, a2) - noise.r(a1 - e, a2)) / (2 * e), atol=1e-8)


def test_a_rest_curvature_curls_the_sheet_into_its_cylinder():
    scene = scenes.hanging(nodes=(9, 9), rest_curvature=(2.0, 0.0))
    np.testing.assert_array_equal(scene.rest_curvature, np.diag([2.0, 0.0]))
    model = FDModel(scene)
    e = model.energy(model.initial_state())  # flat: bent away from its rest curvature
    assert e.bending > 0 and e.stretching == 0


def test_equivalent_weights_match_the_linearised_stiffness_and_invert():
    assert scenes.equivalent_weights(20.0, 1e-5) == (5.0, 5e-6)
    assert scenes.equivalent_weights(*scenes.equivalent_weights(20.0, 1e-5), "variational", "tpbf87") == (20.0, 1e-5)
    assert scenes.equivalent_weights(3.0, 2.0, "frozen", "tpbf87") == (3.0, 2.0)
    with pytest.raises(ValueError, match="force model"):
        scenes.equivalent_weights(1.0, 1.0, "paper")


def test_fold_wavelength_scales_as_the_fourth_root_of_the_bending_stiffness():
    w = [scenes.fold_wavelength(xi, 0.2, 9.81, 1.2) for xi in (1e-5, 16e-5)]
    assert w[1] / w[0] == pytest.approx(2.0)
    assert scenes.fold_wavelength(1e-5, 0.2, 9.81, 1.2, scale=16.0) == pytest.approx(w[0] / 2)
    assert scenes.fold_wavelength(2e-5, 0.2, 9.81, 1.2, force_model="tpbf87") == pytest.approx(w[0])


def test_toml_overrides_a_named_scene_and_round_trips(tmp_path):
    path = tmp_path / "c.toml"
    path.write_text('scene = "curtain"\nfabric = ""\neta = 30.0\nnodes = [20, 24]\n'
                    'rest_metric = [0.9, 1.0]\nseed = 4\n')
    cfg = scenes.read_toml(path)
    assert cfg.scene == "curtain" and cfg.eta == 30.0 and cfg.nodes == (20, 24) and cfg.rest_metric == (0.9, 1.0)
    assert cfg.seed == 4 and cfg.gather == scenes.config("curtain").gather
    again = tmp_path / "again.toml"
    again.write_text(scenes.to_toml(cfg))
    assert scenes.read_toml(again) == cfg
    assert scenes.build(cfg).sheet.nodes == (20, 24)
    # overrides (the command line's values) win over the file's, also for a key the file sets
    assert scenes.read_toml(path, nodes=(6, 5), dt=0.01).nodes == (6, 5)


@pytest.mark.parametrize("text, message", [
    ('scene = "curtain"\netaa = 3.0\n', "unknown key 'etaa'"),
    ('scene = "flag"\npush = 3.0\n', "unknown key 'push'"),
    ('scene = "tablecloth"\n', "unknown scene 'tablecloth'"),
    ('eta = 3.0\n', "must name its scene"),
    ('scene = "flag"\neta = "stiff"\n', "eta must be a finite number"),
    ('scene = "flag"\nnodes = [2.5, 3]\n', "nodes must be two ints"),
    ('scene = "flag"\ndt = 0.0\n', "dt must be positive"),
    ('scene = "flag"\nshear = 1.5\n', "shear must lie in"),
    ('scene = "flag"\nrest_curvature = [1.0]\n', "rest_curvature must be two floats"),
    ('scene = "flag"\nrest_curvature = [inf, 0.0]\n', "rest_curvature must be two floats"),
    ('scene = "curtain"\nseed = 1.5\n', "seed must be an integer"),
    ('scene = "curtain"\ngather = 1.0\n', "gather must lie in"),
    ('scene = "flag"\ncoil = -1.0\n', "coil must be non-negative"),
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
    cfg = scenes.config("curtain")
    model = FDModel(scenes.build(cfg))
    res = dm.TimeStepper(model, cfg.dt).run(model.initial_state(), t_end=cfg.t_end)
    g = model.grid(res.state.X)
    assert res.status == "finished"
    assert np.ptp(g[:, -1, 0]) == pytest.approx((1 - cfg.gather) * cfg.size[0], rel=0.05), "the top is drawn together"
    assert np.ptp(g[..., 1]) > 0.1, "the sheet folds out of its plane"
    cfg = scenes.config("flag")
    model = FDModel(scenes.build(cfg))
    ys = []
    res = dm.TimeStepper(model, cfg.dt).run(
        model.initial_state(), t_end=cfg.t_end, trackers=[dm.Callback(lambda s: ys.append(model.grid(s.X)[-1, :, 1].mean()), 5)])
    assert res.status == "finished"
    ys = np.array(ys[len(ys) // 2:])
    assert np.sum(np.diff(np.sign(ys - ys.mean())) != 0) >= 4, "the free edge swings back and forth"


def test_the_drape_holds_the_cloth_at_four_contact_points_per_cell_side():
    """The rim holds the cloth where it is, not at the nearest node (the drape's convergence, reports/contact)."""
    from deformable.contact.points import contact_points
    from validation.harness.backends import make_model

    cfg = scenes.config("drape", nodes=(5, 5))
    assert cfg.contact.samples == 4 and scenes.config("sphere").contact.samples is None
    for backend in ("fd", "fe"):
        assert contact_points(make_model(scenes.build(cfg), backend)).P == 17 * 17
