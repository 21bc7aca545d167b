r"""Difference operators of the TPBF87 appendix on the M x N node grid.

Nodes r[m, n], m = 0..M-1 along a1, n = 0..N-1 along a2; flat index m N + n.

- ``D1+ u[m,n] = (u[m+1,n] - u[m,n])/h1``, ``D1- u[m,n] = (u[m,n] - u[m-1,n])/h1``
- ``D11 = D1- D1+`` (central), ``D22 = D2- D2+``, ``D12+ = D1+ D2+``

Natural boundary rule (paper, below eq. (19)): any difference that needs a
node outside the grid is zero. Applied to the inner operators of eq. (17)
this makes the outer operators of eq. (16) their adjoints, e.g.
``-D1-(p) = (D1+)^T p`` when p vanishes where D1+ is undefined, so

    K = sum_ij (D_i+)^T diag(alpha_ij) D_j+ + (D_ij)^T diag(beta_ij) D_ij     (eq. 16-20)

is symmetric. The sparse operators below follow that rule; the array
functions (:func:`node_derivatives`, :func:`node_tensors`) give values at
*every* node for reporting G and B, with one-sided differences where the rule
would give zero. The tangents of the normal (:func:`tangents`) are forward
differences, backward on the last row (docs/design.md: the normal at a node
is a documented choice), for both force models; the energy-consistent model
adds a bending half with backward tangents, forward on the first row
(``tangents(..., backward=True)``; central ones were measured and dropped,
docs/design.md); its shear terms take the mean tangents of a cell
(:func:`cell_tangents`), where they are centred (:mod:`fdmodel.energy`).
"""

from __future__ import annotations

import numpy as np
import scipy.sparse as sp

from deformable.geometry import tensors

__all__ = ["forward_1d", "central2_1d", "tangent_1d", "operators", "tangents", "cell_tangents",
           "node_derivatives", "node_tensors", "valid_rows", "centred_tensor"]

#: the weight tensors whose 11 and 22 components weigh first differences (G11 = D1+ r . D1+ r, G22): stretching
STRETCHING = ("eta", "alpha")


def forward_1d(n: int, h: float) -> sp.csr_matrix:
    """(n, n) forward difference, last row zero (the natural boundary rule)."""
    main = np.full(n, -1.0 / h)
    upper = np.full(n - 1, 1.0 / h)
    main[-1] = 0.0
    return sp.diags([main, upper], [0, 1], shape=(n, n), format="csr")


def central2_1d(n: int, h: float) -> sp.csr_matrix:
    """(n, n) central second difference D- D+, first and last rows zero."""
    main = np.full(n, -2.0 / h**2)
    off = np.full(n - 1, 1.0 / h**2)
    lower, upper = off.copy(), off.copy()
    main[[0, -1]] = 0.0
    upper[0] = 0.0  # row 0
    lower[-1] = 0.0  # row n-1
    return sp.diags([lower, main, upper], [-1, 0, 1], shape=(n, n), format="csr")


def tangent_1d(n: int, h: float, backward: bool = False) -> sp.csr_matrix:
    """(n, n) forward difference with the backward one on the last row (the tangents of the normal).

    ``backward=True``: the mirror image, backward difference with the forward one on the first row.
    """
    main = np.full(n, -1.0 / h)
    upper = np.full(n - 1, 1.0 / h)
    lower = np.zeros(n - 1)
    main[-1] = 1.0 / h
    lower[-1] = -1.0 / h
    if backward:  # the reversal J A J of the forward operator, negated: row k of it is row n - 1 - k mirrored
        return -sp.diags([upper[::-1], main[::-1], lower[::-1]], [-1, 0, 1], shape=(n, n), format="csr")
    return sp.diags([lower, main, upper], [-1, 0, 1], shape=(n, n), format="csr")


