"""Sparse matrices on fixed patterns: built once, refilled every step.

Every matrix the time stepper factorises (the strength matrix K(r) of eq. (20), the step matrix A_t of eq. (25), the
Hessians of the energy (13)) keeps its sparsity pattern for a whole run while its values change. The pattern, and
where each contribution lands in the data array, is computed once from the contributions' coordinates
(:class:`FixedPattern`); a refill is one gather or one sparse mat-vec, never a sparse-sparse product or a slice.

- :class:`FixedPattern`: the CSR pattern of a list of (row, column) contributions and the slot of each;
- :class:`BlockPattern`: a coordinate-blocked (3 n, 3 n) matrix of nine n x n blocks on one pattern;
- element matrices of a symmetric operator: :mod:`deformable.algebra.elements`;
- the free and held blocks of a Newton or step matrix: :mod:`deformable.algebra.reduced`.
"""

from __future__ import annotations

import numpy as np
import scipy.sparse as sp

__all__ = ["FixedPattern", "BlockPattern", "canonical", "same_pattern", "coordinates"]


def canonical(A) -> sp.csr_matrix:
    """A as CSR with sorted indices and no duplicates."""
    A = sp.csr_matrix(A)
    A.sum_duplicates()
    A.sort_indices()
    return A


def same_pattern(A, indptr: np.ndarray, indices: np.ndarray) -> bool:
    """Whether compressed matrix A has this indptr and indices: at once when they are the very arrays (a
    :class:`FixedPattern`'s matrices keep them), else compared entry by entry."""
    if A.indptr is indptr and A.indices is indices:
        return True
    return np.array_equal(A.indptr, indptr) and np.array_equal(A.indices, indices)


def coordinates(A: sp.csr_matrix) -> tuple[np.ndarray, np.ndarray]:
    """Row and column of every stored entry of a CSR matrix."""
    rows = np.repeat(np.arange(A.shape[0], dtype=np.int64), np.diff(A.indptr))
    return rows, A.indices.astype(np.int64)


class FixedPattern:
    """The CSR pattern of a set of contributions (rows[k], cols[k]) to an (n, m) matrix.

    Attributes
    ----------
    indptr, indices : int32 arrays
        The canonical CSR pattern (sorted, one entry per distinct coordinate); :meth:`matrix` hands back
        csr_matrices that share them, so a caller can check by identity that the pattern did not change.
    nnz : int
    slot : int array (contributions,)
        Position in the data array that contribution k adds to.
    """

    def __init__(self, rows, cols, shape: tuple[int, int]):
        rows, cols = np.asarray(rows, np.int64), np.asarray(cols, np.int64)
        self.shape = tuple(shape)
        ukeys, self.slot = np.unique(rows * shape[1] + cols, return_inverse=True)
        self.slot = self.slot.ravel()
        self.indices = (ukeys % shape[1]).astype(np.int32)
        self.indptr = np.concatenate([[0], np.cumsum(np.bincount(ukeys // shape[1], minlength=shape[0]))]
                                     ).astype(np.int32)
        self.nnz = int(ukeys.size)
        self._scatter = None

    @property
    def scatter(self) -> sp.csr_matrix:
        """(nnz, contributions) 0/1 matrix: ``scatter @ values`` is the data array."""
        if self._scatter is None:
            k = self.slot.size
            self._scatter = sp.csr_matrix((np.ones(k), (self.slot, np.arange(k))), shape=(self.nnz, k))
        return self._scatter

    def data(self, values: np.ndarray) -> np.ndarray:
        """The data array of the sum of the contributions with these values, (nnz,)."""
        return np.bincount(self.slot, weights=values, minlength=self.nnz)

    def matrix(self, data: np.ndarray) -> sp.csr_matrix:
        """The csr_matrix with this data on the fixed pattern (canonical: sorted, no duplicates)."""
        A = sp.csr_matrix((data, self.indices, self.indptr), shape=self.shape, copy=False)
        A.indices, A.indptr = self.indices, self.indptr  # scipy may hand back views; keep the very arrays
        A.has_canonical_format = True
        return A


class BlockPattern:
    """The fixed pattern of a symmetric 3 x 3 block matrix whose blocks share one scalar pattern.

    :meth:`matrix` takes the six blocks (a, b), a <= b, each on S's very pattern, and returns the coordinate-blocked
    (3 n, 3 n) matrix (index a n + k) on one fixed pattern.

    Parameters
    ----------
    S : sparse (n, n)
        The scalar pattern every block has (e.g. the one ``density_matrix`` returns).
    n : int
        The size of S (each block is n x n).
    """

    def __init__(self, S: sp.csr_matrix, n: int):
        S = sp.csr_matrix(S)
        self.indptr, self.indices = S.indptr.copy(), S.indices.copy()
        r = np.repeat(np.arange(n), np.diff(S.indptr))
        c = S.indices
        order = [(a, b) for a in range(3) for b in range(3)]
        self.pattern = FixedPattern(np.concatenate([a * n + r for a, _ in order]),
                                    np.concatenate([b * n + c for _, b in order]), (3 * n, 3 * n))
        self.order = [(min(a, b), max(a, b)) for a, b in order]

    def matrix(self, blocks: dict) -> sp.csr_matrix:
        for S in blocks.values():
            if not same_pattern(S, self.indptr, self.indices):
                raise ValueError("a block changed its sparsity pattern between calls")
        return self.pattern.matrix(self.pattern.data(np.concatenate([blocks[ab].data for ab in self.order])))
