"""Faults against ``deformable sweep``, by the findings of issue 26 (3, 4, 5 and part of 8).

A sweep too large to run is refused at once, naming its count; a range with an end that is not finite is
refused; a pool worker that dies is replaced and its case retried, the other cases untouched; a sweep with a
failed case says so in its last line and exits 1; a Ctrl-C under Dask is one line and exit code 130. Each
refusal is one line on stderr, exit code 2, and writes nothing. Workers are killed deterministically: a case
function kills its own process on a chosen case (on its first attempt only, recorded by a marker file).
"""

import functools
import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import psutil
import pytest

import validation
from deformable import scenes
from deformable.errors import ResourceError
from validation.harness import sweep as sweep_module
from validation.harness.runner import Runner
from validation.harness.sweep import Sweep, run_case

from .conftest import refused, run_command

TINY = ["hanging", "nodes=6x6", "t_end=0.02"]
#: the code this test process imports, for the commands it starts in processes of their own
CODE = str(Path(validation.__file__).parents[1])
CLI = "import sys; from validation.commands import main; sys.exit(main(sys.argv[1:]))"


_run, _refused = run_command, refused


def _command(argv, **kwargs):
    """``deformable ARGV`` in a process of its own, on this process's code."""
    env = dict(os.environ, PYTHONPATH=CODE)
    return subprocess.Popen([sys.executable, "-c", CLI, *argv], env=env, stdout=subprocess.PIPE,
                            stderr=subprocess.PIPE, text=True, **kwargs)


# -- case functions that kill their own worker -------------------------------------------------------------
def dies(case):
    """``case = (marker folder, value, victim, every time)``: value squared; the victim kills its own process.

    It dies on its first attempt only (a marker file records the attempt) unless ``every time``.
    """
    folder, value, victim, always = case
    if value == victim:
        marker = Path(folder) / f"{value}.died"
        if always or not marker.exists():
            marker.write_text("")
            os._exit(3)
    return value * value


def sweep_case_dies(folder, victim_eta, always, case):
    """run_case, except that the case of eta = ``victim_eta`` kills its own worker process (see :func:`dies`)."""
    if dict(case.fields)["eta"] == victim_eta:
        marker = Path(folder) / f"{case.key}.died"
        if always or not marker.exists():
            marker.write_text("")
            os._exit(3)
    return run_case(case)


# -- 3: a sweep too large to ever run ------------------------------------------------------------------------
def test_the_sweep_of_issue_26_with_1e10_cases_is_refused_at_once_naming_its_count(tmp_path):
    """It built its cases until memory ran out (no output at all)."""
    out = tmp_path / "out"
    child = _command(["sweep", "hanging", "eta=1:2:100000", "xi=0:1:100000", "--out", str(out)])
    try:
        _, err = child.communicate(timeout=30)
    finally:
        child.kill()
        child.wait()
    assert child.returncode == 2, err
    refusal = ("error: a sweep of hanging with 10000000000 cases (1 backend x 100000 eta x 100000 xi) is more than "
               "--max-cases 100000; sweep fewer values, or raise --max-cases")
    assert err.strip().splitlines() == [refusal], err
    assert not out.exists()


def test_max_cases_sets_the_limit_counted_over_backends_and_axes(tmp_path, capsys):
    out = tmp_path / "out"
    code, _, err = _run(["sweep", *TINY, "eta=20,40,80", "mu=0.1,0.2", "--backend", "fd,fe", "--max-cases", 11,
                         "--out", out], capsys)
    _refused(code, err, "with 12 cases (2 backends x 3 eta x 2 mu) is more than --max-cases 11")
    code, _, err = _run(["sweep", *TINY, "eta=1:2:12", "--max-cases", 11, "--out", out], capsys)
    _refused(code, err, "sweep range eta=1:2:12 has 12 values, more than --max-cases 11")
    code, _, err = _run(["sweep", *TINY, "eta=20,40", "--max-cases", 0, "--out", out], capsys)
    _refused(code, err, "--max-cases must be a positive integer, got 0")
    assert not out.exists()
    code, _, err = _run(["sweep", *TINY, "eta=20,40", "--max-cases", 2, "--out", out], capsys)
    assert code == 0, err
    assert len(list((out / "cases").glob("*.json"))) == 2


