"""The free and held blocks of ``A = K + c_m M + c_c C``, refilled by precomputed gathers.

Every system the project solves is the free-free block of a matrix on a fixed pattern, the free-held block carrying
the prescribed values to the right-hand side. :class:`ReducedSystem` builds the union pattern of the varying
matrices (K, the strength matrix of eq. (20), and the springs', contact's and wind's) and of the constant M and C
once, and splits any refill into its blocks by gathers. The semi-implicit step of eq. (22)-(27) takes both blocks
from here; Newton's matrices are :class:`deformable.algebra.upper.FreeUpper`'s.
"""

from __future__ import annotations

import numpy as np
import scipy.sparse as sp

from .patterns import FixedPattern, canonical, coordinates, same_pattern

__all__ = ["ReducedSystem"]


class ReducedSystem:
    """A = K + K_2 + ... + c_m M + c_c C on a fixed pattern, split into free/held blocks by gathers; all symmetric.

    Parameters
    ----------
    K, M, C : sparse (n, n)
        K's pattern must stay the same between refills (:meth:`data` checks it).
    cm, cc : float
        Multipliers of M and C.
    fixed_sets : list of int arrays
        One block split per set of held degrees of freedom.
    extra : sequence of sparse (n, n)
        Further varying matrices with fixed patterns (the springs' Hessian, the wind's damping), refilled with K by
        :meth:`data`.
    """

    def __init__(self, K, M, C, cm: float, cc: float, fixed_sets, extra=()):
        n = K.shape[0]
        self.n = n
        varying = [canonical(A) for A in (K, *extra)]
        M, C = canonical(M), canonical(C)
        parts = [coordinates(A) for A in (*varying, M, C)]
        self.pattern = FixedPattern(np.concatenate([p[0] for p in parts]), np.concatenate([p[1] for p in parts]),
                                    (n, n))
        self.rows, self.cols = coordinates(self.pattern.matrix(np.zeros(self.pattern.nnz)))
        slots = np.split(self.pattern.slot, np.cumsum([A.nnz for A in (*varying, M)]))
        self._varying = [(idx, A.indptr, A.indices) for idx, A in zip(slots, varying)]
        self._MC = (slots[-2], M.data, slots[-1], C.data)
        self.blocks = [self._block(np.asarray(f, dtype=np.int64)) for f in fixed_sets]
        self.rescale(cm, cc)

    def rescale(self, cm: float, cc: float) -> None:
        """Change the multipliers of M and C (a new time step)."""
        iM, M, iC, C = self._MC
        self.cm, self.cc = cm, cc
        self.base = np.zeros(self.pattern.nnz)
        self.base[iM] += cm * M  # a canonical matrix has distinct slots
        self.base[iC] += cc * C
        for block in self.blocks:
            block["base_ff"] = self.base[block["gather_ff"]]

    def _block(self, fixed):
        n = self.n
        isfree = np.ones(n, bool)
        isfree[fixed] = False
        free = np.flatnonzero(isfree)
        new = np.cumsum(isfree) - 1
        newfix = np.cumsum(~isfree) - 1
        r, c = self.rows, self.cols
        ff = np.flatnonzero(isfree[r] & isfree[c])
        rr, cc = new[r[ff]], new[c[ff]]
        # row-major, as the CSR data the gathers read (forward in memory): as CSC arrays this is the free block's
        # transpose, i.e. the block itself (symmetric)
        order = np.lexsort((cc, rr))
        gather_ff = ff[order]
        nf = free.size
        indptr = np.concatenate([[0], np.cumsum(np.bincount(rr[order], minlength=nf))])
        fc = np.flatnonzero(isfree[r] & ~isfree[c])
        return dict(
            free=free,
            fixed=fixed,
            gather_ff=gather_ff,
            indices=cc[order].astype(np.int32),
            indptr=indptr.astype(np.int32),
            gather_fc=fc,
            fc_rows=new[r[fc]],
            fc_cols=newfix[c[fc]],
            shape_fc=(nf, fixed.size),
        )

    def _checked(self, K, extra) -> tuple:
        """(K, *extra), each checked against the pattern the system was built with for it."""
        if len(extra) != len(self._varying) - 1:
            raise ValueError(f"ReducedSystem was built with {len(self._varying) - 1} extra matrices, got {len(extra)}")
        for (_, indptr, indices), B in zip(self._varying, (K, *extra)):
            if not same_pattern(B, indptr, indices):
                raise ValueError("a matrix of the system changed its sparsity pattern between steps")
        return (K, *extra)

    def data(self, K, *extra) -> np.ndarray:
        """The data of A for this K and these extra matrices (the patterns the system was built with)."""
        A = self.base.copy()
        for (idx, _, _), B in zip(self._varying, self._checked(K, extra)):
            A[idx] += B.data
        return A

    def free_matrix(self, A: np.ndarray, block) -> sp.csc_matrix:
        """The free-free block of A's data for one block split (CSC; symmetric, so also its own CSR transpose)."""
        return self._free(A[block["gather_ff"]], block)

    @staticmethod
    def _free(data: np.ndarray, block) -> sp.csc_matrix:
        """The free-free block from its own data, in the block's order."""
        nf = block["free"].size
        return sp.csc_matrix((data, block["indices"], block["indptr"]), shape=(nf, nf))

    def matrices(self, A: np.ndarray, block):
        """The free-free block (CSC) and the free-held block (CSR) of A's data for one block split."""
        Aff = self.free_matrix(A, block)
        Afc = sp.csr_matrix(
            (A[block["gather_fc"]], (block["fc_rows"], block["fc_cols"])), shape=block["shape_fc"]
        )
        return Aff, Afc
