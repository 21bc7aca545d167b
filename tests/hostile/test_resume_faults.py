"""Faults of resumed runs (issue 26, findings 1, 2 and 8): a resume is the same run, a series has no holes.

Each test here failed on ce6e554: a resumed implicit run whose step had adapted took the requested step
again (another trajectory), a resume from a checkpoint later than a cut-back series left a hole in it,
``KEY=VALUE`` after an option was refused, a lock naming a live process that was not the run blocked the
folder for good, and a scene file that is a named pipe hung the run.
"""

import os
import random
import shutil
import subprocess
import sys

import numpy as np
import pytest

from deformable import scenes
from deformable.dynamics import Callback, State, TimeStepper
from deformable.io import CheckpointWriter, load_checkpoint
from deformable.io.folder import LOCK, RunFolder
from validation.commands import main
from validation.harness.backends import make_model

from ..conftest import assert_same_series, series_frames


def _run(argv, capsys):
    code = main(["run", *map(str, argv)])
    out = capsys.readouterr()
    return code, out.out, out.err


def _same_checkpoint(a, b):
    a, b = load_checkpoint(a), load_checkpoint(b)
    assert (a["step"], a["t"], a.get("memory")) == (b["step"], b["t"], b.get("memory"))
    for key in ("X", "V", "A"):
        np.testing.assert_array_equal(a[key], b[key], err_msg=key)


# -- finding 1: the controller's memory is in the checkpoint ---------------------------------------------
@pytest.mark.slow  # a slow fault or a whole pipeline, run by pytest -m slow
def test_the_sphere_resumed_across_its_impact_is_the_same_run(tmp_path, capsys):
    """dt = 0.02 s: the impact on the ball (near t = 0.17 s) halves the step; resumed from the checkpoint
    just after it (step 10, dt 0.01 s) and from one before it (step 6)."""
    base = ["sphere", "--grid", "10x10", "--dt", "0.02", "--t-end", "0.3", "--every", "0.02",
            "--checkpoint-every", "2"]
    full = tmp_path / "full"
    assert _run(base + ["--out", full], capsys)[0] == 0
    assert load_checkpoint(full / "sphere-checkpoint-0000010.npz")["t"] == pytest.approx(0.19)  # one step of 0.01 s
    final = max(full.glob("sphere-checkpoint-*.npz"))
    for k in (10, 6):
        part = tmp_path / f"from-{k}"
        code, _, err = _run(["--resume", full / f"sphere-checkpoint-{k:07d}.npz", "--checkpoint-every", "2",
                             "--out", part], capsys)
        assert code == 0, err
        assert_same_series(full / "sphere.xdmf", part / "sphere.xdmf")
        _same_checkpoint(final, part / final.name)


def test_a_library_run_at_dt_auto_on_fe_resumes_as_the_same_run(tmp_path):
    """dt = "auto" on FE: the step follows Newton's iteration count (0.25 to 1 of the auto step here); a
    second stepper given the checkpoint's state and memory reproduces every later state bit for bit."""
    scene = scenes.build(scenes.config("curtain", nodes=(6, 6)))
    model = make_model(scene, "fe")

    def run(stepper, resume=None, X0=None):
        states = []
        X0 = model.initial_state() if X0 is None else X0
        ck = CheckpointWriter(tmp_path, "ck", 3, X0, scene="curtain", config="", backend="fe", dt=stepper.dt,
                              nodes=(6, 6))
        stepper.run(X0, steps=12 - (0 if resume is None else resume.step), resume=resume,
                    trackers=[Callback(states.append), ck])
        return states

    first = TimeStepper(model, "auto")
    states = run(first)
    ck = load_checkpoint(tmp_path / "ck-0000003.npz")
    assert ck["t"] < 3 * first.dt  # the premise: the step had adapted by the checkpoint
    second = TimeStepper(model, "auto")
    second.restore(ck["memory"])
    resumed = run(second, State(t=ck["t"], X=ck["X"], V=ck["V"], step=ck["step"], A=ck["A"]), ck["X0"])
    assert [s.step for s in resumed] == [s.step for s in states[3:]]
    for a, b in zip(states[3:], resumed):
        assert a.t == b.t
        np.testing.assert_array_equal(a.X, b.X)
        np.testing.assert_array_equal(a.V, b.V)


