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
:class:`Symmetry` puts an edge on a plane of symmetry (a coordinate plane):
its nodes on the plane, the surface meeting it perpendicularly (the quarter
and half models of the shell benchmarks; FE only: FD's operators act alike on
x, y and z, and the mirror ghost row differs between them),
:class:`Clamp` holds an edge and its tangent plane, not the in-plane stretch
across it (FD: the edge row, with a ghost row outside it that holds the slope;
FE: values, the derivative along the edge, and the normal
component of the derivatives across it).
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Callable

import numpy as np

from ..checks import function
from ..errors import InputError
from ..geometry.sheet import CORNERS, EDGES

__all__ = ["Pin", "Slide", "Clamp", "Symmetry", "select", "EDGES", "CORNERS", "AXES", "HeldDofs", "hold", "edges_named"]

AXES = {"x": 0, "y": 1, "z": 2, 0: 0, 1: 1, 2: 2}


def _named(name: str, sheet) -> np.ndarray:
    if name in EDGES:
        return sheet.edge_nodes(name)
    if name not in CORNERS:
        raise InputError(f"unknown edge or corner {name!r}; expected one of {sorted(set(EDGES) | set(CORNERS))}")
    mask = np.zeros(sheet.nodes, bool)
    mask[CORNERS[name]] = True
    return mask


def edges_named(where) -> list[str]:
    """The edge names in a selection (a name or a list of names); [] for any other selection."""
    if isinstance(where, str):
        return [where] if where in EDGES else []
    if isinstance(where, (list, tuple)) and all(isinstance(w, str) for w in where):
        return [w for w in where if w in EDGES]
    return []


def select(where, sheet) -> np.ndarray:
    """Boolean (M, N) mask of the nodes that ``where`` names; ValueError if it names none."""
    M, N = sheet.nodes
    if isinstance(where, str):
        mask = _named(where, sheet)
    elif callable(where):
        a1, a2 = sheet.coordinates()
        mask = np.broadcast_to(np.asarray(where(a1, a2), bool), (M, N)).copy()
    elif isinstance(where, (list, tuple)) and where and all(isinstance(w, str) for w in where):
        mask = np.zeros((M, N), bool)
        for w in where:
            mask |= _named(w, sheet)
    else:
        idx = np.asarray(where)
        if idx.ndim != 2 or idx.shape[1] != 2 or not np.issubdtype(idx.dtype, np.integer):
            raise InputError(f"cannot select nodes with {where!r}: expected an edge name, a list of "
                             "names, a (k, 2) integer array of (m, n) indices or a predicate")
        if idx.size and (idx.min() < 0 or idx[:, 0].max() >= M or idx[:, 1].max() >= N):
            raise InputError(f"node indices {where!r} lie outside the {M} x {N} grid")
        mask = np.zeros((M, N), bool)
        mask[idx[:, 0], idx[:, 1]] = True
    if not mask.any():
        raise InputError(f"selection {where!r} selects no node of the {M} x {N} grid")
    return mask


def _axes(value, most: int) -> tuple[int, ...] | None:
    """The sorted coordinates (0, 1, 2) that ``value`` names (an axis or a tuple of at most ``most`` different
    ones), or None if it names no such set."""
    given = value if isinstance(value, (tuple, list)) else (value,)
    if not 1 <= len(given) <= most or not all(not isinstance(a, bool) and a in AXES for a in given):
        return None
    axes = tuple(sorted({AXES[a] for a in given}))
    return axes if len(axes) == len(given) else None


