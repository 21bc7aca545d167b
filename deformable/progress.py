r"""Progress for people: a live bar on a terminal, plain timestamped lines in a log.

One class serves every long job of the project, a run's steps
(:class:`deformable.dynamics.trackers.ProgressBar`, behind ``deformable run``) and a
study's or a sweep's cases (:class:`validation.harness.runner.Runner`):

- on a terminal, a tqdm bar that redraws itself in place;
- anywhere else (a pipe, a file, a batch job's log), one line at a steady
  cadence: each time another tenth of the work is done, and at least every
  :attr:`Progress.seconds` of wall time while anything moved (once ``after``
  seconds have passed: the runner's cases wait 5 s), each flushed as it is
  written, so that ``deformable run hanging 2>&1 | cat`` or a job's log shows
  how far a run is while it runs. A line reads ::

      2026-12-03 11:40:02 hanging: 30 % (t = 0.3 of 1 s, 60 steps, 84 Newton iterations), 9.1 s elapsed, about 21 s left

The estimate of the time left is the wall time per unit of work so far times
the work left (for a run, simulated seconds; for cases, cases: it counts the
workers' parallelism), leaving out the time numba spent compiling in this
process (:func:`compile_seconds`): a first run compiles the kernels for seconds
(:data:`COMPILING`), which no later step repeats. With ``warmup`` (a run's steps,
a render's frames) the work up to the first update is left out too (its first
step loads the sparse solver's library and analyses the matrix, its first frame
opens the renderer): the rate is measured from the first update on, and the
line of the first update, which has no rate yet, gives no estimate.
"""

from __future__ import annotations

import math
import sys
import time

__all__ = ["COMPILING", "Progress", "compile_seconds", "counted", "duration"]

#: what a run says before the kernels' first compile (a cold numba cache:
#: :func:`deformable.physics.kernels.cached`). Measured (:func:`compile_seconds`, 2026-12): the compile of
#: ``deformable run hanging --t-end 0.05`` with an empty NUMBA_CACHE_DIR took 7.3-7.5 s (FD) and 4.9-5.3 s (``--backend
#: fe``) on a core of its own, and 20 s on two cores shared with a test run (issue 47 saw 27 s on a loaded machine)
COMPILING = "compiling the kernels once (about 10 s; later runs read them from the cache)"

_compiler = None


def compile_seconds() -> float:
    """Wall seconds this process has spent in numba's compiler (compiling, or loading compiled code from its cache)
    since the first call: the time under numba's compiler lock, timed by a listener of its events."""
    global _compiler
    if _compiler is None:
        from numba.core import event

        _compiler = event.TimingListener()
        event.register("numba:compiler_lock", _compiler)
    return _compiler.duration if _compiler.done else 0.0


def duration(seconds: float) -> str:
    """A duration for people: ``"42 s"``, ``"3 min 20 s"``, ``"2 h 05 min"``."""
    s = round(seconds)
    if s < 60:
        return f"{max(seconds, 0):.0f} s" if seconds >= 10 else f"{max(seconds, 0):.1f} s"
    if s < 3600:
        return f"{s // 60} min {s % 60:02d} s"
    return f"{s // 3600} h {s % 3600 // 60:02d} min"


def counted(n: int, noun: str = "case") -> str:
    """``"1 case"``, ``"3 cases"``."""
    return f"{n} {noun}" if n == 1 else f"{n} {noun}s"


