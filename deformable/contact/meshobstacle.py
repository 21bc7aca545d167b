"""A rigid obstacle of any shape, given as a triangle mesh: :class:`MeshObstacle`.

A user's obstacle (a chair, a mannequin, a scanned table) is a triangle mesh, read with meshio from any format it
knows (OBJ, STL, PLY, VTK, ...) or given as arrays. It is neither convex nor, in general, closed, so it has no
signed distance (:mod:`deformable.contact.obstacles`): the sheet meets it primitive against primitive on one IPC
Toolkit mesh (:class:`deformable.contact.meshpotential.ObstacleMesh`), under the IPC barrier of their distances and
a line search bounded by continuous collision detection (Li et al. 2020, "Incremental Potential Contact", ACM TOG
39(4); :class:`deformable.contact.meshpotential.MeshObstaclePotential`).

Motion. The obstacle is static, or moves rigidly on a prescribed path: a rotation at the constant angular velocity
omega (rad/s) about ``pivot`` and a translation at the constant ``velocity`` (m/s),

    y(t) = R(omega t) (y0 - pivot) + pivot + velocity t,

R(theta) the rotation by |theta| about theta / |theta| (Rodrigues' formula). Each implicit step puts it where it is
at the step's end; where its motion over the step would strike the sheet, the sheet near it rides with it into the
step's start, and a step over which even that would strike the sheet is retried shorter
(:meth:`deformable.contact.terms.ContactTerms.safe_start`).
"""

from __future__ import annotations

import os
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ..checks import vector
from ..errors import InputError
from .obstacles import MAX_LENGTH, Obstacle

__all__ = ["MeshObstacle", "rotation", "icosphere", "sag"]


def rotation(theta) -> np.ndarray:
    """The rotation matrix (3, 3) by the angle |theta| (rad) about the axis theta / |theta| (Rodrigues' formula)."""
    theta = np.asarray(theta, float)
    angle = float(np.linalg.norm(theta))
    if angle == 0.0:
        return np.eye(3)
    k = theta / angle
    K = np.array([[0.0, -k[2], k[1]], [k[2], 0.0, -k[0]], [-k[1], k[0], 0.0]])
    return np.eye(3) + np.sin(angle) * K + (1.0 - np.cos(angle)) * (K @ K)


def _read(path: str) -> tuple[np.ndarray, np.ndarray]:
    """The vertices and triangles of a mesh file (meshio); InputError for a file that cannot be read or has none."""
    import meshio

    try:
        mesh = meshio.read(path)
    except Exception as err:  # meshio raises its own errors, OSError, KeyError for an unknown format
        raise InputError(f"MeshObstacle.path: cannot read {path!r} as a mesh ({type(err).__name__}: {err})",
                         field="MeshObstacle.path", value=path) from err
    tris = [c.data for c in mesh.cells if c.type == "triangle"]
    if not tris:
        kinds = sorted({c.type for c in mesh.cells})
        raise InputError(f"MeshObstacle.path: {path!r} has no triangles (cells: {', '.join(kinds) or 'none'})",
                         field="MeshObstacle.path", value=path)
    V = np.asarray(mesh.points, float)
    if V.shape[1] == 2:
        V = np.column_stack([V, np.zeros(len(V))])
    return V[:, :3], np.concatenate(tris).astype(np.int64)


