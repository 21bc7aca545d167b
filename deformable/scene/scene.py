r"""A scene: sheet, material, forces, constraints, obstacles and the force model.

The force model is a registered object (:mod:`deformable.physics.force_models`), given by its name or as
an instance: ``"tpbf87"`` (the paper's force (14)-(15), not the gradient of the energy (13)),
``"frozen"`` (alpha_ij and beta_ij given directly, section 3.2), ``"variational"`` (the exact gradient of
eq. (13)), or any registered :class:`~deformable.physics.force_models.EnergyModel` (docs/design.md, "The
continuous model").
"""

from __future__ import annotations

import logging
import warnings
from dataclasses import dataclass, field, replace

import numpy as np

from ..checks import sequence
from ..contact.obstacles import Obstacle
from ..contact.settings import Contact
from ..errors import IllPosedScene, InputError
from ..geometry.compatibility import warn_if_incompatible
from ..geometry.sheet import Sheet
from ..physics.force_models import ForceModel
from ..physics.forces import ROLES
from ..physics.material import Material
from .constraints import Clamp, Pin, Slide, Symmetry

__all__ = ["Scene"]

log = logging.getLogger(__name__)


def _tensor_override(name: str, value):
    """None, a constant symmetric 2 x 2 tensor, or a callable (a1, a2) -> (..., 2, 2)."""
    if value is None or callable(value):
        return value
    arr = np.asarray(value, float)
    if arr.ndim == 0:
        arr = arr * np.eye(2)
    if arr.shape != (2, 2) or not np.all(np.isfinite(arr)) or arr[0, 1] != arr[1, 0]:
        raise InputError(f"Scene.{name} must be a number, a symmetric finite 2 x 2 tensor or a callable, got {value!r}")
    return arr


