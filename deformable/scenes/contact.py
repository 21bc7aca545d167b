r"""Scenes with obstacles (:mod:`deformable.contact`): a cloth on the floor, on a ball, on a round table.

``floor``
    A square cloth, flat and horizontal, falling onto the floor (a
    :class:`~deformable.contact.obstacles.HalfSpace` at z = 0) and settling there.
``sphere``
    A square cloth dropped centred onto a ball, draping over it.
``drape``
    The Cusick drape test (Cusick 1968, "The measurement of fabric drape",
    J. Text. Inst. 59, 253-260; BS 5058): a square cloth 30 cm a side on a
    round table 18 cm across (a :class:`~deformable.contact.obstacles.Cylinder`
    with a rounded rim), of a stiff fabric (xi = 3e-4 N m, a bending length of
    6.7 cm) whose folds the quick grids resolve, with four contact points per
    cell side (``Contact(samples=4)``) so that the table's rim holds the cloth
    where it is and not at the nearest node. Its drape coefficient
    ``DC = (A_s - A_d) / (A_D - A_d)`` (A_s the area of the draped cloth's
    shadow, A_d the table's, A_D the flat cloth's) is measured by
    :mod:`validation.harness.drape`: 1 for a cloth that stays flat, 0 for one
    that hangs straight down.

The cloth of all three: mu = 0.2 kg/m^2, gamma = 0.1 kg/(m^2 s), eta = 20 N/m, xi = 1e-5 N m, friction 0.3
against the obstacles and a barrier active within 1 mm.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import ClassVar

from ..contact.obstacles import Cylinder, HalfSpace, Sphere
from ..contact.settings import Contact
from ..geometry.sheet import Sheet
from ..geometry.surfaces import Plane
from ..physics.forces import Gravity
from ..scene.scene import Scene
from .config import SceneConfig
from .shapes import HORIZONTAL

__all__ = ["FloorConfig", "SphereConfig", "DrapeConfig"]


@dataclass(frozen=True, kw_only=True)
class ClothOnObstacle(SceneConfig):
    """The cloth of the contact scenes (module docstring): friction 0.3, a barrier within 1 mm."""

    contact: Contact | None = Contact(distance=1e-3, friction=0.3)


@dataclass(frozen=True, kw_only=True)
class FloorConfig(ClothOnObstacle):
    """A cloth falling onto the floor (the plane z = 0).

    Parameters
    ----------
    height : float
        The sheet's starting height above the floor (m). From rest it lands at sqrt(2 g height).
    tilt : float
        The start's tilt about the a2 direction, 0: falling flat (deg).
    """

    name = "floor"
    rank = 5
    summary = "cloth falling flat onto the floor and settling (contact)"
    t_end: float = 1.0

    height: float = 0.3
    tilt: float = 0.0
    POSITIVE: ClassVar[tuple] = SceneConfig.POSITIVE + ("height",)

    def build(self) -> Scene:
        """The Scene of this config."""
        a = math.radians(self.tilt)
        start = Plane(origin=(0.0, 0.0, self.height), e1=(math.cos(a), 0.0, math.sin(a)))
        sheet = Sheet(size=self.size, nodes=self.nodes, rest=HORIZONTAL, initial=start)
        return Scene(sheet, self.material(), forces=[Gravity(self.g)], **self.with_obstacles(HalfSpace()))


@dataclass(frozen=True, kw_only=True)
class SphereConfig(ClothOnObstacle):
    """A cloth dropped centred onto a ball whose top is at z = 0; its skirt folds onto itself.

    The cloth's self-contact is on (``self_distance`` 1 mm, the obstacle's activation distance): measured on FD
    32 x 32 nodes over the 1.5 s, without it the folding skirt passed through itself in 51 of the first 63
    recorded states from t = 0.27 s; with it in none of 306 steps, the closest two faces 0.26 mm apart
    (:mod:`deformable.contact.selfpotential`).

    Parameters
    ----------
    radius : float
        The ball's radius (m).
    gap : float
        The sheet's starting height above the ball's top (m).
    """

    name = "sphere"
    rank = 6
    summary = "square cloth dropped onto a ball, folding onto itself (contact, self-contact)"
    t_end: float = 1.5
    contact: Contact | None = Contact(distance=1e-3, friction=0.3, self_distance=1e-3)

    radius: float = 0.25
    gap: float = 0.05
    POSITIVE: ClassVar[tuple] = SceneConfig.POSITIVE + ("radius", "gap")

    def build(self) -> Scene:
        """The Scene of this config."""
        L1, L2 = self.size
        sheet = Sheet(size=self.size, nodes=self.nodes, rest=HORIZONTAL, initial=Plane(origin=(0.0, 0.0, self.gap)))
        ball = Sphere(center=(0.5 * L1, 0.5 * L2, -self.radius), radius=self.radius)
        return Scene(sheet, self.material(), forces=[Gravity(self.g)], **self.with_obstacles(ball))


@dataclass(frozen=True, kw_only=True)
class DrapeConfig(ClothOnObstacle):
    """The Cusick drape test: a cloth centred on a round table whose top is at z = 0.

    Parameters
    ----------
    table_radius : float
        The table's radius, BS 5058: 0.09 (m).
    table_thickness : float
        The table's thickness (m).
    rim : float
        The radius of the table's rounded rim (m).
    gap : float
        The sheet's starting height above the table (m).
    """

    name = "drape"
    rank = 7
    summary = "the Cusick drape test on a round table, with its drape coefficient (contact)"
    size: tuple = (0.3, 0.3)
    nodes: tuple = (33, 33)
    gamma: float = 1.0
    # a stiff fabric (bending length (2 xi / (mu g))^(1/3) = 6.7 cm): its folds are resolved on the study's quick
    # grids; the limp cloth's (xi = 1e-5) fold at about 3 cm (fold_wavelength) and are not
    xi: float = 3e-4
    t_end: float = 1.5
    # the cloth leaves the table at its rim: contact points only at the nodes (FD) or at h / 2 (FE) support it only
    # where one lands on the table, and the surface between them cuts the rim, a support radius short by up to their
    # spacing (FD 9, 17, 33 nodes: drape coefficient 0.885, 0.898, 0.923). Four contact points per cell side: 0.923,
    # 0.924, 0.924.
    contact: Contact | None = Contact(distance=1e-3, friction=0.3, samples=4)

    table_radius: float = 0.09
    table_thickness: float = 0.02
    rim: float = 0.003
    gap: float = 5e-4
    POSITIVE: ClassVar[tuple] = SceneConfig.POSITIVE + ("table_radius", "table_thickness", "gap")
    NON_NEGATIVE: ClassVar[tuple] = SceneConfig.NON_NEGATIVE + ("rim",)

    def table(self) -> Cylinder:
        """The table: a cylinder under the sheet's centre, its top at z = 0."""
        L1, L2 = self.size
        return Cylinder(center=(0.5 * L1, 0.5 * L2, -0.5 * self.table_thickness), radius=self.table_radius,
                        height=self.table_thickness, rounding=self.rim)

    def build(self) -> Scene:
        """The Scene of this config."""
        sheet = Sheet(size=self.size, nodes=self.nodes, rest=HORIZONTAL, initial=Plane(origin=(0.0, 0.0, self.gap)))
        return Scene(sheet, self.material(), forces=[Gravity(self.g)], **self.with_obstacles(self.table()))