def tangents(M: int, N: int, h1: float, h2: float, backward: bool = False) -> tuple[sp.csr_matrix, sp.csr_matrix]:
    """The sparse tangent operators T1, T2 (MN, MN): r_1, r_2 at every node as in :func:`node_derivatives`.

    ``backward=True``: backward differences, forward on the first row (:func:`tangent_1d`).
    """
    I1, I2 = sp.identity(M, format="csr"), sp.identity(N, format="csr")
    return (sp.kron(tangent_1d(M, h1, backward), I2, format="csr"),
            sp.kron(I1, tangent_1d(N, h2, backward), format="csr"))


def _mean_1d(n: int) -> sp.csr_matrix:
    """(n, n) mean of a node and the next, last row zero."""
    main, upper = np.full(n, 0.5), np.full(n - 1, 0.5)
    main[-1] = 0.0
    return sp.diags([main, upper], [0, 1], shape=(n, n), format="csr")


def cell_tangents(M: int, N: int, h1: float, h2: float) -> tuple[sp.csr_matrix, sp.csr_matrix]:
    """The mean tangents of the cell whose lower-left corner is each node (MN, MN), centred at the cell centre.

    ``(D1+ r[m, n] + D1+ r[m, n + 1]) / 2`` and ``(D2+ r[m, n] + D2+ r[m + 1, n]) / 2``; zero rows where the
    cell leaves the grid.
    """
    return (sp.kron(forward_1d(M, h1), _mean_1d(N), format="csr"),
            sp.kron(_mean_1d(M), forward_1d(N, h2), format="csr"))


def operators(M: int, N: int, h1: float, h2: float) -> dict[str, sp.csr_matrix]:
    """The sparse operators D1, D2 (forward), D11, D22 (central), D12 (= D1+ D2+), each (MN, MN)."""
    I1, I2 = sp.identity(M, format="csr"), sp.identity(N, format="csr")
    D1 = sp.kron(forward_1d(M, h1), I2, format="csr")
    D2 = sp.kron(I1, forward_1d(N, h2), format="csr")
    D11 = sp.kron(central2_1d(M, h1), I2, format="csr")
    D22 = sp.kron(I1, central2_1d(N, h2), format="csr")
    D12 = (D1 @ D2).tocsr()
    out = {"D1": D1, "D2": D2, "D11": D11, "D22": D22, "D12": D12}
    for A in out.values():
        A.eliminate_zeros()
        A.sort_indices()
    return out


def valid_rows(M: int, N: int) -> dict[str, np.ndarray]:
    """(M, N) masks of the nodes where each operator of eq. (17) is defined (non-zero row)."""
    m = np.arange(M)[:, None]
    n = np.arange(N)[None, :]
    f1 = np.broadcast_to(m < M - 1, (M, N))
    f2 = np.broadcast_to(n < N - 1, (M, N))
    c1 = np.broadcast_to((m > 0) & (m < M - 1), (M, N))
    c2 = np.broadcast_to((n > 0) & (n < N - 1), (M, N))
    return {"D1": f1, "D2": f2, "D11": c1, "D22": c2, "D12": f1 & f2}


def _first(u: np.ndarray, axis: int, h: float) -> np.ndarray:
    """Forward difference along ``axis``, backward at the last node."""
    d = np.diff(u, axis=axis) / h
    last = np.take(d, [-1], axis=axis)
    return np.concatenate([d, last], axis=axis)


def _second(u: np.ndarray, axis: int, h: float) -> np.ndarray:
    """Central second difference, copied from the nearest interior node at the two ends."""
    d = np.diff(u, n=2, axis=axis) / h**2
    return np.concatenate([np.take(d, [0], axis=axis), d, np.take(d, [-1], axis=axis)], axis=axis)


