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
weak form of eq. (14) (:mod:`femodel.strength`):

    K(u, v) = integral alpha_ij u_j v_i + beta_ij u_ij v_ij,
    M(u, v) = integral mu u v,   C(u, v) = integral gamma u v,
    F(v)    = integral f v  +  edge integral q v  +  P v(a_P),

so K, M, C are integrated (consistent) matrices and F integrated loads (the
backend contract's convention); the kinetic energy is ``V^T M V / 2`` and,
for the frozen model, the elastic energy ``R^T K R / 2``; for tpbf87 and the
variational model the energy of eq. (13) is integrated with the same Gauss
rule (:mod:`femodel.energy`).

``force_model="variational"``: no K(r); the internal force is the exact
gradient of that Gauss-rule energy (13), normal's dependence on r included,
with a Gauss-Newton and an exact Hessian (3 ndof, 3 ndof) for the implicit
steps and :func:`deformable.equilibrium` (:mod:`femodel.energy`).
Measured (2 shared cores, hanging sheet, dt = 1e-2): Hessian assembly 0.02 s
at 16 x 16 elements, 0.12 s at 32 x 32; an implicit-Euler step 0.37 s and
4.5 s (3 Newton iterations; SuperLU of the 13 068-dof Newton matrix, 1.1 s
each, is 75 % of the step).

Constraints act on degrees of freedom: a pinned node fixes its value; a pin
named by an edge also fixes the derivative along the edge (r is then known
along the whole edge, so is its tangential derivative; the cross derivative
r_12 stays free); a slide does the same for the two other components; a
clamp holds the edge and its tangent plane: the value and the derivative
along the edge in every coordinate, and the derivative across the edge (r_1
at a1 = 0) and the mixed one r_12 (its derivative along the edge) in the
coordinate of the clamp's normal. The tangential components of r_1, the
in-plane stretch at the edge, stay free, as the continuous energy leaves
them: holding them too adds a layer of width h in G at the clamp (measured on
the nonlinear clamped plate: the L2 self-convergence order of G fell to 0.6;
on the clamped strip, tip errors O(h^3) instead of O(h^4)). This needs the
normal of the initial shape along the edge to be a coordinate axis (a
degree of freedom is held coordinate by coordinate); otherwise the whole
r_1 and r_12 are held, with a warning. Prescribed motion translates value
degrees of freedom only.

Stability with the stepper of eq. (22)-(27): alpha is lagged, so stretching
is explicit (docs/design.md, "Time stepping"). With bicubic Hermite elements and the
consistent mass the largest eigenvalue of ``integral u_1 v_1`` against
``integral u v`` is about 91/h1^2 (the FD pair D1+^T D1+, diag(1): 4/h1^2),
so the usable dt is about ``0.21 h sqrt(mu / (2 eta G))``, some 5 times below
the FD bound (:meth:`FEModel.stable_step`). Measured on a hanging 8 x 8 element sheet (eta = 50, mu = 0.1):
stable at dt = 6e-4, diverges at 9e-4 (bound 8.3e-4).

Assembly cost: K's data is linear in the six coefficient fields
(alpha_11, alpha_12, alpha_22, beta_11, beta_12 + beta_21, beta_22) at the
Gauss points; :class:`femodel.strength.StrengthMatrix` maps them to K.data by
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

from deformable.algebra.elements import element_vectors
from deformable.backends.base import BackendBase
from deformable.backends.contract import EdgeRule, Patches, Sample
from deformable.geometry.sheet import bilinear
from deformable.geometry.surfaces import as_surface
from deformable.geometry.tensors import frame
from deformable.physics.force_models import EnergyModel, QuadraticEnergy
from deformable.physics.integrand import FE_SLOTS, DensityIntegrand, Integrand, slot_tensors
from deformable.physics.material import TENSORS
from deformable.scene.scene import Scene

from .energy import DiscreteEnergy, gauss_tensors
from .hermite import DERIVATIVES, LOCAL, NODE_DOFS, basis, evaluate
from .strength import StrengthMatrix

__all__ = ["FEModel", "ELEMENTS", "GAUSS_POINTS", "MEMBRANE_EIGENVALUE"]

log = logging.getLogger(__name__)

#: element families FEModel supports
ELEMENTS = ("hermite",)
#: Gauss points per direction and element (exact for the consistent mass of bicubics)
GAUSS_POINTS = 4
#: points per chunk in :meth:`FEModel.sample` (bounds its memory)
_CHUNK = 1 << 15
#: largest eigenvalue of integral u_1 v_1 against the consistent mass integral u v, times h^2: about 91
#: (FD's 4); written as FD's over 0.21^2, the measured ratio of the two stable steps
MEMBRANE_EIGENVALUE = 4.0 / 0.21**2
#: contact points per element side by default (deformable.contact): a sub-grid of spacing h / 2, the nodes
#: among them, so that the cubic surface between nodes is covered too
CONTACT_SAMPLES = 2


class FEModel(BackendBase):
    """Finite-element backend; satisfies :class:`deformable.Backend`.

    Over :class:`~deformable.backends.BackendBase`: consistent mass and damping (integral mu u v, gamma u v) on
    K's pattern; loads integrated against the basis (body densities and wind by the 4 x 4 Gauss rule, the wind
    with the exact normal of the element surface; edge tractions by the 4-point rule on the element sides; point
    loads and springs by the basis at their point); the energy (13) by the same Gauss rule.

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
        Parameter coordinates of the Gauss points, element e = i (N - 1) + j (the contract's ``points``).
    weights : array (nq,)
        Gauss weights times the element area h1 h2.
    strength : femodel.strength.StrengthMatrix
        The fixed CSR pattern shared by K, M and C, and the form tables.
    """

    #: the basis vanishes exactly at nodes and along element sides; its round-off there is dropped
    point_tolerance = 1e-14

    def __init__(self, scene: Scene, element: str = "hermite"):
        super().__init__(scene)
        if element not in ELEMENTS:
            raise ValueError(f"element must be one of {ELEMENTS}, got {element!r}")
        start = time.perf_counter()
        self.element = element
        sheet, mat, M, N, fm = scene.sheet, scene.material, self.M, self.N, self.force_model
        self.ndof = NODE_DOFS * M * N
        self.value_dofs = NODE_DOFS * np.arange(M * N)
        self.mesh = skfem.MeshQuad.init_tensor(*sheet.axes())
        self._build_elements()
        self._build_quadrature()
        self.points = (self.a1q, self.a2q)

        self.strength = StrengthMatrix(self.ldofs, self.ndof, self.dq, self.weights)
        self.mu, self.gamma = (mat.field_at(name, (M, N), self.points, self.to_quadrature) for name in ("mu", "gamma"))
        self._M = self.strength.density_matrix(self.mu)
        self._C = self.strength.density_matrix(self.gamma)
        self._scatter = element_vectors(self.ldofs, self.ndof)  # element load vectors (E 16) -> (ndof)

        #: the Material's tensor fields at the Gauss points, (2, 2, E, nq) each (a callable evaluated there)
        self.fields = {name: mat.tensor_at(name, (M, N), self.points, self.to_quadrature) for name in TENSORS}
        self.eta, self.xi = self.fields["eta"], self.fields["xi"]
        # rest state at the Gauss points: the discretised rest shape, or the scene's overrides
        if self.linear:
            self._fix_coefficients()
            self._bending = bool(np.any(self.beta_fixed != 0))
            self._energy = QuadraticEnergy(self._K_const, self.strength.matrix(self.alpha_fixed, None),
                                           self.strength.matrix(None, self.beta_fixed))
        else:
            self._bending = bool(np.any(self.xi != 0))
            G, B = self.tensors(self.discretize(sheet.rest), curvature=True)
            self.G0, self.B0 = scene.rest_tensors(self.a1q, self.a2q, G, B)
            w = self.weights[None, None, None, :]
            if isinstance(fm, EnergyModel) and not fm.compiled:  # a general density: the same Gauss rule
                params = {name: self.fields[name] for name in fm.fields}
                q = np.broadcast_to(self.weights, (6, *self.a1q.shape))
                integrand = DensityIntegrand(fm, params, q, self.G0, self.B0, FE_SLOTS)
            else:  # eq. (13), compiled: the variational model, and tpbf87's energy
                integrand = Integrand(self.eta * w, self.xi * w, self.G0, self.B0, FE_SLOTS)
            self._energy = DiscreteEnergy(self.ldofs, self.ndof, self.dq, integrand)
        self._complete(node_dofs=self._node_dofs, edge_dofs=self._edge_tangent_dofs, clamp_dofs=self._clamp_dofs,
                       symmetry_dofs=self._symmetry_dofs)
        log.debug("FEModel %d x %d elements, %d dofs, nnz %d, built in %.3f s",
                  M - 1, N - 1, self.ndof, self.strength.elements.nnz, time.perf_counter() - start)

    # -- mesh, elements, quadrature -----------------------------------------
    def _build_elements(self):
        """Element (i, j) and its 16 global degrees of freedom, from the skfem mesh."""
        N = self.N
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
        return bilinear(field, self.elem_ij[:, 0, None], self.elem_ij[:, 1, None], self.qs, self.qt)

    # -- geometry -----------------------------------------------------------
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
        return evaluate(self._check_state(X), self.ldofs, [self.dq[d] for d in which])

    def tensors(self, X: np.ndarray, curvature: bool = True):
        """G (eq. 4) and B (eq. 8) at the Gauss points, two (2, 2, E, nq) arrays.

        With ``curvature=False`` B is None (no normal is formed, so a sheet
        with degenerate tangents can still be stretched).
        """
        return gauss_tensors(self._check_state(X), self.ldofs, self.dq, curvature)

    def _strain_tensors(self, X: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """G and B at the Gauss points, where alpha and beta of eq. (15) are formed (the hook of :meth:`alpha_beta`);
        B None without bending."""
        return self.tensors(X, curvature=self._bending)

    def _locate(self, a: np.ndarray, what: str):
        """Element index, reference coordinates s, t of parameter points a (P, 2)."""
        i, j, s, t = self.scene.sheet.locate(a, what)
        return i * (self.N - 1) + j, s, t

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
            v = np.stack([np.einsum("plc,lp->pc", Xl, basis(s[sl], t[sl], h, d)) for d in DERIVATIVES], axis=1)
            r[sl] = v[:, 0]
            Gs, Bs = slot_tensors(v[:, 1:], FE_SLOTS)
            G[sl], B[sl] = np.moveaxis(Gs, -1, 0), np.moveaxis(Bs, -1, 0)
        return Sample(r=r, G=G, B=B)

    # -- the hooks of deformable.physics.loads ---------------------------------------
    def integrate(self, density: np.ndarray) -> np.ndarray:
        """integral f phi_k of a density f (N/m^2) at the Gauss points, (E, nq, 3): (ndof, 3) (N)."""
        f = np.asarray(density).reshape(*self.a1q.shape, 3) * self.weights[:, None]  # (E, nq, 3)
        return self._scatter @ (f.transpose(0, 2, 1) @ self.dq[0, 0].T).transpose(0, 2, 1).reshape(-1, 3)

    def at_points(self, X: np.ndarray, d: tuple[int, int] = (0, 0)) -> np.ndarray:
        """The field X or its derivative d = (d1, d2) at the Gauss points, (E nq, 3)."""
        return evaluate(np.asarray(X, float), self.ldofs, [self.dq[tuple(d)]])[:, 0].reshape(3, -1).T

    def density_matrix(self, c: np.ndarray) -> sp.csr_matrix:
        """integral c phi_k phi_l (ndof, ndof) for a field c at the Gauss points (E, nq), on K's pattern."""
        return self.strength.density_matrix(np.asarray(c).reshape(self.a1q.shape))

    def _point_weights(self, a, what: str) -> tuple[np.ndarray, np.ndarray]:
        """The 16 degrees of freedom of the element holding each parameter point a (P, 2) and the basis there, (P, 16)
        each (:meth:`point_matrix` drops its round-off where it vanishes exactly, at nodes and along element sides)."""
        e, s, t = self._locate(a, what)
        return self.ldofs[e], basis(s, t, (self.h1, self.h2)).T

    def patches(self) -> Patches:
        """The Gauss points by element: each reads its element's 16 degrees of freedom."""
        E, nq = self.a1q.shape
        values = np.stack([np.broadcast_to(self.dq[d].T[None], (E, nq, 16)) for d in ((0, 0), (1, 0), (0, 1))])
        return Patches(self.ldofs, values, np.broadcast_to(self.weights, (E, nq)))

    def edge_rule(self, name: str) -> EdgeRule:
        """The 4-point Gauss rule on each element side along the edge, with the basis and its derivative across."""
        x, w = get_quadrature_line(2 * GAUSS_POINTS - 1)
        x = x[0]
        edge = self.scene.sheet.edge(name)
        end = 0 if edge.side == 0 else self.scene.sheet.nodes[edge.axis] - 2  # the elements along the edge
        e = np.flatnonzero(self.elem_ij[:, edge.axis] == end)
        ref = [x, x]
        ref[edge.axis] = np.full_like(x, 0.0 if edge.side == 0 else 1.0)
        s, tt = ref
        rows, cols = np.repeat(np.arange(e.size * x.size), 16), np.repeat(self.ldofs[e], x.size, axis=0).ravel()

        def matrix(d):  # (P, ndof), P = elements x points, element-major
            v = np.broadcast_to(basis(s, tt, self.spacing, d).T[None], (e.size, x.size, 16)).ravel()
            return sp.csr_matrix((v, (rows, cols)), shape=(e.size * x.size, self.ndof))

        a1 = ((self.elem_ij[e, 0, None] + s[None]) * self.h1).ravel()
        a2 = ((self.elem_ij[e, 1, None] + tt[None]) * self.h2).ravel()
        return EdgeRule(a1, a2, np.tile(w * self.spacing[edge.along], e.size), matrix((0, 0)),
                        matrix((1, 0) if edge.axis == 0 else (0, 1)))

    # -- constraints ----------------------------------------------------------
    def _node_dofs(self, mask: np.ndarray, k: int = 0) -> np.ndarray:
        """Degree of freedom k (0 value, 1 h1 r_1, 2 h2 r_2, 3 h1 h2 r_12) of the nodes in an (M, N) mask."""
        return NODE_DOFS * np.flatnonzero(mask) + k

    def _edge_tangent_dofs(self, name: str) -> np.ndarray:
        """The derivative along the edge at its nodes: known once r is known along the whole edge."""
        return self._node_dofs(self.scene.sheet.edge_nodes(name), 1 + self.scene.sheet.edge(name).along)

    def _symmetry_dofs(self, name: str, normal: int) -> tuple:
        """What a Symmetry of the edge holds, (x, y, z): the value and the derivative along the edge in the
        normal's coordinate; the derivative across the edge and the mixed one in the other two."""
        mask, edge = self.scene.sheet.edge_nodes(name), self.scene.sheet.edge(name)
        on_plane = np.concatenate([self._node_dofs(mask, 0), self._node_dofs(mask, 1 + edge.along)])
        square = np.concatenate([self._node_dofs(mask, 1 + edge.axis), self._node_dofs(mask, 3)])
        return tuple(on_plane if k == normal else square for k in range(3))

    def _clamp_dofs(self, name: str):
        """What a clamp of the edge holds (module docstring), per coordinate: (x, y, z) index arrays.

        Values and the derivative along the edge in every coordinate; the derivative across the edge and
        the mixed one (its derivative along the edge) in the coordinate of the clamp's normal only, when
        the normal of the initial shape along the edge is a coordinate axis; in every coordinate otherwise.
        """
        sheet = self.scene.sheet
        mask, edge = sheet.edge_nodes(name), sheet.edge(name)
        position = np.concatenate([self._node_dofs(mask, 0), self._node_dofs(mask, 1 + edge.along)])
        slope = np.concatenate([self._node_dofs(mask, 1 + edge.axis), self._node_dofs(mask, 3)])
        a1, a2 = sheet.coordinates()
        s = as_surface(sheet.initial)
        n, _ = frame(s.r1(a1[mask], a2[mask]), s.r2(a1[mask], a2[mask]))
        axis = [k for k in range(3) if np.all(np.abs(np.abs(n[:, k]) - 1.0) < 1e-12)]
        if not axis:
            log.warning("clamp of edge %r: its normal is not a coordinate axis, so the clamp holds the whole "
                        "derivative across the edge (the in-plane stretch too: an O(h^3) layer)", name)
        held = [np.concatenate([position, slope]) if not axis or k == axis[0] else position for k in range(3)]
        return tuple(held)
