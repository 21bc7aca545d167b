r"""The bicubic Hermite (Bogner-Fox-Schmit) element, built on the reference square.

One dimension. The cubic Hermite shape functions on the reference interval
``s in [0, 1]`` (value and slope at each end)::

    H0(s) = 1 - 3 s^2 + 2 s^3      value at s = 0
    H1(s) = s - 2 s^2 + s^3        slope at s = 0
    H2(s) = 3 s^2 - 2 s^3          value at s = 1
    H3(s) = -s^2 + s^3             slope at s = 1

Two dimensions. On the element ``[a1_i, a1_i + h1] x [a2_j, a2_j + h2]`` with
``s = (a1 - a1_i)/h1``, ``t = (a2 - a2_j)/h2`` the 16 shape functions are the
tensor products ``H_{2a+p}(s) H_{2b+q}(t)``: corner (a, b) in {0, 1}^2 and
derivative order (p, q) in {0, 1}^2. The degrees of freedom at a node are

    (r, h1 r_1, h2 r_2, h1 h2 r_12)        local index k = p + 2 q

i.e. the derivative degrees of freedom are *scaled by the element size*, so
every degree of freedom has the units of r and the element is the same
reference element on every rectangle. Derivatives in the parameters follow by
the chain rule, ``d/da1 = (1/h1) d/ds``, ``d/da2 = (1/h2) d/dt``.

Why not ``skfem.ElementQuadBFS``: it is an ``ElementGlobal`` that inverts a
Vandermonde matrix of monomials in the *global* coordinates on every element;
on fine meshes that matrix is badly conditioned and nodal interpolation loses
accuracy (docs/design.md: value error 1e-7 at 32 x 32, 4e-4 at 128 x 128
elements). The reference-element construction above involves no inversion;
its shape functions are O(1) polynomials in s, t on every element, so the
round-off of an evaluation stays at a few ulp of |r| whatever h is (measured
clean to 256 x 256 elements, tests/femodel/test_hermite.py).

The space is C1 on a tensor-product mesh (H2-conforming), as the bending
term ``beta_ij r_ij . v_ij`` of the weak form of eq. (14) needs.
"""

from __future__ import annotations

import numpy as np

__all__ = ["cubic_hermite", "LOCAL", "basis", "evaluate", "NODE_DOFS", "DERIVATIVES"]

NODE_DOFS = 4  # r, h1 r_1, h2 r_2, h1 h2 r_12

#: the 16 local shape functions: (corner a, corner b, order p, order q), local index 4 (2 a + b) + p + 2 q
LOCAL = tuple((a, b, p, q) for a in (0, 1) for b in (0, 1) for q in (0, 1) for p in (0, 1))
_I1 = np.array([2 * a + p for a, b, p, q in LOCAL])  # 1-D function index along a1
_I2 = np.array([2 * b + q for a, b, p, q in LOCAL])  # 1-D function index along a2

#: derivative orders (d1, d2) evaluated for the model: value, r_1, r_2, r_11, r_12, r_22
DERIVATIVES = ((0, 0), (1, 0), (0, 1), (2, 0), (1, 1), (0, 2))


def cubic_hermite(s, order: int = 0) -> np.ndarray:
    """The four 1-D cubic Hermite functions on [0, 1] or their derivatives in s.

    Parameters
    ----------
    s : array, any shape S
        Reference coordinate.
    order : 0, 1 or 2
        Derivative order d^order/ds^order.

    Returns
    -------
    array (4, *S)
        H0, H1, H2, H3 (value at 0, slope at 0, value at 1, slope at 1).
    """
    s = np.asarray(s, float)
    if order == 0:
        return np.stack([1 - s * s * (3 - 2 * s), s * (1 - s) ** 2, s * s * (3 - 2 * s), s * s * (s - 1)])
    if order == 1:
        return np.stack([6 * s * (s - 1), (1 - s) * (1 - 3 * s), 6 * s * (1 - s), s * (3 * s - 2)])
    if order == 2:
        return np.stack([12 * s - 6, 6 * s - 4, 6 - 12 * s, 6 * s - 2])
    raise ValueError(f"order must be 0, 1 or 2, got {order!r}")


def basis(s, t, h: tuple[float, float], d: tuple[int, int] = (0, 0)) -> np.ndarray:
    """The 16 bicubic shape functions (or a derivative in a1, a2) at reference points.

    Parameters
    ----------
    s, t : arrays of one shape S
        Reference coordinates in [0, 1] of the points in their elements.
    h : (h1, h2)
        Element sides (scene units).
    d : (d1, d2)
        Derivative orders in the parameters a1, a2 (each 0, 1 or 2).

    Returns
    -------
    array (16, *S)
        ``d^(d1+d2) phi_l / da1^d1 da2^d2`` in units of 1/length^(d1+d2), for
        the local degrees of freedom of :data:`LOCAL`.
    """
    d1, d2 = d
    h1, h2 = h
    return cubic_hermite(s, d1)[_I1] * cubic_hermite(t, d2)[_I2] / (h1**d1 * h2**d2)


def evaluate(X: np.ndarray, ldofs: np.ndarray, tables: list) -> np.ndarray:
    """Values of the field X at the points of every element, for several basis tables.

    Parameters
    ----------
    X : array (ndof, 3)
    ldofs : int array (E, 16)
        Global degrees of freedom of every element.
    tables : list of k arrays (16, nq)
        Shape functions or their derivatives at the points (:func:`basis`).

    Returns
    -------
    array (3, k, E, nq)
    """
    D = np.concatenate(tables, axis=1)  # (16, k nq)
    Xl = X.T[:, ldofs]  # (3, E, 16), contiguous
    E = ldofs.shape[0]
    out = (Xl.reshape(-1, Xl.shape[-1]) @ D).reshape(3, E, len(tables), -1)
    return np.ascontiguousarray(out.transpose(0, 2, 1, 3))  # contiguous: the tensor algebra runs faster
