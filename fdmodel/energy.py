r"""The discrete energy (13) on the FD grid, with its exact gradient and Hessians.

The "variational" force model uses the gradient of the energy the paper writes
down instead of the force (14) (docs/design.md: the two differ; under (14) a
flat sheet has no linear bending stiffness); the tpbf87 model reports this
energy too. The paper defines no FD for it; this one is built from the
paper's differences so that each term of eq. (13) is a second-order
quadrature (the midpoint or the trapezoidal rule at the point where its
stencil is centred)::

    E(r) = sum_nodes [ eta_11 (D1+ r . D1+ r - G0_11)^2 w_D1 + eta_22 (D2+ r . D2+ r - G0_22)^2 w_D2   (eq. 18)
                     + sum_{n' = n_f, n_b} [ (xi_11 / 2) (n' . D11 r - B0'_11)^2 w_D11
                                           + (xi_22 / 2) (n' . D22 r - B0'_22)^2 w_D22 ] ]          (eq. 19)
         + sum_cells [ (eta_12 + eta_21) (a1 . a2 - G0_12)^2 + (xi_12 + xi_21) (n_c . D12+ r - B0_12)^2 ] w_D12

times the cell area h1 h2, with the row weights w of the FD model (its
validity mask and, for the control-area weighting, the trapezoidal share).

- The diagonal terms stand at the nodes. D1+ r is centred at the edge midpoint
  (m + 1/2, n), so G11 is the midpoint rule along a1 (and the row weights the
  trapezoidal rule across); D11 r is centred at the node. The normal is not:
  eq. (19)'s normal n_f, of forward tangents (backward on the last row), is
  n + (h/2)(d1 + d2) n + O(h^2). The bending terms B11, B22 are therefore
  split into two halves of weight xi / 2: one with n_f, one with the normal
  n_b of backward tangents (forward on the first row), n - (h/2)(d1 + d2) n
  + O(h^2). The first-order errors are opposite and cancel in the sum of the
  two squares, so the density is second order, while each half still
  involves the node itself. Each half has its own rest tensor B0' (from its
  own slots: zero force at rest) and, at a clamped edge, the clamp's own
  tangent across the edge (:mod:`fdmodel.clamp`). In the parts below the
  backward half is one more node part, with eta = 0. Measured in the
  ``cross`` study: the cantilever's FD self-convergence of G went from order
  0.94 to 2.04, its FD-FE difference of G from 1.06 to 2.96, with the drawn
  curtain's Newton iterations unchanged (1.98 per step at 32 x 32, 1.97
  before). Only the variational model splits; tpbf87 keeps n_f alone.
  Central tangents would centre the normal too, but they do not depend on
  the node itself and decouple alternate rows: measured on the drawn
  curtain, its Newton matrix turned indefinite next to the drawn corner
  (one negative eigenvalue, a mode of rows m - 1 and m + 1) and the run
  diverged at 0.9 s (docs/design.md).
- The shear and twist terms stand at the cell centres (m + 1/2, n + 1/2),
  where D12+ is centred: G12 = a1 . a2 with the cell's mean tangents
  a1 = (D1+ r[m, n] + D1+ r[m, n + 1]) / 2, a2 likewise, and B12 with the
  normal n_c of those tangents. The node product D1+ r . D2+ r of eq. (18)
  has no common centre (its factors stand at (m + 1/2, n) and (m, n + 1/2)):
  as a quadrature of the shear term it is first order, with an error
  proportional to the strain gradients, which made FD's G converge at
  order 0.8 on the nonlinear clamped plate; the paper, with eta_12 = xi_12 = 0,
  never meets it.

A general energy density. A force model with its own density W(s, b)
(:class:`deformable.physics.EnergyModel`) is integrated on the same parts
with weights per residual: a residual the density couples with no other
stands where its term of eq. (13) stands, with the same weights, so eq. (13)
written as such a model gives the compiled path's energy to round-off
(tests/deformable/physics/test_energy_models.py). Residuals the density
couples must be evaluated at one point with one weight:

- the metric alone (a membrane energy, a Poisson coupling of G11 and G22):
  at the cell centres, from the cells' mean tangents, where G11, G22 and
  G12 are all centred (the midpoint rule: second order);
- the curvature alone: at the nodes, in the two halves of forward and
  backward normals, weighted by the node's control area, B12 from D12+ (its
  term stands half a cell away: first order in the coupling);
- metric and curvature together: at the nodes with the paper's eq. (18)-(19)
  and the control area (the metric terms are then first order at free
  edges).

Each part is a set of points (nodes, cells) at which the integrand of
:mod:`deformable.physics.integrand` depends on a few *slot* vectors, each a
difference of the positions: :class:`SlotMap` computes them (one sparse
product, plus the clamp's affine part) and carries the integrand's gradient
back (its transpose). Every slot at node k (or at the cell whose lower-left
corner is k) combines the positions of at most six nodes, the stencil
(m, n), (m + 1, n), (m - 1, n), (m, n + 1), (m, n - 1), (m + 1, n + 1): the
Hessian is assembled node by node as an 18 x 18 block (6 nodes x 3
coordinates) ``C_k^T H_k C_k`` from the point Hessians H_k and the stencil
coefficients C_k of all parts, summed on one fixed pattern
(:class:`deformable.algebra.elements.SymmetricElements`) by the compiled kernels of
:mod:`deformable.physics.kernels`: no sparse-sparse product per call.
Stencil positions outside the grid carry zero coefficients (the natural
boundary rule) and point at the node itself.

Vectors are laid out coordinate by coordinate: flat index ``a * ndof + k`` for
coordinate a of node k.
"""

