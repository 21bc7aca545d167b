"""Trackers: small observers of a run (py-pde's controller/tracker pattern).

Each tracker has a cadence ``every`` (in steps) and three hooks: ``initialize(state, stepper, steps)``,
``handle(state) -> Stop | None`` and ``finalize(result)``. Returning a :class:`Stop` from ``handle`` ends the run;
``Stop(diverged=True)`` discards the state just computed and hands back the previous one. A tracker may also ask for
states at times of its own (:meth:`Tracker.next_time`): :meth:`deformable.TimeStepper.run` then ends a step on each
of them (the XDMF writer's frames, :class:`deformable.io.XDMFWriter`).
"""

from __future__ import annotations

import logging
from collections import deque
from dataclasses import dataclass

import numpy as np

from ..checks import count, function, known_keys, real
from ..contact.selfmesh import ContactMesh
from ..errors import InputError

__all__ = ["Callback", "DivergenceGuard", "EnergyMonitor", "ProgressBar", "REMAINDER", "SelfContactMonitor", "Stop",
           "Tracker", "landing", "next_stop"]

log = logging.getLogger(__name__)
#: a time a run is asked to reach (its t_end, a tracker's :meth:`~Tracker.next_time`) that lies within this fraction
#: of a step of the state a step of that length ends on is reached by that state: the round-off of summing dt, not
#: a further step to take
REMAINDER = 1e-6


def next_stop(trackers, state) -> float | None:
    """The earliest of the trackers' :meth:`Tracker.next_time` after ``state`` (s), or None."""
    times = [real(f"{type(tr).__name__}.next_time", t) for tr in trackers if (t := tr.next_time(state)) is not None]
    return min(times, default=None)


def landing(stop: float | None, t: float, whole: float, t_end: float | None) -> float | None:
    """The step (s) from time ``t`` that ends on ``stop`` (a time a tracker asks for) when a whole step ``whole``
    would pass it; None when it would not, when nothing is asked, or when ``stop`` is the run's end.

    A time within :data:`REMAINDER` of a whole step of ``t``, or of where a whole step ends, is taken as reached by
    it (the round-off of summing dt), so a run whose dt divides the trackers' intervals takes whole steps only.
    """
    if stop is None or (t_end is not None and stop >= t_end - REMAINDER * whole):
        return None
    gap = stop - t
    if gap <= REMAINDER * whole or gap >= (1 - REMAINDER) * whole:
        return None
    return gap


@dataclass(frozen=True)
class Stop:
    """A tracker's request to end the run, with the reason."""

    reason: str
    diverged: bool = False


class Tracker:
    """Base class: override what you need."""

    every: int = 1

    def initialize(self, state, stepper, steps: int) -> None:
        self.stepper = stepper

    def handle(self, state) -> Stop | None:
        return None

    def next_time(self, state) -> float | None:
        """The next time (s) after ``state.t`` at which this tracker wants a state of the run, or None (the default).

        :meth:`deformable.TimeStepper.run` asks it before each step and shortens a step that would pass that time so
        that it ends on it (within :data:`REMAINDER` of a step). A tracker that asks should handle every step
        (``every = 1``).
        """
        return None

    def finalize(self, result) -> None:
        pass


class Callback(Tracker):
    """Call ``fn(state)`` every ``every`` steps; a string it returns stops the run."""

    def __init__(self, fn, every: int = 1):
        self.fn, self.every = function("Callback.fn", fn, optional=False), count("Callback.every", every)

    def handle(self, state):
        reason = self.fn(state)
        return Stop(reason) if isinstance(reason, str) else None


