r"""The reflection clamp of the FD grid: a ghost row outside every clamped edge.

A :class:`deformable.Clamp` holds an edge and its tangent plane. The paper
defines no clamp; a two-row clamp (hold the edge row and the next one)
fixes the position of the row at a1 = h instead of the slope at a1 = 0, which
moves the clamped line by O(h): first order (docs/design.md, "Findings").

The standard second-order closure is a ghost row (the reflection used for the
clamped beam and plate since Collatz): for the edge a1 = 0 the node row m = -1
outside the sheet is eliminated by the slope condition, the central
difference ``(r[1] - r[-1]) / (2 h1) = t``, t the clamp's tangent r_1 at the
edge (taken from the sheet's initial shape, the constraint reference):

    r[-1] = r[1] - 2 h1 t                              (an affine function of r[1] and t)

Only the edge row is held; the row m = 1 is free. The ghost enters the slots
of eq. (18)-(19) at the edge nodes, and nowhere else:

- the second difference across the edge, D11 r[0] = (2 r[1] - 2 r[0] - 2 h1 t) / h1^2;
- the normal's tangent across the edge, the central difference (r[1] - r[-1]) / (2 h1) = t, so
  the normal at a clamped node is the clamp's own (t x r_2, the edge being held).

So B11 at the edge, ``n . D11 r[0] = 2 n . (r[1] - r[0]) / h1^2``, measures the normal component of
the first free row only: the clamp holds the slope, not the in-plane stretch at the edge (which the
energy leaves free). The other edges alike: a1 = L1 with the ghost ``r[M] = r[M - 2] + 2 h1 t``;
a2 = 0 and a2 = L2 along a2 with t = r_2.

The slots become affine in the positions, ``slots = L X + offset``: the energy's gradient is
``L^T p`` and its Hessian ``C^T H C`` on the same six-node stencils as before (the ghost's terms
fall on the node itself and the first free row), so nothing changes in
:mod:`fdmodel.energy` but the offset. The row of D11 at the clamped edge stands for half a cell
along a1 (the trapezoidal rule, and, with it, exactly the classical 13-point plate stencil with
the reflected ghost in the row next to the edge: (7 w1 - 4 w2 + w3) / h^4 for a clamped beam).

The paper's strength matrix K(r) (eq. 20) acts alike on x, y and z with a constant pattern and has
no place for the affine term ``t`` itself: under tpbf87 and frozen K(r) is built on the ghost's
operators and the affine part becomes a force, ``f = h1 h2 sum_k D_k^T diag(w_k beta_kk) c_k`` over the
ghost rows' D11, D22 (``FDModel._clamp_force``), which :meth:`FDModel.load` subtracts, so that the
semi-implicit step K(r_t) r_{t+dt} = F of eq. (24)-(26) holds the slope too (the frozen energy is
``R^T K R / 2 + f . R + const``). The two-row clamp, held before, gave the frozen clamped plate's
centre 6.2 % off at 65 x 65 nodes, order 1.00; the ghost rows give 0.21 %, order 2.
"""

from __future__ import annotations

import numpy as np
import scipy.sparse as sp

from deformable.geometry.surfaces import as_surface

__all__ = ["GhostRows"]

#: for each edge: (slot of the second difference across it, slot of the normal's tangent across it,
#: parameter derivative of the clamp's tangent, sign of the ghost's offset)
_ACROSS = {"left": ("D11", "T1", "r1", -1.0), "right": ("D11", "T1", "r1", 1.0),
           "bottom": ("D22", "T2", "r2", -1.0), "top": ("D22", "T2", "r2", 1.0)}


