"""Frames on their requested times (issue 46): ``XDMFWriter(interval=0.1)`` writes states of the run at 0.1, 0.2, ...

The writer asks the stepper for its next frame time (``Tracker.next_time``) and :meth:`deformable.TimeStepper.run`
shortens the step that would pass it, as it shortens the last step before ``t_end``
(:mod:`deformable.dynamics.stepper`). Before, with dt = 0.011 s the frames fell on the first step past each
multiple: 0.11, 0.209, 0.308 s.
"""

import xml.etree.ElementTree as ET

import h5py
import numpy as np
import pytest

import deformable as dm
from deformable import scenes
from validation.harness.backends import make_model

INTERVAL = 0.1


def _run(backend, dt, t_end, path=None, force_model=None, nodes=(8, 8), **kw):
    """The hanging cloth on ``nodes`` run to ``t_end`` (s) with an XDMFWriter at ``path`` (or none); returns
    (result, stepper, {step: t} of every state the run went through)."""
    fields = {} if force_model is None else {"force_model": force_model}
    model = make_model(scenes.hanging(nodes=nodes, **fields), backend)
    stepper = dm.TimeStepper(model, dt)
    times = {}
    trackers = [dm.Callback(lambda s: times.__setitem__(s.step, s.t))]
    if path is not None:
        trackers.insert(0, dm.XDMFWriter(path, interval=INTERVAL))
    result = stepper.run(model.initial_state(), t_end=t_end, trackers=trackers, **kw)
    return result, stepper, times


def _frames(path):
    """(step, time (s), kind, positions (M N, 3)) of each frame of the series at ``path``, read from its files."""
    out = []
    with h5py.File(path.with_suffix(".h5"), "r") as h5:
        for g in ET.parse(path).getroot().iter("Grid"):
            if g.get("GridType") != "Uniform":
                continue
            item = g.find("Geometry/DataItem").text.split(":/")[-1]
            out.append((int(g.get("Name")[len("step"):]), float(g.find("Time").get("Value")),
                        g.find("Information[@Name='frame']").get("Value"), h5[item][()]))
    return out


@pytest.mark.parametrize("backend, force_model, dt", [
    ("fd", None, 0.011),        # implicit Euler (adaptive), 9 steps of 0.011 s and one of 0.001 s a frame
    ("fe", None, 0.011),
    ("fd", "tpbf87", 0.0011),   # the semi-implicit scheme (fixed dt): 90 steps and one of 0.001 s a frame
])
def test_frames_are_on_the_multiples_of_the_interval_when_dt_does_not_divide_it(tmp_path, backend, force_model, dt):
    path = tmp_path / "hanging.xdmf"
    result, stepper, times = _run(backend, dt, 0.3, path, force_model)
    assert result.status == "finished"
    frames = _frames(path)
    assert [k for _, _, k, _ in frames] == ["first", "cadence", "cadence", "cadence"]
    for k, (step, t, _, _) in enumerate(frames):
        assert abs(t - k * INTERVAL) < 1e-12  # the time written
        assert abs((times[step] if step else 0.0) - k * INTERVAL) < 1e-12  # the state's own time
    assert np.count_nonzero(np.abs(stepper.steps_taken - dt) > 1e-9 * dt) == 3  # one shortened step a frame


@pytest.mark.parametrize("backend, force_model, dt", [("fd", None, 0.011), ("fd", "tpbf87", 0.0011)])
def test_a_frame_is_a_state_of_the_run_not_an_interpolation(tmp_path, backend, force_model, dt):
    """The frame at 0.1 s holds the positions a run to t_end = 0.1 s without a writer ends on, bit for bit."""
    path = tmp_path / "hanging.xdmf"
    _run(backend, dt, 0.3, path, force_model)
    step, t, kind, P = _frames(path)[1]
    end, stepper, _ = _run(backend, dt, INTERVAL, force_model=force_model)
    assert (step, t, kind) == (end.state.step, INTERVAL, "cadence")
    np.testing.assert_array_equal(P, stepper.model.grid(end.state.X).reshape(-1, 3))


@pytest.mark.parametrize("backend, force_model, dt", [("fd", None, 0.005), ("fd", "tpbf87", 1e-3)])
def test_a_run_whose_dt_divides_the_interval_takes_the_same_steps_bit_for_bit(tmp_path, backend, force_model, dt):
    path = tmp_path / "hanging.xdmf"
    written, with_writer, _ = _run(backend, dt, 0.3, path, force_model)
    plain, without, _ = _run(backend, dt, 0.3, force_model=force_model)
    assert written.steps == plain.steps == round(0.3 / dt)
    np.testing.assert_array_equal(with_writer.steps_taken, without.steps_taken)
    np.testing.assert_array_equal(written.state.X, plain.state.X)
    np.testing.assert_array_equal(written.state.V, plain.state.V)
    assert [round(t / INTERVAL) for _, t, _, _ in _frames(path)] == [0, 1, 2, 3]


def test_a_resumed_run_lands_on_the_same_frame_times_and_state(tmp_path):
    """Where a step is shortened follows from the state and the frame times alone: a run resumed between two
    frames (dt = 0.011 s, the state at step 14, t = 0.144 s) ends on the uninterrupted run's state."""
    model = make_model(scenes.hanging(nodes=(8, 8)), "fd")
    stepper = dm.TimeStepper(model, 0.011)
    kept = {}

    def keep(state):
        if state.step == 14:
            kept.update(state=state, memory=stepper.memory())

    X0 = model.initial_state()
    whole = stepper.run(X0, t_end=0.3, trackers=[dm.XDMFWriter(tmp_path / "a.xdmf", interval=INTERVAL),
                                                  dm.Callback(keep)])
    again = dm.TimeStepper(model, 0.011)
    again.restore(kept["memory"])
    resumed = again.run(X0, t_end=0.3, resume=kept["state"],
                        trackers=[dm.XDMFWriter(tmp_path / "b.xdmf", interval=INTERVAL, reference=X0)])
    np.testing.assert_array_equal(resumed.state.X, whole.state.X)
    a, b = _frames(tmp_path / "a.xdmf"), _frames(tmp_path / "b.xdmf")
    assert [f[:2] for f in b[1:]] == [f[:2] for f in a[2:]]  # (step, time) of the frames at 0.2 and 0.3 s
    np.testing.assert_array_equal(b[-1][3], a[-1][3])