class ProgressBar(Tracker):
    """How far a run is, on stderr (:class:`deformable.progress.Progress`).

    A tqdm bar on a terminal; elsewhere a timestamped line at each tenth of the run and at least every 30 s of wall
    time: the simulated time reached (s), the steps taken, the Newton iterations of the implicit schemes, the wall
    time elapsed and an estimate of the time left, measured from the end of the first step and without the time
    spent compiling (:class:`deformable.progress.Progress`'s ``warmup``). The work is simulated seconds for a run to
    ``t_end``, steps for a run of ``steps``. Where numba's cache is cold (:func:`deformable.physics.kernels.cached`)
    a line says so first (:data:`deformable.progress.COMPILING`): :meth:`deformable.TimeStepper.run` starts a
    progress bar before the other trackers, whose start calls the first kernel.

    Parameters
    ----------
    every : int
        Look every ``every`` steps (default 1: the cadence of the lines is the wall clock's, not this).
    disable : bool, optional
        True: silent.
    stream : file, optional
        Default ``sys.stderr``.
    name : str
        The start of each line (default ``"run"``; ``deformable run`` gives the scene's name).
    """

    def __init__(self, every: int = 1, disable: bool | None = None, stream=None, name: str = "run"):
        self.every, self.disable = count("ProgressBar.every", every), disable
        self.stream, self.name = stream, name
        self.progress = None

    def initialize(self, state, stepper, steps):
        from ..physics import kernels
        from ..progress import COMPILING, Progress

        super().initialize(state, stepper, steps)
        self.t0, self.first, self.seen, self.iterations = state.t, state.step, 0, 0
        goal = getattr(stepper, "t_goal", None)
        self.span = goal - state.t if goal is not None and goal > state.t else None
        self.progress = Progress(self.span if self.span is not None else max(steps, 1), self.name,
                                 enabled=not self.disable, stream=self.stream, warmup=True)
        if not kernels.cached():  # before the other trackers' start, where the first kernel call compiles
            self.progress.note(COMPILING)

    def handle(self, state):
        reports = self.stepper.newton_reports
        self.iterations += sum(r.iterations for r in reports[self.seen:])
        self.seen = len(reports)
        done = state.t - self.t0 if self.span is not None else state.step - self.first
        self.progress.update(done, self.detail(state))

    def detail(self, state) -> str:
        """``"t = 0.3 of 1 s, 150 steps, 420 Newton iterations"`` (no iterations for the semi-implicit scheme)."""
        end = f" of {self.t0 + self.span:.4g}" if self.span is not None else ""
        newton = f", {self.iterations} Newton iterations" if self.seen else ""
        return f"t = {state.t:.4g}{end} s, {state.step - self.first} steps{newton}"

    def finalize(self, result):
        if self.progress is not None:
            self.progress.close()


class EnergyMonitor(Tracker):
    """Record the energy of eq. (13) (stretching, bending) and the kinetic energy.

    After the run, ``history`` is an array of rows (t, stretching, bending, kinetic).
    """

    def __init__(self, every: int = 1):
        self.every = count("EnergyMonitor.every", every)
        self.rows: list[tuple[float, float, float, float]] = []

    def _record(self, state):
        e = self.stepper.model.energy(state.X)
        self.rows.append((state.t, e.stretching, e.bending, self.stepper.model.kinetic_energy(state.V)))

    def initialize(self, state, stepper, steps):
        super().initialize(state, stepper, steps)
        self.rows = []
        self._record(state)

    def handle(self, state):
        self._record(state)

    @property
    def history(self) -> np.ndarray:
        return np.array(self.rows).reshape(-1, 4)


