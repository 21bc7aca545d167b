r"""The finite-element discretisation: bicubic Hermite elements on the sheet's node grid.

Mesh: ``skfem.MeshQuad.init_tensor`` on the node coordinates of the sheet, so
the mesh vertices are the M x N nodes of the finite-difference grid and the
(M - 1) x (N - 1) elements are its cells. One scalar C1 space
(:mod:`femodel.hermite`) is shared by x, y and z; a state X is
``(ndof, 3)`` with ``ndof = 4 M N``, row ``4 (m N + n) + k`` holding, at node
(m, n), ``r`` (k = 0), ``h1 r_1`` (k = 1), ``h2 r_2`` (k = 2) and
``h1 h2 r_12`` (k = 3): derivative degrees of freedom scaled by the element
size, so all are lengths.

At the 4 x 4 Gauss points of every element, from the current r:

- metric, eq. (4):    ``G_ij = r_i . r_j``
- curvature, eq. (8): ``B_ij = n . r_ij``, ``n = r_1 x r_2 / |r_1 x r_2|``
- eq. (15):           ``alpha_ij = eta_ij (G_ij - G0_ij)``, ``beta_ij = xi_ij (B_ij - B0_ij)``

(``"tpbf87"``), or alpha, beta given by the Material (``"frozen"``, section
3.2). G0 and B0 are those of the *discretised* rest shape at the same points,
so the rest state carries no internal force, unless the scene overrides them
(``rest_metric``, ``rest_curvature``). Per-node material arrays are
interpolated bilinearly to the Gauss points.

The semi-discrete system (21) ``M R'' + C R' + K(r) R = F`` comes from the
weak form of eq. (14) (:mod:`femodel.assembly`):

    K(u, v) = integral alpha_ij u_j v_i + beta_ij u_ij v_ij,
    M(u, v) = integral mu u v,   C(u, v) = integral gamma u v,
    F(v)    = integral f v  +  edge integral q v  +  P v(a_P),

so K, M, C are integrated (consistent) matrices and F integrated loads; the
kinetic energy is ``V^T M V / 2`` and, for the frozen model, the elastic
energy ``R^T K R / 2``; for tpbf87 the energy of eq. (13) is integrated with
the same Gauss rule.

``force_model="variational"``: no K(r); the internal force is the exact
gradient of that Gauss-rule energy (13), normal's dependence on r included,
with a Gauss-Newton and an exact Hessian (3 ndof, 3 ndof) for the implicit
steps and :func:`deformable.equilibrium` (:mod:`femodel.variational`).
Measured (2 shared cores, hanging sheet, dt = 1e-2): Hessian assembly 0.02 s
at 16 x 16 elements, 0.12 s at 32 x 32; an implicit-Euler step 0.37 s and
4.5 s (3 Newton iterations; SuperLU of the 13 068-dof Newton matrix, 1.1 s
each, is 75 % of the step).

Constraints act on degrees of freedom: a pinned node fixes its value; a pin
named by an edge also fixes the derivative along the edge (r is then known
along the whole edge, so is its tangential derivative; the cross derivative
r_12 stays free); a slide does the same for the two other components; a
clamp fixes all four degrees of freedom of its edge nodes (value and tangent
plane); prescribed motion translates value degrees of freedom only. The clamp
so also holds the tangential components of r_1 (the in-plane stretch at the
edge), which the continuous energy leaves free: measured on the variational
clamped strip, nodal errors O(h^3) with it, O(h^4) with only the normal
components of r_1, r_12 held (tests/femodel/test_variational.py).

Stability with the stepper of eq. (22)-(27): alpha is lagged, so stretching
is explicit (DESIGN.md, findings). With bicubic Hermite elements and the
consistent mass the largest eigenvalue of ``integral u_1 v_1`` against
``integral u v`` is about 91/h1^2 (the FD pair D1+^T D1+, diag(1): 4/h1^2),
so the usable dt is about ``0.21 h sqrt(mu / (2 eta G))``, some 5 times below
the FD bound. Measured on a hanging 8 x 8 element sheet (eta = 50, mu = 0.1):
stable at dt = 6e-4, diverges at 9e-4 (bound 8.3e-4).

Assembly cost: K's data is linear in the six coefficient fields
(alpha_11, alpha_12, alpha_22, beta_11, beta_12 + beta_21, beta_22) at the
Gauss points; :class:`femodel.assembly.FixedPattern` maps them to K.data by
one dense product with precomputed element tables and one sparse scatter, on
a pattern built once. Measured at 64 x 64 elements (16 900 dofs, 2 shared
cores), TimeStepper.timings per step: assembly 14 ms (18 ms with bending),
factorisation 191 ms, solve 17 ms, so assembly is 6-8 % of the step.
"""

