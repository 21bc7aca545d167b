r"""External forces f(r, t) of the equation of motion (11), some of them depending on the state.

Every force is a :class:`Load` and says itself how it enters F of eq. (21), by the role it subclasses;
:class:`~deformable.physics.loads.Loads` asks it, never its name:

- :class:`AppliedLoad`, independent of the state: :meth:`AppliedLoad.applied` integrates it over the
  backend's hooks. :class:`Gravity` (``mu g``) and :class:`BodyForce`, densities per unit of parameter area
  (N/m^2); :class:`EdgeLoad`, a traction per unit of parameter length on an edge (N/m); :class:`PointLoad`,
  a concentrated force at a parameter point (N);
- :class:`ConservativeLoad`, with a potential that depends on the state: its ``potential`` class computes
  the energy, gradient and Hessian of all the scene's loads of its class together. :class:`Spring`, the
  paper's "coil" (section 5, the flag), ``f = -k (|d| - L0) d / |d|``, ``d = r(a) - anchor(t)``, energy
  ``k (|d| - L0)^2 / 2`` (:class:`SpringPotential`); :class:`EdgeMoment`, a moment per unit of parameter
  length on an edge (N m/m) about its rest tangent, the potential ``-m theta`` of the edge's rotation
  (:mod:`deformable.physics.moments`); :class:`Pressure`, a follower pressure p along r_1 x r_2, the
  potential -p V of the enclosed volume, exact where every edge is held (:mod:`deformable.physics.pressure`);
- :class:`VelocityLoad`, depending on positions and velocities: :class:`Wind`, aerodynamic pressure with
  the relative velocity u = w - v (the usual cloth wind model), ``f = c (u . n) |u . n| n`` per unit of
  *current* area (|r_1 x r_2| per unit parameter area), c = rho C_d / 2; not conservative; its Jacobian
  in the velocity, ``-df/dv = 2 c |u . n| n n^T`` (positive semi-definite), is a damping the implicit
  step takes implicitly.

A user's load is one subclass of a role (a frozen dataclass, as these are); a Scene takes it as it takes
these. Each may vary in time through ``time``, a callable ``t -> factor`` such as :class:`Sinusoidal`; a
body force may also be a callable of (a1, a2, t), a spring's anchor and the wind's velocity callables of t.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Callable, ClassVar

import numpy as np
import scipy.sparse as sp

from ..algebra.patterns import FixedPattern
from ..checks import function, real, vector
from ..errors import InputError
from ..geometry.sheet import EDGES
from .callables import called
from .moments import EdgeMoments, rotation_angle
from .pressure import PressurePotential

__all__ = ["Load", "ROLES", "AppliedLoad", "BodyLoad", "ConservativeLoad", "VelocityLoad", "Gravity", "BodyForce",
           "EdgeLoad", "EdgeMoment", "PointLoad", "Pressure", "Spring", "SpringPotential", "Wind", "Sinusoidal",
           "Force"]


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


def _factor(load, t: float) -> float:
    """The load's time factor at t (1 without one), its errors and non-finite values named."""
    return 1.0 if load.time is None else float(called(f"{type(load).__name__}.time", load.time, t))


class Load:
    """A load of a Scene: the protocol :class:`~deformable.physics.loads.Loads` asks (module docstring); a load
    subclasses one of the roles :class:`AppliedLoad`, :class:`ConservativeLoad` or :class:`VelocityLoad`."""

    def check(self, sheet) -> None:
        """InputError when the load does not fit the sheet (a point outside its rectangle); nothing by default."""


class AppliedLoad(Load):
    """A load independent of the state, which :meth:`applied` integrates over the model's hooks."""

    #: a concentrated load: summed after the distributed ones (F of eq. (21) sums the body and edge loads in the
    #: scene's order, then the point loads)
    concentrated: ClassVar[bool] = False

    def applied(self, loads, t: float) -> np.ndarray:
        """The integrated force at time t, (ndof, 3) (N). ``loads`` is the model's Loads: its ``model`` (the
        backend's hooks, :mod:`deformable.physics.loads`), :meth:`~deformable.physics.loads.Loads.edge_rule`
        and :meth:`~deformable.physics.loads.Loads.point_dofs`, each built once."""
        raise NotImplementedError


class BodyLoad(AppliedLoad):
    """A force density per unit of parameter area (N/m^2), ``density(a1, a2, t, mu)``, integrated against the
    backend's basis: ``integral f phi_k``."""

    def density(self, a1, a2, t: float, mu) -> np.ndarray:
        raise NotImplementedError

    def applied(self, loads, t: float) -> np.ndarray:
        m = loads.model
        return m.integrate(self.density(*m.points, t, m.mu))


