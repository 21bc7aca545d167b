"""``deformable view`` (validation/viewer.py): a slider retunes the running simulation; the simulation's frames,
in turn or in a thread of its own; the readout's test at most every READOUT_EVERY; the window under Xvfb."""

import math
import os
import threading
import time

import numpy as np
import pytest

import deformable as dm
from deformable import scenes
from validation import viewer
from validation.commands import main
from validation.viewer import Producer, Session


def _session(**fields):
    return Session(scenes.config("hanging", nodes=(8, 8), **fields), "fd")


def test_a_changed_parameter_changes_the_motion_from_the_same_state():
    a, b = _session(), _session()
    a.advance(0.2)
    b.advance(0.2)
    X, t = b.state.X.copy(), b.state.t
    b.set(xi=30 * b.value("xi"))  # a slider moved: the material changes, the state does not
    assert b.state.t == t and np.array_equal(b.state.X, X) and b.value("xi") == 30 * a.value("xi")
    a.advance(0.3)
    b.advance(0.3)
    assert a.state.t == pytest.approx(b.state.t)
    assert np.max(np.abs(a.points() - b.points())) > 1e-3  # m: the stiffer sheet moves otherwise
    b.reset()
    assert b.state.t == 0.0 and b.value("xi") == a.value("xi")


def test_a_slider_retunes_the_running_stepper_and_keeps_its_solver():
    """The same stepper and Newton solver take the new material (TimeStepper.retune) and go on from the same state,
    moving as a stepper built for the new material would."""
    s = _session()
    s.advance(0.2)
    stepper, newton, model = s.stepper, s.stepper.newton, s.model
    state = s.state
    s.set(eta=4 * s.value("eta"))
    assert s.stepper is stepper and s.stepper.newton is newton and newton is not None
    assert s.model is not model and stepper.model is s.model
    assert np.all(s.model.scene.material.eta == 4 * np.asarray(model.scene.material.eta))
    assert s.state is state
    fresh = dm.TimeStepper(s.model, stepper.dt)
    fresh.start(stepper.reference)
    b = state
    for _ in range(20):
        b = fresh.step(b)
    s.advance(0.1)
    assert s.state.t == pytest.approx(b.t)
    assert np.max(np.abs(s.state.X - b.X)) <= 20 * 1e-2 * stepper.dt  # Newton's tolerance, vtol dt a step
    assert np.max(np.abs(s.state.X - state.X)) > 1e-3  # m: it moved


def test_the_readout_reuses_its_compatibility_test_and_says_when_it_was_taken(monkeypatch):
    calls = []  # two a test: the state at h and at 2h
    monkeypatch.setattr(viewer, "check_compatibility", lambda *a: calls.append(1) or _compatibility(*a))
    s = _session()
    first = s.readout(every=0.2)
    s.advance(0.1)
    reused = s.readout(every=0.2)  # 0.1 s later: the test at t = 0 shown as such
    assert len(calls) == 2 and reused.tested_at == 0.0 and reused.t == pytest.approx(0.1)
    assert (reused.mismatch, reused.mismatch_2h) == (first.mismatch, first.mismatch_2h)
    assert "the state (at t = 0.000 s): a surface" in reused.text() and reused.kinetic > first.kinetic
    s.advance(0.15)
    fresh = s.readout(every=0.2)  # 0.25 s on: taken anew, on this state
    assert len(calls) == 4 and fresh.tested_at == fresh.t and "the state: a surface" in fresh.text()
    assert s.readout() == fresh and len(calls) == 6  # every = 0: always anew (the same numbers, the same state)
    s.reset()
    assert s.readout(every=0.2).tested_at == 0.0 and len(calls) == 8  # not a test from before the reset


def _compatibility(*args):
    from deformable.geometry import check_compatibility

    return check_compatibility(*args)


def test_frames_in_turn_sit_at_the_frame_times_and_take_commands_at_once(monkeypatch):
    calls = []
    monkeypatch.setattr(viewer, "check_compatibility", lambda *a: calls.append(1) or _compatibility(*a))
    p = Producer(_session(), fps=30, readout_every=0.2)
    stepper = p.session.stepper
    for k in range(1, 31):
        assert p.produce()
        assert p.latest.serial == k and p.latest.readout.t == pytest.approx(k / 30, abs=5e-3)  # 5 ms steps
    assert p.latest.readout.t == pytest.approx(1.0)  # 30 frames: a simulated second (not 30 x 7 steps)
    assert 10 <= len(calls) <= 12  # t = 0 and then every 0.2 s or so of the 1 s, at h and 2h: not 62
    gamma = p.session.value("gamma")
    p.submit("set", "gamma", 30 * gamma)  # no thread: applied at once, and a frame says so
    assert p.latest.values["gamma"] == 30 * gamma and p.session.stepper is stepper
    p.submit("pause", True)
    assert not p.produce() and p.session.state.t == pytest.approx(1.0)
    p.submit("pause", False)
    p.submit("reset")
    assert p.latest.readout.t == 0.0 and p.latest.values["gamma"] == gamma
    assert p.produce() and p.latest.readout.t == pytest.approx(1 / 30, abs=5e-3)
    again = Producer(_session(), fps=30)  # deterministic: the same frames
    for _ in range(31):
        again.produce()
    other = Producer(_session(), fps=30)
    for _ in range(31):
        other.produce()
    assert np.array_equal(again.latest.points, other.latest.points) and again.latest.readout == other.latest.readout


