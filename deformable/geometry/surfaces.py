r"""Surfaces on the parameter rectangle: anything with ``r, r1, r2, r12: (a1, a2) -> (..., 3)``.

A *surface* gives the position and the derivatives a bicubic Hermite interpolation needs (:class:`Surface`, a
protocol). A plain callable ``(a1, a2) -> (..., 3)`` is accepted wherever a surface is (:func:`as_surface`), and is
differentiated numerically (:class:`CallableSurface`: central differences, r_1, r_2 to about 1e-10, r_12 to about
1e-7). :class:`Plane` is the flat surface with exact derivatives, the default rest and initial shape of a sheet.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Callable, Protocol, runtime_checkable

import numpy as np

from ..errors import InputError

__all__ = ["Surface", "CallableSurface", "Plane", "FlatSurface", "as_surface"]


@runtime_checkable
class Surface(Protocol):
    """A parametric surface with the derivatives the backends need."""

    def r(self, a1, a2) -> np.ndarray: ...
    def r1(self, a1, a2) -> np.ndarray: ...
    def r2(self, a1, a2) -> np.ndarray: ...
    def r12(self, a1, a2) -> np.ndarray: ...


def _call(f, a1, a2) -> np.ndarray:
    a1, a2 = np.broadcast_arrays(np.asarray(a1, float), np.asarray(a2, float))
    out = np.asarray(f(a1, a2), dtype=float)
    if out.shape != a1.shape + (3,):
        out = np.broadcast_to(out, a1.shape + (3,)) if out.shape in ((3,), (1, 3)) else out
    if out.shape != a1.shape + (3,):
        raise InputError(f"surface callable returned shape {out.shape}, expected {a1.shape + (3,)}")
    return out


@dataclass(frozen=True)
class CallableSurface:
    """A surface from a position callable, its derivatives by central differences."""

    f: Callable
    step: float = 1e-5

    def r(self, a1, a2):
        return _call(self.f, a1, a2)

    def r1(self, a1, a2):
        e = self.step
        return (self.r(np.add(a1, e), a2) - self.r(np.subtract(a1, e), a2)) / (2 * e)

    def r2(self, a1, a2):
        e = self.step
        return (self.r(a1, np.add(a2, e)) - self.r(a1, np.subtract(a2, e))) / (2 * e)

    def r12(self, a1, a2):
        e = self.step
        return (self.r1(a1, np.add(a2, e)) - self.r1(a1, np.subtract(a2, e))) / (2 * e)


@dataclass(frozen=True)
class Plane:
    """The plane ``r(a1, a2) = origin + a1 e1 + a2 e2`` with exact derivatives (a Surface).

    ``Plane()`` is r = (a1, a2, 0), the default rest and initial shape.

    Parameters
    ----------
    origin, e1, e2 : 3-vectors (scene units; e1, e2 the directions of a1 and a2)
    """

    origin: tuple = (0.0, 0.0, 0.0)
    e1: tuple = (1.0, 0.0, 0.0)
    e2: tuple = (0.0, 1.0, 0.0)

    @staticmethod
    def _shape(a1, a2):
        return np.broadcast_arrays(np.asarray(a1, float), np.asarray(a2, float))

    def r(self, a1, a2):
        a1, a2 = self._shape(a1, a2)
        return np.asarray(self.origin) + a1[..., None] * np.asarray(self.e1) + a2[..., None] * np.asarray(self.e2)

    def r1(self, a1, a2):
        a1, _ = self._shape(a1, a2)
        return np.broadcast_to(np.asarray(self.e1, float), a1.shape + (3,)).copy()

    def r2(self, a1, a2):
        a1, _ = self._shape(a1, a2)
        return np.broadcast_to(np.asarray(self.e2, float), a1.shape + (3,)).copy()

    def r12(self, a1, a2):
        a1, _ = self._shape(a1, a2)
        return np.zeros(a1.shape + (3,))


#: the former name of the flat default surface
FlatSurface = Plane


def as_surface(obj) -> Surface:
    """``obj`` as a Surface: None is the plane, a callable gets numerical derivatives."""
    if obj is None:
        return Plane()
    if all(callable(getattr(obj, k, None)) for k in ("r", "r1", "r2", "r12")):
        return obj
    if callable(obj):
        return CallableSurface(obj)
    raise InputError(f"expected a surface (r, r1, r2, r12) or a callable (a1, a2) -> (..., 3), got {obj!r}")
