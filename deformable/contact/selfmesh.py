r"""The sheet as a triangle mesh for self-contact, and how close it comes to itself (the IPC Toolkit, ``ipctk``).

The contact mesh's vertices are the sheet's contact points (:mod:`deformable.contact.points`): a sub-grid of the
parameter rectangle mapped to the degrees of freedom by the fixed sparse matrix W, ``V = W X`` (FD: its nodes;
FE: its sub-grid of spacing h / 2, so the cubic surface between nodes is in the mesh too). Each cell of the
sub-grid is two triangles, split along the diagonal from (i, j) to (i + 1, j + 1); the edges are the
triangles' edges. A quantity on the mesh's vertices maps back to the degrees of freedom exactly, by W^T.

Which pairs may touch. Primitives that share a vertex never count (the IPC Toolkit's rule: a triangle and its
own corner, two edges of one triangle). Beyond those, a pair closer than the thickness plus the activation
distance in the rest mesh (the sheet's initial state) is excluded too: those are neighbours, not a fold meeting another fold.
:attr:`ContactMesh.excluded` lists them (vertex pairs of the IPC Toolkit's ``can_collide``); on a flat rest
sheet with the thickness plus the activation distance below the sub-grid's spacing there are none.

What is measured (Li et al. 2020, "Incremental Potential Contact", ACM TOG 39(4): the same distances and
intersection test): :meth:`ContactMesh.intersects`, whether two non-adjacent triangles of a state cross, and
:meth:`ContactMesh.self_distance`, the smallest distance between non-adjacent primitives (point-triangle and
edge-edge) within a search distance (m).
"""

from __future__ import annotations

import math

import ipctk
import numpy as np
import scipy.sparse as sp

from .points import contact_points

__all__ = ["ContactMesh", "grid_triangles", "vertex_map"]


def grid_triangles(shape: tuple[int, int]) -> np.ndarray:
    """The triangles (F, 3) of an m x n vertex grid, vertex (i, j) at i n + j: two a cell, counter-clockwise in
    (a1, a2), split along the diagonal (i, j) - (i + 1, j + 1). F = 2 (m - 1) (n - 1)."""
    m, n = shape
    if m < 2 or n < 2:
        raise ValueError(f"a contact mesh needs at least 2 x 2 vertices, got {m} x {n}")
    i, j = np.meshgrid(np.arange(m - 1), np.arange(n - 1), indexing="ij")
    a, b = (i * n + j).ravel(), ((i + 1) * n + j).ravel()
    c, d = ((i + 1) * n + j + 1).ravel(), (i * n + j + 1).ravel()
    return np.concatenate([np.stack([a, b, c], 1), np.stack([a, c, d], 1)]).astype(np.int32)


def vertex_map(W) -> tuple[sp.csr_matrix, sp.csr_matrix]:
    """The map (3 P, 3 ndof) from a flat coordinate-blocked state x (a ndof + k) to the contact mesh's vertices as
    the IPC Toolkit orders them (3 p + a), for the map W (P, ndof) of the contact points; and its transpose,
    which takes the toolkit's gradients (3 P,) back to the degrees of freedom."""
    P = W.shape[0]
    W3 = sp.kron(sp.identity(3, format="csr"), W, format="csr")
    order = (3 * np.arange(P)[None, :] + np.arange(3)[:, None]).ravel()  # blocked index a P + p -> 3 p + a
    Wv = W3[np.argsort(order)].tocsr()
    return Wv, Wv.T.tocsr()


