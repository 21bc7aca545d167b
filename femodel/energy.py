r"""The energy (13) of the finite-element surface, with its exact gradient and Hessians.

The "variational" force model uses the gradient of the energy the paper
writes down instead of the force (14) (docs/design.md: the two differ; under
(14) a flat sheet has no linear bending stiffness); the tpbf87 model reports
this energy too. On the bicubic Hermite field (:mod:`femodel.hermite`) the
energy is integrated by the 4 x 4 Gauss rule of :class:`femodel.FEModel`:

    E(X) = sum_{e, q} w_q  sum_ij  eta_ij (G_ij - G0_ij)^2 + xi_ij (B_ij - B0_ij)^2     (eq. 13)
    G_ij = r_i . r_j                                                             (eq. 4)
    B_ij = n . r_ij,   n = c/|c|,   c = r_1 x r_2                                (eq. 8)

at the Gauss points q of every element e (w_q: Gauss weight times element
area), with the shared integrand :func:`deformable.elasticity.energy_density`.
G0, B0 and eta, xi are the model's fields at the Gauss points.

Derivative slots. At a Gauss point r depends on the 48 local degrees of
freedom only through the five vectors ``v = (r_1, r_2, r_11, r_12, r_22)``,
``v_k = sum_l X_l D_k[l, q]`` with the basis tables ``D_k`` of
:func:`femodel.hermite.basis`. Everything below is written per point in
these 15 numbers (5 slots x 3 coordinates) and then carried to the element
by ``D``: gradient ``g_e[l] = sum_{q,k} D_k[l, q] p_k``, Hessian
``K_e[l, m] = sum_{q,k,k'} D_k[l, q] H_{kk'} D_k'[m, q]``.

Gradient. With ``f_ij = 2 w eta_ij (G_ij - G0_ij)``, ``g_ij = 2 w xi_ij (B_ij - B0_ij)``
(12 and 21 share one residual, G and B being symmetric, so only
``f_12 + f_21`` and ``g_12 + g_21`` enter), and, for a vector v,
``d(v . n) = n . dv + W(v) . dc``, ``W(v) = (v - (v.n) n)/|c|``,
``dc = dr_1 x r_2 + r_1 x dr_2``:

    p_1  = 2 f_11 r_1 + (f_12 + f_21) r_2 + r_2 x W
    p_2  = 2 f_22 r_2 + (f_12 + f_21) r_1 + W x r_1
    p_11 = g_11 n,   p_12 = (g_12 + g_21) n,   p_22 = g_22 n

with ``W = W(V)``, ``V = g_11 r_11 + (g_12 + g_21) r_12 + g_22 r_22`` (W is
linear in v).

Hessian. The energy is a weighted sum of squares of the six residuals
``s_11, s_22, s_12`` (stretching) and ``b_11, b_22, b_12`` (bending), so

    Gauss-Newton:  H = 2 J^T diag(c) J                 (symmetric positive semi-definite)
    exact:         H = 2 J^T diag(c) J + sum_res 2 c res Hess(res)

with weights ``c = w (eta_11, eta_22, eta_12 + eta_21, xi_11, xi_22, xi_12 + xi_21)``
and Jacobian rows (in the slots r_1, r_2, r_11, r_12, r_22)

    s_11: (2 r_1, 0, ...),   s_22: (0, 2 r_2, ...),   s_12: (r_2, r_1, 0, ...)
    b_ij: (r_2 x W(r_ij), W(r_ij) x r_1, n in the slot of r_ij).

The second-order terms: stretching ``sum f Hess(s)`` is ``2 f_11 I`` on
(r_1, r_1), ``(f_12 + f_21) I`` on (r_1, r_2) and (r_2, r_1), ``2 f_22 I`` on
(r_2, r_2). Bending, with ``f(c) = V . c/|c|``, ``P = I - n n^T``,
``C = [-[r_2]x, [r_1]x]`` (so ``dc = C (dr_1, dr_2)``) and
``d2c = 2 dr_1 x dr_2``, the second differential

    d2 (V . n) = (C dt)^T Hess f (C dt) + 2 W . (dr_1 x dr_2) + 2 sum_k g_k dv_k . P C dt / |c|,
    Hess f = -(W n^T + n W^T)/|c| - (V.n) P/|c|^2,

dt = (dr_1, dr_2), the same 9 x 9 form per point as in the FD module
(:mod:`fdmodel.energy`), here spread over the three second-derivative
slots with their weights g_11, g_12 + g_21, g_22.

Vectors and matrices are coordinate-blocked: flat index ``a * ndof + k`` for
coordinate a of degree of freedom k; the Hessian is assembled on a fixed
pattern (:class:`deformable.assembly.SymmetricElements` over the 48 = 3 x 16 local
degrees of freedom of an element),
element blocks in one batched product.
"""