@dataclass(frozen=True)
class Pin:
    """Hold the selected nodes at their initial positions.

    ``motion``, optional: a callable ``t -> (3,)`` displacement added to the
    initial positions (prescribed rigid motion of the pinned nodes).
    ``axes``, optional: hold only these coordinates ("x", "y", "z" or 0, 1, 2;
    a tuple), leaving the others free: ``Pin(where, motion, axes=("x", "z"))``
    carries the nodes along x and holds their height, and lets them swing
    along y (a curtain's ring on its rod). None (the default): all three.
    """

    where: object
    motion: Callable[[float], np.ndarray] | None = None
    axes: tuple | None = None

    def __post_init__(self):
        function("Pin.motion", self.motion)
        if self.axes is not None:
            axes = _axes(self.axes, 3)
            if axes is None:
                raise InputError(f"Pin.axes must be None or different axes among 'x', 'y', 'z', 0, 1, 2; got "
                                 f"{self.axes!r}", field="Pin.axes", value=self.axes)
            object.__setattr__(self, "axes", axes)

    @property
    def held(self) -> tuple[int, ...]:
        """The held coordinates (0, 1, 2 for x, y, z)."""
        return (0, 1, 2) if self.axes is None else self.axes


@dataclass(frozen=True)
class Slide:
    """Let the selected nodes move only along ``axis`` ("x", "y", "z" or 0, 1, 2), or in the plane of two axes.

    ``Slide("top", "x")`` is a rail along x; ``Slide("top", ("x", "y"))`` a
    horizontal plane the nodes stay in (a curtain rod whose rings slide along x
    and swing out along y, holding only the height). ``axes`` is the tuple of
    free coordinates.
    """

    where: object
    axis: object = "x"

    def __post_init__(self):
        axes = _axes(self.axis, 2)
        if axes is None:
            raise InputError(f"Slide.axis must be one of 'x', 'y', 'z', 0, 1, 2 or two different ones; got "
                             f"{self.axis!r}", field="Slide.axis", value=self.axis)
        object.__setattr__(self, "axis", axes[0] if len(axes) == 1 else axes)

    @property
    def axes(self) -> tuple[int, ...]:
        return self.axis if isinstance(self.axis, tuple) else (self.axis,)


@dataclass(frozen=True)
class Clamp:
    """Hold an edge (or edges, by name) and its tangent plane."""

    where: object

    def __post_init__(self):
        names = [self.where] if isinstance(self.where, str) else self.where
        if not isinstance(names, (list, tuple)) or not all(n in EDGES for n in names):
            raise InputError(f"Clamp.where must name edges {sorted(EDGES)}, got {self.where!r}")

    @property
    def edges(self) -> list[str]:
        return [self.where] if isinstance(self.where, str) else list(self.where)


@dataclass(frozen=True)
class Symmetry:
    """The edge(s) ``where`` on a plane of symmetry with normal ``normal`` ("x", "y", "z" or 0, 1, 2).

    The mirror image of the sheet across the plane continues it smoothly: the edge's nodes keep their
    coordinate along the normal (the plane through them), and the tangent across the edge is along the normal
    (its other two components vanish, and so do their derivatives along the edge). On FE these are held
    degrees of freedom: the value and the derivative along the edge in the normal's coordinate, the derivative
    across the edge and the mixed one in the other two. The initial shape must meet the plane so (checked).
    The symmetric solution of a whole sheet satisfies these exactly, so a quarter model with two symmetry
    edges has the same discrete solution as the whole on the same elements.
    """

    where: object
    normal: object = "x"

    def __post_init__(self):
        names = [self.where] if isinstance(self.where, str) else self.where
        if not isinstance(names, (list, tuple)) or not names or not all(n in EDGES for n in names):
            raise InputError(f"Symmetry.where must name edges {sorted(EDGES)}, got {self.where!r}",
                             field="Symmetry.where", value=self.where)
        axes = _axes(self.normal, 1)
        if axes is None or len(axes) != 1:
            raise InputError(f"Symmetry.normal must be one of 'x', 'y', 'z', 0, 1, 2; got {self.normal!r}",
                             field="Symmetry.normal", value=self.normal)
        object.__setattr__(self, "normal", axes[0])

    @property
    def edges(self) -> list[str]:
        return [self.where] if isinstance(self.where, str) else list(self.where)

    def check(self, sheet) -> None:
        """InputError unless the initial shape lies on the plane along each edge and meets it perpendicularly."""
        from ..geometry.surfaces import as_surface

        s = as_surface(sheet.initial)
        a1, a2 = sheet.coordinates()
        for name in self.edges:
            mask, edge = sheet.edge_nodes(name), sheet.edge(name)
            r = s.r(a1[mask], a2[mask])
            across = (s.r1, s.r2)[edge.axis](a1[mask], a2[mask])
            scale = float(np.max(np.abs(r))) or 1.0
            off_plane = float(np.ptp(r[:, self.normal]))
            tilt = float(np.max(np.abs(np.delete(across, self.normal, axis=1)))) / float(np.max(np.abs(across)))
            if off_plane > 1e-9 * scale or tilt > 1e-9:
                raise InputError(f"Symmetry({name!r}, normal {'xyz'[self.normal]!r}): the initial shape must lie on "
                                 f"the plane along the edge and meet it perpendicularly (coordinate spread "
                                 f"{off_plane:.3g}, tangent tilt {tilt:.3g})", field="Symmetry.where", value=name)


