r"""What a run produces: states and the outcome of a run (its errors are :mod:`deformable.errors`')."""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

__all__ = ["State", "RunResult"]


@dataclass(frozen=True)
class State:
    """A point of the trajectory: time t (s), positions X and velocities V, (ndof, 3), and the step number.

    ``A``, (ndof, 3) or None: the acceleration the implicit schemes found at this state (m/s^2); Newmark steps from
    it and both schemes start their Newton search with it (a checkpoint keeps it, so that a resumed run is the same
    run).
    """

    t: float
    X: np.ndarray
    V: np.ndarray
    step: int = 0
    A: np.ndarray | None = None


@dataclass
class RunResult:
    """Outcome of :meth:`deformable.TimeStepper.run`.

    ``state`` is the last good state; ``status`` is "finished", "stopped" (a tracker asked to stop), "diverged"
    (non-finite, or a tracker's bound) or "stalled" (an implicit step did not converge down to the smallest dt);
    ``message`` says why.
    """

    state: State
    status: str
    message: str
    steps: int
    wall_time: float
    trackers: list = field(default_factory=list)