from __future__ import annotations

import logging
import time

import numpy as np
import scipy.sparse as sp
import skfem
from skfem.quadrature import get_quadrature_line

from deformable import tensors
from deformable.backend import Energy, Sample
from deformable.constraints import EDGES, Clamp, Pin, Slide, select
from deformable.scene import Scene
from deformable.sheet import as_surface

from .assembly import FixedPattern, bending, mass, membrane
from .hermite import DERIVATIVES, LOCAL, NODE_DOFS, basis
from .variational import DiscreteEnergy

__all__ = ["FEModel", "ELEMENTS"]

log = logging.getLogger(__name__)

#: element families FEModel supports
ELEMENTS = ("hermite",)
#: Gauss points per direction and element (exact for the consistent mass of bicubics)
GAUSS_POINTS = 4
#: local derivative degree of freedom along each edge (k = 1: h1 r_1, k = 2: h2 r_2)
_TANGENTIAL = {"bottom": 1, "top": 1, "left": 2, "right": 2}
#: points per chunk in :meth:`FEModel.sample` (bounds its memory)
_CHUNK = 1 << 15


def _edges_named(where) -> list[str]:
    """The edge names in a selection (a name or a list of names); [] for any other selection."""
    if isinstance(where, str):
        return [where] if where in EDGES else []
    if isinstance(where, (list, tuple)) and all(isinstance(w, str) for w in where):
        return [w for w in where if w in EDGES]
    return []


