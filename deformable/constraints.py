r"""Constraints: which nodes are held, and how.

A selection ``where`` names nodes of the sheet's grid, the same in both
backends:

- an edge name: "left" (a1 = 0), "right" (a1 = L1), "bottom" (a2 = 0),
  "top" (a2 = L2); a corner name: "top-left", "top-right", "bottom-left",
  "bottom-right";
- a list of such names;
- node indices: an integer array of shape (k, 2) of (m, n) pairs;
- a predicate ``(a1, a2) -> bool array`` on the parameter coordinates.

:class:`Pin` holds positions (optionally moving them rigidly in time),
:class:`Slide` lets nodes move along one axis only (the curtain rail),
:class:`Clamp` holds an edge and its tangent plane (FD: the edge row and the
next one in; FE: values and all derivatives at the edge).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Callable

import numpy as np

__all__ = ["Pin", "Slide", "Clamp", "select", "EDGES", "CORNERS", "AXES"]

EDGES = {"left", "right", "bottom", "top"}
CORNERS = {"top-left", "top-right", "bottom-left", "bottom-right"}
AXES = {"x": 0, "y": 1, "z": 2, 0: 0, 1: 1, 2: 2}


def _named(name: str, M: int, N: int) -> np.ndarray:
    mask = np.zeros((M, N), bool)
    if name == "left":
        mask[0, :] = True
    elif name == "right":
        mask[-1, :] = True
    elif name == "bottom":
        mask[:, 0] = True
    elif name == "top":
        mask[:, -1] = True
    elif name in CORNERS:
        vertical, horizontal = name.split("-")
        mask[0 if horizontal == "left" else -1, -1 if vertical == "top" else 0] = True
    else:
        raise ValueError(f"unknown edge or corner {name!r}; expected one of {sorted(EDGES | CORNERS)}")
    return mask


def select(where, sheet) -> np.ndarray:
    """Boolean (M, N) mask of the nodes that ``where`` names; ValueError if it names none."""
    M, N = sheet.nodes
    if isinstance(where, str):
        mask = _named(where, M, N)
    elif callable(where):
        a1, a2 = sheet.coordinates()
        mask = np.broadcast_to(np.asarray(where(a1, a2), bool), (M, N)).copy()
    elif isinstance(where, (list, tuple)) and where and all(isinstance(w, str) for w in where):
        mask = np.zeros((M, N), bool)
        for w in where:
            mask |= _named(w, M, N)
    else:
        idx = np.asarray(where)
        if idx.ndim != 2 or idx.shape[1] != 2 or not np.issubdtype(idx.dtype, np.integer):
            raise ValueError(f"cannot select nodes with {where!r}: expected an edge name, a list of "
                             "names, a (k, 2) integer array of (m, n) indices or a predicate")
        if idx.size and (idx.min() < 0 or idx[:, 0].max() >= M or idx[:, 1].max() >= N):
            raise ValueError(f"node indices {where!r} lie outside the {M} x {N} grid")
        mask = np.zeros((M, N), bool)
        mask[idx[:, 0], idx[:, 1]] = True
    if not mask.any():
        raise ValueError(f"selection {where!r} selects no node of the {M} x {N} grid")
    return mask


@dataclass(frozen=True)
class Pin:
    """Hold the selected nodes at their initial positions.

    ``motion``, optional: a callable ``t -> (3,)`` displacement added to the
    initial positions (prescribed rigid motion of the pinned nodes).
    """

    where: object
    motion: Callable[[float], np.ndarray] | None = None


@dataclass(frozen=True)
class Slide:
    """Let the selected nodes move only along ``axis`` ("x", "y", "z" or 0, 1, 2)."""

    where: object
    axis: object = "x"

    def __post_init__(self):
        if self.axis not in AXES:
            raise ValueError(f"Slide.axis must be one of 'x', 'y', 'z', 0, 1, 2; got {self.axis!r}")
        object.__setattr__(self, "axis", AXES[self.axis])


@dataclass(frozen=True)
class Clamp:
    """Hold an edge (or edges, by name) and its tangent plane."""

    where: object

    def __post_init__(self):
        names = [self.where] if isinstance(self.where, str) else self.where
        if not isinstance(names, (list, tuple)) or not all(n in EDGES for n in names):
            raise ValueError(f"Clamp.where must name edges {sorted(EDGES)}, got {self.where!r}")

    @property
    def edges(self) -> list[str]:
        return [self.where] if isinstance(self.where, str) else list(self.where)
