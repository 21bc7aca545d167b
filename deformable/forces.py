r"""External forces f(r, t) of the equation of motion (11).

Three kinds, so that each backend can integrate them its own way:

- body forces, a density per unit of parameter area (N/m^2):
  :class:`Gravity` (``mu g``) and :class:`BodyForce`;
- :class:`EdgeLoad`, a traction per unit of parameter length on an edge (N/m);
- :class:`PointLoad`, a concentrated force at a parameter point (N).

Each may vary in time through ``time``, a callable ``t -> factor`` such as
:class:`Sinusoidal`; a body force may also be a callable of (a1, a2, t).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Callable

import numpy as np

from .sheet import EDGES

__all__ = ["Gravity", "BodyForce", "EdgeLoad", "PointLoad", "Sinusoidal", "Force"]


def _vector(name: str, value) -> np.ndarray:
    v = np.asarray(value, dtype=float)
    if v.shape != (3,) or not np.all(np.isfinite(v)):
        raise ValueError(f"{name} must be a finite 3-vector, got {value!r}")
    return v


@dataclass(frozen=True)
class Sinusoidal:
    """Time factor ``offset + amplitude sin(2 pi frequency t + phase)`` (frequency in Hz)."""

    amplitude: float = 1.0
    frequency: float = 1.0
    phase: float = 0.0
    offset: float = 0.0

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
        if not np.isfinite(self.g):
            raise ValueError(f"Gravity.g must be finite, got {self.g!r}")
        d = _vector("Gravity.direction", self.direction)
        object.__setattr__(self, "direction", tuple(d / np.linalg.norm(d)))

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
        if self.edge not in EDGES:
            raise ValueError(f"EdgeLoad.edge must be one of {sorted(EDGES)}, got {self.edge!r}")
        if not callable(self.f):
            object.__setattr__(self, "f", tuple(_vector("EdgeLoad.f", self.f)))

    def traction(self, a1, a2, t: float) -> np.ndarray:
        a1, a2 = np.broadcast_arrays(np.asarray(a1, float), np.asarray(a2, float))
        if callable(self.f):
            out = np.broadcast_to(np.asarray(self.f(a1, a2, t), float), a1.shape + (3,))
        else:
            out = np.broadcast_to(np.asarray(self.f), a1.shape + (3,))
        return _factor(self.time, t) * out


@dataclass(frozen=True)
class PointLoad:
    """A concentrated force (N) at the parameter point ``at`` = (a1, a2)."""

    at: tuple[float, float]
    f: tuple[float, float, float] = (0.0, 0.0, 0.0)
    time: Callable[[float], float] | None = None
    kind = "point"

    def __post_init__(self):
        at = np.asarray(self.at, float)
        if at.shape != (2,) or not np.all(np.isfinite(at)):
            raise ValueError(f"PointLoad.at must be a parameter point (a1, a2), got {self.at!r}")
        object.__setattr__(self, "at", tuple(at))
        object.__setattr__(self, "f", tuple(_vector("PointLoad.f", self.f)))

    def force(self, t: float) -> np.ndarray:
        return _factor(self.time, t) * np.asarray(self.f)


Force = Gravity | BodyForce | EdgeLoad | PointLoad
