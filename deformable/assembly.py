r"""Sparse matrices on fixed patterns: built once, refilled every step.

Every matrix the time stepper factorises (the strength matrix K(r) of
eq. (20), the step matrix A_t of eq. (25), the Hessians of the energy (13))
keeps its sparsity pattern for a whole run while its values change. The
pattern, and where each contribution lands in the data array, is therefore
computed once from the contributions' coordinates (:class:`FixedPattern`);
afterwards a refill is one gather or one sparse mat-vec, never a sparse-sparse
product or a slice.

- :class:`FixedPattern`: the CSR pattern of a list of (row, column)
  contributions and the slot of each in the data array;
- :class:`SymmetricElements`: element (or stencil) matrices of a symmetric
  operator, each given by its upper triangle, summed into a FixedPattern; with
  constant element tables (a uniform grid) the data of any coefficient field
  is one dense product and one scatter;
- :class:`ReducedSystem`: ``A = K + c_m M + c_c C`` on the union of the three
  patterns, split into its free-free and free-held blocks by precomputed
  gathers (the constraints of a scene eliminate the held degrees of freedom).
"""

from __future__ import annotations

import numpy as np
import scipy.sparse as sp

from .kernels import scatter_upper

__all__ = ["FixedPattern", "SymmetricElements", "ReducedSystem", "BlockPattern", "canonical", "element_vectors"]


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
        The canonical CSR pattern (sorted, one entry per distinct coordinate).
    nnz : int
    slot : int array (contributions,)
        Position in the data array that contribution k adds to.

    Notes
    -----
    :meth:`matrix` hands back csr_matrices that share ``indptr`` and
    ``indices``, so a caller can check that the pattern did not change by identity.
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


class SymmetricElements:
    """Symmetric element matrices, each given by its upper triangle, summed on a fixed pattern.

    Parameters
    ----------
    ldofs : int array (E, nl)
        Global degrees of freedom of every element's nl local ones (FE: the 16
        of a bicubic element; for a coordinate-blocked Hessian, 3 x 16).
    ndof : int
        Matrix size.

    Attributes
    ----------
    pattern : FixedPattern
    upper : (int array, int array)
        The local (l <= m) pairs, nl (nl + 1) / 2 of them.
    first, second : int arrays (E, nupper)
        Where each element's upper entry lands in the data array, and its mirror image (-1 on the diagonal).
    scatter : sparse (nnz, E nupper)
        The same sum as a matrix (built on first use, for coefficient templates).
    """

    def __init__(self, ldofs: np.ndarray, ndof: int):
        E, nl = ldofs.shape
        self.ndof, self.nelem = ndof, E
        self.upper = np.triu_indices(nl)
        lu, mu = self.upper
        ne = lu.size
        rows, cols = ldofs[:, lu], ldofs[:, mu]
        off = lu != mu
        self.pattern = FixedPattern(np.concatenate([rows.ravel(), cols[:, off].ravel()]),
                                    np.concatenate([cols.ravel(), rows[:, off].ravel()]), (ndof, ndof))
        slot = self.pattern.slot
        self.first = slot[:E * ne].reshape(E, ne)  # where each element's upper entry lands ...
        self.second = np.full((E, ne), -1, np.int64)  # ... and its mirror image (-1 on the diagonal)
        self.second[:, off] = slot[E * ne:].reshape(E, -1)
        self._scatter = None

    @property
    def scatter(self) -> sp.csr_matrix:
        """(nnz, E nupper) 0/1 matrix summing the elements' upper triangles (and mirrors) into the data array."""
        if self._scatter is None:
            E, ne = self.first.shape
            src = np.arange(E * ne).reshape(E, ne)
            off = self.second >= 0
            src = np.concatenate([src.ravel(), src[off].ravel()])
            dst = np.concatenate([self.first.ravel(), self.second[off].ravel()])
            self._scatter = sp.csr_matrix((np.ones(src.size), (dst, src)), shape=(self.pattern.nnz, E * ne))
        return self._scatter

    @property
    def nnz(self) -> int:
        return self.pattern.nnz

    def templates(self, integrand: np.ndarray, weights: np.ndarray) -> np.ndarray:
        """Upper-triangle tables of a form times the quadrature weights.

        Parameters
        ----------
        integrand : array (C, nq, nl, nl)
            A form's integrand per unit coefficient.
        weights : array (nq,)
            Quadrature weights (times the element area, scene units^2).

        Returns
        -------
        array (C nq, nupper)
        """
        T = integrand * weights[None, :, None, None]
        return T[:, :, self.upper[0], self.upper[1]].reshape(-1, self.upper[0].size)

    def data(self, coefficients: np.ndarray, templates: np.ndarray) -> np.ndarray:
        """Data array of sum_e K_e for coefficients (E, C nq) (coefficient-major, then points)."""
        return self.scatter @ (coefficients @ templates).ravel()

    def collect(self, upper: np.ndarray) -> np.ndarray:
        """Data array of the element matrices given by their upper triangles (E, nupper) (a compiled scatter)."""
        data = np.zeros(self.pattern.nnz)
        scatter_upper(np.ascontiguousarray(upper, float), self.first, self.second, data)
        return data

    def matrix(self, data: np.ndarray) -> sp.csr_matrix:
        return self.pattern.matrix(data)


