"""Rigid obstacles: exact signed distances, their derivatives, and the largest safe step along a motion.

Every obstacle is a closed convex solid written as an *inner* convex set K inflated by a rounding radius r >= 0 (its
Minkowski sum with a ball of radius r), so that its signed distance is

    d(x) = sd_K(x) - r                      (positive outside, negative inside; m)

with sd_K the signed distance to K. For x outside K, ``sd_K(x) = |x - P_K(x)|`` (P_K the closest point of K), ``grad
d = n = (x - P_K(x)) / |x - P_K(x)|`` is the outward unit normal and ``hess d = (I - n n^T)(I - DP_K) / |x -
P_K(x)|``, positive semi-definite with ``hess d n = 0``. The shapes:

- :class:`HalfSpace` ``(point, normal)``: K the half-space itself (r = 0), d = n . (x - p); its kind in a scene file
  is "plane" (:class:`deformable.geometry.surfaces.Plane` is the rest shapes' flat surface);
- :class:`Sphere` ``(center, radius)``: K a point, r the radius;
- :class:`Box` ``(lower, upper, rounding)``: an axis-aligned box with edges and corners rounded by ``rounding``;
- :class:`Cylinder` ``(center, radius, height, axis, rounding)``: a capped cylinder, its rim rounded by
  ``rounding``.

Box and cylinder share one formula, the signed distance to a box of half extents e in local coordinates p (3-D for
the box, (rho, z) for the cylinder): with q = |p| - e componentwise and o = max(q, 0),

    sd = |o| + min(max_i q_i, 0),   grad = sign(p) o / |o|,   hess = (diag(q > 0) - grad grad^T) / |o|

outside (|o| > 0), and the inward face normal, zero Hessian, inside. A sphere is that box with e = 0. Every shape is
a registered class (:mod:`deformable.registry`) whose ``name`` is its kind in a scene file's ``[[obstacles]]``
tables; a new convex shape is one subclass with a ``name``, :meth:`Obstacle.derivatives` and
:meth:`Obstacle.picture`.

Safe steps. The sheet must never cross an obstacle between two Newton iterates (Li et al. 2020, "Incremental
Potential Contact", ACM TOG 39(4), section 4). Along a segment x + t dx the signed distance phi(t) = d(x + t dx) of
a convex obstacle is convex in t, so Newton's iteration on phi(t) = L from t = 0 (where phi > L) climbs
monotonically to the first root from below: every iterate is a safe step. :meth:`Obstacle.first_contact` returns
that root (to round-off; infinity when phi never reaches L).

Range. The signed distance near the surface is a difference of numbers of the obstacle's size, with a round-off of
about 4 eps times that size; every length of an obstacle (radius, height, a box's sides) is therefore at most
:data:`MAX_LENGTH`, where that round-off is 1e-6 m. A half-space computes its distance to full precision.
"""

from __future__ import annotations

import math
import warnings
from dataclasses import dataclass, fields
from typing import ClassVar

import numpy as np

from ..checks import known_keys, vector
from ..errors import InputError
from ..registry import Registered

__all__ = ["Obstacle", "HalfSpace", "Sphere", "Box", "Cylinder", "from_table", "to_table", "MAX_LENGTH"]

#: Newton iterations of :meth:`Obstacle.first_contact` (quadratic convergence needs a handful)
_ROOT_ITERATIONS = 60
#: the largest length of an obstacle (m): the signed distance near its surface keeps 4 eps x 1e9 m < 1e-6 m
MAX_LENGTH = 1e9


def _vector(owner: str, name: str, value, unit: bool = False) -> tuple:
    v = vector(f"{owner}.{name}", value, 3, "a finite 3-vector")
    if unit:
        norm = float(np.linalg.norm(v))
        if norm == 0:
            raise InputError(f"{owner}.{name} must be non-zero, got {value!r}", field=f"{owner}.{name}", value=value)
        if abs(norm - 1) > 4 * np.finfo(float).eps:  # a unit vector stays as it is (a table reads back equal)
            v = v / norm
    return tuple(float(c) for c in v)


def _length(owner: str, name: str, value, positive: bool = True) -> float:
    if isinstance(value, bool) or not isinstance(value, (int, float)) or not math.isfinite(value) or (
            value <= 0 if positive else value < 0):
        raise InputError(f"{owner}.{name} must be a finite {'positive' if positive else 'non-negative'} number "
                         f"(m), got {value!r}", field=f"{owner}.{name}", value=value)
    _within_range(owner, name, value)
    return float(value)


