r"""How far the sheet is from the scene's obstacles, of every kind, and whether a step may start from a state.

The analytic obstacles have a signed distance, measured at the sheet's contact points
(:mod:`deformable.contact.points`); a mesh obstacle has none, and the distance is the smallest between the sheet's
contact mesh and its triangles, -inf where they intersect (:class:`deformable.contact.meshpotential.ObstacleMesh`).
"""

from __future__ import annotations

import math

import numpy as np

from .meshpotential import obstacle_contact_mesh
from .points import contact_points, require_outside

__all__ = ["clearance", "require_clear"]


def clearance(model, X: np.ndarray, obstacles=None, t: float = 0.0) -> float:
    """The smallest signed distance from the sheet to the obstacles (m); negative: penetration.

    Against the analytic obstacles the signed distance of the contact points; against a mesh obstacle the smallest
    distance between the sheet's contact mesh and its triangles, -inf where they intersect (the depth is not
    measured).

    Parameters
    ----------
    model : Backend
    X : array (ndof, 3)
    obstacles : sequence of Obstacle, optional
        Default the scene's. Without obstacles the clearance is infinite.
    t : float
        The time (s): where a moving mesh obstacle stands.
    """
    obstacles = model.scene.obstacles if obstacles is None else tuple(obstacles)
    analytic = [o for o in obstacles if o.analytic]
    meshes = [o for o in obstacles if not o.analytic]
    out = math.inf
    if analytic:
        r = contact_points(model).positions(np.asarray(X, float))
        out = float(min(np.min(o.distance(r)) for o in analytic))
    if meshes:
        out = min(out, obstacle_contact_mesh(model, meshes).distance(X, t))
    return out


def require_clear(model, X: np.ndarray, what: str = "the state", t: float = 0.0) -> None:
    """Raise a ValueError when a state X (ndof, 3) at time t (s) cannot start a step: a contact point not strictly
    outside an analytic obstacle (:func:`deformable.contact.points.require_outside`), or the sheet intersecting a
    mesh obstacle."""
    require_outside(model, X, what)
    if any(not o.analytic for o in model.scene.obstacles) and obstacle_contact_mesh(model).intersects(X, t):
        raise ValueError(f"{what}: the sheet intersects a mesh obstacle at t = {t:g} s; it must start clear of every "
                         "obstacle")
