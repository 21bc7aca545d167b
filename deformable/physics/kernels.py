r"""Compiled kernels (numba) of the energy's gradient and Hessian: per point, and summed into element blocks.

The Hessian of eq. (13)'s integrand is the most frequent large computation of the energy-consistent model (one per
Newton iteration). Each point is one loop body that works in scratch arrays, and the projection onto the element (FD:
the six-node stencil) and the scatter into the fixed pattern are compiled loops too.

The formulas are those of :mod:`deformable.physics.integrand` (which documents them): at a point, with slot vectors
d1, d2 (the metric), t1, t2 (the normal) and v11, v22, v12 (the curvature), residuals s = (G11, G22, G12), b = (B11,
B22, B12), weights c (6,), and forces F = 2 c (s, b) - (f0, g0):

- Gauss-Newton: ``sum_r 2 c_r J_r J_r^T``, J_r the residual's gradient in the slots;
- membrane: ``[[2 F11, F12], [F12, 2 F22]] (x I3)`` on (d1, d2) (its positive part for "definite");
- bending: the second derivative of ``V . n``, ``V = sum_k F_bk v_k``, ``n = c / |c|``, ``c = t1 x t2``. With ``W =
  (V - (V . n) n) / |c|``, ``P = I - n n^T``, ``C = [-[t2]x, [t1]x]``: ``Htt = C^T Hf C + [[0, -[W]x], [[W]x, 0]]``,
  ``Hf = -(W n^T + n W^T) / |c| - (V . n) P / |c|^2``, and the mixed blocks ``F_bk P C / |c|`` between v_k and (t1,
  t2);
- "projected": the whole point Hessian projected onto its positive part by an eigen-decomposition (Teran et al.
  2005; Li et al. 2020), :func:`positive_part` (numpy: LAPACK's batched eigh, and no LAPACK to compile).

The gradient at a point is ``sum_r F_r J_r`` with the same Jacobian (:func:`point_gradients`), and its value
:func:`energy_sums`. Kinds are integers here: :data:`KINDS`.
"""

from __future__ import annotations

import numpy as np
from numba import njit

__all__ = ["KINDS", "energy_sums", "point_gradients", "point_hessians", "element_upper", "positive_part",
           "positive_part_2x2", "cross_into", "skew_into", "project_upper", "row_starts", "add_bending_second_order",
           "cached"]

#: Hessian kind name -> the kernels' code
KINDS = {"newton": 0, "gauss-newton": 1, "definite": 2, "projected": 3}


@njit(cache=True)
def positive_part_2x2(a, b, d):
    """The positive semi-definite part of [[a, b], [b, d]] as (a', b', d')."""
    mean, half = 0.5 * (a + d), np.hypot(0.5 * (a - d), b)
    lam1, lam2 = mean + half, mean - half
    if lam2 >= 0.0:
        return a, b, d
    if lam1 <= 0.0:
        return 0.0, 0.0, 0.0
    # the eigenvector of lam1: (b, lam1 - a) or (lam1 - d, b), whichever is better conditioned
    if abs(lam1 - a) >= abs(lam1 - d):
        u0, u1 = b, lam1 - a
    else:
        u0, u1 = lam1 - d, b
    s = 1.0 / (u0 * u0 + u1 * u1)
    return lam1 * u0 * u0 * s, lam1 * u0 * u1 * s, lam1 * u1 * u1 * s


@njit(cache=True)
def cross_into(a, b, out):
    out[0] = a[1] * b[2] - a[2] * b[1]
    out[1] = a[2] * b[0] - a[0] * b[2]
    out[2] = a[0] * b[1] - a[1] * b[0]


@njit(cache=True)
def skew_into(a, M, r0, c0, sign):
    """M[r0:r0+3, c0:c0+3] += sign [a]x."""
    M[r0 + 0, c0 + 1] -= sign * a[2]
    M[r0 + 0, c0 + 2] += sign * a[1]
    M[r0 + 1, c0 + 0] += sign * a[2]
    M[r0 + 1, c0 + 2] -= sign * a[0]
    M[r0 + 2, c0 + 0] -= sign * a[1]
    M[r0 + 2, c0 + 1] += sign * a[0]


