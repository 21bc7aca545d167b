r"""The strength matrix K(r) of the weak form of eq. (14) for the bicubic Hermite element, and its mass.

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
a 0/1 scatter matrix S built once
(:class:`deformable.algebra.elements.SymmetricElements`). No sparse-sparse products
and no change of pattern between steps. :class:`StrengthMatrix` holds the
tables and turns alpha, beta at the Gauss points into K.
"""

from __future__ import annotations

import numpy as np
import scipy.sparse as sp

from deformable.algebra.elements import SymmetricElements

__all__ = ["membrane", "bending", "mass", "StrengthMatrix", "MEMBRANE", "BENDING"]

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


class StrengthMatrix:
    """K of the weak form for alpha, beta at the Gauss points, and M, C, on the elements' fixed pattern.

    Parameters
    ----------
    ldofs : int array (E, 16)
        Global degrees of freedom of every element.
    ndof : int
    dq : dict (d1, d2) -> (16, nq)
        Shape-function derivatives at the Gauss points (:func:`femodel.hermite.basis`).
    weights : array (nq,)
        Gauss weights times the element area.
    """

    def __init__(self, ldofs: np.ndarray, ndof: int, dq: dict, weights: np.ndarray):
        self.elements = SymmetricElements(ldofs, ndof)
        self._T_membrane = self.elements.templates(membrane(dq), weights)
        self._T_stiffness = np.concatenate([self._T_membrane, self.elements.templates(bending(dq), weights)])
        self._T_mass = self.elements.templates(mass(dq), weights)
        self.nq = weights.size

    def density_matrix(self, density: np.ndarray) -> sp.csr_matrix:
        """The consistent matrix integral density u v (mass: mu in kg/m^2 -> kg) for a density (E, nq)."""
        return self.elements.matrix(self.elements.data(density, self._T_mass))

    @staticmethod
    def _coefficients(alpha: np.ndarray, beta: np.ndarray | None) -> np.ndarray:
        """Coefficient fields of the weak form, (E, C nq), in the order of the form tables."""
        c = [alpha[0, 0], 0.5 * (alpha[0, 1] + alpha[1, 0]), alpha[1, 1]]
        if beta is not None:
            c += [beta[0, 0], beta[0, 1] + beta[1, 0], beta[1, 1]]
        return np.stack(c, axis=1).reshape(alpha.shape[2], -1)

    def matrix(self, alpha: np.ndarray | None, beta: np.ndarray | None) -> sp.csr_matrix:
        """K of the weak form for alpha, beta (2, 2, E, nq) at the Gauss points; None is zero."""
        el = self.elements
        if beta is None or not np.any(beta):
            alpha = np.zeros((2, 2, el.nelem, self.nq)) if alpha is None else alpha
            data = el.data(self._coefficients(alpha, None), self._T_membrane)
        else:
            alpha = np.zeros_like(beta) if alpha is None else alpha
            data = el.data(self._coefficients(alpha, beta), self._T_stiffness)
        return el.matrix(data)
