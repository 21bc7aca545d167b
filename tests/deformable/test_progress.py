"""Progress for people (deformable.progress): a bar on a terminal, timestamped lines at a steady cadence elsewhere."""

import io
import os
import re
import subprocess
import sys
import time

import pytest

import deformable as dm
from deformable.physics import kernels
from deformable.progress import COMPILING, Progress, compile_seconds

from ..conftest import flat_model

#: ``deformable`` in a subprocess, whichever copy of the package the subprocess imports
CLI = "import sys; from validation.commands import main; sys.exit(main(sys.argv[1:]))"
LINE = re.compile(r"^\d{4}-\d\d-\d\d \d\d:\d\d:\d\d (?P<desc>[^:]+): (?P<share>\d+) %")


class Clock:
    """A wall clock the test moves by hand."""

    def __init__(self):
        self.now = 0.0

    def __call__(self):
        return self.now


class Terminal(io.StringIO):
    def isatty(self):
        return True


def shares(text: str) -> list[int]:
    return [int(LINE.match(line)["share"]) for line in text.splitlines()]


def test_off_a_terminal_there_is_one_line_per_tenth_of_the_work_however_fine_the_updates():
    stream, clock = io.StringIO(), Clock()
    progress = Progress(2.0, "job", stream=stream, clock=clock)
    for k in range(1, 1001):
        clock.now += 1e-3
        progress.update(2.0 * k / 1000)
    assert shares(stream.getvalue()) == list(range(10, 101, 10))
    assert all(LINE.match(line)["desc"] == "job" for line in stream.getvalue().splitlines())


def test_a_slow_stretch_still_says_something_every_interval_while_the_work_moves_and_nothing_when_it_does_not():
    stream, clock = io.StringIO(), Clock()
    progress = Progress(100.0, "slow", stream=stream, clock=clock, seconds=30.0)
    clock.now = 31.0
    progress.update(1.0, "1 step")  # 1 %: not a tenth, but 31 s since the start
    clock.now = 62.0
    progress.update(1.0)  # nothing moved: no line however long it has been
    clock.now = 55.0
    progress.update(2.0)  # moved, but only 24 s since the last line
    lines = stream.getvalue().splitlines()
    assert len(lines) == 1 and "1 % (1 step), 31 s elapsed, about 51 min 09 s left" in lines[0]


def test_work_that_ends_before_the_quiet_start_says_nothing_and_longer_work_speaks_from_then_on():
    stream, clock = io.StringIO(), Clock()
    progress = Progress(10, "cases", stream=stream, clock=clock, after=5.0)
    for k in range(1, 11):
        clock.now = 0.9 * k  # 10 % a 0.9 s: the first five tenths come before 5 s
        progress.update(k)
    assert shares(stream.getvalue()) == [60, 70, 80, 90, 100]
    brief, clock = io.StringIO(), Clock()
    quick = Progress(10, "cases", stream=brief, clock=clock, after=5.0)
    quick.update(10)
    assert brief.getvalue() == ""


def test_a_terminal_gets_a_bar_and_no_lines_and_quiet_is_silent():
    terminal = Terminal()
    progress = Progress(10, "bar", stream=terminal)
    for k in range(1, 11):
        progress.update(k)
    progress.close()
    assert "bar:" in terminal.getvalue() and not LINE.search(terminal.getvalue().replace("\r", "\n"))
    quiet = io.StringIO()
    silent = Progress(10, "quiet", stream=quiet, enabled=False)
    silent.update(10)
    assert quiet.getvalue() == ""


def test_a_run_to_t_end_says_its_simulated_time_steps_and_newton_iterations_each_tenth():
    model = flat_model("fd", nodes=(7, 7), material=dm.Material(mu=0.1, gamma=0.0, eta=50.0),
                       forces=[dm.Gravity(direction=(0, -1, 0))], constraints=[dm.Pin("top")],
                       force_model="variational")
    stream = io.StringIO()
    stepper = dm.TimeStepper(model, dt=1e-2, scheme="implicit-euler")
    stepper.run(model.initial_state(), t_end=0.2, trackers=[dm.ProgressBar(stream=stream, name="falling")])
    lines = stream.getvalue().splitlines()
    assert shares(stream.getvalue()) == list(range(10, 101, 10))
    assert "falling: 50 % (t = 0.1 of 0.2 s, 10 steps, " in lines[4] and "Newton iterations" in lines[4]
    assert "left" not in lines[-1]


def test_deformable_run_into_a_pipe_prints_a_progress_line_per_tenth_before_it_ends(tmp_path):
    out = subprocess.run([sys.executable, "-c", CLI, "run", "hanging", "--t-end", "0.05", "--grid", "6x6", "--out",
                          str(tmp_path / "run")], capture_output=True, text=True, check=True, cwd=tmp_path)
    said = [line for line in out.stderr.splitlines() if LINE.match(line)]
    assert [int(LINE.match(line)["share"]) for line in said] == list(range(10, 101, 10)), out.stderr


class Compiler:
    """Seconds spent compiling, moved by hand with the clock."""

    def __init__(self, clock):
        self.clock, self.seconds = clock, 0.0

    def compile(self, seconds):
        self.clock.now += seconds
        self.seconds += seconds

    def __call__(self):
        return self.seconds