@njit(cache=True)
def _jacobian(v, sl, bend, bending, J, R, sc):
    """Residual values R (6,) (G11, G22, G12, B11, B22, B12) and their Jacobian J (6, 3S) in the slots at one point.

    Returns (number of residuals, |t1 x t2|); the unit normal is left in sc[0]. Without bending only the three
    metric residuals are formed (R[3:] = 0).
    """
    S = v.shape[0]
    for r in range(6):
        for i in range(3 * S):
            J[r, i] = 0.0
    i1, i2 = sl[0], sl[1]
    R[0] = v[i1, 0] * v[i1, 0] + v[i1, 1] * v[i1, 1] + v[i1, 2] * v[i1, 2]
    R[1] = v[i2, 0] * v[i2, 0] + v[i2, 1] * v[i2, 1] + v[i2, 2] * v[i2, 2]
    R[2] = v[i1, 0] * v[i2, 0] + v[i1, 1] * v[i2, 1] + v[i1, 2] * v[i2, 2]
    for a in range(3):
        J[0, 3 * i1 + a] += 2.0 * v[i1, a]
        J[1, 3 * i2 + a] += 2.0 * v[i2, a]
        J[2, 3 * i1 + a] += v[i2, a]
        J[2, 3 * i2 + a] += v[i1, a]
    if not bending:
        R[3] = R[4] = R[5] = 0.0
        return 3, 1.0
    it1, it2 = sl[2], sl[3]
    n, w, t = sc[0], sc[1], sc[2]
    cross_into(v[it1], v[it2], n)
    area = np.sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2])
    for a in range(3):
        n[a] /= area
    for k in range(3):
        ik = bend[k]
        Bk = n[0] * v[ik, 0] + n[1] * v[ik, 1] + n[2] * v[ik, 2]
        R[3 + k] = Bk
        for a in range(3):
            w[a] = (v[ik, a] - Bk * n[a]) / area
        cross_into(v[it2], w, t)
        for a in range(3):
            J[3 + k, 3 * it1 + a] += t[a]
        cross_into(w, v[it1], t)
        for a in range(3):
            J[3 + k, 3 * it2 + a] += t[a]
            J[3 + k, 3 * ik + a] += n[a]
    return 6, area


@njit(cache=True)
def _eq13_forces(R, c, r0, nres, F):
    """F = dW/d(residuals) of eq. (13) at one point: 2 c R - r0 (the rest terms r0 = 2 c R_rest); 0 unformed."""
    for k in range(6):
        F[k] = 2.0 * c[k] * R[k] - r0[k] if k < nres else 0.0


@njit(cache=True)
def _active(J, r, S, act):
    """The slots that residual r touches, into act; their count."""
    na = 0
    for s in range(S):
        if J[r, 3 * s] != 0.0 or J[r, 3 * s + 1] != 0.0 or J[r, 3 * s + 2] != 0.0:
            act[na] = s
            na += 1
    return na


@njit(cache=True)
def _outer_into(H, x0, J, r, q, act, na, actq, nq):
    """H[slots of r, slots of q] += x0 J_r J_q^T over the slots each touches."""
    for p in range(na):
        for u in range(nq):
            sp, sq = act[p], actq[u]
            for a in range(3):
                x = x0 * J[r, 3 * sp + a]
                for b in range(3):
                    H[3 * sp + a, 3 * sq + b] += x * J[q, 3 * sq + b]


@njit(cache=True)
def _clear(H):
    for i in range(H.shape[0]):
        for j in range(H.shape[1]):
            H[i, j] = 0.0


