r"""Metric and curvature tensors of a parametric surface, as pure functions.

Components come first and points last (the layout of ``skfem.helpers``), so
the same call serves finite-difference nodes (``*pts = M, N``) and
finite-element quadrature points (``*pts = elements, points``).

- metric tensor, eq. (4)-(5):   ``G_ij = r_i . r_j``
- unit normal:                   ``n = (r_1 x r_2) / |r_1 x r_2|`` (:func:`frame` gives n and
  the area element ``|r_1 x r_2|`` along any axis: the energy modules work points first)
- curvature tensor, eq. (8):     ``B_ij = n . r_ij``
- Gaussian curvature:            ``K = det B / det G``
"""

from __future__ import annotations

import numpy as np

__all__ = ["metric", "normal", "frame", "dot", "cross", "curvature", "gaussian_curvature", "det2", "skew", "normal_hessian"]


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


def skew(a: np.ndarray) -> np.ndarray:
    """Cross-product matrices ``[a]x`` with ``[a]x b = a x b``: (..., 3) -> (..., 3, 3)."""
    z = np.zeros(a.shape[:-1])
    return np.stack([np.stack([z, -a[..., 2], a[..., 1]], -1),
                     np.stack([a[..., 2], z, -a[..., 0]], -1),
                     np.stack([-a[..., 1], a[..., 0], z], -1)], -2)


def normal_hessian(t1: np.ndarray, t2: np.ndarray, V: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    r"""Second derivatives of ``f = V . n``, ``n = (t1 x t2)/|t1 x t2|``, for exact curvature Hessians.

    With ``c = t1 x t2``, ``w = (V - (V.n) n)/|c|`` (the gradient of f in c),
    ``Hess_c f = -(w n^T + n w^T)/|c| - (V.n)(I - n n^T)/|c|^2``,
    ``dc = C (dt1, dt2)``, ``C = [-[t2]x, [t1]x]`` and ``d2c = 2 dt1 x dt2``:

        d2f = dt^T (C^T Hess_c f C + [[0, -[w]x], [[w]x, 0]]) dt + 2 dV^T (I - n n^T)/|c| C dt.

    Here the layout is points first (linear algebra per point): t1, t2, V are
    (..., 3). Returns ``Htt`` (..., 6, 6), the Hessian in (t1, t2) at fixed V,
    and ``Q`` (..., 3, 6), the mixed derivative d2f/dV d(t1, t2). Htt is
    linear in V and Q does not depend on it, so residuals that share a frame
    can sum their weighted V first.
    """
    n, area = frame(t1, t2)
    nc = area[..., None, None]
    Vn = dot(V, n)[..., None, None]
    W = (V - Vn[..., 0] * n) / nc[..., 0]
    P = np.eye(3) - n[..., :, None] * n[..., None, :]
    Hf = -(W[..., :, None] * n[..., None, :] + n[..., :, None] * W[..., None, :]) / nc - Vn * P / nc**2
    C = np.concatenate([-skew(t2), skew(t1)], axis=-1)
    Htt = np.swapaxes(C, -1, -2) @ (Hf @ C)
    Wx = skew(W)
    Htt[..., 0:3, 3:6] -= Wx
    Htt[..., 3:6, 0:3] += Wx
    return Htt, (P @ C) / nc