def _until(condition, timeout=30.0):
    start = time.perf_counter()
    while not condition():
        assert time.perf_counter() - start < timeout, "timed out"
        time.sleep(0.01)


def test_the_producer_thread_takes_commands_between_steps_paces_itself_and_stops():
    p = Producer(_session(), fps=30)
    stepper, gamma = p.session.stepper, p.session.value("gamma")
    before = threading.active_count()
    start = time.perf_counter()
    p.start()
    try:
        assert p.running and threading.active_count() == before + 1
        _until(lambda: p.latest.serial >= 3)
        p.submit("set", "gamma", 30 * gamma)
        _until(lambda: p.latest.values["gamma"] == 30 * gamma)
        assert p.session.stepper is stepper  # retuned in the thread, between two steps
        assert p.latest.readout.t <= time.perf_counter() - start + 0.2  # s: never ahead of the clock (a frame or two)
        p.submit("pause", True)
        _until(lambda: p.paused)
        t = p.session.state.t
        time.sleep(0.3)
        assert p.session.state.t == t  # no step while paused
        p.submit("pause", False)
        p.submit("reset")
        _until(lambda: p.latest.values["gamma"] == gamma)
        assert p.session.stepper is not stepper  # a reset builds anew
        _until(lambda: p.latest.readout.t > 0)
    finally:
        p.stop(timeout=30)
    assert not p.running and p.error is None and threading.active_count() == before


def test_the_readout_states_energy_stretch_and_the_compatibility_test():
    s = Session(scenes.config("hanging", nodes=(12, 12)), "fd")
    s.advance(0.1)
    r = s.readout()
    assert r.elastic > 0 and r.kinetic > 0 and 0 < r.stretch < 1 and r.rest == "compatible"
    assert r.mismatch >= 0 and r.mismatch_2h is not None and r.mismatch_2h >= 0 and not r.note
    assert "compatibility (eq. 10): rest state G0, B0 compatible" in r.text() and "largest stretch" in r.text()
    assert f"mismatch {r.mismatch:.3g} at h, {r.mismatch_2h:.3g} at 2h" in r.text()


def test_a_running_curtain_is_a_surface_and_a_rest_state_no_surface_has_is_incompatible():
    """The shipped curtain at 20 x 20 fails the paper's test at every deformed state (its folds unresolved,
    module docstring): its readout never calls it incompatible, and shows the test's own error instead. A rest
    curvature (2, 2) 1/m on the flat metric is no surface's: the readout says so, while the sheet runs."""
    p = Producer(Session(scenes.config("curtain", nodes=(20, 20)), "fd"), fps=10, readout_every=0.1)
    texts = []
    for _ in range(3):  # 0.3 s
        assert p.produce()
        texts.append(p.latest.readout.text())
        assert p.latest.readout.mismatch > 0.05  # the discrete test alone would call it incompatible
    assert all("INCOMPATIBLE" not in t and "rest state G0, B0 compatible" in t and "a surface" in t for t in texts)
    with pytest.warns(dm.IncompatibleRestState):
        s = Session(scenes.config("hanging", nodes=(12, 12), rest_curvature=(2.0, 2.0)), "fd")
    r = s.readout()
    assert r.rest.startswith("INCOMPATIBLE") and "rest state G0, B0 INCOMPATIBLE (no surface has them)" in r.text()


def test_offscreen_frames_write_a_screenshot_saying_how_far_they_are(tmp_path, capsys):
    png = tmp_path / "a.png"
    assert main(["view", "hanging", "--grid", "8x8", "--offscreen", "--frames", "3", "--screenshot", str(png)]) == 0
    out, err = capsys.readouterr()
    assert png.stat().st_size > 1000 and "3 frames" in out and "x real time" in out
    # a line each frame here (each a third of them), with an estimate from the second frame on (issue 47)
    said = [line.split(" ", 2)[2] for line in err.splitlines() if " hanging: " in line and " % (" in line]
    assert [line.split(", t = ")[0] for line in said] == [f"hanging: {p} % ({k} of 3 frames"
                                                         for p, k in ((33, 1), (67, 2), (100, 3))], err
    assert "left" not in said[0] and "left" in said[1] and "left" not in said[2]


