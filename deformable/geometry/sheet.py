"""The parameter rectangle and its node grid.

The parameter domain is ``[0, L1] x [0, L2]`` with coordinates (a1, a2); the node grid has M nodes along a1 and N
along a2, ``h1 = L1/(M-1)``, ``h2 = L2/(N-1)`` (paper section 2.3, "an MxN-node mesh"). Both backends use this grid
(the FD nodes and the FE mesh vertices coincide), so a constraint or a sample names the same points in both. A
sheet's rest and initial shapes are surfaces (:mod:`deformable.geometry.surfaces`). The grid's named places live
here: the four edges (:data:`EDGES`: "left" a1 = 0, "right" a1 = L1, "bottom" a2 = 0, "top" a2 = L2) and corners
(:data:`CORNERS`), with :meth:`Sheet.edge` and :meth:`Sheet.edge_nodes` giving the nodes; and the cell of a
parameter point with its bilinear weights (:meth:`Sheet.locate`, :func:`bilinear`).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..checks import count, real
from ..errors import InputError
from ..limits import check_memory
from .surfaces import as_surface

__all__ = ["Sheet", "Edge", "EDGES", "CORNERS", "bilinear", "bilinear_weights", "CELL_CORNERS"]


@dataclass(frozen=True)
class Edge:
    """An edge of the parameter rectangle: the nodes whose index along ``axis`` is ``side``.

    ``axis`` 0 (index m, along a1) for "left"/"right", 1 (index n) for "bottom"/"top"; ``side`` 0 or -1; the edge
    runs along the other axis, :attr:`along`.
    """

    name: str
    axis: int
    side: int

    @property
    def along(self) -> int:
        """The parameter axis the edge runs along (0: a1, 1: a2)."""
        return 1 - self.axis

    @property
    def index(self) -> tuple:
        """Index of the edge's nodes into an (M, N) array: a 1-D line of nodes."""
        return (self.side, slice(None)) if self.axis == 0 else (slice(None), self.side)

    def rows(self, depth: int = 1) -> tuple[slice, slice]:
        """Index of the ``depth`` node rows at this edge into an (M, N) array."""
        inner = slice(0, depth) if self.side == 0 else slice(-depth, None)
        return (inner, slice(None)) if self.axis == 0 else (slice(None), inner)


#: the four edges by name: "left" a1 = 0, "right" a1 = L1, "bottom" a2 = 0, "top" a2 = L2
EDGES = {e.name: e for e in (Edge("left", 0, 0), Edge("right", 0, -1), Edge("bottom", 1, 0), Edge("top", 1, -1))}
#: the four corners by name, as (index m, index n) with -1 for the last node
CORNERS = {"bottom-left": (0, 0), "bottom-right": (-1, 0), "top-left": (0, -1), "top-right": (-1, -1)}
#: node offsets (di, dj) of a cell's corners, in the order of :func:`bilinear_weights`
CELL_CORNERS = ((0, 0), (1, 0), (0, 1), (1, 1))


def bilinear_weights(s, t) -> tuple:
    """Weights of the cell corners :data:`CELL_CORNERS` at reference coordinates (s, t) in [0, 1]^2."""
    return ((1 - s) * (1 - t), s * (1 - t), (1 - s) * t, s * t)