@njit(cache=True)
def add_bending_second_order(v, it1, it2, bend, F, n, area, H, V, W, Cm, Hf, T6, Htt, Q):
    """H (3S, 3S) += the second derivative of ``V . n``, ``V = sum_k F[3 + k] v_k`` (the bending forces F_bk times
    the second-derivative slots), in the normal's tangents (t1, t2) and its mixed blocks with each v_k (module
    docstring); n the unit normal, area = |t1 x t2|; V, W (3,), Cm, T6, Q (3, 6), Hf (3, 3), Htt (6, 6) scratch."""
    for a in range(3):
        V[a] = F[3] * v[bend[0], a] + F[4] * v[bend[1], a] + F[5] * v[bend[2], a]
    Vn = V[0] * n[0] + V[1] * n[1] + V[2] * n[2]
    for a in range(3):
        W[a] = (V[a] - Vn * n[a]) / area
    for a in range(3):
        for b in range(3):
            Pab = (1.0 if a == b else 0.0) - n[a] * n[b]
            Hf[a, b] = -(W[a] * n[b] + n[a] * W[b]) / area - Vn * Pab / (area * area)
    for a in range(3):  # C = [-[t2]x, [t1]x] (3 x 6)
        for b in range(6):
            Cm[a, b] = 0.0
    skew_into(v[it2], Cm, 0, 0, -1.0)
    skew_into(v[it1], Cm, 0, 3, 1.0)
    for a in range(3):  # T6 = Hf C; Htt = C^T T6
        for b in range(6):
            x = 0.0
            for e in range(3):
                x += Hf[a, e] * Cm[e, b]
            T6[a, b] = x
    for a in range(6):
        for b in range(6):
            x = 0.0
            for e in range(3):
                x += Cm[e, a] * T6[e, b]
            Htt[a, b] = x
    skew_into(W, Htt, 0, 3, -1.0)
    skew_into(W, Htt, 3, 0, 1.0)
    for a in range(3):  # Q = P C / |c|
        for b in range(6):
            x = 0.0
            for e in range(3):
                x += ((1.0 if a == e else 0.0) - n[a] * n[e]) * Cm[e, b]
            Q[a, b] = x / area
    tt = (it1, it2)
    for i in range(2):
        for j in range(2):
            for a in range(3):
                for b in range(3):
                    H[3 * tt[i] + a, 3 * tt[j] + b] += Htt[3 * i + a, 3 * j + b]
    for k in range(3):
        ik = bend[k]
        g = F[3 + k]
        for i in range(2):
            for a in range(3):
                for b in range(3):
                    x = g * Q[a, 3 * i + b]
                    H[3 * ik + a, 3 * tt[i] + b] += x
                    H[3 * tt[i] + b, 3 * ik + a] += x


@njit(cache=True)
def _second_order(v, sl, bend, F, kind, bending, area, n, H, sc, Cm, Hf, T6, Htt, Q):
    """Add the residuals' own second derivatives, weighted by the forces F, to H (3S, 3S): the membrane part ``[[2
    F11, F12], [F12, 2 F22]] (x I3)`` on (d1, d2) (its positive part for "definite") and, with bending and not
    "definite", the second derivative of ``V . n``, ``V = sum_k F_bk v_k`` (module docstring)."""
    i1, i2 = sl[0], sl[1]
    m11, m12, m22 = 2.0 * F[0], F[2], 2.0 * F[1]
    if kind == 2:
        m11, m12, m22 = positive_part_2x2(m11, m12, m22)
    for a in range(3):
        H[3 * i1 + a, 3 * i1 + a] += m11
        H[3 * i1 + a, 3 * i2 + a] += m12
        H[3 * i2 + a, 3 * i1 + a] += m12
        H[3 * i2 + a, 3 * i2 + a] += m22
    if kind == 2 or not bending:
        return
    add_bending_second_order(v, sl[2], sl[3], bend, F, n, area, H, sc[3], sc[4], Cm, Hf, T6, Htt, Q)


@njit(cache=True)
def _hessian_into(v, sl, bend, F, Hr, kind, bending, nres, area, J, H, act, sc, Cm, Hf, T6, Htt, Q, actq):
    """H (3S, 3S) = Gauss-Newton ``sum_rq Hr_rq J_r J_q^T`` over the slots each residual touches, plus (unless
    "gauss-newton") the residuals' own second derivatives weighted by the forces F (:func:`_second_order`)."""
    S = v.shape[0]
    _clear(H)
    for r in range(nres):
        na = -1
        for q in range(nres):
            h = Hr[r, q]
            if h == 0.0:
                continue
            if na < 0:
                na = _active(J, r, S, act)
            nq = _active(J, q, S, actq)
            _outer_into(H, h, J, r, q, act, na, actq, nq)
    if kind == 1:
        return
    _second_order(v, sl, bend, F, kind, bending, area, sc[0], H, sc, Cm, Hf, T6, Htt, Q)


