r"""Rest shapes a scene file can name: G0 and B0 of a surface over the sheet's parameter rectangle.

A scene's ``rest_shape`` table gives the rest metric G0 and curvature B0 of a surface, the shape the sheet
would take free of loads (a curved rest shape, section 3.2), as a Monge patch z = f(a1, a2) over the
parameter rectangle [0, L1] x [0, L2] (x = a1, y = a2):

    G0_ij = delta_ij + f_i f_j,      B0_ij = f_ij / sqrt(1 + f_1^2 + f_2^2)

(eq. (4) and (8) of the patch r = (a1, a2, f)). The kinds, centred on the rectangle's middle (c1, c2):

- ``{kind = "cylinder", radius = R}``: f = R - sqrt(R^2 - (a1 - c1)^2), its axis along a2 (R > L1 / 2);
- ``{kind = "sphere", radius = R}``: f = R - sqrt(R^2 - (a1 - c1)^2 - (a2 - c2)^2) (R above the half diagonal);
- ``{kind = "saddle", curvature = k}``: f = k ((a1 - c1)^2 - (a2 - c2)^2) / 2;
- ``{kind = "height", z = [[...], ...]}``: f sampled on a regular grid over the rectangle (rows along a1, at
  least 4 x 4 values, m), a bicubic interpolating spline (scipy's RectBivariateSpline) between them.

Each kind is a builder in :data:`SHAPES`, looked up by the table's ``kind``; a new shape is one more entry.
A surface's own G0 and B0 pass the paper's compatibility test (eq. (10), ``deformable check``) up to the
differencing error; on a sphere, unlike a plane or a cylinder, every compared vector is resolved, so the
test shows the paper's ratio and cosine rather than the residual.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..errors import InputError

__all__ = ["KINDS", "SHAPES", "MongePatch", "from_table"]


@dataclass(frozen=True)
class MongePatch:
    """z = f(a1, a2) with its first and second derivatives: ``derivatives(a1, a2)`` -> f1, f2, f11, f12, f22."""

    derivatives: object
    table: dict

    def metric(self, a1, a2) -> np.ndarray:
        """G0 at the points, shape S + (2, 2)."""
        f1, f2, *_ = self.derivatives(np.asarray(a1, float), np.asarray(a2, float))
        return np.stack([np.stack([1 + f1 * f1, f1 * f2], -1), np.stack([f1 * f2, 1 + f2 * f2], -1)], -2)

    def curvature(self, a1, a2) -> np.ndarray:
        """B0 at the points, shape S + (2, 2)."""
        f1, f2, f11, f12, f22 = self.derivatives(np.asarray(a1, float), np.asarray(a2, float))
        w = 1.0 / np.sqrt(1 + f1 * f1 + f2 * f2)
        return np.stack([np.stack([f11 * w, f12 * w], -1), np.stack([f12 * w, f22 * w], -1)], -2)


def _number(table, key, where) -> float:
    v = table.get(key)
    if isinstance(v, bool) or not isinstance(v, (int, float)) or not math.isfinite(v):
        raise InputError(f"{where}.{key} must be a finite number, got {v!r}", field=f"{where}.{key}", value=v)
    return float(v)


def _height(table: dict, size: tuple, where: str) -> MongePatch:
    """f sampled on a regular grid ``z`` over the rectangle, a bicubic interpolating spline between the samples."""
    z = table.get("z")
    try:
        z = np.asarray(z, float)
    except (TypeError, ValueError):
        z = np.zeros((0, 0))
    if z.ndim != 2 or min(z.shape) < 4 or not np.all(np.isfinite(z)):
        raise InputError(f"{where}.z must be a grid of at least 4 x 4 finite heights (m), got {table.get('z')!r}",
                         field=f"{where}.z", value=table.get("z"))
    from scipy.interpolate import RectBivariateSpline

    L1, L2 = size
    spline = RectBivariateSpline(np.linspace(0, L1, z.shape[0]), np.linspace(0, L2, z.shape[1]), z, kx=3, ky=3)

    def derivatives(a1, a2):
        return tuple(spline.ev(a1, a2, dx=i, dy=j) for i, j in ((1, 0), (0, 1), (2, 0), (1, 1), (0, 2)))

    return MongePatch(derivatives, {"kind": "height", "z": z.tolist()})


def _saddle(table: dict, size: tuple, where: str) -> MongePatch:
    """f = k ((a1 - c1)^2 - (a2 - c2)^2) / 2."""
    value = _number(table, "curvature", where)
    c1, c2 = size[0] / 2, size[1] / 2

    def derivatives(a1, a2):
        x, y = a1 - c1, a2 - c2
        one = np.ones_like(x + y)
        return value * x * one, -value * y * one, value * one, 0.0 * one, -value * one

    return MongePatch(derivatives, {"kind": "saddle", "curvature": value})


def _radius(table: dict, reach: float, what: str, where: str) -> float:
    R = _number(table, "radius", where)
    if not R > reach:
        raise InputError(f"{where}.radius must exceed {what} of the sheet, {reach:g} m, got {R!r}",
                         field=f"{where}.radius", value=R)
    return R


def _cap(R: float, x, y) -> tuple:
    """s = sqrt(R^2 - x^2 - y^2) and f_1, f_2, f_11, f_12 of f = R - s: f_ij = (delta_ij s^2 + x_i x_j) / s^3."""
    s = np.sqrt(R * R - x * x - y * y)
    return s, x / s, y / s, (R * R - y * y) / s**3, x * y / s**3


def _cylinder(table: dict, size: tuple, where: str) -> MongePatch:
    """f = R - sqrt(R^2 - (a1 - c1)^2), its axis along a2."""
    c1 = size[0] / 2
    R = _radius(table, c1, "half the width", where)

    def derivatives(a1, a2):
        s, f1, f2, f11, f12 = _cap(R, a1 - c1, 0.0 * a2)
        return f1, f2, f11, f12, 0.0 * s

    return MongePatch(derivatives, {"kind": "cylinder", "radius": R})


def _sphere(table: dict, size: tuple, where: str) -> MongePatch:
    """f = R - sqrt(R^2 - (a1 - c1)^2 - (a2 - c2)^2)."""
    c1, c2 = size[0] / 2, size[1] / 2
    R = _radius(table, math.hypot(*size) / 2, "half the diagonal", where)

    def derivatives(a1, a2):
        x = a1 - c1
        s, f1, f2, f11, f12 = _cap(R, x, a2 - c2)
        return f1, f2, f11, f12, (R * R - x * x) / s**3

    return MongePatch(derivatives, {"kind": "sphere", "radius": R})


#: the rest shapes a scene file can name: kind -> (the field it takes, its builder (table, size, where) -> MongePatch)
SHAPES = {"cylinder": ("radius", _cylinder), "sphere": ("radius", _sphere), "saddle": ("curvature", _saddle),
          "height": ("z", _height)}
#: the field each rest shape takes
KINDS = {kind: field for kind, (field, _) in SHAPES.items()}


def from_table(table: dict, size: tuple, where: str = "scene field rest_shape") -> MongePatch:
    """The rest shape of a ``rest_shape`` table over a rectangle of ``size`` (L1, L2) (module docstring), built by
    its kind's entry of :data:`SHAPES`; InputError naming the field and value for anything else."""
    if not isinstance(table, dict) or table.get("kind") not in SHAPES:
        kind = table.get("kind") if isinstance(table, dict) else table
        raise InputError(f"{where}.kind must be one of {', '.join(SHAPES)}, got {kind!r}", field=f"{where}.kind",
                         value=kind)
    field, build = SHAPES[table["kind"]]
    extra = sorted(set(table) - {"kind", field})
    if extra:
        raise InputError(f"{where}: unknown key {extra[0]!r} for kind {table['kind']!r} (it takes {field!r})",
                         field=f"{where}.{extra[0]}", value=table[extra[0]])
    return build(table, size, where)