def _within_range(owner: str, name: str, value: float) -> None:
    """InputError for a length beyond :data:`MAX_LENGTH` (module docstring, "Range"), with the reason."""
    if value > MAX_LENGTH:
        raise InputError(f"{owner}.{name} must be at most {MAX_LENGTH:g} m, got {value!r}: the signed distance of a "
                         f"point near the surface, a difference of numbers of that size, is lost in round-off "
                         f"({4 * np.finfo(float).eps * float(value):.3g} m); a plane (kind \"plane\") is the limit of "
                         "so large an obstacle", field=f"{owner}.{name}", value=value)


def box_distance(p: np.ndarray, e: np.ndarray, hessian: bool = True):
    """Signed distance to the box |p_i| <= e_i in local coordinates, its gradient and Hessian.

    Parameters
    ----------
    p : array (P, k)
        Points relative to the box centre (k = 2 or 3).
    e : array (k,)
        Half extents, >= 0 (e = 0: a point).
    hessian : bool
        Also the Hessian (else None).

    Returns
    -------
    sd (P,), grad (P, k), hess (P, k, k) or None
    """
    s = np.where(p < 0, -1.0, 1.0)
    q = np.abs(p) - e
    o = np.maximum(q, 0.0)
    ro = np.sqrt(np.sum(o * o, axis=1))
    out = ro > 0
    inner = np.max(q, axis=1)
    sd = ro + np.minimum(inner, 0.0)
    grad = np.zeros_like(p)
    grad[out] = s[out] * o[out] / ro[out, None]
    inside = np.flatnonzero(~out)
    face = np.argmax(q[inside], axis=1)
    grad[inside, face] = s[inside, face]
    hess = None
    if hessian:
        hess = np.zeros(p.shape + (p.shape[1],))
        mask = ((q > 0) | (e == 0)).astype(float)
        g = grad[out]
        hess[out] = (mask[out][:, :, None] * np.eye(p.shape[1]) - g[:, :, None] * g[:, None, :]) / ro[out, None, None]
    return sd, grad, hess


