"""The contact points of a sheet: where it may touch an obstacle, and how close it is.

The sheet touches an obstacle at a fixed set of material points a_p (parameter coordinates): a sub-grid of the
parameter rectangle with ``samples`` points per cell side, the nodes among them (:class:`ContactPoints`). Finite
differences take the nodes (samples = 1); finite elements a sub-grid of spacing h / 2 by default, so that the cubic
surface between nodes is covered too. Each point maps to the degrees of freedom by a fixed sparse matrix W (P,
ndof), ``r(a_p) = W X`` (the backend hook ``point_matrix``), and stands for an area A_p (m^2): FD's own node areas
(those of its mass), the trapezoidal rule on FE's sub-grid. Non-penetration is guaranteed at the contact points:
between them the surface may cut a curved obstacle by its chord's sag, about h^2 / (8 R) for cells of side h over a
radius R (``Contact(samples=2)`` quarters it).

:func:`contact_points` builds them once per model; :func:`require_outside` checks a state against the scene's
analytic obstacles (every kind: :mod:`deformable.contact.clearance`).
"""

from __future__ import annotations

import weakref

import numpy as np
import scipy.sparse as sp

from ..algebra.patterns import BlockPattern, FixedPattern
from ..limits import check_memory

__all__ = ["ContactPoints", "subgrid", "contact_points", "require_outside"]


#: bytes a contact point takes, rounded up (:func:`subgrid`)
POINT_BYTES = 2e3


# -- contact points ---------------------------------------------------------------------
def subgrid(sheet, samples: int):
    """The parameter points of a sub-grid with ``samples`` points per cell side (1: the nodes).

    Returns
    -------
    a : array (P, 2)
        The points (m), row-major on the (m, n) sub-grid.
    area : array (P,)
        The area each stands for (the trapezoidal rule, m^2), summing to L1 L2.
    shape : (m, n)
    """
    (L1, L2), (M, N) = sheet.size, sheet.nodes
    m, n = samples * (M - 1) + 1, samples * (N - 1) + 1
    # the memory check every grid gets, before anything is allocated: the points, their area and their matrices
    # took 0.2 kB (FD) and 0.9 kB (FE) a point (tracemalloc, a 12 x 12 floor, 4 and 8 samples); 2 kB with the
    # barrier's arrays
    check_memory((m, n), POINT_BYTES, f"{m} x {n} contact points ({samples} per cell side on a {M}x{N} grid)")
    w1, w2 = np.full(m, L1 / (m - 1)), np.full(n, L2 / (n - 1))
    w1[[0, -1]] *= 0.5
    w2[[0, -1]] *= 0.5
    A1, A2 = np.meshgrid(np.linspace(0.0, L1, m), np.linspace(0.0, L2, n), indexing="ij")
    return np.stack([A1.ravel(), A2.ravel()], axis=1), np.outer(w1, w2).ravel(), (m, n)


