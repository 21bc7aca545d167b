"""The executor layer (validation.harness.runner): serial, process-pool and Dask maps give the same numbers.

The session's Dask LocalCluster (2 workers, 1 thread each; tests/validation/conftest.py) is reached by its
address and by its scheduler file, the two ways a cluster is found. Cases are tiny (6 x 6 nodes, a few
dozen steps).
"""

import contextlib
import io
import json
import os
import pickle
import subprocess
import sys

import distributed
import numpy as np
import pytest

from deformable import scenes
from validation.harness import runner as runner_module
from validation.harness.runner import Progress, Runner, counted, duration, parse_scheduler
from validation.harness.sweep import Sweep, run_case
from validation.studies import STUDIES
from validation.studies.paper import Case
from validation.studies.paper import run_case as paper_case

from .workload import environment, reciprocal, square_and_pid, threads


@pytest.fixture(scope="module")
def executors(dask_scheduler):
    """The runners to compare, started once: serial, a pool of 2, Dask by address and by scheduler file."""
    address, path = dask_scheduler
    runners = {"serial": Runner(), "pool": Runner(2), "dask": Runner(scheduler=address),
               "dask-file": Runner(scheduler=str(path))}
    with contextlib.ExitStack() as stack:
        yield {name: stack.enter_context(r) for name, r in runners.items()}


def tiny_sweep() -> Sweep:
    """Both backends, two etas, and a refused mu (a failed case): 8 cases of 25 steps on 6 x 6 nodes."""
    base = scenes.config("hanging")
    axes = (("nodes", ((6, 6),)), ("t_end", (0.025,)), ("eta", (20.0, 200.0)), ("mu", (-1.0, 0.2)))
    return Sweep(base, axes, ("fd", "fe"), ("kinetic", "metric"))


def without_wall(record: dict) -> str:
    return json.dumps({k: v for k, v in record.items() if k != "wall"}, sort_keys=True)


def same_bits(a, b) -> bool:
    """Equal to the last bit: arrays by their bytes, floats by their representation, containers recursively."""
    if isinstance(a, dict):
        return isinstance(b, dict) and a.keys() == b.keys() and all(same_bits(a[k], b[k]) for k in a)
    if isinstance(a, (list, tuple)):
        return len(a) == len(b) and all(same_bits(x, y) for x, y in zip(a, b))
    if isinstance(a, np.ndarray):
        return a.dtype == b.dtype and a.shape == b.shape and a.tobytes() == b.tobytes()
    if isinstance(a, float):
        return repr(a) == repr(b)
    return a == b


# -- the maps ------------------------------------------------------------------------
def test_a_pool_and_dask_map_in_order_like_the_serial_runner(executors):
    got = {name: r.map(square_and_pid, range(6)) for name, r in executors.items()}
    for name, out in got.items():
        assert [v for v, _ in out] == [x * x for x in range(6)], name
    assert {pid for _, pid in got["serial"]} == {os.getpid()}
    for name in ("pool", "dask", "dask-file"):
        assert os.getpid() not in {pid for _, pid in got[name]}, f"{name} ran in this process"


@pytest.mark.slow  # a whole pipeline (Dask, a real window, a long run): pytest -m slow
def test_sweep_cases_are_bit_identical_serially_on_the_pool_and_on_dask(executors):
    cases = tiny_sweep().cases()
    got = {name: r.map(run_case, cases) for name, r in executors.items()}
    statuses = {r["status"] for r in got["serial"]}
    assert "failed" in statuses and statuses - {"failed"}, statuses  # refused configs, and runs
    reference = [without_wall(r) for r in got["serial"]]
    for name, records in got.items():
        assert [without_wall(r) for r in records] == reference, f"{name} differs from the serial run"


