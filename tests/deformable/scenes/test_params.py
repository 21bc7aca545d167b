"""A scene's parameters as the paper groups them (deformable.scenes.parameters, ``deformable params``)."""

import math

import numpy as np
import pytest

import deformable as dm
from deformable import scenes
from deformable.scenes import parameters
from validation.commands import main
from validation.harness.backends import make_model


def _params(name, backend="fd", **fields):
    cfg = scenes.config(name, **fields)
    return cfg, parameters(cfg, make_model(scenes.build(cfg), backend), backend)


def test_scale_multiplies_the_macro_group_and_leaves_the_micro_group():
    cfg, p = _params("curtain-silky", scale=20.0, nodes=(16, 16))
    macro = {q.name: q for q in p.macro}
    assert cfg.scale == 20 and macro["mu"].used == pytest.approx(20 * macro["mu"].real)
    assert macro["f"].real == pytest.approx(cfg.mu * cfg.g) and macro["f"].used == pytest.approx(20 * cfg.mu * cfg.g)
    assert [(q.name, q.real, q.used) for q in p.micro] == [("eta", cfg.eta, cfg.eta), ("xi", cfg.xi, cfg.xi)]
    assert f"eta = {cfg.eta / 20:.4g} N/m" in p.scaling and "in the simulation" in "\n".join(p.lines())


def test_the_weights_are_the_material_koiter_maps_them_to_at_nu_0():
    """Koiter at nu = 0 is eq. (13) with eta = E h / 8, xi = E h^3 / 24 (docs/design.md): the same stiffness."""
    E, h = 2e5, 1e-3
    _, p = _params("hanging", nodes=(9, 9), eta=E * h / 8, xi=E * h**3 / 24)
    cfg = scenes.config("hanging", nodes=(9, 9))
    koiter = dm.Scene(scenes.build(cfg).sheet, scenes.build(cfg).material, force_model=dm.Koiter(E=E, nu=0.0, h=h))
    k = parameters(cfg, make_model(koiter, "fd"), "fd")
    assert p.stiffness == pytest.approx((E * h, E * h**3 / 12)) and k.stiffness == pytest.approx(p.stiffness)
    assert [q.name for q in k.micro] == ["E", "nu", "h"]


@pytest.mark.parametrize("backend", ["fd", "fe"])
def test_the_semi_implicit_step_is_the_lagged_alpha_bound_and_diverges_above_it(backend):
    cfg, p = _params("hanging", backend, nodes=(9, 9), force_model="tpbf87")
    h = min(p.spacing)
    if backend == "fd":  # h sqrt(mu / (2 eta G)), G = 1 at rest (eq. (25) lags alpha)
        assert p.semi_implicit_step == pytest.approx(h * math.sqrt(cfg.mu / (2 * cfg.eta)), rel=1e-12)
    assert p.own_step == p.semi_implicit_step
    for factor, bounded in ((0.5, True), (3.0, False)):
        scene = scenes.build(cfg.replace(dt=factor * p.semi_implicit_step))
        model = make_model(scene, backend)
        stepper = dm.TimeStepper(model, factor * p.semi_implicit_step, scheme="semi-implicit")
        result = stepper.run(model.initial_state(), steps=400)
        assert (result.status == "finished" and np.all(np.isfinite(result.state.X))) == bounded, result.status


def test_the_folds_length_scale_says_whether_they_are_resolved():
    cfg, coarse = _params("flag", nodes=(16, 16))
    assert coarse.fold_scale == pytest.approx(scenes.fold_wavelength(cfg.xi, cfg.mu, cfg.g, cfg.size[1], cfg.scale),
                                              rel=1e-12)
    assert coarse.bending_length == pytest.approx((2 * cfg.xi / (cfg.mu * cfg.g)) ** (1 / 3), rel=1e-12)
    _, fine = _params("flag", nodes=(80, 80))  # l_f 5.3 grid spacings (on 64 x 64: 4.2, below the rule's 4.5)
    assert not coarse.resolved and fine.resolved
    assert "NOT resolved" in "\n".join(coarse.lines()) and "NOT resolved" not in "\n".join(fine.lines())


def test_the_command_prints_the_groups_and_refuses_bad_input_in_one_line(capsys):
    assert main(["params", "paper", "scale=1", "--grid", "12x12"]) == 0
    out = capsys.readouterr().out
    assert out.startswith("paper: 12 x 12 nodes on fd") and "macro-control" in out and "micro-control" in out
    assert "scale 1: mu, gamma and the forces are the real-world values" in out
    for argv, message in ((["params", "curtain", "scale=-1"], "scale"), (["params", "tablecloth"], "tablecloth"),
                          (["params", "curtain", "--backend", "fem"], "unknown backend 'fem'")):
        assert main(argv) == 2
        err = capsys.readouterr()
        assert len(err.err.strip().splitlines()) == 1 and message in err.err and not err.out


def test_run_prints_them_at_its_start(tmp_path, capsys):
    assert main(["run", "hanging", "--grid", "6x6", "--steps", "2", "--out", str(tmp_path)]) == 0
    out = capsys.readouterr().out
    assert out.startswith("hanging: 6 x 6 nodes on fd") and "stable step of the semi-implicit scheme" in out