@dataclass(frozen=True)
class Obstacle(Registered, family="obstacle"):
    """A rigid obstacle: a convex analytic shape (module docstring), whose subclasses give :meth:`derivatives`, or a
    triangle mesh (:class:`deformable.contact.meshobstacle.MeshObstacle`, ``analytic`` False), which has none.

    Every method takes points x as an array (P, 3) in scene units (m).

    Class attributes
    ----------------
    analytic : bool
        Whether the shape has a signed distance (:meth:`derivatives`): the sheet then meets it at its contact points
        (:mod:`deformable.contact.potential`); a mesh meets the sheet's triangles
        (:mod:`deformable.contact.meshpotential`).
    moving : bool
        Whether it moves on a prescribed path (the analytic shapes stand still).
    """

    analytic: ClassVar[bool] = True
    moving: ClassVar[bool] = False

    @property
    def kind(self) -> str:
        """Its kind in a scene file: the registry name."""
        return self.name

    def derivatives(self, x: np.ndarray, hessian: bool = True):
        """Signed distance d (P,) (m), its gradient n (P, 3) (the outward unit normal) and Hessian (P, 3, 3) (1/m).

        With ``hessian=False`` the Hessian is None.
        """
        raise NotImplementedError

    def distance(self, x: np.ndarray) -> np.ndarray:
        """Signed distance (P,) (m): positive outside, negative inside."""
        return self.derivatives(np.asarray(x, float).reshape(-1, 3), hessian=False)[0]

    def first_contact(self, x: np.ndarray, dx: np.ndarray, level=0.0, t_max: float = 1.0) -> np.ndarray:
        """The first t > 0 at which d(x + t dx) reaches ``level``, per point (module docstring).

        Parameters
        ----------
        x, dx : arrays (P, 3)
            Start points (with d(x) > level) and their displacements (m).
        level : float or array (P,)
            The distance not to go below (m).
        t_max : float
            Roots beyond t_max are not refined: such points get infinity.

        Returns
        -------
        t : array (P,)
            The root, approached from below (every value returned is a safe step), or infinity where d stays above
            ``level`` on [0, t_max].
        """
        x = np.asarray(x, float).reshape(-1, 3)
        dx = np.asarray(dx, float).reshape(-1, 3)
        level = np.broadcast_to(np.asarray(level, float), (x.shape[0],))
        t = np.full(x.shape[0], np.inf)
        d0 = self.distance(x)
        speed = np.sqrt(np.sum(dx * dx, axis=1))
        # d is 1-Lipschitz: a point whose gap exceeds its whole travel cannot reach the level
        idx = np.flatnonzero(d0 - level <= speed * t_max)
        ti = np.zeros(idx.size)
        tol = 1e-13 * np.maximum(np.abs(level[idx]) + speed[idx], 1e-300)
        for _ in range(_ROOT_ITERATIONS):
            if idx.size == 0:
                break
            d, n, _ = self.derivatives(x[idx] + ti[:, None] * dx[idx], hessian=False)
            gap = d - level[idx]
            slope = np.sum(n * dx[idx], axis=1)
            done = gap <= tol
            never = ~done & (slope >= 0)  # convex phi, rising: it never comes down to the level
            t[idx[done]] = ti[done]
            step = np.where(never | done, 0.0, gap / np.where(slope < 0, -slope, 1.0))
            ti = ti + step
            beyond = ti > t_max
            keep = ~(done | never | beyond)
            idx, ti, tol = idx[keep], ti[keep], tol[keep]
        t[idx] = ti  # not converged to round-off within the iterations: still a safe step
        return t

    @classmethod
    def beside(cls, table: dict, folder) -> dict:
        """A scene file's ``[[obstacles]]`` table of this kind with the file names in it made relative to
        ``folder``, the scene file's folder (an analytic shape names none: the table as it is)."""
        return table

    def table(self) -> dict:
        """The obstacle as a TOML table: ``kind`` and its fields."""
        out = {"kind": self.kind}
        for f in fields(self):
            out[f.name] = getattr(self, f.name)
        return out

    def picture(self, pv, bounds: np.ndarray, t: float = 0.0, cell: float = 0.0):
        """Its picture, a pyvista mesh made with the module ``pv`` (:func:`deformable.io.render.obstacle_mesh`):
        ``bounds`` (2, 3) the sheet's extent, t the time (s), ``cell`` the sheet's longest cell diagonal h (m). A
        rounded solid is drawn as its sharp core, never outside the solid, so that a cloth resting on its rounded
        rim is not drawn cut by a sharp one."""
        raise InputError(f"no picture for an obstacle of kind {self.kind!r}: {type(self).__name__} needs a "
                         "picture method", field="obstacle", value=self.kind)


@dataclass(frozen=True)
class HalfSpace(Obstacle):
    """The solid half-space behind a plane: d = normal . (x - point); ``normal`` points out of the solid.

    Parameters
    ----------
    point : 3-vector
        A point of the plane (m).
    normal : 3-vector
        The outward normal (normalised here).
    """

    point: tuple = (0.0, 0.0, 0.0)
    normal: tuple = (0.0, 0.0, 1.0)
    name = "plane"
    rank = 0

    def __post_init__(self):
        object.__setattr__(self, "point", _vector("HalfSpace", "point", self.point))
        object.__setattr__(self, "normal", _vector("HalfSpace", "normal", self.normal, unit=True))

    def derivatives(self, x, hessian: bool = True):
        x = np.asarray(x, float).reshape(-1, 3)
        n = np.asarray(self.normal)
        d = (x - np.asarray(self.point)) @ n
        return d, np.broadcast_to(n, x.shape).copy(), np.zeros(x.shape + (3,)) if hessian else None

    def picture(self, pv, bounds: np.ndarray, t: float = 0.0, cell: float = 0.0):
        """A square patch twice the largest extent of ``bounds`` (1 m when that is 0), centred under the bounds'
        centre (its projection onto the plane)."""
        n = np.asarray(self.normal)
        centre = 0.5 * (bounds[0] + bounds[1])
        centre = centre - float((centre - np.asarray(self.point)) @ n) * n  # projected onto the plane
        size = 2.0 * float(np.max(bounds[1] - bounds[0])) or 1.0
        return pv.Plane(center=centre, direction=n, i_size=size, j_size=size)


