r"""The waving flag of Figs 7-8.

A flag on its pole (the edge a1 = 0 pinned), the paper's "coil force" on its
free side: two springs from the free corners to anchors beyond the flag that
swing across it (``swing``, ``frequency``), and wind along the flag
(aerodynamic pressure on the normal with the relative velocity,
:class:`~deformable.physics.forces.Wind`), which presses on every fold the
coils raise and damps the motion across the flag. The coils drive the waves
from the free side, so they travel towards the pole (a real flag's waves
come from the flow and travel to its free edge; the paper names only the
coil). The springs keep the flag out against gravity, which a real flag's
skin friction does. The swing is 6 Hz (the paper gives none) so that the
wave is shorter than the flag: its phase speed along the flag is about
7 m/s (set by the coils' tension), a wavelength of 1.1-1.2 m at 6 Hz
against the flag's 1.2 m; at 4 Hz (1.75 m) the phase changed by 3.06 rad
(FD 32 x 32) and 3.11 rad (FE 16 x 16 elements) from pole to tip, less
than half a wave, at 6 Hz by 5.2 and 4.4 rad (the paper study's flag
section measures it).

1.2 m x 0.8 m in the vertical x-z plane, pole along a1 = 0. mu = 0.2 kg/m^2, gamma = 0.05 kg/(m^2 s),
eta = 20 N/m, xi = 1e-5 N m, scale 1. Coils of 30 N/m to anchors 0.1 m beyond the free corners, swinging
0.15 m across the flag at 6 Hz; wind 10 m/s along the flag (c = 0.6 kg/m^3).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import ClassVar

from ..geometry.sheet import Sheet
from ..physics.forces import Gravity, Spring, Wind
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
        c = rho C_d / 2 of the wind's pressure (kg/m^3; air 0.6), real-world.
    coil : float
        Stiffness of each of the two coils at the free corners (N/m), real-world.
    reach : float
        How far beyond the free edge the coils' anchors are (m).
    swing : float
        Amplitude of the anchors' swing across the flag, along y (m).
    frequency : float
        Frequency of the swing (Hz).
    ramp : float
        Seconds over which the swing grows to its amplitude.
    """

    name = "flag"
    rank = 4
    summary = "flag on a pole, a coil on its free side, in the wind (Figs 7-8)"
    size: tuple = (1.2, 0.8)
    gamma: float = 0.05

    wind: float = 10.0
    drag: float = 0.6
    coil: float = 30.0
    reach: float = 0.1
    swing: float = 0.15
    frequency: float = 6.0
    ramp: float = 0.5
    POSITIVE: ClassVar[tuple] = SceneConfig.POSITIVE + ("ramp",)
    NON_NEGATIVE: ClassVar[tuple] = SceneConfig.NON_NEGATIVE + ("drag", "coil", "swing", "frequency")

    def build(self) -> Scene:
        """The Scene of this config."""
        L1, L2 = self.size
        sheet = Sheet(size=self.size, nodes=self.nodes, rest=VERTICAL)
        omega = 2.0 * math.pi * self.frequency

        def anchor(z):
            def where(t):
                return (L1 + self.reach, self.swing * math.sin(omega * t) * float(smooth_ramp(t / self.ramp)), z)
            return where

        coils = [Spring((L1, z), anchor(z), self.scale * self.coil) for z in (0.0, L2)]
        forces = [Gravity(self.g), Wind((self.wind, 0.0, 0.0), self.scale * self.drag), *coils]
        return Scene(sheet, self.material(), forces=forces, constraints=[Pin("left")], **self.scene_kwargs())
