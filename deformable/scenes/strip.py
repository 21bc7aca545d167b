r"""A long strip dropped end first onto the floor, folding onto itself (contact, self-contact).

``coil``
    A ribbon 0.6 m long and 4 cm wide, held upright but leaning 5 degrees (towards +x, about its width) with its
    lower end 5 mm above the floor (a :class:`~deformable.contact.obstacles.HalfSpace` at z = 0), released from
    rest under gravity. The lower end lands first, at 0.31 m/s; the rest keeps falling onto it (the top from
    0.6 m), so the strip buckles at the floor and lays itself down in loops on its own lower part, falling
    over towards +x, the way it leans: a ribbon folds about its width, its easy axis, so it folds back and
    forth rather than coiling round like a rope. The folds rest on each other (self-contact on, a ribbon
    0.5 mm thick) and slide freely on each other (``self_friction`` 0, frictionless between folds), so the
    loops open up again as the strip straightens after the fall.

The ribbon: mu = 0.2 kg/m^2, gamma = 0.1 kg/(m^2 s), eta = 20 N/m (the contact scenes' cloth) and the curtain
fabric's xi = 1e-4 N m (bending length (2 xi / (mu g))^(1/3) = 4.7 cm, 9 grid spacings on the default FD
121 x 9 nodes, 5 mm apart); friction 0.3 against the floor, whose barrier is active within 1 mm, and the
sheet's own barrier within 1 mm beyond its 0.5 mm thickness.

The layers, measured on the default grid as the most times a vertical line crosses the strip's centre line: 5,
4, 4 and 2 at t = 0.23, 0.43, 0.63 and 1.0 s, over a pile 0.11, 0.19, 0.23 and 0.34 m long; run on to t = 1.5 s,
it lies nearly still from t = 1.0 s, one loop 4 cm high left (no step intersected). The grid decides
how the folds lie: on 61 x 5 and 91 x 7 nodes the strip was pressed into a flat stack of 7 and 5 layers,
0.16 and 0.15 m long, that stayed until t = 1.5 s; on 121 x 9 and 151 x 11 the loops stay open and unfold
alike (at t = 0.63 s 4 and 3 layers over 0.23 m, at 0.83 s 3 and 2 over 0.27 m): the default is the coarser
of these two.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import ClassVar

from ..contact.obstacles import HalfSpace
from ..contact.settings import Contact
from ..geometry.sheet import Sheet
from ..geometry.surfaces import Plane
from ..physics.forces import Gravity
from ..scene.scene import Scene
from .config import SceneConfig
from .shapes import HORIZONTAL

__all__ = ["CoilConfig"]


@dataclass(frozen=True, kw_only=True)
class CoilConfig(SceneConfig):
    """A long strip held upright, leaning, its lower end just above the floor (the plane z = 0), released from rest;
    it lands end first and folds onto itself.

    Its self-contact is on (``self_distance`` 1 mm beyond a ``thickness`` of 0.5 mm, a thick ribbon's):
    measured on FD 121 x 9 nodes over the 1 s, two parts of the strip came within the barrier's reach
    (1.5 mm) in 167 of the 216 steps, from t = 0.25 s; no step intersected, the closest two faces were
    0.59 mm apart, and the floor's clearance stayed above 1.1e-7 m. Without self-contact the strip passed
    through itself in 150 of its 200 steps, from t = 0.25 s (:mod:`deformable.contact.selfpotential`).
    The run took 216 steps (the step adapted: median 5 ms, 0.16 ms at its smallest, near t = 1 s where two faces
    came closest), 5.8 Newton iterations a step and 118 s of wall time (on a machine shared with other runs).

    Parameters
    ----------
    gap : float
        The lower end's starting height above the floor (m). From rest it lands at sqrt(2 g gap).
    tilt : float
        The strip's lean from the vertical, towards +x, about its width (deg). It falls over that way.
    """

    name = "coil"
    rank = 8
    summary = "long strip dropped end first onto the floor, folding onto itself (contact, self-contact)"
    # a1 along the strip (0.6 m), a2 across it (4 cm); square cells 5 mm a side (module docstring: the grid)
    size: tuple = (0.6, 0.04)
    nodes: tuple = (121, 9)
    # the curtain fabric's (bending length 4.7 cm); measured on 61 x 5 nodes, the contact scenes' limp cloth
    # (xi = 1e-5, 2.2 cm) crumples at the grid scale, and xi = 1e-3 (10 cm) makes one loop and springs straight
    xi: float = 1e-4
    t_end: float = 1.0
    contact: Contact | None = Contact(distance=1e-3, friction=0.3, self_distance=1e-3, thickness=5e-4)

    gap: float = 0.005
    tilt: float = 5.0
    POSITIVE: ClassVar[tuple] = SceneConfig.POSITIVE + ("gap",)

    def build(self) -> Scene:
        """The Scene of this config."""
        a = math.radians(self.tilt)
        start = Plane(origin=(0.0, 0.0, self.gap), e1=(math.sin(a), 0.0, math.cos(a)), e2=(0.0, 1.0, 0.0))
        sheet = Sheet(size=self.size, nodes=self.nodes, rest=HORIZONTAL, initial=start)
        return Scene(sheet, self.material(), forces=[Gravity(self.g)], **self.with_obstacles(HalfSpace()))
