r"""What a run produces: states, the outcome of a run, and the error of a diverging step."""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from ..errors import NumericalError

__all__ = ["State", "RunResult", "DivergenceError", "StalledError"]


@dataclass(frozen=True)
class State:
    """A point of the trajectory: time t (s), positions X and velocities V, (ndof, 3), and the step number.

    ``A``, (ndof, 3) or None: the acceleration the implicit schemes found at this state (m/s^2); Newmark
    steps from it and both schemes start their Newton search with it (a checkpoint keeps it, so that a
    resumed run is the same run).
    """

    t: float
    X: np.ndarray
    V: np.ndarray
    step: int = 0
    A: np.ndarray | None = None


class DivergenceError(NumericalError):
    """The run left the range of finite numbers or a tracker's bound; ``state`` is the last good one."""

    def __init__(self, message: str, state: State):
        super().__init__(message)
        self.state = state


class StalledError(NumericalError):
    """An implicit step did not converge even at the smallest allowed dt; ``state`` is the last good one."""

    def __init__(self, message: str, state: State):
        super().__init__(message)
        self.state = state


@dataclass
class RunResult:
    """Outcome of :meth:`deformable.TimeStepper.run`.

    ``state`` is the last good state; ``status`` is "finished", "stopped" (a
    tracker asked to stop), "diverged" (non-finite, or a tracker's bound) or
    "stalled" (an implicit step did not converge down to the smallest dt);
    ``message`` says why.
    """

    state: State
    status: str
    message: str
    steps: int
    wall_time: float
    trackers: list = field(default_factory=list)