@njit(cache=True)
def _point(v, sl, bend, c, r0, kind, bending, J, H, F, act, sc, Cm, Hf, T6, Htt, Q, R, actq, Hr):
    """The Hessian of eq. (13)'s integrand at one point into H (3S, 3S), index 3 slot + coordinate; the rest are
    scratch arrays. Its residual Hessian is diagonal, 2 c."""
    nres, area = _jacobian(v, sl, bend, bending, J, R, sc)
    _eq13_forces(R, c, r0, nres, F)
    for i in range(6):
        for k in range(6):
            Hr[i, k] = 2.0 * c[i] if i == k else 0.0
    _hessian_into(v, sl, bend, F, Hr, kind, bending, nres, area, J, H, act, sc, Cm, Hf, T6, Htt, Q, actq)


@njit(cache=True)
def _point_general(v, sl, bend, Fp, Hr, kind, bending, J, H, F, act, sc, Cm, Hf, T6, Htt, Q, R, actq):
    """The Hessian of a general energy density at one point into H (3S, 3S): the forces Fp (6,) and the residual
    Hessian Hr (6, 6) given (:class:`deformable.physics.integrand.DensityIntegrand`)."""
    nres, area = _jacobian(v, sl, bend, bending, J, R, sc)
    for k in range(6):
        F[k] = Fp[k] if k < nres else 0.0
    _hessian_into(v, sl, bend, F, Hr, kind, bending, nres, area, J, H, act, sc, Cm, Hf, T6, Htt, Q, actq)


@njit(cache=True)
def _scratch(S):
    return (np.zeros((6, 3 * S)), np.zeros((3 * S, 3 * S)), np.zeros(6), np.zeros(S, np.int64), np.zeros((5, 3)),
            np.zeros((3, 6)), np.zeros((3, 3)), np.zeros((3, 6)), np.zeros((6, 6)), np.zeros((3, 6)), np.zeros(6),
            np.zeros(S, np.int64))


@njit(cache=True)
def _gradient_into(J, F, nres, S, g):
    for r in range(nres):
        for s in range(S):
            for a in range(3):
                g[s, a] += F[r] * J[r, 3 * s + a]


@njit(cache=True)
def point_gradients(v, sl, bend, c, r0, bending):
    """dW/d(slots) of eq. (13) at every point, (P, S, 3): sum_r F_r J_r (arguments as :func:`point_hessians`)."""
    P, S = v.shape[0], v.shape[1]
    J, F, R, sc = np.zeros((6, 3 * S)), np.zeros(6), np.zeros(6), np.zeros((5, 3))
    out = np.zeros((P, S, 3))
    for p in range(P):
        nres, _ = _jacobian(v[p], sl, bend, bending, J, R, sc)
        _eq13_forces(R, c[:, p], r0[:, p], nres, F)
        _gradient_into(J, F, nres, S, out[p])
    return out


@njit(cache=True)
def point_gradients_general(v, sl, bend, F, bending):
    """dW/d(slots) at every point, (P, S, 3), from the forces F (6, P) = dW/d(residuals) of a general density."""
    P, S = v.shape[0], v.shape[1]
    J, R, sc = np.zeros((6, 3 * S)), np.zeros(6), np.zeros((5, 3))
    out = np.zeros((P, S, 3))
    for p in range(P):
        nres, _ = _jacobian(v[p], sl, bend, bending, J, R, sc)
        _gradient_into(J, F[:, p], nres, S, out[p])
    return out


@njit(cache=True)
def point_residuals(v, sl, bend, bending):
    """The residual values (G11, G22, G12, B11, B22, B12) at every point, (6, P) (B zero without bending)."""
    P, S = v.shape[0], v.shape[1]
    J, R, sc = np.zeros((6, 3 * S)), np.zeros(6), np.zeros((5, 3))
    out = np.zeros((6, P))
    for p in range(P):
        _jacobian(v[p], sl, bend, bending, J, R, sc)
        for k in range(6):
            out[k, p] = R[k]
    return out


