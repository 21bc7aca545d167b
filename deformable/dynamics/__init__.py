"""Motion: the run controller (:mod:`.stepper`), its trackers, and the time-stepping schemes.

- :mod:`.state`: State, RunResult, DivergenceError;
- :mod:`.stepper`: TimeStepper, the controller (it knows no scheme);
- :mod:`.trackers`: progress, energy monitor, divergence guard, callbacks;
- :mod:`.scheme`: what a scheme is, the registry of schemes;
- :mod:`.semi_implicit`: the paper's eq. (22)-(27);
- :mod:`.implicit`: the Newton step on an incremental potential, shared by :mod:`.implicit_euler` and
  :mod:`.newmark`.
"""

from ..errors import DivergenceError, StalledError, StepRejected
from .implicit import Implicit
from .implicit_euler import ImplicitEuler
from .newmark import Newmark
from .scheme import Scheme
from .semi_implicit import SemiImplicit
from .state import RunResult, State
from .stepper import SCHEMES, TimeStepper
from .trackers import Callback, DivergenceGuard, EnergyMonitor, ProgressBar, SelfContactMonitor, Stop, Tracker

__all__ = ["DivergenceError", "RunResult", "StalledError", "State", "SCHEMES", "TimeStepper", "Callback",
           "DivergenceGuard", "EnergyMonitor", "ProgressBar", "SelfContactMonitor", "Stop", "Tracker", "Scheme", "SemiImplicit", "Implicit",
           "ImplicitEuler", "Newmark", "StepRejected"]
