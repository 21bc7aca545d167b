"""deformable: the Terzopoulos et al. (1987) elastic-surface model, shared by two discretisations.

This package holds what both backends discretise, a wing per job, each
importing only the wings below it (docs/design.md, "The map"):

- :mod:`deformable.errors` (every exception and warning) and the ground floor:
  :mod:`deformable.checks`, :mod:`deformable.registry` (the one registry of every
  extension point), :mod:`deformable.limits`, :mod:`deformable.tomlio`;
- :mod:`deformable.geometry`: the tensors of eq. (4)-(8), surfaces, the sheet,
  the paper's compatibility test (section 3.2);
- :mod:`deformable.algebra`: sparse patterns, assembly and solvers;
- :mod:`deformable.physics`: material, the force models (eq. (13)-(15) and any
  energy density one adds, :class:`ForceModel`), forces and loads;
- :mod:`deformable.contact`: rigid obstacles and the barrier;
- :mod:`deformable.scene`: a :class:`Scene` and its constraints;
- :mod:`deformable.backends`: the contract both discretisations satisfy and
  their registry;
- :mod:`deformable.solve`: Newton's method, its line searches, equilibrium;
- :mod:`deformable.dynamics`: the time stepping of eq. (22)-(27) and the
  implicit schemes, under one controller;
- :mod:`deformable.scenes`: the catalogue of the paper's scenes (section 5) and
  scene files;
- :mod:`deformable.io`: the output of runs (an XDMF series for ParaView,
  frames rendered from it, checkpoints);
- :mod:`deformable.session`: a run as one object, :class:`Simulation` (config,
  backend by name, output folder; its model, stepper, run, resume, checkpoints).

The backends are ``fdmodel.FDModel`` (finite differences) and
``femodel.FEModel`` (finite elements); the validation harness and the command
line live in ``validation``.
"""

import warnings

from .backends.contract import Backend, EnergyBackend, Sample
from .contact.meshobstacle import MeshObstacle
from .contact.obstacles import Box, Cylinder, HalfSpace, Sphere
from .contact.clearance import clearance
from .contact.selfmesh import ContactMesh
from .contact.settings import Contact
from .dynamics import (
    SCHEMES,
    Callback,
    DivergenceError,
    DivergenceGuard,
    EnergyMonitor,
    ProgressBar,
    RunResult,
    SelfContactMonitor,
    StalledError,
    State,
    Stop,
    TimeStepper,
    Tracker,
)
from .errors import (
    CheckpointError,
    ConvergenceError,
    DeformableError,
    IllPosedScene,
    IncompatibleRestState,
    InputError,
    LoadBelowRoundOff,
    NumericalError,
    OutputFolderError,
    ResourceError,
    SelfContactIgnored,
    UnstableEquilibrium,
    WriteError,
)
from .geometry.compatibility import check_compatibility, check_rest_state
from .geometry.sheet import Sheet
from .geometry.surfaces import Surface, as_surface
from .geometry.tensors import curvature, gaussian_curvature, metric, normal
from .io import (
    CheckpointWriter,
    RunFolder,
    XDMFWriter,
    load_checkpoint,
    read_series,
    render_frame,
    render_series,
    save_checkpoint,
)
from .physics.energy import Energy
from .physics.fabric import Fabric
from .physics.force_models import EnergyModel, ForceModel, Koiter, Orthotropic, StrengthModel
from .physics.forces import BodyForce, EdgeLoad, EdgeMoment, Gravity, PointLoad, Pressure, Sinusoidal, Spring, Wind
from .physics.material import Material
from .scene.constraints import Clamp, Pin, Slide, Symmetry, select
from .scene.scene import Scene
from .session import Simulation
from .solve.continuation import equilibrium_path
from .solve.equilibrium import equilibrium

from .checks import installed_version as _installed_version

__version__ = _installed_version()  # the installed distribution's (deformable-sheets): pyproject.toml is its source

__all__ = ["IncompatibleRestState", "check_compatibility", "check_rest_state", "Backend", "EnergyBackend", "Energy",
    "Sample", "ConvergenceError", "equilibrium", "equilibrium_path", "Clamp", "Pin", "Slide", "Symmetry", "select", "BodyForce", "EdgeLoad", "EdgeMoment", "Pressure", "Gravity",
    "PointLoad", "Sinusoidal", "Spring", "Wind", "Material", "ForceModel", "EnergyModel", "StrengthModel", "Koiter", "Orthotropic", "Fabric",
    "IllPosedScene", "Scene", "Sheet", "Surface", "as_surface", "DivergenceError", "StalledError", "RunResult", "State",
    "TimeStepper", "SCHEMES", "curvature", "gaussian_curvature", "metric", "normal", "Callback", "DivergenceGuard",
    "EnergyMonitor", "ProgressBar", "Stop", "Tracker", "__version__", "DeformableError", "InputError",
    "CheckpointError", "OutputFolderError", "ResourceError", "WriteError", "NumericalError", "XDMFWriter",
    "read_series", "render_series", "render_frame", "CheckpointWriter", "save_checkpoint", "load_checkpoint",
    "RunFolder", "Contact", "clearance", "ContactMesh", "SelfContactMonitor", "HalfSpace", "Sphere", "Box", "Cylinder", "MeshObstacle",
    "LoadBelowRoundOff", "SelfContactIgnored",
    "UnstableEquilibrium", "Simulation"]

#: former names: the value a caller gets, and what to use instead (each warns once, DeprecationWarning)
_FORMER = {"FORCE_MODELS": (lambda: ForceModel.names(), "deformable.ForceModel.names()")}


def __getattr__(name):
    if name in _FORMER:
        value, instead = _FORMER[name]
        warnings.warn(f"deformable.{name} is deprecated; use {instead}", DeprecationWarning, stacklevel=2)
        return value()
    raise AttributeError(f"module 'deformable' has no attribute {name!r}")
