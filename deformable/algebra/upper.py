"""The Newton matrix's free block as one upper triangle, assembled where the solver reads it.

Newton's matrix ``A = c_M M + c_C C + H + (the springs', obstacles' and wind's matrices) + (the self-contact's)`` is
symmetric, and only its free-free block is factorised. :class:`FreeUpper` keeps that block's upper triangle as CSR
arrays (``indptr``, ``indices``: rows in the free numbering, columns sorted) on a pattern built once from every
contribution's pattern, and precomputes where each contribution lands in its data array:

- the energy's Hessian, given as element upper triangles (E, nu) over element degrees of freedom
  (:class:`deformable.algebra.elements.SymmetricElements`): each entry goes to one slot (an entry (l, m), l < m,
  whose two local degrees of freedom are one global one, to the diagonal twice), held rows dropped, by the compiled
  scatter :func:`deformable.algebra.elements.scatter_upper`;
- any fixed-pattern symmetric matrix (M, C, the springs', the obstacles', the wind's, a Hessian given whole): a
  gather of its data;
- a *loose* matrix, whose pattern changes between calls (the self-contact's Hessian): its entries are looked up in
  the block's pattern, which grows to the union of every pattern seen when one falls outside it (rarely: the pattern
  is grown ahead by the pairs that may touch within the step, :meth:`FreeUpper.grow`).

The result is a :class:`SymmetricUpper`, which the direct solvers factorise as it is (PARDISO reads an upper
triangle in CSR; its analysis is kept while the pattern's ``version`` stays the same).
"""

from __future__ import annotations

import numpy as np
import scipy.sparse as sp

from .elements import SymmetricElements, scatter_upper
from .patterns import canonical, coordinates, same_pattern

__all__ = ["SymmetricUpper", "FreeUpper"]


class SymmetricUpper:
    """A symmetric n x n matrix given by its upper triangle in CSR (columns sorted in each row).

    Attributes
    ----------
    indptr, indices : int32 arrays
        The upper triangle's pattern.
    data : float array
    version : int
        Changes exactly when the pattern does (a solver keeps its analysis while it stays).
    diagonal_slots : int array (n,)
        Where each diagonal entry sits in ``data``.
    """

    __slots__ = ("indptr", "indices", "data", "version", "diagonal_slots")

    def __init__(self, indptr, indices, data, version: int, diagonal_slots):
        self.indptr, self.indices, self.data, self.version = indptr, indices, data, version
        self.diagonal_slots = diagonal_slots

    @property
    def shape(self) -> tuple[int, int]:
        n = self.indptr.size - 1
        return n, n

    @property
    def nnz(self) -> int:
        """Stored entries of the whole symmetric matrix (both triangles)."""
        return 2 * self.data.size - self.diagonal_slots.size

    def diagonal(self) -> np.ndarray:
        return self.data[self.diagonal_slots]

    def shifted(self, shift: float) -> "SymmetricUpper":
        """A + shift I, on the same pattern."""
        data = self.data.copy()
        data[self.diagonal_slots] += shift
        return SymmetricUpper(self.indptr, self.indices, data, self.version, self.diagonal_slots)

    def upper(self) -> sp.csr_matrix:
        """The upper triangle as a scipy CSR matrix (sharing the arrays)."""
        return sp.csr_matrix((self.data, self.indices, self.indptr), shape=self.shape, copy=False)

    def tocsc(self) -> sp.csc_matrix:
        """The whole symmetric matrix, CSC."""
        U = self.upper()
        return (U + U.T - sp.diags(self.diagonal())).tocsc()

    def dot(self, v: np.ndarray) -> np.ndarray:
        """A v."""
        U = self.upper()
        return U @ v + U.T @ v - self.diagonal() * v

    __matmul__ = dot