class FEModel:
    """Finite-element backend; satisfies :class:`deformable.Backend`.

    Parameters
    ----------
    scene : deformable.Scene
    element : str
        Element family, one of :data:`ELEMENTS` ("hermite": bicubic Hermite,
        Bogner-Fox-Schmit, on the reference square; see :mod:`femodel.hermite`).

    Attributes
    ----------
    mesh : skfem.MeshQuad
        The tensor mesh on the sheet's nodes.
    ndof : int
        4 M N degrees of freedom per coordinate.
    a1q, a2q : arrays (E, nq)
        Parameter coordinates of the Gauss points, element e = i (N - 1) + j.
    weights : array (nq,)
        Gauss weights times the element area h1 h2.
    pattern : femodel.assembly.FixedPattern
        The CSR pattern shared by K, M and C.
    measure : float
        1: rows of K, M, C, F are integrated already (FD: h1 h2).
    """

    #: the tpbf87 step is stable on stretching for dt below about step_factor h sqrt(mu / (2 eta G)):
    #: the consistent Hermite mass makes the stiffest stretching mode ~91/h^2 against FD's 4/h^2
    step_factor = 0.21

    def __init__(self, scene: Scene, element: str = "hermite"):
        if element not in ELEMENTS:
            raise ValueError(f"element must be one of {ELEMENTS}, got {element!r}")
        start = time.perf_counter()
        self.scene, self.element = scene, element
        sheet, mat = scene.sheet, scene.material
        self.M, self.N = M, N = sheet.nodes
        self.h1, self.h2 = sheet.h
        self.ndof = NODE_DOFS * M * N
        self.measure = 1.0  # K, M, C and F are integrated already: rows carry no area factor
        self.linear = scene.force_model == "frozen"
        self.mesh = skfem.MeshQuad.init_tensor(*sheet.axes())
        self._build_elements()
        self._build_quadrature()

        self.pattern = FixedPattern(self.ldofs, self.ndof)
        self._T_membrane = self.pattern.templates(membrane(self.dq), self.weights)
        self._T_stiffness = np.concatenate([self._T_membrane, self.pattern.templates(bending(self.dq), self.weights)])
        T_mass = self.pattern.templates(mass(self.dq), self.weights)
        self.mu = self.to_quadrature(mat.field("mu", (M, N)))
        self.gamma = self.to_quadrature(mat.field("gamma", (M, N)))
        self._M = self.pattern.matrix(self.pattern.data(self.mu, T_mass))
        self._C = self.pattern.matrix(self.pattern.data(self.gamma, T_mass))
        # scatter of element load vectors (E 16) into the global vector (ndof)
        E = self.ldofs.shape[0]
        self._gather_t = sp.csr_matrix(
            (np.ones(E * 16), (self.ldofs.ravel(), np.arange(E * 16))), shape=(self.ndof, E * 16)
        )

        # rest state at the Gauss points: the discretised rest shape, or the scene's overrides
        self._energy = None  # the discrete energy (13) with its derivatives ("variational")
        if scene.force_model == "frozen":
            self.alpha_fixed = self.to_quadrature(mat.tensor("alpha", (M, N)))
            self.beta_fixed = self.to_quadrature(mat.tensor("beta", (M, N)))
            self._bending = bool(np.any(self.beta_fixed != 0))
            self._K_const = self._assemble(self.alpha_fixed, self.beta_fixed)
        else:
            self.eta = self.to_quadrature(mat.tensor("eta", (M, N)))
            self.xi = self.to_quadrature(mat.tensor("xi", (M, N)))
            self._bending = bool(np.any(self.xi != 0))
            G, B = self.tensors(self.discretize(sheet.rest), curvature=True)
            self.G0, self.B0 = scene.rest_tensors(self.a1q, self.a2q, G, B)
        self._energy = DiscreteEnergy(self) if scene.force_model == "variational" else None
        self._build_constraints()
        log.debug("FEModel %d x %d elements, %d dofs, nnz %d, built in %.3f s",
                  M - 1, N - 1, self.ndof, self.pattern.nnz, time.perf_counter() - start)

    # -- mesh, elements, quadrature -----------------------------------------
    def _build_elements(self):
        """Element (i, j) and its 16 global degrees of freedom, from the skfem mesh."""
        M, N = self.M, self.N
        p, t = self.mesh.p, self.mesh.t
        m = np.rint(p[0] / self.h1).astype(np.int64)
        n = np.rint(p[1] / self.h2).astype(np.int64)
        a1, a2 = self.scene.sheet.axes()
        if not (np.allclose(p[0], a1[m], rtol=0, atol=1e-12 * a1[-1])
                and np.allclose(p[1], a2[n], rtol=0, atol=1e-12 * a2[-1])):
            raise RuntimeError("skfem mesh vertices do not coincide with the sheet's nodes")
        i, j = m[t].min(axis=0), n[t].min(axis=0)
        order = np.argsort(i * (N - 1) + j)
        self.elem_ij = np.stack([i[order], j[order]], axis=1)  # (E, 2), e = i (N - 1) + j
        corner = np.array([(a, b) for a, b, _, _ in LOCAL])
        k = np.array([p_ + 2 * q_ for _, _, p_, q_ in LOCAL])
        nodes = (self.elem_ij[:, :1] + corner[None, :, 0]) * N + (self.elem_ij[:, 1:] + corner[None, :, 1])
        self.ldofs = NODE_DOFS * nodes + k[None, :]  # (E, 16)

    def _build_quadrature(self):
        """Tensor Gauss rule on the reference square, its points on every element, shape tables."""
        x, w = get_quadrature_line(2 * GAUSS_POINTS - 1)
        x, w = x[0], w
        self.qs = np.repeat(x, x.size)  # (nq,), s-major
        self.qt = np.tile(x, x.size)
        self.weights = np.repeat(w, w.size) * np.tile(w, w.size) * self.h1 * self.h2
        i, j = self.elem_ij[:, 0:1], self.elem_ij[:, 1:2]
        self.a1q = (i + self.qs[None]) * self.h1  # (E, nq)
        self.a2q = (j + self.qt[None]) * self.h2
        h = (self.h1, self.h2)
        self.dq = {d: basis(self.qs, self.qt, h, d) for d in DERIVATIVES}  # (16, nq) each

    def to_quadrature(self, field: np.ndarray) -> np.ndarray:
        """Bilinear interpolation of a node field (..., M, N) to the Gauss points (..., E, nq)."""
        i, j = self.elem_ij[:, 0], self.elem_ij[:, 1]
        s, t = self.qs, self.qt
        field = np.asarray(field, float)

        def f(di, dj):
            return field[..., i + di, j + dj][..., None]

        return (1 - s) * (1 - t) * f(0, 0) + s * (1 - t) * f(1, 0) + (1 - s) * t * f(0, 1) + s * t * f(1, 1)

    # -- geometry -----------------------------------------------------------
    def _check_state(self, X, name: str = "X") -> np.ndarray:
        X = np.asarray(X, float)
        if X.shape != (self.ndof, 3):
            raise ValueError(f"{name} has shape {X.shape}, expected ({self.ndof}, 3)")
        return X

    def grid(self, X: np.ndarray) -> np.ndarray:
        """Node positions (value degrees of freedom), (M, N, 3)."""
        return self._check_state(X)[0::NODE_DOFS].reshape(self.M, self.N, 3)

    def discretize(self, surface) -> np.ndarray:
        """Nodal Hermite interpolation of a surface: X (ndof, 3).

        ``surface`` has r, r1, r2, r12 callables (a1, a2) -> (..., 3), or is a
        plain callable (then differentiated numerically, see
        :func:`deformable.as_surface`).
        """
        s = as_surface(surface)
        a1, a2 = self.scene.sheet.coordinates()
        X = np.stack([s.r(a1, a2), self.h1 * s.r1(a1, a2), self.h2 * s.r2(a1, a2),
                      self.h1 * self.h2 * s.r12(a1, a2)], axis=2)  # (M, N, 4, 3)
        return X.reshape(self.ndof, 3)

    def initial_state(self) -> np.ndarray:
        """The sheet's initial shape, (ndof, 3)."""
        return self.discretize(self.scene.sheet.initial)

    def derivatives(self, X: np.ndarray, which=DERIVATIVES[1:]) -> np.ndarray:
        """Parameter derivatives of r at the Gauss points.

        Parameters
        ----------
        X : (ndof, 3)
        which : sequence of (d1, d2)
            Derivative orders (default r_1, r_2, r_11, r_12, r_22).

        Returns
        -------
        array (3, len(which), E, nq)
        """
        X = self._check_state(X)
        D = np.concatenate([self.dq[d] for d in which], axis=1)  # (16, k nq)
        Xl = X.T[:, self.ldofs]  # (3, E, 16), contiguous
        E, nq = self.a1q.shape
        out = (Xl.reshape(-1, Xl.shape[-1]) @ D).reshape(3, E, len(which), nq)
        return np.ascontiguousarray(out.transpose(0, 2, 1, 3))  # contiguous: the tensor algebra runs faster

    def tensors(self, X: np.ndarray, curvature: bool = True):
        """G (eq. 4) and B (eq. 8) at the Gauss points, two (2, 2, E, nq) arrays.

        With ``curvature=False`` B is None (no normal is formed, so a sheet
        with degenerate tangents can still be stretched).
        """
        d = self.derivatives(X)
        dr = d[:, 0:2]
        G = tensors.metric(dr)
        if not curvature:
            return G, None
        ddr = np.stack([d[:, 2:4], d[:, 3:5]], axis=1)  # (3, 2, 2, E, nq): [[r11, r12], [r12, r22]]
        return G, tensors.curvature(ddr, tensors.normal(dr))

    def alpha_beta(self, X: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """alpha_ij and beta_ij of eq. (15) at the Gauss points, two (2, 2, E, nq) arrays."""
        if self.linear:
            return self.alpha_fixed, self.beta_fixed
        G, B = self.tensors(X, curvature=self._bending)
        alpha = self.eta * (G - self.G0)
        beta = self.xi * (B - self.B0) if self._bending else np.zeros_like(alpha)
        return alpha, beta

    def _locate(self, a: np.ndarray, what: str):
        """Element index, reference coordinates s, t of parameter points a (P, 2)."""
        a = np.asarray(a, float)
        if a.ndim == 1:
            a = a[None]
        L1, L2 = self.scene.sheet.size
        tol = 1e-12 * max(L1, L2)
        if a.ndim != 2 or a.shape[1] != 2 or not np.all(np.isfinite(a)):
            raise ValueError(f"{what} must be (P, 2) finite parameter points, got shape {a.shape}")
        outside = (a[:, 0] < -tol) | (a[:, 0] > L1 + tol) | (a[:, 1] < -tol) | (a[:, 1] > L2 + tol)
        if np.any(outside):
            raise ValueError(f"{what} {a[outside][0]!r} lies outside [0, {L1}] x [0, {L2}]")
        s, t = a[:, 0] / self.h1, a[:, 1] / self.h2
        i = np.clip(np.floor(s).astype(np.int64), 0, self.M - 2)
        j = np.clip(np.floor(t).astype(np.int64), 0, self.N - 2)
        return i * (self.N - 1) + j, np.clip(s - i, 0.0, 1.0), np.clip(t - j, 0.0, 1.0)

    def sample(self, X: np.ndarray, a: np.ndarray) -> Sample:
        """r, G (eq. 4), B (eq. 8) of the finite-element surface at parameter points.

        Parameters
        ----------
        X : (ndof, 3)
        a : array (P, 2)
            Parameter points (a1, a2) inside the rectangle.

        Returns
        -------
        Sample with r (P, 3), G (P, 2, 2), B (P, 2, 2)
        """
        X = self._check_state(X)
        e, s, t = self._locate(a, "sample points")
        h = (self.h1, self.h2)
        r, G, B = np.empty((e.size, 3)), np.empty((e.size, 2, 2)), np.empty((e.size, 2, 2))
        for lo in range(0, e.size, _CHUNK):  # chunks of points, to bound memory
            sl = slice(lo, lo + _CHUNK)
            Xl = X[self.ldofs[e[sl]]]  # (P, 16, 3)
            v = [np.einsum("plc,lp->cp", Xl, basis(s[sl], t[sl], h, d)) for d in DERIVATIVES]
            dr = np.stack([v[1], v[2]], axis=1)
            ddr = np.stack([np.stack([v[3], v[4]], axis=1), np.stack([v[4], v[5]], axis=1)], axis=1)
            r[sl] = v[0].T
            G[sl] = np.moveaxis(tensors.metric(dr), -1, 0)
            B[sl] = np.moveaxis(tensors.curvature(ddr, tensors.normal(dr)), -1, 0)
        return Sample(r=r, G=G, B=B)

    # -- the semi-discrete system (21) --------------------------------------
    def _coefficients(self, alpha: np.ndarray, beta: np.ndarray | None) -> np.ndarray:
        """Coefficient fields of the weak form, (E, C nq), in the order of the form tables."""
        c = [alpha[0, 0], 0.5 * (alpha[0, 1] + alpha[1, 0]), alpha[1, 1]]
        if beta is not None:
            c += [beta[0, 0], beta[0, 1] + beta[1, 0], beta[1, 1]]
        return np.stack(c, axis=1).reshape(alpha.shape[2], -1)

    def _assemble(self, alpha: np.ndarray | None, beta: np.ndarray | None) -> sp.csr_matrix:
        """K of the weak form for alpha, beta (2, 2, E, nq) at the Gauss points; None is zero."""
        if beta is None or not np.any(beta):
            alpha = np.zeros((2, 2) + self.a1q.shape) if alpha is None else alpha
            data = self.pattern.data(self._coefficients(alpha, None), self._T_membrane)
        else:
            alpha = np.zeros_like(beta) if alpha is None else alpha
            data = self.pattern.data(self._coefficients(alpha, beta), self._T_stiffness)
        return self.pattern.matrix(data)

    def stiffness(self, X: np.ndarray) -> sp.csr_matrix:
        """Strength matrix K(r) (ndof, ndof) of the weak form of eq. (14), symmetric, fixed pattern.

        Defined for the tpbf87 and frozen force models; the variational model
        couples the coordinates and has :meth:`energy_hessian` instead (ValueError).
        """
        if self.linear:
            return self._K_const
        if self._energy is not None:
            raise ValueError("the variational force model has no strength matrix K(r) of eq. (20); "
                             "use energy_gradient / energy_hessian (TimeStepper scheme 'implicit-euler' or 'newmark')")
        return self._assemble(*self.alpha_beta(X))

    def energy_gradient(self, X: np.ndarray) -> np.ndarray:
        """Exact gradient of the discrete energy, (ndof, 3) (N).

        Variational model: the gradient of eq. (13) by the Gauss rule
        (:mod:`femodel.variational`); frozen model: K R. The tpbf87 force (14)
        is not a gradient (ValueError).
        """
        if self.linear:
            return self._K_const @ self._check_state(X)
        if self._energy is None:
            raise ValueError(f"force_model {self.scene.force_model!r} has no energy gradient on FEModel: its force "
                             "(14) is not the gradient of eq. (13); use force_model 'variational'")
        return self._energy.gradient(self._check_state(X))

    def energy_hessian(self, X: np.ndarray, kind: str = "newton") -> sp.csr_matrix:
        """Hessian of the discrete energy, (3 ndof, 3 ndof), coordinates in blocks (index a ndof + k).

        Variational model: ``kind`` "newton" (exact) or "gauss-newton"
        (symmetric positive semi-definite), on a fixed pattern. Frozen model:
        the block diagonal of K (exact, so ``kind`` does not matter).
        """
        if self.linear:
            return sp.kron(sp.identity(3), self._K_const, format="csr")
        if self._energy is None:
            raise ValueError(f"force_model {self.scene.force_model!r} has no energy Hessian on FEModel; "
                             "use force_model 'variational'")
        return self._energy.hessian(self._check_state(X), kind)

    def internal_force(self, X: np.ndarray) -> np.ndarray:
        """The weak internal force, (ndof, 3) (N, integrated against the basis).

        K(r) R for tpbf87 and frozen; the energy gradient for the variational model.
        """
        if self._energy is not None:
            return self.energy_gradient(X)
        return self.stiffness(X) @ self._check_state(X)

    def mass(self) -> sp.csr_matrix:
        """Consistent mass matrix, integral mu u v (kg), on K's pattern."""
        return self._M

    def damping(self) -> sp.csr_matrix:
        """Consistent damping matrix, integral gamma u v (kg/s), on K's pattern."""
        return self._C

    def _scatter(self, local: np.ndarray) -> np.ndarray:
        """Element vectors (E, 16, 3) summed into the global vector (ndof, 3)."""
        return self._gather_t @ local.reshape(-1, 3)

    def load(self, X: np.ndarray, t: float) -> np.ndarray:
        """F of eq. (21) at time t, (ndof, 3) (N): loads integrated against the basis.

        Body densities (Gravity, BodyForce) by the 4 x 4 Gauss rule, edge
        tractions (EdgeLoad) by the 4-point Gauss rule on the edge's element
        sides, point loads (PointLoad) by the basis at the point.
        """
        F = np.zeros((self.ndof, 3))
        h = (self.h1, self.h2)
        x, w = get_quadrature_line(2 * GAUSS_POINTS - 1)
        x = x[0]
        for force in self.scene.forces:
            if force.kind == "body":
                f = force.density(self.a1q, self.a2q, t, self.mu) * self.weights[:, None]  # (E, nq, 3)
                F += self._scatter((f.transpose(0, 2, 1) @ self.dq[0, 0].T).transpose(0, 2, 1))
            elif force.kind == "edge":
                i, j = self.elem_ij[:, 0], self.elem_ij[:, 1]
                L1, L2 = self.scene.sheet.size
                zero, one = np.zeros_like(x), np.ones_like(x)
                sel, s, tt, length = {
                    "bottom": (j == 0, x, zero, self.h1),
                    "top": (j == self.N - 2, x, one, self.h1),
                    "left": (i == 0, zero, x, self.h2),
                    "right": (i == self.M - 2, one, x, self.h2),
                }[force.edge]
                e = np.flatnonzero(sel)
                a1 = (i[e, None] + s[None]) * self.h1
                a2 = (j[e, None] + tt[None]) * self.h2
                q = force.traction(a1, a2, t) * (w * length)[None, :, None]  # (Ee, nq, 3)
                local = np.einsum("eqc,lq->elc", q, basis(s, tt, h))
                np.add.at(F, self.ldofs[e], local)
            else:
                e, s, tt = self._locate(np.asarray(force.at)[None], "PointLoad.at")
                F[self.ldofs[e[0]]] += basis(s, tt, h)[:, 0, None] * force.force(t)[None]
        return F

    def energy(self, X: np.ndarray) -> Energy:
        """Elastic energy (J): eq. (13) by the Gauss rule (tpbf87, variational); R^T K R / 2 split alpha/beta (frozen)."""
        X = self._check_state(X)
        if self.linear:
            Ks = self._assemble(self.alpha_fixed, None)
            Kb = self._assemble(None, self.beta_fixed)
            return Energy(0.5 * float(np.sum(X * (Ks @ X))), 0.5 * float(np.sum(X * (Kb @ X))))
        G, B = self.tensors(X, curvature=self._bending)
        es = float(np.sum(self.eta * (G - self.G0) ** 2 * self.weights))
        eb = float(np.sum(self.xi * (B - self.B0) ** 2 * self.weights)) if self._bending else 0.0
        return Energy(es, eb)

    def kinetic_energy(self, V: np.ndarray) -> float:
        """Kinetic energy V^T M V / 2 (J) with the consistent mass."""
        V = self._check_state(V, "V")
        return 0.5 * float(np.sum(V * (self._M @ V)))

    # -- constraints ----------------------------------------------------------
    def _node_dofs(self, mask: np.ndarray, k: int = 0) -> np.ndarray:
        """Degree of freedom k (0 value, 1 h1 r_1, 2 h2 r_2, 3 h1 h2 r_12) of the nodes in an (M, N) mask."""
        return NODE_DOFS * np.flatnonzero(mask) + k

    def _selection_dofs(self, where) -> np.ndarray:
        """Value dofs of a selection, plus the tangential derivative dofs of the edges it names."""
        dofs = [self._node_dofs(select(where, self.scene.sheet))]
        for edge in _edges_named(where):
            dofs.append(self._node_dofs(select(edge, self.scene.sheet), _TANGENTIAL[edge]))
        return np.concatenate(dofs)

    def _build_constraints(self):
        fixed = np.zeros((3, self.ndof), bool)
        self._motions = []
        for c in self.scene.constraints:
            if isinstance(c, Pin):
                dofs = self._selection_dofs(c.where)
                fixed[:, dofs] = True
                if c.motion is not None:
                    self._motions.append((self._node_dofs(select(c.where, self.scene.sheet)), c.motion))
            elif isinstance(c, Slide):
                dofs = self._selection_dofs(c.where)
                for k in range(3):
                    if k != c.axis:
                        fixed[k, dofs] = True
            elif isinstance(c, Clamp):
                for edge in c.edges:
                    mask = select(edge, self.scene.sheet)
                    for k in range(NODE_DOFS):
                        fixed[:, self._node_dofs(mask, k)] = True
        self._fixed = tuple(np.flatnonzero(f) for f in fixed)

    def fixed_dofs(self) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Indices of the held degrees of freedom of x, y and z."""
        return self._fixed

    def prescribed(self, X0: np.ndarray, t: float) -> np.ndarray:
        """X0 with the value dofs of moving pins translated by their motion at time t, (ndof, 3)."""
        X = np.array(self._check_state(X0, "X0"), dtype=float)
        for idx, motion in self._motions:
            X[idx] += np.asarray(motion(t), float)
        return X
