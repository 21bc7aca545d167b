r"""The Hessian of eq. (13)'s integrand at a point, block by block, and carried to its element (compiled).

The general kernels of :mod:`deformable.physics.kernels` form a point's Hessian from a dense Jacobian of the six
residuals in all 3S slot coordinates, a residual Hessian and the slots each residual touches, found by scanning:
they serve any energy density. Eq. (13)'s own integrand, the one every shipped scene steps, has a diagonal residual
Hessian ``2 c`` and residuals that touch known slots, so its Hessian is written here 3 x 3 block by 3 x 3 block (the
formulas of :mod:`deformable.physics.integrand`, in the same order as the general kernels'):

- the metric (G11 = d1 . d1, G22 = d2 . d2, G12 = d1 . d2): Gauss-Newton ``2 c_r J_r J_r^T`` on the blocks of (d1,
  d2), and the membrane's second order ``[[2 F11, F12], [F12, 2 F22]] (x I3)`` (its positive part for "definite");
- the curvature (B_k = n . v_k, n = t1 x t2 / |t1 x t2|): Gauss-Newton on the blocks of (t1, t2, v_k), with ``J_k =
  (t2 x w_k, w_k x t1, n)``, ``w_k = (v_k - B_k n) / |t1 x t2|``, and (exact Hessian only) the second derivative of
  ``V . n``, ``V = sum_k F_bk v_k``, on (t1, t2) and its mixed blocks with each v_k.

A point's Hessian is then carried to its element (``B^T H B`` (x I3), B the slots' coefficients in the element's
local nodes) by :func:`deformable.physics.kernels.element_upper`'s projection, over the slot blocks eq. (13) fills
and the stencil's nonzero coefficients only, in the same loop (:func:`element_hessians`): no array of point
Hessians.
"""

from __future__ import annotations

import numpy as np
from numba import njit

from .kernels import add_bending_second_order, cross_into, positive_part_2x2, project_upper, row_starts

__all__ = ["point_hessians", "element_hessians", "slot_blocks"]


@njit(cache=True)
def _outer(H, s, t, a, b, scale):
    """H[3 s:3 s + 3, 3 t:3 t + 3] += scale a b^T."""
    for i in range(3):
        x = scale * a[i]
        for j in range(3):
            H[3 * s + i, 3 * t + j] += x * b[j]


@njit(cache=True)
def _identity(H, s, t, scale):
    """H[3 s:3 s + 3, 3 t:3 t + 3] += scale I."""
    for i in range(3):
        H[3 * s + i, 3 * t + i] += scale


@njit(cache=True)
def _hessian(x, sl, bend, c, r0, kind, bending, H, sc, Cm, Hf, T6, Htt, Q, F):
    """Eq. (13)'s integrand's Hessian at one point into H (3S, 3S), cleared first (module docstring).

    x (S, 3): the point's slot vectors; c, r0 (6,): the residual weights and rest terms; kind 0 exact, 1
    Gauss-Newton, 2 definite; the rest scratch: sc (6, 3), Cm (3, 6), Hf (3, 3), T6 (3, 6), Htt (6, 6), Q (3, 6), F
    (6,) (the bending forces F[3:]).
    """
    for i in range(H.shape[0]):
        for j in range(H.shape[1]):
            H[i, j] = 0.0
    i1, i2, it1, it2 = sl[0], sl[1], sl[2], sl[3]
    d1, d2 = x[i1], x[i2]
    R0 = d1[0] * d1[0] + d1[1] * d1[1] + d1[2] * d1[2]
    R1 = d2[0] * d2[0] + d2[1] * d2[1] + d2[2] * d2[2]
    R2 = d1[0] * d2[0] + d1[1] * d2[1] + d1[2] * d2[2]
    _outer(H, i1, i1, d1, d1, 8.0 * c[0])
    _outer(H, i2, i2, d2, d2, 8.0 * c[1])
    g = 2.0 * c[2]
    _outer(H, i1, i1, d2, d2, g)
    _outer(H, i1, i2, d2, d1, g)
    _outer(H, i2, i1, d1, d2, g)
    _outer(H, i2, i2, d1, d1, g)
    if kind != 1:
        m11, m12, m22 = 2.0 * (2.0 * c[0] * R0 - r0[0]), 2.0 * c[2] * R2 - r0[2], 2.0 * (2.0 * c[1] * R1 - r0[1])
        if kind == 2:
            m11, m12, m22 = positive_part_2x2(m11, m12, m22)
        _identity(H, i1, i1, m11)
        _identity(H, i1, i2, m12)
        _identity(H, i2, i1, m12)
        _identity(H, i2, i2, m22)
    if not bending:
        return
    n, w, a1, a2 = sc[0], sc[1], sc[2], sc[3]
    t1, t2 = x[it1], x[it2]
    cross_into(t1, t2, n)
    area = np.sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2])
    for a in range(3):
        n[a] /= area
    for k in range(3):
        ik = bend[k]
        vk = x[ik]
        Bk = n[0] * vk[0] + n[1] * vk[1] + n[2] * vk[2]
        F[3 + k] = 2.0 * c[3 + k] * Bk - r0[3 + k]
        for a in range(3):
            w[a] = (vk[a] - Bk * n[a]) / area
        cross_into(t2, w, a1)
        cross_into(w, t1, a2)
        g = 2.0 * c[3 + k]
        _outer(H, it1, it1, a1, a1, g)
        _outer(H, it1, it2, a1, a2, g)
        _outer(H, it2, it1, a2, a1, g)
        _outer(H, it2, it2, a2, a2, g)
        _outer(H, it1, ik, a1, n, g)
        _outer(H, ik, it1, n, a1, g)
        _outer(H, it2, ik, a2, n, g)
        _outer(H, ik, it2, n, a2, g)
        _outer(H, ik, ik, n, n, g)
    if kind == 0:
        add_bending_second_order(x, it1, it2, bend, F, n, area, H, sc[4], sc[5], Cm, Hf, T6, Htt, Q)


