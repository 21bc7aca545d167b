"""The time stepper: a controller that runs a scheme under trackers (py-pde's controller pattern).

:class:`TimeStepper` chooses the scheme for the model's force model, starts a run (the constraint reference X0),
advances it step by step (:meth:`~TimeStepper.iterate`), and runs it under trackers (:meth:`~TimeStepper.run`:
progress, output, energy, divergence guard), each watching at its own cadence and free to stop the run. The schemes
know nothing of the run, and the controller knows no scheme: it looks the scheme up by name in the registry
(:class:`~deformable.dynamics.scheme.Scheme`), the force model's own ``scheme`` by default:

- ``"semi-implicit"``: the paper's eq. (22)-(27) (:mod:`deformable.dynamics.semi_implicit`), for force models with a
  strength matrix (tpbf87 and frozen: their default); its old name ``"tpbf87"`` warns (DeprecationWarning);
- ``"implicit-euler"`` and ``"newmark"``: Newton steps on an incremental potential
  (:mod:`deformable.dynamics.implicit`), for force models with an energy (their default: implicit Euler).

Step size. ``dt="auto"`` is the backend's own (:mod:`deformable.dynamics.dt`); with it the implicit schemes also aim
at :data:`TARGET_ITERATIONS` Newton iterations a step. The implicit schemes adapt dt: a step whose Newton solve does
not reach its tolerance is retried with half the step, and dt doubles back after :data:`GROW_AFTER` accepted steps
up to the requested one; a run that would need a step below ``dt_min`` (default dt / 2^10) stops with the status
"stalled" and its last good state. A run to ``t_end`` ends exactly there with every scheme (the semi-implicit one
adds one shorter step, with its own step matrix, when ``t_end - t`` is not a whole number of steps to within 1e-6 of
a step). Likewise the step that would pass a time a tracker asks for
(:meth:`~deformable.dynamics.trackers.Tracker.next_time`, e.g. the XDMF writer's frame times) is shortened to end on
it, so a frame is a state of the run at its time.

Bounds on work. ``dt`` is at least :data:`DT_MIN` (below it M/dt^2 swamps every stiffness in double precision); a
run is at most :attr:`TimeStepper.max_steps` steps (:data:`MAX_STEPS`; None lifts the cap). Bad arguments raise
:class:`~deformable.errors.InputError`; a singular step matrix or a non-finite state ends the run with the status
"diverged" and the last good state, never with a SciPy error.
"""

from __future__ import annotations

import logging
import time
import warnings
from array import array
from collections.abc import Iterator, Sequence

import numpy as np

from ..algebra.solvers import one_blas_thread
from ..checks import count, known_keys, real, suggest
from ..errors import DivergenceError, InputError, ResourceError, StalledError, StepRejected
from .dt import DT_MIN, resolve_dt, round_down
from .implicit_euler import ImplicitEuler
from .newmark import Newmark
from .scheme import Scheme
from .semi_implicit import SemiImplicit
from .state import RunResult, State
from .trackers import REMAINDER, DivergenceGuard, ProgressBar, Stop, Tracker, landing, next_stop

__all__ = ["DT_MIN", "GROW_AFTER", "MAX_STEPS", "SCHEMES", "TARGET_ITERATIONS", "TimeStepper", "round_down"]

log = logging.getLogger(__name__)
#: the built-in schemes (the registry, :class:`Scheme`, knows any other)
SCHEMES = tuple(cls.name for cls in (SemiImplicit, ImplicitEuler, Newmark))
#: former scheme names -> current ones
_RENAMED = {"tpbf87": "semi-implicit"}
#: an adapted dt doubles after this many accepted steps in a row (up to the requested dt)
GROW_AFTER = 4
#: with dt = "auto", the implicit schemes also aim at this many Newton iterations a step: dt halves after a step
#: that took more than twice as many, and grows by half after one that took at most half as many
TARGET_ITERATIONS = 4
#: the most steps a run may take unless :attr:`TimeStepper.max_steps` is raised (or None)
MAX_STEPS = 10**7


