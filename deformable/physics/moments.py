r"""Edge moments as a potential over a backend's edge rule (:class:`~deformable.physics.forces.EdgeMoment`).

For each moment, at the P points of the backend's rule on its edge (:meth:`Backend.edge_rule`: weights w,
the fixed matrix ``across`` of the derivative across the edge), the outward tangent d = s across X
(s = -1 on "left" and "bottom", +1 on "right" and "top") and the rest frame of the analytic rest surface
(e0 the unit tangent along the edge, u0 the unit outward tangent made normal to e0, v0 = e0 x u0):

    Pi(X) = -sum_p w_p m_p theta_p,   grad = -s across^T (w m dtheta/dd),
    Hessian = -across^T blockdiag(w m d^2theta/dd^2) across        (exact, indefinite in general)

on one fixed pattern (:class:`~deformable.algebra.patterns.FixedPattern`). theta is unwrapped: each
gradient call (Newton takes one at every iterate) moves the reference angles to the state it was given,
and theta lies within pi of the reference, so a sheet can roll past a half turn in steps of less than
one. The potential is scaled by a load factor (``equilibrium``'s load steps) and the moment's time factor.
"""

from __future__ import annotations

import numpy as np
import scipy.sparse as sp

from ..algebra.patterns import FixedPattern
from ..geometry.surfaces import as_surface

__all__ = ["EdgeMoments", "rotation_angle"]


def rotation_angle(d: np.ndarray, u0: np.ndarray, v0: np.ndarray, reference: np.ndarray):
    """theta, d theta / d d and d^2 theta / d d^2 at P points: (P,), (P, 3), (P, 3, 3).

    ``d`` (P, 3) the tangents, ``u0``, ``v0`` (P, 3) the rest frame, ``reference`` (P,) the angles to
    unwrap against (theta lies within pi of it). With x = d . u0, y = d . v0, rho^2 = x^2 + y^2:
    dtheta = (x v0 - y u0) / rho^2, and in (x, y) the Hessian [[2 x y, y^2 - x^2], [y^2 - x^2, -2 x y]] / rho^4.
    """
    x, y = np.sum(d * u0, -1), np.sum(d * v0, -1)
    rho2 = x**2 + y**2
    theta = reference + np.angle(np.exp(1j * (np.arctan2(y, x) - reference)))
    g = (x[:, None] * v0 - y[:, None] * u0) / rho2[:, None]
    hxx, hxy = 2 * x * y / rho2**2, (y**2 - x**2) / rho2**2
    uu, vv = np.einsum("pi,pj->pij", u0, u0), np.einsum("pi,pj->pij", v0, v0)
    uv = np.einsum("pi,pj->pij", u0, v0)
    H = hxx[:, None, None] * (uu - vv) + hxy[:, None, None] * (uv + np.swapaxes(uv, 1, 2))
    return theta, g, H


class EdgeMoments:
    """The scene's edge moments on a model (module docstring): the potential of
    :class:`~deformable.physics.forces.EdgeMoment`, second in the sum of potentials, scaled by the load factor."""

    rank, factored, linear = 1, True, False

    def __init__(self, model, moments):
        self.model, self.n = model, model.ndof
        sheet = model.scene.sheet
        rest = as_surface(sheet.rest)
        self.parts = []
        rows, cols, coef, point = [], [], [], []
        offset = 0
        for moment in moments:
            edge = sheet.edge(moment.edge)
            rule = model.edge_rule(moment.edge)
            sign = -1.0 if edge.side == 0 else 1.0
            t = [rest.r1(rule.a1, rule.a2), rest.r2(rule.a1, rule.a2)]
            e0 = t[edge.along] / np.linalg.norm(t[edge.along], axis=-1, keepdims=True)
            u0 = sign * t[edge.axis]
            u0 = u0 - np.sum(u0 * e0, -1, keepdims=True) * e0
            u0 /= np.linalg.norm(u0, axis=-1, keepdims=True)
            v0 = np.cross(e0, u0)
            A = sp.csr_matrix(rule.across)
            X0 = model.initial_state()
            theta0 = np.arctan2(np.sum(sign * (A @ X0) * v0, -1), np.sum(sign * (A @ X0) * u0, -1))
            self.parts.append(dict(moment=moment, rule=rule, A=A, sign=sign, u0=u0, v0=v0, reference=theta0))
            # A^T C A: for each point p the pairs of its entries (k, l), coefficient a_pk a_pl
            for p in range(A.shape[0]):
                k, a = A.indices[A.indptr[p]:A.indptr[p + 1]], A.data[A.indptr[p]:A.indptr[p + 1]]
                rows.append(np.repeat(k, k.size))
                cols.append(np.tile(k, k.size))
                coef.append(np.outer(a, a).ravel())
                point.append(np.full(k.size**2, offset + p))
            offset += A.shape[0]
        rows, cols = np.concatenate(rows), np.concatenate(cols)
        self._coef, self._point = np.concatenate(coef), np.concatenate(point)
        n = self.n
        pairs = [(a, b) for a in range(3) for b in range(3)]
        self._pairs = pairs
        self._pattern = FixedPattern(np.concatenate([a * n + rows for a, _ in pairs]),
                                     np.concatenate([b * n + cols for _, b in pairs]), (3 * n, 3 * n))

    def _evaluate(self, X, t: float, factor: float):
        out = []
        for part in self.parts:
            rule = part["rule"]
            d = part["sign"] * (part["A"] @ X)
            theta, g, H = rotation_angle(d, part["u0"], part["v0"], part["reference"])
            wm = factor * rule.weights * part["moment"].moment(rule.a1, rule.a2, t)
            out.append((part, theta, g, H, wm))
        return out

    def energy(self, X, t: float, factor: float = 1.0) -> float:
        """-sum w m theta (J)."""
        return float(sum(-np.sum(wm * theta) for _, theta, _, _, wm in self._evaluate(X, t, factor)))

    def gradient(self, X, t: float, factor: float = 1.0) -> np.ndarray:
        """The gradient of :meth:`energy`, (ndof, 3) (N); moves the reference angles to X (module docstring)."""
        G = np.zeros((self.n, 3))
        for part, theta, g, _, wm in self._evaluate(X, t, factor):
            G -= part["sign"] * (part["A"].T @ (wm[:, None] * g))
            part["reference"] = theta
        return G

    def hessian(self, X, t: float, factor: float = 1.0) -> sp.csr_matrix:
        """The exact Hessian of :meth:`energy`, (3 ndof, 3 ndof) coordinate-blocked, on a fixed pattern."""
        C = np.concatenate([-wm[:, None, None] * H for _, _, _, H, wm in self._evaluate(X, t, factor)])  # (P, 3, 3)
        values = np.concatenate([self._coef * C[self._point, a, b] for a, b in self._pairs])
        return self._pattern.matrix(self._pattern.data(values))

    def angles(self, X) -> list[np.ndarray]:
        """The unwrapped rotation theta (rad) at each moment's points, against the current references."""
        return [rotation_angle(part["sign"] * (part["A"] @ X), part["u0"], part["v0"], part["reference"])[0]
                for part in self.parts]