@dataclass(frozen=True)
class Sphere(Obstacle):
    """A solid ball: d = |x - center| - radius.

    Parameters
    ----------
    center : 3-vector (m)
    radius : float (m), positive
    """

    center: tuple = (0.0, 0.0, 0.0)
    radius: float = 1.0
    name = "sphere"
    rank = 1

    def __post_init__(self):
        object.__setattr__(self, "center", _vector("Sphere", "center", self.center))
        object.__setattr__(self, "radius", _length("Sphere", "radius", self.radius))

    def derivatives(self, x, hessian: bool = True):
        x = np.asarray(x, float).reshape(-1, 3)
        sd, g, H = box_distance(x - np.asarray(self.center), np.zeros(3), hessian)
        return sd - self.radius, g, H

    def picture(self, pv, bounds: np.ndarray, t: float = 0.0, cell: float = 0.0):
        """The ball smaller by the sag h^2 / (8 R) of the chord h = ``cell`` (at most R / 2): the sheet touches it
        at its contact points, and the flat face between two of them may cut the ball by that much
        (:mod:`deformable.contact.points`); drawn at full size the ball would show through a cloth on it."""
        R = self.radius
        return pv.Sphere(radius=R - min(cell * cell / (8 * R), 0.5 * R), center=self.center, theta_resolution=64,
                         phi_resolution=64)


@dataclass(frozen=True)
class Box(Obstacle):
    """An axis-aligned solid box [lower, upper] with edges and corners rounded by ``rounding``.

    Parameters
    ----------
    lower, upper : 3-vectors (m), lower < upper componentwise
    rounding : float (m), 0 <= rounding <= half the shortest side
    """

    lower: tuple = (-0.5, -0.5, -0.5)
    upper: tuple = (0.5, 0.5, 0.5)
    rounding: float = 0.0
    name = "box"
    rank = 2

    def __post_init__(self):
        lo, hi = _vector("Box", "lower", self.lower), _vector("Box", "upper", self.upper)
        if not all(a < b for a, b in zip(lo, hi)):
            raise InputError(f"Box.lower must lie below Box.upper in every coordinate, got {lo!r} and {hi!r}",
                             field="Box.lower", value=lo)
        _within_range("Box", "upper - lower", max(b - a for a, b in zip(lo, hi)))
        r = _length("Box", "rounding", self.rounding, positive=False)
        if r > 0.5 * min(b - a for a, b in zip(lo, hi)):
            raise InputError(f"Box.rounding must be at most half the shortest side, got {r!r}", field="Box.rounding",
                             value=r)
        object.__setattr__(self, "lower", lo)
        object.__setattr__(self, "upper", hi)
        object.__setattr__(self, "rounding", r)

    def derivatives(self, x, hessian: bool = True):
        x = np.asarray(x, float).reshape(-1, 3)
        lo, hi = np.asarray(self.lower), np.asarray(self.upper)
        sd, g, H = box_distance(x - 0.5 * (lo + hi), 0.5 * (hi - lo) - self.rounding, hessian)
        return sd - self.rounding, g, H

    def picture(self, pv, bounds: np.ndarray, t: float = 0.0, cell: float = 0.0):
        """Its sharp core: the box shrunk by its rounding."""
        r = self.rounding
        lo, hi = np.asarray(self.lower) + r, np.asarray(self.upper) - r
        return pv.Box(bounds=(lo[0], hi[0], lo[1], hi[1], lo[2], hi[2]))