from __future__ import annotations

from typing import Sequence

import numpy as np
import scipy.sparse as sp

from deformable.algebra.elements import SymmetricElements
from deformable.physics.energy import Energy
from deformable.physics.integrand import HESSIANS, Integrand, slot_tensors

__all__ = ["DiscreteEnergy", "SlotMap", "HESSIANS", "STENCIL"]

#: node offsets (dm, dn) of the stencil of a node's slots
STENCIL = ((0, 0), (1, 0), (-1, 0), (0, 1), (0, -1), (1, 1))


class SlotMap:
    """Slot vectors at every node (or cell) of the grid as differences of the positions, and their stencils.

    Parameters
    ----------
    rows : sequence of sparse (MN, MN)
        One operator per slot, in the order of ``layout``'s positions.
    shape : (M, N)
    layout : dict
        Slot name -> position (:data:`deformable.physics.integrand.FD_SLOTS` or ``FE_SLOTS``).
    offset : array (S, MN, 3), optional
        The affine part of the slots (the clamp's ghost rows, :mod:`fdmodel.clamp`); zero by default.

    Attributes
    ----------
    L : sparse (S MN, MN)
        Slot s at point k is row ``s MN + k`` applied to the positions.
    stencil : int array (MN, 6)
        The stencil nodes of every point (the node itself where the stencil leaves the grid).
    C : array (MN, S, 6)
        The coefficient of stencil node p in slot s at point k.
    """

    def __init__(self, rows: Sequence[sp.spmatrix], shape: tuple[int, int], layout: dict,
                 offset: np.ndarray | None = None):
        M, N = shape
        self.shape, self.layout = shape, dict(layout)
        self.n = n = M * N
        self.S = S = len(rows)
        self.offset = None if offset is None else np.ascontiguousarray(offset.transpose(1, 0, 2))  # (MN, S, 3)
        self.L = sp.vstack(list(rows), format="csr")
        self.LT = self.L.T.tocsr()  # the adjoint's own CSR (a transposed view would be converted at every call)
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
        code = 3 * (cm - m[node] + 1) + ck - k[node] + 1
        p = position[np.clip(code, 0, 8)]
        if np.any((np.abs(cm - m[node]) > 1) | (np.abs(ck - k[node]) > 1) | (p < 0)):
            raise ValueError("a slot operator reaches outside the six-node stencil of its point")
        self.C = np.zeros((n, S, len(STENCIL)))
        np.add.at(self.C, (node, slot, p), coo.data)

    def __call__(self, X: np.ndarray, offset: np.ndarray | None = None) -> np.ndarray:
        """The slot vectors at every point, (MN, S, 3): ``L X`` plus the offset (``offset`` (S, MN, 3)
        replaces the map's own, e.g. by the ghost rows of the rest shape)."""
        v = (self.L @ X).reshape(self.S, self.n, 3).transpose(1, 0, 2)
        off = self.offset if offset is None else offset.transpose(1, 0, 2)
        return v if off is None else v + off

    def adjoint(self, p: np.ndarray) -> np.ndarray:
        """The nodal vector (MN, 3) of slot covectors p (MN, S, 3): L^T p."""
        return self.LT @ p.transpose(1, 0, 2).reshape(-1, 3)

    def tensors(self, X: np.ndarray, offset: np.ndarray | None = None) -> tuple[np.ndarray, np.ndarray]:
        """G and B of the slots at every point, (2, 2, M, N) each (zero where a difference is undefined)."""
        G, B = slot_tensors(self(X, offset), self.layout)
        return G.reshape(2, 2, *self.shape), B.reshape(2, 2, *self.shape)

