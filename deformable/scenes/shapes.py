r"""Shapes and motions the scenes are made of: their rest planes, the curtain's seeded start, a smooth ramp in time."""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..geometry.surfaces import Plane

__all__ = ["VERTICAL", "HORIZONTAL", "smooth_ramp", "FoldNoise"]

#: the vertical x-z plane: a1 along x, a2 up (the curtain and the flag hang in it)
VERTICAL = Plane(e1=(1.0, 0.0, 0.0), e2=(0.0, 0.0, 1.0))
#: the horizontal x-y plane (the default rest shape)
HORIZONTAL = Plane()


def smooth_ramp(s):
    """0 before s = 0, 1 after s = 1, ``s^3 (10 - 15 s + 6 s^2)`` between: no jump in velocity or acceleration."""
    s = np.clip(s, 0.0, 1.0)
    return s**3 * (10.0 - 15.0 * s + 6.0 * s * s)


@dataclass(frozen=True)
class FoldNoise:
    """The curtain's start: its rest plane plus a small seeded ripple along y, a Surface with exact derivatives.

    ``y = noise * sum_k c_k sin(k pi a1 / L1 + phi_k)`` for k = 1..modes, c_k
    standard normal over sqrt(modes / 2) (so the RMS is about ``noise``) and
    phi_k uniform: white over the wavelengths 2 L1 / modes .. 2 L1, the same
    function on every grid and backend.
    """

    width: float
    noise: float
    seed: int
    modes: int = 32

    def _coefficients(self):
        rng = np.random.default_rng(self.seed)
        c = rng.normal(size=self.modes) / math.sqrt(self.modes / 2)
        phi = rng.uniform(0.0, 2.0 * math.pi, self.modes)
        k = np.arange(1, self.modes + 1) * math.pi / self.width
        return self.noise * c, k, phi

    def _ripple(self, a1, order):
        c, k, phi = self._coefficients()
        a1 = np.asarray(a1, float)[..., None]
        if order == 0:
            return np.sum(c * np.sin(k * a1 + phi), axis=-1)
        return np.sum(c * k * np.cos(k * a1 + phi), axis=-1)

    def r(self, a1, a2):
        a1, a2 = np.broadcast_arrays(np.asarray(a1, float), np.asarray(a2, float))
        return np.stack([a1, self._ripple(a1, 0), a2], axis=-1)

    def r1(self, a1, a2):
        a1, a2 = np.broadcast_arrays(np.asarray(a1, float), np.asarray(a2, float))
        return np.stack([np.ones_like(a1), self._ripple(a1, 1), np.zeros_like(a1)], axis=-1)

    def r2(self, a1, a2):
        a1, _ = np.broadcast_arrays(np.asarray(a1, float), np.asarray(a2, float))
        return np.broadcast_to(np.array([0.0, 0.0, 1.0]), a1.shape + (3,)).copy()

    def r12(self, a1, a2):
        a1, _ = np.broadcast_arrays(np.asarray(a1, float), np.asarray(a2, float))
        return np.zeros(a1.shape + (3,))
