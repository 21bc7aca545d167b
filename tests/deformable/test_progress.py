"""Progress for people (deformable.progress): a bar on a terminal, timestamped lines at a steady cadence elsewhere."""

import io
import re
import subprocess
import sys

import deformable as dm
from deformable.progress import Progress

from ..conftest import flat_model

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
    out = subprocess.run([sys.executable, "-c", "import sys; from validation.commands import main; sys.exit(main(sys.argv[1:]))", "run", "hanging", "--t-end", "0.05",
                          "--grid", "6x6", "--out", str(tmp_path / "run")], capture_output=True, text=True,
                         check=True, cwd=tmp_path)
    said = [line for line in out.stderr.splitlines() if LINE.match(line)]
    assert [int(LINE.match(line)["share"]) for line in said] == list(range(10, 101, 10)), out.stderr