def element_vectors(ldofs: np.ndarray, ndof: int) -> sp.csr_matrix:
    """(ndof, E nl) 0/1 matrix summing element vectors (E, nl, ...) flattened into the global vector."""
    E, nl = ldofs.shape
    return sp.csr_matrix((np.ones(E * nl), (ldofs.ravel(), np.arange(E * nl))), shape=(ndof, E * nl))


class ReducedSystem:
    """A = K + K_2 + ... + c_m M + c_c C on a fixed pattern, split into free/held blocks; all symmetric.

    Built once from the patterns of the varying matrices K (K_2, ...) and of
    the constant M and C; afterwards each refill only gathers data arrays (no
    sparse-sparse products, no slicing).

    Parameters
    ----------
    K, M, C : sparse (n, n)
        K's pattern must stay the same between refills (:meth:`data` checks it).
    cm, cc : float
        Multipliers of M and C.
    fixed_sets : list of int arrays
        One block split per set of held degrees of freedom.
    extra : sequence of sparse (n, n)
        Further varying matrices with fixed patterns (the springs' Hessian, the
        wind's damping), refilled with K by :meth:`data`.
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
        # each varying matrix's data index of every free-free entry: a gather where it has them all (K), else
        # the entries it has and their data indices (the springs' few)
        where = np.full(self.pattern.nnz, -1, np.int64)
        sources = []
        for idx, _, _ in self._varying:
            where[:] = -1
            where[idx] = np.arange(idx.size)
            src = where[gather_ff]
            sources.append(src if np.all(src >= 0) else (np.flatnonzero(src >= 0), src[src >= 0]))
        return dict(
            sources=sources,
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

    def free_block(self, K, *extra, block: int = 0) -> sp.csc_matrix:
        """The free-free block of A for this K and these extra matrices, gathered from their data directly.

        The same matrix as ``free_matrix(data(K, *extra), blocks[block])`` without forming A's whole data:
        the Newton matrix of every iteration (:mod:`deformable.newton`).
        """
        b = self.blocks[block]
        A = b["base_ff"].copy()
        for B, src in zip(self._checked(K, extra), b["sources"]):
            if isinstance(src, tuple):
                A[src[0]] += B.data[src[1]]
            else:
                A += B.data[src]
        return self._free(A, b)

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


class BlockPattern:
    """The fixed pattern of a symmetric 3 x 3 block matrix whose blocks share one scalar pattern.

    Parameters
    ----------
    S : sparse (n, n)
        The scalar pattern every block has (e.g. the one ``density_matrix`` returns).
    n : int

    :meth:`matrix` takes the six blocks (a, b), a <= b, each on S's very pattern, and returns the
    coordinate-blocked (3 n, 3 n) matrix (index a n + k) on one fixed pattern.
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