class ContactPoints:
    """The sheet's contact points: a sub-grid of the parameter rectangle, mapped to the degrees of freedom.

    Parameters
    ----------
    model : Backend (with the hook ``point_matrix``)
    samples : int
        Points per cell side (1: the nodes).

    Attributes
    ----------
    a : array (P, 2)
        Parameter coordinates (m).
    W : sparse (P, ndof)
        ``r(a_p) = W @ X``.
    owner : int array (P,)
        The degree of freedom whose own point each is (W's row is that one alone, with weight 1: FD's nodes, FE's at
        the nodes), else -1.
    area : array (P,)
        The area each point stands for (m^2): the backend's own weights where the contact points are its own points
        (FD's nodes: h1 h2, times the control-area weights when chosen), else the trapezoidal rule on the sub-grid
        (summing to L1 L2).
    """

    def __init__(self, model, samples: int):
        self.samples = samples
        self.a, self.area, self.shape = subgrid(model.scene.sheet, samples)
        own = np.stack([np.ravel(p) for p in model.points], axis=1)
        if own.shape == self.a.shape and np.allclose(own, self.a, rtol=0, atol=1e-12 * max(model.scene.sheet.size)):
            # the backend's own points (FD: the nodes): its own weights, so that each stands for what its mass does
            density = np.zeros(model.points[0].shape + (3,))
            density[..., 0] = 1.0
            self.area = model.integrate(density)[np.asarray(model.value_dofs), 0]
        W = sp.csr_matrix(model.point_matrix(self.a))
        # weights at round-off of zero (a neighbour's bilinear weight at a node, 4e-16) are zeros: a point at a node is
        # that node's alone (ContactPotential.relax needs to know)
        W.data[np.abs(W.data) <= 1e-12 * np.max(np.abs(W.data), initial=0.0)] = 0.0
        W.eliminate_zeros()
        self.W = W
        single = np.flatnonzero(np.diff(W.indptr) == 1)  # rows of one weight; weight 1: the point is its dof's own
        first = W.indptr[single]
        one = np.abs(W.data[first] - 1.0) <= 1e-12
        self.owner = np.full(W.shape[0], -1, np.int64)
        self.owner[single[one]] = W.indices[first[one]]
        self.WT = self.W.T.tocsr()
        self.n, self.P = model.ndof, self.a.shape[0]
        self._gram = None

    def positions(self, X: np.ndarray) -> np.ndarray:
        """The contact points' positions (P, 3) of a state X (ndof, 3) (m)."""
        return self.W @ X

    def _build_gram(self):
        """The pattern of W^T diag(c) W and the (nnz, P) matrix that fills it from c."""
        W = self.W
        counts = np.diff(W.indptr)
        k = int(counts.max())
        cols = np.full((self.P, k), -1, np.int64)
        vals = np.zeros((self.P, k))
        pos = np.arange(W.nnz) - np.repeat(W.indptr[:-1], counts)
        rows = np.repeat(np.arange(self.P), counts)
        cols[rows, pos], vals[rows, pos] = W.indices, W.data
        ok = (cols[:, :, None] >= 0) & (cols[:, None, :] >= 0)
        r = np.broadcast_to(cols[:, :, None], ok.shape)[ok]
        c = np.broadcast_to(cols[:, None, :], ok.shape)[ok]
        v = (vals[:, :, None] * vals[:, None, :])[ok]
        p = np.broadcast_to(np.arange(self.P)[:, None, None], ok.shape)[ok]
        pattern = FixedPattern(r, c, (self.n, self.n))
        fill = sp.csr_matrix((v, (pattern.slot, p)), shape=(pattern.nnz, self.P))
        self._gram = (pattern, fill, BlockPattern(pattern.matrix(np.zeros(pattern.nnz)), self.n))

    def blocks(self, K: np.ndarray) -> sp.csr_matrix:
        """``sum_p W_p^T K_p W_p`` for symmetric 3 x 3 blocks K (P, 3, 3): (3 ndof, 3 ndof), coordinate-blocked.

        On one fixed pattern for every K (the pattern of W^T W in every coordinate block).
        """
        if self._gram is None:
            self._build_gram()
        pattern, fill, block = self._gram
        mats = {(a, b): pattern.matrix(fill @ K[:, a, b]) for a in range(3) for b in range(a, 3)}
        return block.matrix(mats)


_POINTS: weakref.WeakKeyDictionary = weakref.WeakKeyDictionary()


def contact_points(model, samples: int | None = None) -> ContactPoints:
    """The model's contact points (:class:`ContactPoints`), built once per model and sample count.

    ``samples`` None: the scene's ``Contact.samples``, else the backend's own ``contact_samples``.
    """
    if samples is None:
        contact = model.scene.contact
        samples = (contact.samples if contact is not None and contact.samples else None) or model.contact_samples
    cache = _POINTS.setdefault(model, {})
    if samples not in cache:
        cache[samples] = ContactPoints(model, samples)
    return cache[samples]


def require_outside(model, X: np.ndarray, what: str = "the state") -> None:
    """Raise a ValueError naming the deepest contact point when one of X (ndof, 3) is not strictly outside every
    analytic obstacle of the scene (the barrier is infinite there: no step can start from such a state); the mesh
    obstacles: :func:`deformable.contact.clearance.require_clear`."""
    r = contact_points(model).positions(np.asarray(X, float))
    for k, obstacle in enumerate(model.scene.obstacles):
        if not obstacle.analytic:
            continue
        d = obstacle.distance(r)
        p = int(np.argmin(d))
        if d[p] <= 0:
            a = contact_points(model).a[p]
            raise ValueError(f"{what}: contact point a = ({a[0]:.4g}, {a[1]:.4g}) m lies {-d[p]:.3g} m inside "
                             f"obstacle {k} ({obstacle.kind}); every contact point must start outside every obstacle")
