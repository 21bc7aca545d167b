r"""Trackers: small observers of a run (py-pde's controller/tracker pattern).

Each tracker has a cadence ``every`` (in steps) and three hooks:
``initialize(state, stepper, steps)``, ``handle(state) -> Stop | None`` and
``finalize(result)``. Returning a :class:`Stop` from ``handle`` ends the run;
``Stop(diverged=True)`` discards the state just computed and hands back the
previous one.
"""

from __future__ import annotations

import logging
from collections import deque
from dataclasses import dataclass

import numpy as np

from ..checks import count, function, real
from ..errors import InputError

__all__ = ["Tracker", "Stop", "ProgressBar", "EnergyMonitor", "DivergenceGuard", "Callback"]

log = logging.getLogger(__name__)


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
    """A tqdm progress bar on stderr (silent when stderr is not a terminal)."""

    def __init__(self, every: int = 1, disable: bool | None = None):
        self.every, self.disable = count("ProgressBar.every", every), disable
        self.bar = None

    def initialize(self, state, stepper, steps):
        from tqdm.auto import tqdm

        super().initialize(state, stepper, steps)
        self.bar = tqdm(total=steps, unit="step", disable=self.disable, leave=False)
        self._last = state.step

    def handle(self, state):
        self.bar.update(state.step - self._last)
        self._last = state.step
        self.bar.set_postfix_str(f"t={state.t:.4g}s", refresh=False)

    def finalize(self, result):
        if self.bar is not None:
            self.bar.close()


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

    The bounds are meant to trip *before* the sheet is destroyed, so that the
    last good state a diverged run hands back (and the frames before it) are
    still a sheet: a blow-up of a time step grows the energy by orders of
    magnitude within a few steps and stretches the grid far beyond anything a
    cloth does, while a stable run's energy stays of the order of the work its
    loads can do.

    Parameters
    ----------
    max_displacement : float, optional
        Bound on max |X - X0| (scene units); default 100 times the diagonal
        of the parameter rectangle.
    max_stretch : float or None
        Bound on how much any grid edge between neighbouring nodes may grow
        against the initial state (default 3: an edge three times its length);
        None: unchecked.
    max_energy : float, optional
        Bound on the elastic energy of eq. (13) (J); unchecked by default.
    energy_growth : float or None
        Bound on the growth of the total energy E (elastic + kinetic): the run
        diverged when E exceeds ``energy_growth`` times the larger of the
        energy scale of the scene and the largest E seen more than
        :attr:`WINDOW` checks before (default 10). The scale is the largest of
        E at the start, the work of the loads at the start over one diagonal of
        the sheet (sum of |F| times the diagonal) and the energy of the sheet
        stretched by 10 % everywhere. None: unchecked.
    every : int
        Cadence in steps (default 1).
    """

    #: checks between the energies compared by ``energy_growth``
    WINDOW = 10

    def __init__(self, max_displacement: float | None = None, max_energy: float | None = None,
                 max_stretch: float | None = 3.0, every: int = 1, energy_growth: float | None = 10.0):
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
        eta = scene.material.tensor(scene.force_model.weights[0], scene.sheet.nodes)
        stretched = float(np.mean(eta[0, 0] + eta[1, 1])) * 0.21**2 * L1 * L2
        return max(self._energy(state), work, stretched)

    def initialize(self, state, stepper, steps):
        super().initialize(state, stepper, steps)
        self.X0 = state.X
        self.max_displacement_now = self.max_displacement
        if self.max_displacement_now is None:
            L1, L2 = stepper.model.scene.sheet.size
            self.max_displacement_now = 100.0 * float(np.hypot(L1, L2))
        if self.max_stretch is not None:
            h1, h2 = stepper.model.scene.sheet.h
            e1, e2 = self._edges(stepper.model.grid(state.X))
            # an edge that starts collapsed is measured against a tenth of its parameter length
            self._edges0 = (np.maximum(e1, 0.1 * h1), np.maximum(e2, 0.1 * h2))
        if self.energy_growth is not None:
            self._scale = self.energy_scale(state)
            self._recent = deque(maxlen=self.WINDOW)
            self._old_peak = self._scale

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
        return None