@dataclass(frozen=True)
class Scene:
    """Everything a backend needs to discretise one problem.

    Parameters
    ----------
    sheet : Sheet
    material : Material
    forces : sequence of Load
        Gravity, BodyForce, EdgeLoad, EdgeMoment, PointLoad, Pressure, Spring, Wind, or a user's load: any
        subclass of a role of :class:`deformable.physics.forces.Load` (asked what it adds, never named).
    constraints : sequence of Pin, Slide, Clamp, Symmetry
    force_model : str or ForceModel
        The force of eq. (11): a registered name ("tpbf87", "frozen", "variational", or a user's energy
        model's) or a ForceModel instance; kept as the instance. The default, "tpbf87", is the paper's force
        (14)-(15) as written, so that a bare Scene is the paper's model; it is not the gradient of the
        energy (13), has no linear bending stiffness about a flat sheet and no stiffness in compression.
        For a physical sheet choose "variational" (the exact gradient of eq. (13), stepped implicitly) with
        full weight tensors, as the shipped scenes (:mod:`deformable.scenes`), the command line and the
        README do.
    rest_metric, rest_curvature : optional
        G0 and B0 overriding those of the rest shape: a number s (s I), a
        symmetric 2 x 2 tensor, or a callable (a1, a2) -> (..., 2, 2).
    name : str
        A label for outputs.
    obstacles : sequence of deformable.contact.obstacles.Obstacle
        Rigid obstacles the sheet must stay outside of (:mod:`deformable.contact.obstacles`).
    contact : deformable.Contact, optional
        How the sheet meets them (:mod:`deformable.contact`); default ``Contact()`` when there are obstacles.

    Warns
    -----
    IncompatibleRestState
        When rest_metric / rest_curvature override the rest shape with a pair
        that is not the metric and curvature of any surface (eq. 10, section 3.2).
    IllPosedScene
        When the force model leaves deformations free at these weights (the variational model without
        eta_12, or xi_12 with bending: shear (twist) then costs nothing, a compressed sheet shears in its own
        plane and a static problem has no unique solution).
    """

    sheet: Sheet
    material: Material
    forces: tuple = ()
    constraints: tuple = ()
    force_model: str | ForceModel = "tpbf87"
    rest_metric: object = None
    rest_curvature: object = None
    name: str = "scene"
    notes: str = field(default="", compare=False)
    obstacles: tuple = ()
    contact: Contact | None = None

    def __post_init__(self):
        if not isinstance(self.sheet, Sheet):
            raise InputError(f"Scene.sheet must be a Sheet, got {self.sheet!r}")
        if not isinstance(self.material, Material):
            raise InputError(f"Scene.material must be a Material, got {self.material!r}")
        try:
            force_model = ForceModel.of(self.force_model)
        except InputError:
            raise InputError(f"Scene.force_model must be one of {', '.join(ForceModel.names())} or a ForceModel, "
                             f"got {self.force_model!r}", field="Scene.force_model", value=self.force_model) from None
        force_model.check(self.material)
        object.__setattr__(self, "force_model", force_model)
        self.material.check(self.sheet.nodes)
        nodal = self.nodal_material()  # evaluates a callable weight at the nodes: an InputError naming it
        forces = sequence("Scene.forces", self.forces, ROLES, "Gravity, BodyForce, EdgeLoad, EdgeMoment, PointLoad, "
                          "Pressure, Spring, Wind or another load (a subclass of AppliedLoad, ConservativeLoad or "
                          "VelocityLoad, deformable.physics.forces)")
        for f in forces:
            f.check(self.sheet)  # a point load's or a spring's point inside the rectangle, or an InputError naming it
        constraints = sequence("Scene.constraints", self.constraints, (Pin, Slide, Clamp, Symmetry),
                               "Pin, Slide, Clamp or Symmetry")
        if not isinstance(self.name, str):
            raise InputError(f"Scene.name must be a string, got {self.name!r}", field="Scene.name", value=self.name)
        object.__setattr__(self, "forces", forces)
        object.__setattr__(self, "constraints", constraints)
        obstacles = (self.obstacles,) if isinstance(self.obstacles, Obstacle) else tuple(self.obstacles)
        for o in obstacles:
            if not isinstance(o, Obstacle):
                raise ValueError(f"Scene.obstacles: {o!r} is not an obstacle (deformable.contact.obstacles)")
        if self.contact is not None and not isinstance(self.contact, Contact):
            raise ValueError(f"Scene.contact must be a deformable.Contact, got {self.contact!r}")
        object.__setattr__(self, "obstacles", obstacles)
        if obstacles and self.contact is None:
            object.__setattr__(self, "contact", Contact())
        object.__setattr__(self, "rest_metric", _tensor_override("rest_metric", self.rest_metric))
        object.__setattr__(self, "rest_curvature", _tensor_override("rest_curvature", self.rest_curvature))
        free = force_model.free_modes(nodal)
        if free:
            warnings.warn(f"scene {self.name!r}: the {force_model.name} model leaves {' and '.join(free)} free: "
                          "those deformations cost no energy, a compressed sheet shears in its own plane and a "
                          "static problem has no unique solution; give full weight tensors, e.g. "
                          "eta = [[eta, eta], [eta, eta]] (and the same for xi), the isotropic sheet with Poisson "
                          "ratio 0 (shear = 1 in a scene file)", IllPosedScene, stacklevel=3)
        if self.rest_metric is not None or self.rest_curvature is not None:
            # a rest shape alone is always compatible; overrides may not be (eq. 10)
            warn_if_incompatible(self, stacklevel=4)  # the caller of Scene(...)

    def rest_tensors(self, a1, a2, G: np.ndarray, B: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """G0 and B0 at points (a1, a2) of shape S, each (2, 2, *S).

        ``G`` and ``B`` (2, 2, *S) are the backend's own tensors of the
        discretised rest shape; ``rest_metric`` / ``rest_curvature`` override them.
        """
        out = []
        for name, default in (("rest_metric", G), ("rest_curvature", B)):
            value = getattr(self, name)
            if value is None:
                out.append(default)
            elif callable(value):
                field = np.asarray(value(a1, a2), float)
                if field.shape != np.shape(a1) + (2, 2):
                    raise InputError(f"Scene.{name} callable returned shape {field.shape}, "
                                     f"expected {np.shape(a1) + (2, 2)}")
                out.append(np.moveaxis(field, (-2, -1), (0, 1)))
            else:
                out.append(np.broadcast_to(value.reshape((2, 2) + (1,) * np.ndim(a1)), default.shape).copy())
        for name, T in zip(("metric G0", "curvature B0"), out):
            bad = ~np.all(np.isfinite(T), axis=(0, 1))
            if np.any(bad):
                where = tuple(float(np.asarray(a)[bad].flat[0]) for a in np.broadcast_arrays(a1, a2))
                raise InputError(f"the rest {name} is not finite at (a1, a2) = {where}: Sheet.rest must be a finite "
                                 "surface with independent tangents r_1, r_2 there", field="Sheet.rest")
        return out[0], out[1]

    def nodal_material(self) -> Material:
        """The material with its callables evaluated at the sheet's nodes (:meth:`Material.nodal`)."""
        return self.material.nodal(self.sheet)

    def with_nodes(self, nodes: tuple[int, int]) -> Scene:
        """The same scene on another node grid (per-node material arrays must be scalars or callables)."""
        return replace(self, sheet=self.sheet.with_nodes(nodes))
