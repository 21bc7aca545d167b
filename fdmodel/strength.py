r"""The strength matrix K(r) of eq. (16)-(20) on the node grid, assembled on a fixed pattern.

The force of eq. (16)-(17), with the natural boundary rule making the outer
operators the adjoints of the inner ones (:mod:`fdmodel.operators`), is
``e = K(r) R`` with

    K = sum_ij D_i+^T diag(alpha_ij) D_j+ + D_ij^T diag(beta_ij) D_ij     (eq. 20)

(D_ij = D11, D12+, D22), symmetric. Rows are integrated (the backend contract):
every row is multiplied by the cell area h1 h2 and by the row's quadrature
weight (1 for the paper's pointwise scheme; the share of the row's control
area inside the sheet for the control-area weighting, :mod:`fdmodel.model`).

Assembly: K's data array is linear in the 7 node fields (alpha_11, alpha_12,
alpha_21, alpha_22, beta_11, beta_12 + beta_21, beta_22), so a sparse matrix
P that maps them to K.data is built once on the fixed pattern of all the
operator products (:class:`deformable.algebra.patterns.FixedPattern`); each refill
is one sparse mat-vec ``K.data = P w``. When the bending weights vanish
everywhere the pattern holds the membrane stencil only, so the factorisation
does not pay for explicit zeros of the bending one.
"""

from __future__ import annotations

import numpy as np
import scipy.sparse as sp

from deformable.algebra.patterns import FixedPattern

__all__ = ["StrengthMatrix", "TERMS"]

#: (outer, inner) operator pairs of K in the order of the weight fields
TERMS = (("D1", "D1"), ("D1", "D2"), ("D2", "D1"), ("D2", "D2"), ("D11", "D11"), ("D12", "D12"), ("D22", "D22"))
#: the first this many terms are the membrane (alpha) part
STRETCH_TERMS = 4


def _pair_products(Da: sp.csr_matrix, Db: sp.csr_matrix):
    """COO triples of Da^T diag(w) Db: entry (p, q) gets coef * w[k].

    Returns rows p, cols q, coefficients and the weight index k of every product.
    """
    na = np.diff(Da.indptr)
    nb = np.diff(Db.indptr)
    ka = np.repeat(np.arange(Da.shape[0]), na)  # row of every Da entry
    counts = nb[ka]
    rep = np.repeat(np.arange(Da.nnz), counts)
    offsets = np.arange(rep.size) - np.repeat(np.cumsum(counts) - counts, counts)
    jb = Db.indptr[ka[rep]] + offsets
    return Da.indices[rep], Db.indices[jb], Da.data[rep] * Db.data[jb], ka[rep]


class StrengthMatrix:
    """K(r) of eq. (20) from alpha and beta at the nodes, on a fixed pattern.

    Parameters
    ----------
    ops : dict of sparse (MN, MN)
        D1, D2, D11, D22, D12 of :func:`fdmodel.operators.operators`.
    row_weight : dict of arrays (M, N)
        Quadrature weight of every difference row (zero where the row is undefined).
    area : float
        The cell area h1 h2 every row stands for.
    bending : bool
        Whether the pattern holds the bending stencil.
    """

    def __init__(self, ops: dict, row_weight: dict, area: float, bending: bool):
        self.row_weight, self.bending = row_weight, bending
        n = ops["D1"].shape[0]
        self.n = n
        rows, cols, coefs, widx = [], [], [], []
        for t, (a, b) in enumerate(TERMS):
            if t >= STRETCH_TERMS and not bending:
                continue
            p, q, c, k = _pair_products(ops[a], ops[b])
            rows.append(p)
            cols.append(q)
            coefs.append(c)
            widx.append(k + t * n)
        self.pattern = FixedPattern(np.concatenate(rows), np.concatenate(cols), (n, n))
        self._P = sp.csr_matrix((area * np.concatenate(coefs), (self.pattern.slot, np.concatenate(widx))),
                                shape=(self.pattern.nnz, len(TERMS) * n))
        split = STRETCH_TERMS * n
        self._P_alpha = self._P[:, :split].tocsr()
        self._P_beta = self._P[:, split:].tocsr()

    def weights(self, alpha: np.ndarray, beta: np.ndarray) -> np.ndarray:
        """The 7 weight fields of K (times the row weights), flattened in the order of :data:`TERMS`."""
        rw = self.row_weight
        w = [alpha[0, 0] * rw["D1"], alpha[0, 1] * rw["D12"], alpha[1, 0] * rw["D12"], alpha[1, 1] * rw["D2"],
             beta[0, 0] * rw["D11"], (beta[0, 1] + beta[1, 0]) * rw["D12"], beta[1, 1] * rw["D22"]]
        return np.concatenate([x.ravel() for x in w])

    def matrix(self, alpha: np.ndarray, beta: np.ndarray) -> sp.csr_matrix:
        """K for alpha, beta (2, 2, M, N) at the nodes: (MN, MN), symmetric, on the fixed pattern."""
        return self.pattern.matrix(self._P @ self.weights(alpha, beta))

    def parts(self, alpha: np.ndarray, beta: np.ndarray) -> tuple[sp.csr_matrix, sp.csr_matrix]:
        """The membrane (alpha) and bending (beta) parts of K, each on the fixed pattern."""
        w = self.weights(alpha, beta)
        split = STRETCH_TERMS * self.n
        return self.pattern.matrix(self._P_alpha @ w[:split]), self.pattern.matrix(self._P_beta @ w[split:])