@dataclass(frozen=True)
class Cylinder(Obstacle):
    """A solid capped cylinder (a round table): |z| <= height / 2 along ``axis``, radius ``radius`` across.

    Parameters
    ----------
    center : 3-vector (m)
        The centre of the cylinder (half way up).
    radius, height : float (m), positive
    axis : 3-vector
        The cylinder's axis (normalised here).
    rounding : float (m), 0 <= rounding <= min(radius, height / 2)
        Radius of the rounded rims.
    """

    center: tuple = (0.0, 0.0, 0.0)
    radius: float = 0.5
    height: float = 0.1
    axis: tuple = (0.0, 0.0, 1.0)
    rounding: float = 0.0
    name = "cylinder"
    rank = 3

    def __post_init__(self):
        object.__setattr__(self, "center", _vector("Cylinder", "center", self.center))
        object.__setattr__(self, "axis", _vector("Cylinder", "axis", self.axis, unit=True))
        R = _length("Cylinder", "radius", self.radius)
        H = _length("Cylinder", "height", self.height)
        r = _length("Cylinder", "rounding", self.rounding, positive=False)
        if r > min(R, 0.5 * H):
            raise InputError(f"Cylinder.rounding must be at most min(radius, height / 2), got {r!r}",
                             field="Cylinder.rounding", value=r)
        object.__setattr__(self, "radius", R)
        object.__setattr__(self, "height", H)
        object.__setattr__(self, "rounding", r)

    def derivatives(self, x, hessian: bool = True):
        x = np.asarray(x, float).reshape(-1, 3)
        a = np.asarray(self.axis)
        u = x - np.asarray(self.center)
        z = u @ a
        w = u - z[:, None] * a
        rho = np.sqrt(np.sum(w * w, axis=1))
        safe = np.maximum(rho, 1e-300)
        er = np.where(rho[:, None] > 0, w / safe[:, None], _perpendicular(a))
        e = np.array([self.radius - self.rounding, 0.5 * self.height - self.rounding])
        sd, g2, H2 = box_distance(np.stack([rho, z], axis=1), e, hessian)
        g = g2[:, :1] * er + g2[:, 1:] * a
        H = None
        if hessian:
            B = np.stack([er, np.broadcast_to(a, er.shape)], axis=2)  # (P, 3, 2): d(rho, z)/dx
            H = np.einsum("pik,pkl,pjl->pij", B, H2, B)
            # the radial direction turns with x: grad_rho-part g_rho (I - a a^T - er er^T) / rho
            turn = np.eye(3) - np.outer(a, a) - er[:, :, None] * er[:, None, :]
            H += np.where(rho > 0, g2[:, 0] / safe, 0.0)[:, None, None] * turn
        return sd - self.rounding, g, H

    def picture(self, pv, bounds: np.ndarray, t: float = 0.0, cell: float = 0.0):
        """Its sharp core: radius and half height less the rounding."""
        r = self.rounding
        return pv.Cylinder(center=self.center, direction=self.axis, radius=self.radius - r,
                           height=self.height - 2 * r, resolution=96, capping=True)


def _perpendicular(a: np.ndarray) -> np.ndarray:
    """A unit vector perpendicular to the unit vector a."""
    e = np.array([1.0, 0.0, 0.0]) if abs(a[0]) < 0.9 else np.array([0.0, 1.0, 0.0])
    p = e - (e @ a) * a
    return p / np.linalg.norm(p)


def from_table(table, source: str = "obstacle") -> Obstacle:
    """An obstacle from a TOML table ``{kind = "sphere", center = [...], radius = ...}``.

    Raises
    ------
    ValueError
        Not a table, a missing or unknown ``kind``, an unknown key (named with the known ones), a bad value.
    """
    if isinstance(table, Obstacle):
        return table
    if not isinstance(table, dict):
        raise InputError(f"{source} must be a table with a kind ({', '.join(Obstacle.names())}), got {table!r}",
                         field=source, value=table)
    table = dict(table)
    kind = table.pop("kind", None)
    if kind not in Obstacle.names():
        raise InputError(f"{source} needs kind = one of {', '.join(map(repr, Obstacle.names()))}, got {kind!r}",
                         field=source, value=kind)
    cls = Obstacle.lookup(kind)
    known_keys(table, ["kind"] + [f.name for f in fields(cls)], f"in {source} of kind {kind!r}")
    return cls(**table)


def to_table(obstacle: Obstacle) -> dict:
    """The TOML table of an obstacle (:meth:`Obstacle.table`)."""
    return obstacle.table()


def __getattr__(name):
    """Former names, each warning once: ``Plane`` (the half-space obstacle; ``Plane`` is the rest-shape surface now)
    and ``OBSTACLES`` (the registry: ``Obstacle.names()``, ``Obstacle.lookup(kind)``)."""
    former = {"Plane": (lambda: HalfSpace, "deformable.HalfSpace"),
              "OBSTACLES": (lambda: {n: Obstacle.lookup(n) for n in Obstacle.names()}, "Obstacle.lookup(kind)")}
    if name in former:
        value, instead = former[name]
        warnings.warn(f"deformable.contact.obstacles.{name} is deprecated; use {instead}", DeprecationWarning,
                      stacklevel=2)
        return value()
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