from __future__ import annotations

import numpy as np
import scipy.sparse as sp

from deformable import tensors
from deformable.assembly import SymmetricElements, element_vectors
from deformable.backend import Energy
from deformable.elasticity import energy_density

from .hermite import DERIVATIVES, evaluate, surface_tensors

__all__ = ["DiscreteEnergy", "HESSIANS", "SLOTS"]

HESSIANS = ("gauss-newton", "newton")
#: derivative orders (d1, d2) of the five slots: r_1, r_2, r_11, r_12, r_22
SLOTS = DERIVATIVES[1:]
#: elements per block in the Hessian assembly (small enough that the point and element Hessians stay in cache: 8x faster than one block of 1024)
_BLOCK = 64


class DiscreteEnergy:
    """Energy (13) of a bicubic Hermite field by the Gauss rule (module docstring).

    Parameters
    ----------
    ldofs : int array (E, 16)
        Global degrees of freedom of every element.
    ndof : int
    dq : dict (d1, d2) -> (16, nq)
        Shape-function derivatives at the Gauss points (:func:`femodel.hermite.basis`).
    weights : array (nq,)
        Gauss weights times the element area.
    eta, xi, G0, B0 : arrays (2, 2, E, nq)
        Weights and rest tensors at the Gauss points.
    """

    def __init__(self, ldofs: np.ndarray, ndof: int, dq: dict, weights: np.ndarray, eta: np.ndarray,
                 xi: np.ndarray, G0: np.ndarray, B0: np.ndarray):
        self.ldofs, self.ndof = ldofs, ndof
        nq = weights.size
        self.tables = [dq[d] for d in SLOTS]
        self.D = np.stack(self.tables).transpose(2, 0, 1).copy()  # (nq, 5, 16)
        self.Dflat = self.D.reshape(nq * 5, 16)  # rows (q, k)
        self.weights, self.eta, self.xi, self.G0, self.B0 = weights, eta, xi, G0, B0
        w = weights[None, :]  # (1, nq)
        # residual weights c (times the Gauss weight): 11, 22, and 12 + 21 sharing one residual
        self.cS = np.stack([eta[0, 0], eta[1, 1], eta[0, 1] + eta[1, 0]]) * w  # (3, E, nq)
        self.cB = np.stack([xi[0, 0], xi[1, 1], xi[0, 1] + xi[1, 0]]) * w
        self.bending = bool(np.any(xi != 0))  # False: no normal is formed (degenerate tangents allowed)
        # 2 w (eta_12 (G12 - G0_12) + eta_21 (G12 - G0_21)) = 2 c_12 G12 - 2 w (eta_12 G0_12 + eta_21 G0_21)
        self.fS0 = 2 * np.stack([eta[0, 0] * G0[0, 0], eta[1, 1] * G0[1, 1],
                                 eta[0, 1] * G0[0, 1] + eta[1, 0] * G0[1, 0]]) * w
        self.fB0 = 2 * np.stack([xi[0, 0] * B0[0, 0], xi[1, 1] * B0[1, 1],
                                 xi[0, 1] * B0[0, 1] + xi[1, 0] * B0[1, 0]]) * w
        self._scatter = element_vectors(ldofs, ndof)
        self._pattern = None

    # -- pieces -------------------------------------------------------------
    @property
    def pattern(self) -> SymmetricElements:
        """Fixed CSR pattern of the coordinate-blocked Hessian (3 ndof, 3 ndof), built on first use."""
        if self._pattern is None:
            ld48 = np.concatenate([a * self.ndof + self.ldofs for a in range(3)], axis=1)  # (E, 48): index a 16 + l
            self._pattern = SymmetricElements(ld48, 3 * self.ndof)
        return self._pattern

    def slots(self, X: np.ndarray) -> np.ndarray:
        """r_1, r_2, r_11, r_12, r_22 at the Gauss points, (E, nq, 5, 3)."""
        d = evaluate(X, self.ldofs, self.tables)  # (3, 5, E, nq)
        return np.ascontiguousarray(d.transpose(2, 3, 1, 0))

    def energy(self, X: np.ndarray) -> Energy:
        """(stretching, bending) parts of E (J), eq. (13) by the Gauss rule."""
        G, B = surface_tensors(evaluate(X, self.ldofs, self.tables), self.bending)
        stretching, bending = energy_density(self.eta, self.xi, G, self.G0, B, self.B0)
        return Energy(float(np.sum(stretching * self.weights)), float(np.sum(bending * self.weights)))

    def _forces(self, v: np.ndarray, sl=slice(None)):
        """Per-point quantities of the module docstring for the elements ``sl``.

        Returns
        -------
        f : (3, Ec, nq)    f_11, f_22, f_12 + f_21 (J per unit G)
        g : (3, Ec, nq)    g_11, g_22, g_12 + g_21 (J per unit B), zeros without bending
        frame : tuple or None
            (n, |c|) with n (Ec, nq, 3), |c| (Ec, nq); None without bending.
        """
        t1, t2 = v[..., 0, :], v[..., 1, :]
        G = np.stack([tensors.dot(t1, t1), tensors.dot(t2, t2), tensors.dot(t1, t2)])
        f = 2 * self.cS[:, sl] * G - self.fS0[:, sl]
        if not self.bending:
            return f, np.zeros_like(f), None
        n, nc = tensors.frame(t1, t2)
        B = np.stack([tensors.dot(n, v[..., 2, :]), tensors.dot(n, v[..., 4, :]), tensors.dot(n, v[..., 3, :])])
        g = 2 * self.cB[:, sl] * B - self.fB0[:, sl]
        return f, g, (n, nc)

    @staticmethod
    def _bend_slot(g):
        """Weights of the slots r_11, r_12, r_22 from (g_11, g_22, g_12 + g_21)."""
        return g[0], g[2], g[1]

    # -- energy, gradient, Hessian --------------------------------------------
    def gradient(self, X: np.ndarray) -> np.ndarray:
        """Exact gradient dE/dX, (ndof, 3) (J per unit of the degrees of freedom, i.e. N)."""
        v = self.slots(X)
        f, g, frame = self._forces(v)
        t1, t2 = v[..., 0, :], v[..., 1, :]
        p = np.zeros_like(v)
        p[..., 0, :] = 2 * f[0][..., None] * t1 + f[2][..., None] * t2
        p[..., 1, :] = 2 * f[1][..., None] * t2 + f[2][..., None] * t1
        if frame is not None:
            n, nc = frame
            g11, g12, g22 = self._bend_slot(g)
            V = g11[..., None] * v[..., 2, :] + g12[..., None] * v[..., 3, :] + g22[..., None] * v[..., 4, :]
            W = (V - tensors.dot(V, n)[..., None] * n) / nc[..., None]
            p[..., 0, :] += np.cross(t2, W)
            p[..., 1, :] += np.cross(W, t1)
            p[..., 2, :] = g11[..., None] * n
            p[..., 3, :] = g12[..., None] * n
            p[..., 4, :] = g22[..., None] * n
        E, nq = p.shape[:2]
        local = self.Dflat.T @ p.reshape(E, nq * 5, 3)  # (E, 16, 3)
        return self._scatter @ local.reshape(-1, 3)

    def point_hessian(self, v: np.ndarray, kind: str, sl=slice(None)) -> np.ndarray:
        """Hessian of the integrand w.r.t. the 15 slot values at every point, (Ec, nq, 15, 15).

        Index ``3 k + a`` for coordinate a of slot k (r_1, r_2, r_11, r_12, r_22);
        includes the Gauss weight.
        """
        Ec, nq = v.shape[:2]
        t1, t2 = v[..., 0, :], v[..., 1, :]
        f, g, frame = self._forces(v, sl)
        # Jacobian rows of the six residuals, (Ec, nq, 6, 5, 3), and their weights 2 c
        J = np.zeros((Ec, nq, 6, 5, 3))
        J[:, :, 0, 0] = 2 * t1
        J[:, :, 1, 1] = 2 * t2
        J[:, :, 2, 0] = t2
        J[:, :, 2, 1] = t1
        cw = [self.cS[0, sl], self.cS[1, sl], self.cS[2, sl]]
        if frame is not None:
            n, nc = frame
            for res, (slot, k) in enumerate(((2, 0), (4, 1), (3, 2))):  # b_11, b_22, b_12
                vk = v[..., slot, :]
                w = (vk - tensors.dot(vk, n)[..., None] * n) / nc[..., None]
                J[:, :, 3 + res, 0] = np.cross(t2, w)
                J[:, :, 3 + res, 1] = np.cross(w, t1)
                J[:, :, 3 + res, slot] = n
                cw.append(self.cB[k, sl])
        nres = len(cw)
        J = J[:, :, :nres].reshape(Ec, nq, nres, 15)
        cw = 2 * np.stack(cw, axis=-1)  # (Ec, nq, nres)
        H = (np.swapaxes(J, -1, -2) * cw[..., None, :]) @ J
        if kind == "gauss-newton":
            return H
        H = H.reshape(Ec, nq, 5, 3, 5, 3)
        I3 = np.eye(3)
        H[:, :, 0, :, 0, :] += 2 * f[0][..., None, None] * I3
        H[:, :, 1, :, 1, :] += 2 * f[1][..., None, None] * I3
        H[:, :, 0, :, 1, :] += f[2][..., None, None] * I3
        H[:, :, 1, :, 0, :] += f[2][..., None, None] * I3
        if frame is not None:
            n, nc = frame
            g11, g12, g22 = self._bend_slot(g)
            V = g11[..., None] * v[..., 2, :] + g12[..., None] * v[..., 3, :] + g22[..., None] * v[..., 4, :]
            Htt, Q = tensors.normal_hessian(t1, t2, V)
            H = H.reshape(Ec, nq, 15, 15)
            H[..., :6, :6] += Htt
            for slot, gk in ((2, g11), (3, g12), (4, g22)):
                block = gk[..., None, None] * Q
                H[..., 3 * slot:3 * slot + 3, :6] += block
                H[..., :6, 3 * slot:3 * slot + 3] += np.swapaxes(block, -1, -2)
        return H.reshape(Ec, nq, 15, 15)

    def element_matrices(self, H: np.ndarray) -> np.ndarray:
        """Element Hessians from point Hessians (Ec, nq, 15, 15): (Ec, 48, 48), index a 16 + l."""
        Ec, nq = H.shape[:2]
        H = H.reshape(Ec, nq, 5, 3, 5, 3).transpose(0, 1, 2, 3, 5, 4).reshape(Ec, nq, 45, 5)
        T = H @ self.D  # (Ec, nq, 45, 16): [e, q, (k, a, b), m]
        T = T.reshape(Ec, nq, 5, 3, 3, 16).transpose(0, 3, 4, 5, 1, 2).reshape(Ec, 144, nq * 5)
        K = T @ self.Dflat  # (Ec, 144, 16): [e, (a, b, m), l]
        return K.reshape(Ec, 3, 3, 16, 16).transpose(0, 1, 4, 2, 3).reshape(Ec, 48, 48)

    def hessian(self, X: np.ndarray, kind: str = "newton") -> sp.csr_matrix:
        """Hessian (3 ndof, 3 ndof), coordinate-blocked, on a fixed pattern.

        ``"gauss-newton"``: ``2 J^T diag(c) J``, symmetric positive semi-definite.
        ``"newton"``: the exact Hessian (may be indefinite, e.g. under compression).
        """
        if kind not in HESSIANS:
            raise ValueError(f"hessian kind must be one of {HESSIANS}, got {kind!r}")
        v = self.slots(X)
        pat = self.pattern
        iu = pat.upper
        E = v.shape[0]
        upper = np.empty((E, iu[0].size))
        for lo in range(0, E, _BLOCK):  # blocks of elements bound the memory of the point Hessians
            sl = slice(lo, min(lo + _BLOCK, E))
            Ke = self.element_matrices(self.point_hessian(v[sl], kind, sl))
            upper[sl] = Ke[:, iu[0], iu[1]]
        return pat.matrix(pat.collect(upper))
