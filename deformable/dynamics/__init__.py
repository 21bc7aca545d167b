"""Motion: the run controller (:mod:`.stepper`), its trackers, and the time-stepping schemes.

- :mod:`.state`: State, RunResult, DivergenceError;
- :mod:`.stepper`: TimeStepper, the controller;
- :mod:`.trackers`: progress, energy monitor, divergence guard, callbacks;
- :mod:`.semi_implicit`: the paper's eq. (22)-(27);
- :mod:`.implicit`: implicit Euler and Newmark on an incremental potential.
"""

from .state import DivergenceError, RunResult, StalledError, State
from .stepper import SCHEMES, TimeStepper
from .trackers import Callback, DivergenceGuard, EnergyMonitor, ProgressBar, Stop, Tracker

__all__ = ["DivergenceError", "RunResult", "StalledError", "State", "SCHEMES", "TimeStepper", "Callback", "DivergenceGuard",
           "EnergyMonitor", "ProgressBar", "Stop", "Tracker"]
