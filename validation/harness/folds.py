r"""A sheet bent into a U whose legs fly at each other: the self-impact of the contact study and its tests.

The unit sheet is bent across a2 (a2 its arc length) into two flat legs ``gap`` apart joined by a half circle
of radius gap / 2; the legs start moving towards each other at ``speed`` each (2 speed closing), the velocity
linear in the height between them, without gravity. The self-contact barrier (``Contact(self_distance=...)``)
stops them and they bounce back (:mod:`deformable.contact.selfpotential`).
"""

from __future__ import annotations

import math

import numpy as np

import deformable as dm

__all__ = ["u_fold", "closing", "impact_scene", "GAP", "DHAT", "SPEED"]

#: the legs' starting distance (m), the self-contact's activation distance (m), each leg's speed (m/s)
GAP, DHAT, SPEED = 0.1, 0.01, 5.0


def u_fold(gap: float = GAP):
    """The map r(a1, a2) (m) of the unit sheet bent into a U: flat legs ``gap`` apart, a half circle between."""
    R = gap / 2
    s1 = (1.0 - math.pi * R) / 2

    def r(a1, a2):
        theta = np.clip((a2 - s1) / R, 0.0, math.pi)
        y = np.where(a2 < s1, a2, np.where(theta < math.pi, s1 + R * np.sin(theta), s1 - (a2 - s1 - math.pi * R)))
        z = np.where(a2 < s1, 0.0, R * (1 - np.cos(theta)))
        return np.stack([np.asarray(a1, float) + 0 * y, y, z], -1)

    return r


def closing(speed: float = SPEED, gap: float = GAP):
    """The legs' velocity field (m/s): +speed at z = 0, -speed at z = gap, linear in z between."""
    fold = u_fold(gap)

    def v(a1, a2):
        z = fold(a1, a2)[..., 2]
        return np.stack([0 * z, 0 * z, speed * (1 - 2 * z / gap)], -1)

    return v


def impact_scene(nodes: int, thickness: float = 0.0, gamma: float = 0.0, gap: float = GAP,
                 distance: float = DHAT) -> dm.Scene:
    """The U-fold sheet (1 m x 1 m, mu = 0.1 kg/m^2, eta = 10 N/m, xi = 1e-4 N m, no gravity) on nodes x nodes
    with self-contact within ``distance`` beyond ``thickness`` (m)."""
    full = np.full((2, 2), 1.0)
    return dm.Scene(dm.Sheet(size=(1.0, 1.0), nodes=(nodes, nodes), initial=u_fold(gap)),
                    dm.Material(mu=0.1, gamma=gamma, eta=10.0 * full, xi=1e-4 * full),
                    contact=dm.Contact(self_distance=distance, thickness=thickness), force_model="variational",
                    name="u-fold")
