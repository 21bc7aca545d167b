r"""The discrete energy (13) on the FD grid, with its exact gradient and Hessian approximations.

The "variational" force model uses the gradient of the energy the paper writes
down instead of the force (14) (docs/design.md: the two differ; under (14) a
flat sheet has no linear bending stiffness); the tpbf87 model reports this
energy too. On the node grid

    E(r) = h1 h2 sum_k sum_ij  c^S_ij[k] s_ij[k]^2 + c^B_ij[k] b_ij[k]^2,
    s_ij = D_i+ r . D_j+ r - G0_ij                  (eq. 18)
    b_ij = n . D_ij r - B0_ij                         (eq. 19)

with ``c^S_11 = eta_11``, ``c^S_22 = eta_22``, ``c^S_12 = eta_12 + eta_21``
(G12 = G21 share one residual), likewise ``c^B`` with xi, each times the row
weight of the FD model (its validity mask and, for the control-area weighting,
the trapezoidal share). The energy itself is the shared integrand of eq. (13)
(:func:`deformable.elasticity.energy_density`) with these weights.

The normal depends on r: ``n = c/|c|``, ``c = t1 x t2``, ``t_i = T_i r`` (forward
differences, backward on the last row). For a vector v, ``d(v . n) = w . dc``
with ``w = (v - (v.n) n)/|c|``, so ``d(v . n)/dt1 = t2 x w`` and
``d(v . n)/dt2 = w x t1``. That gives the exact gradient and the Jacobian J of
the residuals; the Hessian is offered as Gauss-Newton ``2 J^T diag(c) J``
(symmetric positive semi-definite) or the exact Hessian, which adds
``sum 2 c rho Hess(rho)`` over the residuals. For stretching
``Hess(s_ij) = D_i^T D_j + D_j^T D_i`` per coordinate. For bending, with
``f(c) = v . c/|c|``, ``w = grad f = (v - (v.n) n)/|c|``,
``Hess f = -(w n^T + n w^T)/|c| - (v.n)(I - n n^T)/|c|^2``, ``dc = C (dt1, dt2)``,
``C = [-[t2]x, [t1]x]`` and ``d2c = 2 dt1 x dt2``:

    d2 b = 2 dv . (I - n n^T)/|c| C (dt1, dt2) + (C dt)^T Hess f (C dt) + 2 w . (dt1 x dt2),

a 9 x 9 form per node in (dt1, dt2, dv), assembled through the operators.

Vectors are laid out coordinate by coordinate: flat index ``a * ndof + k`` for
coordinate a of node k.
"""

from __future__ import annotations

import numpy as np
import scipy.sparse as sp

from deformable import tensors
from deformable.backend import Energy
from deformable.elasticity import energy_density

from .operators import node_tensors

__all__ = ["DiscreteEnergy", "HESSIANS"]

HESSIANS = ("gauss-newton", "newton")


