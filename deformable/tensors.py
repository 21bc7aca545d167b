r"""Metric and curvature tensors of a parametric surface, as pure functions.

Components come first and points last (the layout of ``skfem.helpers``), so
the same call serves finite-difference nodes (``*pts = M, N``) and
finite-element quadrature points (``*pts = elements, points``).

- metric tensor, eq. (4)-(5):   ``G_ij = r_i . r_j``
- unit normal:                   ``n = (r_1 x r_2) / |r_1 x r_2|``
- curvature tensor, eq. (8):     ``B_ij = n . r_ij``
- Gaussian curvature:            ``K = det B / det G``
"""

from __future__ import annotations

import numpy as np

__all__ = ["metric", "normal", "curvature", "gaussian_curvature", "det2"]


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


def normal(dr: np.ndarray) -> np.ndarray:
    """Unit normal n = (r_1 x r_2)/|r_1 x r_2|, shape (3, *pts) from dr (3, 2, *pts).

    Where the tangents are parallel (a degenerate surface) the normal is NaN:
    callers that can meet such points must guard them.
    """
    c = np.cross(dr[:, 0], dr[:, 1], axis=0)
    with np.errstate(invalid="ignore", divide="ignore"):
        return c / np.linalg.norm(c, axis=0)


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