@pytest.mark.parametrize("argv, message", [
    (["view", "hanging", "--offscreen"], "--offscreen needs --frames"),
    (["view", "hanging", "--fps", "0", "--offscreen", "--frames", "2"], "--fps must be positive"),
    (["view", "tablecloth", "--offscreen", "--frames", "2"], "unknown scene 'tablecloth'"),
])
def test_bad_input_is_one_line(argv, message, capsys):
    assert main(argv) == 2
    err = capsys.readouterr().err
    assert len(err.strip().splitlines()) == 1 and message in err


@pytest.fixture
def display(monkeypatch, request):
    """An X display for a real window: pytest-xvfb's virtual one (it starts Xvfb in each test process where Xvfb is
    installed; .ci/run installs it), else the desktop's (DISPLAY, e.g. under ``--no-xvfb``). Where there is neither,
    the test is skipped, saying why; .ci/run sets DEFORMABLE_TEST_DISPLAY=required, and there it fails instead.
    The window is an X window also after an off-screen test in this process (VTK's default window and pyvista's
    OFF_SCREEN put back)."""
    import pyvista

    xvfb = request.getfixturevalue("xvfb") if request.config.pluginmanager.hasplugin("xvfb") else None
    if xvfb is None and not os.environ.get("DISPLAY"):
        reason = ("no X display for a real window: no Xvfb on PATH for pytest-xvfb (Debian: apt-get install xvfb; "
                  ".ci/run installs it) and DISPLAY is not set")
        if os.environ.get("DEFORMABLE_TEST_DISPLAY") == "required":
            pytest.fail(reason)
        pytest.skip(reason)
    monkeypatch.delenv("VTK_DEFAULT_OPENGL_WINDOW", raising=False)
    monkeypatch.setattr(pyvista, "OFF_SCREEN", False)
    return os.environ["DISPLAY"]


@pytest.mark.slow  # a whole pipeline (Dask, a real window, a long run): pytest -m slow
def test_a_real_window_shows_a_moved_slider_changing_the_motion(display, tmp_path):
    """Frames in turn (``--frames``) in a real window. The damping moves the sheet visibly within 0.4 s; xi x 30
    does not (0.1 grey levels on the sheet: the readout's digits alone made the difference)."""
    from matplotlib.image import imread

    from validation.viewer import Window

    shots = {}
    for moved in (False, True):
        window = Window(_session(), offscreen=False, fps=30)
        assert not window.plotter.off_screen
        window.plotter.show(auto_close=False, interactive=False)
        for k in range(12):
            if moved and k == 3:
                window.move("gamma", 30 * window.session.value("gamma"))  # the widget's value and its end event
            window.frame()
        assert (window.session.value("gamma") == pytest.approx(30 * scenes.config("hanging").gamma, rel=1e-9)) == moved
        path = tmp_path / f"{moved}.png"
        window.plotter.screenshot(str(path))
        window.plotter.close()
        shots[moved] = 255 * imread(path).astype(float)
    assert shots[False].shape == shots[True].shape
    assert np.mean(np.abs(shots[True] - shots[False])) > 0.5  # grey levels: the sheet is drawn elsewhere


def test_the_window_draws_while_the_simulation_runs_in_its_own_thread(display):
    """The interactive window: the simulation in its thread, a slider moved (the same stepper and solver take it,
    the slider's title shows it once drawn), then q, as a user would: the window closes and the thread stops."""
    from validation.viewer import Window

    window = Window(_session(), offscreen=False, fps=30)
    assert type(window.plotter.render_window).__name__ == "vtkXOpenGLRenderWindow"  # X events: a real window
    stepper, newton = window.session.stepper, window.session.stepper.newton
    gamma = 30 * window.session.value("gamma")
    title = window.sliders["gamma"][1].GetRepresentation()
    before, seen, start = threading.active_count(), [], time.perf_counter()
    iren = window.plotter.iren

    def user(*_):  # every 20 ms, in the window's loop
        if not seen and window.producer.latest.serial >= 5:
            window.move("gamma", gamma)
            seen.append("moved")
        elif seen == ["moved"] and f"= {gamma:.3g}" in title.GetTitleText():
            seen.append("shown")
            iren.interactor.SetKeySym("q")
            iren.interactor.SetKeyCode("q")
            iren.interactor.CharEvent()  # q closes the window (VTK's interactor style)
        if time.perf_counter() - start > 60:  # a safety net: never a hanging test
            iren.terminate_app()

    iren.add_observer("TimerEvent", user)
    iren.create_timer(20)
    window.run()
    assert seen == ["moved", "shown"]
    assert not window.producer.running and window.producer.error is None and threading.active_count() == before
    assert window.session.stepper is stepper and window.session.stepper.newton is newton
    assert window.session.value("gamma") == pytest.approx(gamma) and window.session.state.t > 0


