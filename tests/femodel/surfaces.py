r"""Analytic test surfaces with closed-form derivatives, metric (eq. 4) and curvature (eq. 8).

- :class:`MongePatch`: the generic (asymmetric) Monge patch of DESIGN.md,
  ``r = (a1, a2, f)``, ``f = 0.3 sin(2 a1 + 0.3) sin(3 a2 + 0.7)``; orthogonal
  parameters only to first order (``G12 = f_1 f_2``).
- :class:`SkewSheet`: a non-orthogonal parametrisation with non-polynomial
  in-plane part, ``r = (a1 + 0.4 a2, a2 + 0.3 sin a1, g)``,
  ``g = 0.2 sin(2 a1 + 0.3) cos(1.5 a2 + 0.2)``, so
  ``G11 = 1 + 0.09 cos^2 a1 + g_1^2``, ``G12 = 0.4 + 0.3 cos a1 + g_1 g_2``,
  ``G22 = 1.16 + g_2^2``.

For both, ``B_ij = n . r_ij`` with ``n = r_1 x r_2 / |r_1 x r_2|`` evaluated
from the closed-form derivatives.
"""

from __future__ import annotations

import numpy as np


def _vec(x, y, z):
    x, y, z = np.broadcast_arrays(x, y, z)
    return np.stack([x, y, z], axis=-1).astype(float)


class _Closed:
    """Common part: G and B from the closed-form first and second derivatives."""

    def G(self, a1, a2):
        """Metric tensor, (..., 2, 2)."""
        r1, r2 = self.r1(a1, a2), self.r2(a1, a2)
        g11, g12, g22 = (r1 * r1).sum(-1), (r1 * r2).sum(-1), (r2 * r2).sum(-1)
        return np.stack([np.stack([g11, g12], -1), np.stack([g12, g22], -1)], -2)

    def B(self, a1, a2):
        """Curvature tensor, (..., 2, 2)."""
        c = np.cross(self.r1(a1, a2), self.r2(a1, a2))
        n = c / np.linalg.norm(c, axis=-1, keepdims=True)
        b11, b12, b22 = ((n * d).sum(-1) for d in (self.r11(a1, a2), self.r12(a1, a2), self.r22(a1, a2)))
        return np.stack([np.stack([b11, b12], -1), np.stack([b12, b22], -1)], -2)


class MongePatch(_Closed):
    """z = 0.3 sin(2 a1 + 0.3) sin(3 a2 + 0.7) over (a1, a2)."""

    def r(self, a1, a2):
        return _vec(a1, a2, 0.3 * np.sin(2 * a1 + 0.3) * np.sin(3 * a2 + 0.7))

    def r1(self, a1, a2):
        return _vec(1.0, 0.0, 0.6 * np.cos(2 * a1 + 0.3) * np.sin(3 * a2 + 0.7))

    def r2(self, a1, a2):
        return _vec(0.0, 1.0, 0.9 * np.sin(2 * a1 + 0.3) * np.cos(3 * a2 + 0.7))

    def r11(self, a1, a2):
        return _vec(0.0, 0.0, -1.2 * np.sin(2 * a1 + 0.3) * np.sin(3 * a2 + 0.7))

    def r12(self, a1, a2):
        return _vec(0.0, 0.0, 1.8 * np.cos(2 * a1 + 0.3) * np.cos(3 * a2 + 0.7))

    def r22(self, a1, a2):
        return _vec(0.0, 0.0, -2.7 * np.sin(2 * a1 + 0.3) * np.sin(3 * a2 + 0.7))


class SkewSheet(_Closed):
    """r = (a1 + 0.4 a2, a2 + 0.3 sin a1, 0.2 sin(2 a1 + 0.3) cos(1.5 a2 + 0.2)): G12 != 0."""

    def r(self, a1, a2):
        return _vec(a1 + 0.4 * a2, a2 + 0.3 * np.sin(a1), 0.2 * np.sin(2 * a1 + 0.3) * np.cos(1.5 * a2 + 0.2))

    def r1(self, a1, a2):
        return _vec(1.0, 0.3 * np.cos(a1), 0.4 * np.cos(2 * a1 + 0.3) * np.cos(1.5 * a2 + 0.2))

    def r2(self, a1, a2):
        return _vec(0.4, 1.0, -0.3 * np.sin(2 * a1 + 0.3) * np.sin(1.5 * a2 + 0.2))

    def r11(self, a1, a2):
        return _vec(0.0, -0.3 * np.sin(a1), -0.8 * np.sin(2 * a1 + 0.3) * np.cos(1.5 * a2 + 0.2))

    def r12(self, a1, a2):
        return _vec(0.0, 0.0, -0.6 * np.cos(2 * a1 + 0.3) * np.sin(1.5 * a2 + 0.2))

    def r22(self, a1, a2):
        return _vec(0.0, 0.0, -0.45 * np.sin(2 * a1 + 0.3) * np.cos(1.5 * a2 + 0.2))