def test_a_stepper_refuses_a_memory_that_is_not_its_own():
    model = make_model(scenes.build(scenes.config("hanging", nodes=(5, 5))), "fd")
    stepper = TimeStepper(model, 0.01)
    for memory, field in [({"dt_now": 1.0}, "memory.dt_now"), ({"speed": 1}, "speed"),
                          ({"accepted": -1}, "memory.accepted"), ("dt_now=1", "memory")]:
        with pytest.raises(ValueError) as err:
            stepper.restore(memory)
        assert err.value.field == field


# -- finding 2: a series never has a hole ----------------------------------------------------------------
def _kill_at(monkeypatch, step):
    """Make the next run end as a Ctrl-C does, just before it takes step ``step``."""
    original = TimeStepper.step

    def step_or_die(self, state, dt=None):
        if state.step + 1 == step:
            raise KeyboardInterrupt
        return original(self, state, dt)

    monkeypatch.setattr(TimeStepper, "step", step_or_die)
    return lambda: monkeypatch.setattr(TimeStepper, "step", original)


def _continuous(xdmf, every):
    times = [t for t, _, _ in series_frames(xdmf)]
    gaps = np.diff(times)
    return bool(np.all(gaps > 0) and np.max(gaps) <= every * (1 + 1e-9) + 0.005)  # dt = 0.005 s


def test_a_resume_killed_after_an_older_checkpoint_leaves_no_hole(tmp_path, capsys, monkeypatch, caplog):
    """Finding 2's sequence: a run to step 40 with checkpoints every 5; a resume from step 10 killed at
    step 19; then a resume from the first run's step 30 (ce6e554 took it: exit 0, frames 0.1-0.15 s gone).
    Now the later checkpoints are removed when the resume from step 10 starts, and a copy of step 30 put
    back is refused in one line, the series untouched; a resume from step 15 then completes it."""
    folder = tmp_path / "run"
    base = ["curtain", "--grid", "8x8", "--every", "0.01", "--checkpoint-every", "5"]
    assert _run(base + ["--steps", "40", "--out", folder], capsys)[0] == 0
    shutil.copy(folder / "curtain.xdmf", tmp_path / "full.xdmf")
    shutil.copy(folder / "curtain.h5", tmp_path / "full.h5")
    stale = tmp_path / "stale-30.npz"
    shutil.copy(folder / "curtain-checkpoint-0000030.npz", stale)
    undo = _kill_at(monkeypatch, 20)
    code, _, err = _run(["--resume", folder / "curtain-checkpoint-0000010.npz", "--checkpoint-every", "5",
                         "--steps", "40"], capsys)
    undo()
    assert code == 130
    assert "removed 6 checkpoints later than step 10" in caplog.text
    assert sorted(p.name for p in folder.glob("*.npz")) == [f"curtain-checkpoint-{k:07d}.npz" for k in (5, 10, 15)]
    shutil.copy(stale, folder / "curtain-checkpoint-0000030.npz")
    before = (folder / "curtain.xdmf").read_bytes()
    code, out, err = _run(["--resume", folder / "curtain-checkpoint-0000030.npz", "--steps", "40"], capsys)
    assert code == 2 and out == "" and len(err.strip().splitlines()) == 1
    assert "its frames end at step 18 (t = 0.09 s)" in err and "resume from a checkpoint at or before" in err
    assert (folder / "curtain.xdmf").read_bytes() == before
    code, _, err = _run(["--resume", folder / "curtain-checkpoint-0000015.npz", "--steps", "40"], capsys)
    assert code == 0, err
    assert _continuous(folder / "curtain.xdmf", 0.01)
    os.replace(tmp_path / "full.h5", tmp_path / "curtain.h5")  # the copy's heavy data under the name it names
    shutil.copy(tmp_path / "full.xdmf", tmp_path / "curtain.xdmf")
    assert_same_series(tmp_path / "curtain.xdmf", folder / "curtain.xdmf")


