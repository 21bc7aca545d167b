"""The sheet as a triangle mesh for self-contact, and how close it comes to itself (the IPC Toolkit, ``ipctk``).

The contact mesh's vertices are the sheet's contact points (:mod:`deformable.contact.points`), ``V = W X`` (FD: its
nodes; FE: its sub-grid of spacing h / 2). Each cell of the sub-grid is two triangles, split along the diagonal from
(i, j) to (i + 1, j + 1). A quantity on the mesh's vertices maps back to the degrees of freedom exactly, by W^T.

Which pairs may touch. Primitives that share a vertex never count (the IPC Toolkit's rule). Beyond those, a pair
closer than the thickness plus the activation distance in the rest mesh (the sheet's initial state) is excluded:
neighbours, not folds. :attr:`ContactMesh.excluded` lists them (vertex pairs of the toolkit's ``can_collide``).

What is measured (Li et al. 2020, "Incremental Potential Contact", ACM TOG 39(4): the same distances and
intersection test): :meth:`ContactMesh.intersects`, whether two non-adjacent triangles of a state cross, and
:meth:`ContactMesh.self_distance`, the smallest distance between non-adjacent primitives within a search distance.
"""

from __future__ import annotations

import math

import ipctk
import numpy as np
import scipy.sparse as sp

from .points import contact_points

__all__ = ["ContactMesh", "grid_triangles", "vertex_map", "point_triangle_distances", "segment_distances"]


def grid_triangles(shape: tuple[int, int]) -> np.ndarray:
    """The triangles (F, 3) of an m x n vertex grid, vertex (i, j) at i n + j: two a cell, counter-clockwise in (a1,
    a2), split along the diagonal (i, j) - (i + 1, j + 1). F = 2 (m - 1) (n - 1)."""
    m, n = shape
    if m < 2 or n < 2:
        raise ValueError(f"a contact mesh needs at least 2 x 2 vertices, got {m} x {n}")
    i, j = np.meshgrid(np.arange(m - 1), np.arange(n - 1), indexing="ij")
    a, b = (i * n + j).ravel(), ((i + 1) * n + j).ravel()
    c, d = ((i + 1) * n + j + 1).ravel(), (i * n + j + 1).ravel()
    return np.concatenate([np.stack([a, b, c], 1), np.stack([a, c, d], 1)]).astype(np.int32)


def _ids(candidates: list, fields: tuple[str, str]) -> np.ndarray:
    """The two primitive indices of each of the IPC Toolkit's candidates, (C, 2)."""
    a, b = fields
    return np.fromiter((i for c in candidates for i in (getattr(c, a), getattr(c, b))), np.int64,
                       count=2 * len(candidates)).reshape(-1, 2)


#: candidates whose distances are computed at once (a chunk's temporaries stay near 100 MB)
CHUNK = 500_000


