"""Element matrices of a symmetric operator, each given by its upper triangle, summed on a fixed pattern.

With constant element tables (a uniform grid) the data of any coefficient field is one dense product and one scatter
(:class:`SymmetricElements`); the scatter of element upper triangles into the CSR data is compiled
(:func:`scatter_upper`, numba). Element load vectors go to the degrees of freedom through one sparse matrix
(:func:`element_vectors`).
"""

from __future__ import annotations

import numpy as np
import scipy.sparse as sp
from numba import njit

from .patterns import FixedPattern

__all__ = ["SymmetricElements", "element_vectors", "scatter_upper"]


class SymmetricElements:
    """Symmetric element matrices, each given by its upper triangle, summed on a fixed pattern.

    Parameters
    ----------
    ldofs : int array (E, nl)
        Global degrees of freedom of every element's nl local ones (FE: the 16 of a bicubic element; for a
        coordinate-blocked Hessian, 3 x 16).
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
        self.ndof, self.nelem, self.ldofs = ndof, E, ldofs
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


@njit(cache=True)
def scatter_upper(upper, first, second, data):
    """Add element upper triangles (E, nu) into a CSR data array: entry k of element e at data[first[e, k]] and, off
    the diagonal, at data[second[e, k]] too (second < 0 on the diagonal); first < 0: dropped (a held row or column,
    :class:`deformable.algebra.upper.FreeUpper`)."""
    E, nu = upper.shape
    for e in range(E):
        for k in range(nu):
            i = first[e, k]
            if i < 0:
                continue
            x = upper[e, k]
            data[i] += x
            j = second[e, k]
            if j >= 0:
                data[j] += x