def node_derivatives(R: np.ndarray, h1: float, h2: float) -> tuple[np.ndarray, np.ndarray]:
    """Difference approximations of r_i and r_ij at every node.

    Parameters
    ----------
    R : array (M, N, 3)
        Node positions.

    Returns
    -------
    dr : array (3, 2, M, N)
        ``D1+ r``, ``D2+ r`` (eq. 18); backward differences on the last row/column.
    ddr : array (3, 2, 2, M, N)
        ``D11 r``, ``D12+ r``, ``D22 r`` (eq. 19); at the edges where the
        central difference leaves the grid, the value of the nearest interior
        node (first order there), and D12 with backward differences where
        the forward ones leave the grid.

    These agree with the sparse operators wherever those are defined, so
    alpha and beta (eq. 18-19) computed from them enter K unchanged.
    """
    R = np.moveaxis(np.asarray(R, float), -1, 0)  # (3, M, N)
    r1 = _first(R, 1, h1)
    r2 = _first(R, 2, h2)
    r11 = _second(R, 1, h1)
    r22 = _second(R, 2, h2)
    r12 = _first(r1, 2, h2)  # D2 (D1 r): forward-forward inside, one-sided at the far edges
    dr = np.stack([r1, r2], axis=1)
    ddr = np.stack([np.stack([r11, r12], axis=1), np.stack([r12, r22], axis=1)], axis=1)
    return dr, ddr


def node_tensors(R: np.ndarray, h1: float, h2: float) -> tuple[np.ndarray, np.ndarray]:
    """G (eq. 18) and B (eq. 19) at every node from positions R (M, N, 3): two (2, 2, M, N) arrays."""
    dr, ddr = node_derivatives(R, h1, h2)
    return tensors.metric(dr), tensors.curvature(ddr, tensors.normal(dr))


def _midpoints(w: np.ndarray, axis: int) -> np.ndarray:
    """The mean of neighbouring nodes along ``axis``, the last one kept (it stands where no term is)."""
    out = np.array(w, float)
    lo, hi = [slice(None)] * w.ndim, [slice(None)] * w.ndim
    lo[axis], hi[axis] = slice(None, -1), slice(1, None)
    out[tuple(lo)] = 0.5 * (w[tuple(lo)] + w[tuple(hi)])
    return out


def centred_tensor(material, name: str, sheet, at: str | None = None) -> np.ndarray:
    """Weight tensor ``name`` of a Material where the difference terms it weighs are centred, (2, 2, M, N),
    indexed by the node whose row the term is.

    Stretching weights (eta, alpha): component 11 at (m + 1/2, n), where G11 = D1+ r . D1+ r stands; 22 at
    (m, n + 1/2); 12 at the cell centre (m + 1/2, n + 1/2), where the energy's shear term stands
    (:mod:`fdmodel.energy`). Bending weights (xi, beta): 11 and 22 at the node (D11, D22 are central), 12 at
    the cell centre (D12+). ``at`` ("node" or "cell") puts every component at one place instead. A callable is
    evaluated there; node values are averaged there (the mean of two or four nodes, second order), so that a
    weight varying over the sheet keeps each term a midpoint rule and FD second order (the order of a node's
    own weight half a cell from its term is one). A centre past the last row or column is no term's: the
    node itself stands there.
    """
    M, N = sheet.nodes
    h1, h2 = sheet.h
    a1, a2 = sheet.coordinates()
    s1 = a1 + np.where(np.arange(M) < M - 1, 0.5 * h1, 0.0)[:, None]
    s2 = a2 + np.where(np.arange(N) < N - 1, 0.5 * h2, 0.0)[None, :]
    places = {"node": ((a1, a2), lambda w: w), "d1": ((s1, a2), lambda w: _midpoints(w, 2)),
              "d2": ((a1, s2), lambda w: _midpoints(w, 3)),
              "cell": ((s1, s2), lambda w: _midpoints(_midpoints(w, 2), 3))}
    if at is not None:
        layout = ((at, at), (at, at))
    elif name in STRETCHING:
        layout = (("d1", "cell"), ("cell", "d2"))
    else:
        layout = (("node", "cell"), ("cell", "node"))
    values, out = {}, np.empty((2, 2, M, N))
    for i in range(2):
        for j in range(2):
            key = layout[i][j]
            if key not in values:
                values[key] = material.tensor_at(name, (M, N), *places[key])
            out[i, j] = values[key][i, j]
    return out