@njit(cache=True)
def slot_blocks(S, sl, bend, bending):
    """Which slot blocks (s, t) of a point's Hessian eq. (13) may fill, (S, S) bool."""
    mask = np.zeros((S, S), np.bool_)
    for s in (sl[0], sl[1]):
        for t in (sl[0], sl[1]):
            mask[s, t] = True
    if bending:
        for k in range(3):
            for s in (sl[2], sl[3], bend[k]):
                for t in (sl[2], sl[3], bend[k]):
                    mask[s, t] = True
    return mask


@njit(cache=True)
def _scratch():
    return (np.zeros((6, 3)), np.zeros((3, 6)), np.zeros((3, 3)), np.zeros((3, 6)), np.zeros((6, 6)),
            np.zeros((3, 6)), np.zeros(6))


@njit(cache=True, nogil=True)
def point_hessians(v, sl, bend, c, r0, kind, bending):
    """The Hessian of eq. (13)'s integrand at every point, (P, 3S, 3S) (index 3 slot + coordinate); the arguments of
    :func:`deformable.physics.kernels.point_hessians` (kind 0, 1 or 2)."""
    P, S = v.shape[0], v.shape[1]
    sc, Cm, Hf, T6, Htt, Q, F = _scratch()
    out = np.empty((P, 3 * S, 3 * S))
    for p in range(P):
        _hessian(v[p], sl, bend, c[:, p], r0[:, p], kind, bending, out[p], sc, Cm, Hf, T6, Htt, Q, F)
    return out


@njit(cache=True, nogil=True)
def element_hessians(v, sl, bend, c, r0, kind, bending, table, which, element, out):
    """Add every point's Hessian of eq. (13)'s integrand, carried to its element, to the elements' upper triangles
    ``out`` (E, 3L (3L + 1) / 2): :func:`point_hessians` and :func:`deformable.physics.kernels.element_upper` in one
    loop (no array of point Hessians), the projection over the slot blocks eq. (13) fills (kind 0, 1 or 2;
    ``table``, ``which``, ``element`` as element_upper's)."""
    P, S, L = v.shape[0], v.shape[1], table.shape[2]
    sc, Cm, Hf, T6, Htt, Q, F = _scratch()
    H = np.zeros((3 * S, 3 * S))
    T = np.zeros((S, 3, 3 * L))
    start = row_starts(3 * L)
    mask = slot_blocks(S, sl, bend, bending)
    for p in range(P):
        _hessian(v[p], sl, bend, c[:, p], r0[:, p], kind, bending, H, sc, Cm, Hf, T6, Htt, Q, F)
        project_upper(H, table[which[p]], out[element[p]], T, start, mask)