class DivergenceGuard(Tracker):
    """Stop a run that leaves finite numbers or the range where its states are physical.

    The bounds trip *before* the sheet is destroyed, so that the last good state a diverged run hands back is still
    a sheet: a blow-up grows the energy by orders of magnitude within a few steps, while a stable run's energy stays
    of the order of the work its loads can do.

    Parameters
    ----------
    max_displacement : float, optional
        Bound on max |X - X0| (scene units); default 100 times the diagonal of the parameter rectangle.
    max_stretch : float or None
        Bound on how much any grid edge between neighbouring nodes may grow against the initial state (default 3: an
        edge three times its length); None: unchecked.
    max_energy : float, optional
        Bound on the elastic energy of eq. (13) (J); unchecked by default.
    energy_growth : float or None
        Bound on the growth of the total energy E (elastic + kinetic): diverged when E exceeds ``energy_growth``
        times the larger of the scene's energy scale and the largest E seen more than :attr:`WINDOW` checks before
        (default 10). The scale is the largest of E at the start, the work of the loads at the start over one
        diagonal of the sheet (sum of |F| times the diagonal) and the energy of the sheet stretched by 10 %
        everywhere. None: unchecked.
    kinetic_budget : float or None
        Bound on the kinetic energy K against the energy the sheet can have received (default 2; must exceed 1):
        diverged when K exceeds ``kinetic_budget`` times its total energy at the start (eq. (13), kinetic, springs)
        plus an upper bound of the work done since by its loads (sum over the free coordinates of |F| times the
        path, max(|dX|, |V| dt), between checks) and by its held nodes (|internal force| times their prescribed
        path, and their own kinetic energy). The equation of motion (11) with a gradient force makes no energy, so a
        K above the budget is made by the numerics, or by a force that is no gradient (the paper's force (14)); a
        blow-up at the grid scale is stopped while the speeds are still those of the motion. Unchecked in a scene
        with obstacles, whose forces do work this budget does not bound. None: unchecked.
    max_speed : float or None
        Bound on the speed of any node (m/s); unchecked by default.
    every : int
        Cadence in steps (default 1).

    Attributes
    ----------
    last_good : State
        The last state that passed every check (the run's start before the first): with ``every`` > 1, the states
        between checks were never checked, and a run that diverges should hand back this one.
    """

    #: checks between the energies compared by ``energy_growth``
    WINDOW = 10

    def __init__(self, max_displacement: float | None = None, max_energy: float | None = None,
                 max_stretch: float | None = 3.0, every: int = 1, energy_growth: float | None = 10.0,
                 kinetic_budget: float | None = 2.0, max_speed: float | None = None):
        def bound(name, value, low=None):
            if value is None:
                return None
            x = real(f"DivergenceGuard.{name}", value, positive=True)
            if low is not None and not x > low:
                raise InputError(f"DivergenceGuard.{name} must be greater than {low}, got {value!r}",
                                 field=f"DivergenceGuard.{name}", value=value)
            return x

        self.max_displacement = bound("max_displacement", max_displacement)
        self.max_energy = bound("max_energy", max_energy)
        self.max_stretch = bound("max_stretch", max_stretch, 1.0)
        self.energy_growth = bound("energy_growth", energy_growth, 1.0)
        self.kinetic_budget = bound("kinetic_budget", kinetic_budget, 1.0)
        self.max_speed = bound("max_speed", max_speed)
        self.every = count("DivergenceGuard.every", every)

    @staticmethod
    def _edges(grid: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Lengths of the grid edges along a1 and a2, (M-1, N) and (M, N-1)."""
        return (np.linalg.norm(np.diff(grid, axis=0), axis=-1), np.linalg.norm(np.diff(grid, axis=1), axis=-1))

    def _energy(self, state) -> float:
        model = self.stepper.model
        return float(model.energy(state.X).total + model.kinetic_energy(state.V))

    def energy_scale(self, state) -> float:
        """The energy scale of the run at ``state`` (J): see ``energy_growth``."""
        model = self.stepper.model
        scene = model.scene
        L1, L2 = scene.sheet.size
        diagonal = float(np.hypot(L1, L2))
        work = float(np.sum(np.linalg.norm(model.load(state.X, state.t, state.V), axis=1))) * diagonal
        # eq. (13) with G = 1.21 G0 (10 % stretch) and B = B0: sum of eta_ii (0.21 G0_ii)^2 over the area
        eta = scene.nodal_material().tensor(scene.force_model.weights[0], scene.sheet.nodes)
        stretched = float(np.mean(eta[0, 0] + eta[1, 1])) * 0.21**2 * L1 * L2
        return max(self._energy(state), work, stretched)

    def initialize(self, state, stepper, steps):
        super().initialize(state, stepper, steps)
        reference = getattr(stepper, "reference", None)
        self.X0 = state.X if reference is None else reference  # the run's start, also when it is resumed
        self.last_good = state
        self.max_displacement_now = self.max_displacement
        if self.max_displacement_now is None:
            L1, L2 = stepper.model.scene.sheet.size
            self.max_displacement_now = 100.0 * float(np.hypot(L1, L2))
        if self.max_stretch is not None:
            h1, h2 = stepper.model.scene.sheet.h
            e1, e2 = self._edges(stepper.model.grid(self.X0))
            # an edge that starts collapsed is measured against a tenth of its parameter length
            self._edges0 = (np.maximum(e1, 0.1 * h1), np.maximum(e2, 0.1 * h2))
        if self.energy_growth is not None:
            self._scale = self.energy_scale(state)
            self._recent = deque(maxlen=self.WINDOW)
            self._old_peak = self._scale
        # the obstacles' forces (the barrier, TPBF87's repulsion) do work the budget does not bound: unchecked there
        self._budgeted = self.kinetic_budget is not None and not stepper.model.scene.obstacles
        if self._budgeted:
            model = stepper.model
            self._held = np.zeros(state.X.shape, bool)
            for a, dofs in enumerate(model.fixed_dofs()):
                self._held[np.asarray(dofs, dtype=np.int64), a] = True
            loads = getattr(model, "loads", None)
            springs = float(loads.potential_energy(state.X, state.t)) if loads is not None and loads.potentials \
                else 0.0
            self._budget = self._energy(state) + springs  # the energy at the start; the work done is added
            self._floor = 1e-12 * (self._scale if self.energy_growth is not None else self.energy_scale(state))
            self._last = (state.X, state.V, state.t, np.abs(model.load(state.X, state.t, state.V)))

    def memory(self) -> dict:
        """What the guard carries from check to check (J): a checkpoint keeps it, so that a resumed run's guard
        decides as the uninterrupted run's (:meth:`deformable.TimeStepper.memory`)."""
        out = {}
        if self.energy_growth is not None:
            out.update(old_peak=self._old_peak, recent=list(self._recent))
        if self._budgeted:
            out.update(budget=self._budget, floor=self._floor)
        return out

    def restore(self, memory: dict) -> None:
        """Take up :meth:`memory` after :meth:`initialize` (a resumed run)."""
        known_keys(memory, ("old_peak", "recent", "budget", "floor"), "in the divergence guard's memory")
        if self.energy_growth is not None and "old_peak" in memory:
            self._old_peak = real("DivergenceGuard.old_peak", memory["old_peak"], non_negative=True)
            self._recent = deque((real("DivergenceGuard.recent", e) for e in memory.get("recent", ())),
                                 maxlen=self.WINDOW)
        if self._budgeted and "budget" in memory:
            self._budget = real("DivergenceGuard.budget", memory["budget"], non_negative=True)
            self._floor = real("DivergenceGuard.floor", memory.get("floor", self._floor), non_negative=True)

    def _work(self, state) -> float:
        """An upper bound of the work done on the sheet since the last check (J): see ``kinetic_budget``."""
        model = self.stepper.model
        X0, V0, t0, F0 = self._last
        F = np.abs(model.load(state.X, state.t, state.V))
        path = np.maximum(np.abs(state.X - X0), 0.5 * (np.abs(V0) + np.abs(state.V)) * (state.t - t0))
        free = ~self._held
        work = float(np.sum((np.maximum(F0, F) * path)[free]))
        if np.any(path[self._held] > 0):  # prescribed motion: the held nodes push the sheet
            f = np.abs(model.internal_force(state.X)) + F
            work += float(np.sum((f * path)[self._held]))
        self._last = (state.X, state.V, state.t, F)
        return work

    def _speed(self, state) -> float:
        """The speed of the fastest node (m/s)."""
        return float(np.max(np.linalg.norm(self.stepper.model.grid(state.V), axis=-1)))

    def handle(self, state):
        where = f"at step {state.step} (t = {state.t:.6g} s)"
        if not (np.all(np.isfinite(state.X)) and np.all(np.isfinite(state.V))):
            return Stop(f"diverged {where}: non-finite state", diverged=True)
        d = float(np.max(np.abs(state.X - self.X0)))
        if d > self.max_displacement_now:
            return Stop(f"diverged {where}: displacement {d:.3g} exceeds {self.max_displacement_now:.3g}",
                        diverged=True)
        if self.max_stretch is not None:
            e1, e2 = self._edges(self.stepper.model.grid(state.X))
            s = max(float(np.max(e1 / self._edges0[0])), float(np.max(e2 / self._edges0[1])))
            if s > self.max_stretch:
                return Stop(f"diverged {where}: a grid edge stretched {s:.3g} times its initial length "
                            f"(bound {self.max_stretch:g})", diverged=True)
        if self.max_energy is not None:
            e = self.stepper.model.energy(state.X).total
            if not np.isfinite(e) or e > self.max_energy:
                return Stop(f"diverged {where}: energy {e:.3g} J exceeds {self.max_energy:.3g} J", diverged=True)
        if self.energy_growth is not None:
            e = self._energy(state)
            if not np.isfinite(e) or e > self.energy_growth * self._old_peak:
                return Stop(f"diverged {where}: the energy grew to {e:.3g} J, more than {self.energy_growth:g} "
                            f"times {self._old_peak:.3g} J (the scene's energy scale, or the largest energy "
                            f"{self.WINDOW} checks before)", diverged=True)
            if len(self._recent) == self.WINDOW:
                self._old_peak = max(self._old_peak, self._recent[0])
            self._recent.append(e)
        if self._budgeted:
            self._budget += self._work(state)
            model = self.stepper.model
            K = float(model.kinetic_energy(state.V))
            held = float(model.kinetic_energy(np.where(self._held, state.V, 0.0))) if self._held.any() else 0.0
            budget = max(self._budget + held, self._floor)
            if not np.isfinite(K) or K > self.kinetic_budget * budget:
                return Stop(f"diverged {where}: the kinetic energy {K:.3g} J (fastest node {self._speed(state):.3g} "
                            f"m/s) exceeds {self.kinetic_budget:g} times {budget:.3g} J, the energy at the start and "
                            "the most work the loads and held nodes can have done since: energy made by the "
                            "numerics, or by a force that is not the gradient of an energy (the paper's eq. (14))",
                            diverged=True)
        if self.max_speed is not None:
            v = self._speed(state)
            if not v <= self.max_speed:
                return Stop(f"diverged {where}: a node moves at {v:.3g} m/s, faster than {self.max_speed:.3g} m/s",
                            diverged=True)
        self.last_good = state
        return None


class SelfContactMonitor(Tracker):
    """How close the sheet comes to itself during a run: the smallest distance between primitives of its contact
    mesh that may touch, and the steps at which two of its triangles cross (:class:`deformable.ContactMesh`, the IPC
    Toolkit's distances and intersection test). It measures; it stops nothing.

    Parameters
    ----------
    distance : float
        The search distance (m): closer pairs are measured, and pairs closer than it in the rest mesh are never
        counted (neighbours, not folds).
    every : int
        Measure every ``every`` steps (and the first state).

    Attributes
    ----------
    times, distances : list of float
        The measured states' times (s) and smallest self-distances (m; inf: no pair within ``distance``).
    crossed : list of float
        The times (s) at which the mesh intersected itself.
    """

    def __init__(self, distance: float, every: int = 1):
        self.distance = real("SelfContactMonitor.distance", distance, positive=True)
        self.every = count("SelfContactMonitor.every", every)
        self.times, self.distances, self.crossed = [], [], []

    def initialize(self, state, stepper, steps: int) -> None:
        super().initialize(state, stepper, steps)
        self.mesh = ContactMesh(stepper.model, self.distance, rest=state.X)
        self.handle(state)

    def handle(self, state):
        self.times.append(float(state.t))
        self.distances.append(self.mesh.self_distance(state.X))
        if self.mesh.intersects(state.X):
            self.crossed.append(float(state.t))

    @property
    def smallest(self) -> float:
        """The smallest self-distance measured (m)."""
        return min(self.distances, default=float("inf"))