class ConservativeLoad(Load):
    """A load with a potential that depends on the state. ``potential`` is the class that computes it for all
    the scene's loads naming it, built once as ``potential(model, loads)`` (the loads in the scene's order), with
    ``energy``, ``gradient`` and ``hessian`` of (X, t, factor) (J, (ndof, 3), (3 ndof, 3 ndof) blocked on a fixed
    pattern) and the class attributes ``rank`` (its place in the sum: springs 0, moments 1, pressures 2),
    ``factored`` (the load factor of ``equilibrium`` scales it) and ``linear`` (its Hessian does not depend on
    the state; may be an instance's attribute)."""

    potential: ClassVar[type]


class VelocityLoad(Load):
    """A load depending on positions and velocities, not conservative: ``density(n, area, v, t)`` per unit of
    parameter area (P, 3) at points of unit normal n (P, 3), area element |r_1 x r_2| (P,) and velocity v (P, 3),
    and ``damping(n, area, v, t)``, its Jacobian -d density / dv (P, 3, 3)."""


#: the roles a Scene's load subclasses
ROLES = (AppliedLoad, ConservativeLoad, VelocityLoad)


@dataclass(frozen=True)
class Gravity(BodyLoad):
    """Weight ``mu g direction`` per unit area (N/m^2); g in m/s^2."""

    g: float = 9.81
    direction: tuple[float, float, float] = (0.0, 0.0, -1.0)
    time: Callable[[float], float] | None = None

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
        return (_factor(self, t) * self.g * mu)[..., None] * np.asarray(self.direction)


@dataclass(frozen=True)
class BodyForce(BodyLoad):
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

    def __post_init__(self):
        if not callable(self.f):
            object.__setattr__(self, "f", tuple(_vector("BodyForce.f", self.f)))
        function("BodyForce.where", self.where)
        function("BodyForce.time", self.time)

    def density(self, a1, a2, t: float, mu=None) -> np.ndarray:
        a1, a2 = np.broadcast_arrays(np.asarray(a1, float), np.asarray(a2, float))
        if callable(self.f):
            out = np.broadcast_to(called("BodyForce.f", self.f, a1, a2, t), a1.shape + (3,)).copy()
        else:
            out = np.broadcast_to(np.asarray(self.f), a1.shape + (3,)).copy()
        if self.where is not None:
            out *= called("BodyForce.where", self.where, a1, a2).astype(bool)[..., None]
        return _factor(self, t) * out


@dataclass(frozen=True)
class EdgeLoad(AppliedLoad):
    """A traction per unit of parameter length (N/m) on one edge.

    ``f`` is a 3-vector or a callable (a1, a2, t) -> (..., 3) evaluated on the edge.
    """

    edge: str
    f: object = (0.0, 0.0, 0.0)
    time: Callable[[float], float] | None = None

    def __post_init__(self):
        if not isinstance(self.edge, str) or self.edge not in EDGES:
            raise InputError(f"EdgeLoad.edge must be one of {sorted(EDGES)}, got {self.edge!r}")
        if not callable(self.f):
            object.__setattr__(self, "f", tuple(_vector("EdgeLoad.f", self.f)))
        function("EdgeLoad.time", self.time)

    def traction(self, a1, a2, t: float) -> np.ndarray:
        a1, a2 = np.broadcast_arrays(np.asarray(a1, float), np.asarray(a2, float))
        if callable(self.f):
            out = np.broadcast_to(called("EdgeLoad.f", self.f, a1, a2, t), a1.shape + (3,))
        else:
            out = np.broadcast_to(np.asarray(self.f), a1.shape + (3,))
        return _factor(self, t) * out

    def applied(self, loads, t: float) -> np.ndarray:
        """``at^T (w q)`` over the backend's rule on the edge (:class:`~deformable.backends.contract.EdgeRule`)."""
        rule = loads.edge_rule(self.edge)
        return rule.at.T @ (rule.weights[:, None] * self.traction(rule.a1, rule.a2, t))


@dataclass(frozen=True)
class EdgeMoment(ConservativeLoad):
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
    potential = EdgeMoments

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
        m = np.broadcast_to(called("EdgeMoment.m", self.m, a1, a2, t) if callable(self.m) else float(self.m), a1.shape)
        return _factor(self, t) * m

    #: theta, d theta / d d and d^2 theta / d d^2 (:func:`deformable.physics.moments.rotation_angle`)
    angle = staticmethod(rotation_angle)


@dataclass(frozen=True)
class Pressure(ConservativeLoad):
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
    potential = PressurePotential

    def __post_init__(self):
        object.__setattr__(self, "p", real("Pressure.p", self.p))
        function("Pressure.time", self.time)

    def pressure(self, t: float) -> float:
        """p at time t (Pa)."""
        return _factor(self, t) * self.p