def test_a_sweep_above_its_limit_is_refused_by_the_library_before_any_case_is_built():
    base = scenes.config("hanging")
    axes = (("eta", tuple(float(v) for v in range(1000))), ("xi", tuple(float(v) for v in range(1000))))
    with pytest.raises(ResourceError, match=r"with 1000000 cases \(1 backend x 1000 eta x 1000 xi\)"):
        Sweep(base, axes, max_cases=999_999)


# -- 8 (part): ranges with ends that are not finite -------------------------------------------------------
@pytest.mark.parametrize("item, message", [
    ("eta=1:inf:3", "sweep range eta=1:inf:3: START and STOP must be finite, got 'inf'"),
    ("eta=-inf:1:3", "sweep range eta=-inf:1:3: START and STOP must be finite, got '-inf'"),
    ("eta=nan:1:3", "sweep range eta=nan:1:3: START and STOP must be finite, got 'nan'"),
    ("xi=1e-4:inf:3:log", "sweep range xi=1e-4:inf:3:log: START and STOP must be finite, got 'inf'"),
    ("eta=-1e308:1e308:3", "sweep range eta=-1e308:1e308:3 spans more than a float can hold"),
])
def test_a_range_with_an_end_that_is_not_finite_is_refused(item, message, tmp_path, capsys):
    code, _, err = _run(["sweep", *TINY, item, "--out", tmp_path / "out"], capsys)
    _refused(code, err, message)
    assert not (tmp_path / "out").exists()


# -- 5: a pool worker that dies ------------------------------------------------------------------------------
@pytest.mark.slow  # a slow fault or a whole pipeline, run by pytest -m slow
def test_a_dead_pool_worker_is_replaced_and_its_case_retried_the_others_untouched(tmp_path):
    cases = [(str(tmp_path), v, 2, False) for v in range(6)]
    with Runner(2) as runner:
        outcomes = sorted(runner.completed(dies, cases))
    assert (tmp_path / "2.died").exists(), "the victim did not kill its worker"
    assert [(i, result, error) for i, result, error in outcomes] == [(v, v * v, None) for v in range(6)]


@pytest.mark.slow  # a slow fault (several seconds of real processes): pytest -m slow; the default run stays under 2 min
def test_a_case_that_kills_every_worker_fails_alone_after_three_retries(tmp_path):
    cases = [(str(tmp_path), v, 1, True) for v in range(5)]
    with Runner(2) as runner:
        outcomes = sorted(runner.completed(dies, cases), key=lambda o: o[0])
        assert runner.map(dies, [(str(tmp_path), v, -1, False) for v in range(4)]) == [0, 1, 4, 9]  # still works
    assert [o[1] for o in outcomes] == [0, None, 4, 9, 16]
    assert [o[2] is None for o in outcomes] == [True, False, True, True, True]
    assert "died 4 times running it (last exit code 3)" in str(outcomes[1][2])


@pytest.fixture
def victim(monkeypatch, tmp_path):
    """Make the sweep's case of eta = 40 kill its worker: ``victim(always)``; returns the marker folder."""
    def make(always: bool) -> Path:
        folder = tmp_path / "markers"
        folder.mkdir()
        monkeypatch.setattr(sweep_module, "run_case", functools.partial(sweep_case_dies, str(folder), 40.0, always))
        return folder
    return make


