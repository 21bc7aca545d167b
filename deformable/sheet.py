r"""The parameter rectangle, its node grid, and surfaces defined on it.

The parameter domain is ``[0, L1] x [0, L2]`` with coordinates (a1, a2); the
node grid has M nodes along a1 and N along a2, ``h1 = L1/(M-1)``,
``h2 = L2/(N-1)`` (paper section 2.3, "an MxN-node mesh"). Both backends use
this grid: the finite-difference nodes and the finite-element mesh vertices
coincide, so a constraint or a sample names the same points in both.

A *surface* is anything with callables ``r, r1, r2, r12: (a1, a2) -> (..., 3)``
(position and the derivatives a bicubic Hermite interpolation needs). A plain
callable ``(a1, a2) -> (..., 3)`` is accepted wherever a surface is, and is
differentiated numerically (central differences, error about 1e-10).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Callable, Protocol, runtime_checkable

import numpy as np

__all__ = ["Sheet", "Surface", "CallableSurface", "FlatSurface", "as_surface"]


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
        raise ValueError(f"surface callable returned shape {out.shape}, expected {a1.shape + (3,)}")
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


class FlatSurface:
    """The plane r = (a1, a2, 0): the default rest and initial shape."""

    def r(self, a1, a2):
        a1, a2 = np.broadcast_arrays(np.asarray(a1, float), np.asarray(a2, float))
        return np.stack([a1, a2, np.zeros_like(a1)], axis=-1)

    def r1(self, a1, a2):
        a1, _ = np.broadcast_arrays(np.asarray(a1, float), np.asarray(a2, float))
        return np.broadcast_to([1.0, 0.0, 0.0], a1.shape + (3,)).copy()

    def r2(self, a1, a2):
        a1, _ = np.broadcast_arrays(np.asarray(a1, float), np.asarray(a2, float))
        return np.broadcast_to([0.0, 1.0, 0.0], a1.shape + (3,)).copy()

    def r12(self, a1, a2):
        a1, _ = np.broadcast_arrays(np.asarray(a1, float), np.asarray(a2, float))
        return np.zeros(a1.shape + (3,))


def as_surface(obj) -> Surface:
    """``obj`` as a Surface: None is the plane, a callable gets numerical derivatives."""
    if obj is None:
        return FlatSurface()
    if all(callable(getattr(obj, k, None)) for k in ("r", "r1", "r2", "r12")):
        return obj
    if callable(obj):
        return CallableSurface(obj)
    raise ValueError(f"expected a surface (r, r1, r2, r12) or a callable (a1, a2) -> (..., 3), got {obj!r}")


@dataclass(frozen=True)
class Sheet:
    """The parameter rectangle and its node grid.

    Parameters
    ----------
    size : (L1, L2)
        Side lengths of the parameter rectangle (scene units, metres in the scenes).
    nodes : (M, N)
        Number of nodes along a1 and a2, at least 3 each.
    rest : surface or callable, optional
        Rest shape; its G and B are G0, B0 (default: the plane (a1, a2, 0)).
    initial : surface or callable, optional
        Initial shape (default: the rest shape).
    """

    size: tuple[float, float] = (1.0, 1.0)
    nodes: tuple[int, int] = (17, 17)
    rest: object = None
    initial: object = None

    def __post_init__(self):
        try:
            size = tuple(float(s) for s in self.size)
        except (TypeError, ValueError):
            raise ValueError(f"Sheet.size must be two numbers, got {self.size!r}") from None
        if len(size) != 2 or not all(np.isfinite(s) and s > 0 for s in size):
            raise ValueError(f"Sheet.size must be two positive numbers, got {self.size!r}")
        try:
            nodes = tuple(int(n) for n in self.nodes)
        except (TypeError, ValueError):
            raise ValueError(f"Sheet.nodes must be two integers, got {self.nodes!r}") from None
        if len(nodes) != 2 or any(n != v for n, v in zip(nodes, self.nodes)):
            raise ValueError(f"Sheet.nodes must be two integers, got {self.nodes!r}")
        if min(nodes) < 3:
            raise ValueError(f"Sheet.nodes needs at least 3 nodes a side, got {self.nodes!r}")
        object.__setattr__(self, "size", size)
        object.__setattr__(self, "nodes", nodes)
        object.__setattr__(self, "rest", as_surface(self.rest))
        object.__setattr__(self, "initial", self.rest if self.initial is None else as_surface(self.initial))

    @property
    def h(self) -> tuple[float, float]:
        """Grid spacings (h1, h2)."""
        (L1, L2), (M, N) = self.size, self.nodes
        return L1 / (M - 1), L2 / (N - 1)

    def axes(self) -> tuple[np.ndarray, np.ndarray]:
        """Node coordinates a1 (M,) and a2 (N,)."""
        (L1, L2), (M, N) = self.size, self.nodes
        return np.linspace(0.0, L1, M), np.linspace(0.0, L2, N)

    def coordinates(self) -> tuple[np.ndarray, np.ndarray]:
        """Parameter coordinates of the nodes, two (M, N) arrays (index order m, n)."""
        return np.meshgrid(*self.axes(), indexing="ij")

    def with_nodes(self, nodes: tuple[int, int]) -> Sheet:
        """The same rectangle and shapes on another node grid."""
        return Sheet(size=self.size, nodes=nodes, rest=self.rest, initial=self.initial)
