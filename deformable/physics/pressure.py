r"""Follower pressure as a potential over a backend's patches (:class:`~deformable.physics.forces.Pressure`).

At the backend's quadrature points, grouped by the degrees of freedom they read (:meth:`Backend.patches`:
FE its elements' Gauss points; FD its cells' centres, r the mean of the four corners, r_1 and r_2 the cell's
mean differences), with tau = r . (r_1 x r_2):

    Pi(X) = -p V,   V = (1/3) sum_g sum_q w tau,
    d tau = dr . (r_1 x r_2) + dr_1 . (r_2 x r) + dr_2 . (r x r_1),
    d^2 tau: (r, r_1) -> -[r_2]x, (r, r_2) -> [r_1]x, (r_1, r_2) -> -[r]x   ([a]x b = a x b),

the exact gradient and Hessian, assembled per group on one fixed pattern. The continuum variation of V is
int dr . (r_1 x r_2) da plus boundary terms (1/3) oint of dr against r x r_i: with every edge held the load
is p r_1 x r_2, the follower pressure (Schweizerhof and Ramm 1984); the potential checks that every edge
node's position is held, and refuses the pressure otherwise. The origin only shifts V by a constant then.
The discrete gradient against the follower load -p int phi (r_1 x r_2) by the same points
(tests/deformable/physics/test_pressure.py): FE equal to round-off (its quadrature integrates the discrete
summation by parts exactly), FD 6.3e-3, 1.7e-3, 4.3e-4 of it on 9, 17, 33 nodes (second order; node-centred
forward differences, backward on the last row, tried first, were inconsistent there: 1.3 to 9.2, growing as
1 / h).
"""

from __future__ import annotations

import numpy as np
import scipy.sparse as sp

from ..algebra.patterns import FixedPattern
from ..errors import InputError

__all__ = ["PressurePotential"]


def _skew(a: np.ndarray) -> np.ndarray:
    """[a]x (..., 3, 3) of vectors a (..., 3)."""
    z = np.zeros(a.shape[:-1])
    return np.stack([np.stack([z, -a[..., 2], a[..., 1]], -1), np.stack([a[..., 2], z, -a[..., 0]], -1),
                     np.stack([-a[..., 1], a[..., 0], z], -1)], -2)


class PressurePotential:
    """The scene's pressures on a model (module docstring): the potential of
    :class:`~deformable.physics.forces.Pressure`, third in the sum of potentials, scaled by the load factor."""

    rank, factored, linear = 2, True, False

    def __init__(self, model, pressures):
        self.model, self.n, self.pressures = model, model.ndof, tuple(pressures)
        sheet = model.scene.sheet
        boundary = np.zeros(sheet.nodes, bool)
        boundary[[0, -1], :] = boundary[:, [0, -1]] = True
        values = np.asarray(model.value_dofs)[boundary.ravel()]
        fixed = model.fixed_dofs()
        free = [name for name in ("left", "right", "bottom", "top")
                if not all(np.isin(np.asarray(model.value_dofs)[sheet.edge_nodes(name).ravel()], f).all()
                           for f in fixed)]
        if free or not all(np.isin(values, f).all() for f in fixed):
            raise InputError(f"Pressure: a follower pressure is a potential (and conservative) only on a sheet whose "
                             f"edges are all held (Pin or Clamp in x, y and z); free: {', '.join(free)}",
                             field="Scene.forces", value="Pressure")
        patch = model.patches()
        self.cols, self.T, self.w = patch.cols, np.asarray(patch.values), np.asarray(patch.weights)
        G, c = self.cols.shape
        n = self.n
        rows = (np.arange(3)[:, None, None, None, None] * n + self.cols[None, :, :, None, None])
        cols = (np.arange(3)[None, None, None, None, :] * n + self.cols[None, :, None, :, None])
        shape = (3, G, c, c, 3)  # (alpha, group, c, c', beta)
        self._pattern = FixedPattern(np.broadcast_to(rows, shape).ravel(), np.broadcast_to(cols, shape).ravel(),
                                     (3 * n, 3 * n))

    def _fields(self, X):
        Xl = np.asarray(X, float)[self.cols]  # (G, c, 3)
        return [np.einsum("gqc,gcd->gqd", self.T[i], Xl) for i in range(3)]  # r, r_1, r_2, each (G, q, 3)

    def _p(self, t: float, factor: float) -> float:
        return factor * sum(f.pressure(t) for f in self.pressures)

    def volume(self, X) -> float:
        """V = (1/3) int r . (r_1 x r_2) da (m^3)."""
        r, r1, r2 = self._fields(X)
        return float(np.sum(self.w * np.sum(r * np.cross(r1, r2), -1)) / 3)

    def energy(self, X, t: float, factor: float = 1.0) -> float:
        """-p V (J)."""
        return -self._p(t, factor) * self.volume(X)

    def gradient(self, X, t: float, factor: float = 1.0) -> np.ndarray:
        """The gradient of :meth:`energy`, (ndof, 3) (N): minus the integrated follower pressure."""
        r, r1, r2 = self._fields(X)
        parts = (np.cross(r1, r2), np.cross(r2, r), np.cross(r, r1))
        local = sum(np.einsum("gqc,gq,gqd->gcd", self.T[i], self.w, parts[i]) for i in range(3))
        G = np.zeros((self.n, 3))
        np.add.at(G, self.cols, -self._p(t, factor) / 3 * local)
        return G

    def hessian(self, X, t: float, factor: float = 1.0) -> sp.csr_matrix:
        """The exact Hessian of :meth:`energy`, (3 ndof, 3 ndof) coordinate-blocked, on a fixed pattern."""
        r, r1, r2 = self._fields(X)
        C = {(0, 1): -_skew(r2), (0, 2): _skew(r1), (1, 2): -_skew(r)}  # (G, q, 3, 3) each
        local = 0.0
        for (i, j), Cij in C.items():
            Tw = self.T[i] * self.w[..., None]
            local = local + np.einsum("gqc,gqe,gqab->agceb", Tw, self.T[j], Cij) \
                + np.einsum("gqc,gqe,gqba->agceb", self.T[j] * self.w[..., None], self.T[i], Cij)
        values = -self._p(t, factor) / 3 * local
        return self._pattern.matrix(self._pattern.data(np.ascontiguousarray(values).ravel()))