@dataclass(frozen=True)
class MeshObstacle(Obstacle):
    """A rigid triangle-mesh obstacle, static or moving on a prescribed rigid path (module docstring).

    Parameters
    ----------
    path : str, optional
        A mesh file meshio reads (its triangles are the obstacle; other cells are left out). Relative paths are
        relative to the working directory (a scene file's ``[[obstacles]]`` to the file's folder); kept absolute, so
        that the resolved config written beside a run reads it again from anywhere.
    vertices : array (Q, 3), optional
        The vertices (m), instead of a file.
    faces : int array (F, 3), optional
        The triangles, indices into ``vertices``.
    velocity : 3-vector
        The translation's velocity (m/s).
    angular_velocity : 3-vector
        The rotation's angular velocity omega (rad/s) about ``pivot``.
    pivot : 3-vector
        The point the obstacle turns about (m), at t = 0.

    Every vertex is used by a triangle; there are at least one triangle and no degenerate one (zero area).
    """

    path: str | None = None
    vertices: tuple | None = None
    faces: tuple | None = None
    velocity: tuple = (0.0, 0.0, 0.0)
    angular_velocity: tuple = (0.0, 0.0, 0.0)
    pivot: tuple = (0.0, 0.0, 0.0)
    name = "mesh"
    rank = 4
    analytic = False

    def __post_init__(self):
        if (self.path is None) == (self.vertices is None):
            raise InputError("MeshObstacle.path: give either a mesh file (path) or vertices and faces, not "
                             f"{'both' if self.path is not None else 'neither'}", field="MeshObstacle.path",
                             value=self.path)
        if self.path is not None:
            if not isinstance(self.path, (str, Path)):
                raise InputError(f"MeshObstacle.path must be a file name, got {self.path!r}",
                                 field="MeshObstacle.path", value=self.path)
            if self.faces is not None:
                raise InputError("MeshObstacle.faces goes with vertices, not with path", field="MeshObstacle.faces",
                                 value="...")
            object.__setattr__(self, "path", os.path.abspath(self.path))  # a resolved config re-reads it anywhere
            V, F = _read(self.path)
        else:
            V, F = self._arrays()
        self._check(V, F)
        V.setflags(write=False)
        F.setflags(write=False)
        object.__setattr__(self, "_V", V)
        object.__setattr__(self, "_F", F)
        for name in ("velocity", "angular_velocity", "pivot"):
            v = vector(f"MeshObstacle.{name}", getattr(self, name), 3, "a finite 3-vector")
            object.__setattr__(self, name, tuple(float(c) for c in v))

    def _arrays(self) -> tuple[np.ndarray, np.ndarray]:
        try:
            V = np.array(self.vertices, dtype=float)
        except (TypeError, ValueError):
            V = None
        if V is None or V.ndim != 2 or V.shape[1] != 3 or len(V) < 3 or not np.all(np.isfinite(V)):
            raise InputError("MeshObstacle.vertices must be an array (Q, 3) of finite coordinates, Q >= 3",
                             field="MeshObstacle.vertices", value="...")
        if self.faces is None:
            raise InputError("MeshObstacle.faces is needed with vertices", field="MeshObstacle.faces", value=None)
        try:
            F = np.array(self.faces)
        except (TypeError, ValueError):
            F = np.zeros((0, 0))
        if F.ndim != 2 or F.shape[1] != 3 or len(F) == 0 or not np.issubdtype(F.dtype, np.integer):
            raise InputError("MeshObstacle.faces must be an integer array (F, 3), F >= 1", field="MeshObstacle.faces",
                             value="...")
        # kept as nested tuples: the dataclass compares, hashes and writes them as a scene file's table
        object.__setattr__(self, "vertices", tuple(map(tuple, V.tolist())))
        object.__setattr__(self, "faces", tuple(map(tuple, F.astype(int).tolist())))
        return V, F.astype(np.int64)

    @staticmethod
    def _check(V: np.ndarray, F: np.ndarray) -> None:
        if F.min() < 0 or F.max() >= len(V):
            raise InputError(f"MeshObstacle.faces index vertices 0..{len(V) - 1}, got {F.min()}..{F.max()}",
                             field="MeshObstacle.faces", value="...")
        used = np.zeros(len(V), bool)
        used[F.ravel()] = True
        if not used.all():
            raise InputError(f"MeshObstacle.vertices: {int(np.sum(~used))} vertices belong to no triangle",
                             field="MeshObstacle.vertices", value="...")
        area = 0.5 * np.linalg.norm(np.cross(V[F[:, 1]] - V[F[:, 0]], V[F[:, 2]] - V[F[:, 0]]), axis=1)
        extent = float(np.max(V.max(axis=0) - V.min(axis=0)))
        if extent > MAX_LENGTH:
            raise InputError(f"MeshObstacle.vertices: the mesh spans {extent:g} m, beyond {MAX_LENGTH:g} m",
                             field="MeshObstacle.vertices", value="...")
        bad = np.flatnonzero(area <= 1e-12 * extent * extent)
        if bad.size:
            raise InputError(f"MeshObstacle.faces: {bad.size} triangles have no area (first: face {int(bad[0])})",
                             field="MeshObstacle.faces", value="...")

    # -- the mesh ---------------------------------------------------------------------
    @property
    def triangles(self) -> np.ndarray:
        """The triangles (F, 3), indices into :meth:`points`."""
        return self._F

    @property
    def moving(self) -> bool:
        """Whether it moves (a non-zero velocity or angular velocity)."""
        return any(self.velocity) or any(self.angular_velocity)

    def points(self, t: float = 0.0) -> np.ndarray:
        """The vertices (Q, 3) at time t (s) (m) (module docstring, "Motion")."""
        if not self.moving or t == 0.0:
            return self._V
        return self.carried(self._V, 0.0, t)

    def carried(self, p, t0: float, t1: float) -> np.ndarray:
        """Where points p (P, 3) (m) riding with the obstacle from t0 are at t1 (s): its rigid motion over the step,
        ``R(omega (t1 - t0)) (p - pivot - velocity t0) + pivot + velocity t1``."""
        c, v = np.asarray(self.pivot), np.asarray(self.velocity)
        R = rotation(np.asarray(self.angular_velocity) * (t1 - t0))
        return (np.asarray(p, float) - c - v * t0) @ R.T + c + v * t1

    def derivatives(self, x, hessian: bool = True):
        """Not defined: a triangle mesh has no signed distance (module docstring); the sheet meets it on the IPC
        Toolkit's mesh (:class:`deformable.contact.meshpotential.MeshObstaclePotential`)."""
        raise TypeError("a MeshObstacle has no signed distance: its contact is the IPC Toolkit's, primitive against "
                        "primitive (deformable.contact.meshpotential.MeshObstaclePotential)")

    def picture(self, pv, bounds: np.ndarray, t: float = 0.0, cell: float = 0.0):
        """Its own triangles where they are at time t (s)."""
        F = np.asarray(self.triangles)
        return pv.PolyData(np.asarray(self.points(t)), np.column_stack([np.full(len(F), 3), F]).ravel())

    def table(self) -> dict:
        """The obstacle as a TOML table (the arrays as lists when it has no file; fields at their defaults left
        out)."""
        out = {"kind": self.kind}
        if self.path is not None:
            out["path"] = self.path
        else:
            out["vertices"] = [list(v) for v in self.vertices]
            out["faces"] = [list(f) for f in self.faces]
        for name in ("velocity", "angular_velocity", "pivot"):
            if any(getattr(self, name)):
                out[name] = list(getattr(self, name))
        return out

    @classmethod
    def beside(cls, table: dict, folder) -> dict:
        """A scene file's table with a relative ``path`` made relative to ``folder``, the scene file's folder."""
        path = table.get("path")
        if isinstance(path, (str, Path)) and not os.path.isabs(path):
            return {**table, "path": os.path.join(str(folder), str(path))}
        return table