@pytest.mark.slow  # a whole pipeline (Dask, a real window, a long run): pytest -m slow
def test_paper_study_cases_are_bit_identical_serially_on_the_pool_and_on_dask(executors):
    cases = [Case("run", "hanging", b, 6, (("eta", 30.0),), t_end=0.03, every=10) for b in ("fd", "fe")]
    cases.append(Case("spectrum", "hanging", "fd", 6))
    got = {name: r.map(paper_case, cases) for name, r in executors.items()}
    for out in got.values():
        for r in out:
            r.pop("wall")
    for name, out in got.items():
        assert same_bits(out, got["serial"]), f"{name} differs from the serial run"


def test_a_study_gives_the_same_result_serially_on_the_pool_and_on_dask(executors):
    study = STUDIES["statics"]
    got = {name: study.run(3, runner=r) for name, r in executors.items() if name != "dask-file"}
    serial = got["serial"]
    assert serial.checks and serial.tables
    for name, res in got.items():
        assert res.checks == serial.checks and res.tables == serial.tables, name
        assert same_bits(res.data, serial.data), name


def test_map_raises_the_first_error_and_completed_yields_every_outcome(executors):
    for name, r in executors.items():
        with pytest.raises(ZeroDivisionError):
            r.map(reciprocal, [1.0, 0.0, 2.0])
        outcomes = sorted(r.completed(reciprocal, [1.0, 0.0, 2.0]), key=lambda o: o[0])
        assert [o[1] for o in outcomes] == [1.0, None, 0.5], name
        assert outcomes[0][2] is None and isinstance(outcomes[1][2], ZeroDivisionError), name


def test_local_workers_are_two_of_one_thread_each_with_one_blas_thread_and_no_malloc_trimming(dask_scheduler):
    with distributed.Client(dask_scheduler[0]) as client:
        assert set(client.nthreads().values()) == {1} and len(client.nthreads()) == 2
        for name, value in (("MKL_NUM_THREADS", "1"), ("OPENBLAS_NUM_THREADS", "1"), ("MALLOC_TRIM_THRESHOLD_", None)):
            assert set(client.run(environment, name).values()) == {value}, name


@contextlib.contextmanager
def mkl_threads(n: int):
    """MKL computes on n threads in this thread, as if it had started with MKL_NUM_THREADS=n (where it is installed)."""
    try:
        import pypardiso
    except ImportError:
        yield
        return
    previous = pypardiso.ps.libmkl.MKL_Set_Num_Threads_Local(n)
    try:
        yield
    finally:
        pypardiso.ps.libmkl.MKL_Set_Num_Threads_Local(previous)


def test_a_case_has_the_same_bits_whatever_ran_before_it_and_on_any_number_of_mkl_threads():
    """MKL fixes its thread count when it starts, from OMP_NUM_THREADS / MKL_NUM_THREADS: 1 on Dask's workers, and
    in a process that first used it after a LocalCluster had set them (Dask sets them in the parent to spawn its
    workers); so PARDISO's factorisations (the Newton matrix of FE 6 x 6 nodes is big enough) must not depend on it."""
    first, *others = [c for c in tiny_sweep().cases() if c.backend == "fe" and dict(c.fields)["mu"] > 0]
    with mkl_threads(2):
        reference = without_wall(run_case(first))
    for case in others:
        run_case(case)
    with mkl_threads(1):
        assert without_wall(run_case(first)) == reference, "the rerun on one MKL thread differs"
    code = "import json, pickle, sys; from validation.harness.sweep import run_case; " \
           "print(json.dumps(run_case(pickle.load(sys.stdin.buffer))))"
    env = dict(os.environ, OMP_NUM_THREADS="1", MKL_NUM_THREADS="1", OPENBLAS_NUM_THREADS="1")  # a Dask worker's
    fresh = subprocess.run([sys.executable, "-c", code], input=pickle.dumps(first), capture_output=True, env=env,
                           check=True)
    assert without_wall(json.loads(fresh.stdout)) == reference, "a fresh process on one thread differs"