def test_the_readout_says_where_the_compatibility_test_refuses_the_grid():
    r = Session(scenes.config("hanging", nodes=(5, 5)), "fd").readout()  # the test needs 6 nodes a side
    assert np.isnan(r.mismatch) and r.mismatch_2h is None and "margin" in r.note
    assert f"the state: not computed ({r.note})" in r.text()


def test_the_force_scale_moves_the_shown_mu_and_gamma_with_it():
    """Section 3.1: f multiplies mu, gamma and every force; the mu and gamma sliders show the values in effect."""
    from validation.viewer import Window

    window = Window(_session(), offscreen=True, fps=30)
    mu, gamma = window.session.value("mu"), window.session.value("gamma")
    titles = {name: w.GetRepresentation() for name, (_, w) in window.sliders.items()}
    assert titles["mu"].GetTitleText() == f"mu (kg/m^2) = {mu:.3g}"
    window.move("scale", 2.0)
    for _ in range(2):
        window.frame()
    assert window.session.value("scale") == pytest.approx(2.0) and window.session.value("mu") == mu
    assert titles["mu"].GetTitleText() == f"mu (kg/m^2) = {2 * mu:.3g} (f x {mu:.3g})"
    assert titles["gamma"].GetTitleText() == f"gamma (kg/(m^2 s)) = {2 * gamma:.3g} (f x {gamma:.3g})"
    assert titles["scale"].GetTitleText() == "force scale f (x) = 2: mu, gamma, forces"
    window.plotter.close()


def test_the_readout_shows_the_stable_step_where_the_scheme_has_one():
    """The paper's force runs the semi-implicit scheme, stable below h sqrt(mu / (2 eta G)) (section 2.3): the
    readout gives it and dt; eta x 4 halves it, and the view takes a new dt below it. The implicit scheme has none."""
    s = _session(force_model="tpbf87")
    r = s.readout()
    assert math.isfinite(r.stable) and r.dt <= r.stable and "stable step of the semi-implicit scheme" in r.text()
    s.set(eta=4 * s.value("eta"))
    r4 = s.readout()
    assert r4.stable == pytest.approx(r.stable / 2, rel=1e-6) and r4.dt <= r4.stable
    assert math.isinf(_session().readout().stable) and "stable step" not in _session().readout().text()


def test_the_fabric_menu_runs_a_named_fabric_and_a_slider_leaves_it():
    """The menu's choice is the running simulation's material (its density and warp and weft weights, the sliders
    showing them); a micro slider then leaves the fabric for an isotropic sheet of the slider's values; the
    menu's first entry is the scene's own material back."""
    from validation.viewer import Window

    window = Window(_session(), offscreen=True, fps=30)
    own = window.session.config
    stepper = window.session.stepper
    window.choose("denim")
    for _ in range(2):
        window.frame()
    s, denim = window.session, dm.Fabric.preset("denim")
    assert s.config.fabric == "denim" and s.value("mu") == denim.density and s.stepper is stepper
    np.testing.assert_array_equal(s.model.scene.material.eta, denim.weights()[0])
    assert "fabric denim" in window.producer.latest.readout.text()
    assert window.sliders["mu"][1].GetRepresentation().GetTitleText() == f"mu (kg/m^2) = {denim.density:.3g}"
    s.set(eta=2 * s.value("eta"))
    assert s.config.fabric == "" and s.value("eta") == 2 * denim.weights()[0][0, 0] and s.value("mu") == denim.density
    window.choose(Window.OWN)
    window.frame()
    assert s.config.fabric == "" and (s.value("mu"), s.value("eta")) == (own.mu, own.eta)
    window.plotter.close()


def test_a_fabric_chosen_in_the_view_keeps_the_running_grid():
    """A curtain in jacket-polyester ships on 80 x 80 nodes; chosen in the running view it keeps the view's grid."""
    s = Session(scenes.config("curtain", nodes=(12, 12)), "fd")
    stepper = s.stepper
    s.set(fabric="jacket-polyester")
    assert s.config.fabric == "jacket-polyester" and s.config.nodes == (12, 12) and s.stepper is stepper


def test_the_readout_warns_where_the_grid_does_not_resolve_the_folds():
    """The same criterion as deformable params: the curtain's limp cloth (xi = 1e-5) on 12 x 12 nodes is not
    resolved, the shipped curtain's xi on its own 64 x 64 grid is; a slider to the limp xi warns."""
    from deformable.scenes import parameters

    s = Session(scenes.config("curtain", nodes=(12, 12), fabric="", xi=1e-5), "fd")
    assert not parameters(s.config, s.model, "fd").resolved
    assert "grid NOT resolving the folds" in s.readout().text()
    s.set(xi=1.0)
    assert parameters(s.config, s.model, "fd").resolved and "NOT resolving" not in s.readout().text()