class ContactMesh:
    """The sheet's contact points as a triangle mesh (module docstring).

    Parameters
    ----------
    model : Backend (with the hook ``point_matrix``)
    distance : float
        The activation distance (m): pairs of primitives closer than it in the rest mesh are excluded.
    samples : int, optional
        Contact points per cell side (default: the scene's ``Contact.samples``, else the backend's own).
    rest : array (ndof, 3), optional
        The rest mesh's state (default: the model's initial state).
    thickness : float
        The sheet's thickness dmin (m): the barrier's distances count from it, and pairs closer than
        ``thickness + distance`` in the rest mesh are excluded.

    Attributes
    ----------
    points : ContactPoints
        The vertices' parameter points and their map W (P, ndof).
    faces : int array (F, 3)
    edges : int array (E, 2)
    excluded : frozenset of (int, int)
        Vertex pairs closer than ``distance`` in the rest mesh that share no triangle: never in contact.
    """

    def __init__(self, model, distance: float, samples: int | None = None, rest=None, thickness: float = 0.0):
        if isinstance(distance, bool) or not isinstance(distance, (int, float)) or not 0 < distance < math.inf:
            raise ValueError(f"ContactMesh.distance must be a positive finite number (m), got {distance!r}")
        if isinstance(thickness, bool) or not isinstance(thickness, (int, float)) or not 0 <= thickness < math.inf:
            raise ValueError(f"ContactMesh.thickness must be a non-negative finite number (m), got {thickness!r}")
        self.distance, self.thickness = float(distance), float(thickness)
        self.points = contact_points(model, samples)
        self.faces = grid_triangles(self.points.shape)
        self.edges = np.asarray(ipctk.edges(self.faces), dtype=np.int32)
        X0 = model.initial_state() if rest is None else np.asarray(rest, float)
        self.rest = self.vertices(X0)
        self.mesh = ipctk.CollisionMesh(self.rest, self.edges, self.faces)
        self.excluded = self._close_at_rest()
        if self.excluded:  # a sparse filter, evaluated in the IPC Toolkit's own code
            self.mesh.can_collide = ipctk.make_sparse_filter({pair: False for pair in self.excluded}, True)

    def vertices(self, X) -> np.ndarray:
        """The mesh's vertices (P, 3) of a state X (ndof, 3) (m), Fortran-ordered as the IPC Toolkit takes them."""
        return np.asfortranarray(self.points.positions(np.asarray(X, float)))

    def collisions(self, V, distance: float | None = None, area_weighting: bool = False):
        """The IPC Toolkit's normal collisions of vertices V (P, 3): the pairs closer than the thickness plus
        the activation distance, their barrier counted from the thickness; ``distance`` (m): the pairs closer than
        it, with no thickness (a measurement). ``area_weighting``: each weighted by its primitives' rest areas (the
        barrier's weights)."""
        collisions = ipctk.NormalCollisions()
        collisions.use_area_weighting = area_weighting
        if distance is None:
            collisions.build(self.mesh, np.asfortranarray(V), self.distance, self.thickness)
        else:
            collisions.build(self.mesh, np.asfortranarray(V), distance)
        return collisions

    def _close_at_rest(self) -> frozenset:
        """The vertex pairs across every pair of primitives (point-triangle, edge-edge) closer than the activation
        distance in the rest mesh: each pair of the two primitives' vertices, so that no collision between them
        is left, whichever feature is closest."""
        reach = self.thickness + self.distance
        candidates = ipctk.Candidates()
        candidates.build(self.mesh, self.rest, reach)
        pairs = set()
        for kind in (candidates.fv_candidates, candidates.ee_candidates):
            for c in kind:
                squared = float(c.compute_distance(self.rest, self.edges, self.faces))  # the IPC Toolkit's d^2
                if math.sqrt(max(0.0, squared)) < reach:
                    ids = [int(v) for v in c.vertex_ids(self.edges, self.faces)]
                    pairs.update((min(u, v), max(u, v)) for u in ids for v in ids if u != v)
        return frozenset(pairs)

    def intersects(self, X) -> bool:
        """Whether two triangles of state X (ndof, 3) that share no vertex cross each other."""
        return bool(ipctk.has_intersections(self.mesh, self.vertices(X)))

    def self_distance(self, X, within: float | None = None) -> float:
        """The smallest distance between primitives of state X (ndof, 3) that may touch (m); inf when none is
        closer than ``within`` (m, default the activation distance)."""
        within = self.distance if within is None else float(within)
        V = self.vertices(X)
        collisions = self.collisions(V, within)
        if len(collisions) == 0:
            return math.inf
        return math.sqrt(max(0.0, float(collisions.compute_minimum_distance(self.mesh, V))))