class DiscreteEnergy:
    """Energy (13) of an FD node grid as a function of the positions (module docstring).

    Parameters
    ----------
    ops : dict of sparse (MN, MN)
        D1, D2, D11, D22, D12 of :func:`fdmodel.operators.operators`.
    T : (sparse, sparse)
        The tangent operators T1, T2 of :func:`fdmodel.operators.tangents`.
    shape, spacing : (M, N), (h1, h2)
    eta, xi : arrays (2, 2, M, N)
        Weights of eq. (13) times each component's row weight and the cell area (J per unit G^2, B^2).
    G0, B0 : arrays (2, 2, M, N)
        The rest tensors at the nodes.
    """

    STRETCH = ((0, 0, "D1", "D1"), (1, 1, "D2", "D2"), (0, 1, "D1", "D2"))
    BEND = ((0, 0, "D11"), (1, 1, "D22"), (0, 1, "D12"))

    def __init__(self, ops: dict, T: tuple, shape: tuple[int, int], spacing: tuple[float, float],
                 eta: np.ndarray, xi: np.ndarray, G0: np.ndarray, B0: np.ndarray):
        self.ops, self.shape, self.spacing = ops, tuple(shape), tuple(spacing)
        self.T1, self.T2 = T
        self.eta, self.xi, self.G0_field, self.B0_field = eta, xi, G0, B0
        self.n = n = shape[0] * shape[1]

        def both(w, i, j):
            return w[i, j] if i == j else w[0, 1] + w[1, 0]

        self.cS = [both(eta, i, j).ravel() for i, j, _, _ in self.STRETCH]
        self.cB = [both(xi, i, j).ravel() for i, j, _ in self.BEND]
        self.G0 = [G0[i, j].ravel() for i, j, _, _ in self.STRETCH]
        self.B0 = [B0[i, j].ravel() for i, j, _ in self.BEND]
        # local variables of the bending terms at each node: t1, t2, D11 r, D22 r, D12 r (3 coordinates each)
        I3 = sp.identity(3, format="csr")
        self._L15 = sp.vstack([sp.kron(I3, A) for A in (self.T1, self.T2, ops["D11"], ops["D22"], ops["D12"])],
                              format="csr")
        local = (np.arange(5)[:, None] * 3 * n + np.arange(3)[None, :] * n).ravel()  # (group, coordinate)
        rows = local[None, :, None] + np.arange(n)[:, None, None]
        rows = np.broadcast_to(rows, (n, 15, 15))
        self._local15 = (rows.ravel(), np.swapaxes(rows, 1, 2).ravel())

    # -- pieces -------------------------------------------------------------
    def _frame(self, X):
        t1, t2 = self.T1 @ X, self.T2 @ X
        n, area = tensors.frame(t1, t2)
        return t1, t2, n, area

    def tensors(self, X: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """G (eq. 18) and B (eq. 19) at every node, (2, 2, M, N) each."""
        return node_tensors(np.asarray(X).reshape(*self.shape, 3), *self.spacing)

    def residuals(self, X: np.ndarray):
        """Stretching and bending residuals s_ij, b_ij, each a list of three (ndof,) arrays.

        G and B are the FD model's own (eq. 18-19), so the rest state has residuals exactly zero.
        """
        G, B = self.tensors(X)
        s = [G[i, j].ravel() - g0 for (i, j, _, _), g0 in zip(self.STRETCH, self.G0)]
        b = [B[i, j].ravel() - b0 for (i, j, _), b0 in zip(self.BEND, self.B0)]
        return s, b

    def energy(self, X: np.ndarray) -> Energy:
        """(stretching, bending) parts of E (J)."""
        G, B = self.tensors(X)
        stretching, bending = energy_density(self.eta, self.xi, G, self.G0_field, B, self.B0_field)
        return Energy(float(stretching.sum()), float(bending.sum()))

    def gradient(self, X: np.ndarray) -> np.ndarray:
        """Exact gradient dE/dX, (ndof, 3) (N)."""
        ops = self.ops
        d = {k: ops[k] @ X for k in ("D1", "D2")}
        g = np.zeros_like(X)
        for (i, j, a, b), c, g0 in zip(self.STRETCH, self.cS, self.G0):
            f = 2 * c * (tensors.dot(d[a], d[b]) - g0)
            g += ops[a].T @ (f[:, None] * d[b]) + ops[b].T @ (f[:, None] * d[a])
        t1, t2, nrm, nc = self._frame(X)
        W = np.zeros_like(X)
        for (i, j, op), c, b0 in zip(self.BEND, self.cB, self.B0):
            v = ops[op] @ X
            vn = tensors.dot(nrm, v)
            f = 2 * c * (vn - b0)
            g += ops[op].T @ (f[:, None] * nrm)
            W += (f / nc)[:, None] * (v - vn[:, None] * nrm)
        g += self.T1.T @ np.cross(t2, W) + self.T2.T @ np.cross(W, t1)
        return g

    def jacobian(self, X: np.ndarray) -> tuple[sp.csr_matrix, np.ndarray]:
        """Jacobian of all six residuals (6 ndof, 3 ndof) and their weights c (6 ndof,)."""
        ops = self.ops
        d = {k: ops[k] @ X for k in ("D1", "D2")}
        blocks, weights = [], []
        for (_, _, a, b), c in zip(self.STRETCH, self.cS):
            row = [sp.diags(d[b][:, k]) @ ops[a] + sp.diags(d[a][:, k]) @ ops[b] for k in range(3)]
            blocks.append(sp.hstack(row))
            weights.append(c)
        t1, t2, nrm, nc = self._frame(X)
        for (_, _, op), c in zip(self.BEND, self.cB):
            v = ops[op] @ X
            w = (v - tensors.dot(nrm, v)[:, None] * nrm) / nc[:, None]
            p1, p2 = np.cross(t2, w), np.cross(w, t1)
            row = [sp.diags(nrm[:, k]) @ ops[op] + sp.diags(p1[:, k]) @ self.T1 + sp.diags(p2[:, k]) @ self.T2
                   for k in range(3)]
            blocks.append(sp.hstack(row))
            weights.append(c)
        return sp.vstack(blocks, format="csr"), np.concatenate(weights)

    def hessian(self, X: np.ndarray, kind: str = "gauss-newton") -> sp.csr_matrix:
        """Hessian approximation (3 ndof, 3 ndof), coordinate-blocked.

        ``"gauss-newton"``: ``2 J^T diag(c) J``, symmetric positive semi-definite.
        ``"newton"``: the exact Hessian (may be indefinite, e.g. under compression).
        """
        if kind not in HESSIANS:
            raise ValueError(f"hessian kind must be one of {HESSIANS}, got {kind!r}")
        J, c = self.jacobian(X)
        H = (J.T @ sp.diags(2 * c) @ J).tocsr()
        if kind == "newton":
            s, _ = self.residuals(X)
            S = None
            for (_, _, a, b), cc, r in zip(self.STRETCH, self.cS, s):
                A, B = self.ops[a], self.ops[b]
                f = sp.diags(2 * cc * r)
                term = A.T @ f @ B + B.T @ f @ A
                S = term if S is None else S + term
            H = (H + sp.kron(sp.identity(3), S) + self._bending_second_order(X)).tocsr()
        return H

    def _bending_second_order(self, X: np.ndarray) -> sp.csr_matrix:
        """sum_ij 2 c b_ij Hess(b_ij), (3 ndof, 3 ndof): see the module docstring.

        The three bending residuals share the frame (t1, t2), so their weighted
        vectors are summed before :func:`deformable.tensors.normal_hessian`, and
        one 15 x 15 form per node in (t1, t2, v11, v22, v12) is assembled once.
        """
        t1, t2, nrm, _ = self._frame(X)
        weights, V = [], np.zeros_like(X)
        for (_, _, op), c, b0 in zip(self.BEND, self.cB, self.B0):
            v = self.ops[op] @ X
            f = 2 * c * (tensors.dot(nrm, v) - b0)
            weights.append(f)
            V += f[:, None] * v
        Htt, Q = tensors.normal_hessian(t1, t2, V)
        H15 = np.zeros((self.n, 15, 15))
        H15[:, :6, :6] = Htt
        for k, f in enumerate(weights):
            block = f[:, None, None] * Q
            H15[:, 6 + 3 * k:9 + 3 * k, :6] = block
            H15[:, :6, 6 + 3 * k:9 + 3 * k] = np.swapaxes(block, 1, 2)
        rows, cols = self._local15
        Hd = sp.csr_matrix((H15.ravel(), (rows, cols)), shape=(15 * self.n, 15 * self.n))
        return self._L15.T @ Hd @ self._L15