@dataclass(frozen=True)
class PointLoad(AppliedLoad):
    """A concentrated force (N) at the parameter point ``at`` = (a1, a2)."""

    at: tuple[float, float]
    f: tuple[float, float, float] = (0.0, 0.0, 0.0)
    time: Callable[[float], float] | None = None
    concentrated = True

    def __post_init__(self):
        object.__setattr__(self, "at", _point("PointLoad.at", self.at))
        object.__setattr__(self, "f", tuple(_vector("PointLoad.f", self.f)))
        function("PointLoad.time", self.time)

    def force(self, t: float) -> np.ndarray:
        return _factor(self, t) * np.asarray(self.f)

    def check(self, sheet) -> None:
        sheet.locate(self.at, f"{type(self).__name__}.at")  # inside the rectangle, or an InputError naming it

    def applied(self, loads, t: float) -> np.ndarray:
        """The force at the point's degrees of freedom, ``w_k f`` (``r(a) = sum_k w_k X_k``)."""
        dofs, w = loads.point_dofs(self.at, "PointLoad.at")
        F = np.zeros((loads.n, 3))
        F[dofs] += w[:, None] * self.force(t)[None]
        return F


def _point(name: str, value) -> tuple:
    return tuple(vector(name, value, 2, "a parameter point (a1, a2)"))


def _of_time(name: str, value):
    """A 3-vector, or a callable of t returning one (checked when called)."""
    return value if callable(value) else tuple(_vector(name, value))


def _at_time(name: str, value, t: float) -> np.ndarray:
    return _vector(f"{name} at t = {t:g}", called(name, value, t)) if callable(value) else np.asarray(value, float)


class SpringPotential:
    """The scene's springs on a model: the sum of their energies k (|r(a) - anchor| - L0)^2 / 2 (J) at their points
    ``r(a) = sum_k w_k X_k``, its gradient (minus the springs' force) and its Hessian (each spring's definite part,
    :meth:`Spring.hessian`), (3 ndof, 3 ndof) coordinate-blocked on one fixed pattern. The load factor does not
    scale it."""

    rank, factored = 0, False

    def __init__(self, model, springs):
        self.n = n = model.ndof
        self.parts = [(s, *model.point_dofs(s.at, "Spring.at")) for s in springs]
        #: linear springs only (rest length 0): the Hessian does not depend on the state
        self.linear = all(s.rest_length == 0 for s in springs)
        rows, cols = [], []
        for _, dofs, _ in self.parts:
            k = dofs.size
            for a in range(3):
                for b in range(3):
                    rows.append(np.repeat(a * n + dofs, k))
                    cols.append(np.tile(b * n + dofs, k))
        self._pattern = FixedPattern(np.concatenate(rows), np.concatenate(cols), (3 * n, 3 * n))

    def _ends(self, X):
        return [(s, dofs, w, w @ X[dofs]) for s, dofs, w in self.parts]

    def energy(self, X: np.ndarray, t: float, factor: float = 1.0) -> float:
        return float(sum(s.energy(r, t) for s, _, _, r in self._ends(X)))

    def gradient(self, X: np.ndarray, t: float, factor: float = 1.0) -> np.ndarray:
        G = np.zeros((self.n, 3))
        for s, dofs, w, r in self._ends(X):
            G[dofs] -= w[:, None] * s.force(r, t)[None]
        return G

    def hessian(self, X: np.ndarray, t: float, factor: float = 1.0) -> sp.csr_matrix:
        values = []
        for s, dofs, w, r in self._ends(X):
            H = s.hessian(r, t)
            ww = np.outer(w, w).ravel()
            values += [H[a, b] * ww for a in range(3) for b in range(3)]
        return self._pattern.matrix(self._pattern.data(np.concatenate(values)))


@dataclass(frozen=True)
class Spring(ConservativeLoad):
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
    potential = SpringPotential

    def __post_init__(self):
        object.__setattr__(self, "at", _point("Spring.at", self.at))
        object.__setattr__(self, "anchor", _of_time("Spring.anchor", self.anchor))
        for name in ("stiffness", "rest_length"):
            v = getattr(self, name)
            if isinstance(v, bool) or not isinstance(v, (int, float)) or not np.isfinite(v) or v < 0:
                raise InputError(f"Spring.{name} must be a finite non-negative number, got {v!r}")
            object.__setattr__(self, name, float(v))

    def check(self, sheet) -> None:
        sheet.locate(self.at, f"{type(self).__name__}.at")  # inside the rectangle, or an InputError naming it

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
class Wind(VelocityLoad):
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

    def __post_init__(self):
        object.__setattr__(self, "velocity", _of_time("Wind.velocity", self.velocity))
        c = self.coefficient
        if isinstance(c, bool) or not isinstance(c, (int, float)) or not np.isfinite(c) or c < 0:
            raise InputError(f"Wind.coefficient must be a finite non-negative number, got {c!r}")
        object.__setattr__(self, "coefficient", float(c))
        function("Wind.time", self.time)

    def _normal_speed(self, n, v, t):
        w = _factor(self, t) * _at_time("Wind.velocity", self.velocity, t)
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


#: every force of a Scene (formerly the union of the classes above; now the protocol they and a user's loads share)
Force = Load
