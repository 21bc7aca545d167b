"""A run as one object (:class:`deformable.Simulation`): on both backends by name, with and without an output
folder, resumed bit for bit, and refusing what cannot run before anything is written."""

import numpy as np
import pytest

import deformable as dm
from deformable import scenes
from deformable.backends.registry import Discretisation
from deformable.session import Simulation


def test_the_simulation_is_the_core_s_and_the_package_s():
    assert dm.Simulation is Simulation


@pytest.mark.parametrize("backend, nodes", [("fd", (8, 8)), ("fe", (5, 5))])
def test_a_scene_runs_on_each_backend_by_name(backend, nodes):
    cfg = scenes.config("hanging", nodes=(8, 8))
    sim = Simulation(cfg, backend=backend)
    assert sim.config.nodes == nodes  # FE takes the scene's FD grid as half as many elements a side
    result = sim.run(t_end=0.02)
    assert result.status == "finished" and result.state.t == pytest.approx(0.02, abs=1e-12)
    assert np.all(np.isfinite(result.state.X)) and result.state.X.shape == (sim.model.ndof, 3)
    # the lowest point fell: gravity pulls the free edge of the hanging sheet down
    assert result.state.X[:, 2].min() < sim.X0[:, 2].min()


def test_the_backends_are_found_through_their_entry_points():
    from importlib.metadata import entry_points

    declared = {p.name for p in entry_points(group="deformable.backends")}
    assert {"fd", "fe"} <= declared and {"fd", "fe"} <= set(Discretisation.names())


def test_an_unknown_backend_is_one_input_error_naming_the_known_ones():
    with pytest.raises(dm.InputError, match="unknown backend 'fx'; choose one of fd, fe"):
        Simulation("hanging", backend="fx")
    with pytest.raises(dm.InputError, match="scene config"):
        Simulation(3.0)


def test_the_step_is_the_scene_s_within_half_the_backend_s_bound():
    cfg = scenes.config("hanging", nodes=(8, 8), force_model="tpbf87", dt=10.0)
    sim = Simulation(cfg, "fd")
    assert 0 < sim.config.dt <= 0.5 * sim.model.stable_step()
    assert Simulation(cfg, "fd", dt=10.0).config.dt == 10.0  # a step the caller set is taken as is


def test_a_run_with_an_output_folder_resumes_as_the_uninterrupted_run(tmp_path):
    cfg = scenes.config("hanging", nodes=(8, 8))
    whole = Simulation(cfg, "fd", out=tmp_path / "whole")
    whole.run(steps=4, every=0.01, checkpoint_every=2)
    assert [p.name for p in whole.checkpoints] == ["hanging-checkpoint-0000002.npz", "hanging-checkpoint-0000004.npz"]
    assert (tmp_path / "whole" / "hanging.toml").is_file() and whole.series.frames >= 2
    half = Simulation(cfg, "fd", out=tmp_path / "whole", overwrite=True).resume(whole.checkpoints[0])
    result = half.run(steps=4, every=0.01)
    assert result.state.step == 4 and np.array_equal(result.state.X, whole.result.state.X)


def test_what_cannot_run_is_refused_before_anything_is_written(tmp_path):
    sim = Simulation(scenes.config("hanging", nodes=(8, 8)), "fd", out=tmp_path / "out")
    with pytest.raises(dm.InputError, match="t = 0 s"):
        sim.prepare(t_end=-1.0)
    assert not (tmp_path / "out").exists()
    with pytest.raises(dm.InputError, match="does not fit the run asked for: eta"):
        done = Simulation(scenes.config("hanging", nodes=(8, 8)), "fd", out=tmp_path / "a")
        done.run(steps=2, checkpoint_every=2)
        Simulation(scenes.config("hanging", nodes=(8, 8), eta=3.0), "fd").resume(done.checkpoints[0])


def _hammock():
    return dm.Scene(dm.Sheet(size=(1.0, 1.0), nodes=(6, 6)), dm.Material(mu=0.1, eta=50.0, xi=1e-3, gamma=0.05),
                    forces=[dm.Gravity()], constraints=[dm.Pin(["top-left", "top-right"])], force_model="variational")


def test_a_scene_built_by_hand_runs_as_the_stepper_runs_it():
    scene = _hammock()
    sim = Simulation(scene, "fe", dt=0.01)
    result = sim.run(t_end=0.05)
    model = sim.descriptor.build(scene)
    alone = dm.TimeStepper(model, 0.01).run(model.initial_state(), t_end=0.05)
    assert sim.config is None and np.array_equal(result.state.X, alone.state.X)


@pytest.mark.parametrize("kwargs, field", [(dict(), "dt"), (dict(dt=0.01, nodes=(4, 4)), "nodes"),
                                           (dict(dt=0.01, out="x"), "out")])
def test_a_scene_built_by_hand_refuses_what_it_cannot_take(kwargs, field):
    with pytest.raises(dm.InputError) as err:
        Simulation(_hammock(), "fd", **kwargs)
    assert err.value.field == field
    with pytest.raises(dm.InputError, match="t_end"):
        Simulation(_hammock(), "fd", dt=0.01).run()
