r"""A scene: sheet, material, forces, constraints and the named force model.

Force models (docs/design.md, "The continuous model"):

- ``"tpbf87"``: the papers' force (14)-(15), ``e = sum_ij -d_i(alpha_ij d_j r)
  + d_ij(beta_ij d_ij r)`` with ``alpha_ij = eta_ij (G_ij - G0_ij)`` and
  ``beta_ij = xi_ij (B_ij - B0_ij)`` frozen at the current r (eq. (20): K(r)).
  It is *not* the gradient of the energy (13).
- ``"frozen"``: alpha_ij and beta_ij given directly as material parameters
  (section 3.2); linear, the controlled-continuity spline.
- ``"variational"``: the exact gradient of the discrete energy (13).
"""

from __future__ import annotations

import logging
from dataclasses import dataclass, field, replace

import numpy as np

from .compatibility import warn_if_incompatible
from .constraints import Clamp, Pin, Slide
from .contact import Contact
from .forces import BodyForce, EdgeLoad, Gravity, PointLoad, Spring, Wind
from .material import Material
from .obstacles import Obstacle
from .sheet import Sheet

__all__ = ["Scene", "FORCE_MODELS"]

FORCE_MODELS = ("tpbf87", "frozen", "variational")
log = logging.getLogger(__name__)


def _tensor_override(name: str, value):
    """None, a constant symmetric 2 x 2 tensor, or a callable (a1, a2) -> (..., 2, 2)."""
    if value is None or callable(value):
        return value
    arr = np.asarray(value, float)
    if arr.ndim == 0:
        arr = arr * np.eye(2)
    if arr.shape != (2, 2) or not np.all(np.isfinite(arr)) or arr[0, 1] != arr[1, 0]:
        raise ValueError(f"Scene.{name} must be a number, a symmetric finite 2 x 2 tensor or a callable, got {value!r}")
    return arr


@dataclass(frozen=True)
class Scene:
    """Everything a backend needs to discretise one problem.

    Parameters
    ----------
    sheet : Sheet
    material : Material
    forces : sequence of Gravity, BodyForce, EdgeLoad, PointLoad, Spring, Wind
    constraints : sequence of Pin, Slide, Clamp
    force_model : "tpbf87" | "frozen" | "variational"
    rest_metric, rest_curvature : optional
        G0 and B0 overriding those of the rest shape: a number s (s I), a
        symmetric 2 x 2 tensor, or a callable (a1, a2) -> (..., 2, 2).
    name : str
        A label for outputs.
    obstacles : sequence of deformable.obstacles.Obstacle
        Rigid obstacles the sheet must stay outside of (:mod:`deformable.obstacles`).
    contact : deformable.Contact, optional
        How the sheet meets them (:mod:`deformable.contact`); default ``Contact()`` when there are obstacles.

    Warns
    -----
    IncompatibleRestState
        When rest_metric / rest_curvature override the rest shape with a pair
        that is not the metric and curvature of any surface (eq. 10, section 3.2).
    """

    sheet: Sheet
    material: Material
    forces: tuple = ()
    constraints: tuple = ()
    force_model: str = "tpbf87"
    rest_metric: object = None
    rest_curvature: object = None
    name: str = "scene"
    notes: str = field(default="", compare=False)
    obstacles: tuple = ()
    contact: Contact | None = None

    def __post_init__(self):
        if not isinstance(self.sheet, Sheet):
            raise ValueError(f"Scene.sheet must be a Sheet, got {self.sheet!r}")
        if not isinstance(self.material, Material):
            raise ValueError(f"Scene.material must be a Material, got {self.material!r}")
        if self.force_model not in FORCE_MODELS:
            raise ValueError(f"Scene.force_model must be one of {FORCE_MODELS}, got {self.force_model!r}")
        if self.force_model == "frozen" and self.material.alpha is None and self.material.beta is None:
            raise ValueError("Scene.force_model 'frozen' needs Material.alpha and/or Material.beta")
        self.material.check(self.sheet.nodes)
        forces = tuple(self.forces)
        for f in forces:
            if not isinstance(f, (Gravity, BodyForce, EdgeLoad, PointLoad, Spring, Wind)):
                raise ValueError(f"Scene.forces: {f!r} is not a Gravity, BodyForce, EdgeLoad, PointLoad, Spring or Wind")
            if isinstance(f, (PointLoad, Spring)):
                self.sheet.locate(f.at, f"{type(f).__name__}.at")  # inside the rectangle, or a ValueError naming it
        constraints = tuple(self.constraints)
        for c in constraints:
            if not isinstance(c, (Pin, Slide, Clamp)):
                raise ValueError(f"Scene.constraints: {c!r} is not a Pin, Slide or Clamp")
        object.__setattr__(self, "forces", forces)
        object.__setattr__(self, "constraints", constraints)
        obstacles = (self.obstacles,) if isinstance(self.obstacles, Obstacle) else tuple(self.obstacles)
        for o in obstacles:
            if not isinstance(o, Obstacle):
                raise ValueError(f"Scene.obstacles: {o!r} is not an obstacle (deformable.obstacles)")
        if self.contact is not None and not isinstance(self.contact, Contact):
            raise ValueError(f"Scene.contact must be a deformable.Contact, got {self.contact!r}")
        object.__setattr__(self, "obstacles", obstacles)
        if obstacles and self.contact is None:
            object.__setattr__(self, "contact", Contact())
        object.__setattr__(self, "rest_metric", _tensor_override("rest_metric", self.rest_metric))
        object.__setattr__(self, "rest_curvature", _tensor_override("rest_curvature", self.rest_curvature))
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
                    raise ValueError(f"Scene.{name} callable returned shape {field.shape}, "
                                     f"expected {np.shape(a1) + (2, 2)}")
                out.append(np.moveaxis(field, (-2, -1), (0, 1)))
            else:
                out.append(np.broadcast_to(value.reshape((2, 2) + (1,) * np.ndim(a1)), default.shape).copy())
        return out[0], out[1]

    def with_nodes(self, nodes: tuple[int, int]) -> Scene:
        """The same scene on another node grid (per-node material arrays must be scalars)."""
        return replace(self, sheet=self.sheet.with_nodes(nodes))
