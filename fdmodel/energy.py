r"""The discrete energy (13) on the FD grid, with its exact gradient and Hessians.

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
the trapezoidal share). The normal is ``n = t1 x t2 / |t1 x t2|`` with the
tangents ``t_i = T_i r`` (forward differences, backward on the last row).

At node k the integrand depends on seven vectors, the *slots* of
:mod:`deformable.integrand`: d_i = D_i+ r, t_i = T_i r and v_ij = D_ij r;
:class:`SlotMap` computes them (one sparse product) and carries the
integrand's gradient back (its transpose). Each slot at node k is a
combination of the positions of six nodes, the stencil (m, n), (m + 1, n),
(m - 1, n), (m, n + 1), (m, n - 1), (m + 1, n + 1): the Hessian is assembled
node by node as an 18 x 18 block (6 nodes x 3 coordinates)
``C_k^T H_k C_k`` from the integrand's point Hessian H_k and the stencil
coefficients C_k, summed on a fixed pattern
(:class:`deformable.assembly.SymmetricElements`): no sparse-sparse product
per call. Stencil positions outside the grid carry zero coefficients (the
natural boundary rule) and point at the node itself.

Vectors are laid out coordinate by coordinate: flat index ``a * ndof + k`` for
coordinate a of node k.
"""

from __future__ import annotations

import numpy as np
import scipy.sparse as sp

from deformable.assembly import SymmetricElements
from deformable.backend import Energy
from deformable.integrand import FD_SLOTS, HESSIANS, Integrand, slot_tensors

__all__ = ["DiscreteEnergy", "SlotMap", "HESSIANS", "STENCIL"]

#: node offsets (dm, dn) of the stencil of a node's slots
STENCIL = ((0, 0), (1, 0), (-1, 0), (0, 1), (0, -1), (1, 1))
#: the operators of the slots, in the order of deformable.integrand.FD_SLOTS
_SLOT_OPERATORS = ("D1", "D2", "T1", "T2", "D11", "D12", "D22")


class SlotMap:
    """The FD slots (d1, d2, t1, t2, v11, v12, v22) at every node, and their stencils.

    Parameters
    ----------
    ops : dict of sparse (MN, MN)
        D1, D2, D11, D22, D12 of :func:`fdmodel.operators.operators`.
    T : (sparse, sparse)
        The tangent operators T1, T2 of :func:`fdmodel.operators.tangents`.
    shape : (M, N)

    Attributes
    ----------
    L : sparse (7 MN, MN)
        Slot s at node k is row ``s MN + k`` applied to the positions.
    stencil : int array (MN, 6)
        The stencil nodes of every node (the node itself where the stencil leaves the grid).
    C : array (MN, 7, 6)
        The coefficient of stencil node p in slot s at node k.
    """

    def __init__(self, ops: dict, T: tuple, shape: tuple[int, int]):
        M, N = shape
        self.n = n = M * N
        named = dict(ops, T1=T[0], T2=T[1])
        self.L = sp.vstack([named[k] for k in _SLOT_OPERATORS], format="csr")
        m, k = np.divmod(np.arange(n), N)
        stencil = np.empty((n, len(STENCIL)), np.int64)
        for p, (dm, dn) in enumerate(STENCIL):
            inside = (m + dm >= 0) & (m + dm < M) & (k + dn >= 0) & (k + dn < N)
            stencil[:, p] = np.where(inside, np.arange(n) + dm * N + dn, np.arange(n))
        self.stencil = stencil
        coo = self.L.tocoo()
        slot, node = np.divmod(coo.row, n)
        cm, ck = np.divmod(coo.col, N)
        position = np.full(9, -1)  # offset code 3 (dm + 1) + (dn + 1) -> stencil position
        for q, (dm, dn) in enumerate(STENCIL):
            position[3 * (dm + 1) + dn + 1] = q
        p = position[3 * (cm - m[node] + 1) + ck - k[node] + 1]
        self.C = np.zeros((n, len(_SLOT_OPERATORS), len(STENCIL)))
        np.add.at(self.C, (node, slot, p), coo.data)

    def __call__(self, X: np.ndarray) -> np.ndarray:
        """The slot vectors at every node, (MN, 7, 3)."""
        return (self.L @ X).reshape(len(_SLOT_OPERATORS), self.n, 3).transpose(1, 0, 2)

    def adjoint(self, p: np.ndarray) -> np.ndarray:
        """The nodal vector (MN, 3) of slot covectors p (MN, 7, 3): L^T p."""
        return self.L.T @ p.transpose(1, 0, 2).reshape(-1, 3)

    def tensors(self, X: np.ndarray, shape: tuple[int, int]) -> tuple[np.ndarray, np.ndarray]:
        """G and B of the slots at every node, (2, 2, M, N) each (zero rows where a difference is undefined)."""
        G, B = slot_tensors(self(X), FD_SLOTS)
        return G.reshape(2, 2, *shape), B.reshape(2, 2, *shape)


class DiscreteEnergy:
    """Energy (13) of an FD node grid as a function of the positions (module docstring).

    Parameters
    ----------
    slots : SlotMap
    eta, xi : arrays (2, 2, M, N)
        Weights of eq. (13) times each component's row weight and the cell area (J per unit G^2, B^2).
    G0, B0 : arrays (2, 2, M, N)
        The rest tensors of the slots (:meth:`SlotMap.tensors` of the rest state, or the scene's overrides).
    """

    def __init__(self, slots: SlotMap, eta: np.ndarray, xi: np.ndarray, G0: np.ndarray, B0: np.ndarray):
        self.slots = slots
        self.n = slots.n
        self.integrand = Integrand(eta, xi, G0, B0, FD_SLOTS)
        ldofs = np.concatenate([a * self.n + slots.stencil for a in range(3)], axis=1)  # (n, 18): index a 6 + p
        self._pattern = None
        self._ldofs = ldofs

    @property
    def pattern(self) -> SymmetricElements:
        """The fixed pattern of the coordinate-blocked Hessian (3 ndof, 3 ndof), built on first use."""
        if self._pattern is None:
            self._pattern = SymmetricElements(self._ldofs, 3 * self.n)
        return self._pattern

    def energy(self, X: np.ndarray) -> Energy:
        """(stretching, bending) parts of E (J)."""
        return self.integrand.energy(self.slots(X))

    def gradient(self, X: np.ndarray) -> np.ndarray:
        """Exact gradient dE/dX, (ndof, 3) (N)."""
        return self.slots.adjoint(self.integrand.gradient(self.slots(X)))

    def hessian(self, X: np.ndarray, kind: str = "newton") -> sp.csr_matrix:
        """Hessian (3 ndof, 3 ndof), coordinate-blocked, on a fixed pattern.

        ``kind``: "newton" (exact; may be indefinite, e.g. under compression),
        "gauss-newton" (``2 J^T diag(c) J``, positive semi-definite), "definite"
        or "projected" (:mod:`deformable.integrand`).
        """
        H = self.integrand.hessian(self.slots(X), kind)  # (n, 7, 3, 7, 3)
        C = self.slots.C  # (n, 7, 6)
        Hc = H.transpose(0, 2, 4, 1, 3)  # (n, 3, 3, 7, 7)
        He = np.swapaxes(C, 1, 2)[:, None, None] @ Hc @ C[:, None, None]  # (n, 3, 3, 6, 6)
        He = He.transpose(0, 1, 3, 2, 4).reshape(self.n, 18, 18)
        pat = self.pattern
        return pat.matrix(pat.collect(He[:, pat.upper[0], pat.upper[1]]))
