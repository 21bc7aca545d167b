r"""Trackers: small observers of a run (py-pde's controller/tracker pattern).

Each tracker has a cadence ``every`` (in steps) and three hooks:
``initialize(state, stepper, steps)``, ``handle(state) -> Stop | None`` and
``finalize(result)``. Returning a :class:`Stop` from ``handle`` ends the run;
``Stop(diverged=True)`` discards the state just computed and hands back the
previous one.
"""

from __future__ import annotations

import logging
from dataclasses import dataclass

import numpy as np

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
        self.fn, self.every = fn, int(every)

    def handle(self, state):
        reason = self.fn(state)
        return Stop(reason) if isinstance(reason, str) else None


class ProgressBar(Tracker):
    """A tqdm progress bar on stderr (silent when stderr is not a terminal)."""

    def __init__(self, every: int = 1, disable: bool | None = None):
        self.every, self.disable = int(every), disable
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
        self.every = int(every)
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
    """Stop a run that leaves finite numbers or a bound.

    Parameters
    ----------
    max_displacement : float, optional
        Bound on max |X - X0| (scene units); default 100 times the diagonal
        of the parameter rectangle.
    max_stretch : float, optional
        Bound on how much any grid edge between neighbouring nodes may grow
        against the initial state (default 10: a sheet stretched tenfold has
        left the model's range long before it overflows, so the last good
        state handed back is still meaningful).
    max_energy : float, optional
        Bound on the elastic energy of eq. (13) (J); unchecked by default
        (it costs an energy evaluation each ``every`` steps).
    """

    def __init__(self, max_displacement: float | None = None, max_energy: float | None = None,
                 max_stretch: float | None = 10.0, every: int = 1):
        self.max_displacement, self.max_energy, self.every = max_displacement, max_energy, int(every)
        self.max_stretch = max_stretch

    @staticmethod
    def _edges(grid: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Lengths of the grid edges along a1 and a2, (M-1, N) and (M, N-1)."""
        return (np.linalg.norm(np.diff(grid, axis=0), axis=-1), np.linalg.norm(np.diff(grid, axis=1), axis=-1))

    def initialize(self, state, stepper, steps):
        super().initialize(state, stepper, steps)
        self.X0 = state.X
        if self.max_displacement is None:
            L1, L2 = stepper.model.scene.sheet.size
            self.max_displacement = 100.0 * float(np.hypot(L1, L2))
        if self.max_stretch is not None:
            h1, h2 = stepper.model.scene.sheet.h
            e1, e2 = self._edges(stepper.model.grid(state.X))
            # an edge that starts collapsed is measured against a tenth of its parameter length
            self._edges0 = (np.maximum(e1, 0.1 * h1), np.maximum(e2, 0.1 * h2))

    def handle(self, state):
        where = f"at step {state.step} (t = {state.t:.6g} s)"
        if not (np.all(np.isfinite(state.X)) and np.all(np.isfinite(state.V))):
            return Stop(f"diverged {where}: non-finite state", diverged=True)
        d = float(np.max(np.abs(state.X - self.X0)))
        if d > self.max_displacement:
            return Stop(f"diverged {where}: displacement {d:.3g} exceeds {self.max_displacement:.3g}", diverged=True)
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
        return None
