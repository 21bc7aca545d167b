r"""Weak forms and fixed-pattern assembly for the bicubic Hermite element.

Weak form of the force of eq. (14) (TPBF87), for one coordinate u of r and a
test function v, with alpha and beta frozen at the current r (eq. (15)):

    K(u, v) = integral  alpha_ij u_j v_i  +  beta_ij u_ij v_ij   da1 da2

summed over i, j; with alpha symmetric the membrane part is
``alpha_11 u_1 v_1 + alpha_12 (u_2 v_1 + u_1 v_2) + alpha_22 u_2 v_2`` and the
bending part ``beta_11 u_11 v_11 + (beta_12 + beta_21) u_12 v_12 +
beta_22 u_22 v_22``. Mass and damping are ``integral mu u v``, ``integral
gamma u v`` (the consistent matrices of eq. (21)).

The forms :func:`membrane`, :func:`bending` and :func:`mass` give, per unit
coefficient, the integrand ``v_l u_m`` of each coefficient at each quadrature
point of the reference element; on a uniform tensor mesh these 16 x 16 tables
are the same on every element. So the element matrices of any coefficient
field sampled at the quadrature points are one dense product

    K_e[l, m] = sum_{c, q} w_c(e, q) T_c(q)[l, m]        (E, 6 nq) @ (6 nq, 136)

(136 = the upper triangle of a symmetric 16 x 16 matrix), and the global
data array on the fixed CSR pattern is one sparse product ``data = S k`` with
a 0/1 scatter matrix S built once (:class:`FixedPattern`). No sparse-sparse
products and no change of pattern between steps.
"""

from __future__ import annotations

import numpy as np
import scipy.sparse as sp

__all__ = ["membrane", "bending", "mass", "FixedPattern", "MEMBRANE", "BENDING"]

#: coefficient fields of the membrane form, in order
MEMBRANE = ("alpha_11", "alpha_12", "alpha_22")
#: coefficient fields of the bending form, in order (beta_12 stands for beta_12 + beta_21)
BENDING = ("beta_11", "beta_12", "beta_22")


def _outer(v: np.ndarray, u: np.ndarray) -> np.ndarray:
    """(16, nq), (16, nq) -> (nq, 16, 16): test function l (row) times trial m (column)."""
    return np.einsum("lq,mq->qlm", v, u)


def membrane(d: dict) -> np.ndarray:
    """Membrane integrand ``alpha_ij u_j v_i`` per unit alpha_11, alpha_12 (= alpha_21), alpha_22.

    Parameters
    ----------
    d : dict (d1, d2) -> array (16, nq)
        Shape-function derivatives at the quadrature points (:func:`femodel.hermite.basis`).

    Returns
    -------
    array (3, nq, 16, 16)
    """
    d1, d2 = d[1, 0], d[0, 1]
    return np.stack([_outer(d1, d1), _outer(d1, d2) + _outer(d2, d1), _outer(d2, d2)])


def bending(d: dict) -> np.ndarray:
    """Bending integrand ``beta_ij u_ij v_ij`` per unit beta_11, beta_12 + beta_21, beta_22.

    Returns
    -------
    array (3, nq, 16, 16)
    """
    d11, d12, d22 = d[2, 0], d[1, 1], d[0, 2]
    return np.stack([_outer(d11, d11), _outer(d12, d12), _outer(d22, d22)])


def mass(d: dict) -> np.ndarray:
    """Mass integrand ``mu u v`` per unit mu (also damping per unit gamma), (1, nq, 16, 16)."""
    return _outer(d[0, 0], d[0, 0])[None]


class FixedPattern:
    """A symmetric sparse matrix on a fixed CSR pattern, refilled from element matrices.

    Parameters
    ----------
    ldofs : int array (E, 16)
        Global degrees of freedom of every element's 16 local ones.
    ndof : int
        Matrix size.

    Notes
    -----
    ``indptr`` and ``indices`` are built once; :meth:`matrix` returns a new
    csr_matrix sharing them, so a caller can check that the pattern did not
    change by identity.
    """

    def __init__(self, ldofs: np.ndarray, ndof: int):
        E, nl = ldofs.shape
        self.ndof, self.nelem = ndof, E
        self.upper = np.triu_indices(nl)  # the 136 local (l <= m) pairs
        lu, mu = self.upper
        ne = lu.size
        rows, cols = ldofs[:, lu], ldofs[:, mu]
        src = np.arange(E * ne).reshape(E, ne)
        off = lu != mu
        R = np.concatenate([rows.ravel(), cols[:, off].ravel()]).astype(np.int64)
        C = np.concatenate([cols.ravel(), rows[:, off].ravel()]).astype(np.int64)
        src = np.concatenate([src.ravel(), src[:, off].ravel()])
        ukeys, pos = np.unique(R * ndof + C, return_inverse=True)
        self.indices = (ukeys % ndof).astype(np.int32)
        self.indptr = np.concatenate([[0], np.cumsum(np.bincount(ukeys // ndof, minlength=ndof))]).astype(np.int32)
        self.nnz = ukeys.size
        self.scatter = sp.csr_matrix((np.ones(src.size), (pos.ravel(), src)), shape=(self.nnz, E * ne))

    def templates(self, integrand: np.ndarray, weights: np.ndarray) -> np.ndarray:
        """Upper-triangle tables of a form times the quadrature weights.

        Parameters
        ----------
        integrand : array (C, nq, 16, 16)
            A form's integrand per unit coefficient (:func:`membrane`, ...).
        weights : array (nq,)
            Quadrature weights times the element area (scene units^2).

        Returns
        -------
        array (C nq, 136)
        """
        T = integrand * weights[None, :, None, None]
        return T[:, :, self.upper[0], self.upper[1]].reshape(-1, self.upper[0].size)

    def data(self, coefficients: np.ndarray, templates: np.ndarray) -> np.ndarray:
        """Data array of sum_e K_e for coefficients (E, C nq) (coefficient-major, then points)."""
        return self.scatter @ (coefficients @ templates).ravel()

    def matrix(self, data: np.ndarray) -> sp.csr_matrix:
        """The csr_matrix with this data on the fixed pattern (canonical: sorted, no duplicates)."""
        A = sp.csr_matrix((data, self.indices, self.indptr), shape=(self.ndof, self.ndof), copy=False)
        A.indices, A.indptr = self.indices, self.indptr  # scipy may hand back views; keep the very arrays
        A.has_canonical_format = True
        return A