@njit(cache=True)
def energy_sums(v, sl, bend, eta, G0, xi, B0, bending):
    """Eq. (13)'s integrand summed over the points: (stretching, bending) (J).

    ``eta``, ``G0``, ``xi``, ``B0``: (4, P), the components (11, 22, 12, 21) of the weights and rest tensors at each
    point (weights already times the quadrature weights); the metric's and curvature's 12 and 21 components are one
    value (G and B are symmetric), each weighed by its own weight against its own rest value.
    """
    P = v.shape[0]
    R, n = np.zeros(6), np.zeros(3)
    stretching = 0.0
    curving = 0.0
    for p in range(P):
        x = v[p]
        i1, i2 = sl[0], sl[1]
        R[0] = x[i1, 0] * x[i1, 0] + x[i1, 1] * x[i1, 1] + x[i1, 2] * x[i1, 2]
        R[1] = x[i2, 0] * x[i2, 0] + x[i2, 1] * x[i2, 1] + x[i2, 2] * x[i2, 2]
        R[2] = x[i1, 0] * x[i2, 0] + x[i1, 1] * x[i2, 1] + x[i1, 2] * x[i2, 2]
        e = 0.0
        for k in range(4):
            r = R[min(k, 2)] - G0[k, p]
            e += eta[k, p] * r * r
        stretching += e
        if bending:
            # the arithmetic of the rest tensors' (tensors.frame): residuals 0 at rest
            cross_into(x[sl[2]], x[sl[3]], n)
            area = np.sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2])
            for a in range(3):
                n[a] = n[a] / area
            for k in range(3):
                ik = bend[k]
                R[3 + k] = n[0] * x[ik, 0] + n[1] * x[ik, 1] + n[2] * x[ik, 2]
            e = 0.0
            for k in range(4):
                r = R[3 + min(k, 2)] - B0[k, p]
                e += xi[k, p] * r * r
            curving += e
    return stretching, curving


@njit(cache=True, nogil=True)
def point_hessians(v, sl, bend, c, r0, kind, bending):
    """The Hessian of eq. (13)'s integrand at every point, (P, 3S, 3S) (index 3 slot + coordinate).

    Parameters
    ----------
    v : (P, S, 3) slot vectors
    sl : int (4,) positions of d1, d2, t1, t2; ``bend`` int (3,) those of v11, v22, v12
    c, r0 : (6, P) residual weights and their rest terms (f0, g0)
    kind : int, 0 (exact), 1 (Gauss-Newton) or 2 (definite) (:data:`KINDS`; "projected" is the exact one
        projected by the caller, :func:`positive_part`); bending : bool (False: no normal is formed)
    """
    P, S = v.shape[0], v.shape[1]
    J, Hp, F, act, sc, Cm, Hf, T6, Htt, Q, R, actq = _scratch(S)
    out = np.empty((P, 3 * S, 3 * S))
    Hr = np.zeros((6, 6))
    for p in range(P):
        _point(v[p], sl, bend, c[:, p], r0[:, p], kind, bending, J, Hp, F, act, sc, Cm, Hf, T6, Htt, Q, R, actq, Hr)
        out[p] = Hp
    return out


@njit(cache=True, nogil=True)
def point_hessians_general(v, sl, bend, F, Hr, kind, bending):
    """The Hessian of a general density at every point, (P, 3S, 3S): forces F (6, P) and residual Hessians Hr (6, 6,
    P) given (for "gauss-newton" and "definite", Hr positive semi-definite); other arguments as
    :func:`point_hessians`."""
    P, S = v.shape[0], v.shape[1]
    J, Hp, Fs, act, sc, Cm, Hf, T6, Htt, Q, R, actq = _scratch(S)
    out = np.empty((P, 3 * S, 3 * S))
    Hs = np.zeros((6, 6))
    for p in range(P):
        for i in range(6):
            for j in range(6):
                Hs[i, j] = Hr[i, j, p]
        _point_general(v[p], sl, bend, F[:, p], Hs, kind, bending, J, Hp, Fs, act, sc, Cm, Hf, T6, Htt, Q, R,
                       actq)
        out[p] = Hp
    return out