class FreeUpper:
    """The free block's upper triangle of ``c_M M + c_C C + H + sum(extra) + sum(loose)`` (module docstring).

    Parameters
    ----------
    n : int
        The whole matrix's size.
    fixed : int array
        The held degrees of freedom (their rows and columns are dropped).
    M, C : sparse (n, n), symmetric
        Constant; ``c_M`` and ``c_C`` multiply them (:meth:`rescale`).
    cm, cc : float
    hessian : SymmetricElements or sparse (n, n)
        The Hessian's pattern: element upper triangles over ``hessian.ldofs``-like element degrees of freedom
        (:class:`deformable.algebra.elements.SymmetricElements`), or a symmetric matrix whose pattern stays.
    extra : sequence of sparse (n, n), symmetric
        Further matrices with fixed patterns (refilled by :meth:`assemble` in this order).
    """

    def __init__(self, n: int, fixed, M, C, cm: float, cc: float, hessian, extra=()):
        isfree = np.ones(n, bool)
        isfree[np.asarray(fixed, np.int64)] = False
        self.n, self.free = n, np.flatnonzero(isfree)
        self.nf = self.free.size
        self.new = np.where(isfree, np.cumsum(isfree) - 1, -1)
        self.elements = hessian if isinstance(hessian, SymmetricElements) else None
        fixed_csr = [canonical(B) for B in (M, C, *([] if self.elements is not None else [hessian]), *extra)]
        self._Mdata, self._Cdata = fixed_csr[0].data, fixed_csr[1].data
        keys = [self._keys(*coordinates(B))[0] for B in fixed_csr]
        if self.elements is not None:
            keys.append(self._keys(*coordinates(self.elements.pattern.matrix(np.zeros(self.elements.nnz))))[0])
        self._set_pattern(np.unique(np.concatenate(keys)), version=0)
        self._M, self._C = (self._gather(B) for B in fixed_csr[:2])
        self._H = None if self.elements is not None else self._gather(fixed_csr[2])
        self._extra = [self._gather(B) for B in fixed_csr[2 + (self.elements is None):]]
        self._patterns = [(B.indptr, B.indices) for B in fixed_csr[2:]]  # the whole Hessian's (if given) and extras
        self._first = self._second = None
        if self.elements is not None:
            self._element_slots()
        self.rescale(cm, cc)

    # -- the pattern ------------------------------------------------------------------
    def _keys(self, rows, cols):
        """Row-major keys ``i nf + j`` (i <= j, free numbering) of the free upper entries among (rows, cols), and
        which of them they are."""
        i, j = self.new[rows], self.new[cols]
        on = (i >= 0) & (j >= 0) & (i <= j)
        return i[on] * self.nf + j[on], on

    def _set_pattern(self, keys: np.ndarray, version: int) -> None:
        nf = self.nf
        self.keys, self.version = keys, version
        self.indices = (keys % nf).astype(np.int32)
        self.indptr = np.concatenate([[0], np.cumsum(np.bincount(keys // nf, minlength=nf))]).astype(np.int32)
        self.diagonal_slots = np.searchsorted(keys, np.arange(nf, dtype=np.int64) * (nf + 1))

    def _slots(self, keys: np.ndarray) -> np.ndarray:
        """The data slots of keys the pattern holds."""
        return np.searchsorted(self.keys, keys)

    def _gather(self, B: sp.csr_matrix) -> tuple[np.ndarray, np.ndarray]:
        """(source positions in B.data, destination slots) of B's free upper entries."""
        keys, on = self._keys(*coordinates(B))
        return np.flatnonzero(on), self._slots(keys)

    def _element_slots(self) -> None:
        """Each element upper entry's slot (first), and again (second) where its two local degrees of freedom are
        one global one off the local diagonal; -1 where a row or column is held."""
        el = self.elements
        lu, mu = el.upper
        I, J = el.ldofs[:, lu], el.ldofs[:, mu]
        i, j = self.new[I], self.new[J]
        on = (i >= 0) & (j >= 0)
        keys = np.minimum(i, j) * self.nf + np.maximum(i, j)
        first = np.full(I.shape, -1, np.int64)
        first[on] = self._slots(keys[on])
        second = np.where(on & (I == J) & (lu != mu)[None, :], first, -1)
        self._first, self._second = first, second

    def holds(self, rows, cols) -> bool:
        """Whether the pattern holds every free upper entry among (rows, cols) (global indices)."""
        keys, _ = self._keys(np.asarray(rows, np.int64), np.asarray(cols, np.int64))
        at = np.minimum(np.searchsorted(self.keys, keys), self.keys.size - 1)
        return bool(np.all(self.keys[at] == keys))

    def grow(self, rows, cols) -> None:
        """Add the free upper entries among (rows, cols) (global indices) to the pattern, if any is new; the version
        changes only then."""
        keys, _ = self._keys(np.asarray(rows, np.int64), np.asarray(cols, np.int64))
        keys = np.unique(keys)
        at = np.minimum(np.searchsorted(self.keys, keys), self.keys.size - 1)
        missing = keys[self.keys[at] != keys]
        if missing.size == 0:
            return
        old = self.keys
        self._set_pattern(np.insert(old, np.searchsorted(old, missing), missing), self.version + 1)
        remap = self._slots(old)
        self._M, self._C = ((src, remap[dst]) for src, dst in (self._M, self._C))
        self._extra = [(src, remap[dst]) for src, dst in self._extra]
        if self._H is not None:
            self._H = (self._H[0], remap[self._H[1]])
        if self._first is not None:
            self._first = np.where(self._first >= 0, remap[np.maximum(self._first, 0)], -1)
            self._second = np.where(self._second >= 0, remap[np.maximum(self._second, 0)], -1)
        self.rescale(self.cm, self.cc)

    # -- the data -----------------------------------------------------------------------
    def refill(self, M, C) -> None:
        """New values of M and C on the patterns the block was built with (ValueError otherwise)."""
        data = []
        for name, B, (_, _) in (("M", M, self._M), ("C", C, self._C)):
            B = canonical(B)
            if B.nnz != (self._Mdata if name == "M" else self._Cdata).size:
                raise ValueError(f"FreeUpper.refill: {name} has another pattern than the block was built with")
            data.append(B.data)
        self._Mdata, self._Cdata = data
        self.rescale(self.cm, self.cc)

    def rescale(self, cm: float, cc: float) -> None:
        """New multipliers of M and C (a new time step)."""
        self.cm, self.cc = cm, cc
        base = np.zeros(self.keys.size)
        for (src, dst), B, c in ((self._M, self._Mdata, cm), (self._C, self._Cdata, cc)):
            base[dst] += c * B[src]
        self.base = base

    def assemble(self, hessian, extra=(), loose=(), reserve=None) -> SymmetricUpper:
        """The free block's upper triangle of the whole matrix.

        ``hessian``: element upper triangles (E, nu) when the block was built on elements, else a matrix on the
        pattern it was built with; ``extra``: the fixed-pattern matrices, in order; ``loose``: symmetric sparse (n,
        n) matrices of any pattern (the block grows to hold them); ``reserve``: a callable giving (rows, columns)
        the loose matrices may soon need, added too where the pattern must grow anyway (it then grows rarely).
        """
        loose = [sp.coo_matrix(L) for L in loose]
        rows = np.concatenate([L.row for L in loose]).astype(np.int64) if loose else np.zeros(0, np.int64)
        cols = np.concatenate([L.col for L in loose]).astype(np.int64) if loose else np.zeros(0, np.int64)
        if rows.size and not self.holds(rows, cols):
            more = reserve() if reserve is not None else (rows[:0], cols[:0])
            self.grow(np.concatenate([rows, more[0]]), np.concatenate([cols, more[1]]))
        if len(extra) != len(self._extra):
            raise ValueError(f"FreeUpper was built with {len(self._extra)} extra matrices, got {len(extra)}")
        data = self.base.copy()
        whole = []
        if self._first is not None:
            scatter_upper(np.ascontiguousarray(hessian, float), self._first, self._second, data)
        else:
            whole = [(self._H, sp.csr_matrix(hessian))]
        for (src, dst), (indptr, indices), B in zip([*(h for h, _ in whole), *self._extra], self._patterns,
                                                    [*(B for _, B in whole), *extra]):
            if not same_pattern(B, indptr, indices):
                B = canonical(B)  # the same pattern written another way (unsorted, duplicates)?
                if not same_pattern(B, indptr, indices):
                    raise ValueError("a matrix of the Newton system changed its sparsity pattern between calls")
            data[dst] += B.data[src]
        for L in loose:
            keys, on = self._keys(L.row.astype(np.int64), L.col.astype(np.int64))
            np.add.at(data, self._slots(keys), L.data[on])
        return SymmetricUpper(self.indptr, self.indices, data, self.version, self.diagonal_slots)