def bilinear(field: np.ndarray, i, j, s, t) -> np.ndarray:
    """Bilinear interpolation of a node field (..., M, N) in cells (i, j) at reference coordinates (s, t).

    i, j, s, t broadcast against each other (shape P); the result is (..., P).
    """
    field = np.asarray(field, float)
    return sum(w * field[..., i + di, j + dj] for w, (di, dj) in zip(bilinear_weights(s, t), CELL_CORNERS))


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
        if not isinstance(self.size, (tuple, list, np.ndarray)) or len(self.size) != 2:
            raise InputError(f"Sheet.size must be two positive numbers, got {self.size!r}", field="Sheet.size",
                             value=self.size)
        size = tuple(real("Sheet.size", s, low=1e-30, high=1e30) for s in self.size)  # h^-4 stays finite
        if not isinstance(self.nodes, (tuple, list, np.ndarray)) or len(self.nodes) != 2:
            raise InputError(f"Sheet.nodes must be two integers, got {self.nodes!r}", field="Sheet.nodes",
                             value=self.nodes)
        try:
            nodes = tuple(count("Sheet.nodes", n, minimum=3) for n in self.nodes)
        except InputError:
            raise InputError(f"Sheet.nodes must be two integers, at least 3 nodes a side, got {self.nodes!r}",
                             field="Sheet.nodes", value=self.nodes) from None
        check_memory(nodes)  # the least a grid needs, before anything is allocated
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

    def fibre_stretch(self, grid: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """How much each grid segment of the positions ``grid`` ((M, N, 3), m) is stretched against the rest
        shape's: |r(m+1, n) - r(m, n)| / |r0(m+1, n) - r0(m, n)| - 1 along a1, (M - 1, N), and likewise along a2,
        (M, N - 1) (dimensionless; a fibre's strain, the segment's chord against its rest chord)."""
        rest = self.rest.r(*self.coordinates())
        out = []
        for axis in (0, 1):
            d, d0 = np.diff(np.asarray(grid, float), axis=axis), np.diff(rest, axis=axis)
            out.append(np.linalg.norm(d, axis=-1) / np.linalg.norm(d0, axis=-1) - 1.0)
        return out[0], out[1]

    def edge(self, name: str) -> Edge:
        """The edge called ``name`` (one of :data:`EDGES`); ValueError naming the valid ones otherwise."""
        try:
            return EDGES[name]
        except (KeyError, TypeError):
            raise InputError(f"unknown edge {name!r}; expected one of {sorted(EDGES)}") from None

    def edge_nodes(self, name: str, depth: int = 1) -> np.ndarray:
        """Boolean (M, N) mask of the ``depth`` node rows at the edge called ``name``."""
        mask = np.zeros(self.nodes, bool)
        mask[self.edge(name).rows(depth)] = True
        return mask

    def locate(self, a, what: str = "parameter points") -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
        """Cells and reference coordinates of parameter points.

        Parameters
        ----------
        a : array (P, 2) (or (2,))
            Points (a1, a2) inside the rectangle (scene units).
        what : str
            Named in the error message.

        Returns
        -------
        i, j : int arrays (P,)
            Cell (node index of its lower-left corner), 0 <= i <= M - 2, 0 <= j <= N - 2.
        s, t : arrays (P,)
            Reference coordinates in [0, 1] of the points in their cells.

        Raises
        ------
        ValueError
            For points that are not finite or lie outside the rectangle (naming the first).
        """
        a = np.asarray(a, float)
        if a.ndim == 1:
            a = a[None]
        (L1, L2), (M, N) = self.size, self.nodes
        if a.ndim != 2 or a.shape[1] != 2 or not np.all(np.isfinite(a)):
            raise InputError(f"{what} must be (P, 2) finite parameter points, got shape {a.shape}")
        tol = 1e-12 * max(L1, L2)
        outside = (a[:, 0] < -tol) | (a[:, 0] > L1 + tol) | (a[:, 1] < -tol) | (a[:, 1] > L2 + tol)
        if np.any(outside):
            raise InputError(f"{what} {tuple(a[outside][0])!r} lies outside [0, {L1}] x [0, {L2}]")
        h1, h2 = self.h
        s, t = a[:, 0] / h1, a[:, 1] / h2
        i = np.clip(np.floor(s).astype(np.int64), 0, M - 2)
        j = np.clip(np.floor(t).astype(np.int64), 0, N - 2)
        return i, j, np.clip(s - i, 0.0, 1.0), np.clip(t - j, 0.0, 1.0)

    def with_nodes(self, nodes: tuple[int, int]) -> Sheet:
        """The same rectangle and shapes on another node grid."""
        return Sheet(size=self.size, nodes=nodes, rest=self.rest, initial=self.initial)