@pytest.mark.slow  # a slow fault or a whole pipeline, run by pytest -m slow
def test_a_sweep_whose_worker_dies_once_finishes_every_case_and_exits_0(tmp_path, capsys, caplog, victim):
    """Before, every case pending when the worker died was a failed row (also those not started), exit code 0."""
    markers = victim(always=False)
    code, out, err = _run(["sweep", *TINY, "eta=10,20,40,80,160,320", "--jobs", 2, "--oversubscribe",
                           "--out", tmp_path / "out"], capsys)
    assert len(list(markers.glob("*.died"))) == 1, "the victim did not kill its worker"
    assert code == 0, err
    assert "6 cases (6 finished)" in out
    records = sorted((tmp_path / "out" / "cases").glob("*.json"))
    assert len(records) == 6 and all('"status": "finished"' in p.read_text() for p in records)
    assert "a worker process died running a case (exit code 3); the case runs again" in caplog.text


@pytest.mark.slow  # a slow fault or a whole pipeline, run by pytest -m slow
def test_a_sweep_with_failed_cases_says_so_in_its_last_line_and_exits_1(tmp_path, capsys, victim):
    victim(always=True)
    code, out, err = _run(["sweep", *TINY, "eta=20,40,80", "--jobs", 2, "--oversubscribe",
                           "--out", tmp_path / "out"], capsys)
    assert code == 1, err
    assert err.strip().splitlines()[-1] == (f"sweep: 1 of 3 cases failed; their messages are in "
                                            f"{tmp_path / 'out' / 'sweep.md'}")
    assert "3 cases (2 finished, 1 failed)" in out
    assert "| failed |" in (tmp_path / "out" / "sweep.md").read_text()
    assert "worker: BrokenProcessPool: its worker process died 4 times" in (tmp_path / "out" / "sweep.csv").read_text()


def test_a_case_the_scene_refuses_fails_the_sweep_too(tmp_path, capsys):
    code, _, err = _run(["sweep", *TINY, "mu=-1,0.2", "--out", tmp_path / "out"], capsys)
    assert code == 1, err
    assert err.strip().splitlines()[-1].startswith("sweep: 1 of 2 cases failed; their messages are in ")


# -- 4: Ctrl-C under Dask ------------------------------------------------------------------------------------
@pytest.mark.slow  # a slow fault (several seconds of real processes): pytest -m slow; the default run stays under 2 min
def test_ctrl_c_under_dask_stops_the_workers_quietly_and_exits_130_with_one_line(tmp_path):
    """A terminal's Ctrl-C is SIGINT to the whole process group: the workers got it too and printed 65-91 lines
    of tracebacks. About 4 s: the LocalCluster's start, two cases, the interrupt."""
    out = tmp_path / "out"
    child = _command(["sweep", "hanging", "nodes=10x10", "t_end=0.3", "eta=10,20,40,80,160,320",
                      "--scheduler", "local:2", "--out", str(out)], start_new_session=True)
    workers, started = [], time.monotonic()
    try:
        for line in child.stderr:  # a progress line per stored case: the workers run the others now
            if "cases done" in line:
                workers = psutil.Process(child.pid).children(recursive=True)
                os.killpg(child.pid, signal.SIGINT)
                break
            assert time.monotonic() - started < 60, "no case finished in 60 s"
        _, err = child.communicate(timeout=60)
    finally:
        child.kill()
        child.wait()
    assert workers, "the sweep ended before it was interrupted"
    assert child.returncode == 130, err
    assert [line for line in err.splitlines() if "cases done" not in line] == ["interrupted"], err
    _, alive = psutil.wait_procs(workers, timeout=10)
    for process in alive:
        process.kill()
    assert not alive, "Dask's workers outlived the interrupted sweep"
    stored = [p.read_text() for p in (out / "cases").glob("*.json")]
    assert 1 <= len(stored) < 6 and all('"status": "failed"' not in text for text in stored)
    assert not (out / "sweep.csv").exists()


def test_a_sweep_of_a_field_of_tables_is_refused_naming_it(tmp_path, capsys):
    """Finding 8: ``obstacles=1,2`` was read as a node grid ("grid '1x1' needs at least 3 nodes a side")."""
    code, _, err = _run(["sweep", "hanging", "obstacles=1,2", "--out", tmp_path / "out"], capsys)
    _refused(code, err, "a sweep cannot vary obstacles")
    assert not (tmp_path / "out").exists()
