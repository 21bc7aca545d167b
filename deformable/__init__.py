"""deformable: the Terzopoulos et al. (1987) elastic-surface model, shared by two discretisations.

This package holds what both backends discretise: the sheet, material,
forces, constraints and scene, the tensors of eq. (4)-(8) and the elastic law
of eq. (13)-(15), the backend contract, fixed-pattern sparse assembly, the time
stepping of eq. (22)-(27) and the implicit schemes, static equilibrium, the
paper's compatibility test and scenes, rigid obstacles and contact
(:mod:`deformable.obstacles`, :mod:`deformable.contact`; the obstacle plane is
``deformable.HalfSpace``, also ``deformable.obstacles.Plane``), and the output of runs (an XDMF
series for ParaView, frames rendered from it, checkpoints). The backends are ``fdmodel.FDModel``
(finite differences) and ``femodel.FEModel`` (finite elements); the validation
harness and the command line live in ``validation``. The design is in
docs/design.md.
"""

from .backend import Backend, Energy, EnergyBackend, Sample
from .compatibility import IncompatibleRestState, check_compatibility, check_rest_state
from .constraints import Clamp, Pin, Slide, select
from .contact import Contact, clearance
from .dynamics import (
                       SCHEMES,
                       Callback,
                       DivergenceError,
                       DivergenceGuard,
                       EnergyMonitor,
                       ProgressBar,
                       RunResult,
                       StalledError,
                       State,
                       Stop,
                       TimeStepper,
                       Tracker,
)
from .equilibrium import equilibrium
from .errors import (
                       CheckpointError,
                       DeformableError,
                       InputError,
                       NumericalError,
                       OutputFolderError,
                       ResourceError,
                       WriteError,
)
from .forces import BodyForce, EdgeLoad, Gravity, PointLoad, Sinusoidal, Spring, Wind
from .material import Material
from .newton import ConvergenceError
from .obstacles import Box, Cylinder, HalfSpace, Sphere
from .output import (
                       CheckpointWriter,
                       RunFolder,
                       XDMFWriter,
                       load_checkpoint,
                       read_series,
                       render_frame,
                       render_series,
                       save_checkpoint,
)
from .scene import FORCE_MODELS, IllPosedScene, Scene
from .sheet import Sheet, Surface, as_surface
from .tensors import curvature, gaussian_curvature, metric, normal

__version__ = "0.1.0"

__all__ = [
    "IncompatibleRestState", "check_compatibility", "check_rest_state", "Backend", "EnergyBackend", "Energy", "Sample",
    "ConvergenceError", "equilibrium", "Clamp", "Pin", "Slide", "select", "BodyForce", "EdgeLoad", "Gravity",
    "PointLoad", "Sinusoidal", "Spring", "Wind", "Material", "FORCE_MODELS", "IllPosedScene", "Scene", "Sheet", "Surface", "as_surface",
    "DivergenceError", "StalledError", "RunResult", "State", "TimeStepper", "SCHEMES", "curvature", "gaussian_curvature", "metric",
    "normal", "Callback", "DivergenceGuard", "EnergyMonitor", "ProgressBar", "Stop", "Tracker", "__version__",
    "DeformableError", "InputError", "CheckpointError", "OutputFolderError", "ResourceError", "WriteError",
    "NumericalError", "XDMFWriter", "read_series", "render_series", "render_frame", "CheckpointWriter",
    "save_checkpoint", "load_checkpoint", "RunFolder",
    "Contact", "clearance", "HalfSpace", "Sphere", "Box", "Cylinder",
]