class DiscreteEnergy:
    """Energy (13) of an FD node grid as a function of the positions: a sum of parts (module docstring).

    Parameters
    ----------
    parts : sequence of (SlotMap, Integrand)
        The points of each part, and eq. (13)'s integrand there (weights times the row weights and the
        cell area, rest tensors of the same slots).
    """

    def __init__(self, parts: Sequence[tuple[SlotMap, Integrand]]):
        self.parts = list(parts)
        self.n = n = self.parts[0][0].n
        self._ldofs = np.concatenate([a * n + self.parts[0][0].stencil for a in range(3)], axis=1)  # a 6 + p
        for slots, _ in self.parts:
            if not np.array_equal(slots.stencil, self.parts[0][0].stencil):
                raise ValueError("the parts of the FD energy must share the node stencils")
        self._pattern = None
        self._slots = None  # (X, the parts' slot vectors) of the last state asked about

    @property
    def pattern(self) -> SymmetricElements:
        """The fixed pattern of the coordinate-blocked Hessian (3 ndof, 3 ndof), built on first use."""
        if self._pattern is None:
            self._pattern = SymmetricElements(self._ldofs, 3 * self.n)
        return self._pattern

    def slots(self, X: np.ndarray) -> list:
        """Every part's slot vectors at X, kept for the next call at the same X (a line search asks for the energy
        and the gradient of one point)."""
        if self._slots is None or not np.array_equal(self._slots[0], X):
            self._slots = (np.array(X, float), [slots(X) for slots, _ in self.parts])
        return self._slots[1]

    def energy(self, X: np.ndarray) -> Energy:
        """(stretching, bending) parts of E (J)."""
        parts = [w.energy(v) for (_, w), v in zip(self.parts, self.slots(X))]
        return Energy(sum(e.stretching for e in parts), sum(e.bending for e in parts))

    def gradient(self, X: np.ndarray) -> np.ndarray:
        """Exact gradient dE/dX, (ndof, 3) (N)."""
        return sum(slots.adjoint(w.gradient(v)) for (slots, w), v in zip(self.parts, self.slots(X)))

    def hessian(self, X: np.ndarray, kind: str = "newton") -> sp.csr_matrix:
        """Hessian (3 ndof, 3 ndof), coordinate-blocked, on a fixed pattern.

        ``kind``: "newton" (exact; may be indefinite, e.g. under compression),
        "gauss-newton" (``2 J^T diag(c) J``, positive semi-definite), "definite"
        or "projected" (:mod:`deformable.physics.integrand`).
        """
        pat = self.pattern
        return pat.matrix(pat.collect(self.hessian_uppers(X, kind)))

    def elements(self, X: np.ndarray, kind: str = "newton"):
        """The Hessian as element upper triangles with their pattern: (:meth:`hessian_uppers`, :attr:`pattern`)."""
        return self.hessian_uppers(X, kind), self.pattern

    def hessian_uppers(self, X: np.ndarray, kind: str = "newton") -> np.ndarray:
        """The Hessian as element upper triangles, (MN, 171): node k's element is its stencil's 6 nodes x 3
        coordinates (local index a 6 + p), entries in :attr:`pattern`'s order; ``kind`` as :meth:`hessian`."""
        pat, n = self.pattern, self.n  # an unknown kind: InputError from the integrand
        upper = np.zeros((n, pat.upper[0].size))
        every = np.arange(n)
        for (slots, w), v in zip(self.parts, self.slots(X)):
            w.add_element_hessians(v, kind, slots.C, every, every, upper)
        return upper