class GhostRows:
    """The ghost rows of a sheet's clamped edges (module docstring).

    Parameters
    ----------
    sheet : deformable.Sheet
    edges : sequence of edge names
        The clamped edges ("left", "right", "bottom", "top").

    Attributes
    ----------
    edges : tuple of str
    rows : dict slot name -> bool array (M, N)
        The nodes whose second difference (D11 or D22) the ghost defines.
    """

    def __init__(self, sheet, edges):
        self.sheet = sheet
        self.edges = tuple(dict.fromkeys(edges))
        self.rows = {"D11": np.zeros(sheet.nodes, bool), "D22": np.zeros(sheet.nodes, bool)}
        for e in self.edges:
            self.rows[_ACROSS[e][0]] |= sheet.edge_nodes(e)

    def __bool__(self) -> bool:
        return bool(self.edges)

    def _edge(self, name: str):
        """Flat indices of the edge's nodes and of the first free row next to them, and the spacing across."""
        M, N = self.sheet.nodes
        idx = np.arange(M * N).reshape(M, N)
        edge = self.sheet.edge(name)
        if edge.axis == 1:
            idx = idx.T
        inward = 1 if edge.side == 0 else -2
        return idx[edge.side], idx[inward], self.sheet.h[edge.axis]

    def operators(self, ops: dict, T: tuple) -> tuple[dict, tuple]:
        """Copies of the difference operators (D11, D22) and the normal's tangents (T1, T2) with the ghost's rows.

        At a clamped node the second difference across the edge is ``2 (r_next - r) / h^2`` (its affine part
        is :meth:`offset`) and the tangent across the edge has no linear part (it is the clamp's t).
        """
        ops = dict(ops)
        tangents = {"T1": T[0], "T2": T[1]}
        for e in self.edges:
            d, tn, _, _ = _ACROSS[e]
            nodes, nxt, h = self._edge(e)
            n = ops[d].shape[0]
            keep = np.ones(n)
            keep[nodes] = 0.0
            ghost = sp.csr_matrix((np.concatenate([np.full(nodes.size, -2.0 / h**2), np.full(nodes.size, 2.0 / h**2)]),
                                   (np.concatenate([nodes, nodes]), np.concatenate([nodes, nxt]))), shape=(n, n))
            ops[d] = (sp.diags(keep) @ ops[d] + ghost).tocsr()
            tangents[tn] = (sp.diags(keep) @ tangents[tn]).tocsr()
        for A in list(ops.values()) + list(tangents.values()):
            A.eliminate_zeros()
            A.sort_indices()
        return ops, (tangents["T1"], tangents["T2"])

    def offset(self, surface, slots: tuple[str, ...]) -> np.ndarray:
        """The affine part of the slots at the clamped nodes for the clamp tangent of ``surface``: (S, M N, 3).

        ``slots`` names the operator of each slot (e.g. ("D1", "D2", "T1", "T2", "D11", "D12", "D22")).
        """
        s = as_surface(surface)
        a1, a2 = (c.ravel() for c in self.sheet.coordinates())
        out = np.zeros((len(slots), a1.size, 3))
        for e in self.edges:
            d, tn, deriv, sign = _ACROSS[e]
            nodes, _, h = self._edge(e)
            t = getattr(s, deriv)(a1[nodes], a2[nodes])
            out[slots.index(d), nodes] += sign * 2.0 * t / h
            out[slots.index(tn), nodes] += t
        return out

    @staticmethod
    def force(ops: dict, row_weight: dict, area: float, beta: np.ndarray, offset: np.ndarray) -> np.ndarray:
        """The affine part of the ghost rows under K(r) as a force: ``f = h1 h2 sum_k D_k^T diag(w_k beta_kk) c_k``
        over the slots D11, D22 (``ops`` the ghost's operators, ``offset`` (2, M N, 3) their :meth:`offset`),
        (M N, 3) (N).

        The bending rows of K(r) R + f are those of the clamped energy sum w beta (D_g r + c) . (D_g r + c) / 2:
        the frozen model's gradient is K R + f, and ``FDModel.load`` carries -f, so that the semi-implicit step
        of eq. (24), K(r_t) r_{t+dt} = F, holds the clamp's slope at second order (module docstring).
        """
        return sum(area * (ops[k].T @ ((row_weight[k] * beta[i, i]).ravel()[:, None] * offset[i]))
                   for i, k in enumerate(("D11", "D22")))

    @staticmethod
    def constant(row_weight: dict, area: float, beta: np.ndarray, offset: np.ndarray) -> float:
        """The clamped energy's constant ``h1 h2 sum w beta c . c / 2`` (J) (:meth:`force`)."""
        return float(sum(0.5 * area * np.sum((row_weight[k] * beta[i, i]).ravel()[:, None] * offset[i] ** 2)
                         for i, k in enumerate(("D11", "D22"))))
