r"""The energy (13) of the finite-element surface, with its exact gradient and Hessians.

The "variational" force model uses the gradient of the energy the paper
writes down instead of the force (14) (docs/design.md: the two differ; under
(14) a flat sheet has no linear bending stiffness); the tpbf87 model reports
this energy too. On the bicubic Hermite field (:mod:`femodel.hermite`) the
energy is integrated by the 4 x 4 Gauss rule of :class:`femodel.FEModel`:

    E(X) = sum_{e, q} w_q  sum_ij  eta_ij (G_ij - G0_ij)^2 + xi_ij (B_ij - B0_ij)^2     (eq. 13)

at the Gauss points q of every element e (w_q: Gauss weight times element
area). At a Gauss point r depends on the 48 local degrees of freedom only
through the five vectors ``(r_1, r_2, r_11, r_12, r_22)``,
``v_k = sum_l X_l D_k[l, q]`` with the basis tables ``D_k`` of
:func:`femodel.hermite.basis`: the *slots* of :mod:`deformable.physics.integrand`
(with the normal's tangents equal to the metric's), which gives the
integrand, its gradient p and its Hessian H per point. They are carried to the
element by ``D``: gradient ``g_e[l] = sum_{q,k} D_k[l, q] p_k``, Hessian
``K_e[l, m] = sum_{q,k,k'} D_k[l, q] H_{kk'} D_k'[m, q]``, summed on a fixed
pattern (:class:`deformable.algebra.elements.SymmetricElements` over the 48 = 3 x 16
local degrees of freedom of an element): point Hessians by the compiled
kernel of :mod:`deformable.physics.kernels`, element blocks by two dense products.

Vectors and matrices are coordinate-blocked: flat index ``a * ndof + k`` for
coordinate a of degree of freedom k.
"""

from __future__ import annotations

import numpy as np
import scipy.sparse as sp

from deformable.algebra.elements import SymmetricElements, element_vectors
from deformable.algebra.solvers import one_blas_thread
from deformable.physics.energy import Energy
from deformable.physics.integrand import FE_SLOTS, HESSIANS, for_blocks, slot_tensors

from .hermite import DERIVATIVES, evaluate

__all__ = ["DiscreteEnergy", "HESSIANS", "SLOTS", "slots"]

#: derivative orders (d1, d2) of the five slots: r_1, r_2, r_11, r_12, r_22
SLOTS = DERIVATIVES[1:]
#: the coordinate blocks (a, b), a <= b, of an element Hessian, as a 3 + b
_PAIRS = np.array([3 * a + b for a in range(3) for b in range(a, 3)])
#: elements per block of the Hessian assembly (measured at FE 32 x 32: 16 best, 64 1.5x, 128 1.7x slower)
_BLOCK = 16


def slots(X: np.ndarray, ldofs: np.ndarray, dq: dict) -> np.ndarray:
    """r_1, r_2, r_11, r_12, r_22 at the Gauss points of every element, (E nq, 5, 3)."""
    d = evaluate(X, ldofs, [dq[k] for k in SLOTS])  # (3, 5, E, nq)
    return np.ascontiguousarray(d.transpose(2, 3, 1, 0)).reshape(-1, len(SLOTS), 3)


def gauss_tensors(X: np.ndarray, ldofs: np.ndarray, dq: dict, curvature: bool = True):
    """G (eq. 4) and B (eq. 8) at the Gauss points, (2, 2, E, nq) each (B None without curvature)."""
    E, nq = ldofs.shape[0], dq[SLOTS[0]].shape[1]
    G, B = slot_tensors(slots(X, ldofs, dq), FE_SLOTS, curvature)
    return G.reshape(2, 2, E, nq), None if B is None else B.reshape(2, 2, E, nq)