def test_pool_workers_compute_on_one_thread_each():
    """--jobs N runs at most a worker per core: each assembles its Hessians and calls BLAS / MKL on one thread,
    as Dask's workers do (before, each of two workers ran two of each on two cores)."""
    with Runner(jobs=2) as runner:
        assert runner.map(threads, [0, 1]) == [(1, 1), (1, 1)]


def test_a_local_cluster_leaves_the_environment_of_this_process_as_it_was():
    """Dask sets its workers' environment (OMP_NUM_THREADS=1, PYTHONHASHSEED, ...) in this process to spawn them."""
    before = dict(os.environ)
    with Runner(scheduler="local:1") as runner:
        assert dict(os.environ) == before
        assert runner.map(environment, ["OMP_NUM_THREADS"]) == ["1"]  # the worker's own
    assert dict(os.environ) == before


# -- bad input -----------------------------------------------------------------------
@pytest.mark.parametrize("spec, expected", [
    ("local:3", ("local", 3)),
    ("tcp://10.0.0.5:8786", ("address", "tcp://10.0.0.5:8786")),
])
def test_scheduler_specs(spec, expected):
    assert parse_scheduler(spec) == expected


def test_a_scheduler_file_is_a_spec(tmp_path):
    path = tmp_path / "scheduler.json"
    path.write_text("{}")
    assert parse_scheduler(str(path)) == ("file", str(path))


@pytest.mark.parametrize("spec, message", [
    ("local:0", "needs a positive number of workers"),
    ("local:two", "needs a positive number of workers"),
    ("tcp://", "names no host"),
    ("no-such-file.json", "is none of them (no such file)"),
])
def test_bad_scheduler_specs_say_why(spec, message):
    with pytest.raises(ValueError, match=message.replace("(", r"\(").replace(")", r"\)")):
        parse_scheduler(spec)


def test_jobs_and_scheduler_together_are_refused():
    with pytest.raises(ValueError, match="either --jobs"):
        Runner(2, scheduler="local:2")


def test_without_dask_the_scheduler_option_says_how_to_get_it(monkeypatch):
    monkeypatch.setitem(sys.modules, "distributed", None)  # import distributed -> ImportError
    with pytest.raises(ValueError, match=r'pip install "\.\[distributed\]"'):
        Runner(scheduler="local:2")


def test_an_unreachable_scheduler_is_one_line(monkeypatch):
    monkeypatch.setattr(runner_module, "CONNECT_TIMEOUT", 0.5)
    with pytest.raises(ValueError, match="cannot reach the Dask scheduler 'tcp://127.0.0.1:9'") as err:
        with Runner(scheduler="tcp://127.0.0.1:9"):
            pass
    assert "\n" not in str(err.value)


def test_a_runner_with_workers_maps_only_inside_with():
    with pytest.raises(RuntimeError, match="inside `with runner:`"):
        Runner(2).map(reciprocal, [1.0, 2.0])


@pytest.mark.parametrize("jobs", [0, -1, 1.5, True])
def test_jobs_must_be_a_positive_integer(jobs):
    with pytest.raises(ValueError, match="jobs must be a positive integer"):
        Runner(jobs)


# -- progress ------------------------------------------------------------------------
def test_progress_off_a_terminal_is_a_line_per_tenth_of_the_cases_with_the_time_left():
    stream = io.StringIO()
    progress = Progress(3, "sweep x", stream=stream)
    for k in range(1, 4):
        progress.update(k, f"{k}/3 cases done")
    lines = stream.getvalue().splitlines()
    assert [line.split(" ", 2)[2].split(",")[0] for line in lines] == [
        f"sweep x: {100 * k / 3:.0f} % ({k}/3 cases done)" for k in (1, 2, 3)]
    assert all("left" in line for line in lines[:2]) and "left" not in lines[2]


def test_durations_and_counts_read_like_text():
    assert [duration(s) for s in (3.25, 42, 200, 7500)] == ["3.2 s", "42 s", "3 min 20 s", "2 h 05 min"]
    assert [counted(n) for n in (1, 2)] == ["1 case", "2 cases"]