class TimeStepper:
    """Integrate ``model`` in time with one of :data:`SCHEMES`.

    Parameters
    ----------
    model : Backend
        FDModel or FEModel (anything satisfying :class:`deformable.Backend`).
    dt : float or "auto"
        Time step (s), positive; "auto": the backend's own (module docstring).
    scheme : str, optional
        "semi-implicit" (eq. 22-27, the default for the tpbf87 and frozen models), "implicit-euler" (the default for
        the variational model) or "newmark" (second order): Newton steps on an incremental potential, for models
        with an energy (:mod:`deformable.dynamics.implicit`).
    newton : dict or NewtonSettings, optional
        rtol, atol, max_iter, hessian, solver, reuse of the Newton solves of the implicit schemes
        (:class:`deformable.solve.newton.NewtonSettings`).
    dt_min : float, optional
        The smallest step the implicit schemes may adapt down to (default dt / 2^10).
    solver : str
        The linear solver of the semi-implicit scheme ("auto", "superlu", "pardiso").

    Attributes
    ----------
    dt : float
        The requested step (s); ``dt_now`` is the current one of an adaptive run.
    rejected : int
        Steps retried with a smaller dt.
    max_steps : int or None
        The most steps :meth:`run` takes (default :data:`MAX_STEPS`); None: no cap.
    """

    max_steps: int | None = MAX_STEPS

    def __init__(self, model, dt, scheme: str | None = None, newton=None, dt_min: float | None = None,
                 solver: str = "auto"):
        from ..algebra.solvers import SOLVERS
        from ..scene.scene import Scene

        if not isinstance(getattr(model, "scene", None), Scene):
            raise InputError(f"model must be a backend (FDModel, FEModel), got {model!r}", field="model", value=model)
        if not isinstance(solver, str) or solver not in SOLVERS:
            raise InputError(f"solver must be one of {SOLVERS}, got {solver!r}", field="solver", value=solver)
        force_model = model.scene.force_model
        if not (scheme is None or isinstance(scheme, str)):
            raise InputError(f"scheme must be one of {', '.join(Scheme.names())}, got {scheme!r}"
                             f"{suggest(scheme, Scheme.names())}", field="scheme", value=scheme)
        if scheme in _RENAMED:
            warnings.warn(f"scheme {scheme!r} is now called {_RENAMED[scheme]!r}", DeprecationWarning, stacklevel=2)
            scheme = _RENAMED[scheme]
        scheme = scheme or force_model.scheme
        if scheme not in Scheme.names():
            raise InputError(f"scheme must be one of {', '.join(Scheme.names())}, got {scheme!r}"
                             f"{suggest(scheme, Scheme.names())}", field="scheme", value=scheme)
        kind = Scheme.lookup(scheme)
        kind.check(force_model)
        self.model, self.scheme = model, scheme
        self.auto = isinstance(dt, str) and dt == "auto"
        self.dt = resolve_dt(model, Scheme.lookup(self.scheme).implicit, dt)
        if dt_min is None:
            dt_min = self.dt / 2**10
        if isinstance(dt_min, bool) or not isinstance(dt_min, (int, float)) or not 0 < dt_min <= self.dt:
            raise InputError(f"dt_min must be a positive number not above dt = {self.dt:g} s, got {dt_min!r}")
        self.dt_min, self.dt_now, self.rejected = float(dt_min), self.dt, 0
        self._accepted = 0
        self._taken = array("d")  # the length of each step taken (s)
        self._trackers, self._pending = [], {}  # the current run's trackers; memories for the next run's
        self._scheme = kind(model, self.dt, newton=newton, solver=solver)

    def retune(self, model) -> None:
        """Go on with ``model`` from the state at hand: the same backend, grid and held degrees of freedom, other
        material values (mu, gamma, eta, xi) and loads (a slider of ``deformable view``). The implicit schemes keep
        their solver's pattern, analysis and compiled kernels; InputError when the model does not fit."""
        if type(model) is not type(self.model) or model.ndof != self.model.ndof:
            raise InputError("retune: the new model must be of the same backend and grid", field="model",
                             value=type(model).__name__)
        Scheme.lookup(self.scheme).check(model.scene.force_model)
        self._scheme.retune(model)
        self.model = model

    @property
    def timings(self) -> dict:
        """Seconds per part of the steps so far (semi-implicit: assembly, factorisation, solve; implicit: the Newton
        solves' hessian, factor, solve, search)."""
        return self._scheme.timings

    @property
    def newton(self):
        """The :class:`deformable.solve.newton.Newton` of an implicit scheme (None for the semi-implicit one)."""
        return getattr(self._scheme, "newton", None)

    @property
    def newton_reports(self) -> list:
        """Newton iterations and residuals per accepted step of the implicit schemes (empty for the semi-implicit
        scheme)."""
        return getattr(self._scheme, "reports", [])

    @property
    def reference(self) -> np.ndarray | None:
        """The run's constraint reference X0, (ndof, 3): its initial positions, also in a resumed run."""
        return getattr(self, "_X0", None)

    @property
    def adaptive(self) -> bool:
        """Whether the scheme adapts its step (the implicit ones: module docstring)."""
        return self._scheme.adaptive

    @property
    def steps_taken(self) -> np.ndarray:
        """The length (s) of each step this stepper has taken, in order, (steps,): what an adaptive run took."""
        return np.frombuffer(self._taken, dtype=float).copy()

    def memory(self) -> dict:
        """What the controller carries from step to step, as numbers, for a checkpoint (:meth:`restore`).

        ``dt_now`` (the adapted step, s), ``accepted`` (steps accepted since dt last changed), ``rejected`` (steps
        retried so far), the scheme's own (:meth:`Scheme.memory`) and, under ``trackers``, the memories of the
        current run's trackers that keep one (by class name). With the state (X, V, A, t, step), a resumed run is
        the same run bit for bit.
        """
        trackers = {type(tr).__name__: tr.memory() for tr in self._trackers if callable(getattr(tr, "memory", None))}
        return {"dt_now": self.dt_now, "accepted": self._accepted, "rejected": self.rejected,
                **self._scheme.memory(), **({"trackers": trackers} if trackers else {})}

    def restore(self, memory: dict) -> None:
        """Take up the controller's memory (:meth:`memory`) of another stepper of the same run.

        Raises InputError naming the key when ``memory`` is not such a dict (an unknown key, a step outside [dt_min,
        dt], a negative count).
        """
        if not isinstance(memory, dict):
            raise InputError(f"memory must be a dict of the controller's numbers, got {memory!r:.60}", field="memory",
                             value=memory)
        own = {"dt_now", "accepted", "rejected", "trackers"}
        known_keys(memory, sorted(own | set(self._scheme.remembers)), "in the controller's memory")
        if "dt_now" in memory:
            dt_now = real("memory.dt_now", memory["dt_now"], positive=True)
            if not self.dt_min * (1 - 1e-12) <= dt_now <= self.dt * (1 + 1e-12):
                raise InputError(f"memory.dt_now = {dt_now!r} s is outside [dt_min, dt] = [{self.dt_min:g}, "
                                 f"{self.dt:g}] s", field="memory.dt_now", value=dt_now)
            self.dt_now = dt_now
        if "accepted" in memory:
            self._accepted = count("memory.accepted", memory["accepted"], minimum=0)
        if "rejected" in memory:
            self.rejected = count("memory.rejected", memory["rejected"], minimum=0)
        trackers = memory.get("trackers", {})
        if not isinstance(trackers, dict) or not all(isinstance(v, dict) for v in trackers.values()):
            raise InputError(f"memory.trackers must map tracker names to their memories, got {trackers!r:.60}",
                             field="memory.trackers", value=trackers)
        self._pending = dict(trackers)  # taken up by the trackers of the next run, after their initialize
        self._scheme.restore({k: v for k, v in memory.items() if k not in own})

    def step(self, state: State, dt: float | None = None) -> State:
        """Advance one step (of ``dt``, default the current one); implicit schemes retry with smaller steps.

        Raises StalledError (with the last good state) when the step would fall below ``dt_min``, and
        DivergenceError when positions leave the finite numbers.
        """
        with one_blas_thread():
            return self._step(state, dt)

    def _step(self, state: State, dt: float | None) -> State:
        new = self._advance(state, dt)
        self._taken.append(new.t - state.t)
        return new

    def _advance(self, state: State, dt: float | None) -> State:
        if not self._scheme.adaptive:
            return self._scheme.step(state, self._X0, dt)
        dt = self.dt_now if dt is None else min(dt, self.dt_now)
        while True:
            try:
                new = self._scheme.step(state, self._X0, dt)
            except StepRejected as err:
                self.rejected += 1
                self._accepted = 0
                dt *= 0.5
                self.dt_now = min(self.dt_now, dt)
                if dt < self.dt_min:
                    raise StalledError(f"stalled at t = {state.t:.6g} s: no step down to dt_min = {self.dt_min:.3g} s "
                                       f"converges ({err})", state) from err
                continue
            self._accepted += 1
            iterations = self._scheme.reports[-1].iterations
            if self.auto and iterations > 2 * TARGET_ITERATIONS:
                self.dt_now, self._accepted = max(0.5 * dt, self.dt_min), 0
            elif self.auto and iterations <= TARGET_ITERATIONS // 2 and self.dt_now < self.dt:
                self.dt_now = min(1.5 * self.dt_now, self.dt)
            elif self._accepted >= GROW_AFTER and self.dt_now < self.dt:
                self.dt_now, self._accepted = min(2 * self.dt_now, self.dt), 0
            return new

    def start(self, X0: np.ndarray, V0: np.ndarray | None = None, t0: float = 0.0) -> State:
        """The initial state; also fixes the reference positions of the constraints.

        X0 and V0 must be finite (ndof, 3) arrays, t0 a finite number (InputError otherwise).
        """
        X0 = self._array("X0", X0)
        V0 = np.zeros_like(X0) if V0 is None else self._array("V0", V0)
        self._X0 = X0
        return State(t=real("t0", t0), X=X0, V=V0, step=0)

    def _array(self, name: str, value) -> np.ndarray:
        try:
            arr = np.array(value, dtype=float)
        except (TypeError, ValueError):
            arr = None
        shape = (self.model.ndof, 3)
        if arr is None or arr.shape != shape:
            got = f"{value!r:.40}" if arr is None else f"has shape {arr.shape}"
            raise InputError(f"{name} {got}, expected {shape}", field=name)
        if not np.all(np.isfinite(arr)):
            raise InputError(f"{name} must be finite: it holds {np.count_nonzero(~np.isfinite(arr))} NaN or "
                             "infinite entries", field=name)
        return arr

    def _resume(self, state) -> State:
        if not isinstance(state, State):
            raise InputError(f"resume must be a State, got {state!r}", field="resume", value=state)
        for name in ("X", "V") + (("A",) if state.A is not None else ()):
            self._array(f"resume.{name}", getattr(state, name))
        count("resume.step", state.step, minimum=0)
        real("resume.t", state.t)
        return state

    def iterate(self, X0, steps: int | None = None, V0=None, t0: float = 0.0,
                 t_end: float | None = None) -> Iterator[State]:
        """Yield the state after each step from (X0, V0) at t0: ``steps`` of them, or until ``t_end``.

        The last step before ``t_end`` is shortened to end on it (module docstring). Raises DivergenceError if
        positions become non-finite and StalledError if dt falls below ``dt_min`` (each with the last good state).
        """
        state = X0 if isinstance(X0, State) else self.start(X0, V0, t0)
        for state, _ in self._iterate(state, steps, t_end):
            yield state

    def _iterate(self, state: State, steps: int | None, t_end: float | None, stops=None,
                 planned: int | None = None) -> Iterator[tuple[State, bool]]:
        """:meth:`iterate` from ``state``, each state with whether it is the last; ``stops(state)``: the next time
        (s) a tracker asks for, or None, on which a step is to end (:meth:`_landing`). ``planned``: the step number
        a run to ``t_end`` of an adaptive scheme was planned to end on (:meth:`length`); the state that reaches it,
        unless a step landed on a tracker's time, is also called the last."""
        if not hasattr(self, "_X0"):
            self._X0 = state.X
        taken, landed = 0, False
        if t_end is not None and not self._scheme.adaptive:
            full, last = self._plan(state, t_end)
            while (full or last) and (steps is None or taken < steps):
                dt = self._landing(state, stops, t_end)
                if dt is not None:  # a step onto a tracker's time; then whole steps from there again
                    state = self.step(state, dt)
                    full, last = self._plan(state, t_end)
                elif full:
                    state, full = self.step(state), full - 1
                else:
                    state, last = self.step(state, t_end - state.t), False
                taken += 1
                yield state, not (full or last) or taken == steps
            return
        while (steps is None or taken < steps) and (t_end is None or t_end - state.t > 1e-12 * max(1.0, t_end)):
            dt = self._landing(state, stops, t_end)
            landed = landed or dt is not None
            if dt is None and t_end is not None:
                dt = t_end - state.t
            state = self.step(state, dt)
            taken += 1
            ended = t_end is not None and t_end - state.t <= 1e-12 * max(1.0, t_end)
            yield state, ended or taken == steps or (not landed and state.step == planned)

    def _landing(self, state: State, stops, t_end: float | None) -> float | None:
        """The step (s) from ``state`` onto the next time a tracker asks for, ``stops(state)``
        (:func:`~deformable.dynamics.trackers.landing`), or None."""
        stop = None if stops is None else stops(state)
        return landing(stop, state.t, self.dt_now if self._scheme.adaptive else self.dt, t_end)

    def _plan(self, state: State, t_end) -> tuple[int, bool]:
        """Whole steps of dt from ``state`` to ``t_end``, and whether a shorter last step follows."""
        t_end = real("t_end", t_end)
        if not t_end > state.t:
            raise InputError(f"t_end must be later than the start time {state.t}, got {t_end!r}", field="t_end",
                             value=t_end)
        q = (t_end - state.t) / self.dt
        if not np.isfinite(q) or q > 1e15:
            raise ResourceError(f"t_end = {t_end!r} s is {q:.3g} steps of dt = {self.dt:g} s away", field="t_end",
                                value=t_end)
        n = round(q)
        if abs(q - n) <= REMAINDER:
            return n, False
        return int(np.floor(q)), True

    def _steps_to(self, state: State, t_end: float) -> int:
        full, last = self._plan(state, t_end)
        return full + int(last)

    def length(self, t: float, *, t_end: float | None = None, steps: int | None = None) -> int:
        """The steps a run from time ``t`` takes (the requested ones of an adaptive run), checked.

        Steps shortened to end on the times trackers ask for are not counted (at most one more for each such time
        that no whole step reaches). Exactly one of ``t_end`` and ``steps``; InputError for a bad value,
        ResourceError beyond :attr:`max_steps`. :meth:`run` calls it first; a caller can check a run before it
        writes anything.
        """
        if (t_end is None) == (steps is None):
            raise InputError("give exactly one of t_end and steps")
        if steps is None:  # checks t_end; every scheme ends on it exactly
            expected = self._steps_to(State(t=real("t", t), X=None, V=None), t_end)
        else:
            expected = count("steps", steps, minimum=0)
        if self.max_steps is not None and expected > self.max_steps:
            raise ResourceError(f"a run of {expected:,} steps exceeds the cap of {self.max_steps:,} steps "
                                "(TimeStepper.max_steps; set it to None to lift the cap)", field="steps",
                                value=expected)
        return expected

    # -- a controlled run ---------------------------------------------------
    def run(
        self,
        X0,
        *,
        t_end: float | None = None,
        steps: int | None = None,
        V0=None,
        t0: float = 0.0,
        trackers: Sequence = (),
        progress: bool | str = False,
        resume: State | None = None,
    ) -> RunResult:
        """Run to ``t_end`` (s) or for ``steps`` steps under a set of trackers (:mod:`deformable.dynamics.trackers`).

        A :class:`~deformable.dynamics.trackers.DivergenceGuard` is added unless one is given; a diverging run stops
        at that step and the result holds the last good state. ``progress``: True (or a name to start its lines
        with) adds a :class:`~deformable.dynamics.trackers.ProgressBar`. A step that would pass a time a tracker
        asks for (its ``next_time``) is shortened to end on it; such steps count among the run's ``steps``.
        """
        state = self.start(X0, V0, t0)
        if resume is not None:
            state = self._resume(resume)
        first = state.step
        expected = self.length(state.t, t_end=t_end, steps=steps)
        if steps is not None:
            steps = expected
        if isinstance(trackers, Tracker) or not isinstance(trackers, (list, tuple)):
            raise InputError(f"trackers must be a list of trackers, got {trackers!r}", field="trackers",
                             value=trackers)
        for tr in trackers:
            if not all(callable(getattr(tr, k, None)) for k in ("initialize", "handle", "finalize")):
                raise InputError(f"trackers: {tr!r} is not a tracker (initialize, handle, finalize, every)",
                                 field="trackers", value=tr)
            count(f"{type(tr).__name__}.every", getattr(tr, "every", None))
        trackers = list(trackers)
        if not any(isinstance(tr, DivergenceGuard) for tr in trackers):
            trackers.insert(0, DivergenceGuard())
        if progress:
            trackers.append(ProgressBar(name=progress if isinstance(progress, str) else "run"))
        self.t_goal = t_end  # the end of the run in progress (s), or None: read by a ProgressBar
        pending, self._pending = self._pending, {}
        # a progress bar starts first: its clock, and its line on a cold compile, before the others' first kernel call
        for tr in sorted(trackers, key=lambda tr: not isinstance(tr, ProgressBar)):
            tr.initialize(state, self, expected)
            if type(tr).__name__ in pending and callable(getattr(tr, "restore", None)):
                tr.restore(pending[type(tr).__name__])  # a resumed run's tracker takes up its memory
        self._trackers = trackers
        status, message = "finished", ""
        start = time.perf_counter()
        timed = [tr for tr in trackers if callable(getattr(tr, "next_time", None))]
        stops = (lambda s: next_stop(timed, s)) if timed else None
        try:
            for new, final in self._iterate(state, steps, t_end, stops, state.step + expected):
                stop = None
                for tr in trackers:
                    if new.step % tr.every == 0 or final:
                        stop = tr.handle(new) or stop
                        if isinstance(stop, Stop) and stop.diverged:
                            break
                if isinstance(stop, Stop) and stop.diverged:
                    status, message = "diverged", stop.reason
                    state = getattr(tr, "last_good", state)  # a guard's last checked state (its cadence > 1)
                    break
                state = new
                if isinstance(stop, Stop):
                    status, message = "stopped", stop.reason
                    break
        except DivergenceError as err:
            status, message, state = "diverged", str(err), err.state
        except StalledError as err:
            status, message, state = "stalled", str(err), err.state
        wall = time.perf_counter() - start
        if status == "finished":
            message = f"{state.step - first} steps to t = {state.t:.6g} s"
        result = RunResult(state=state, status=status, message=message, steps=state.step, wall_time=wall,
                           trackers=trackers)
        for tr in trackers:
            tr.finalize(result)
        if status in ("diverged", "stalled"):
            log.warning("run %s; last good state at t = %.6g s", message, state.t)
        return result