@njit(cache=True)
def row_starts(nl):
    """Offset of row i in the row-major upper triangle of an nl x nl matrix, minus i."""
    start = np.zeros(nl, np.int64)
    for i in range(1, nl):
        start[i] = start[i - 1] + nl - (i - 1)
    for i in range(nl):
        start[i] -= i
    return start


@njit(cache=True)
def project_upper(Hp, B, row, T, start, mask):
    """row += upper triangle of B^T Hp B (x I3): Hp (3S, 3S), B (S, L), row (3L (3L + 1) / 2), T scratch (S, 3, 3L);
    ``mask`` (S, S): the slot blocks of Hp that may be nonzero (the others are skipped), and slots of no element
    node (a zero row of B) skipped too."""
    S, L = B.shape
    nl = 3 * L
    used = np.zeros(S, np.bool_)
    for t in range(S):
        for m in range(L):
            if B[t, m] != 0.0:
                used[t] = True
    # T[s, a, b L + m] = sum_t H[s a, t b] B[t, m]  (inner loops contiguous: vectorised)
    for s in range(S):
        if not used[s]:
            continue
        for a in range(3):
            Tsa = T[s, a]
            for j in range(nl):
                Tsa[j] = 0.0
            for t in range(S):
                if not (used[t] and mask[s, t]):
                    continue
                Bt = B[t]
                for b in range(3):
                    h = Hp[3 * s + a, 3 * t + b]
                    if h != 0.0:
                        for m in range(L):
                            Tsa[b * L + m] += h * Bt[m]
    # row[(a L + l, j)] += sum_s B[s, l] T[s, a, j] for j >= a L + l
    for s in range(S):
        if not used[s]:
            continue
        for q in range(L):
            x = B[s, q]
            if x != 0.0:
                for a in range(3):
                    i = a * L + q
                    base = start[i]
                    Tsa = T[s, a]
                    for j in range(i, nl):
                        row[base + j] += x * Tsa[j]


@njit(cache=True, nogil=True)
def element_upper(H, table, which, element, out):
    """Add every point's Hessian, projected onto its element, to the elements' upper triangles.

    The block of point p on its element e = element[p] is ``B^T H_p B`` (x I3 in the coordinates), ``B =
    table[which[p]]`` (S, L) the coefficients of the element's L local nodes (or basis functions) in the point's
    slots; local index ``a L + l`` (coordinate a), upper entries in ``numpy.triu_indices(3 L)`` order.

    Parameters
    ----------
    H : (P, 3S, 3S) point Hessians (:func:`point_hessians`)
    table : (nB, S, L); which : int (P,); element : int (P,)
    out : (E, 3L (3L + 1) / 2), added to
    """
    S, L = table.shape[1], table.shape[2]
    T = np.zeros((S, 3, 3 * L))
    start = row_starts(3 * L)
    mask = np.ones((S, S), np.bool_)
    for p in range(H.shape[0]):
        project_upper(H[p], table[which[p]], out[element[p]], T, start, mask)


def positive_part(H: np.ndarray) -> np.ndarray:
    """Symmetric matrices (P, n, n) projected onto their positive semi-definite part (an eigen-decomposition)."""
    w, U = np.linalg.eigh(H)
    return (U * np.maximum(w, 0.0)[:, None, :]) @ np.swapaxes(U, 1, 2)


def cached() -> bool:
    """Whether numba's on-disk cache holds :func:`energy_sums`, the kernel every run calls first, for its current
    source: False on a fresh install, an empty NUMBA_CACHE_DIR or an edited module (the run compiles; the cache's
    index file read, a few hundred bytes). True where numba's cache cannot be read so (say nothing, not guess)."""
    try:
        return bool(energy_sums._cache._cache_file._load_index())
    except Exception:  # noqa: BLE001 - numba's private layout moved
        return True