def icosphere(center, radius: float, level: int) -> MeshObstacle:
    """The sphere's triangulation: an icosahedron subdivided ``level`` times (each triangle into four), its vertices
    on the sphere (F = 20 4^level triangles), as a static :class:`MeshObstacle`."""
    t = (1.0 + 5.0**0.5) / 2.0
    V = [(-1, t, 0), (1, t, 0), (-1, -t, 0), (1, -t, 0), (0, -1, t), (0, 1, t), (0, -1, -t), (0, 1, -t),
         (t, 0, -1), (t, 0, 1), (-t, 0, -1), (-t, 0, 1)]
    F = [(0, 11, 5), (0, 5, 1), (0, 1, 7), (0, 7, 10), (0, 10, 11), (1, 5, 9), (5, 11, 4), (11, 10, 2), (10, 7, 6),
         (7, 1, 8), (3, 9, 4), (3, 4, 2), (3, 2, 6), (3, 6, 8), (3, 8, 9), (4, 9, 5), (2, 4, 11), (6, 2, 10),
         (8, 6, 7), (9, 8, 1)]
    V = [np.asarray(v, float) / np.linalg.norm(v) for v in V]
    for _ in range(level):
        mid: dict = {}

        def middle(a, b):
            key = (min(a, b), max(a, b))
            if key not in mid:
                m = V[a] + V[b]
                V.append(m / np.linalg.norm(m))
                mid[key] = len(V) - 1
            return mid[key]

        F = [g for a, b, c in F for g in ((a, middle(a, b), middle(c, a)), (b, middle(b, c), middle(a, b)),
                                           (c, middle(c, a), middle(b, c)), (middle(a, b), middle(b, c), middle(c, a)))]
    return MeshObstacle(vertices=np.asarray(center, float) + radius * np.asarray(V), faces=np.asarray(F))


def sag(obstacle: MeshObstacle, center, radius: float) -> float:
    """The triangulation's error against the sphere it approximates (m): the largest distance from the sphere to a
    triangle's plane, radius - min over faces of the plane's distance from the centre (vertices on the sphere)."""
    V, F = obstacle.points(), obstacle.triangles
    n = np.cross(V[F[:, 1]] - V[F[:, 0]], V[F[:, 2]] - V[F[:, 0]])
    n /= np.linalg.norm(n, axis=1)[:, None]
    h = np.abs(np.sum(n * (V[F[:, 0]] - np.asarray(center, float)), axis=1))
    return float(radius - np.min(h))
