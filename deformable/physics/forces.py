r"""External forces f(r, t) of the equation of motion (11), some of them depending on the state.

Kinds, so that each backend can integrate them its own way:

- ``"body"``: a density per unit of parameter area (N/m^2): :class:`Gravity`
  (``mu g``) and :class:`BodyForce`;
- ``"edge"``: :class:`EdgeLoad`, a traction per unit of parameter length on an edge (N/m);
- ``"point"``: :class:`PointLoad`, a concentrated force at a parameter point (N);
- ``"moment"``: :class:`EdgeMoment`, a moment per unit of parameter length on an edge (N m/m), about the
  edge's rest tangent: conservative, the potential ``-m theta`` of the edge's rotation, with its exact
  gradient and Hessian;
- ``"spring"``: :class:`Spring`, the paper's "coil" (section 5, the flag): a
  spring between a material point of the sheet and an anchor (which may move),
  ``f = -k (|d| - L0) d / |d|``, ``d = r(a) - anchor(t)``: conservative, with
  the energy ``k (|d| - L0)^2 / 2`` and its exact Hessian for the implicit step;
- ``"pressure"``: :class:`Pressure`, a follower pressure p on the deformed surface along its normal
  r_1 x r_2, as the potential -p V of the enclosed volume (:mod:`deformable.physics.pressure`): exact
  where every edge is held;
- ``"surface"``: :class:`Wind`, aerodynamic pressure on the sheet's normal with
  the relative velocity u = w - v (the usual cloth wind model),
  ``f = c (u . n) |u . n| n`` per unit of *current* area (|r_1 x r_2| per unit
  parameter area), c = rho C_d / 2; not conservative; its Jacobian in the
  velocity, ``-df/dv = 2 c |u . n| n n^T`` (positive semi-definite), is a
  damping the implicit step takes implicitly.

Each may vary in time through ``time``, a callable ``t -> factor`` such as
:class:`Sinusoidal`; a body force may also be a callable of (a1, a2, t), a
spring's anchor and the wind's velocity callables of t.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Callable

import numpy as np

from ..checks import function, real, vector
from ..errors import InputError
from ..geometry.sheet import EDGES

__all__ = ["Gravity", "BodyForce", "EdgeLoad", "EdgeMoment", "PointLoad", "Pressure", "Spring", "Wind", "Sinusoidal", "Force"]


def _vector(name: str, value) -> np.ndarray:
    return vector(name, value, 3, "a finite 3-vector")


@dataclass(frozen=True)
class Sinusoidal:
    """Time factor ``offset + amplitude sin(2 pi frequency t + phase)`` (frequency in Hz)."""

    amplitude: float = 1.0
    frequency: float = 1.0
    phase: float = 0.0
    offset: float = 0.0

    def __post_init__(self):
        for name in ("amplitude", "frequency", "phase", "offset"):
            object.__setattr__(self, name, real(f"Sinusoidal.{name}", getattr(self, name)))

    def __call__(self, t: float) -> float:
        return self.offset + self.amplitude * np.sin(2 * np.pi * self.frequency * t + self.phase)


def _factor(time, t: float) -> float:
    return 1.0 if time is None else float(time(t))


@dataclass(frozen=True)
class Gravity:
    """Weight ``mu g direction`` per unit area (N/m^2); g in m/s^2."""

    g: float = 9.81
    direction: tuple[float, float, float] = (0.0, 0.0, -1.0)
    time: Callable[[float], float] | None = None
    kind = "body"

    def __post_init__(self):
        object.__setattr__(self, "g", real("Gravity.g", self.g))
        d = _vector("Gravity.direction", self.direction)
        largest = float(np.max(np.abs(d)))
        if largest == 0:
            raise InputError(f"Gravity.direction must be a non-zero 3-vector, got {self.direction!r}",
                             field="Gravity.direction", value=self.direction)
        d = d / largest  # scaled first, so that neither a tiny nor a huge vector loses its direction
        object.__setattr__(self, "direction", tuple(d / np.linalg.norm(d)))
        function("Gravity.time", self.time)

    def density(self, a1, a2, t: float, mu) -> np.ndarray:
        """Force density at points (a1, a2) of any shape S: array S + (3,)."""
        mu = np.broadcast_to(np.asarray(mu, float), np.shape(a1))
        return (_factor(self.time, t) * self.g * mu)[..., None] * np.asarray(self.direction)


@dataclass(frozen=True)
class BodyForce:
    """A force density per unit area (N/m^2), constant or a callable of (a1, a2, t).

    Parameters
    ----------
    f : 3-vector, or callable (a1, a2, t) -> (..., 3)
    where : callable (a1, a2) -> bool array, optional
        Region the force acts on (default: the whole sheet).
    time : callable t -> float, optional
        Time factor, e.g. ``Sinusoidal(frequency=0.5)``.
    """

    f: object = (0.0, 0.0, 0.0)
    where: Callable | None = None
    time: Callable[[float], float] | None = None
    kind = "body"

    def __post_init__(self):
        if not callable(self.f):
            object.__setattr__(self, "f", tuple(_vector("BodyForce.f", self.f)))
        function("BodyForce.where", self.where)
        function("BodyForce.time", self.time)

    def density(self, a1, a2, t: float, mu=None) -> np.ndarray:
        a1, a2 = np.broadcast_arrays(np.asarray(a1, float), np.asarray(a2, float))
        if callable(self.f):
            out = np.broadcast_to(np.asarray(self.f(a1, a2, t), float), a1.shape + (3,)).copy()
        else:
            out = np.broadcast_to(np.asarray(self.f), a1.shape + (3,)).copy()
        if self.where is not None:
            out *= np.asarray(self.where(a1, a2), bool)[..., None]
        return _factor(self.time, t) * out


@dataclass(frozen=True)
class EdgeLoad:
    """A traction per unit of parameter length (N/m) on one edge.

    ``f`` is a 3-vector or a callable (a1, a2, t) -> (..., 3) evaluated on the edge.
    """

    edge: str
    f: object = (0.0, 0.0, 0.0)
    time: Callable[[float], float] | None = None
    kind = "edge"

    def __post_init__(self):
        if not isinstance(self.edge, str) or self.edge not in EDGES:
            raise InputError(f"EdgeLoad.edge must be one of {sorted(EDGES)}, got {self.edge!r}")
        if not callable(self.f):
            object.__setattr__(self, "f", tuple(_vector("EdgeLoad.f", self.f)))
        function("EdgeLoad.time", self.time)

    def traction(self, a1, a2, t: float) -> np.ndarray:
        a1, a2 = np.broadcast_arrays(np.asarray(a1, float), np.asarray(a2, float))
        if callable(self.f):
            out = np.broadcast_to(np.asarray(self.f(a1, a2, t), float), a1.shape + (3,))
        else:
            out = np.broadcast_to(np.asarray(self.f), a1.shape + (3,))
        return _factor(self.time, t) * out


@dataclass(frozen=True)
class EdgeMoment:
    r"""A moment per unit of parameter length (N m/m) on one edge, about the edge's tangent at rest.

    The edge's rotation theta at each point is the angle by which the sheet's tangent across the edge (r_1
    on "left" and "right", r_2 on "bottom" and "top", pointing out of the sheet) has turned about the
    rest tangent e0 of the edge (a fixed axis, right-handed: a positive m turns the outward tangent u0
    towards e0 x u0), measured from its rest direction u0 and unwrapped, so that theta runs past pi (a
    sheet rolled into a full circle has theta = 2 pi at its end). With the potential

        Pi = -int_edge m theta ds,      theta = atan2(d . v0, d . u0),  v0 = e0 x u0,

    (d the outward tangent) the load is conservative, its work m theta per unit length, and its gradient
    and Hessian are exact (:meth:`angle`); the moment about a fixed axis is the classical end moment of a
    rolled cantilever (Sze, Liu and Lo 2004, "Popular benchmark problems for geometric nonlinear analysis of
    shells", FEAD 40, test 3.2). It stays "about the edge's tangent" while the edge keeps its
    direction, as there; where the edge itself turns, its component along the turned edge is what acts.

    Parameters
    ----------
    edge : "left", "right", "bottom" or "top"
    m : float or callable (a1, a2, t) -> (...)
        The moment per unit length (N m/m = N), evaluated on the edge.
    time : callable t -> float, optional
        A factor in time.
    """

    edge: str
    m: object = 0.0
    time: Callable[[float], float] | None = None
    kind = "moment"

    def __post_init__(self):
        if not isinstance(self.edge, str) or self.edge not in EDGES:
            raise InputError(f"EdgeMoment.edge must be one of {sorted(EDGES)}, got {self.edge!r}",
                             field="EdgeMoment.edge", value=self.edge)
        if not callable(self.m):
            object.__setattr__(self, "m", real("EdgeMoment.m", self.m))
        function("EdgeMoment.time", self.time)

    def moment(self, a1, a2, t: float) -> np.ndarray:
        """m at the edge points (a1, a2) at time t (N m/m), shape of a1."""
        a1, a2 = np.broadcast_arrays(np.asarray(a1, float), np.asarray(a2, float))
        m = np.broadcast_to(np.asarray(self.m(a1, a2, t) if callable(self.m) else self.m, float), a1.shape)
        return _factor(self.time, t) * m

    @staticmethod
    def angle(d: np.ndarray, u0: np.ndarray, v0: np.ndarray, reference: np.ndarray):
        """theta, d theta / d d and d^2 theta / d d^2 at P points: (P,), (P, 3), (P, 3, 3).

        ``d`` (P, 3) the tangents, ``u0``, ``v0`` (P, 3) the rest frame, ``reference`` (P,) the angles to
        unwrap against (theta lies within pi of it). With x = d . u0, y = d . v0, rho^2 = x^2 + y^2:
        dtheta = (x v0 - y u0) / rho^2, and in (x, y) the Hessian [[2 x y, y^2 - x^2], [y^2 - x^2, -2 x y]] / rho^4.
        """
        x, y = np.sum(d * u0, -1), np.sum(d * v0, -1)
        rho2 = x**2 + y**2
        theta = reference + np.angle(np.exp(1j * (np.arctan2(y, x) - reference)))
        g = (x[:, None] * v0 - y[:, None] * u0) / rho2[:, None]
        hxx, hxy = 2 * x * y / rho2**2, (y**2 - x**2) / rho2**2
        uu, vv = np.einsum("pi,pj->pij", u0, u0), np.einsum("pi,pj->pij", v0, v0)
        uv = np.einsum("pi,pj->pij", u0, v0)
        H = hxx[:, None, None] * (uu - vv) + hxy[:, None, None] * (uv + np.swapaxes(uv, 1, 2))
        return theta, g, H


@dataclass(frozen=True)
class Pressure:
    r"""A follower pressure p (Pa = N/m^2) on the deformed sheet, along its normal: the force density
    ``p r_1 x r_2`` per unit parameter area (p |r_1 x r_2| n per unit current area, n = r_1 x r_2 / |.|).

    It is the gradient of the potential ``-p V``, V = (1/3) int r . (r_1 x r_2) da the volume of the cone from
    the origin to the sheet, exactly when the boundary terms of the variation vanish: every edge held (Pin or
    Clamp), which :class:`deformable.physics.pressure.PressurePotential` checks. On a sheet with a free edge a
    follower pressure is not conservative (its load stiffness is not symmetric; Schweizerhof and Ramm 1984,
    "Displacement dependent pressure loads in nonlinear finite element analyses", Computers & Structures 18,
    1099-1114) and is refused. Its exact Hessian enters Newton; it scales with ``equilibrium``'s load steps
    and an arc length's load factor, and with ``time``.
    """

    p: float = 0.0
    time: Callable[[float], float] | None = None
    kind = "pressure"

    def __post_init__(self):
        object.__setattr__(self, "p", real("Pressure.p", self.p))
        function("Pressure.time", self.time)

    def pressure(self, t: float) -> float:
        """p at time t (Pa)."""
        return _factor(self.time, t) * self.p


@dataclass(frozen=True)
class PointLoad:
    """A concentrated force (N) at the parameter point ``at`` = (a1, a2)."""

    at: tuple[float, float]
    f: tuple[float, float, float] = (0.0, 0.0, 0.0)
    time: Callable[[float], float] | None = None
    kind = "point"

    def __post_init__(self):
        object.__setattr__(self, "at", _point("PointLoad.at", self.at))
        object.__setattr__(self, "f", tuple(_vector("PointLoad.f", self.f)))
        function("PointLoad.time", self.time)

    def force(self, t: float) -> np.ndarray:
        return _factor(self.time, t) * np.asarray(self.f)


def _point(name: str, value) -> tuple:
    return tuple(vector(name, value, 2, "a parameter point (a1, a2)"))


def _of_time(name: str, value):
    """A 3-vector, or a callable of t returning one (checked when called)."""
    return value if callable(value) else tuple(_vector(name, value))


def _at_time(name: str, value, t: float) -> np.ndarray:
    return _vector(f"{name} at t = {t:g}", value(t)) if callable(value) else np.asarray(value, float)


@dataclass(frozen=True)
class Spring:
    """The paper's "coil": a spring from the material point ``at`` to an anchor (section 5, the flag).

    Parameters
    ----------
    at : (a1, a2)
        The material point (parameter coordinates).
    anchor : 3-vector or callable t -> (3,)
        Where the spring's other end is (m), fixed or moving.
    stiffness : float
        k (N/m), non-negative.
    rest_length : float
        L0 (m), non-negative; 0 makes the force linear, ``-k (r - anchor)``.
    """

    at: tuple[float, float]
    anchor: object = (0.0, 0.0, 0.0)
    stiffness: float = 1.0
    rest_length: float = 0.0
    kind = "spring"

    def __post_init__(self):
        object.__setattr__(self, "at", _point("Spring.at", self.at))
        object.__setattr__(self, "anchor", _of_time("Spring.anchor", self.anchor))
        for name in ("stiffness", "rest_length"):
            v = getattr(self, name)
            if isinstance(v, bool) or not isinstance(v, (int, float)) or not np.isfinite(v) or v < 0:
                raise InputError(f"Spring.{name} must be a finite non-negative number, got {v!r}")
            object.__setattr__(self, name, float(v))

    def _d(self, r, t):
        d = np.asarray(r, float) - _at_time("Spring.anchor", self.anchor, t)
        return d, float(np.linalg.norm(d))

    def energy(self, r, t: float) -> float:
        """k (|d| - L0)^2 / 2 (J) with the sheet's point at r."""
        _, length = self._d(r, t)
        return 0.5 * self.stiffness * (length - self.rest_length) ** 2

    def force(self, r, t: float) -> np.ndarray:
        """The force on the sheet's point (N), (3,)."""
        d, length = self._d(r, t)
        if self.rest_length == 0 or length == 0:
            return -self.stiffness * d
        return -self.stiffness * (1 - self.rest_length / length) * d

    def hessian(self, r, t: float) -> np.ndarray:
        """d^2 energy / dr^2 (N/m), (3, 3): k I for L0 = 0; else k (I - L0 (I - e e^T) / |d|), made definite."""
        d, length = self._d(r, t)
        if self.rest_length == 0 or length == 0:
            return self.stiffness * np.eye(3)
        e = d / length
        H = self.stiffness * (np.eye(3) - self.rest_length / length * (np.eye(3) - np.outer(e, e)))
        w, U = np.linalg.eigh(H)  # a compressed spring's transverse stiffness is negative: keep its positive part
        return (U * np.maximum(w, 0.0)) @ U.T


@dataclass(frozen=True)
class Wind:
    """Aerodynamic pressure on the sheet, ``c ((w - v)·n) |(w - v)·n| n`` per unit current area (N/m^2).

    Parameters
    ----------
    velocity : 3-vector or callable t -> (3,)
        The wind w (m/s).
    coefficient : float
        c = rho C_d / 2 (kg/m^3), non-negative (air: rho = 1.2 kg/m^3, C_d about 1: c = 0.6).
    time : callable t -> float, optional
        A factor on the wind velocity (gusts).
    """

    velocity: object = (0.0, 0.0, 0.0)
    coefficient: float = 0.6
    time: Callable[[float], float] | None = None
    kind = "surface"

    def __post_init__(self):
        object.__setattr__(self, "velocity", _of_time("Wind.velocity", self.velocity))
        c = self.coefficient
        if isinstance(c, bool) or not isinstance(c, (int, float)) or not np.isfinite(c) or c < 0:
            raise InputError(f"Wind.coefficient must be a finite non-negative number, got {c!r}")
        object.__setattr__(self, "coefficient", float(c))
        function("Wind.time", self.time)

    def _normal_speed(self, n, v, t):
        w = _factor(self.time, t) * _at_time("Wind.velocity", self.velocity, t)
        return np.einsum("pa,pa->p", w - np.asarray(v, float), n)

    def density(self, n, area, v, t: float) -> np.ndarray:
        """Force per unit parameter area (N/m^2), (P, 3), at points with normals n (P, 3), area elements
        |r_1 x r_2| (P,) and velocities v (P, 3)."""
        un = self._normal_speed(n, v, t)
        return (self.coefficient * un * np.abs(un) * area)[:, None] * n

    def damping(self, n, area, v, t: float) -> np.ndarray:
        """-d density / dv per unit parameter area (kg/(m^2 s)), (P, 3, 3): 2 c |u . n| area n n^T."""
        un = self._normal_speed(n, v, t)
        return (2 * self.coefficient * np.abs(un) * area)[:, None, None] * n[:, :, None] * n[:, None, :]


Force = Gravity | BodyForce | EdgeLoad | EdgeMoment | PointLoad | Pressure | Spring | Wind