def test_a_runs_first_estimate_leaves_the_compile_and_the_first_step_out():
    """Issue 47: a first run compiled for 27 s, then said "about 4 min 02 s left" for a run that ended 0.1 s later.
    Ten steps of 0.1 s, the first one 27 s of compiling and 0.5 s of loading the solver's library longer: the first
    line (the first step's) gives no estimate, the second says 0.8 s, the truth."""
    stream, clock = io.StringIO(), Clock()
    compiler = Compiler(clock)
    progress = Progress(1.0, "hanging", stream=stream, clock=clock, compiling=compiler, warmup=True)
    compiler.compile(27.0)
    clock.now += 0.5
    for k in range(1, 11):
        clock.now += 0.1
        progress.update(k / 10)
    lines = stream.getvalue().splitlines()
    assert shares(stream.getvalue()) == list(range(10, 101, 10))
    assert lines[0].endswith("10 %, 28 s elapsed")  # the truth, compile included; no rate yet, so no estimate
    assert lines[1].endswith("20 %, 28 s elapsed, about 0.8 s left") and "left" not in lines[-1]


def test_without_warmup_the_compile_is_still_left_out_of_the_rate():
    """Cases (no warmup): the rate is measured from the start, less the time spent compiling meanwhile, wherever it
    fell (here during the second case)."""
    stream, clock = io.StringIO(), Clock()
    compiler = Compiler(clock)
    progress = Progress(10, "cases", stream=stream, clock=clock, compiling=compiler)
    clock.now = 2.0
    progress.update(1)
    compiler.compile(20.0)
    clock.now += 2.0
    progress.update(2)
    assert progress.left() == pytest.approx(16.0)  # 2 s a case, 8 cases left; the 20 s of compiling left out
    assert stream.getvalue().splitlines()[1].endswith("24 s elapsed, about 16 s left")


def test_the_compile_clock_counts_numba_compiling_in_this_process():
    from numba import njit

    before = compile_seconds()
    njit(lambda x: x + 1)(1)  # a fresh function: compiled now (no cache)
    assert compile_seconds() > before


def test_a_cold_cache_gets_its_line_before_the_first_kernel_call_and_a_warm_one_none(monkeypatch):
    """The logic of the compile line (the cold compile itself, in a subprocess, is the slow test below): a run's
    ProgressBar says COMPILING before any other tracker starts (the divergence guard's start calls the first
    kernel), and nothing where the cache holds the kernels."""
    model = flat_model("fd", nodes=(5, 5), force_model="variational", material=dm.Material(mu=0.1, eta=50.0))
    said = []

    class First(dm.Tracker):
        def initialize(self, state, stepper, steps):
            said.append(stream.getvalue())

    for cached in (False, True):
        stream = io.StringIO()
        said.clear()
        monkeypatch.setattr(kernels, "cached", lambda cached=cached: cached)
        stepper = dm.TimeStepper(model, dt=1e-2, scheme="implicit-euler")
        stepper.run(model.initial_state(), steps=2, trackers=[First(), dm.ProgressBar(stream=stream, name="c")])
        assert (COMPILING in said[0]) == (not cached) and said[0].count("\n") == (0 if cached else 1)
        assert stream.getvalue().count(COMPILING) == (0 if cached else 1)


def test_the_cold_cache_probe_reads_numbas_index():
    """kernels.cached() reads energy_sums's index file: True once the kernel ran here (the tests' cache is warm by
    then), False where its index is missing (a fresh NUMBA_CACHE_DIR, an edited source)."""
    flat_model("fd", nodes=(5, 5)).energy(flat_model("fd", nodes=(5, 5)).initial_state())
    cache = kernels.energy_sums._cache._cache_file
    assert kernels.cached()
    path = cache._index_path
    try:
        cache._index_path = path + ".absent"
        assert not kernels.cached()
    finally:
        cache._index_path = path


@pytest.mark.slow  # a cold compile of the kernels: about 8 s on two idle cores, 20 s and more on loaded ones
def test_deformable_run_says_it_compiles_with_a_cold_cache_and_not_with_a_warm_one(tmp_path):
    """The line comes before the run goes quiet (before the first progress line), and the run's first estimate of
    the time left is within a factor of 2 of the time to its last line (issue 47), each line timed as it comes."""
    env = {**os.environ, "NUMBA_CACHE_DIR": str(tmp_path / "numba")}
    said = []
    for k in range(2):
        proc = subprocess.Popen([sys.executable, "-c", CLI, "run", "hanging", "--t-end", "0.05", "--out",
                                 str(tmp_path / f"run{k}")], stderr=subprocess.PIPE, stdout=subprocess.DEVNULL,
                                text=True, cwd=tmp_path, env=env)
        said.append([(time.perf_counter(), line) for line in proc.stderr if COMPILING in line or LINE.match(line)])
        assert proc.wait() == 0
    cold, warm = said
    assert COMPILING in cold[0][1] and LINE.match(cold[1][1]) and not any(COMPILING in line for _, line in warm)
    for lines in said:
        at, first = next((t, line) for t, line in lines if " left" in line)
        estimate, truth = float(re.search(r"about ([\d.]+) s left", first)[1]), lines[-1][0] - at
        assert truth / 2 - 0.05 <= estimate <= 2 * truth + 0.05, (truth, first)  # 0.05 s: the estimate's digits
