r"""The waving flag of Figs 7-8.

A flag on its pole (the edge a1 = 0 pinned) in the wind. The paper's "coil force on one side" drives it
from the pole's side: two coils (springs) from the material points (``coil_at``, L2 / 4) and
(``coil_at``, 3 L2 / 4) to anchors beside them that swing across the flag (``swing``, ``frequency``), the
way a real flag is shaken where the flow leaves the pole. The wind (aerodynamic pressure on the normal
with the relative velocity, :class:`~deformable.physics.forces.Wind`) presses on every fold and damps the
motion across the flag, and the flow's mean pull along the flag (``pull``, a uniform force density along
+x) holds it out against gravity, as the drag of the flow on a fluttering flag does: it puts the flag in a
tension that falls from tau L1 at the pole to nothing at the free edge. So the waves travel from the pole to
the free edge, slowing as the tension falls (phase speed sqrt(T / mu)) and growing in amplitude towards it,
as a real flag's do (the paper study's flag section measures the direction, the phase speed and the
amplitude along the flag). The swing is 6 Hz (the paper gives none); the pull, 4 N/m^2 (0.067 of the
wind's dynamic pressure 1/2 rho U^2 = 60 Pa at 10 m/s), is a model parameter, not a measured drag.

Before issue 29 the coils pulled the free corners towards anchors beyond the flag: the waves came from the
free edge and travelled towards the pole, about 5 cm high; that design is gone.

1.2 m x 0.8 m in the vertical x-z plane, pole along a1 = 0. mu = 0.2 kg/m^2, gamma = 0.05 kg/(m^2 s),
eta = 20 N/m, xi = 1e-5 N m, scale 1. Coils of 30 N/m at 0.15 m from the pole, swinging 0.2 m across
the flag at 6 Hz; wind 10 m/s along the flag (c = 0.6 kg/m^3), pull 4 N/m^2.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import ClassVar

from ..geometry.sheet import Sheet
from ..physics.forces import BodyForce, Gravity, Spring, Wind
from ..scene.constraints import Pin
from ..scene.scene import Scene
from .config import SceneConfig
from .shapes import VERTICAL, smooth_ramp

__all__ = ["FlagConfig"]


@dataclass(frozen=True, kw_only=True)
class FlagConfig(SceneConfig):
    """The waving flag (Figs 7-8).

    Parameters
    ----------
    wind : float
        Wind speed along +x, away from the pole (m/s).
    drag : float
        Real-world c = rho C_d / 2 of the wind's pressure, air 0.6 (kg/m^3).
    coil : float
        Real-world stiffness of each of the two coils (N/m).
    coil_at : float
        Distance along a1 from the pole at which the coils hold the flag (m). At a quarter and three
        quarters of its height; their anchors swing beside those points.
    swing : float
        Amplitude of the anchors' swing across the flag, along y (m).
    pull : float
        Real-world mean pull of the flow along the flag, a force density along +x (N/m^2).
    frequency : float
        Frequency of the swing (Hz).
    ramp : float
        Time over which the swing grows to its amplitude (s).
    """

    name = "flag"
    rank = 4
    summary = "flag on a pole, shaken by coils beside the pole, in the wind (Figs 7-8)"
    size: tuple = (1.2, 0.8)
    gamma: float = 0.05

    wind: float = 10.0
    drag: float = 0.6
    coil: float = 30.0
    coil_at: float = 0.15
    swing: float = 0.2
    pull: float = 4.0
    frequency: float = 6.0
    ramp: float = 0.5
    POSITIVE: ClassVar[tuple] = SceneConfig.POSITIVE + ("ramp",)
    NON_NEGATIVE: ClassVar[tuple] = SceneConfig.NON_NEGATIVE + ("drag", "coil", "coil_at", "swing", "frequency", "pull")

    def build(self) -> Scene:
        """The Scene of this config."""
        L1, L2 = self.size
        sheet = Sheet(size=self.size, nodes=self.nodes, rest=VERTICAL)
        omega = 2.0 * math.pi * self.frequency

        def anchor(z):
            def where(t):
                return (self.coil_at, self.swing * math.sin(omega * t) * float(smooth_ramp(t / self.ramp)), z)
            return where

        coils = [Spring((self.coil_at, z), anchor(z), self.scale * self.coil) for z in (0.25 * L2, 0.75 * L2)]
        forces = [Gravity(self.g), Wind((self.wind, 0.0, 0.0), self.scale * self.drag),
                  BodyForce((self.scale * self.pull, 0.0, 0.0)), *coils]
        return Scene(sheet, self.material(), forces=forces, constraints=[Pin("left")], **self.scene_kwargs())
