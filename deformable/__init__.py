"""deformable: the Terzopoulos et al. (1987) elastic-surface model, shared by two discretisations.

This package holds what both backends discretise (numpy/scipy only): the sheet,
material, forces, constraints and scene, the tensors of eq. (4)-(8), the
backend protocol and the time stepper of eq. (22)-(27). The backends are
``fdmodel.FDModel`` (finite differences) and ``femodel.FEModel`` (finite
elements); the validation harness and the command line live in ``validation``.
"""

from .backend import Backend, Energy, EnergyBackend, Sample
from .compatibility import IncompatibleRestState, check_compatibility, check_rest_state
from .constraints import Clamp, Pin, Slide, select
from .implicit import ConvergenceError, equilibrium
from .forces import BodyForce, EdgeLoad, Gravity, PointLoad, Sinusoidal
from .material import Material
from .scene import FORCE_MODELS, Scene
from .sheet import Sheet, Surface, as_surface
from .stepper import DivergenceError, RunResult, State, TimeStepper
from .tensors import curvature, gaussian_curvature, metric, normal
from .trackers import Callback, DivergenceGuard, EnergyMonitor, ProgressBar, Stop, Tracker

__version__ = "0.1.0"

__all__ = [
    "IncompatibleRestState", "check_compatibility", "check_rest_state", "Backend", "EnergyBackend", "Energy", "Sample", "ConvergenceError", "equilibrium", "Clamp", "Pin", "Slide", "select", "BodyForce", "EdgeLoad", "Gravity",
    "PointLoad", "Sinusoidal", "Material", "FORCE_MODELS", "Scene", "Sheet", "Surface", "as_surface",
    "DivergenceError", "RunResult", "State", "TimeStepper", "curvature", "gaussian_curvature", "metric",
    "normal", "Callback", "DivergenceGuard", "EnergyMonitor", "ProgressBar", "Stop", "Tracker", "__version__",
]
