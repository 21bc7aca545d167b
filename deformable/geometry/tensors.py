r"""Metric and curvature tensors of a parametric surface, as pure functions.

Components come first and points last (the layout of ``skfem.helpers``), so the same call serves finite-difference
nodes (``*pts = M, N``) and finite-element quadrature points (``*pts = elements, points``).

- metric tensor, eq. (4)-(5):   ``G_ij = r_i . r_j``
- unit normal:                   ``n = (r_1 x r_2) / |r_1 x r_2|`` (:func:`frame` gives n and
  the area element ``|r_1 x r_2|`` along any axis: the energy modules work points first)
- curvature tensor, eq. (8):     ``B_ij = n . r_ij``
- Gaussian curvature:            ``K = det B / det G``
- an orthonormal basis of the plane perpendicular to a unit normal (:func:`tangent_basis`)
"""

from __future__ import annotations

import numpy as np

__all__ = ["metric", "normal", "frame", "dot", "cross", "curvature", "gaussian_curvature", "det2", "tangent_basis"]


def metric(dr: np.ndarray) -> np.ndarray:
    """Metric tensor G_ij = r_i . r_j, eq. (4).

    Parameters
    ----------
    dr : array (3, 2, *pts)
        First derivatives: ``dr[:, i]`` is r_i = dr/da_i.

    Returns
    -------
    array (2, 2, *pts)
    """
    return np.einsum("ai...,aj...->ij...", dr, dr)


def dot(a: np.ndarray, b: np.ndarray, axis: int = -1) -> np.ndarray:
    """The dot product over the 3 components on ``axis`` (default last: points first)."""
    a, b = np.moveaxis(a, axis, 0), np.moveaxis(b, axis, 0)
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]


def cross(a: np.ndarray, b: np.ndarray, axis: int = -1) -> np.ndarray:
    """The cross product of 3-vectors on ``axis`` (written out: several times faster than numpy.cross)."""
    a, b = np.moveaxis(a, axis, 0), np.moveaxis(b, axis, 0)
    c = np.stack([a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]])
    return np.moveaxis(c, 0, axis)


def frame(t1: np.ndarray, t2: np.ndarray, axis: int = -1) -> tuple[np.ndarray, np.ndarray]:
    """Unit normal n = (t1 x t2)/|t1 x t2| and the area element |t1 x t2|.

    Parameters
    ----------
    t1, t2 : arrays with the 3 components on ``axis``
        The tangents r_1, r_2.

    Returns
    -------
    n : array of the shape of t1
    area : array without ``axis``
        |r_1 x r_2| = sqrt(det G).

    Where the tangents are parallel (a degenerate surface) the normal is NaN:
    callers that can meet such points must guard them.
    """
    c = cross(t1, t2, axis=axis)
    area = np.sqrt(dot(c, c, axis=axis))
    with np.errstate(invalid="ignore", divide="ignore"):
        return c / np.expand_dims(area, axis), area


def normal(dr: np.ndarray) -> np.ndarray:
    """Unit normal n = (r_1 x r_2)/|r_1 x r_2|, shape (3, *pts) from dr (3, 2, *pts) (see :func:`frame`)."""
    return frame(dr[:, 0], dr[:, 1], axis=0)[0]


def curvature(ddr: np.ndarray, n: np.ndarray) -> np.ndarray:
    """Curvature tensor B_ij = n . r_ij, eq. (8).

    Parameters
    ----------
    ddr : array (3, 2, 2, *pts)
        Second derivatives: ``ddr[:, i, j]`` is r_ij.
    n : array (3, *pts)
        Unit normal.

    Returns
    -------
    array (2, 2, *pts)
    """
    return np.einsum("aij...,a...->ij...", ddr, n)


def det2(T: np.ndarray) -> np.ndarray:
    """Determinant of a field of 2 x 2 tensors, shape (2, 2, *pts) -> (*pts)."""
    return T[0, 0] * T[1, 1] - T[0, 1] * T[1, 0]


def gaussian_curvature(G: np.ndarray, B: np.ndarray) -> np.ndarray:
    """Gaussian curvature K = det B / det G, shape (*pts), from (2, 2, *pts) fields."""
    return det2(B) / det2(G)


def tangent_basis(n: np.ndarray) -> np.ndarray:
    """An orthonormal basis (P, 3, 2) of the planes perpendicular to unit normals n (P, 3)."""
    e = np.where(np.abs(n[:, 2:3]) < 0.9, np.array([0.0, 0.0, 1.0]), np.array([1.0, 0.0, 0.0]))
    t1 = np.cross(n, e)
    t1 /= np.linalg.norm(t1, axis=1, keepdims=True)
    return np.stack([t1, np.cross(n, t1)], axis=2)