@pytest.mark.slow  # a slow fault (24 killed and resumed runs): pytest -m slow; the default run stays under 2 min
def test_any_sequence_of_kills_and_resumes_keeps_the_series_continuous_or_is_refused(tmp_path, capsys,
                                                                                    monkeypatch):
    """Twenty-four rounds, each a resume from a random checkpoint of the folder (also stale copies put back)
    killed at a random later step or run to the end: after each round the series' frame times increase,
    with no gap above the frame interval, or the resume was refused and the series is as it was."""
    rng = random.Random(26)
    folder, attic = tmp_path / "run", tmp_path / "attic"
    attic.mkdir()
    base = ["curtain", "--grid", "8x8", "--every", "0.01", "--checkpoint-every", "4"]
    assert _run(base + ["--steps", "32", "--out", folder], capsys)[0] == 0
    for p in folder.glob("*.npz"):
        shutil.copy(p, attic / p.name)  # every checkpoint of the first run, to put back later
    refused = finished = 0
    for _ in range(24):
        choice = rng.choice([p for p in sorted(folder.glob("*.npz")) + sorted(attic.glob("*.npz"))
                             if load_checkpoint(p)["step"] < 32])
        ck = folder / choice.name
        if choice.parent == attic:
            shutil.copy(choice, ck)
        step = load_checkpoint(ck)["step"]
        kill = None if rng.random() < 0.35 else rng.randint(step + 1, 32)
        before = (folder / "curtain.xdmf").read_bytes()
        undo = _kill_at(monkeypatch, kill) if kill else (lambda: None)
        code, _, err = _run(["--resume", ck, "--checkpoint-every", "4", "--steps", "32"], capsys)
        undo()
        assert code in (0, 2, 130), err
        if code == 2:
            refused += 1
            assert "missing" in err and (folder / "curtain.xdmf").read_bytes() == before
        finished += code == 0
        assert _continuous(folder / "curtain.xdmf", 0.01)
    assert refused and finished  # the sequence went through both branches


# -- finding 8: the command line and the files it reads ---------------------------------------------------
def test_key_value_after_an_option_sets_the_field(tmp_path, capsys):
    code, _, err = _run(["hanging", "--grid", "6x6", "eta=25", "--steps", "2", "xi=0.001", "--out", tmp_path],
                        capsys)
    assert code == 0, err
    cfg = scenes.read_toml(tmp_path / "hanging.toml")
    assert (cfg.eta, cfg.xi, cfg.nodes) == (25.0, 0.001, (6, 6))
    code, _, err = _run(["hanging", "--steps", "2", "--bogus", "eta=2", "--out", tmp_path / "b"], capsys)
    assert code == 2 and err.strip() == "deformable run: unrecognized arguments: --bogus"


def _lock(folder, pid, mtime=None):
    folder.mkdir(parents=True, exist_ok=True)
    (folder / LOCK).write_text(f"{pid} {os.uname().nodename}\n")
    if mtime is not None:
        os.utime(folder / LOCK, (mtime, mtime))


def test_a_stale_lock_naming_a_live_process_is_cleared_with_a_message(tmp_path, capsys, caplog):
    """A lock file whose pid is a live process that is not a run (pid reuse): a non-Python process, and this very
    (Python) process named in a lock written before it started. ce6e554 refused both for good; nobody holds the
    file's OS lock, so it is taken over."""
    other = subprocess.Popen(["cat"], stdin=subprocess.PIPE)
    try:
        for k, (pid, mtime) in enumerate([(other.pid, None), (os.getpid(), 1e9)]):
            folder = tmp_path / f"out-{k}"
            _lock(folder, pid, mtime)
            code, _, err = _run(["hanging", "--grid", "5x5", "--steps", "1", "--out", folder], capsys)
            assert code == 0, err
            assert "cleared the stale lock" in caplog.text and not (folder / LOCK).exists()
            caplog.clear()
    finally:
        other.communicate()


def test_a_live_run_s_lock_still_keeps_a_second_run_out(tmp_path, capsys):
    """A folder whose OS lock a live run holds (this process): a second run is refused in one line, --overwrite
    or not."""
    with RunFolder(tmp_path):
        code, _, err = _run(["hanging", "--grid", "5x5", "--steps", "1", "--out", tmp_path, "--overwrite"], capsys)
    assert code == 2 and f"in use by another run (pid {os.getpid()} on" in err and len(err.strip().splitlines()) == 1


@pytest.mark.slow  # a slow fault or a whole pipeline, run by pytest -m slow
def test_a_scene_file_that_is_a_named_pipe_is_refused(tmp_path):
    """ce6e554 opened it and waited for a writer for ever; run in a subprocess with a timeout."""
    pipe = tmp_path / "scene.toml"
    os.mkfifo(pipe)
    for command in (["run", str(pipe), "--steps", "1", "--out", str(tmp_path / "o")], ["check", str(pipe)]):
        code = "import sys; from validation.commands import main; sys.exit(main(sys.argv[1:]))"
        done = subprocess.run([sys.executable, "-c", code, *command], capture_output=True, text=True, timeout=60,
                              check=False)
        assert done.returncode == 2, done.stderr
        assert done.stderr.strip().endswith("it is a named pipe, not a regular file")