@dataclass
class HeldDofs:
    """The constraints of a scene on one backend's degrees of freedom.

    Attributes
    ----------
    fixed : (3,) tuple of int arrays
        Held degrees of freedom of x, y and z (sorted, unique).
    motions : list of (int array, callable t -> (3,))
        Value degrees of freedom translated by a pin's prescribed motion.
    """

    fixed: tuple
    motions: list = field(default_factory=list)

    def prescribed(self, X0: np.ndarray, t: float) -> np.ndarray:
        """X0 (ndof, 3) with the moving pins' value degrees of freedom translated to time t."""
        X = np.array(X0, dtype=float)
        for idx, motion in self.motions:
            X[idx] += np.asarray(motion(t), float)
        return X


def hold(scene, ndof: int, node_dofs: Callable, edge_dofs: Callable, clamp_dofs: Callable,
         symmetry_dofs: Callable | None = None) -> HeldDofs:
    """Map a scene's Pin, Slide, Clamp and Symmetry to held degrees of freedom, the same way for every backend.

    Parameters
    ----------
    scene : Scene
    ndof : int
        Degrees of freedom per coordinate.
    node_dofs : callable (M, N) bool mask -> int array
        The degrees of freedom that carry the positions of the masked nodes (FD: the nodes; FE: their value dofs).
    edge_dofs : callable edge name -> int array
        What else a pin or slide of a whole named edge holds (FE: the derivative along the edge, known once
        r is known along it; FD: nothing).
    clamp_dofs : callable edge name -> int array, or a tuple of three (x, y, z)
        What a Clamp of the edge holds, for every coordinate or per coordinate (FD: the edge row, with
        the ghost row of the reflection clamp; FE: values and the
        derivative along the edge, and the normal component of the derivatives across it).
    symmetry_dofs : callable (edge name, normal axis) -> tuple of three (x, y, z) int arrays, optional
        What a Symmetry of the edge holds (FE: :class:`Symmetry`); None: the backend has no symmetry plane
        (an InputError when the scene has one).
    """
    sheet = scene.sheet
    fixed = np.zeros((3, ndof), bool)
    motions = []
    for c in scene.constraints:
        if isinstance(c, Symmetry):
            if symmetry_dofs is None:
                raise InputError("Symmetry is a constraint of the FE backend only (FD's mirror ghost row would differ "
                                 "between x, y and z); use backend 'fe'", field="Scene.constraints", value=c)
            c.check(sheet)
            for edge in c.edges:
                for k, dofs in enumerate(symmetry_dofs(edge, c.normal)):
                    fixed[k, dofs] = True
            continue
        if isinstance(c, Clamp):
            for edge in c.edges:
                held = clamp_dofs(edge)
                if isinstance(held, tuple):
                    for k in range(3):
                        fixed[k, held[k]] = True
                else:
                    fixed[:, held] = True
            continue
        values = node_dofs(select(c.where, sheet))
        held = np.concatenate([values] + [edge_dofs(e) for e in edges_named(c.where)])
        if isinstance(c, Pin):
            for k in c.held:
                fixed[k, held] = True
            if c.motion is not None:
                motions.append((values, c.motion))
        else:  # Slide: every component but the rail's axes
            for k in range(3):
                if k not in c.axes:
                    fixed[k, held] = True
    return HeldDofs(tuple(np.flatnonzero(f) for f in fixed), motions)
