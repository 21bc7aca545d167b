"""``deformable view`` (validation/viewer.py): a slider changes the running simulation; the window under Xvfb."""

import os
import shutil
import subprocess
import time

import numpy as np
import pytest

from deformable import scenes
from validation.commands import main
from validation.viewer import Session


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


def test_the_readout_states_energy_stretch_and_the_compatibility_test():
    s = _session()
    s.advance(0.1)
    r = s.readout()
    assert r.elastic > 0 and r.kinetic > 0 and 0 < r.stretch < 1 and r.verdict in ("compatible", "INCOMPATIBLE")
    assert (r.ratio is None) == (r.cosine is None)
    assert "compatibility (eq. 10)" in r.text() and "largest stretch" in r.text()


def test_offscreen_frames_write_a_screenshot(tmp_path, capsys):
    png = tmp_path / "a.png"
    assert main(["view", "hanging", "--grid", "8x8", "--offscreen", "--frames", "3", "--screenshot", str(png)]) == 0
    out = capsys.readouterr().out
    assert png.stat().st_size > 1000 and "3 frames" in out and "x real time" in out


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
def display():
    """A virtual X display (Xvfb; .ci/run installs it), for a real window."""
    exe = shutil.which("Xvfb")
    assert exe, "this test needs Xvfb for a real window (Debian: apt-get install xvfb; .ci/run installs it)"
    number = 90 + os.getpid() % 100
    proc = subprocess.Popen([exe, f":{number}", "-screen", "0", "1280x1024x24", "-nolisten", "tcp"],
                            stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    old = os.environ.get("DISPLAY")
    os.environ["DISPLAY"] = f":{number}"
    for _ in range(100):  # until the server answers (its socket appears)
        if os.path.exists(f"/tmp/.X11-unix/X{number}"):
            break
        time.sleep(0.05)
    yield os.environ["DISPLAY"]
    proc.terminate()
    proc.wait(timeout=10)
    if old is None:
        os.environ.pop("DISPLAY", None)
    else:
        os.environ["DISPLAY"] = old


def test_a_real_window_shows_a_moved_slider_changing_the_motion(display, tmp_path):
    from matplotlib.image import imread

    from validation.viewer import Window

    shots = {}
    for moved in (False, True):
        window = Window(_session(), offscreen=False, fps=30)
        assert not window.plotter.off_screen
        window.plotter.show(auto_close=False, interactive=False)
        for k in range(12):
            if moved and k == 3:
                window.move("xi", 30 * window.session.value("xi"))  # the widget's value and its end event
            window.frame()
        assert (window.session.value("xi") == pytest.approx(30 * scenes.config("hanging").xi, rel=1e-9)) == moved
        path = tmp_path / f"{moved}.png"
        window.plotter.screenshot(str(path))
        window.plotter.close()
        shots[moved] = 255 * imread(path).astype(float)
    assert shots[False].shape == shots[True].shape
    assert np.mean(np.abs(shots[True] - shots[False])) > 0.5  # grey levels: the sheet is drawn elsewhere