class DiscreteEnergy:
    """Energy (13) of a bicubic Hermite field by the Gauss rule (module docstring).

    Parameters
    ----------
    ldofs : int array (E, 16)
        Global degrees of freedom of every element.
    ndof : int
    dq : dict (d1, d2) -> (16, nq)
        Shape-function derivatives at the Gauss points (:func:`femodel.hermite.basis`).
    integrand : Integrand or DensityIntegrand
        The energy's integrand at the E nq Gauss points (weights times the Gauss weights and element area;
        rest tensors G0, B0 from :func:`gauss_tensors`).
    """

    def __init__(self, ldofs: np.ndarray, ndof: int, dq: dict, integrand):
        self.ldofs, self.ndof, self.dq = ldofs, ndof, dq
        self.nq = nq = dq[SLOTS[0]].shape[1]
        self.D = np.stack([dq[k] for k in SLOTS]).transpose(2, 0, 1).copy()  # (nq, 5, 16)
        self.Dflat = self.D.reshape(nq * 5, 16)  # rows (q, k)
        self.integrand = integrand
        self._scatter = element_vectors(ldofs, ndof)
        self._pattern = None
        self.DflatT = np.ascontiguousarray(self.Dflat.T)
        # the point Hessian's entries (k a, k' b) of the pairs, [k, pair, k'] in its flat 15 x 15 ...
        k, pair, kp = np.meshgrid(np.arange(5), np.arange(len(_PAIRS)), np.arange(5), indexing="ij")
        self._pair_entries = (3 * k + _PAIRS[pair] // 3) * 15 + 3 * kp + _PAIRS[pair] % 3
        self._gathers = {}  # ... and in a block of Ec elements' point Hessians, by Ec
        # where upper entry (a 16 + l, b 16 + m) of an element sits in D^T T: [l, (pair, m)]
        lu, mu = np.triu_indices(48)
        self._upper_l = lu % 16
        self._upper_pm = np.searchsorted(_PAIRS, 3 * (lu // 16) + mu // 16) * 16 + mu % 16

    @property
    def pattern(self) -> SymmetricElements:
        """Fixed CSR pattern of the coordinate-blocked Hessian (3 ndof, 3 ndof), built on first use."""
        if self._pattern is None:
            ld48 = np.concatenate([a * self.ndof + self.ldofs for a in range(3)], axis=1)  # (E, 48): index a 16 + l
            self._pattern = SymmetricElements(ld48, 3 * self.ndof)
        return self._pattern

    def energy(self, X: np.ndarray) -> Energy:
        """(stretching, bending) parts of E (J), eq. (13) by the Gauss rule."""
        return self.integrand.energy(slots(X, self.ldofs, self.dq))

    def gradient(self, X: np.ndarray) -> np.ndarray:
        """Exact gradient dE/dX, (ndof, 3) (J per unit of the degrees of freedom, i.e. N)."""
        p = self.integrand.gradient(slots(X, self.ldofs, self.dq))  # (E nq, 5, 3)
        E = self.ldofs.shape[0]
        local = self.Dflat.T @ p.reshape(E, self.nq * 5, 3)  # (E, 16, 3)
        return self._scatter @ local.reshape(-1, 3)

    def element_uppers(self, H: np.ndarray) -> np.ndarray:
        """Upper triangles of the element Hessians from point Hessians (Ec, nq, 15, 15): (Ec, 1176).

        Entries in :attr:`pattern`'s order (``numpy.triu_indices(48)``, local index a 16 + l). Only the
        coordinate blocks a <= b are formed, by one gather and two dense products (BLAS): ``T = H D`` per
        point and slot, then ``D^T T`` over all the element's points at once, laid out so that neither
        product needs a transposed copy. Measured at FE 32 x 32 elements: faster than a compiled point-by-
        point projection (40 against 118 ms of CPU per Hessian) because the basis tables D are dense; and
        one Hessian on one thread 45 -> 32 ms against all nine blocks with a transposed copy before each
        product.
        """
        Ec, nq = H.shape[:2]
        P = len(_PAIRS)
        if Ec not in self._gathers:  # H's entry [q, k, (e, pair), k'] in the flat (Ec, nq, 15, 15) array
            e, q = np.arange(Ec), np.arange(nq)
            self._gathers[Ec] = (e[None, None, :, None, None] * nq + q[:, None, None, None, None]) * 225 \
                + self._pair_entries[None, :, None]
        T = np.take(H, self._gathers[Ec]).reshape(nq, 5, Ec * P, 5) @ self.D[:, None]  # [q, k, (e, pair), m]
        KT = self.DflatT @ T.reshape(nq * 5, Ec * P * 16)  # (16, Ec P 16): [l, (e, pair, m)]
        return KT.reshape(16, Ec, P * 16)[self._upper_l, :, self._upper_pm].T

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
        """The Hessian as element upper triangles, (E, 1176), in :attr:`pattern`'s order (local index a 16 + l);
        ``kind`` as :meth:`hessian`."""
        v = slots(X, self.ldofs, self.dq)
        pat, nq, E = self.pattern, self.nq, self.ldofs.shape[0]
        iu = pat.upper
        upper = np.empty((E, iu[0].size))

        def block(lo):  # blocks of elements keep the point and element Hessians in cache
            hi = min(lo + _BLOCK, E)
            pts = slice(lo * nq, hi * nq)
            H = self.integrand.hessian(v[pts], kind, pts).reshape(hi - lo, nq, 15, 15)
            upper[lo:hi] = self.element_uppers(H)

        with one_blas_thread():  # BLAS threads inside the blocks' threads would fight over the cores
            for_blocks(block, range(0, E, _BLOCK))
        return upper
