"""TPBF87's obstacle force, for the paper's semi-implicit scheme.

The paper's own obstacle force (Terzopoulos et al. 1987, section 4, "Collisions"): an exponential force field along
the obstacle's normal, ``f = c exp(-d / eps) n`` per unit area (c in N/m^2, eps = the contact ``distance``),
evaluated at the start of each step like the other applied forces (:class:`Repulsion`). It is soft: a point pressed
hard enough, or arriving fast enough within one step, goes through; it does not guarantee non-penetration.
"""

from __future__ import annotations

import numpy as np

from .points import contact_points
from .settings import weight_per_area

__all__ = ["Repulsion"]


class Repulsion:
    """TPBF87's obstacle force, ``c exp(-d / eps) n`` per unit area at the contact points (module docstring).

    For the semi-implicit scheme, evaluated at the start of each step. It does not guarantee non-penetration.
    """

    def __init__(self, model):
        scene = model.scene
        self.obstacles = tuple(scene.obstacles)
        self.points = contact_points(model)
        self.eps = scene.contact.distance
        self.c = scene.contact.repulsion_pressure(weight_per_area(scene))

    def force(self, X: np.ndarray) -> np.ndarray:
        """The integrated force on the degrees of freedom, (ndof, 3) (N)."""
        r = self.points.positions(np.asarray(X, float))
        f = np.zeros_like(r)
        for obstacle in self.obstacles:
            d, nrm, _ = obstacle.derivatives(r, hessian=False)
            f += (self.c * self.points.area * np.exp(-np.maximum(d, -50 * self.eps) / self.eps))[:, None] * nrm
        return self.points.WT @ f