def _dot(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    return np.einsum("ij,ij->i", a, b)


def point_triangle_distances(p: np.ndarray, a: np.ndarray, b: np.ndarray, c: np.ndarray) -> np.ndarray:
    """The distances (N,) from points p to triangles (a, b, c), all (N, 3): the closest point by the triangle's
    Voronoi regions (Ericson 2005, "Real-Time Collision Detection", 5.1.5), for all at once."""
    ab, ac = b - a, c - a
    d1, d2 = _dot(ab, p - a), _dot(ac, p - a)
    d3, d4 = _dot(ab, p - b), _dot(ac, p - b)
    d5, d6 = _dot(ab, p - c), _dot(ac, p - c)
    va, vb, vc = d3 * d6 - d5 * d4, d5 * d2 - d1 * d6, d1 * d4 - d3 * d2
    with np.errstate(divide="ignore", invalid="ignore"):
        total = va + vb + vc
        q = a + ab * (vb / total)[:, None] + ac * (vc / total)[:, None]  # inside; the regions below in reverse order
        t = (d4 - d3) / ((d4 - d3) + (d5 - d6))
        q = np.where(((va <= 0) & (d4 - d3 >= 0) & (d5 - d6 >= 0))[:, None], b + (c - b) * t[:, None], q)
        q = np.where(((vb <= 0) & (d2 >= 0) & (d6 <= 0))[:, None], a + ac * (d2 / (d2 - d6))[:, None], q)
        q = np.where(((d6 >= 0) & (d5 <= d6))[:, None], c, q)
        q = np.where(((vc <= 0) & (d1 >= 0) & (d3 <= 0))[:, None], a + ab * (d1 / (d1 - d3))[:, None], q)
        q = np.where(((d3 >= 0) & (d4 <= d3))[:, None], b, q)
        q = np.where(((d1 <= 0) & (d2 <= 0))[:, None], a, q)
    return np.sqrt(np.sum((p - q) ** 2, axis=1))


def segment_distances(p0: np.ndarray, p1: np.ndarray, q0: np.ndarray, q1: np.ndarray) -> np.ndarray:
    """The distances (N,) between segments p0 p1 and q0 q1, all (N, 3): the closest points by clamped parameters
    (Ericson 2005, "Real-Time Collision Detection", 5.1.9), for all at once."""
    d1, d2, r = p1 - p0, q1 - q0, p0 - q0
    a, e, f = _dot(d1, d1), _dot(d2, d2), _dot(d2, r)
    c, b = _dot(d1, r), _dot(d1, d2)
    tiny = 1e-300
    denom = a * e - b * b
    with np.errstate(divide="ignore", invalid="ignore"):
        s = np.where(denom > 1e-14 * np.maximum(a * e, tiny), np.clip((b * f - c * e) / denom, 0.0, 1.0), 0.0)
        t = np.where(e > tiny, (b * s + f) / np.maximum(e, tiny), 0.0)
        s = np.where(t < 0, np.where(a > tiny, np.clip(-c / np.maximum(a, tiny), 0.0, 1.0), 0.0), s)
        s = np.where(t > 1, np.where(a > tiny, np.clip((b - c) / np.maximum(a, tiny), 0.0, 1.0), 0.0), s)
        t = np.clip(t, 0.0, 1.0)
        point = e <= tiny  # q of no length: the closest point of p0 p1 to q0
        s = np.where(point, np.where(a > tiny, np.clip(-c / np.maximum(a, tiny), 0.0, 1.0), 0.0), s)
    return np.sqrt(np.sum((p0 + d1 * s[:, None] - q0 - d2 * t[:, None]) ** 2, axis=1))


def vertex_map(W) -> tuple[sp.csr_matrix, sp.csr_matrix]:
    """The map (3 P, 3 ndof) from a flat coordinate-blocked state x (a ndof + k) to the contact mesh's vertices as
    the IPC Toolkit orders them (3 p + a), for the map W (P, ndof) of the contact points; and its transpose, which
    takes the toolkit's gradients (3 P,) back to the degrees of freedom."""
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
        The sheet's thickness dmin (m): the barrier's distances count from it, and pairs closer than ``thickness +
        distance`` in the rest mesh are excluded.

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
        """The IPC Toolkit's normal collisions of vertices V (P, 3): the pairs closer than the thickness plus the
        activation distance, their barrier counted from the thickness; ``distance`` (m): the pairs closer than it,
        with no thickness (a measurement). ``area_weighting``: each weighted by its primitives' rest areas (the
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
        distance in the rest mesh, each pair of the two primitives' vertices. The IPC Toolkit's broad phase finds
        the candidates; their distances are computed all at once (:func:`point_triangle_distances`,
        :func:`segment_distances`)."""
        reach = self.thickness + self.distance
        candidates = ipctk.Candidates()
        candidates.build(self.mesh, self.rest, 0.5 * reach)  # boxes grown by half the reach: every pair within it
        V, E, F = self.rest, self.edges.astype(np.int64), self.faces.astype(np.int64)
        fv, ee = (_ids(getattr(candidates, name), fields) for name, fields in
                  (("fv_candidates", ("face_id", "vertex_id")), ("ee_candidates", ("edge0_id", "edge1_id"))))
        keys = [np.zeros(0, np.int64)]
        for k in range(0, max(len(fv), len(ee)), CHUNK):  # chunks: millions of candidates at FD 256 x 256 nodes
            tri, pts = F[fv[k:k + CHUNK, 0]], fv[k:k + CHUNK, 1]
            e0, e1 = E[ee[k:k + CHUNK, 0]], E[ee[k:k + CHUNK, 1]]
            near = [np.column_stack([tri, pts])[point_triangle_distances(V[pts], *(V[tri[:, i]] for i in range(3)))
                                                < reach],
                    np.column_stack([e0, e1])[segment_distances(V[e0[:, 0]], V[e0[:, 1]], V[e1[:, 0]], V[e1[:, 1]])
                                              < reach]]
            groups = np.concatenate(near)
            a, b = np.repeat(groups, 4, axis=1).ravel(), np.tile(groups, (1, 4)).ravel()
            keep = a != b
            keys.append(np.unique(np.minimum(a[keep], b[keep]) * V.shape[0] + np.maximum(a[keep], b[keep])))
        keys = np.unique(np.concatenate(keys))
        return frozenset(zip((keys // V.shape[0]).tolist(), (keys % V.shape[0]).tolist()))

    def intersects(self, X) -> bool:
        """Whether two triangles of state X (ndof, 3) that share no vertex cross each other."""
        return bool(ipctk.has_intersections(self.mesh, self.vertices(X)))

    def self_distance(self, X, within: float | None = None) -> float:
        """The smallest distance between primitives of state X (ndof, 3) that may touch (m); inf when none is closer
        than ``within`` (m, default the activation distance)."""
        within = self.distance if within is None else float(within)
        V = self.vertices(X)
        collisions = self.collisions(V, within)
        if len(collisions) == 0:
            return math.inf
        return math.sqrt(max(0.0, float(collisions.compute_minimum_distance(self.mesh, V))))
