r"""The simplest scene: a square cloth pinned at its two top corners, falling from horizontal and swinging (not in
the paper)."""

from __future__ import annotations

from dataclasses import dataclass

from ..geometry.sheet import Sheet
from ..physics.forces import Gravity
from ..scene.constraints import Pin
from ..scene.scene import Scene
from .config import SceneConfig
from .shapes import HORIZONTAL

__all__ = ["HangingConfig"]


@dataclass(frozen=True, kw_only=True)
class HangingConfig(SceneConfig):
    """A cloth pinned at its two top corners, starting horizontal: 1 m x 1 m, mu = 0.2 kg/m^2, gamma = 0.05
    kg/(m^2 s), eta = 50 N/m, xi = 1e-5 N m, full tensors, scale 1 (real-world values, section 4)."""

    name = "hanging"
    rank = 0
    summary = "cloth pinned at its two top corners, falling under gravity"
    gamma: float = 0.05
    eta: float = 50.0

    def build(self) -> Scene:
        """The Scene of this config."""
        sheet = Sheet(size=self.size, nodes=self.nodes, rest=HORIZONTAL)
        return Scene(sheet, self.material(), forces=[Gravity(self.g)], constraints=[Pin(["top-left", "top-right"])],
                     **self.scene_kwargs())
