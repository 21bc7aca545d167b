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

A surface's own G0 and B0 pass the paper's compatibility test (eq. (10), ``deformable check``) up to the
differencing error; on a sphere, unlike a plane or a cylinder, every compared vector is resolved, so the
test shows the paper's ratio and cosine rather than the residual.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..errors import InputError

__all__ = ["KINDS", "MongePatch", "from_table"]

#: the rest shapes a scene file can name, and the field each needs
KINDS = {"cylinder": "radius", "sphere": "radius", "saddle": "curvature", "height": "z"}


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


def from_table(table: dict, size: tuple, where: str = "scene field rest_shape") -> MongePatch:
    """The rest shape of a ``rest_shape`` table over a rectangle of ``size`` (L1, L2) (module docstring);
    InputError naming the field and value for anything else."""
    if not isinstance(table, dict) or table.get("kind") not in KINDS:
        kind = table.get("kind") if isinstance(table, dict) else table
        raise InputError(f"{where}.kind must be one of {', '.join(KINDS)}, got {kind!r}", field=f"{where}.kind",
                         value=kind)
    kind = table["kind"]
    extra = set(table) - {"kind", KINDS[kind]}
    if extra:
        raise InputError(f"{where}: unknown key {sorted(extra)[0]!r} for kind {kind!r} (it takes {KINDS[kind]!r})",
                         field=f"{where}.{sorted(extra)[0]}", value=table[sorted(extra)[0]])
    (L1, L2), c1, c2 = size, size[0] / 2, size[1] / 2
    if kind == "height":
        z = table.get("z")
        try:
            z = np.asarray(z, float)
        except (TypeError, ValueError):
            z = np.zeros((0, 0))
        if z.ndim != 2 or min(z.shape) < 4 or not np.all(np.isfinite(z)):
            raise InputError(f"{where}.z must be a grid of at least 4 x 4 finite heights (m), got {table.get('z')!r}",
                             field=f"{where}.z", value=table.get("z"))
        from scipy.interpolate import RectBivariateSpline

        spline = RectBivariateSpline(np.linspace(0, L1, z.shape[0]), np.linspace(0, L2, z.shape[1]), z, kx=3, ky=3)

        def derivatives(a1, a2):
            return tuple(spline.ev(a1, a2, dx=i, dy=j) for i, j in ((1, 0), (0, 1), (2, 0), (1, 1), (0, 2)))

        return MongePatch(derivatives, {"kind": kind, "z": z.tolist()})
    value = _number(table, KINDS[kind], where)
    if kind == "saddle":
        def derivatives(a1, a2):
            x, y = a1 - c1, a2 - c2
            one = np.ones_like(x + y)
            return value * x * one, -value * y * one, value * one, 0.0 * one, -value * one

        return MongePatch(derivatives, {"kind": kind, "curvature": value})
    reach = L1 / 2 if kind == "cylinder" else math.hypot(L1, L2) / 2
    if not value > reach:
        raise InputError(f"{where}.radius must exceed {'half the width' if kind == 'cylinder' else 'half the diagonal'}"
                         f" of the sheet, {reach:g} m, got {value!r}", field=f"{where}.radius", value=value)
    R = value

    def derivatives(a1, a2):
        x = a1 - c1
        y = (a2 - c2) if kind == "sphere" else 0.0 * a2
        s = np.sqrt(R * R - x * x - y * y)
        f1, f2 = x / s, y / s
        # f = R - s: f_ij = (delta_ij s^2 + x_i x_j) / s^3 over the coordinates that enter s
        f11 = (R * R - y * y) / s**3
        f22 = (R * R - x * x) / s**3 if kind == "sphere" else 0.0 * s
        f12 = x * y / s**3
        return f1, f2, f11, f12, f22

    return MongePatch(derivatives, {"kind": kind, "radius": R})