class Progress:
    """Work done out of ``total``: a tqdm bar on a terminal, timestamped lines otherwise.

    Parameters
    ----------
    total : float
        The amount of work (cases, steps, simulated seconds: any unit), > 0.
    desc : str
        What is being done, the start of every line (``"hanging"``, ``"statics"``).
    enabled : bool
        False: silent (``--quiet``).
    stream : file, optional
        Where to write (default ``sys.stderr``); a bar only when it is a terminal.
    fraction : float
        A line each time another ``fraction`` of the total is done (default 0.1: ten lines a run).
    seconds : float
        And a line at least every ``seconds`` of wall time while the work moved (default 30 s).
    after : float
        No line before ``after`` seconds of wall time (default 0): work that ends sooner says nothing (the
        runner's cases: a study of a few seconds is one summary line, not ten).
    warmup : bool
        The work up to the first update is a warm-up (module docstring): the estimate's rate is measured from the
        first update on (default False: from the start; cases finishing on parallel workers).
    clock : callable
        The wall clock (``time.perf_counter``; a test's own clock).
    compiling : callable
        Seconds spent compiling so far, left out of the estimate (default :func:`compile_seconds`; a test's own).
    """

    def __init__(self, total: float, desc: str, *, enabled: bool = True, stream=None, fraction: float = 0.1,
                 seconds: float = 30.0, after: float = 0.0, warmup: bool = False, clock=time.perf_counter,
                 compiling=compile_seconds):
        self.total, self.desc, self.enabled = float(total), desc, enabled
        self.stream = sys.stderr if stream is None else stream
        self.fraction, self.seconds, self.after, self.clock = fraction, seconds, after, clock
        self.warmup, self.compiling = warmup, compiling
        self.done, self.start = 0.0, clock()
        #: (wall clock, compiling, work done) where the estimate's rate is measured from: the start, then (warmup)
        #: the first update
        self._base, self._first = (self.start, compiling(), 0.0), None
        self._said, self._said_at, self._bar = 0.0, self.start, None
        if enabled and getattr(self.stream, "isatty", lambda: False)():
            from tqdm.auto import tqdm

            self._bar = tqdm(total=self.total, desc=desc, leave=False, file=self.stream,
                             bar_format="{desc}: {percentage:3.0f}%|{bar}| {postfix} [{elapsed}<{remaining}]")

    def left(self) -> float:
        """Estimated seconds left: the wall time per unit of work since the estimate's base (the start; with
        ``warmup`` the first update), less the time spent compiling meanwhile, times the work left (inf before
        there is a rate)."""
        wall, compiled, done = self._base
        if self.done <= done:
            return math.inf
        busy = max(self.clock() - wall - (self.compiling() - compiled), 0.0)
        return busy / (self.done - done) * max(self.total - self.done, 0.0)

    def update(self, done: float, detail: str = "") -> None:
        """The work done so far is ``done`` (absolute, not an increment); ``detail`` says it in the task's terms."""
        self.done = min(float(done), self.total)
        if self.done >= self.total * (1 - 1e-9):  # the end, but for the round-off of summed steps
            self.done = self.total
        if self.warmup and self._first is None and self.done > 0:
            self._first = self._base = (self.clock(), self.compiling(), self.done)
        if not self.enabled:
            return
        if self._bar is not None:
            self._bar.n = self.done
            self._bar.set_postfix_str(detail, refresh=False)
            self._bar.refresh()
            return
        now = self.clock()
        if now - self.start < self.after:
            return
        step = self.fraction * self.total
        crossed = math.floor(self.done / step + 1e-9) > math.floor(self._said / step + 1e-9)
        finished = self.done >= self.total
        if crossed or finished or (now - self._said_at >= self.seconds and self.done > self._said):
            self.line(detail, now)

    def line(self, detail: str = "", now: float | None = None) -> None:
        """Write one timestamped line of where the work stands."""
        now = self.clock() if now is None else now
        self._said, self._said_at = self.done, now
        stamp = time.strftime("%Y-%m-%d %H:%M:%S")
        share = f"{100 * self.done / self.total:.0f} %" if self.total > 0 else "?"
        detail = f" ({detail})" if detail else ""
        left = self.left()
        left = "" if self.done >= self.total or math.isinf(left) else f", about {duration(left)} left"
        print(f"{stamp} {self.desc}: {share}{detail}, {duration(now - self.start)} elapsed{left}",
              file=self.stream, flush=True)

    def note(self, text: str) -> None:
        """One line that is not a share of the work (what is about to happen, :data:`COMPILING`): timestamped off a
        terminal, above the bar on one; nothing when disabled."""
        if not self.enabled:
            return
        if self._bar is not None:
            self._bar.write(f"{self.desc}: {text}", file=self.stream)
            return
        print(f"{time.strftime('%Y-%m-%d %H:%M:%S')} {self.desc}: {text}", file=self.stream, flush=True)

    def close(self) -> None:
        if self._bar is not None:
            self._bar.close()
            self._bar = None
