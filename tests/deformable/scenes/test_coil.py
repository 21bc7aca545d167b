"""The ``coil`` scene (deformable.scenes.strip): a strip dropped end first onto the floor folds onto itself. At every
step of its fall (FD 31 x 3 nodes, the first 0.3 s) the strip never passes through itself, no two of its faces come
closer than its thickness and it never reaches the floor; and it does touch itself (the self-contact barrier is
active at some step: two parts of the strip within the thickness plus the activation distance), so that the checks
are not passed by a strip that never folded."""

import math

import numpy as np
import pytest

import deformable as dm
from deformable import scenes
from deformable.contact.selfmesh import ContactMesh
from fdmodel import FDModel


@pytest.mark.slow  # a whole pipeline (Dask, a real window, a long run): pytest -m slow
def test_the_strip_folds_onto_itself_never_crossing_itself_nor_the_floor():
    cfg = scenes.config("coil", nodes=(31, 3), t_end=0.3)
    scene = scenes.build(cfg)
    own = scene.contact
    assert own.self_distance > 0 and own.thickness > 0
    model = FDModel(scene)
    mesh = ContactMesh(model, own.self_distance, thickness=own.thickness)
    reach = own.thickness + own.self_distance
    top = np.max(model.initial_state()[:, 2])
    times, crossed, distances, clearances = [], [], [], []

    def record(s):
        times.append(s.t)
        crossed.append(mesh.intersects(s.X))
        distances.append(mesh.self_distance(s.X, 3 * reach))
        clearances.append(dm.clearance(model, s.X))

    result = dm.TimeStepper(model, cfg.dt).run(model.initial_state(), t_end=cfg.t_end, trackers=[dm.Callback(record)])
    assert result.status == "finished", result.message
    assert len(times) == result.steps and math.isclose(times[-1], cfg.t_end)
    d = np.array(distances)
    assert not any(crossed), f"the strip crossed itself at t = {[t for t, c in zip(times, crossed) if c]}"
    assert np.min(d) > own.thickness, f"two faces {np.min(d):.3g} m apart at t = {times[int(np.argmin(d))]:.3g} s"
    assert min(clearances) > 0
    # measured: within reach in 29 of the 60 steps, from t = 0.16 s; the closest two faces 0.97 mm apart
    assert np.any(d < reach), f"the strip never touched itself (no two faces within {reach:.3g} m)"
    # it fell: its top has come down to below two thirds of its start (0.27 of 0.60 m when measured)
    assert np.max(result.state.X[:, 2]) < 2 / 3 * top
